//! Behaviour of the escape FSM (paper Sec. II-B, Eqs. 13–15) and its swarm variant (Sec. IV-D):
//! the transition table, the short-mode override, the γ path and the long takeoff in closed
//! loop with odometry, the quiet period, the takeoff timeout and robustness to bad input.

use alvs_tasks::model::closed_loop::derotate::FOCAL_PX;
use alvs_tasks::model::closed_loop::movers::{Movers, Sighting};
use alvs_tasks::model::fsm::LOOK_TIMEOUT_FRAMES;
use alvs_tasks::model::fsm::{
    Behaviour, Blocked, Escape, FirmwareFsm, Fsm, FsmParamError, FsmParams, HeadingEstimator,
    Motion, MotorCommand, Odometry, ShortPhase, State, Suppression, Swarm, Timing,
};
use alvs_tasks::model::visuomotor::{bearing, wrap_deg, Visuomotor};
use alvs_tasks::Params;
use alvs_tasks::{PIXELS, WIDTH};
use core::num::NonZeroU32;
use proptest::prelude::*;

mod blocked_way;
mod firmware;
mod fixtures;
mod gamma;
mod parameters;
mod robustness;
mod saccade;
mod strength;
mod suppression;
mod swarm;
mod table;
mod timing;

use fixtures::*;

//! The robot controllers the experiments swap with a flag, behind one trait: ALVS (the firmware's
//! perception and FSM from `alvs_tasks`), its swarm variant, and the LGMD2 baseline with its
//! direction-blind escape. A scripted controller drives obstacle robots.

use alvs_tasks::model::closed_loop::movers::Movers;
use alvs_tasks::model::fsm::{Behaviour, Fsm, FsmParams, State};
use alvs_tasks::model::param_table::off0;
use alvs_tasks::model::visuomotor::wrap_deg;
use alvs_tasks::{Frame, Network, Params};

use crate::lgmd2::{Lgmd2, Lgmd2Params};
use crate::rng::Rng;

/// What a controller's perception reported for one frame (for traces; zero for the blind).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Seen {
    /// ALVS: `ΣLPLC2`; LGMD2: its spikes of the current burst.
    pub response: u32,
    /// ALVS: `X̄`, the threat's column; LGMD2: none (it has no direction).
    pub threat_x: Option<f32>,
    /// ALVS: attention fields standing; LGMD2: 0.
    pub fields: u8,
    /// ALVS: the short mode is on (`ΣLPLC2 > T_s`).
    pub short_mode: bool,
}

/// What a controller asks of the motors for one camera frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Command {
    /// Left wheel, mm/s.
    pub left_mm_s: f32,
    /// Right wheel, mm/s.
    pub right_mm_s: f32,
    /// Name of the controller's state (for time-per-state statistics).
    pub state: &'static str,
    /// The controller's collision detector fired this frame.
    pub alert: bool,
    /// What its perception reported.
    pub seen: Seen,
}

/// A robot's brain: one call per camera frame with the frame and the heading estimate.
pub trait Controller: Send {
    /// Short name for reports ("alvs", "swarm", "lgmd2", "scripted").
    fn name(&self) -> &'static str;
    /// One camera frame.
    fn step(&mut self, frame: &Frame, heading_deg: f32) -> Command;
    /// Whether the controller looks at its frame. A blind one (a scripted obstacle) is handed
    /// a stale frame and the camera is not rendered for it: rendering is most of the cost of a
    /// robot that runs no model.
    fn sees(&self) -> bool {
        true
    }
    /// The wheels did not carry out the last command (the robot is held): a controller with
    /// efference copies of its commands forgets that one.
    fn command_not_applied(&mut self) {}
}

/// Which controller a robot runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// ALVS: aLPLC2 perception + escape FSM (paper Sec. II).
    Alvs,
    /// ALVS perception + spin-on-approach (paper Sec. IV-D).
    Swarm,
    /// LGMD2 perception + direction-blind escape (the paper's baseline).
    Lgmd2,
}

impl Kind {
    /// Name used in JSON and pictures.
    pub const fn name(self) -> &'static str {
        match self {
            Kind::Alvs => "alvs",
            Kind::Swarm => "swarm",
            Kind::Lgmd2 => "lgmd2",
        }
    }

    /// A fresh controller of this kind with the model parameters `params` (ALVS) and the
    /// motion parameters `fsm` (LGMD2's turn and cruise use the same speeds and limits);
    /// `seed` feeds the LGMD2 escape's random turns.
    pub fn make(self, params: Params, fsm: FsmParams, seed: u64) -> Box<dyn Controller> {
        match self {
            Kind::Alvs => Box::new(AlvsController::new(params, fsm, Behaviour::Escape)),
            Kind::Swarm => Box::new(AlvsController::new(params, fsm, Behaviour::Swarm)),
            Kind::Lgmd2 => Box::new(Lgmd2Controller::new(Lgmd2Params::default(), fsm, seed)),
        }
    }
}

/// The firmware's perception and motor-control task bodies, unchanged.
pub struct AlvsController {
    net: Network,
    fsm: Fsm,
    swarm: bool,
    /// The heading of the previous frame: the turn since then is the efference copy the
    /// network takes (`Params::derotate`).
    last_heading: Option<f32>,
    /// The swarm's look (`Params::look_change`), beside the network: only the swarm needs its
    /// 2.6 KB, and the firmware, which escapes, has none.
    movers: Movers,
    /// The wheels were commanded to stand still for this frame (the efference copy).
    standing: bool,
}

impl AlvsController {
    /// With the given model parameters (validated by the caller: `Params::validate`).
    pub fn new(params: Params, fsm: FsmParams, behaviour: Behaviour) -> Self {
        AlvsController {
            net: Network::new(params).unwrap_or_else(|_| {
                Network::new(Params::default()).expect("the paper's defaults are valid")
            }),
            fsm: Fsm::new(fsm, behaviour),
            swarm: behaviour == Behaviour::Swarm,
            last_heading: None,
            movers: Movers::new(),
            standing: false,
        }
    }

    /// The perception state (for layer pictures).
    pub fn network(&self) -> &Network {
        &self.net
    }
}

impl Controller for AlvsController {
    fn name(&self) -> &'static str {
        if self.swarm {
            "swarm"
        } else {
            "alvs"
        }
    }

    fn step(&mut self, frame: &Frame, heading_deg: f32) -> Command {
        if let Some(last) = self.last_heading.replace(heading_deg) {
            self.net.turned(wrap_deg(heading_deg - last));
        }
        let mut out = self.net.step(frame);
        if self.swarm {
            let change = self.net.params().swarm.look_change;
            out.vm.sighting = self.movers.step(frame, self.standing, off0(change));
        }
        let cmd = self.fsm.step(&out.vm, heading_deg);
        // the efference copies of forward motion and of standing for the next frame
        self.net.driving((cmd.left_mm_s + cmd.right_mm_s) / 2.0);
        self.standing = cmd.stands();
        Command {
            left_mm_s: cmd.left_mm_s,
            right_mm_s: cmd.right_mm_s,
            state: cmd.state.name(),
            alert: out.vm.alert,
            seen: Seen {
                response: out.vm.lplc2_sum,
                threat_x: out.vm.threat_x,
                fields: out.afs.len() as u8,
                short_mode: out.vm.short_mode,
            },
        }
    }

    fn command_not_applied(&mut self) {
        self.fsm.command_not_applied();
        self.net.driving(0.0);
    }
}

/// LGMD2 baseline behaviour (paper Sec. III, Fig. 4c; `docs/lgmd2.md`, last paragraph): on
/// a collision alert the robot turns in place by a random angle of random sign (it has no
/// direction information), 60°–180°, then goes straight on at its cruise speed with its
/// perception live, as the authors' Colias LGMD2 firmware does (`Decision_making` queues a long
/// left or right turn on the motion board; when the turn is done the robot drives on and the
/// next alert queues the next turn). Alerts during the turn are ignored (the firmware's motion
/// queue is busy). There is no escape sprint: the firmware has none, and a 1 s run at
/// `max_escape_mm_s` that ignores the LGMD2 (what this adapter did before) drove most LGMD2
/// robots that had detected a wall into it after their random turn.
pub struct Lgmd2Controller {
    model: Lgmd2,
    rng: Rng,
    params: FsmParams,
    state: State,
    setpoint_deg: f32,
    frames_in_state: u32,
}

/// Smallest random turn of the LGMD2 escape, degrees.
pub const LGMD2_TURN_MIN_DEG: f32 = 60.0;
/// Largest random turn of the LGMD2 escape, degrees.
pub const LGMD2_TURN_MAX_DEG: f32 = 180.0;

impl Lgmd2Controller {
    /// With LGMD2 parameters, the escape's motion parameters and a seed for the random turns.
    pub fn new(params: Lgmd2Params, fsm: FsmParams, seed: u64) -> Self {
        Lgmd2Controller {
            model: Lgmd2::new(params),
            rng: Rng::new(seed),
            params: fsm,
            state: State::Wander,
            setpoint_deg: f32::NAN,
            frames_in_state: 0,
        }
    }

    fn enter(&mut self, s: State) {
        self.state = s;
        self.frames_in_state = 0;
    }
}

impl Controller for Lgmd2Controller {
    fn name(&self) -> &'static str {
        "lgmd2"
    }

    fn step(&mut self, frame: &Frame, heading_deg: f32) -> Command {
        self.step_with(frame, heading_deg, false)
    }
}

impl Lgmd2Controller {
    /// One frame, with `proximity` an alert from outside the LGMD2 (a proximity sensor's, in
    /// `cargo alvs validate --proximity-mm`, a diagnostic): it starts the same random turn.
    pub fn step_with(&mut self, frame: &Frame, heading_deg: f32, proximity: bool) -> Command {
        let mut out = self.model.step(frame);
        out.collision |= proximity;
        let p = self.params;
        if !self.setpoint_deg.is_finite() {
            self.setpoint_deg = heading_deg;
        }
        self.frames_in_state = self.frames_in_state.saturating_add(1);
        match self.state {
            State::Wander if out.collision => {
                let mag = LGMD2_TURN_MIN_DEG
                    + (LGMD2_TURN_MAX_DEG - LGMD2_TURN_MIN_DEG) * self.rng.uniform() as f32;
                let sign = if self.rng.uniform() < 0.5 { -1.0 } else { 1.0 };
                self.setpoint_deg =
                    alvs_tasks::model::visuomotor::wrap_deg(heading_deg + sign * mag);
                self.enter(State::LongTakeoff);
            }
            State::LongTakeoff => {
                let err = alvs_tasks::model::fsm::heading_error_deg(self.setpoint_deg, heading_deg);
                if err.abs() <= p.motion.align_tol_deg
                    || self.frames_in_state > p.timing.takeoff_timeout_frames
                {
                    // straight on along the new heading, perception live
                    self.enter(State::Wander);
                }
            }
            _ => {}
        }
        let v = match self.state {
            State::LongTakeoff => 0.0,
            _ => p.motion.cruise_mm_s,
        };
        let err = alvs_tasks::model::fsm::heading_error_deg(self.setpoint_deg, heading_deg);
        let omega = alvs_tasks::model::fsm::yaw_rate_rad_s(err, &p);
        let (l, r) = alvs_tasks::model::fsm::mix(v, omega, &p);
        Command {
            left_mm_s: l,
            right_mm_s: r,
            state: self.state.name(),
            alert: out.collision,
            seen: Seen {
                response: out.accumulated,
                ..Seen::default()
            },
        }
    }
}

/// An obstacle robot: constant wheel speeds, ignores its camera.
pub struct Scripted {
    /// Left wheel, mm/s.
    pub left_mm_s: f32,
    /// Right wheel, mm/s.
    pub right_mm_s: f32,
}

impl Controller for Scripted {
    fn name(&self) -> &'static str {
        "scripted"
    }

    fn sees(&self) -> bool {
        false
    }

    fn step(&mut self, _frame: &Frame, _heading_deg: f32) -> Command {
        Command {
            left_mm_s: self.left_mm_s,
            right_mm_s: self.right_mm_s,
            state: "scripted",
            ..Command::default()
        }
    }
}

/// A controller whose perception runs but whose wheels stay still (the stationary observer of
/// the paper's Fig. 3 experiments).
pub struct Stationary(pub Box<dyn Controller>);

impl Controller for Stationary {
    fn name(&self) -> &'static str {
        self.0.name()
    }

    fn sees(&self) -> bool {
        self.0.sees()
    }

    fn step(&mut self, frame: &Frame, heading_deg: f32) -> Command {
        let c = self.0.step(frame, heading_deg);
        Command {
            left_mm_s: 0.0,
            right_mm_s: 0.0,
            ..c
        }
    }
}

/// An obstacle robot of the paper's open-loop trials (Fig. 4a): drives straight at a constant
/// speed for a given number of camera frames, then stops (so that it ends where it was aimed,
/// not chasing an evader across the arena).
pub struct Approach {
    /// Forward speed, mm/s.
    pub speed_mm_s: f32,
    /// Frames left to drive.
    pub frames_left: u32,
}

impl Controller for Approach {
    fn name(&self) -> &'static str {
        "scripted"
    }

    fn sees(&self) -> bool {
        false
    }

    fn step(&mut self, _frame: &Frame, _heading_deg: f32) -> Command {
        let v = if self.frames_left > 0 {
            self.frames_left -= 1;
            self.speed_mm_s
        } else {
            0.0
        };
        Command {
            left_mm_s: v,
            right_mm_s: v,
            state: "scripted",
            ..Command::default()
        }
    }
}

/// A robot that stands still, its perception running, until its controller first alerts; from
/// then on the controller drives it. This is the tested robot of the paper's evasion trials:
/// "placed at the same initial position" while an obstacle approaches. Once released it stays
/// released.
pub struct HoldUntilAlert {
    inner: Box<dyn Controller>,
    released: bool,
}

impl HoldUntilAlert {
    /// Holds `inner` still until its first alert.
    pub fn new(inner: Box<dyn Controller>) -> Self {
        HoldUntilAlert {
            inner,
            released: false,
        }
    }
}

impl Controller for HoldUntilAlert {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn sees(&self) -> bool {
        self.inner.sees()
    }

    fn command_not_applied(&mut self) {
        self.inner.command_not_applied();
    }

    fn step(&mut self, frame: &Frame, heading_deg: f32) -> Command {
        let c = self.inner.step(frame, heading_deg);
        self.released |= c.alert;
        if self.released {
            c
        } else {
            self.inner.command_not_applied();
            Command {
                left_mm_s: 0.0,
                right_mm_s: 0.0,
                ..c
            }
        }
    }
}

//! # alvs-tasks: what the ALVS firmware tasks compute
//!
//! The attention-driven LPLC2 visuomotor system (ALVS) of Liu, Zhou, Fang and Fu, "How Fly
//! Neural Perception Mechanisms Enhance Visuomotor Control of Micro Robots", written once as
//! `no_std` Rust with no heap and no hardware types, so that the RTIC firmware, the replay tool,
//! the simulator and the tests all run exactly the same code.
//!
//! Two module trees (`docs/architecture.md` draws the data path through them):
//!
//! - [`model`]: the paper's neural network and escape behaviour, one module per neural stage,
//!   equation numbers in their docs (see `docs/model.md`): parameters, retina, attention fields,
//!   T4/T5 correlators, LPLC2 quadrants, visuomotor pathway, escape FSM.
//! - [`robot`]: the firmware's logic that is not a register access, tested on the host: the
//!   camera hand-off, the motor-control task, the motor protocol, health and safety policy,
//!   telemetry, and the timed bench frame.
//!
//! [`frame`] holds the frame geometry both share. The types most callers need are re-exported
//! here: [`Frame`], [`Network`], [`Perception`], [`Params`].
#![no_std]
#![deny(unsafe_code)] // allowed in `model::dsp` only: single DSP instructions
#![warn(missing_docs)]

pub mod frame;
pub mod model;
pub mod robot;

pub use frame::{Frame, FrameError, HEIGHT, PIXELS, WIDTH};
pub use model::network::{AfReport, Network, Perception};
pub use model::params::{ParamError, Params};
pub use model::MAX_AFS;

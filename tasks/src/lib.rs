//! # alvs-tasks: what the ALVS firmware tasks compute
//!
//! The attention-driven LPLC2 visuomotor system (ALVS) of Liu, Zhou, Fang and Fu, "How Fly
//! Neural Perception Mechanisms Enhance Visuomotor Control of Micro Robots", written once as
//! `no_std` Rust with no heap and no hardware types, so that the RTIC firmware, the replay tool,
//! the simulator and the tests all run exactly the same code.
//!
//! One module per neural stage; equation numbers refer to the paper (see `docs/model.md`):
//!
//! | stage | module | paper |
//! |---|---|---|
//! | frame geometry, conventions | [`frame`] | Sec. II-A, Sec. II-C |
//! | Table I parameters and documented choices | [`params`] | Table I |
//! | retina, ON/OFF, 3x3 mean | [`retina`] | Eqs. (1)–(2) |
//! | multi-attention fields | [`attention`] | Eqs. (3)–(5), (10) |
//! | T4/T5 correlators, local motion | [`hrc`] | Eqs. (6)–(7) |
//! | quadrants and LPLC2 gate | [`lplc2`] | Eqs. (8)–(9) |
//! | one perception step | [`network`] | Sec. II-A |
//! | strength, threat centroid, escape angles | [`visuomotor`] | Eqs. (11)–(15) |
//! | escape FSM (and the swarm variant) | [`fsm`] | Sec. II-B, IV-D |
//! | telemetry records | [`telemetry`] | — |
//! | the motor-control task: FSM, heading, motor frames | [`control`] | Sec. II-B |
//! | one timed frame of perception and control | [`bench`] | — |
//!
//! The firmware's logic that is not a register access, tested on the host:
//!
//! | concern | module |
//! |---|---|
//! | luminance from YUV422, frame hand-off camera → perception | [`camera`] |
//! | bottom-board UART protocol, wheel powers | [`motor`] |
//! | 1 Hz summary statistics, safety and watchdog policy | [`health`] |
//! | Cortex-M4 DSP instructions of the pixel loops, with their plain meaning | [`dsp`] |
#![no_std]
#![deny(unsafe_code)] // allowed in `dsp` only: single DSP instructions
#![warn(missing_docs)]

pub mod attention;
pub mod bench;
pub mod camera;
pub mod control;
pub mod dsp;
pub mod frame;
pub mod fsm;
pub mod health;
pub mod hrc;
pub mod lplc2;
pub mod motor;
pub mod network;
pub mod params;
pub mod retina;
pub mod telemetry;
pub mod visuomotor;

pub use frame::{Frame, FrameError, HEIGHT, PIXELS, WIDTH};
pub use network::{AfReport, Network, Perception, MAX_AFS};
pub use params::{ParamError, Params};

//! The firmware's logic that is not a register access, tested on the host: what the RTIC tasks
//! of `src/` call once the hardware has delivered its bytes.
//!
//! | concern | module |
//! |---|---|
//! | luminance from YUV422, frame hand-off camera → perception | [`camera`] |
//! | the motor-control task: FSM, heading, motor frames | [`control`] |
//! | bottom-board UART protocol, wheel powers | [`motor`] |
//! | 1 Hz summary statistics, safety and watchdog policy | [`health`] |
//! | telemetry records | [`telemetry`] |
//! | one timed frame of perception and control | [`bench`](mod@bench) |

pub mod bench;
pub mod camera;
pub mod control;
pub mod health;
pub mod motor;
pub mod telemetry;

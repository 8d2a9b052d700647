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
//! | the boot self-test: its frames and its `bench:` lines | [`self_test`] |
//! | what the RTT lines' parsers share | [`line`] |

pub mod bench;
pub mod camera;
pub mod control;
pub mod health;
pub mod line;
pub mod motor;
pub mod self_test;
pub mod telemetry;

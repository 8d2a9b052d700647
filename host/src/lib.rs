//! Host tools for ALVS (`cargo alvs …`): replay of recorded video through the exact firmware
//! task code, synthetic demo scenes, the paper's experiments in the simulated world (`alvs_sim`),
//! the recorded Colias runs they are validated against, and saved RTT sessions read back.

pub mod clip;
pub mod data;
pub mod experiments;
pub mod multi_target;
pub mod recordings;
pub mod replay;
pub mod rtt_log;
pub mod scenes;

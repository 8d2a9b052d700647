//! Host tools for ALVS: replay of recorded video through the exact firmware task code,
//! synthetic demo scenes, and pictures.

pub mod clip;
pub mod data;
pub mod experiments;
pub mod recordings;
pub mod replay;
pub mod rtt_log;
pub mod scenes;

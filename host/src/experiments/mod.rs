//! The paper's experiments on the simulated arena (`cargo alvs <experiment>`): each one builds
//! its trials from a configuration, runs them (in parallel where they are independent), and
//! reports a summary table, JSON and pictures.
//!
//! | experiment | paper | module |
//! |---|---|---|
//! | `arena`: robots wandering among each other and the walls, success rate and collisions | Figs. 5–6, Sec. III-C | [`arena`] |

pub mod arena;

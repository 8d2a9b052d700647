//! What the project adds to the paper's model for a robot that moves: each mechanism is a
//! parameter, off in `--model paper`, and earns its place in the default on held-out seeds
//! (`docs/model.md` says what each does and why, `docs/ablation.md` what each earns).
//!
//! | mechanism | module | reads |
//! |---|---|---|
//! | whole-field luminance events (exposure steps, flicker) | [`luminance`] | the retina's input |
//! | noise frames: pictures no lens could make (a corrupted transfer) | [`noise_frames`] | the frame |
//! | efference copy of turns: the retina's memory re-registered after a commanded turn | [`derotate`] | the motor command |
//! | efference copy of forward travel: the blocked-way view | [`progress`] | the motor command |
//! | the floor line: an obstacle's distance from its foot | [`floor`] | the frame |
//! | moving objects seen while standing, the swarm's look | [`movers`] | the frame |

pub mod derotate;
pub mod floor;
pub mod luminance;
pub mod movers;
pub mod noise_frames;
pub mod progress;

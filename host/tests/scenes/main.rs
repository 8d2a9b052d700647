//! Behaviour of the whole aLPLC2 network (paper Sec. II) on synthetic scenes rendered here,
//! always with `Params::default()` (Table I plus the documented choices): nothing is calibrated
//! to the scenes.
//!
//! Scenes are 99 x 72 frames at 30 fps. Pixel `(x, y)` is centred on the integer point `(x, y)`;
//! squares are drawn with their exact area coverage, discs with 4x4 supersampling. Every scene
//! starts with `LEAD` still frames (the first one primes the network).
//!
//! Every test prints its numbers (alerts per scene, `X̄`, AF counts, peak `ΣLPLC2`):
//! `cargo test --target host-tuple -p alvs-host --test scenes -- --nocapture`.
//!
//! Limitations of the model that these scenes expose are kept at the end as `#[ignore]`d tests
//! that state the wanted behaviour, with the measured numbers; they fail today
//! (`-- --ignored` runs them).

use alvs_tasks::{Network, Params, Perception, HEIGHT, PIXELS, WIDTH};

mod approach;
mod firmware;
mod harness;
mod limitations;
mod non_looming;
mod render;
mod several;
mod stimuli;
mod strength;

use harness::*;
use render::*;
use stimuli::*;

type Frame = [u8; PIXELS];

/// Horizontal centre of the retina (`X̄ = 49` is straight ahead).
const CENTRE: f32 = 49.0;

/// Still frames before a stimulus starts: the priming frame plus a few quiet ones.
const LEAD: usize = 5;

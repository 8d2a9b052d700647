//! The LGMD2 baseline (`alvs_sim::lgmd2`): hand-computed checks of each layer on tiny inputs,
//! whole-network properties (priming, rest, determinism, reset, extreme input), and the
//! looming clips of `data/clips` with a per-clip table for both parameter sets.

use alvs_host::{clip, data};
use alvs_sim::lgmd2::*;
use alvs_tasks::{Frame, PIXELS, WIDTH};
use std::io::Write;

pub(crate) fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 1e-4 * (1.0 + a.abs().max(b.abs()))
}

macro_rules! assert_close {
    ($a:expr, $b:expr) => {{
        let (a, b): (f32, f32) = ($a, $b);
        assert!(close(a, b), "{} = {a}, expected {b}", stringify!($a));
    }};
}

/// A dark square growing at the centre of a white frame, `2 + t` px half-side.
pub(crate) fn looming(t: usize) -> Frame {
    let half = 2 + t as i32;
    std::array::from_fn(|i| {
        let (x, y) = ((i % WIDTH) as i32 - 49, (i / WIDTH) as i32 - 36);
        if x.abs() < half && y.abs() < half {
            0
        } else {
            255
        }
    })
}

mod clips;
mod layers;
mod network;
mod robot;

//! Efference copy of forward motion: the way ahead is blocked (a closed-loop mechanism,
//! `Params::blocked_change` > 0; on in the default, off in the paper's model; measurements in
//! `docs/experiments.md`).
//!
//! A robot that commands forward travel sees its view change: textures grow and slide. One
//! pressed against a wall (or another robot) commands the same travel and sees nothing change.
//! The network reports a coarse [`View`] of each frame (9×9-pixel block means, 11×8 cells); the
//! escape FSM compares it with the view of `blocked_frames` frames earlier whenever it commanded
//! at least `blocked_travel_mm` of travel with little turning in between, and turns around when
//! the mean change is below `blocked_change` grey levels (measured separation and closed-loop
//! effect in `docs/experiments.md`, "Closed-loop mechanisms").

use crate::frame::{Frame, HEIGHT, WIDTH};

/// Pixels a side of a view cell.
pub const BLOCK: usize = 9;
/// View cells across.
pub const VIEW_W: usize = WIDTH / BLOCK;
/// View cells down.
pub const VIEW_H: usize = HEIGHT / BLOCK;
/// Cells of a view.
pub const VIEW_CELLS: usize = VIEW_W * VIEW_H;

/// A coarse view of a frame: the mean grey level of each 9×9 block.
pub type View = [u8; VIEW_CELLS];

const _: () = assert!(VIEW_W * BLOCK == WIDTH && VIEW_H * BLOCK == HEIGHT);

/// The view of `frame`.
pub fn view(frame: &Frame) -> View {
    let mut sums = [0u16; VIEW_CELLS];
    for (y, row) in frame.chunks_exact(WIDTH).enumerate() {
        // a row's 11 blocks of 9 pixels into its cells' sums (no division per pixel: the
        // firmware runs this on every frame)
        let line = sums.iter_mut().skip((y / BLOCK) * VIEW_W);
        for (s, block) in line.zip(row.chunks_exact(BLOCK)) {
            // ≤ 9 × 255 a block, ≤ 81 × 255 = 20,655 a cell: no overflow
            *s += block.iter().map(|&p| u16::from(p)).sum::<u16>();
        }
    }
    let mut v = [0u8; VIEW_CELLS];
    for (out, s) in v.iter_mut().zip(sums.iter()) {
        *out = (s / (BLOCK * BLOCK) as u16) as u8;
    }
    v
}

/// Mean absolute difference of two views, grey levels (rounded down).
pub fn change(a: &View, b: &View) -> u8 {
    let sum: u32 = a
        .iter()
        .zip(b.iter())
        .map(|(&x, &y)| u32::from(x.abs_diff(y)))
        .sum();
    (sum / VIEW_CELLS as u32) as u8
}

/// What the FSM tracks between two comparisons.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// The view at the start of the period.
    pub snapshot: Option<View>,
    /// Frames since the snapshot.
    pub frames: u32,
    /// Forward travel commanded since the snapshot, mm (the efference copy).
    pub travel_mm: f32,
    /// Heading at the snapshot, degrees.
    pub heading_deg: f32,
}

impl Progress {
    /// Nothing seen yet.
    pub const NEW: Progress = Progress {
        snapshot: None,
        frames: 0,
        travel_mm: 0.0,
        heading_deg: 0.0,
    };
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::PIXELS;

    #[test]
    fn view_is_the_block_means() {
        let mut f = [0u8; PIXELS];
        for (i, p) in f.iter_mut().enumerate() {
            let (x, y) = (i % WIDTH, i / WIDTH);
            *p = if x < BLOCK && y < BLOCK {
                200
            } else {
                (x % 2) as u8 * 100
            };
        }
        let v = view(&f);
        assert_eq!(v[0], 200);
        // columns 9..=17 alternate 100/0 from an odd one: 5 of 9 are 100 → 55
        assert_eq!(v[1], 55);
        assert_eq!(change(&v, &v), 0);
        let mut w = v;
        w[5] = w[5].wrapping_add(88);
        assert_eq!(change(&v, &w), 1, "88 levels on one cell of 88");
        assert_eq!(change(&[255; VIEW_CELLS], &[0; VIEW_CELLS]), 255);
    }

    #[test]
    fn the_network_reports_views_only_when_the_mechanism_is_on() {
        use crate::model::params::Efference;
        use crate::{Network, Params};
        use core::num::NonZeroU8;
        let frame = [77u8; PIXELS];
        let on = Params {
            efference: Efference {
                blocked_change: NonZeroU8::new(6),
                ..Params::ALVS.efference
            },
            ..Params::ALVS
        };
        let mut n = Network::new(on).unwrap();
        n.step(&frame);
        let vm = n.step(&frame).vm;
        assert_eq!(vm.view, Some(([77; VIEW_CELLS], 6)));
        let mut n = Network::alvs();
        n.step(&frame);
        assert_eq!(
            n.step(&frame).vm.view,
            None,
            "an option the default leaves off"
        );
        let mut n = Network::paper();
        n.step(&frame);
        assert_eq!(n.step(&frame).vm.view, None, "never in the paper's model");
    }
}

//! Scenes.

use super::*;

/// Frames `f(t)` for t = 0..n.
pub(crate) fn scene(n: usize, f: impl Fn(usize) -> Canvas) -> Vec<Frame> {
    (0..n).map(|t| f(t).frame()).collect()
}

/// Frames since the stimulus started moving: 0 during the lead, then 1, 2, ...
pub(crate) fn moving(t: usize) -> f32 {
    t.saturating_sub(LEAD - 1) as f32
}

/// An object whose half size changes linearly: `h0 + rate·k` at the k-th frame of motion.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Looming {
    pub(crate) cx: f32,
    pub(crate) cy: f32,
    pub(crate) h0: f32,
    /// Pixels per frame per edge; negative for a receding object.
    pub(crate) rate: f32,
    pub(crate) grey: f32,
}

impl Looming {
    /// An approaching square, 2 px in half size (5 px wide with the 3x3 retina blur) at onset.
    pub(crate) fn square(cx: f32, cy: f32, rate: f32, grey: f32) -> Self {
        Looming {
            cx,
            cy,
            h0: 2.0,
            rate,
            grey,
        }
    }

    pub(crate) fn half(&self, t: usize) -> f32 {
        (self.h0 + self.rate * moving(t)).max(0.5)
    }
}

/// `LEAD` still frames, then `n` frames of expansion (or contraction) of every object.
pub(crate) fn looming_scene(bg: &Canvas, objs: &[Looming], n: usize) -> Vec<Frame> {
    scene(LEAD + n, |t| {
        let mut c = bg.clone();
        for o in objs {
            c.square(o.cx, o.cy, o.half(t), o.grey);
        }
        c
    })
}

/// A disc of radius `r` metres approaching at `v` m/s from `d0` to `d1` metres at 30 fps, its
/// image size from the retina's α = 0.707°/px.
#[allow(clippy::too_many_arguments)]
pub(crate) fn looming_disc(
    bg: &Canvas,
    cx: f32,
    cy: f32,
    grey: f32,
    r: f32,
    v: f32,
    d0: f32,
    d1: f32,
) -> Vec<Frame> {
    let focal = 1.0 / 0.707f32.to_radians().tan();
    let n = ((d0 - d1) / v * 30.0) as usize;
    scene(LEAD + n, |t| {
        let d = d0 - v * moving(t) / 30.0;
        let mut c = bg.clone();
        c.disc(cx, cy, focal * r / d, grey);
        c
    })
}

/// A bar of `width` px crossing the whole retina at `speed` px/frame: vertical bars travel
/// left to right (right to left when `speed < 0`), horizontal bars top to bottom.
pub(crate) fn bar(bg: &Canvas, speed: f32, width: f32, grey: f32, vertical: bool) -> Vec<Frame> {
    let extent = if vertical { WIDTH } else { HEIGHT } as f32;
    let n = ((extent + 2.0 * width) / speed.abs()) as usize + LEAD;
    scene(n, |t| {
        let travelled = speed.abs() * moving(t);
        let a = if speed > 0.0 {
            -0.5 - width + travelled
        } else {
            extent - 0.5 - travelled
        };
        let mut c = bg.clone();
        if vertical {
            c.rect(a, a + width, -0.5, HEIGHT as f32, grey);
        } else {
            c.rect(-0.5, WIDTH as f32, a, a + width, grey);
        }
        c
    })
}

/// A square of half side `h` crossing the retina left to right along row `y`.
pub(crate) fn translating_square(bg: &Canvas, y: f32, h: f32, speed: f32, grey: f32) -> Vec<Frame> {
    let n = ((WIDTH as f32 + 4.0 * h) / speed) as usize + LEAD;
    scene(n, |t| {
        let mut c = bg.clone();
        c.square(-2.0 * h + speed * moving(t), y, h, grey);
        c
    })
}

/// 60 frames of a drifting grating: sine (`mean ± amp`) or square wave (`mean − amp` and
/// `mean + amp` half periods); vertical stripes drift rightwards, horizontal ones downwards.
pub(crate) fn grating(
    period: f32,
    speed: f32,
    mean: f32,
    amp: f32,
    square: bool,
    vertical: bool,
) -> Vec<Frame> {
    scene(60, |t| {
        let phase = speed * t as f32;
        if square {
            let mut c = Canvas::plain(mean - amp);
            let extent = if vertical { WIDTH } else { HEIGHT } as f32;
            let mut a = phase % period - period - 0.5;
            while a < extent {
                if vertical {
                    c.rect(a, a + period / 2.0, -0.5, HEIGHT as f32, mean + amp);
                } else {
                    c.rect(-0.5, WIDTH as f32, a, a + period / 2.0, mean + amp);
                }
                a += period;
            }
            c
        } else {
            let mut c = Canvas::plain(0.0);
            for y in 0..HEIGHT {
                for x in 0..WIDTH {
                    let u = if vertical { x } else { y } as f32 - phase;
                    c.0[y * WIDTH + x] = mean + amp * (u * std::f32::consts::TAU / period).sin();
                }
            }
            c
        }
    })
}

/// 60 frames of a still scene whose brightness steps between `−amp` and `+amp` every
/// `half_period` frames.
pub(crate) fn flicker(bg: &Canvas, amp: f32, half_period: usize) -> Vec<Frame> {
    let (lo, hi) = (bg.offset(-amp).frame(), bg.offset(amp).frame());
    (0..60)
        .map(|t| {
            if (t / half_period).is_multiple_of(2) {
                lo
            } else {
                hi
            }
        })
        .collect()
}

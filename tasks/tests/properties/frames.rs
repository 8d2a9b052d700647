//! Frames: compact descriptions (`Spec`) rendered to frames, and the strategies generating
//! sequences of them.

use super::*;

/// A frame, described compactly.
#[derive(Debug, Clone)]
pub(crate) enum Spec {
    Uniform(u8),
    /// Uniform noise in `lo..=hi` from a seed.
    Noise {
        seed: u64,
        lo: u8,
        hi: u8,
    },
    /// Checkerboard of `cell`-pixel squares of `a` and `b`, swapped when `phase`.
    Checker {
        cell: u8,
        a: u8,
        b: u8,
        phase: bool,
    },
    /// Square of half side `h` and grey `fg` centred on `(cx, cy)` over `bg`.
    Square {
        cx: u8,
        cy: u8,
        h: u8,
        fg: u8,
        bg: u8,
    },
    /// Linear ramp 0 → 255 across the frame.
    Gradient {
        horizontal: bool,
        invert: bool,
    },
}

impl Spec {
    pub(crate) fn render(&self) -> Frame {
        let mut f = [0u8; PIXELS];
        match *self {
            Spec::Uniform(v) => f = [v; PIXELS],
            Spec::Noise { seed, lo, hi } => {
                let (lo, hi) = (lo.min(hi), lo.max(hi));
                let mut s = seed | 1;
                for v in f.iter_mut() {
                    s ^= s << 13;
                    s ^= s >> 7;
                    s ^= s << 17;
                    *v = lo + (s % (u64::from(hi - lo) + 1)) as u8;
                }
            }
            Spec::Checker { cell, a, b, phase } => {
                let cell = usize::from(cell.max(1));
                for y in 0..HEIGHT {
                    for x in 0..WIDTH {
                        let odd = ((x / cell + y / cell) % 2 == 1) ^ phase;
                        f[y * WIDTH + x] = if odd { b } else { a };
                    }
                }
            }
            Spec::Square { cx, cy, h, fg, bg } => {
                f = [bg; PIXELS];
                let (cx, cy, h) = (usize::from(cx), usize::from(cy), usize::from(h));
                for y in cy.saturating_sub(h)..(cy + h + 1).min(HEIGHT) {
                    for x in cx.saturating_sub(h)..(cx + h + 1).min(WIDTH) {
                        f[y * WIDTH + x] = fg;
                    }
                }
            }
            Spec::Gradient { horizontal, invert } => {
                for y in 0..HEIGHT {
                    for x in 0..WIDTH {
                        let v = if horizontal {
                            x * 255 / (WIDTH - 1)
                        } else {
                            y * 255 / (HEIGHT - 1)
                        } as u8;
                        f[y * WIDTH + x] = if invert { 255 - v } else { v };
                    }
                }
            }
        }
        f
    }
}

fn spec() -> impl Strategy<Value = Spec> {
    prop_oneof![
        prop_oneof![Just(0u8), Just(255u8), any::<u8>()].prop_map(Spec::Uniform),
        (any::<u64>(), any::<u8>(), any::<u8>()).prop_map(|(seed, lo, hi)| Spec::Noise {
            seed,
            lo,
            hi
        }),
        (1u8..=16, any::<u8>(), any::<u8>(), any::<bool>())
            .prop_map(|(cell, a, b, phase)| Spec::Checker { cell, a, b, phase }),
        (0u8..99, 0u8..72, 0u8..60, any::<u8>(), any::<u8>())
            .prop_map(|(cx, cy, h, fg, bg)| Spec::Square { cx, cy, h, fg, bg }),
        (any::<bool>(), any::<bool>())
            .prop_map(|(horizontal, invert)| Spec::Gradient { horizontal, invert }),
    ]
}

/// Frame sequences: 2–6 arbitrary frames, or adversarial runs of up to 16 frames (all-0/all-255
/// alternation, inverting checkerboards, fresh full-range noise, an expanding square).
pub(crate) fn sequence() -> impl Strategy<Value = Vec<Spec>> {
    prop_oneof![
        3 => prop::collection::vec(spec(), 2..=6),
        1 => (2usize..=16, any::<bool>()).prop_map(|(n, start)| {
            (0..n)
                .map(|i| Spec::Uniform(if (i % 2 == 0) ^ start { 0 } else { 255 }))
                .collect()
        }),
        1 => (1u8..=12, 2usize..=16).prop_map(|(cell, n)| {
            (0..n)
                .map(|i| Spec::Checker { cell, a: 0, b: 255, phase: i % 2 == 1 })
                .collect()
        }),
        1 => prop::collection::vec(any::<u64>(), 2..=16).prop_map(|seeds| {
            seeds
                .into_iter()
                .map(|seed| Spec::Noise { seed, lo: 0, hi: 255 })
                .collect()
        }),
        2 => growing_square(0u8..99, 0u8..72, 1u8..=4, 2usize..=16),
    ]
}

/// A square of any grey on any background, centred at a drawn `(cx, cy)`, whose side grows by
/// a drawn `rate` pixels a frame over a drawn number of frames.
pub(crate) fn growing_square(
    cx: impl Strategy<Value = u8>,
    cy: impl Strategy<Value = u8>,
    rate: impl Strategy<Value = u8>,
    frames: impl Strategy<Value = usize>,
) -> impl Strategy<Value = Vec<Spec>> {
    (cx, cy, rate, frames, any::<u8>(), any::<u8>()).prop_map(|(cx, cy, rate, n, fg, bg)| {
        (0..n)
            .map(|i| Spec::Square {
                cx,
                cy,
                h: 1 + rate * i as u8,
                fg,
                bg,
            })
            .collect()
    })
}

pub(crate) fn render(specs: &[Spec]) -> Vec<Frame> {
    specs.iter().map(Spec::render).collect()
}

//! Rendering.

use super::*;

/// Small deterministic PRNG (xorshift64*): seeded scenes without another dependency.
pub(crate) struct Rng(u64);

impl Rng {
    pub(crate) fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform integer in `lo..=hi`.
    pub(crate) fn range(&mut self, lo: i32, hi: i32) -> i32 {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as i32
    }
}

/// A grey-level picture in f32, rounded and clipped to 0..=255 only when it becomes a frame.
#[derive(Clone)]
pub(crate) struct Canvas(pub(crate) Vec<f32>);

impl Canvas {
    pub(crate) fn plain(g: f32) -> Self {
        Canvas(vec![g; PIXELS])
    }

    /// Random blocks of `cell` x `cell` pixels with grey levels `mean ± amp`, seeded.
    pub(crate) fn textured(mean: f32, amp: i32, cell: usize, seed: u64) -> Self {
        let mut rng = Rng::new(seed);
        let cw = WIDTH.div_ceil(cell);
        let cells: Vec<f32> = (0..cw * HEIGHT.div_ceil(cell))
            .map(|_| mean + rng.range(-amp, amp) as f32)
            .collect();
        let mut c = Canvas::plain(0.0);
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                c.0[y * WIDTH + x] = cells[(y / cell) * cw + x / cell];
            }
        }
        c
    }

    /// The rectangle `[x0, x1) x [y0, y1)` in continuous coordinates, blended by covered area.
    pub(crate) fn rect(&mut self, x0: f32, x1: f32, y0: f32, y1: f32, g: f32) {
        let cover = |lo: f32, hi: f32, p: usize| {
            let p = p as f32;
            (hi.min(p + 0.5) - lo.max(p - 0.5)).clamp(0.0, 1.0)
        };
        let span = |lo: f32, hi: f32, n: usize| {
            let a = (lo + 0.5).floor().clamp(0.0, n as f32) as usize;
            let b = ((hi + 0.5).ceil().max(0.0) as usize).min(n);
            (a, b)
        };
        let ((xa, xb), (ya, yb)) = (span(x0, x1, WIDTH), span(y0, y1, HEIGHT));
        for y in ya..yb {
            let cy = cover(y0, y1, y);
            for x in xa..xb {
                let a = cy * cover(x0, x1, x);
                let v = &mut self.0[y * WIDTH + x];
                *v = *v * (1.0 - a) + g * a;
            }
        }
    }

    /// Square of half side `h` centred on `(cx, cy)`.
    pub(crate) fn square(&mut self, cx: f32, cy: f32, h: f32, g: f32) {
        self.rect(cx - h, cx + h, cy - h, cy + h, g);
    }

    /// Disc of radius `r` centred on `(cx, cy)`.
    pub(crate) fn disc(&mut self, cx: f32, cy: f32, r: f32, g: f32) {
        let lo = |c: f32| (c - r).floor().max(0.0) as usize;
        let hi = |c: f32, n: usize| ((c + r).ceil() + 1.0).clamp(0.0, n as f32) as usize;
        for y in lo(cy)..hi(cy, HEIGHT) {
            for x in lo(cx)..hi(cx, WIDTH) {
                let mut hits = 0;
                for sy in 0..4 {
                    for sx in 0..4 {
                        let px = x as f32 + (sx as f32 - 1.5) / 4.0 - cx;
                        let py = y as f32 + (sy as f32 - 1.5) / 4.0 - cy;
                        hits += usize::from(px * px + py * py <= r * r);
                    }
                }
                let a = hits as f32 / 16.0;
                let v = &mut self.0[y * WIDTH + x];
                *v = *v * (1.0 - a) + g * a;
            }
        }
    }

    /// The same picture `d` grey levels brighter.
    pub(crate) fn offset(&self, d: f32) -> Canvas {
        Canvas(self.0.iter().map(|v| v + d).collect())
    }

    pub(crate) fn frame(&self) -> Frame {
        let mut f = [0u8; PIXELS];
        for (o, &v) in f.iter_mut().zip(self.0.iter()) {
            *o = v.round().clamp(0.0, 255.0) as u8;
        }
        f
    }
}

/// Adds seeded uniform sensor noise of `±amp` grey levels to every pixel of every frame.
pub(crate) fn add_noise(frames: &[Frame], amp: i32, seed: u64) -> Vec<Frame> {
    let mut rng = Rng::new(seed);
    frames
        .iter()
        .map(|f| {
            let mut g = *f;
            for v in g.iter_mut() {
                *v = (i32::from(*v) + rng.range(-amp, amp)).clamp(0, 255) as u8;
            }
            g
        })
        .collect()
}

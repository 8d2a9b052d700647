//! Noise frames, a closed-loop mechanism the paper leaves out (`docs/model.md`, "Closed-loop
//! mechanisms", with its measured effect).
//!
//! A picture that came through a lens has neighbouring pixels alike: the optics blur, the
//! OV7670 averages its photosites down to 99x72, and the world is made of surfaces. On every
//! frame of the recorded clips the correlation of neighbouring pixels is 0.55 or more along
//! the rows or down the columns (the lowest: the helmet clip); a frame of independent random
//! pixels measures 0 ± 0.05 in both. Such a frame is not an image of anything (a corrupted
//! transfer, interference, a sensor fault), yet every pixel of it changes and the correlators
//! of Eq. (6) find "motion" in every direction in every quadrant, so Eq. (9)'s gate opens. The
//! frame after it is measured against it and is as meaningless. This detector reports such
//! frames so that the network stimulates no field on them, as it does for a whole-field
//! luminance event ([`crate::model::closed_loop::luminance`]).

use crate::frame::{Frame, HEIGHT, WIDTH};

/// Every how many pixels one is sampled: 436 samples measure a noise frame's correlation of 0
/// to ± 0.05 and the clips' frames within 0.03 of every 8th pixel's figure, at a sixteenth of
/// the cost of every pixel (≈ 6 k cycles a frame, `docs/budget.md`). 99 mod 16 = 3, so the
/// sampled columns shift from row to row.
pub const SAMPLE_STEP: usize = 16;

/// The mean squared difference of neighbouring pixels must reach this many grey levels²
/// (a root mean square of 8 levels) for the frame to count as noise: four times the
/// camera's own noise of about 2 levels per pixel (`docs/world.md`), so a plain scene with
/// the sensor's grain in it is left alone.
pub const FLOOR_SQ: u32 = 64;

/// Sums over the sampled pixels of one frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Grain {
    /// Pixels sampled.
    pub n: u32,
    /// `Σ L`.
    pub sum: u32,
    /// `Σ L²`.
    pub sum_sq: u32,
    /// `Σ (L(x+1, y) − L(x, y))²`.
    pub right_sq: u32,
    /// `Σ (L(x, y+1) − L(x, y))²`.
    pub down_sq: u32,
}

/// The sums of `frame`, on every [`SAMPLE_STEP`]-th pixel that has a right and a lower
/// neighbour. At most 7,128 / 16 samples of 255² each: every sum fits in `u32`.
pub fn grain(frame: &Frame) -> Grain {
    let mut g = Grain::default();
    // the last row has no lower neighbour
    for y in 0..HEIGHT - 1 {
        let Some(rows) = frame.get(y * WIDTH..(y + 2) * WIDTH) else {
            break;
        };
        // the first sampled column of row `y`: pixel indices divisible by the step
        let mut x = (SAMPLE_STEP - y * WIDTH % SAMPLE_STEP) % SAMPLE_STEP;
        while x < WIDTH - 1 {
            if let (Some(&l), Some(&r), Some(&d)) =
                (rows.get(x), rows.get(x + 1), rows.get(x + WIDTH))
            {
                let (l, r, d) = (i32::from(l), i32::from(r), i32::from(d));
                g.n += 1;
                g.sum += l as u32;
                g.sum_sq += (l * l) as u32;
                g.right_sq += ((r - l) * (r - l)) as u32;
                g.down_sq += ((d - l) * (d - l)) as u32;
            }
            x += SAMPLE_STEP;
        }
    }
    g
}

/// Whether a frame with these sums is noise: the correlation of neighbouring pixels,
/// `1 − E[(ΔL)²] / (2·Var L)`, lies below `pct` % both along the rows and down the columns,
/// and the neighbours differ by more than the sensor's grain ([`FLOOR_SQ`]). Stripes one
/// pixel wide are unlike their neighbours in one direction only and are not noise.
/// `pct = 0` is off.
pub fn is_noise(g: &Grain, pct: u8) -> bool {
    if pct == 0 || g.n == 0 {
        return false;
    }
    let n = u64::from(g.n);
    // n²·Var L
    let var_n2 = (n * u64::from(g.sum_sq)).saturating_sub(u64::from(g.sum).pow(2));
    // correlation < pct %  ⇔  100·E[(ΔL)²] > (100 − pct)·2·Var L, both sides times n²
    let keep = u64::from(100u8.saturating_sub(pct)) * 2 * var_n2;
    let unlike = |sq: u32| 100 * n * u64::from(sq) > keep && sq >= g.n * FLOOR_SQ;
    unlike(g.right_sq) && unlike(g.down_sq)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::PIXELS;

    fn noise(amp: i32, seed: u32) -> Frame {
        let mut s = seed.wrapping_mul(2_654_435_761) | 1;
        core::array::from_fn(|_| {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            (128 + (s % (2 * amp as u32 + 1)) as i32 - amp).clamp(0, 255) as u8
        })
    }

    fn from_fn(f: impl Fn(usize, usize) -> u8) -> Frame {
        core::array::from_fn(|i| f(i % WIDTH, i / WIDTH))
    }

    #[test]
    fn random_pixels_are_noise_at_every_contrast_above_the_grain() {
        for seed in 1..20 {
            for amp in [16, 32, 64, 128, 255] {
                assert!(
                    is_noise(&grain(&noise(amp, seed)), 25),
                    "±{amp} seed {seed}"
                );
            }
            // the sensor's own grain on a plain wall is not
            assert!(!is_noise(&grain(&noise(4, seed)), 25), "seed {seed}");
        }
    }

    #[test]
    fn pictures_are_not_noise() {
        let scenes = [
            // edges, a gradient, blocks of 3 px, a fine grating of period 6
            from_fn(|x, _| if x < 50 { 20 } else { 230 }),
            from_fn(|x, y| (x + 2 * y) as u8),
            from_fn(|x, y| if (x / 3 + y / 3) % 2 == 0 { 0 } else { 255 }),
            from_fn(|x, _| [0, 128, 255, 255, 128, 0][x % 6]),
            // stripes one pixel wide: unlike along the rows, alike down the columns
            from_fn(|x, _| if x % 2 == 0 { 0 } else { 255 }),
            from_fn(|_, y| if y % 2 == 0 { 0 } else { 255 }),
            [128; PIXELS],
        ];
        for (k, f) in scenes.iter().enumerate() {
            assert!(!is_noise(&grain(f), 25), "scene {k}: {:?}", grain(f));
        }
    }

    #[test]
    fn off_is_never_noise_and_the_sums_hold_at_full_contrast() {
        let f = from_fn(|x, y| if (x + y) % 2 == 0 { 0 } else { 255 });
        let g = grain(&f);
        assert_eq!(g.n, 436);
        assert_eq!(g.right_sq, g.n * 255 * 255);
        assert!(
            is_noise(&g, 25),
            "a 1 px checkerboard is unlike in both directions"
        );
        assert!(!is_noise(&g, 0));
        assert!(!is_noise(&Grain::default(), 25));
    }
}

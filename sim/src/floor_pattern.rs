//! A pattern on the floor (the robustness suite's textured and shaded floors): the floor's grey,
//! [`super::FloorShade`] by viewing distance, is multiplied by `1 + contrast · n(x, y)` where
//! `n` is a sum of octaves of value noise fixed to the floor.
//!
//! # Noise
//!
//! Each octave is a lattice of independent uniform values in [−1, 1], one per `λ` mm (its
//! wavelength), interpolated with a smoothstep in x and in y. Octaves run from
//! [`FloorPattern::finest_mm`] up, doubling, to [`FloorPattern::coarsest_mm`], with equal
//! weights; the sum is scaled to unit RMS, so [`FloorPattern::contrast`] is the RMS of the
//! relative grey variation. (For smoothstep weights `s = 3t² − 2t³`, `E[s²] = E[(1 − s)²] =
//! 13/35`, so one octave's variance is `(26/35)² / 3`.)
//!
//! # Filtering
//!
//! A pixel sees a patch of floor, not a point: at axial depth `s` it spans `s/f` mm across and
//! `s²/(f·h)` mm along the view (the floor is seen at a grazing angle, so the patch is long and
//! narrow). An octave finer than two footprints would alias and shimmer as the robot moves, and
//! shimmer is motion to a looming detector; as a GPU's anisotropic filter does, the pixel takes
//! the mean of up to [`MAX_SAMPLES`] samples spread along its long side (no closer than a
//! quarter of the finest octave), each of which fades out the octaves finer than four of its
//! own (shorter) footprints, linearly down to zero at two: what averaging a zero-mean pattern
//! over the pixel does. The lattices are precomputed over the arena (tiling beyond it).

use super::rng::Rng;
use super::world::Arena;

/// A pattern fixed to the floor: which scales, how strong, which seed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FloorPattern {
    /// RMS of the relative grey variation (0.1 = the floor's grey varies by 10 % RMS).
    pub contrast: f32,
    /// Wavelength of the finest octave, mm.
    pub finest_mm: f32,
    /// Wavelength of the coarsest octave, mm (octaves double from the finest up to this).
    pub coarsest_mm: f32,
    /// Seed of the lattices.
    pub seed: u64,
}

impl FloorPattern {
    /// The octaves' wavelengths, mm: the finest, doubling, up to the coarsest (at least one).
    pub fn wavelengths(&self) -> Vec<f32> {
        let mut v = vec![self.finest_mm];
        while v.len() < 16 && v[v.len() - 1] * 2.0 <= self.coarsest_mm * 1.0001 {
            v.push(v[v.len() - 1] * 2.0);
        }
        v
    }

    /// Checks the numbers (one line): a contrast in 0..1, wavelengths positive and ordered.
    pub fn check(&self) -> anyhow::Result<()> {
        anyhow::ensure!(
            self.contrast.is_finite() && (0.0..1.0).contains(&self.contrast),
            "floor pattern contrast must be in 0..1, got {}",
            self.contrast
        );
        anyhow::ensure!(
            self.finest_mm.is_finite()
                && self.finest_mm > 0.0
                && self.coarsest_mm.is_finite()
                && self.coarsest_mm >= self.finest_mm,
            "floor pattern wavelengths must be positive with finest <= coarsest, got {} and {}",
            self.finest_mm,
            self.coarsest_mm
        );
        Ok(())
    }
}

/// Variance of one octave of smoothstep value noise over uniform [−1, 1] lattice values.
const OCTAVE_VARIANCE: f32 = (26.0 / 35.0) * (26.0 / 35.0) / 3.0;

/// Most lattice points kept per octave and axis (a finer octave tiles).
const MAX_LATTICE: usize = 1024;

/// Most samples a pixel takes along its long side on the floor (each costs every active
/// octave's look-up: with 4, a frame over the textured floor takes ≈ 10 times a plain one's
/// rendering, ≈ 3 times the whole robot-frame's time).
pub const MAX_SAMPLES: usize = 4;

/// One octave's lattice: `nx` by `ny` values, both powers of two (so that wrapping an index is
/// a mask).
#[derive(Debug, Clone)]
struct Octave {
    wavelength: f32,
    /// `1 / wavelength`.
    per_mm: f32,
    nx: usize,
    ny: usize,
    values: Vec<f32>,
}

impl Octave {
    fn at(&self, x_mm: f32, y_mm: f32) -> f32 {
        let (gx, gy) = (x_mm * self.per_mm, y_mm * self.per_mm);
        let (fx, fy) = (floor(gx), floor(gy));
        let (tx, ty) = (smoothstep(gx - fx as f32), smoothstep(gy - fy as f32));
        // two's complement: the mask wraps negative cells too
        let i0 = (fx as usize) & (self.nx - 1);
        let j0 = (fy as usize) & (self.ny - 1);
        let (i1, j1) = ((i0 + 1) & (self.nx - 1), (j0 + 1) & (self.ny - 1));
        let v = |i: usize, j: usize| self.values[j * self.nx + i];
        let top = v(i0, j0) + tx * (v(i1, j0) - v(i0, j0));
        let bottom = v(i0, j1) + tx * (v(i1, j1) - v(i0, j1));
        top + ty * (bottom - top)
    }
}

/// `x` rounded down, for the lattice's range (|x| < 2³¹): without SSE4.1, `f32::floor` is a
/// call into libm, which cost more than the rest of a look-up.
fn floor(x: f32) -> i64 {
    let i = x as i64;
    if (i as f32) > x {
        i - 1
    } else {
        i
    }
}

fn smoothstep(t: f32) -> f32 {
    t * t * (3.0 - 2.0 * t)
}

/// A [`FloorPattern`] precomputed for one arena.
#[derive(Debug, Clone)]
pub struct FloorMap {
    contrast: f32,
    finest_mm: f32,
    /// `contrast` over the RMS of the octaves' sum.
    gain: f32,
    octaves: Vec<Octave>,
}

impl FloorMap {
    /// The lattices of `pattern` over `arena`.
    pub fn new(pattern: &FloorPattern, arena: &Arena) -> Self {
        let rng = Rng::new(pattern.seed);
        let octaves: Vec<Octave> = pattern
            .wavelengths()
            .into_iter()
            .enumerate()
            .map(|(k, wavelength)| {
                let cells = |size: f64| {
                    ((size / f64::from(wavelength)).ceil() as usize + 2)
                        .next_power_of_two()
                        .clamp(2, MAX_LATTICE)
                };
                let (nx, ny) = (cells(arena.size_x_mm), cells(arena.size_y_mm));
                let mut r = rng.fork(k as u64);
                let values = (0..nx * ny)
                    .map(|_| (2.0 * r.uniform() - 1.0) as f32)
                    .collect();
                Octave {
                    wavelength,
                    per_mm: 1.0 / wavelength,
                    nx,
                    ny,
                    values,
                }
            })
            .collect();
        let rms = (octaves.len() as f32 * OCTAVE_VARIANCE).sqrt();
        FloorMap {
            contrast: pattern.contrast,
            finest_mm: pattern.finest_mm,
            gain: pattern.contrast / rms,
            octaves,
        }
    }

    /// The factor on the floor's grey seen by a pixel centred on the floor point (x, y) whose
    /// footprint is `across_mm` wide and `along_mm` long in the unit direction `view` (the
    /// view's on the floor): `1 + contrast · n`, `n` filtered over the footprint (see the
    /// module documentation); never below 0.
    pub fn factor(
        &self,
        (x_mm, y_mm): (f32, f32),
        view: (f32, f32),
        across_mm: f32,
        along_mm: f32,
    ) -> f32 {
        let across = across_mm.max(1e-6);
        let along = along_mm.max(across);
        // samples no closer than a quarter of the finest octave: closer ones would see the same
        let spacing = across.max(0.25 * self.finest_mm);
        let samples = ((along / spacing).ceil() as usize).clamp(1, MAX_SAMPLES);
        let step = along / samples as f32;
        let footprint = step.max(across);
        let mut n = 0.0;
        for o in &self.octaves {
            let w = ((o.wavelength / footprint - 2.0) * 0.5).clamp(0.0, 1.0);
            if w == 0.0 {
                continue;
            }
            let mut sum = 0.0;
            for k in 0..samples {
                let t = (k as f32 + 0.5) * step - 0.5 * along;
                sum += o.at(x_mm + t * view.0, y_mm + t * view.1);
            }
            n += w * sum;
        }
        (1.0 + self.gain * n / samples as f32).max(0.0)
    }

    /// The pattern's RMS relative contrast.
    pub fn contrast(&self) -> f32 {
        self.contrast
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pattern() -> FloorPattern {
        FloorPattern {
            contrast: 0.1,
            finest_mm: 5.0,
            coarsest_mm: 80.0,
            seed: 3,
        }
    }

    #[test]
    fn octaves_double_from_the_finest_to_the_coarsest() {
        assert_eq!(pattern().wavelengths(), vec![5.0, 10.0, 20.0, 40.0, 80.0]);
        let one = FloorPattern {
            coarsest_mm: 5.0,
            ..pattern()
        };
        assert_eq!(one.wavelengths(), vec![5.0]);
    }

    /// Sharp up close: the RMS of the factor is the contrast (within sampling error); a pixel
    /// wider than every octave sees the mean floor; a long narrow one keeps some contrast (the
    /// octaves wider than its width, averaged along its length), less than a small one.
    #[test]
    fn the_contrast_is_the_rms_and_a_wide_pixel_sees_the_mean() {
        let arena = Arena::new(1309.0, 751.0);
        let map = FloorMap::new(&pattern(), &arena);
        let mut rng = Rng::new(9);
        let n = 20_000;
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let (x, y) = (rng.range(0.0, 1309.0) as f32, rng.range(0.0, 751.0) as f32);
            let d = f64::from(map.factor((x, y), (1.0, 0.0), 0.5, 0.5) - 1.0);
            sum += d;
            sum2 += d * d;
            assert_eq!(map.factor((x, y), (0.0, 1.0), 100.0, 100.0), 1.0);
        }
        let rms = (sum2 / n as f64).sqrt();
        let streak: f64 = (0..2000)
            .map(|k| {
                let (x, y) = (200.0 + 0.37 * k as f32, 300.0 + 0.11 * k as f32);
                f64::from(map.factor((x, y), (0.0, 1.0), 3.0, 100.0) - 1.0).powi(2)
            })
            .sum::<f64>()
            / 2000.0;
        assert!(
            (0.0005..rms * rms / 2.0).contains(&streak),
            "{streak} against {}",
            rms * rms
        );
        assert!((rms - 0.1).abs() < 0.015, "rms {rms}");
        assert!((sum / n as f64).abs() < 0.01, "mean {}", sum / n as f64);
    }

    #[test]
    fn bad_numbers_are_refused() {
        assert!(pattern().check().is_ok());
        for bad in [
            FloorPattern {
                contrast: f32::NAN,
                ..pattern()
            },
            FloorPattern {
                contrast: 1.5,
                ..pattern()
            },
            FloorPattern {
                finest_mm: 0.0,
                ..pattern()
            },
            FloorPattern {
                coarsest_mm: 2.0,
                ..pattern()
            },
        ] {
            let e = bad.check().unwrap_err().to_string();
            assert_eq!(e.lines().count(), 1, "{e}");
        }
    }
}

//! The arena's random numbers: SplitMix64, seeded and forkable, so that every run is a pure
//! function of its `--seed` (same seed → identical poses and frames, on every machine).
//!
//! SplitMix64 (Steele, Lea and Flood 2014) passes BigCrush, costs one add and three
//! multiply-xor-shifts per number, and has no dependency. Each noisy component (a camera, a
//! robot's motors, its gyro, a texture) takes its own stream from [`Rng::fork`], so adding a
//! robot or turning sensor noise on does not shift the numbers any other component draws.

/// A SplitMix64 generator.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rng {
    state: u64,
}

const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;

fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl Rng {
    /// A generator for `seed`.
    pub fn new(seed: u64) -> Self {
        Rng { state: mix(seed) }
    }

    /// An independent generator for sub-stream `stream` of this one's seed; does not advance
    /// `self`. `Rng::new(s).fork(k)` is the same for the same `(s, k)`.
    pub fn fork(&self, stream: u64) -> Self {
        Rng {
            state: mix(self.state ^ mix(stream.wrapping_add(GOLDEN))),
        }
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(GOLDEN);
        mix(self.state)
    }

    /// Uniform in [0, 1).
    #[inline]
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [lo, hi).
    #[inline]
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// Uniform integer in `0..n` (`n > 0`; 0 gives 0).
    #[inline]
    pub fn below(&mut self, n: u64) -> u64 {
        if n == 0 {
            0
        } else {
            ((u128::from(self.next_u64()) * u128::from(n)) >> 64) as u64
        }
    }

    /// Approximately standard normal: the Irwin–Hall sum of four 16-bit uniforms, centred and
    /// scaled to unit variance (range ±3.46). One 64-bit draw, no transcendental function: cheap
    /// enough for per-pixel sensor noise, and as good as a Gaussian for every noise here.
    #[inline]
    pub fn normal(&mut self) -> f32 {
        let r = self.next_u64();
        let sum = (r & 0xffff) + ((r >> 16) & 0xffff) + ((r >> 32) & 0xffff) + (r >> 48);
        // Each term is uniform on [0, 65535]: mean 2·65535, variance 4·(65536² − 1)/12.
        const SCALE: f32 = 1.732_050_8 / 65_536.0;
        (sum as f32 - 2.0 * 65_535.0) * SCALE
    }

    /// Two approximately standard normal numbers from one 64-bit draw: each is the Irwin–Hall
    /// sum of four bytes, centred and scaled to unit variance (range ±3.46). Half the cost of
    /// two [`Rng::normal`] calls, for per-pixel sensor noise.
    #[inline]
    pub fn normal_pair(&mut self) -> (f32, f32) {
        let r = self.next_u64();
        // Both halves' byte sums at once (SWAR): add neighbouring bytes into 16-bit lanes, then
        // neighbouring lanes into 32-bit lanes. Exactly the sums of the four bytes of each half,
        // in about half the operations of summing them one by one (this runs per pixel pair).
        const BYTES: u64 = 0x00ff_00ff_00ff_00ff;
        const PAIRS: u64 = 0x0000_ffff_0000_ffff;
        let pairs = (r & BYTES) + ((r >> 8) & BYTES);
        let sums = (pairs & PAIRS) + ((pairs >> 16) & PAIRS);
        // Each byte: mean 127.5, variance (256² − 1)/12; four of them: sd 147.80.
        const SCALE: f32 = 1.0 / 147.799_86;
        (
            ((sums & 0xffff_ffff) as f32 - 510.0) * SCALE,
            ((sums >> 32) as f32 - 510.0) * SCALE,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let a: Vec<u64> = (0..4).map(|_| Rng::new(7).next_u64()).collect();
        assert!(a.iter().all(|&x| x == a[0]));
        let mut f1 = Rng::new(7).fork(1);
        let mut f1b = Rng::new(7).fork(1);
        let mut f2 = Rng::new(7).fork(2);
        let x = f1.next_u64();
        assert_eq!(x, f1b.next_u64());
        assert_ne!(x, f2.next_u64());
    }

    #[test]
    fn normal_pair_sums_the_bytes_of_each_half() {
        let (mut a, mut b) = (Rng::new(9), Rng::new(9));
        for _ in 0..1000 {
            let r = b.next_u64();
            let sum4 = |x: u64| (0..4).map(|k| (x >> (8 * k)) & 0xff).sum::<u64>();
            let expect = (
                (sum4(r) as f32 - 510.0) / 147.799_86,
                (sum4(r >> 32) as f32 - 510.0) / 147.799_86,
            );
            let got = a.normal_pair();
            assert!((got.0 - expect.0).abs() < 1e-6 && (got.1 - expect.1).abs() < 1e-6);
        }
    }

    #[test]
    fn normal_has_unit_variance() {
        let mut r = Rng::new(3);
        let n = 200_000;
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let x = f64::from(r.normal());
            s += x;
            s2 += x * x;
        }
        let mean = s / n as f64;
        let var = s2 / n as f64 - mean * mean;
        assert!(mean.abs() < 0.01, "{mean}");
        assert!((var - 1.0).abs() < 0.02, "{var}");
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n / 2 {
            let (a, b) = r.normal_pair();
            s += f64::from(a) + f64::from(b);
            s2 += f64::from(a * a) + f64::from(b * b);
        }
        let mean = s / n as f64;
        let var = s2 / n as f64 - mean * mean;
        assert!(mean.abs() < 0.01, "{mean}");
        assert!((var - 1.0).abs() < 0.02, "{var}");
        let u: f64 = (0..n).map(|_| r.uniform()).sum::<f64>() / n as f64;
        assert!((u - 0.5).abs() < 0.005);
        assert!((0..1000).all(|_| r.below(5) < 5));
    }
}

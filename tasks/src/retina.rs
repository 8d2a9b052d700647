//! Retina and lamina: Eqs. (1)–(2) of the paper.
//!
//! * Retina, `R(x,y,t) = P(x,y,t) − P(x,y,t−1)` — the brightness change of each photoreceptor.
//! * ON/OFF half-wave rectification, Eq. (1): `L_ON = w·(R+|R|)/2`, `L_OFF = (|R|−R)/2`.
//! * 3x3 mean, Eq. (2), on both channels.
//!
//! Stored representation: the maps kept between frames are 8-bit grey-level means of the
//! *unweighted* rectified change, `on = ⌊Σ₃ₓ₃ max(R,0) / 9⌋` and `off = ⌊Σ₃ₓ₃ max(−R,0) / 9⌋`.
//! The ON weight `w` and the retina gain are applied where the maps are read ([`Weights`]), so no
//! precision is lost to `w = 0.25` and both maps fit a byte (two frames of history = 28.5 KB).
//!
//! Border (the paper is silent): there are no photoreceptors outside the retina, so the change
//! outside is 0 and border pixels are still divided by 9.

use crate::frame::{Frame, HEIGHT, PIXELS, WIDTH};
use crate::params::Params;

/// `⌊s / 9⌋` for a 3x3 sum of bytes (`s ≤ 2295`) as a multiply and shift (exact on that range,
/// checked by a test), since the Cortex-M4 divider takes up to 12 cycles.
#[inline(always)]
pub fn div9(s: u16) -> u8 {
    ((u32::from(s) * 7282) >> 16) as u8
}

/// Eqs. (1)–(2): the ON and OFF maps of the change from `prev` to `cur`, 3x3-averaged.
///
/// One pass over the frame: each row's horizontal 3-sums go into a 3-row ring, and a row of
/// output is written as soon as the row below it has been summed.
pub fn on_off_mean(cur: &Frame, prev: &Frame, on: &mut [u8; PIXELS], off: &mut [u8; PIXELS]) {
    // Horizontal 3-sums of rows y-1, y, y+1 (index y % 3); a row outside the retina sums to 0.
    let mut h_on = [[0u16; WIDTH]; 3];
    let mut h_off = [[0u16; WIDTH]; 3];
    row_sums(cur, prev, 0, &mut h_on[0], &mut h_off[0]);
    for y in 0..HEIGHT {
        let below = (y + 1) % 3;
        if y + 1 < HEIGHT {
            row_sums(cur, prev, y + 1, &mut h_on[below], &mut h_off[below]);
        } else {
            h_on[below] = [0; WIDTH];
            h_off[below] = [0; WIDTH];
        }
        // Row y-1 is in slot (y+2)%3; for y = 0 that slot is still zero (never written).
        let above = (y + 2) % 3;
        let mid = y % 3;
        let out_on = &mut on[y * WIDTH..(y + 1) * WIDTH];
        let out_off = &mut off[y * WIDTH..(y + 1) * WIDTH];
        for x in 0..WIDTH {
            out_on[x] = div9(h_on[above][x] + h_on[mid][x] + h_on[below][x]);
            out_off[x] = div9(h_off[above][x] + h_off[mid][x] + h_off[below][x]);
        }
    }
}

/// Horizontal 3-sums of the rectified change of row `y`.
fn row_sums(cur: &Frame, prev: &Frame, y: usize, on: &mut [u16; WIDTH], off: &mut [u16; WIDTH]) {
    let c = &cur[y * WIDTH..(y + 1) * WIDTH];
    let p = &prev[y * WIDTH..(y + 1) * WIDTH];
    let mut r_on = [0u16; WIDTH + 2];
    let mut r_off = [0u16; WIDTH + 2];
    for x in 0..WIDTH {
        // Eq. (1) without the weight: R > 0 feeds ON, R < 0 feeds OFF.
        let r = i16::from(c[x]) - i16::from(p[x]);
        r_on[x + 1] = r.max(0) as u16;
        r_off[x + 1] = (-r).max(0) as u16;
    }
    for x in 0..WIDTH {
        on[x] = r_on[x] + r_on[x + 1] + r_on[x + 2];
        off[x] = r_off[x] + r_off[x + 1] + r_off[x + 2];
    }
}

/// How the stored byte maps become model values: `L̂_ON = gain·w·on`, `L̂_OFF = gain·off`,
/// as Q8 fixed-point factors fixed once per parameter set (f32 never enters a pixel loop).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Weights {
    /// `gain · w` in Q8.
    pub on_q8: u32,
    /// `gain` in Q8.
    pub off_q8: u32,
}

impl Weights {
    /// Factors for `p` (assumed validated).
    pub fn new(p: &Params) -> Self {
        let g = u32::from(p.gain);
        Weights {
            on_q8: (f32::from(p.gain) * p.w * 256.0 + 0.5) as u32,
            off_q8: g * 256,
        }
    }

    /// `L̂_t = L̂_ON + L̂_OFF` in model units (the saliency of Eqs. 3–4).
    #[inline(always)]
    pub fn saliency(&self, on: u8, off: u8) -> u32 {
        (self.on_q8 * u32::from(on) + self.off_q8 * u32::from(off)) >> 8
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn div9_is_exact_floor_on_its_range() {
        for s in 0..=2295u16 {
            assert_eq!(u16::from(div9(s)), s / 9, "s = {s}");
        }
    }

    #[test]
    fn on_off_split_and_mean_by_hand() {
        // One pixel brightens by 90 at (10,10), another darkens by 45 at (50,30).
        let prev = [100u8; PIXELS];
        let mut cur = prev;
        cur[10 * WIDTH + 10] = 190;
        cur[30 * WIDTH + 50] = 55;
        let (mut on, mut off) = ([0u8; PIXELS], [0u8; PIXELS]);
        on_off_mean(&cur, &prev, &mut on, &mut off);
        // the 3x3 neighbourhood of the ON pixel holds 90/9 = 10, nothing in OFF
        for y in 9..=11 {
            for x in 9..=11 {
                assert_eq!(on[y * WIDTH + x], 10);
                assert_eq!(off[y * WIDTH + x], 0);
            }
        }
        assert_eq!(on[10 * WIDTH + 12], 0);
        assert_eq!(on[8 * WIDTH + 10], 0);
        // OFF: 45/9 = 5 around (50,30)
        assert_eq!(off[30 * WIDTH + 50], 5);
        assert_eq!(off[31 * WIDTH + 51], 5);
        assert_eq!(off[32 * WIDTH + 50], 0);
        assert_eq!(on.iter().map(|&v| u32::from(v)).sum::<u32>(), 90);
        assert_eq!(off.iter().map(|&v| u32::from(v)).sum::<u32>(), 45);
    }

    #[test]
    fn borders_count_outside_as_no_change() {
        // a whole frame darkening by 90: interior 90, edges 60, corners 40
        let prev = [200u8; PIXELS];
        let cur = [110u8; PIXELS];
        let (mut on, mut off) = ([0u8; PIXELS], [0u8; PIXELS]);
        on_off_mean(&cur, &prev, &mut on, &mut off);
        assert_eq!(off[20 * WIDTH + 20], 90);
        assert_eq!(off[20 * WIDTH], 60);
        assert_eq!(off[WIDTH - 1], 40);
        assert_eq!(off[PIXELS - 1], 40);
        assert_eq!(off[(HEIGHT - 1) * WIDTH + 40], 60);
        assert!(on.iter().all(|&v| v == 0));
    }

    #[test]
    fn weights_apply_w_and_gain() {
        let w = Weights::new(&Params::default());
        // gain 4, w 0.25: ON enters at 1x, OFF at 4x (a 10-bit luminance scale)
        assert_eq!(
            w,
            Weights {
                on_q8: 256,
                off_q8: 1024
            }
        );
        assert_eq!(w.saliency(100, 0), 100);
        assert_eq!(w.saliency(0, 25), 100);
        assert_eq!(w.saliency(255, 255), 255 + 1020);
    }
}

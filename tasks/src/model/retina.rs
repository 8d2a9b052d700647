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
//!
//! # Streaming
//!
//! [`Retina`] takes a frame row by row as the camera delivers it ([`Retina::push_row`]), so the
//! firmware keeps no frame buffer: the only copy of a frame is the previous one, `P(t−1)`, which
//! each row overwrites once its change is computed. A row of the means is final once the row
//! below it has arrived; finalising it first moves the old mean into the delay line of Eq. (6)
//! ([`delay`]) and then stores the new one. [`on_off_mean`] is the plain whole-frame reference the
//! tests hold the streaming form to.

use crate::frame::{Frame, HEIGHT, PIXELS, WIDTH};
use crate::model::closed_loop::derotate::{Map, Turn};
use crate::model::dsp;
use crate::model::hrc::{Cells, Maps};
use crate::model::params::Params;

/// Rows a streamed frame has; a row index beyond this is refused.
const ROWS: u8 = HEIGHT as u8;
const _: () = assert!(HEIGHT <= u8::MAX as usize);

/// Why a streamed row or frame end is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowError {
    /// A frame already holds all its rows.
    TooManyRows,
    /// The frame ended after `rows` rows, not [`HEIGHT`].
    Short {
        /// Rows received.
        rows: u8,
    },
}

impl core::fmt::Display for RowError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RowError::TooManyRows => write!(f, "more than {HEIGHT} rows in a frame"),
            RowError::Short { rows } => write!(f, "frame ended after {rows} of {HEIGHT} rows"),
        }
    }
}

impl core::error::Error for RowError {}

/// Retina, lamina and the delay line: the state kept between frames (35.6 KB) and the
/// 3-row ring of horizontal sums that turns rows into 3x3 means.
#[derive(Clone)]
pub struct Retina {
    prev: Frame,
    /// The means at `t` and `t − C_d`, one word per pixel ([`Cells`]).
    cells: Cells,
    /// Horizontal 3-sums of the rectified change of the last rows, row `y` in slot `y % 3`,
    /// packed `on | off << 16`: a lane holds at most 3 · 255, three rows 2295, so adding
    /// packed words never carries from one lane into the other.
    h: [[u32; WIDTH]; 3],
    /// Rows of the current frame received.
    rows: u8,
    /// Whether `prev` holds a frame (the priming frame has been seen).
    primed: bool,
    /// Delay-filter gain `1/C_d` in Q8.
    delay_q8: i32,
    /// Columns `lo..hi` of `P(t−1)` that a turn brought into view ([`Retina::turn`]): each
    /// row takes the new frame's pixels there, so new content shows no change.
    fresh: (u8, u8),
}

impl Retina {
    /// Empty maps, waiting for a priming frame; `delay_q8` is `1/C_d` in Q8 ([`delay_q8`]).
    pub const fn new(delay_q8: i32) -> Self {
        Retina {
            prev: [0; PIXELS],
            cells: [0; PIXELS],
            h: [[0; WIDTH]; 3],
            rows: 0,
            primed: false,
            delay_q8,
            fresh: (0, 0),
        }
    }

    /// Changes the delay-filter gain (new parameters), keeping the maps.
    pub fn set_delay_q8(&mut self, delay_q8: i32) {
        self.delay_q8 = delay_q8;
    }

    /// Forgets every frame: the next one primes.
    pub fn reset(&mut self) {
        *self = Retina::new(self.delay_q8);
    }

    /// Whether the maps describe a change (a priming frame came before the last frame).
    pub fn primed(&self) -> bool {
        self.primed
    }

    /// Rows of the current frame received so far.
    pub fn rows(&self) -> u8 {
        self.rows
    }

    /// Drops a partly received frame. Rows already taken have overwritten `P(t−1)` and the
    /// maps, so the retina primes again (the caller must not use the maps until then).
    pub fn abort_frame(&mut self) {
        if self.rows != 0 {
            self.reset();
        }
    }

    /// The next row of the current frame (rows arrive top to bottom).
    pub fn push_row(&mut self, row: &[u8; WIDTH]) -> Result<(), RowError> {
        let y = self.rows;
        if y >= ROWS {
            return Err(RowError::TooManyRows);
        }
        self.rows = y + 1;
        let y = usize::from(y);
        let Some(prev) = self.prev.get_mut(y * WIDTH..(y + 1) * WIDTH) else {
            return Err(RowError::TooManyRows);
        };
        if self.primed {
            let (lo, hi) = (usize::from(self.fresh.0), usize::from(self.fresh.1));
            if let (Some(p), Some(r)) = (prev.get_mut(lo..hi), row.get(lo..hi)) {
                p.copy_from_slice(r);
            }
            // also replaces the row of P(t−1) by this one, word by word as it is read
            row_sums_packed(row, prev, &mut self.h[y % 3]);
        } else {
            prev.copy_from_slice(row);
        }
        if self.primed && y >= 1 {
            self.finish_row(y - 1);
        }
        Ok(())
    }

    /// Ends the frame: the last row of the means is finalised. Returns whether the maps now
    /// hold a change (false for the priming frame).
    pub fn end_frame(&mut self) -> Result<bool, RowError> {
        let rows = self.rows;
        if rows != ROWS {
            self.abort_frame();
            return Err(RowError::Short { rows });
        }
        self.rows = 0;
        self.fresh = (0, 0);
        if !self.primed {
            self.primed = true;
            return Ok(false);
        }
        self.finish_row(HEIGHT - 1);
        Ok(true)
    }

    /// Row `y`'s 3x3 means from the ring (rows outside the retina sum to 0); the old means go
    /// through the delay line first. One pass for both channels.
    ///
    /// With the paper's `C_d = 2` (`g = 128`) the delay line runs on two pixels' `[on, off]`
    /// bytes per word ([`half_step4`]); any other gain takes [`delay_step`] pixel by pixel.
    /// Either way each pixel's cell is read and written once.
    fn finish_row(&mut self, y: usize) {
        const ZERO: [u32; WIDTH] = [0; WIDTH];
        let above = if y == 0 { &ZERO } else { &self.h[(y + 2) % 3] };
        let below = if y + 1 >= HEIGHT {
            &ZERO
        } else {
            &self.h[(y + 1) % 3]
        };
        let mid = &self.h[y % 3];
        let Some(cells) = self.cells.get_mut(y * WIDTH..(y + 1) * WIDTH) else {
            return;
        };
        let g = self.delay_q8;
        if g == 128 {
            finish_cells::<true>(above, mid, below, cells, g);
        } else {
            finish_cells::<false>(above, mid, below, cells, g);
        }
    }

    /// Re-registers the memory (`P(t−1)`, the means and their delay line) to a turn of the
    /// robot since the last frame ([`crate::model::closed_loop::derotate`]); between frames only (the caller checks).
    /// Means with no past (what came into view) are 0.
    pub fn turn(&mut self, turn: &Turn) {
        if !self.primed || turn.is_zero() {
            return;
        }
        let map = Map::new(turn);
        map.remap_pair(&mut self.prev, None, &mut self.cells, Some(0));
        let (lo, hi) = map.fresh_columns();
        // two turns before one frame: the hull of both (at worst a frame without change)
        self.fresh = match (self.fresh, lo < hi) {
            ((a, b), true) if a < b => (a.min(lo), b.max(hi)),
            (old, false) => old,
            (_, true) => (lo, hi),
        };
    }

    /// Sets the means and their delayed copies to "no change", keeping `P(t−1)`: nothing of a
    /// frame that was no image (`Params::noise_pct`) stays in the delay line to be correlated
    /// with the frames after it.
    pub fn forget_change(&mut self) {
        // in place: a 28 KB temporary would not fit the firmware's stack
        self.cells.fill(0);
    }

    /// The newest ON/OFF means (`t`) and their delayed copies, as the correlators read them.
    pub fn maps(&self) -> Maps<'_> {
        Maps::new(&self.cells)
    }

    /// The previous frame `P(t−1)` (after a frame ends: that frame).
    pub fn prev(&self) -> &Frame {
        &self.prev
    }
}

/// `1/C_d` in Q8 (256 = a pure one-frame delay).
pub const fn delay_q8(p: &Params) -> i32 {
    (256.0 / p.choices.c_d + 0.5) as i32
}

/// First-order low-pass delay line of Eq. (6): `D ← D + (L − D)/C_d`, rounded to nearest but
/// moving at least one grey level while `D ≠ L` (8-bit rounding would otherwise leave `D` stuck
/// up to `C_d/2` levels off a steady input: a ghost the correlators would see). With `C_d = 1`
/// it copies `L`: the pure one-frame delay of the paper's Eq. (6); larger `C_d` delays by `C_d`
/// frames on average, tuning the correlators to slower motion at no extra memory.
pub fn delay(d: &mut [u8; PIXELS], l: &[u8; PIXELS], gain_q8: i32) {
    for (d, &l) in d.iter_mut().zip(l.iter()) {
        *d = delay_step(*d, l, gain_q8);
    }
}

/// One pixel of [`delay`].
#[inline(always)]
fn delay_step(d: u8, l: u8, gain_q8: i32) -> u8 {
    let diff = i32::from(l) - i32::from(d);
    // |step| ≤ |diff| for gain ≤ 256 (C_d ≥ 1), so D never overshoots L nor leaves 0..=255;
    // and at least one grey level towards L, so D never sticks short of a steady input
    let step = (diff * gain_q8 + 128) >> 8;
    let step = if step == 0 { diff.signum() } else { step };
    (i32::from(d) + step) as u8
}

/// One row of [`Retina::finish_row`] on its [`Cells`]: `on_d ← delay(on_d, on)`,
/// `off_d ← delay(off_d, off)`, then `on`, `off` ← the 3x3 means `div9(above + mid + below)`
/// of the packed ring rows. `HALF`: the gain is 128 and the delay runs by [`half_step4`] on two
/// pixels per word (`[on_d, off_d]` of both against `[on, off]` of both).
#[inline(always)]
fn finish_cells<const HALF: bool>(
    above: &[u32; WIDTH],
    mid: &[u32; WIDTH],
    below: &[u32; WIDTH],
    cells: &mut [u32],
    g: i32,
) {
    // the new means of a pixel, `on | off << 8`, from its packed 3x3 sum
    #[inline(always)]
    fn means(s: u32) -> u32 {
        div9_lo(s) | div9_hi(s) << 8
    }
    // one pixel's delay line by `delay_step`: the old means (low half) into the delayed ones
    #[inline(always)]
    fn delayed(c: u32, g: i32) -> u32 {
        let [on, off, on_d, off_d] = c.to_le_bytes();
        u32::from(delay_step(on_d, on, g)) << 16 | u32::from(delay_step(off_d, off, g)) << 24
    }
    let (a2, a_t) = above.as_chunks::<2>();
    let (m2, m_t) = mid.as_chunks::<2>();
    let (b2, b_t) = below.as_chunks::<2>();
    let (c2, c_t) = cells.as_chunks_mut::<2>();
    for (((a, m), b), c) in a2.iter().zip(m2).zip(b2).zip(c2.iter_mut()) {
        let d = if HALF {
            // [on_d, off_d] of both pixels against their [on, off]: PKHTB / PKHBT
            let d = (c[0] >> 16) | (c[1] & 0xFFFF_0000);
            let l = (c[0] & 0xFFFF) | (c[1] << 16);
            let n = half_step4(d, l);
            [n << 16, n & 0xFFFF_0000]
        } else {
            [delayed(c[0], g), delayed(c[1], g)]
        };
        c[0] = means(a[0] + m[0] + b[0]) | d[0];
        c[1] = means(a[1] + m[1] + b[1]) | d[1];
    }
    for (((&a, &m), &b), c) in a_t.iter().zip(m_t).zip(b_t).zip(c_t.iter_mut()) {
        *c = means(a + m + b) | delayed(*c, g);
    }
}

/// [`delay_step`] with the paper's gain `g = 128` (`C_d = 2`) on four pixels at once, one per
/// byte of `d` and `l`.
///
/// Why it is the same: with `diff = L − D`, `step = ⌊(128·diff + 128)/256⌋ = ⌊(diff + 1)/2⌋`,
/// which is `⌈diff/2⌉`, and it is 0 only for `diff ∈ {0, −1}`, where the fix-up makes it
/// `signum(diff)`. So `D' = D + ⌈(L − D)/2⌉ = ⌈(D + L)/2⌉` where `L ≥ D`; where `L < D` the
/// same except `D' = L = D − 1` for `diff = −1`, and since `⌈(D + L)/2⌉ ≤ D − 1` for every
/// other `L < D`, `D' = min(⌈(D + L)/2⌉, D − 1)` there. Per byte, `⌈(D + L)/2⌉ =
/// (D | L) − ((D ^ L) >> 1)` (from `D + L = (D ^ L) + 2·(D & L)`), which never borrows across
/// bytes; `D − 1` is `UQSUB8` (`D ≥ 1` wherever it is used), the minimum and the choice by
/// `L ≥ D` are `USUB8` + `SEL` ([`dsp::sel_ge`]). The test
/// `half_step4_is_delay_step_with_gain_128` checks all 65,536 `(D, L)` pairs in every byte
/// position.
#[inline(always)]
fn half_step4(d: u32, l: u32) -> u32 {
    const LOW7: u32 = 0x7F7F_7F7F;
    let ceil = (d | l) - (((d ^ l) >> 1) & LOW7);
    let below = dsp::uqsub8(d, 0x0101_0101);
    let falling = dsp::sel_ge(ceil, below, below, ceil);
    dsp::sel_ge(l, d, ceil, falling)
}

/// `⌊s / 9⌋` for a 3x3 sum of bytes (`s ≤ 2295`) as a multiply and shift (exact on that range,
/// checked by a test), since the Cortex-M4 divider takes up to 12 cycles.
#[inline(always)]
pub fn div9(s: u16) -> u8 {
    ((u32::from(s) * 7282) >> 16) as u8
}

/// [`div9`] of the low lane of a packed sum (`s ≤ 2295`): `(7282·s) >> 16` is the top half of
/// the 32x16 product, one `SMULWB` taking the lane straight from the packed word (no `UXTH`,
/// no shift, no mask: the quotient is ≤ 255).
#[inline(always)]
fn div9_lo(s: u32) -> u32 {
    dsp::smulwb(7282, s) as u32
}

/// [`div9`] of the high lane of a packed sum (`SMULWT`).
#[inline(always)]
fn div9_hi(s: u32) -> u32 {
    dsp::smulwt(7282, s) as u32
}

/// Eqs. (1)–(2): the ON and OFF maps of the change from `prev` to `cur`, 3x3-averaged (the
/// whole-frame reference of [`Retina`]).
///
/// One pass over the frame: each row's horizontal 3-sums go into a 3-row ring, and a row of
/// output is written as soon as the row below it has been summed.
pub fn on_off_mean(cur: &Frame, prev: &Frame, on: &mut [u8; PIXELS], off: &mut [u8; PIXELS]) {
    // Horizontal 3-sums of rows y-1, y, y+1 (index y % 3); a row outside the retina sums to 0.
    let mut h_on = [[0u16; WIDTH]; 3];
    let mut h_off = [[0u16; WIDTH]; 3];
    row_sums(row(cur, 0), row(prev, 0), &mut h_on[0], &mut h_off[0]);
    for y in 0..HEIGHT {
        let below = (y + 1) % 3;
        if y + 1 < HEIGHT {
            row_sums(
                row(cur, y + 1),
                row(prev, y + 1),
                &mut h_on[below],
                &mut h_off[below],
            );
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

fn row(f: &Frame, y: usize) -> &[u8] {
    &f[y * WIDTH..(y + 1) * WIDTH]
}

/// Eq. (1) at one pixel, unweighted and packed: `max(R, 0) | max(−R, 0) << 16`.
#[inline(always)]
fn rectified(c: u8, p: u8) -> u32 {
    let r = i32::from(c) - i32::from(p);
    if r >= 0 {
        r as u32
    } else {
        ((-r) as u32) << 16
    }
}

/// [`rectified`] of four pixels, one per byte of `c` and `p`: the ON bytes are `c − p`
/// saturated at 0 and the OFF bytes `p − c` (`UQSUB8` twice); `PKHBT`/`PKHTB` put each
/// pixel's ON and OFF bytes in the byte lanes 0 and 2 or 1 and 3 of a word, and `UXTB16`
/// spreads them into 16-bit lanes.
#[inline(always)]
fn rectified4(c: u32, p: u32) -> [u32; 4] {
    const LANES: u32 = 0x00FF_00FF;
    let (on, off) = (dsp::uqsub8(c, p), dsp::uqsub8(p, c));
    // [on0 on1 off0 off1] and [on2 on3 off2 off3]
    let lo = (on & 0xFFFF) | (off << 16);
    let hi = (on >> 16) | (off & 0xFFFF_0000);
    [lo & LANES, (lo >> 8) & LANES, hi & LANES, (hi >> 8) & LANES]
}

/// [`row_sums`] for both channels at once, packed (see [`Retina`]): the rectified change of
/// the row four pixels at a time ([`rectified4`]), each group's 3-sums written as soon as the
/// next group's first pixel is known (`out[4k − 1 ..= 4k + 2]` from group `k` and the last two
/// values of group `k − 1`), then the leftover pixels one by one. The previous row `p` is
/// overwritten with `c` as it is read (the retina keeps only `P(t−1)`), so no separate copy.
#[inline(always)]
fn row_sums_packed(c: &[u8; WIDTH], p: &mut [u8], out: &mut [u32; WIDTH]) {
    let Some(p) = p.get_mut(..WIDTH) else {
        return;
    };
    let (c4, c_t) = c.as_chunks::<4>();
    let (p4, p_t) = p.as_chunks_mut::<4>();
    let mut groups = c4.iter().zip(p4.iter_mut()).map(|(c, p)| {
        let r = rectified4(u32::from_le_bytes(*c), u32::from_le_bytes(*p));
        *p = *c;
        r
    });
    // (r(x − 2), r(x − 1)) before the next pixel x; 0 off the retina
    let (mut left, mut mid) = (0u32, 0u32);
    // pixels consumed (WIDTH ≥ 4: the first group exists)
    let mut x = 0usize;
    if let (Some([r0, r1, r2, r3]), Some(o)) = (groups.next(), out.first_chunk_mut::<3>()) {
        *o = [r0 + r1, r0 + r1 + r2, r1 + r2 + r3];
        (left, mid, x) = (r2, r3, 4);
    }
    let (o4, _) = out[3..].as_chunks_mut::<4>();
    for (o, [r0, r1, r2, r3]) in o4.iter_mut().zip(groups) {
        *o = [left + mid + r0, mid + r0 + r1, r0 + r1 + r2, r1 + r2 + r3];
        (left, mid) = (r2, r3);
        x += 4;
    }
    // out[x − 1] is the first not written; the leftover pixels x.. and the zero beyond
    let tail = c_t.iter().zip(p_t.iter_mut()).map(|(&c, p)| {
        let r = rectified(c, *p);
        *p = c;
        r
    });
    for (o, right) in out[x.saturating_sub(1)..]
        .iter_mut()
        .zip(tail.chain(core::iter::once(0)))
    {
        *o = left + mid + right;
        (left, mid) = (mid, right);
    }
}

/// Horizontal 3-sums of the rectified change from row `p` to row `c`.
#[inline(always)]
fn row_sums(c: &[u8], p: &[u8], on: &mut [u16; WIDTH], off: &mut [u16; WIDTH]) {
    let mut r_on = [0u16; WIDTH + 2];
    let mut r_off = [0u16; WIDTH + 2];
    for (x, (&c, &p)) in c.iter().zip(p).enumerate().take(WIDTH) {
        // Eq. (1) without the weight: R > 0 feeds ON, R < 0 feeds OFF.
        let r = i16::from(c) - i16::from(p);
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
    pub const fn new(p: &Params) -> Self {
        let g = p.choices.gain as u32;
        Weights {
            on_q8: (p.choices.gain as f32 * p.table1.w * 256.0 + 0.5) as u32,
            off_q8: g * 256,
        }
    }

    /// `L̂_t = L̂_ON + L̂_OFF` in model units (the saliency of Eqs. 3–4).
    #[inline(always)]
    pub fn saliency(&self, on: u8, off: u8) -> u32 {
        (self.on_q8 * u32::from(on) + self.off_q8 * u32::from(off)) >> 8
    }

    /// [`Weights::saliency`] of a pixel's [`Cells`] word (its `on` and `off` bytes).
    #[inline(always)]
    pub fn saliency_cell(&self, c: u32) -> u32 {
        self.saliency_q8_cell(c) >> 8
    }

    /// [`Weights::saliency_cell`] before its `>> 8` (Q8), for comparisons.
    #[inline(always)]
    pub fn saliency_q8_cell(&self, c: u32) -> u32 {
        self.on_q8 * (c & 0xFF) + self.off_q8 * (c >> 8 & 0xFF)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::hrc::Layer;

    #[test]
    fn div9_is_exact_floor_on_its_range() {
        for s in 0..=2295u16 {
            assert_eq!(u16::from(div9(s)), s / 9, "s = {s}");
        }
    }

    #[test]
    fn div9_of_a_lane_is_div9() {
        // every lane value a 3x3 sum can take, next to any other lane value
        for s in 0..=2295u32 {
            for other in [0u32, 1, 9, 1147, 2294, 2295] {
                assert_eq!(
                    div9_lo(s | other << 16),
                    u32::from(div9(s as u16)),
                    "lo {s} {other}"
                );
                assert_eq!(
                    div9_hi(other | s << 16),
                    u32::from(div9(s as u16)),
                    "hi {s} {other}"
                );
            }
        }
    }

    #[test]
    fn half_step4_is_delay_step_with_gain_128() {
        for d in 0..=255u8 {
            for l in 0..=255u8 {
                let want = delay_step(d, l, 128);
                // the pair in each byte, the other bytes holding other pairs
                for k in 0..4 {
                    let (dw, lw) = ([d, l, 255 - d, l ^ d], [l, d, 255 - l, d]);
                    let (mut dd, mut ll) = ([0u8; 4], [0u8; 4]);
                    for i in 0..4 {
                        dd[(i + k) % 4] = dw[i];
                        ll[(i + k) % 4] = lw[i];
                    }
                    let got =
                        half_step4(u32::from_le_bytes(dd), u32::from_le_bytes(ll)).to_le_bytes();
                    for i in 0..4 {
                        assert_eq!(got[i], delay_step(dd[i], ll[i], 128), "d {d} l {l} k {k}");
                    }
                    assert_eq!(got[k], want);
                }
            }
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

    /// A deterministic pseudo-random frame.
    fn noise(seed: u32) -> Frame {
        let mut f = [0u8; PIXELS];
        let mut s = seed.wrapping_mul(2_654_435_761).max(1);
        for v in f.iter_mut() {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            *v = (s >> 24) as u8;
        }
        f
    }

    fn stream(r: &mut Retina, f: &Frame) -> Result<bool, RowError> {
        for row in f.chunks_exact(WIDTH) {
            r.push_row(row.try_into().unwrap())?;
        }
        r.end_frame()
    }

    #[test]
    fn streaming_rows_equals_the_whole_frame_reference_with_its_delay_line() {
        for gain in [256, 128, 43] {
            let mut r = Retina::new(gain);
            let (mut on_d, mut off_d) = ([0u8; PIXELS], [0u8; PIXELS]);
            let (mut on, mut off) = ([0u8; PIXELS], [0u8; PIXELS]);
            let mut prev = noise(0);
            assert_eq!(stream(&mut r, &prev), Ok(false), "the first frame primes");
            assert!(r.primed());
            for t in 1..6 {
                let cur = noise(t);
                // the reference: delay the maps of t − 1, then the means of t
                delay(&mut on_d, &on, gain);
                delay(&mut off_d, &off, gain);
                on_off_mean(&cur, &prev, &mut on, &mut off);
                assert_eq!(stream(&mut r, &cur), Ok(true));
                let m = r.maps();
                let planes = Layer::ALL.map(|l| m.plane(l));
                assert!(planes[..2] == [on, off], "means, frame {t} gain {gain}");
                assert!(planes[2..] == [on_d, off_d], "delayed, frame {t}");
                assert_eq!(r.prev(), &cur);
                prev = cur;
            }
        }
    }

    #[test]
    fn a_frame_with_the_wrong_number_of_rows_is_refused_and_primes_again() {
        let mut r = Retina::new(128);
        stream(&mut r, &noise(1)).unwrap();
        stream(&mut r, &noise(2)).unwrap();
        // short: 10 rows then the end
        for row in noise(3).chunks_exact(WIDTH).take(10) {
            r.push_row(row.try_into().unwrap()).unwrap();
        }
        assert_eq!(r.end_frame(), Err(RowError::Short { rows: 10 }));
        assert!(
            !r.primed(),
            "a torn frame is never used: the retina starts over"
        );
        assert_eq!(stream(&mut r, &noise(4)), Ok(false), "primes");
        assert_eq!(stream(&mut r, &noise(5)), Ok(true));
        // too many: the 73rd row is refused, the frame still ends whole
        for row in noise(6).chunks_exact(WIDTH) {
            r.push_row(row.try_into().unwrap()).unwrap();
        }
        assert_eq!(r.push_row(&[0; WIDTH]), Err(RowError::TooManyRows));
        assert_eq!(r.end_frame(), Ok(true));
        assert_eq!(r.prev(), &noise(6));
        // an end with no rows at all
        assert_eq!(r.end_frame(), Err(RowError::Short { rows: 0 }));
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

//! Bottom-up multi-attention: attention fields (AFs), Eqs. (3)–(5) and (10) of the paper.
//!
//! * Eq. (3), new field: the argmax of the saliency `L̂_t = L̂_ON + L̂_OFF` over the retina
//!   *outside* every existing field becomes a new field's centroid if it exceeds `T_a`. One new
//!   field per frame; ties go to the first pixel in raster order.
//! * Eq. (4), centroid: each field's centroid moves to the saliency-weighted first moments inside
//!   its square (half side `R_AF`, clipped to the retina), rounded to the nearest pixel; a field
//!   with no saliency inside keeps its centroid.
//! * Eq. (5), fusion: a field whose new centroid lies inside another field's square is discarded.
//!   All squares have the same half side, so containment is mutual: of two fields that come
//!   within `R_AF` of each other one must go, and it is the younger — the older one keeps its
//!   response history for Eq. (10). Fields are checked youngest first against those still
//!   standing, so one field always remains.
//! * Eq. (10), retirement: a field whose mean LPLC2 over its last `d` frames is below `T_d` is
//!   retired — once it has lived `d` frames (a newborn field has no history yet) — but the
//!   strongest field always remains once one exists. `Params::strict_retire` judges as the
//!   authors' firmware does ([`Fields::retire_strict`]): from the first frame, none kept.
//!
//! Capacity: [`MAX_AFS`], or fewer (`Params::max_fields`; the authors' firmware has one). When
//! full, no new field is created until one retires; with Table I's `R_AF` the geometry never
//! lets more than 3 x 2 fields coexist, so [`MAX_AFS`] is not reached.

use crate::frame::{HEIGHT, WIDTH};
use crate::model::dsp;
use crate::model::hrc::Maps;
use crate::model::params::{Params, MAX_D};
use crate::model::retina::Weights;
use crate::model::MAX_AFS;

/// `Params::t_a_quiet`: the share of the retina, in percent, that must be changing (by
/// [`crate::model::closed_loop::luminance::CHANGE_LEVEL`] levels or more, one direction) for Eq. (3) to use
/// Table I's `T_a`; below it the threshold falls linearly towards `t_a_quiet`. Measured on
/// the rendered arena (medians): a standing robot's view changes on 0 % of its pixels, one
/// driving at 100 mm/s past the built-in walls on 4–14 %, at 200 mm/s on 11–25 % (plain walls:
/// 0 % at any speed).
pub const BUSY_PCT: u32 = 10;

/// The attention threshold of Eq. (3) for a frame in which `changing` = `(on, off, sampled)`
/// pixels changed ([`crate::model::closed_loop::luminance::changing`]): `T_a` in a busy scene, down to
/// `Params::t_a_quiet` in a still one (salience normalised by the scene's overall activity,
/// as photoreceptor and lamina gain rise in a quiet, low-contrast scene). `T_a` when the
/// mechanism is off (0) or not below `T_a`.
pub fn spawn_threshold((on, off, sampled): (u32, u32, u32), p: &Params) -> u32 {
    let quiet = u32::from(crate::model::param_table::off0(p.mechanisms.t_a_quiet));
    let t_a = u32::from(p.table1.t_a);
    if quiet == 0 || quiet >= t_a {
        return t_a;
    }
    // `sampled · BUSY_PCT` ≤ 1,782 · 10: no overflow
    let busy = (sampled * BUSY_PCT).div_ceil(100).max(1);
    let share = on.max(off).min(busy);
    quiet + ((u64::from(t_a - quiet) * u64::from(share)) / u64::from(busy)) as u32
}

/// The pixels `c − r ..= c + r` along an axis of `len` pixels, clipped to it (inclusive): one
/// side of a field's square ([`Field::square`]).
#[inline(always)]
pub fn span(c: usize, r: usize, len: usize) -> (usize, usize) {
    (c.saturating_sub(r), c.saturating_add(r).min(len - 1))
}

/// `L̂ = on + 4·off` of a cell, Table I's weights (gain 4, w = 0.25) without a multiply.
#[inline(always)]
fn sal_table_i(c: u32) -> u32 {
    (c & 0xFF) + ((c >> 6) & 0x3FC)
}

/// [`sal_table_i`] of two cells in the 16-bit lanes of a word (`L̂ ≤ 1275`): bytes
/// `[on0, off0, on1, off1]`, then `4·off` per lane (one masked shift) plus `on` per lane
/// (`UXTAB16`).
#[inline(always)]
fn sal2_table_i(c0: u32, c1: u32) -> u32 {
    let t = (c0 & 0xFFFF) | (c1 << 16);
    dsp::uxtab16((t >> 6) & 0x03FC_03FC, t)
}

/// The largest [`sal_table_i`] of `cells` (0 if none), two pixels a step (`USUB16` + `SEL`):
/// four cells a step, then the last four again in place of a loop over the rest (a maximum
/// does not mind a pixel read twice).
#[inline(always)]
fn peak_table_i(cells: &[u32]) -> u32 {
    let Some(last) = cells.last_chunk::<4>() else {
        return cells.iter().fold(0, |m, &c| m.max(sal_table_i(c)));
    };
    let step = |peak2: u32, q: &[u32; 4]| {
        let (a, b) = (sal2_table_i(q[0], q[1]), sal2_table_i(q[2], q[3]));
        let peak2 = dsp::sel_ge16(peak2, a, peak2, a);
        dsp::sel_ge16(peak2, b, peak2, b)
    };
    let peak2 = cells.as_chunks::<4>().0.iter().fold(step(0, last), step);
    (peak2 & 0xFFFF).max(peak2 >> 16)
}

/// `Σ L̂` in two lanes and `Σ L̂·x` of the pixels of `quads` at or above the floor (`floor2`,
/// in both lanes), the first pair's columns `xs` (`[x, x + 1]`), one [`moments_quad`] each. A
/// row's lanes sum at most 50 pixels each (`≤ 63,750`): no carry between them.
#[inline(always)]
fn moments_table_i(quads: &[[u32; 4]], floor2: u32, xs: u32) -> (u32, i32) {
    let step = 0x0002_0002;
    let (s2, sx, _) = quads.iter().fold((0, 0, xs), |(s2, sx, xs), q| {
        let (s2, sx) = moments_quad(q, [floor2; 2], [xs, xs.wrapping_add(step)], s2, sx);
        (s2, sx, xs.wrapping_add(2 * step))
    });
    (s2, sx)
}

/// One quad's `Σ L̂` (lane-wise) and `Σ L̂·x` added to `(s2, sx)`: per pair its floor as a
/// lane-wise select (`USUB16` + `SEL`), a lane-wise add and one `SMLAD` against its columns.
#[inline(always)]
fn moments_quad(q: &[u32; 4], floor: [u32; 2], xs: [u32; 2], s2: u32, sx: i32) -> (u32, i32) {
    let a = sal2_table_i(q[0], q[1]);
    let a = dsp::sel_ge16(a, floor[0], a, 0);
    let b = sal2_table_i(q[2], q[3]);
    let b = dsp::sel_ge16(b, floor[1], b, 0);
    let sx = dsp::smlad(a, xs[0], sx);
    (s2.wrapping_add(a).wrapping_add(b), dsp::smlad(b, xs[1], sx))
}

/// One attention field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Field {
    /// Identifier, unique over a run (4 × 10⁹ fields: years at one field per frame).
    pub id: u32,
    /// Centroid column `x̄_k`.
    pub x: u8,
    /// Centroid row `ȳ_k`.
    pub y: u8,
    /// Frames this field has lived through (1 in its first frame).
    pub age: u32,
    /// The quadrant sum `ΣQ` of its last frame, gate or not (`Params::q_grow_pct`).
    pub drive: u32,
    /// Where `drive` was measured: the centroid of its last frame, moved with the view by
    /// turns (`Params::derotate`) but not by recentring.
    pub drive_at: (u8, u8),
    /// Frames in a row on which `drive` grew at the same place (`Params::q_grow_run`).
    pub drive_run: u8,
    /// LPLC2 responses of the last `MAX_D` frames, newest at `head`.
    history: [u32; MAX_D as usize],
    /// Slot of the newest response; wraps independently of `age`, which saturates.
    head: u8,
}

impl Field {
    fn new(id: u32, x: usize, y: usize) -> Self {
        Field {
            id,
            x: x as u8,
            y: y as u8,
            age: 0,
            drive: 0,
            drive_at: (x as u8, y as u8),
            drive_run: 0,
            history: [0; MAX_D as usize],
            head: 0,
        }
    }

    /// The square of half side `r` around the centroid, clipped: `((x0, x1), (y0, y1))` inclusive.
    pub fn square(&self, r: u8) -> ((usize, usize), (usize, usize)) {
        let r = usize::from(r);
        (
            span(usize::from(self.x), r, WIDTH),
            span(usize::from(self.y), r, HEIGHT),
        )
    }

    /// Whether pixel `(x, y)` lies in the square of half side `r`.
    #[inline(always)]
    pub fn contains(&self, x: usize, y: usize, r: u8) -> bool {
        usize::from(self.x).abs_diff(x) <= usize::from(r)
            && usize::from(self.y).abs_diff(y) <= usize::from(r)
    }

    /// How far recentring moved the centroid since `drive` was measured, pixels (Chebyshev).
    pub fn shift_since_drive(&self) -> u8 {
        let (x, y) = self.drive_at;
        self.x.abs_diff(x).max(self.y.abs_diff(y))
    }

    /// Records this frame's LPLC2 response.
    pub fn push_response(&mut self, r: u32) {
        self.age = self.age.saturating_add(1);
        self.head = (self.head + 1) % MAX_D;
        self.history[usize::from(self.head)] = r;
    }

    /// The newest LPLC2 response.
    pub fn response(&self) -> u32 {
        self.history[usize::from(self.head)]
    }

    /// Mean LPLC2 over the last `d` frames with the frames before this field's birth counting
    /// 0 (`Params::t_lplc2`, `Params::strict_retire`: the authors' firmware's ring of outputs).
    pub fn window_mean(&self, d: u8) -> u32 {
        let k = u32::from(d.clamp(1, MAX_D));
        let mut sum = 0u64;
        for i in 0..k {
            let slot = (u32::from(self.head) + u32::from(MAX_D) - i) % u32::from(MAX_D);
            sum += u64::from(self.history[slot as usize]);
        }
        (sum / u64::from(k)) as u32
    }

    /// Mean LPLC2 over the last `d` frames (Eq. 10), over fewer while younger than `d`.
    pub fn mean_response(&self, d: u8) -> u32 {
        let k = u32::from(d.min(MAX_D)).min(self.age).max(1);
        let mut sum = 0u64;
        for i in 0..k {
            let slot = (u32::from(self.head) + u32::from(MAX_D) - i) % u32::from(MAX_D);
            sum += u64::from(self.history[slot as usize]);
        }
        (sum / u64::from(k)) as u32
    }
}

/// Eq. (4)'s first moments of one field's window, summed row by row.
#[derive(Default)]
struct Moments {
    /// `Σ L̂`, `Σ L̂·x`, `Σ L̂·y`.
    m: u64,
    mx: u64,
    my: u64,
}

impl Moments {
    /// Adds row `y` with `Σ L̂ = s` and `Σ L̂·x = sx`.
    #[inline(always)]
    fn add_row(&mut self, s: u32, sx: u32, y: usize) {
        self.m += u64::from(s);
        self.mx += u64::from(sx);
        self.my += u64::from(s) * y as u64;
    }

    /// Moves `f` to the centroid, rounded to the nearest pixel; without weight it stays.
    fn move_centroid(&self, f: &mut Field) {
        let (m, mx, my) = (self.m, self.mx, self.my);
        // the quotient lies inside the square, so it fits a byte
        if let (Some(x), Some(y)) = ((mx + m / 2).checked_div(m), (my + m / 2).checked_div(m)) {
            f.x = x as u8;
            f.y = y as u8;
        }
    }
}

/// The set of attention fields, oldest first.
#[derive(Debug, Clone, Default)]
pub struct Fields {
    list: heapless::Vec<Field, MAX_AFS>,
    next_id: u32,
}

impl Fields {
    /// No field; the first id is 0.
    pub const fn new() -> Self {
        Fields {
            list: heapless::Vec::new(),
            next_id: 0,
        }
    }

    /// The fields, oldest first.
    pub fn iter(&self) -> core::slice::Iter<'_, Field> {
        self.list.iter()
    }

    /// The fields, mutable, oldest first.
    pub fn iter_mut(&mut self) -> core::slice::IterMut<'_, Field> {
        self.list.iter_mut()
    }

    /// Number of fields.
    pub fn len(&self) -> usize {
        self.list.len()
    }

    /// No field yet.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// Drops every field.
    pub fn clear(&mut self) {
        self.list.clear();
    }

    /// Whether `(x, y)` lies in any field.
    pub fn covers(&self, x: usize, y: usize, r: u8) -> bool {
        self.list.iter().any(|f| f.contains(x, y, r))
    }

    /// Eq. (3): adds a field at the most salient pixel outside all fields if it exceeds `T_a`.
    /// Returns the new field's id.
    ///
    /// Same result as the pixel-by-pixel [`Fields::spawn_reference`]: the fields' squares cut
    /// each row into covered column intervals, and only the gaps between them are scanned, in
    /// raster order with a strict `>` (so ties still go to the first pixel), with no per-pixel
    /// containment test.
    pub fn spawn(&mut self, m: &Maps, w: &Weights, p: &Params) -> Option<u32> {
        self.spawn_above(m, w, p, u32::from(p.table1.t_a))
    }

    /// [`Fields::spawn`] with the threshold `t_a` in place of `p.t_a` ([`spawn_threshold`]).
    ///
    /// The squares are sorted by their first column once; each row takes those that cover it
    /// in that order. With Table I's weights a gap's peak is taken two pixels a step
    /// (`L̂ = on + 4·off` in the lanes of a word, as in `Fields::recentre_table_i`), and only a
    /// gap whose peak beats the best so far is scanned again for its first pixel at that peak:
    /// the same pixel as the scan in raster order with a strict `>`.
    pub fn spawn_above(&mut self, m: &Maps, w: &Weights, p: &Params, t_a: u32) -> Option<u32> {
        // `Params::max_fields`: no new field while that many live
        if self.list.is_full() || self.list.len() >= usize::from(p.firmware.max_fields) {
            return None;
        }
        let r = usize::from(p.exclusion());
        // each field's square as (first column, end column, first row, last row), columns
        // half-open, sorted by first column (insertion, at most MAX_AFS entries)
        let mut sq = [(0usize, 0usize, 0usize, 0usize); MAX_AFS];
        let mut k = 0;
        for f in self.list.iter() {
            let (x, y) = (usize::from(f.x), usize::from(f.y));
            let s = (
                x.saturating_sub(r).min(WIDTH),
                (x + r + 1).min(WIDTH),
                y.saturating_sub(r),
                y + r,
            );
            let mut j = k;
            while j > 0 && sq[j - 1].0 > s.0 {
                sq[j] = sq[j - 1];
                j -= 1;
            }
            sq[j] = s;
            k += 1;
        }
        let sq = &sq[..k];
        let table_i = (w.on_q8, w.off_q8) == (256, 1024);
        let mut best = (0u32, 0usize, 0usize);
        for (y, cells) in m.cells.chunks_exact(WIDTH).enumerate() {
            let mut x = 0;
            for &(c0, c1, y0, y1) in sq.iter().chain(core::iter::once(&(WIDTH, WIDTH, 0, y))) {
                if y < y0 || y > y1 {
                    continue;
                }
                if let Some(gap) = cells.get(x..c0) {
                    if table_i {
                        let l = peak_table_i(gap);
                        if l > best.0 {
                            // the gap's first pixel at its peak
                            let i = gap.iter().position(|&c| sal_table_i(c) == l).unwrap_or(0);
                            best = (l, x + i, y);
                        }
                    } else {
                        for (i, &c) in gap.iter().enumerate() {
                            let l = w.saliency_cell(c);
                            if l > best.0 {
                                best = (l, x + i, y);
                            }
                        }
                    }
                }
                x = x.max(c1);
            }
        }
        self.open(best, t_a)
    }

    /// Eq. (3)'s decision on the strongest candidate `(L̂, x, y)`: a new field there if `L̂`
    /// is strictly above `t_a` and there is room; its id.
    fn open(&mut self, (l, x, y): (u32, usize, usize), t_a: u32) -> Option<u32> {
        if l <= t_a {
            return None;
        }
        let id = self.next_id;
        self.next_id = self.next_id.wrapping_add(1);
        self.list.push(Field::new(id, x, y)).ok()?;
        Some(id)
    }

    /// Eq. (4): moves every centroid to the saliency-weighted first moments of its square.
    ///
    /// Same result as [`Fields::recentre_reference`]. The peak is taken on the saliencies
    /// before their `>> 8` (the shift is monotonic: one shift per field, not per pixel); Table
    /// I's weights take `Fields::recentre_table_i`. A row's moments are summed in `u32`
    /// (`L̂ ≤ (16384 + 4096)·255 / 256 = 20400` with `gain ≤ 16`, `w ≤ 4`, so a row of at
    /// most 99 pixels sums to `Σ L̂ < 2.1·10⁶`), then added to `u64` totals; pixels under the
    /// floor weigh 0 instead of being branched around.
    /// The row's `Σ L̂·x` comes from running sums, `S_x = Σ_{x' ≤ x} L̂_x'` and `T = Σ_x S_x`:
    /// `Σ L̂_x·x = (x1 + 1)·S − T` (`T ≤ 99·S < 2.1·10⁸`), two additions per pixel and no
    /// column counter.
    pub fn recentre(&mut self, maps: &Maps, w: &Weights, p: &Params) {
        if (w.on_q8, w.off_q8) == (256, 1024) {
            self.recentre_table_i(maps, p);
        } else {
            self.recentre_general(maps, w, p);
        }
    }

    /// [`Fields::recentre`] with Table I's weights (gain 4, w = 0.25): `L̂ = on + 4·off`
    /// exactly, no multiply and no shift, two pixels per step in the 16-bit lanes of a word
    /// (`L̂ ≤ 1275`). Peak: lane-wise maximum (`USUB16` + `SEL`, [`peak_table_i`]), kept per
    /// row. Moments ([`moments_table_i`]): the floor as a lane-wise select, `Σ L̂` lane-wise and
    /// `Σ L̂·x` of the pair by one `SMLAD` (against `[x, x + 1]`); a row's `Σ L̂·x ≤
    /// 99·1275·98 < 2^31`. A row's last `w % 4` pixels come from its last four again, the
    /// others' lanes under a floor no `L̂` reaches. The rows whose peak is under the floor
    /// add 0 to every moment: skipped.
    fn recentre_table_i(&mut self, maps: &Maps, p: &Params) {
        // each window row's peak (`L̂ ≤ 1275`), for the moments' pass to skip the rows with no
        // pixel at the floor: they add 0 to every moment
        let mut row_peak = [0u16; HEIGHT];
        for f in self.list.iter_mut() {
            let ((x0, x1), (y0, y1)) = f.square(p.choices.r_c.min(p.table1.r_af));
            let xe = x1 + 1;
            // the window's rows, whole
            let band = maps.cells.get(y0 * WIDTH..(y1 + 1) * WIDTH).unwrap_or(&[]);
            let rows = band.as_chunks::<WIDTH>().0;
            let mut peak = 0u32;
            for (row, rp) in rows.iter().zip(row_peak.iter_mut()) {
                let m = peak_table_i(row.get(x0..xe).unwrap_or(&[]));
                *rp = m as u16;
                peak = peak.max(m);
            }
            // 1 ≤ ⌈peak·c_frac/100⌉ ≤ peak ≤ 1275 (or 1): a 16-bit lane
            let floor = (peak * u32::from(p.choices.c_frac)).div_ceil(100).max(1);
            let floor2 = floor | floor << 16;
            // a row's last four cells again, for the `w % 4` its quads leave out: the lanes
            // counted already take a floor no `L̂` reaches
            let w = xe.saturating_sub(x0);
            let fresh = |j: usize| if j + w % 4 >= 4 { floor } else { 0xFFFF };
            let last_floor = [fresh(0) | fresh(1) << 16, fresh(2) | fresh(3) << 16];
            let xl = xe.saturating_sub(4) as u32;
            let last_xs = [xl | (xl + 1) << 16, (xl + 2) | (xl + 3) << 16];
            let xs0 = (x0 as u32) | (x0 as u32 + 1) << 16;
            let mut mo = Moments::default();
            for ((y, row), &rp) in (y0..).zip(rows).zip(row_peak.iter()) {
                if u32::from(rp) < floor {
                    continue;
                }
                let row = row.get(x0..xe).unwrap_or(&[]);
                let (s, sx) = match row.last_chunk::<4>() {
                    Some(last) => {
                        let (quads, _) = row.as_chunks::<4>();
                        let (s2, sx) = moments_table_i(quads, floor2, xs0);
                        let (s2, sx) = moments_quad(last, last_floor, last_xs, s2, sx);
                        // lanes of at most 50 pixels: `Σ L̂ ≤ 63,750` each, no carry between
                        // them; `Σ L̂·x ≥ 0`
                        ((s2 & 0xFFFF) + (s2 >> 16), sx as u32)
                    }
                    // fewer than four cells (a half side of 1 at most)
                    None => (x0..).zip(row).fold((0, 0), |(s, sx), (x, &c)| {
                        let l = sal_table_i(c);
                        let l = if l >= floor { l } else { 0 };
                        (s + l, sx + l * x as u32)
                    }),
                };
                mo.add_row(s, sx, y);
            }
            mo.move_centroid(f);
        }
    }

    /// [`Fields::recentre`] with any weights: the saliency in Q8 (`L̂ << 8`) per cell.
    #[inline(always)]
    fn recentre_general(&mut self, maps: &Maps, w: &Weights, p: &Params) {
        let (sal, k) = (|c: u32| w.saliency_q8_cell(c), 8);
        for f in self.list.iter_mut() {
            let ((x0, x1), (y0, y1)) = f.square(p.choices.r_c.min(p.table1.r_af));
            let mut peak = 0u32;
            for y in y0..=y1 {
                let i = y * WIDTH;
                let mut max = |c: u32| peak = peak.max(sal(c));
                // four pixels per iteration: one loop branch per four, not an end test per pixel
                let (quads, rest) = maps.cells[i + x0..=i + x1].as_chunks::<4>();
                for q in quads {
                    q.iter().for_each(|&c| max(c));
                }
                rest.iter().for_each(|&c| max(c));
            }
            let peak = peak >> k;
            // ⌈peak·c_frac/100⌉ ≤ peak (c_frac ≤ 100), so it fits a u32
            let floor = (u64::from(peak) * u64::from(p.choices.c_frac))
                .div_ceil(100)
                .max(1);
            let floor = u32::try_from(floor).unwrap_or(u32::MAX);
            let mut mo = Moments::default();
            for y in y0..=y1 {
                let i = y * WIDTH;
                let (mut s, mut t) = (0u32, 0u32);
                let mut add = |c: u32| {
                    let l = sal(c) >> k;
                    let l = if l >= floor { l } else { 0 };
                    s = s.wrapping_add(l);
                    t = t.wrapping_add(s);
                };
                // four pixels per iteration, as for the peak
                let (quads, rest) = maps.cells[i + x0..=i + x1].as_chunks::<4>();
                for q in quads {
                    q.iter().for_each(|&c| add(c));
                }
                rest.iter().for_each(|&c| add(c));
                let sx = (x1 as u32 + 1).wrapping_mul(s).wrapping_sub(t);
                mo.add_row(s, sx, y);
            }
            mo.move_centroid(f);
        }
    }

    /// Eq. (3), pixel by pixel: the plain reference of [`Fields::spawn`].
    pub fn spawn_reference(&mut self, m: &Maps, w: &Weights, p: &Params) -> Option<u32> {
        if self.list.is_full() {
            return None;
        }
        let mut best = (0u32, 0usize, 0usize);
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                let i = y * WIDTH + x;
                let l = w.saliency(m.on(i), m.off(i));
                if l > best.0 && !self.covers(x, y, p.exclusion()) {
                    best = (l, x, y);
                }
            }
        }
        self.open(best, u32::from(p.table1.t_a))
    }

    /// Eq. (4), pixel by pixel: the plain reference of [`Fields::recentre`].
    pub fn recentre_reference(&mut self, maps: &Maps, w: &Weights, p: &Params) {
        for f in self.list.iter_mut() {
            let ((x0, x1), (y0, y1)) = f.square(p.choices.r_c.min(p.table1.r_af));
            // Weak, wide-spread change (ego-motion over texture) would drag the centroid off the
            // object: only pixels at or above `c_frac` % of the window's peak weigh in.
            let mut peak = 0u32;
            for y in y0..=y1 {
                for i in y * WIDTH + x0..=y * WIDTH + x1 {
                    peak = peak.max(w.saliency(maps.on(i), maps.off(i)));
                }
            }
            let floor = (u64::from(peak) * u64::from(p.choices.c_frac))
                .div_ceil(100)
                .max(1);
            let (mut m, mut mx, mut my) = (0u64, 0u64, 0u64);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let i = y * WIDTH + x;
                    let l = u64::from(w.saliency(maps.on(i), maps.off(i)));
                    if l >= floor {
                        m += l;
                        mx += l * x as u64;
                        my += l * y as u64;
                    }
                }
            }
            // round to nearest; the quotient lies inside the square, so it fits a byte
            if let (Some(x), Some(y)) = ((mx + m / 2).checked_div(m), (my + m / 2).checked_div(m)) {
                f.x = x as u8;
                f.y = y as u8;
            }
        }
    }

    /// Eq. (5): discards fields whose centroid lies inside another standing field's exclusion
    /// zone of half side `r` ([`Params::exclusion`]).
    pub fn fuse(&mut self, r: u8) {
        let mut k = self.list.len();
        while k > 0 {
            k -= 1;
            let f = self.list[k];
            let inside = self
                .list
                .iter()
                .enumerate()
                .any(|(j, g)| j != k && g.contains(usize::from(f.x), usize::from(f.y), r));
            if inside {
                self.list.remove(k);
            }
        }
    }

    /// Eq. (10): retires fields whose mean response over `d` frames is below `T_d`, keeping the
    /// strongest one (the oldest among equals) when all would go.
    pub fn retire(&mut self, d: u8, t_d: u32) {
        let Some(keep) = self
            .list
            .iter()
            .enumerate()
            .max_by_key(|(i, f)| (f.mean_response(d), core::cmp::Reverse(*i)))
            .map(|(_, f)| f.id)
        else {
            return;
        };
        self.list
            .retain(|f| f.id == keep || f.age < u32::from(d) || f.mean_response(d) >= t_d);
    }

    /// Eq. (10) as the authors' firmware runs it (`Params::strict_retire`): retires every
    /// field whose [`Field::window_mean`] over `d` frames is below `T_d`, from its first frame
    /// on, the last one too.
    pub fn retire_strict(&mut self, d: u8, t_d: u32) {
        self.list.retain(|f| f.window_mean(d) >= t_d);
    }

    /// Adds a field directly (tests and replays of recorded states).
    pub fn insert(&mut self, x: u8, y: u8) -> Option<u32> {
        let id = self.next_id;
        let (x, y) = (
            usize::from(x).min(WIDTH - 1),
            usize::from(y).min(HEIGHT - 1),
        );
        self.list.push(Field::new(id, x, y)).ok()?;
        self.next_id = self.next_id.wrapping_add(1);
        Some(id)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::PIXELS;
    use crate::model::param_table::off0;
    use crate::model::params::{Choices, FirmwareVariant, Mechanisms, TableOne};
    use core::num::{NonZeroU16, NonZeroU8};

    fn p() -> Params {
        Params::default()
    }

    fn w() -> Weights {
        Weights::new(&p())
    }

    #[test]
    fn a_quiet_scene_lowers_the_spawn_threshold_towards_t_a_quiet() {
        let p = Params::ALVS;
        assert_eq!(
            (p.table1.t_a, off0(p.mechanisms.t_a_quiet), BUSY_PCT),
            (100, 30, 10)
        );
        // 1,782 pixels sampled: 179 changing (10 %) or more is a busy scene
        assert_eq!(spawn_threshold((0, 0, 1782), &p), 30);
        assert_eq!(spawn_threshold((179, 3, 1782), &p), 100);
        assert_eq!(spawn_threshold((3, 900, 1782), &p), 100);
        // half-way: half-way between the two
        assert_eq!(spawn_threshold((89, 0, 1782), &p), 64);
        // off, or not below T_a: Table I's T_a
        for quiet in [0, 100, 500] {
            let q = Params {
                mechanisms: Mechanisms {
                    t_a_quiet: NonZeroU16::new(quiet),
                    ..p.mechanisms
                },
                ..p
            };
            assert_eq!(spawn_threshold((0, 0, 1782), &q), 100);
        }
        // nothing sampled cannot divide by zero
        assert_eq!(spawn_threshold((0, 0, 0), &p), 30);
    }

    /// OFF map with blobs of value `v` (model saliency 4·v) at the given pixels.
    fn cm(on: &[u8; PIXELS], off: &[u8; PIXELS]) -> crate::model::hrc::Cells {
        crate::model::hrc::cells_of([on, off, &[0; PIXELS], &[0; PIXELS]])
    }

    fn off_map(points: &[(usize, usize, u8)]) -> [u8; PIXELS] {
        let mut m = [0u8; PIXELS];
        for &(x, y, v) in points {
            m[y * WIDTH + x] = v;
        }
        m
    }

    #[test]
    fn a_field_is_born_at_the_argmax_above_t_a_only() {
        let zero = [0u8; PIXELS];
        let mut f = Fields::default();
        // saliency 4·25 = 100 is not above T_a = 100
        assert_eq!(
            f.spawn(
                &Maps::new(&cm(&zero, &off_map(&[(10, 10, 25)]))),
                &w(),
                &p()
            ),
            None
        );
        let off = off_map(&[(10, 10, 26), (70, 40, 30)]);
        assert_eq!(f.spawn(&Maps::new(&cm(&zero, &off)), &w(), &p()), Some(0));
        let g = f.iter().next().unwrap();
        assert_eq!((g.x, g.y), (70, 40));
        // (10,10) lies outside the first square (columns 34..=98): a second field
        assert_eq!(f.spawn(&Maps::new(&cm(&zero, &off)), &w(), &p()), Some(1));
        // nothing salient is left outside both squares
        assert_eq!(f.spawn(&Maps::new(&cm(&zero, &off)), &w(), &p()), None);
    }

    #[test]
    fn a_second_field_needs_a_peak_outside_the_first() {
        let zero = [0u8; PIXELS];
        let mut f = Fields::default();
        let off = off_map(&[(90, 40, 60), (60, 40, 50), (5, 5, 40)]);
        assert_eq!(f.spawn(&Maps::new(&cm(&zero, &off)), &w(), &p()), Some(0)); // at (90,40)
                                                                                // (60,40) lies inside 90±36; (5,5) does not
        assert_eq!(f.spawn(&Maps::new(&cm(&zero, &off)), &w(), &p()), Some(1));
        let v: heapless::Vec<(u8, u8), 6> = f.iter().map(|g| (g.x, g.y)).collect();
        assert_eq!(&v[..], &[(90, 40), (5, 5)]);
    }

    #[test]
    fn centroids_move_to_the_first_moments() {
        let zero = [0u8; PIXELS];
        let mut f = Fields::default();
        f.insert(50, 30);
        // two equal blobs at x = 40 and 61, rows 20 and 30: centroid (50.5 → 51, 25)
        let off = off_map(&[(40, 20, 50), (61, 30, 50)]);
        f.recentre(&Maps::new(&cm(&zero, &off)), &w(), &p());
        let g = f.iter().next().unwrap();
        assert_eq!((g.x, g.y), (51, 25));
        // saliencies 240 and 120 → x = (240·40 + 120·61)/360 = 47
        let off = off_map(&[(40, 20, 60), (61, 20, 30)]);
        f.recentre(&Maps::new(&cm(&zero, &off)), &w(), &p());
        assert_eq!(f.iter().next().unwrap().x, 47);
        // saliency 80 is below half the peak (240): only x = 40 pulls
        let off = off_map(&[(40, 20, 60), (61, 20, 20)]);
        f.recentre(&Maps::new(&cm(&zero, &off)), &w(), &p());
        assert_eq!(f.iter().next().unwrap().x, 40);
        // nothing inside: the centroid stays
        f.recentre(&Maps::new(&cm(&zero, &zero)), &w(), &p());
        assert_eq!(f.iter().next().unwrap().x, 40);
    }

    #[test]
    fn a_field_whose_centroid_enters_another_is_fused_away() {
        let mut f = Fields::default();
        f.insert(20, 36);
        f.insert(80, 36);
        f.fuse(36);
        assert_eq!(f.len(), 2);
        // the younger field walks to x = 50, inside the older one's square (20 ± 36)
        f.iter_mut().nth(1).unwrap().x = 50;
        f.fuse(36);
        assert_eq!(f.len(), 1);
        assert_eq!(f.iter().next().unwrap().x, 20);
        // the older field walks into the younger one: still the younger one goes
        let mut f = Fields::default();
        f.insert(10, 10);
        f.insert(90, 60);
        f.insert(10, 60);
        f.iter_mut().next().unwrap().x = 60;
        f.iter_mut().next().unwrap().y = 40;
        f.fuse(36);
        // (60,40) is within 36 of (90,60) but not of (10,60)
        assert_eq!(
            f.iter().map(|g| g.id).collect::<heapless::Vec<u32, 6>>()[..],
            [0, 2]
        );
    }

    #[test]
    fn the_exclusion_zone_sets_where_a_field_is_born_and_which_fuse() {
        // three salient points 30 columns apart on one row
        let zero = [0u8; PIXELS];
        let off = off_map(&[(10, 36, 60), (40, 36, 50), (70, 36, 40)]);
        let cells = cm(&zero, &off);
        let maps = Maps::new(&cells);
        let born = |p: &Params| {
            let mut f = Fields::default();
            while f.spawn(&maps, &w(), p).is_some() {}
            f.iter().map(|g| g.x).collect::<heapless::Vec<u8, 6>>()
        };
        // the paper's text: the field's square (R_AF = 36) is its exclusion zone
        assert_eq!(p().exclusion(), 36);
        assert_eq!(born(&p())[..], [10, 70]);
        // a zone of 24 (the authors' multi-field simulator): a field on each point
        let mut q = p();
        q.choices.r_x = NonZeroU8::new(24);
        assert_eq!(q.exclusion(), 24);
        assert_eq!(born(&q)[..], [10, 40, 70]);
        let mut f = Fields::default();
        while f.spawn_reference(&maps, &w(), &q).is_some() {}
        assert_eq!(f.len(), 3);
        // Eq. (5) with the same zone: 30 apart stand, 24 apart fuse
        f.fuse(q.exclusion());
        assert_eq!(f.len(), 3);
        f.iter_mut().nth(2).unwrap().x = 64;
        f.fuse(q.exclusion());
        assert_eq!(f.len(), 2);
    }

    #[test]
    fn weak_fields_retire_after_d_frames_but_one_remains() {
        let mut f = Fields::default();
        f.insert(10, 10);
        f.insert(90, 60);
        for frame in 0..4 {
            for (k, g) in f.iter_mut().enumerate() {
                g.push_response(if k == 0 { 6000 } else { 4000 });
            }
            f.retire(4, 5000);
            // both survive while younger than d = 4 frames
            assert_eq!(f.len(), if frame < 3 { 2 } else { 1 }, "frame {frame}");
        }
        assert_eq!(f.iter().next().unwrap().x, 10);
        // the survivor's mean falls below T_d: it still remains, being the last one
        for _ in 0..8 {
            f.iter_mut().next().unwrap().push_response(0);
            f.retire(4, 5000);
        }
        assert_eq!(f.len(), 1);
    }

    #[test]
    fn the_firmwares_retirement_judges_from_the_first_frame_and_keeps_none() {
        // `Params::strict_retire`: the mean over d frames counts the frames before the
        // field's birth as 0
        let mut f = Fields::default();
        f.insert(10, 10);
        f.insert(90, 60);
        for (k, g) in f.iter_mut().enumerate() {
            g.push_response(if k == 0 { 60_000 } else { 40_000 });
        }
        let g = f.iter().next().unwrap();
        assert_eq!((g.window_mean(4), g.mean_response(4)), (15_000, 60_000));
        // the second (10,000 < 12,500) goes at once; Eq. (10) would have waited d frames
        let mut paper = f.clone();
        paper.retire(4, 12_500);
        assert_eq!(paper.len(), 2);
        f.retire_strict(4, 12_500);
        assert_eq!(f.iter().map(|g| g.x).collect::<heapless::Vec<_, 6>>(), [10]);
        // and the last one goes too, once its response has left the window
        for frame in 0..4 {
            f.iter_mut().next().unwrap().push_response(0);
            f.retire_strict(4, 12_500);
            assert_eq!(f.len(), if frame < 3 { 1 } else { 0 }, "frame {frame}");
        }
    }

    #[test]
    fn no_field_opens_beyond_max_fields() {
        // two salient spots far apart: Eq. (3) opens one field a frame, up to `max_fields`
        let mut off = [0u8; PIXELS];
        off[10 * WIDTH + 10] = 200;
        off[60 * WIDTH + 90] = 150;
        let cells = cm(&[0u8; PIXELS], &off);
        let m = Maps::new(&cells);
        for (max, want) in [(1u8, 1usize), (2, 2), (6, 2)] {
            let p = Params {
                firmware: FirmwareVariant {
                    max_fields: max,
                    ..p().firmware
                },
                ..p()
            };
            let mut f = Fields::default();
            for _ in 0..3 {
                f.spawn(&m, &Weights::new(&p), &p);
            }
            assert_eq!(f.len(), want, "max_fields {max}");
        }
    }

    #[test]
    fn table_i_weights_take_the_multiply_free_saliency_with_the_same_centroids() {
        // Table I's weights (`on + 4·off`) have their own recentre path: hold it to the
        // reference on noise, thinned noise and in every corner
        let (p, w) = (p(), w());
        assert_eq!((w.on_q8, w.off_q8), (256, 1024));
        for seed in 0..8 {
            let maps = crate::model::hrc::random_maps(seed);
            let mut off = maps[1];
            if seed % 2 == 1 {
                off.iter_mut().step_by(3).for_each(|v| *v = 0);
            }
            let cells = cm(&maps[0], &off);
            let m = Maps::new(&cells);
            let mut f = Fields::default();
            for (x, y) in [(0, 0), (98, 71), (50, 36), (10, 60)] {
                f.insert(x, y);
            }
            let mut g = f.clone();
            f.recentre(&m, &w, &p);
            g.recentre_reference(&m, &w, &p);
            let at = |f: &Fields| {
                f.iter()
                    .map(|a| (a.x, a.y))
                    .collect::<heapless::Vec<_, 6>>()
            };
            assert_eq!(at(&f), at(&g), "seed {seed}");
        }
    }

    #[test]
    fn mean_response_is_over_the_last_d_frames() {
        let mut g = Field::new(0, 0, 0);
        for r in [100, 200, 300, 400, 500] {
            g.push_response(r);
        }
        assert_eq!(g.response(), 500);
        assert_eq!(g.mean_response(4), 350);
        assert_eq!(g.mean_response(1), 500);
        assert_eq!(g.mean_response(16), 300, "only 5 frames of history");
    }

    #[test]
    fn squares_are_clipped() {
        let g = Field::new(0, 3, 70);
        assert_eq!(g.square(36), ((0, 39), (34, 71)));
    }

    #[test]
    fn capacity_is_respected() {
        let mut f = Fields::default();
        for k in 0..MAX_AFS {
            assert!(f.insert(k as u8 * 10, 0).is_some());
        }
        assert_eq!(f.insert(0, 0), None);
        let off = off_map(&[(50, 50, 200)]);
        assert_eq!(
            f.spawn(&Maps::new(&cm(&[0; PIXELS], &off)), &w(), &p()),
            None
        );
    }

    #[test]
    fn the_mean_stays_right_for_fields_older_than_any_counter() {
        let mut g = Field::new(0, 0, 0);
        for _ in 0..70_000 {
            g.push_response(0);
        }
        for _ in 0..4 {
            g.push_response(9000);
        }
        assert_eq!(g.mean_response(4), 9000);
        assert_eq!(g.response(), 9000);
    }

    fn centroids(f: &Fields) -> heapless::Vec<(u32, u8, u8), MAX_AFS> {
        f.iter().map(|g| (g.id, g.x, g.y)).collect()
    }

    mod fast_equals_reference {
        use super::*;
        use proptest::prelude::*;

        proptest! {
            #![proptest_config(ProptestConfig::with_cases(256))]
            #[test]
            fn spawn_and_recentre(
                seed in any::<u32>(),
                sparse in 0u8..5,
                fields in prop::collection::vec((0u8..99, 0u8..72), 0..=MAX_AFS),
                r_af in 1u8..=99,
                r_c in 1u8..=99,
                r_x in 0u8..=99,
                c_frac in 0u8..=100,
                gain in 1u8..=16,
                w in prop::sample::select(&[0.0f32, 0.25, 0.3, 1.0, 4.0][..]),
                t_a in 0u16..3000,
                table_i in any::<bool>(),
            ) {
                // half the cases on Table I's weights, which have their own recentre path
                let (gain, w) = if table_i { (4, 0.25) } else { (gain, w) };
                let maps = crate::model::hrc::random_maps(seed);
                let (mut on, mut off) = (maps[0], maps[1]);
                for (i, (a, b)) in on.iter_mut().zip(off.iter_mut()).enumerate() {
                    // sparse maps: ties and empty windows; sparse = 3: all equal, 4: all saturated
                    match sparse {
                        1 if i % 7 != 0 => (*a, *b) = (0, 0),
                        2 => (*a, *b) = (*a / 64, *b / 64),
                        3 => (*a, *b) = (9, 9),
                        4 => (*a, *b) = (255, 255),
                        _ => {}
                    }
                }
                let p = Params { table1: TableOne { r_af, w, t_a, ..Params::PAPER.table1 }, choices: Choices { r_c, r_x: NonZeroU8::new(r_x), c_frac, gain, ..Params::PAPER.choices }, ..Params::PAPER };
                prop_assert_eq!(p.validate(), Ok(()));
                let w = Weights::new(&p);
                let mut f = Fields::default();
                for &(x, y) in &fields {
                    f.insert(x, y);
                }
                let mut g = f.clone();
                let cells = cm(&on, &off);
                let m = Maps::new(&cells);
                prop_assert_eq!(f.spawn(&m, &w, &p), g.spawn_reference(&m, &w, &p));
                prop_assert_eq!(centroids(&f), centroids(&g));
                f.recentre(&m, &w, &p);
                g.recentre_reference(&m, &w, &p);
                prop_assert_eq!(centroids(&f), centroids(&g));
            }
        }
    }
}

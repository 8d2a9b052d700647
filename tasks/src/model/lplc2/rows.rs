//! The row kernels of Eqs. (6)–(8) for the paper's spacing `s = 1`: the same quadrant sums as
//! [`integrate`](super::integrate), computed row by row with neighbour box sums and the Cortex-M4
//! DSP instructions (the firmware's hot loop; `docs/budget.md` logs how it got here).

use super::{Gate, Lplc2, Region};
use crate::frame::{HEIGHT, WIDTH};
use crate::model::dsp;
use crate::model::hrc::{LmScale, Maps};

/// Eq. (7)'s fixed-point combine `(t4_q16·T4 + t5_q16·T5) >> shift` in 32-bit form.
///
/// Both factors and the shift share a power of two `2^k` (Table I: `t4_q16 = 2^16`,
/// `t5_q16 = 2^20`, `shift = 24`); dropping it is exact, `⌊2^k·Z / 2^shift⌋ = ⌊Z / 2^(shift−k)⌋`,
/// so `LM = max(0, (a·T4 + b·T5) >> shift')` with `a = t4_q16 >> k`, `b = t5_q16 >> k`.
/// It is used only where that is provably the same number in `i32`/`u32`:
/// * `s = 1`, `n ≤ MAX_N` (the row kernel's neighbour sums);
/// * `a, b ≤ 128`, so `a·L` and `b·L` of a byte `L` fit an `i16` lane (`128·255 = 32640`);
/// * `|T| ≤ n·255²` per channel, so `|a·T4 + b·T5| ≤ 256·4·255² < 2^31`;
/// * the largest `LM` times [`WIDTH`] fits a `u32`, so a row's running sum cannot wrap.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Narrow {
    /// `t4_q16 >> k`.
    pub a: i32,
    /// `t5_q16 >> k`.
    pub b: i32,
    /// `shift − k`, capped at 31 (for `|Z| < 2^31`, `Z >> 31` is `⌊Z / 2^m⌋` for every `m ≥ 31`).
    pub shift: u32,
    /// Connected neurons `n`.
    pub n: usize,
    /// Rows whose sums of `LM` over the retina's width stay below `u32::MAX` (≥ 1): a band of
    /// up to this many rows is summed in `u32`.
    pub rows: usize,
}

impl Narrow {
    /// The narrow form of `sc`, if it has one.
    pub fn new(sc: &LmScale) -> Option<Narrow> {
        // the row kernel computes the opponent form only
        if !sc.opponent || sc.s != 1 || sc.n == 0 || sc.n > usize::from(crate::model::params::MAX_N)
        {
            return None;
        }
        if sc.t4_q16 < 0 || sc.t5_q16 < 0 || sc.shift > 63 {
            return None;
        }
        let tz = |v: i64| if v == 0 { 63 } else { v.trailing_zeros() };
        let k = tz(sc.t4_q16).min(tz(sc.t5_q16)).min(sc.shift);
        let (a, b, shift) = (sc.t4_q16 >> k, sc.t5_q16 >> k, sc.shift - k);
        if a > 128 || b > 128 {
            return None;
        }
        let t_max = sc.n as i64 * 255 * 255;
        let lm_max = ((a + b) * t_max) >> shift;
        if lm_max * WIDTH as i64 > i64::from(u32::MAX) {
            return None;
        }
        let row_max = (lm_max * WIDTH as i64).max(1);
        Some(Narrow {
            a: a as i32,
            b: b as i32,
            shift: shift.min(31),
            n: sc.n,
            rows: (i64::from(u32::MAX) / row_max).clamp(1, HEIGHT as i64) as usize,
        })
    }
}

/// Columns of margin around a packed row, so that neighbours `x ± c` (`c ≤ MAX_N`) of any
/// column index without a bounds test; the margin holds zeros: no neuron outside the retina.
const PAD: usize = crate::model::params::MAX_N as usize;
/// A packed row with its margins (and one spare slot for the running windows' last update).
const PADDED: usize = WIDTH + 2 * PAD + 1;
/// Column breakpoints of up to [`MAX_AFS`](crate::model::MAX_AFS) fields: each field's
/// `x0`, `x̄` and `x̄ + 1` (clamped to the square) and `x1 + 1`.
const MAX_BP: usize = 4 * crate::model::MAX_AFS;

/// Byte lanes 0 and 2 of a [`Cells`](crate::model::hrc::Cells) word: `[on | on_d << 16]` (`>> 8` first for `off`).
const LANES: u32 = 0x00FF_00FF;

/// A cell's channels as 16-bit lane pairs, `[on | on_d << 16, off | off_d << 16]` (`UXTB16`,
/// `UXTB16 …, ROR #8`).
#[inline(always)]
fn unpack(c: u32) -> [u32; 2] {
    [c & LANES, (c >> 8) & LANES]
}

/// One column of a row as the row kernel reads it, at index `x + PAD` of a [`Row`]: `[0..2]`
/// the pixel's [`unpack`]ed channels (per channel its value at `t` and at `t − C_d` in the two
/// 16-bit lanes of a word, the layout of the dual multiply-subtract in [`lm`]), `[2..4]` its
/// vertical neighbour sums in the same layout. Lane sums of up to `MAX_N` such words stay
/// ≤ 1020: word arithmetic never carries or borrows between the lanes. Own values and vertical
/// sums side by side: the kernel walks one pointer, no second array zipped in.
type Column = [u32; 4];
/// A row of [`Column`]s with its margins (and one spare slot for the running windows' last
/// update).
type Row = [Column; PADDED];

/// `row[x + PAD][0..2] =` [`unpack`] of the cells of row `y`, columns `c0..c1`.
#[inline(always)]
fn pack_row(row: &mut Row, m: &Maps, y: usize, c0: usize, c1: usize) {
    let r = y * WIDTH;
    let cells = m.cells.get(r + c0..r + c1).unwrap_or_default();
    for (p, &c) in row[c0 + PAD..c1 + PAD].iter_mut().zip(cells) {
        [p[0], p[1]] = unpack(c);
    }
}

/// For columns `c0..c1` of row `y`: `row[x + PAD]` = the pixel's own values ([`pack_row`]'s
/// work) and its vertical neighbour sums `Σ_{c=1..K} P(x, y ∓ c)` (up if `UP`, else down),
/// packed the same way, in one pass over the columns. Rows `y − K ..= y` or `y ..= y + K`
/// must be on the retina (were they not, the block would be empty and the row keep its old
/// values). A column's cells are `WIDTH` apart in one window of those rows, whose length is a
/// constant: no bounds test per load; one word load per cell, both channels' lanes summed with
/// `UXTAB16` (a lane sum of `K ≤ 4` bytes is ≤ 1020, no carry).
#[inline(always)]
fn columns_k<const K: usize, const UP: bool>(
    row: &mut Row,
    m: &Maps,
    y: usize,
    c0: usize,
    c1: usize,
) {
    let out = &mut row[c0 + PAD..c1 + PAD];
    let len = out.len();
    let top = if UP { y.checked_sub(K) } else { Some(y) };
    let base = top.map_or(usize::MAX, |t| t * WIDTH + c0);
    let Some(blk) = m.cells.get(base..base.saturating_add(K * WIDTH + len)) else {
        return;
    };
    // offsets of the first neighbour row and of the own row in the block
    let (v0, own) = if UP { (0, K * WIDTH) } else { (WIDTH, 0) };
    // one slice of `len` cells per row, zipped: one loop bound, no bounds test per load (rows
    // past `K` are not read)
    let at = |o: usize| blk.get(o..o + len).unwrap_or_default();
    let nb = |k: usize| {
        at(if K == 0 {
            own
        } else {
            v0 + k.min(K - 1) * WIDTH
        })
    };
    let cols = out.iter_mut().zip(at(own)).zip(nb(0)).zip(nb(1));
    for ((((o, &p), &c0), &c1), (&c2, &c3)) in cols.zip(nb(2).iter().zip(nb(3))) {
        let c = [c0, c1, c2, c3];
        let [mut on, mut off] = [0u32, 0u32];
        if K > 0 {
            [on, off] = unpack(c[0]);
        }
        for &c in c.get(1..K).unwrap_or_default() {
            on = dsp::uxtab16(on, c);
            off = dsp::uxtab16_ror8(off, c);
        }
        let [p_on, p_off] = unpack(p);
        *o = [p_on, p_off, on, off];
    }
}

/// [`columns_k`] with `K = min(n, rows left on the retina)` (Eq. 6's `q_c = p + c·(0, ±1)`;
/// the neurons off the retina are 0).
fn columns<const UP: bool>(row: &mut Row, m: &Maps, y: usize, n: usize, c0: usize, c1: usize) {
    let k = if UP {
        n.min(y)
    } else {
        n.min((HEIGHT - 1).saturating_sub(y))
    };
    match k {
        0 => columns_k::<0, UP>(row, m, y, c0, c1),
        1 => columns_k::<1, UP>(row, m, y, c0, c1),
        2 => columns_k::<2, UP>(row, m, y, c0, c1),
        3 => columns_k::<3, UP>(row, m, y, c0, c1),
        _ => columns_k::<4, UP>(row, m, y, c0, c1),
    }
}

/// What the row kernel reads for one row `y`.
#[derive(Clone, Copy)]
struct RowCtx<'a> {
    /// Row `y` ([`pack_row`]) with its vertical neighbour sums (one direction, [`columns`]),
    /// column `x` at index `x + PAD`.
    row: &'a Row,
    /// `a` and `b` of [`Narrow`] (≤ 128, so `a·L` of a byte fits an `i16` lane).
    a: u32,
    b: u32,
    shift: u32,
}

/// Eq. (7), rectified, from the pixel's own scaled values and its packed neighbour sums:
///
/// `T = Σ_c [L(q_c,t)·L(p,t−C_d) − L(q_c,t−C_d)·L(p,t)] = L(p,t−C_d)·S(t) − L(p,t)·S(t−C_d)`
/// with `S = Σ_c L(q_c)` (Eq. 6). Per channel the own word holds `[a·L(p,t) | a·L(p,t−C_d)]`
/// and the sum word `[S(t) | S(t−C_d)]`, so `a·T` is one dual multiply-subtract with exchanged
/// halves (`SMUSDX`), `+ b·T5` a second one (`SMLSDX`), and the scaling and half-wave
/// rectification `max(0, · >> SH)` one `USAT` ([`dsp`](crate::model::dsp)). Every product is below
/// `32640·1020 < 2^25`: no `i32` overflow. `SH = 0` takes the shift from `shift` instead.
#[inline(always)]
fn lm<const SH: u32>(own_on: u32, own_off: u32, s_on: u32, s_off: u32, shift: u32) -> u32 {
    let pre = dsp::smlsdx(s_off, own_off, dsp::smusdx(s_on, own_on));
    if SH == 0 {
        // a row's sum stays below u32::MAX (Narrow::new)
        (pre >> shift).max(0) as u32
    } else {
        dsp::rectify_asr::<SH>(pre)
    }
}

/// `[Σ LM_r, Σ LM_l, Σ LM_v]` over the columns `s..e` of the row, `N` connected neurons: `v`
/// (the direction of the vertical sums in the row's columns) if `V`, `r` if `R`, `l` if `L`
/// (0 for a direction not asked: a segment right of every field's centroid needs no `l`,
/// Eq. 8). `SH` as in [`lm`].
///
/// Horizontal neighbour sums are running windows in registers:
/// `R(x) = Σ_{c=1..N} P(x + c)`, `R(x+1) = R(x) + P(x+1+N) − P(x+1)`;
/// `L(x) = Σ_{c=1..N} P(x − c)`, `L(x+1) = L(x) + P(x) − P(x−N)` (zeros off the retina).
#[inline(always)]
fn seg<const R: bool, const L: bool, const V: bool, const N: usize, const SH: u32>(
    r: &RowCtx,
    s: usize,
    e: usize,
) -> [u32; 3] {
    // P(x) sits at index x + PAD; the windows span P(x − N ..= x + N + 1)
    let (i0, i1) = (s + PAD - N, e + PAD + N + 1);
    let row = &r.row[i0..i1];
    let sum = |p: &[Column]| {
        p.iter().fold([0u32; 2], |a, v| {
            [a[0].wrapping_add(v[0]), a[1].wrapping_add(v[1])]
        })
    };
    let [mut l_on, mut l_off] = sum(&row[..N]);
    let [mut r_on, mut r_off] = sum(&row[N + 1..2 * N + 1]);
    let (a, b, shift) = (r.a, r.b, r.shift);
    let (mut sr, mut sl, mut sv) = (0u32, 0u32, 0u32);
    // P(x), carried: the next pixel's own values are the R window's leaving word
    let mut own = row[N];
    for w in row.windows(2 * N + 2) {
        let [p_on, p_off, v_on, v_off] = own;
        own = w[N + 1];
        // both lanes scaled at once: a·L, b·L ≤ 32640 never carry into the next lane
        let (own_on, own_off) = (p_on * a, p_off * b);
        if V {
            sv = sv.wrapping_add(lm::<SH>(own_on, own_off, v_on, v_off, shift));
        }
        if R {
            sr = sr.wrapping_add(lm::<SH>(own_on, own_off, r_on, r_off, shift));
            let ([e_on, e_off, ..], [x_on, x_off, ..]) = (w[2 * N + 1], own);
            r_on = r_on.wrapping_add(e_on).wrapping_sub(x_on);
            r_off = r_off.wrapping_add(e_off).wrapping_sub(x_off);
        }
        if L {
            sl = sl.wrapping_add(lm::<SH>(own_on, own_off, l_on, l_off, shift));
            let [x_on, x_off, ..] = w[0];
            l_on = l_on.wrapping_add(p_on).wrapping_sub(x_on);
            l_off = l_off.wrapping_add(p_off).wrapping_sub(x_off);
        }
    }
    [sr, sl, sv]
}

/// [`seg`] with the vertical direction, `r` if `R` and `l` if `L`; both `r` and `l` in two
/// passes (`r` with the vertical, then `l`), which keeps each loop's running sums in registers
/// where one loop with all three spilled.
#[inline(always)]
fn seg_vs<const R: bool, const L: bool, const N: usize, const SH: u32>(
    r: &RowCtx,
    s: usize,
    e: usize,
) -> [u32; 3] {
    if R && L {
        let [sr, _, sv] = seg::<true, false, true, N, SH>(r, s, e);
        let [_, sl, _] = seg::<false, true, false, N, SH>(r, s, e);
        [sr, sl, sv]
    } else {
        seg::<R, L, true, N, SH>(r, s, e)
    }
}

/// `Σ LM_d` over the columns `s..e` of row `y` with `K ≥ 1` neurons below it, all on the
/// retina: the second vertical direction of a row with fields above and below. The down sums
/// are taken from the cells as they are needed (as in [`columns_k`]), not stored in the row.
/// `SH` as in [`lm`].
#[inline(always)]
fn seg_down<const K: usize, const SH: u32>(
    r: &RowCtx,
    m: &Maps,
    y: usize,
    s: usize,
    e: usize,
) -> u32 {
    let own = r.row.get(s + PAD..e + PAD).unwrap_or_default();
    let len = own.len();
    let base = (y + 1) * WIDTH + s;
    let blk = m.cells.get(base..base + (K - 1) * WIDTH + len);
    // one slice of `len` cells per row below, zipped as in `columns_k` (rows past `K` unread)
    let at = |k: usize| {
        let o = k.min(K - 1) * WIDTH;
        blk.and_then(|b| b.get(o..o + len)).unwrap_or_default()
    };
    let (a, b, shift) = (r.a, r.b, r.shift);
    let mut sv = 0u32;
    let cols = own.iter().zip(at(0)).zip(at(1));
    for (((o, &c0), &c1), (&c2, &c3)) in cols.zip(at(2).iter().zip(at(3))) {
        let c = [c0, c1, c2, c3];
        let [mut on, mut off] = unpack(c[0]);
        for &c in c.get(1..K).unwrap_or_default() {
            on = dsp::uxtab16(on, c);
            off = dsp::uxtab16_ror8(off, c);
        }
        sv = sv.wrapping_add(lm::<SH>(o[0] * a, o[1] * b, on, off, shift));
    }
    sv
}

/// [`seg_down`] with `K = min(N, rows below y)` (none: no neighbour, no motion).
#[inline(always)]
fn seg_down_n<const N: usize, const SH: u32>(
    r: &RowCtx,
    m: &Maps,
    y: usize,
    s: usize,
    e: usize,
) -> u32 {
    match N.min((HEIGHT - 1).saturating_sub(y)) {
        k if k == N => seg_down::<N, SH>(r, m, y, s, e),
        1 => seg_down::<1, SH>(r, m, y, s, e),
        2 => seg_down::<2, SH>(r, m, y, s, e),
        3 => seg_down::<3, SH>(r, m, y, s, e),
        _ => 0,
    }
}

/// [`integrate_all`](super::integrate_all) row by row in the narrow form (`s = 1`).
///
/// The fields' columns `x0`, `x̄`, `x̄ + 1` (clamped to the square) and `x1 + 1` cut the row
/// into at most `MAX_BP − 1` segments. For each row, every segment some field (off its
/// centroid's row) covers is run once through the row kernel: per pixel its own values and the
/// local motion of r, l and the row's vertical direction (u above a centroid, d below; a
/// second, vertical-only run when the row has fields of both kinds), summed per segment over
/// a band of rows that no field starts, ends or crosses its centroid in. Prefix sums over the
/// segments then give each field its quadrant segments, Eq. (8): left of `x̄` to Q2 (l + u) or
/// Q3 (l + d), right of `x̄` to Q1 (r + u) or Q4 (r + d); the centroid's own row and column
/// belong to no quadrant. A band's sums stay below `u32::MAX` (`Narrow::rows`).
pub fn integrate_rows(m: &Maps, nw: &Narrow, regions: &[Region], g: &Gate, out: &mut [Lplc2]) {
    let count = regions.len().min(out.len()).min(crate::model::MAX_AFS);
    let (regions, out) = (&regions[..count], &mut out[..count]);
    let n = nw.n.clamp(1, PAD);
    // per field: rows (y0, y1 + 1), centroid row, and the breakpoints x0, left end, right
    // start, x1 + 1 (as columns, then as indices into `bp`)
    // (an empty square keeps rows 0..0: never on a row)
    let mut fields = [(0usize, 0usize, 0usize, [0usize; 4]); crate::model::MAX_AFS];
    let mut bp = [0usize; MAX_BP];
    let mut nbp = 0;
    for (f, r) in fields.iter_mut().zip(regions) {
        let (x0, x1) = (r.cols.0, r.cols.1.saturating_add(1).min(WIDTH));
        let (y0, y1) = (r.rows.0, r.rows.1.saturating_add(1).min(HEIGHT));
        let cx = r.centre.0;
        let cols = [x0, cx.clamp(x0, x1), cx.saturating_add(1).clamp(x0, x1), x1];
        if x0 < x1 && y0 < y1 {
            for (b, c) in bp[nbp..].iter_mut().zip(cols) {
                *b = c;
            }
            nbp = (nbp + 4).min(MAX_BP);
            *f = (y0, y1, r.centre.1, cols);
        }
    }
    // sorted, unique breakpoints
    let bp = {
        let v = &mut bp[..nbp];
        v.sort_unstable();
        let mut u = 0;
        for i in 0..v.len() {
            if u == 0 || v[i] != v[u - 1] {
                v[u] = v[i];
                u += 1;
            }
        }
        &bp[..u]
    };
    for f in fields[..count].iter_mut() {
        for c in f.3.iter_mut() {
            *c = bp.iter().position(|&b| b == *c).unwrap_or(0);
        }
    }
    let fields = &fields[..count];

    let mut q = [[0u64; 4]; crate::model::MAX_AFS];
    let a = u32::try_from(nw.a).unwrap_or(0);
    let b = u32::try_from(nw.b).unwrap_or(0);
    let (rows, shift) = (nw.rows, nw.shift);
    // the kernels' `n` and Table I's constants chosen once, not per segment
    let (f, q_) = (fields, &mut q);
    match n {
        3 if (a, b, shift) == (1, 16, 8) => bands::<3, 8>(m, (1, 16, 8), rows, f, bp, q_),
        1 => bands::<1, 0>(m, (a, b, shift), rows, f, bp, q_),
        2 => bands::<2, 0>(m, (a, b, shift), rows, f, bp, q_),
        3 => bands::<3, 0>(m, (a, b, shift), rows, f, bp, q_),
        _ => bands::<4, 0>(m, (a, b, shift), rows, f, bp, q_),
    }
    for (o, qk) in out.iter_mut().zip(q.iter()) {
        *o = Lplc2::from_sums(*qk, g);
    }
}

/// The rows of [`integrate_rows`] with `N` connected neurons (`SH` as in [`lm`]): the
/// `fields` (rows, centroid row, breakpoint indices) add their quadrant sums to `q`.
#[inline(always)]
fn bands<const N: usize, const SH: u32>(
    m: &Maps,
    (a, b, shift): (u32, u32, u32),
    rows: usize,
    fields: &[(usize, usize, usize, [usize; 4])],
    bp: &[usize],
    q: &mut [[u64; 4]; crate::model::MAX_AFS],
) {
    let n = N;
    let mut row: Row = [[0; 4]; PADDED];
    let (y_lo, y_hi) = fields
        .iter()
        .fold((HEIGHT, 0), |(a, b), f| (a.min(f.0), b.max(f.1)));
    // Bands of rows in which no field starts, ends or crosses its centroid's row: the segments
    // needed, the directions and the fields' quadrants are the same on every row of a band, so
    // they are worked out once per band, and each segment's sums are added up over the band's
    // rows before the fields take their spans. At most `nw.rows` rows a band, so that the
    // band's sums stay below `u32::MAX` (`Narrow::rows`).
    // a band's segment sums and kernel calls (below), rewritten as far as each band uses them
    let mut acc = [[0u32; 4]; MAX_BP];
    let mut calls = [(0u8, 0u8, 0u8, 0u8); MAX_BP];
    let mut downs = [(0u8, 0u8, 0u8); MAX_BP];
    let mut y = y_lo;
    while y < y_hi {
        let mut y_end = y_hi.min(y.saturating_add(rows.max(1)));
        for &(y0, y1, cy, _) in fields {
            for e in [y0, cy, cy.saturating_add(1), y1] {
                if e > y && e < y_end {
                    y_end = e;
                }
            }
        }
        let band = y..y_end;
        let y0_band = y;
        y = y_end;
        // the segments some field needs in this band, and the vertical directions
        // bit 0: r, bit 1: l (left of some field's centroid), bit 2: d (some field below its
        // centroid)
        let mut need = [0u8; MAX_BP];
        let (mut up, mut down) = (false, false);
        // the columns of the fields above their centroid (u) and of those below it (d)
        let (mut cols_u, mut cols_d) = ((WIDTH, 0), (WIDTH, 0));
        // the breakpoints some field's spans start or end at (bit `i`: breakpoint `i`), per
        // sum: r, l, and the vertical of the fields above their centroid (u) and below it (d)
        let bit = |i: usize| 1u32.checked_shl(i as u32).unwrap_or(0);
        let (mut cut_r, mut cut_l, mut cut_v) = (0u32, 0u32, [0u32; 2]);
        for &(y0, y1, cy, c) in fields {
            if (y0..y1).contains(&y0_band) && y0_band != cy {
                let below = y0_band > cy;
                up |= !below;
                down |= below;
                let d = if below { 4 } else { 0 };
                need[c[0]..c[1]].iter_mut().for_each(|m| *m |= 2 | d);
                need[c[2]..c[3]].iter_mut().for_each(|m| *m |= 1 | d);
                let cols = if below { &mut cols_d } else { &mut cols_u };
                *cols = (cols.0.min(bp[c[0]]), cols.1.max(bp[c[3]]));
                let (l, r) = (bit(c[0]) | bit(c[1]), bit(c[2]) | bit(c[3]));
                cut_r |= r;
                cut_l |= l;
                cut_v[usize::from(below)] |= l | r;
            }
        }
        if !(up || down) {
            continue;
        }
        let (ua, ub) = (cols_u.0.min(cols_d.0), cols_u.1.max(cols_d.1));
        let (p0, p1) = (ua.saturating_sub(n), (ub + n).min(WIDTH));
        // own values on p0..p1; the primary vertical sums (u if the band has an upward field,
        // else d) only under the fields of that direction, va..vb: the other columns keep an
        // earlier row's sums, and their local motion enters only segments that no field of
        // the primary direction sums
        let (va, vb) = if up { cols_u } else { cols_d };
        let segs = bp.len().saturating_sub(1);
        // per segment, summed over the band's rows: [r, l, primary vertical, second vertical]
        // (zeroed where this band's segments and prefix sums use it)
        acc.iter_mut().take(segs + 1).for_each(|a| *a = [0; 4]);
        // the cuts per sum as `acc` holds them: r, l, the primary vertical, the second one (d in
        // a band with fields above and below)
        let [cut_u, cut_d] = cut_v;
        let cut = if up {
            [cut_r, cut_l, cut_u, cut_d]
        } else {
            [cut_r, cut_l, cut_d, 0]
        };
        // the kernel calls: runs of segments that need the same directions, cut only where a
        // sum they compute is read (a run's sums go to its first segment, the others keep 0:
        // the prefix sums are the same at every cut a field reads). Main pass: (first segment,
        // start, end, r/l need); second vertical: (first segment, start, end).
        let (mut nc, mut nd) = (0, 0);
        let col = |i: usize| bp.get(i).map_or(0, |&c| c as u8);
        let mut i = 0;
        while i < segs {
            let kind = need[i] & 3;
            let reads = cut[2] | [0, cut[0], cut[1], cut[0] | cut[1]][usize::from(kind)];
            let mut j = i + 1;
            while j < segs && need[j] & 3 == kind && reads & bit(j) == 0 {
                j += 1;
            }
            if kind != 0 {
                if let Some(c) = calls.get_mut(nc) {
                    *c = (i as u8, col(i), col(j), kind);
                    nc += 1;
                }
            }
            i = j;
        }
        let mut i = 0;
        while i < segs && up && down {
            let mut j = i + 1;
            if need[i] & 4 != 0 {
                while j < segs && need[j] & 4 != 0 && cut[3] & bit(j) == 0 {
                    j += 1;
                }
                if let Some(c) = downs.get_mut(nd) {
                    *c = (i as u8, col(i), col(j));
                    nd += 1;
                }
            }
            i = j;
        }
        for y in band {
            pack_row(&mut row, m, y, p0, va);
            if up {
                columns::<true>(&mut row, m, y, n, va, vb);
            } else {
                columns::<false>(&mut row, m, y, n, va, vb);
            }
            pack_row(&mut row, m, y, vb, p1);
            let ctx = RowCtx {
                row: &row,
                a,
                b,
                shift,
            };
            for &(i, s, e, kind) in calls.get(..nc).unwrap_or_default() {
                let (s, e) = (usize::from(s), usize::from(e));
                let sums = match kind {
                    1 => seg_vs::<true, false, N, SH>(&ctx, s, e),
                    2 => seg_vs::<false, true, N, SH>(&ctx, s, e),
                    _ => seg_vs::<true, true, N, SH>(&ctx, s, e),
                };
                if let Some(acc) = acc.get_mut(usize::from(i)) {
                    for (a, v) in acc.iter_mut().zip(sums) {
                        *a = a.wrapping_add(v);
                    }
                }
            }
            for &(i, s, e) in downs.get(..nd).unwrap_or_default() {
                let d = seg_down_n::<N, SH>(&ctx, m, y, usize::from(s), usize::from(e));
                if let Some(acc) = acc.get_mut(usize::from(i)) {
                    acc[3] = acc[3].wrapping_add(d);
                }
            }
        }
        // prefix sums over the segments, in place: `pre[i]` = sums of the segments before `i`
        // (`segs < MAX_BP`)
        let mut run = [0u32; 4];
        for p in acc.iter_mut().take(segs + 1) {
            let v = *p;
            *p = run;
            for (r, v) in run.iter_mut().zip(v) {
                *r = r.wrapping_add(v);
            }
        }
        let pre = &acc;
        // the down sums: the primary vertical when the band has no upward field
        let d_slot = if up { 3 } else { 2 };
        for (&(y0, y1, cy, c), acc) in fields.iter().zip(q.iter_mut()) {
            if !(y0..y1).contains(&y0_band) || y0_band == cy {
                continue;
            }
            let span = |k: usize, s: usize, e: usize| u64::from(pre[e][k].wrapping_sub(pre[s][k]));
            // left: x0..x̄, right: x̄+1..=x1
            let (l0, l1, r0, r1) = (c[0], c[1], c[2], c[3]);
            if y0_band < cy {
                acc[0] += span(0, r0, r1) + span(2, r0, r1);
                acc[1] += span(1, l0, l1) + span(2, l0, l1);
            } else {
                acc[3] += span(0, r0, r1) + span(d_slot, r0, r1);
                acc[2] += span(1, l0, l1) + span(d_slot, l0, l1);
            }
        }
    }
}

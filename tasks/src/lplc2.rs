//! LPLC2 integration within an attention field: Eqs. (8)–(9).
//!
//! The field's square is split by its centroid into four quadrants; each quadrant collects the
//! two *outward* directions of its dendritic arms (Eq. 8):
//!
//! | quadrant | where (image) | collects |
//! |---|---|---|
//! | Q1 | upper right (`x > x̄`, `y < ȳ`) | right + up |
//! | Q2 | upper left (`x < x̄`, `y < ȳ`) | left + up |
//! | Q3 | lower left (`x < x̄`, `y > ȳ`) | left + down |
//! | Q4 | lower right (`x > x̄`, `y > ȳ`) | right + down |
//!
//! Pixels on the centroid's row or column belong to no quadrant, so a stimulus centred on the
//! field excites the four quadrants symmetrically.
//!
//! Eq. (9): `LPLC2 = bool(∏Q)·ΣQ`, the cell fires only when every arm sees its preferred
//! (outward) motion. A quadrant counts as excited only above the noise floor `q_floor`: without it
//! sensor noise alone opens the gate now and then (`docs/model.md`).

use crate::frame::{HEIGHT, PIXELS, WIDTH};
use crate::hrc::{local_motion, Direction, LmScale, Maps};

/// The four quadrant sums and the LPLC2 response of one field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Lplc2 {
    /// `Q1..Q4` of Eq. (8), saturating.
    pub quadrants: [u32; 4],
    /// `LPLC2_k` of Eq. (9).
    pub response: u32,
}

/// The outward directions collected by each quadrant (Eq. 8).
pub const QUADRANT_DIRECTIONS: [[Direction; 2]; 4] = [
    [Direction::Right, Direction::Up],
    [Direction::Left, Direction::Up],
    [Direction::Left, Direction::Down],
    [Direction::Right, Direction::Down],
];

/// Quadrant (0..4) of pixel `(x, y)` around centroid `(cx, cy)`, `None` on the axes.
#[inline(always)]
pub fn quadrant_of(x: usize, y: usize, cx: usize, cy: usize) -> Option<usize> {
    use core::cmp::Ordering::*;
    match (x.cmp(&cx), y.cmp(&cy)) {
        (Greater, Less) => Some(0),
        (Less, Less) => Some(1),
        (Less, Greater) => Some(2),
        (Greater, Greater) => Some(3),
        _ => None,
    }
}

/// Eq. (9): the gate and sum over four quadrant values. A quadrant is excited when it exceeds
/// the absolute floor `q_floor` and `q_balance` % of the strongest quadrant: an arm that sees a
/// trickle while another sees a flood is not "receiving its preferred motion" (translation and
/// gratings flood two arms and leak into the other two).
pub fn gate(quadrants: [u32; 4], q_floor: u32, q_balance: u8) -> u32 {
    let max = quadrants.iter().copied().max().unwrap_or(0);
    let rel = (u64::from(max) * u64::from(q_balance)) / 100;
    if quadrants
        .iter()
        .all(|&q| q > q_floor && u64::from(q) >= rel)
    {
        quadrants.iter().fold(0u32, |a, &q| a.saturating_add(q))
    } else {
        0
    }
}

/// Eqs. (8)–(9) for the field centred at `(cx, cy)` whose square spans columns `x0..=x1` and
/// rows `y0..=y1` (already clipped to the retina).
pub fn integrate(
    m: &Maps,
    sc: &LmScale,
    centre: (usize, usize),
    cols: (usize, usize),
    rows: (usize, usize),
    q_floor: u32,
    q_balance: u8,
) -> Lplc2 {
    let (cx, cy) = centre;
    let mut q = [0u64; 4];
    for y in rows.0..=rows.1 {
        for x in cols.0..=cols.1 {
            if let Some(k) = quadrant_of(x, y, cx, cy) {
                let [a, b] = QUADRANT_DIRECTIONS[k];
                q[k] += u64::from(local_motion(m, sc, x, y, a))
                    + u64::from(local_motion(m, sc, x, y, b));
            }
        }
    }
    let quadrants = q.map(|v| v.min(u64::from(u32::MAX)) as u32);
    Lplc2 {
        quadrants,
        response: gate(quadrants, q_floor, q_balance),
    }
}

/// Where one field integrates: its centroid and its clipped square.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Region {
    /// Centroid `(x̄, ȳ)`.
    pub centre: (usize, usize),
    /// Columns `x0..=x1`.
    pub cols: (usize, usize),
    /// Rows `y0..=y1`.
    pub rows: (usize, usize),
}

/// Eqs. (8)–(9) for several fields in one pass over the union of their squares. Same result as
/// [`integrate`] per field (tests hold it to that on random maps, regions and parameters).
///
/// With the paper's spacing `s = 1` and a narrow combine ([`Narrow`], true of Table I), it runs
/// row by row ([`integrate_rows`]): neighbour box sums instead of per-neuron products, each
/// needed direction's local motion once per pixel, and quadrants summed as row segments.
/// Otherwise it takes the pixel-by-pixel [`integrate_all_general`].
pub fn integrate_all(
    m: &Maps,
    sc: &LmScale,
    regions: &[Region],
    q_floor: u32,
    q_balance: u8,
    out: &mut [Lplc2],
) {
    match Narrow::new(sc) {
        Some(nw) => integrate_rows(m, &nw, regions, q_floor, q_balance, out),
        None => integrate_all_general(m, sc, regions, q_floor, q_balance, out),
    }
}

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
}

impl Narrow {
    /// The narrow form of `sc`, if it has one.
    pub fn new(sc: &LmScale) -> Option<Narrow> {
        if sc.s != 1 || sc.n == 0 || sc.n > usize::from(crate::params::MAX_N) {
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
        Some(Narrow {
            a: a as i32,
            b: b as i32,
            shift: shift.min(31),
            n: sc.n,
        })
    }
}

/// Columns of margin around a packed row, so that neighbours `x ± c` (`c ≤ MAX_N`) of any
/// column index without a bounds test; the margin holds zeros: no neuron outside the retina.
const PAD: usize = crate::params::MAX_N as usize;
/// A packed row with its margins (and one spare slot for the running window's last read).
const PADDED: usize = WIDTH + 2 * PAD + 1;

/// Signed low half of a packed word (an `i16` lane).
#[inline(always)]
fn lo(v: u32) -> i32 {
    i32::from(v as u16 as i16)
}

/// Signed high half of a packed word (an `i16` lane).
#[inline(always)]
fn hi(v: u32) -> i32 {
    (v as i32) >> 16
}

/// One channel pair (`on`/`off` at `t`, or at `t − C_d`) of the row being processed, packed
/// as `on | off << 16`: sums of up to `MAX_N` bytes (≤ 1020) never carry between the lanes.
struct Packed {
    /// The row itself, at index `x + PAD`.
    row: [u32; PADDED],
    /// Horizontal window `W(x) = Σ_{c=0..n−1} P(x + c)` at index `x + PAD`: the rightward
    /// neighbours of `x` are `W(x + 1)`, the leftward ones `W(x − n)`.
    win: [u32; PADDED],
    /// Downward neighbours `Σ_{c=1..n} P(x, y + c)` of the current row.
    down: [u32; WIDTH],
    /// Upward neighbours `Σ_{c=1..n} P(x, y − c)` of the current row.
    up: [u32; WIDTH],
}

impl Packed {
    const fn new() -> Self {
        Packed {
            row: [0; PADDED],
            win: [0; PADDED],
            down: [0; WIDTH],
            up: [0; WIDTH],
        }
    }
}

/// Row `y` of two byte maps, columns `c0..c1`.
#[inline(always)]
fn rows2<'a>(
    a: &'a [u8; PIXELS],
    b: &'a [u8; PIXELS],
    y: usize,
    c0: usize,
    c1: usize,
) -> (&'a [u8], &'a [u8]) {
    let r = y * WIDTH;
    (&a[r + c0..r + c1], &b[r + c0..r + c1])
}

/// `acc[i] += pack(a[i], b[i])` (`add`) or `acc[i] −= pack(a[i], b[i])`; lane-wise sums stay
/// in `0..=MAX_N·255`, so the word arithmetic never borrows or carries between lanes.
#[inline(always)]
fn acc_packed(acc: &mut [u32], a: &[u8], b: &[u8], add: bool) {
    let it = acc.iter_mut().zip(a).zip(b);
    if add {
        for ((s, &a), &b) in it {
            *s = s.wrapping_add(u32::from(a) | u32::from(b) << 16);
        }
    } else {
        for ((s, &a), &b) in it {
            *s = s.wrapping_sub(u32::from(a) | u32::from(b) << 16);
        }
    }
}

impl Packed {
    /// Neighbour sums of the first row `y` of the box, columns `c0..c1`, from scratch.
    fn start(
        &mut self,
        (a, b): (&[u8; PIXELS], &[u8; PIXELS]),
        y: usize,
        n: usize,
        (c0, c1): (usize, usize),
    ) {
        self.down[c0..c1].fill(0);
        self.up[c0..c1].fill(0);
        for c in 1..=n {
            if y + c < HEIGHT {
                let (ra, rb) = rows2(a, b, y + c, c0, c1);
                acc_packed(&mut self.down[c0..c1], ra, rb, true);
            }
            if let Some(yu) = y.checked_sub(c) {
                let (ra, rb) = rows2(a, b, yu, c0, c1);
                acc_packed(&mut self.up[c0..c1], ra, rb, true);
            }
        }
    }

    /// Moves the vertical sums from row `y − 1` to row `y` (columns `c0..c1`), then packs row `y`
    /// (columns `p0..p1`) and its horizontal windows (columns `c0 − n ..= c1`).
    ///
    /// `U(y) = U(y−1) + P(y−1) − P(y−1−n)` and `D(y) = D(y−1) − P(y) + P(y+n)`: each sum drops
    /// the neuron that left the reach and takes the one that entered (none beyond the retina).
    fn advance(
        &mut self,
        (a, b): (&[u8; PIXELS], &[u8; PIXELS]),
        y: usize,
        n: usize,
        (c0, c1): (usize, usize),
        (p0, p1): (usize, usize),
        first: bool,
    ) {
        if !first {
            // U gains row y − 1 (still in `row`) and loses row y − 1 − n
            for (u, &p) in self.up[c0..c1]
                .iter_mut()
                .zip(&self.row[c0 + PAD..c1 + PAD])
            {
                *u = u.wrapping_add(p);
            }
            if let Some(yo) = (y - 1).checked_sub(n) {
                let (ra, rb) = rows2(a, b, yo, c0, c1);
                acc_packed(&mut self.up[c0..c1], ra, rb, false);
            }
        }
        let (ra, rb) = rows2(a, b, y, p0, p1);
        for ((p, &a), &b) in self.row[p0 + PAD..p1 + PAD].iter_mut().zip(ra).zip(rb) {
            *p = u32::from(a) | u32::from(b) << 16;
        }
        if !first {
            // D loses row y and gains row y + n
            for (d, &p) in self.down[c0..c1]
                .iter_mut()
                .zip(&self.row[c0 + PAD..c1 + PAD])
            {
                *d = d.wrapping_sub(p);
            }
            if y + n < HEIGHT {
                let (ra, rb) = rows2(a, b, y + n, c0, c1);
                acc_packed(&mut self.down[c0..c1], ra, rb, true);
            }
        }
        // W(x) for x = c0 − n ..= c1, i.e. indices j0 ..= j1, by a running window
        let (j0, j1) = (c0 + PAD - n, c1 + PAD);
        let mut w = self.row[j0..j0 + n]
            .iter()
            .fold(0u32, |s, &p| s.wrapping_add(p));
        self.win[j0] = w;
        let leaving = &self.row[j0..j1];
        let entering = &self.row[j0 + n..j1 + n];
        for ((o, &l), &e) in self.win[j0 + 1..=j1].iter_mut().zip(leaving).zip(entering) {
            w = w.wrapping_add(e).wrapping_sub(l);
            *o = w;
        }
    }
}

/// Eq. (7) along one direction for columns `ua..ub` of a row, as a running sum:
/// `out[i] = Σ_{x < ua + i} LM(x)` (so `out[0] = 0`).
///
/// Per pixel, Eq. (6) with the neighbour sums `S_ch = Σ_c L_ch(q_c)`:
/// `T = Σ_c [L(q_c,t)·L(p,t−C_d) − L(q_c,t−C_d)·L(p,t)] = L(p,t−C_d)·S(t) − L(p,t)·S(t−C_d)`,
/// so `a·T4 + b·T5 = a·on_d·S_on − a·on·S_on_d + b·off_d·S_off − b·off·S_off_d`: four 16x16
/// multiplies of packed lanes (`own_d = a·on_d | b·off_d << 16`,
/// `own_n = −a·on | −b·off << 16`, `sum_n = S_on | S_off << 16`, `sum_d` likewise), which the
/// Cortex-M4 does as SMULBB/SMLATT.
#[inline(always)]
fn lm_run(own_d: &[u32], own_n: &[u32], sum_n: &[u32], sum_d: &[u32], shift: u32, out: &mut [u32]) {
    let mut acc = 0u32;
    if let Some(o) = out.first_mut() {
        *o = 0;
    }
    let tail = out.get_mut(1..).unwrap_or_default();
    for ((((o, &xd), &xn), &sn), &sd) in tail.iter_mut().zip(own_d).zip(own_n).zip(sum_n).zip(sum_d)
    {
        let pre = lo(xd) * lo(sn) + hi(xd) * hi(sn) + lo(xn) * lo(sd) + hi(xn) * hi(sd);
        // rectified; a row's sum stays below u32::MAX (Narrow::new)
        acc = acc.wrapping_add((pre >> shift).max(0) as u32);
        *o = acc;
    }
}

/// [`integrate_all`] row by row in the narrow form (`s = 1`).
///
/// For each row of the union of the squares:
/// 1. the packed neighbour sums of both channel pairs (horizontal windows, vertical running
///    sums carried from the row above);
/// 2. for each direction some field needs on this row (r and l where a field's row is not its
///    centroid's, u above a centroid, d below), the rectified local motion of every column the
///    row's fields cover, as a running sum ([`lm_run`]);
/// 3. each field adds its segments: left of `x̄` to Q2 (l, u) or Q3 (l, d), right of `x̄` to Q1
///    (r, u) or Q4 (r, d), Eq. (8); the centroid's own row and column belong to no quadrant.
pub fn integrate_rows(
    m: &Maps,
    nw: &Narrow,
    regions: &[Region],
    q_floor: u32,
    q_balance: u8,
    out: &mut [Lplc2],
) {
    let count = regions.len().min(out.len()).min(crate::network::MAX_AFS);
    let (regions, out) = (&regions[..count], &mut out[..count]);
    // squares clipped to the retina, inclusive ranges as (x0, x1 + 1) half-open
    let mut boxes = [((0usize, 0usize), (0usize, 0usize)); crate::network::MAX_AFS];
    let mut bound: Option<((usize, usize), (usize, usize))> = None;
    for (b, r) in boxes.iter_mut().zip(regions) {
        let cols = (r.cols.0, r.cols.1.saturating_add(1).min(WIDTH));
        let rows = (r.rows.0, r.rows.1.saturating_add(1).min(HEIGHT));
        *b = (cols, rows);
        if cols.0 < cols.1 && rows.0 < rows.1 {
            bound = Some(match bound {
                None => (cols, rows),
                Some((c, w)) => (
                    (c.0.min(cols.0), c.1.max(cols.1)),
                    (w.0.min(rows.0), w.1.max(rows.1)),
                ),
            });
        }
    }
    let mut q = [[0u64; 4]; crate::network::MAX_AFS];
    if let Some(((c0, c1), (r0, r1))) = bound {
        let n = nw.n;
        // columns whose packed values the windows read
        let (p0, p1) = (c0.saturating_sub(n), (c1 + n).min(WIDTH));
        let mut now = Packed::new();
        let mut del = Packed::new();
        now.start((m.on, m.off), r0, n, (c0, c1));
        del.start((m.on_d, m.off_d), r0, n, (c0, c1));
        let mut own_d = [0u32; WIDTH];
        let mut own_n = [0u32; WIDTH];
        let mut run = [0u32; WIDTH + 1];
        let (a, b) = (nw.a, nw.b);
        for y in r0..r1 {
            now.advance((m.on, m.off), y, n, (c0, c1), (p0, p1), y == r0);
            del.advance((m.on_d, m.off_d), y, n, (c0, c1), (p0, p1), y == r0);
            // the row's span and the directions its fields need
            let (mut ua, mut ub) = (WIDTH, 0);
            let (mut horiz, mut up, mut down) = (false, false, false);
            for &((x0, x1), (y0, y1)) in &boxes[..count] {
                if (y0..y1).contains(&y) && x0 < x1 {
                    (ua, ub) = (ua.min(x0), ub.max(x1));
                }
            }
            for (r, &((x0, x1), (y0, y1))) in regions.iter().zip(&boxes[..count]) {
                if (y0..y1).contains(&y) && x0 < x1 {
                    up |= y < r.centre.1;
                    down |= y > r.centre.1;
                }
            }
            horiz |= up || down;
            if !horiz {
                continue;
            }
            // own values, scaled and packed (a·on_d, b·off_d) and (−a·on, −b·off)
            let (on, off) = rows2(m.on, m.off, y, ua, ub);
            let (on_d, off_d) = rows2(m.on_d, m.off_d, y, ua, ub);
            let own = own_d[ua..ub].iter_mut().zip(own_n[ua..ub].iter_mut());
            for ((((d, nn), &on), &off), (&on_d, &off_d)) in
                own.zip(on).zip(off).zip(on_d.iter().zip(off_d))
            {
                *d = (a * i32::from(on_d)) as u32 | ((b * i32::from(off_d)) as u32) << 16;
                *nn = (-a * i32::from(on)) as u16 as u32 | ((-b * i32::from(off)) as u32) << 16;
            }
            let (od, on_) = (&own_d[ua..ub], &own_n[ua..ub]);
            let span = &mut run[ua..=ub];
            for dir in Direction::ALL {
                let (sn, sd): (&[u32], &[u32]) = match dir {
                    Direction::Right => (&now.win[ua + PAD + 1..], &del.win[ua + PAD + 1..]),
                    Direction::Left => (&now.win[ua + PAD - n..], &del.win[ua + PAD - n..]),
                    Direction::Down if down => (&now.down[ua..], &del.down[ua..]),
                    Direction::Up if up => (&now.up[ua..], &del.up[ua..]),
                    _ => continue,
                };
                lm_run(od, on_, sn, sd, nw.shift, span);
                let seg = |s: usize, e: usize| -> u64 {
                    match (span.get(s - ua), span.get(e - ua)) {
                        (Some(&s), Some(&e)) if e >= s => u64::from(e - s),
                        _ => 0,
                    }
                };
                for ((r, &((x0, x1), (y0, y1))), acc) in
                    regions.iter().zip(&boxes[..count]).zip(q.iter_mut())
                {
                    if !(y0..y1).contains(&y) || x0 >= x1 {
                        continue;
                    }
                    let (cx, cy) = r.centre;
                    let left = (x0, cx.clamp(x0, x1));
                    let right = ((cx + 1).clamp(x0, x1), x1);
                    use core::cmp::Ordering::*;
                    match (dir, y.cmp(&cy)) {
                        (_, Equal) => {}
                        (Direction::Right, Less) => acc[0] += seg(right.0, right.1),
                        (Direction::Right, Greater) => acc[3] += seg(right.0, right.1),
                        (Direction::Left, Less) => acc[1] += seg(left.0, left.1),
                        (Direction::Left, Greater) => acc[2] += seg(left.0, left.1),
                        (Direction::Up, Less) => {
                            acc[0] += seg(right.0, right.1);
                            acc[1] += seg(left.0, left.1);
                        }
                        (Direction::Down, Greater) => {
                            acc[3] += seg(right.0, right.1);
                            acc[2] += seg(left.0, left.1);
                        }
                        _ => {}
                    }
                }
            }
        }
    }
    for (o, qk) in out.iter_mut().zip(q.iter()) {
        let quadrants = qk.map(|v| v.min(u64::from(u32::MAX)) as u32);
        *o = Lplc2 {
            quadrants,
            response: gate(quadrants, q_floor, q_balance),
        };
    }
}

/// Eqs. (8)–(9) for several fields in one pass over the union of their squares, pixel by pixel
/// with [`local_motion`]: each pixel's local motion is computed once per direction however many
/// fields need it. Same result as [`integrate`] per field. The general path of
/// [`integrate_all`], taken when the parameters have no [`Narrow`] form.
pub fn integrate_all_general(
    m: &Maps,
    sc: &LmScale,
    regions: &[Region],
    q_floor: u32,
    q_balance: u8,
    out: &mut [Lplc2],
) {
    let n = regions.len().min(out.len());
    let (regions, out) = (&regions[..n], &mut out[..n]);
    let Some(first) = regions.first() else {
        return;
    };
    let mut bounds = (first.cols, first.rows);
    for r in regions {
        bounds.0 = (bounds.0 .0.min(r.cols.0), bounds.0 .1.max(r.cols.1));
        bounds.1 = (bounds.1 .0.min(r.rows.0), bounds.1 .1.max(r.rows.1));
    }
    let mut q = [[0u64; 4]; crate::network::MAX_AFS];
    for y in bounds.1 .0..=bounds.1 .1 {
        for x in bounds.0 .0..=bounds.0 .1 {
            // local motion per direction (r, l, d, u), computed on first need
            let mut lm: [Option<u32>; 4] = [None; 4];
            for (k, r) in regions.iter().enumerate() {
                let inside =
                    (r.cols.0..=r.cols.1).contains(&x) && (r.rows.0..=r.rows.1).contains(&y);
                let Some(quad) = inside
                    .then(|| quadrant_of(x, y, r.centre.0, r.centre.1))
                    .flatten()
                else {
                    continue;
                };
                for d in QUADRANT_DIRECTIONS[quad] {
                    let slot = d as usize;
                    let v = *lm[slot].get_or_insert_with(|| local_motion(m, sc, x, y, d));
                    if let Some(acc) = q.get_mut(k) {
                        acc[quad] += u64::from(v);
                    }
                }
            }
        }
    }
    for (o, qk) in out.iter_mut().zip(q.iter()) {
        let quadrants = qk.map(|v| v.min(u64::from(u32::MAX)) as u32);
        *o = Lplc2 {
            quadrants,
            response: gate(quadrants, q_floor, q_balance),
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Params;
    use proptest::prelude::*;

    #[test]
    fn quadrants_follow_the_image_axes() {
        assert_eq!(quadrant_of(60, 10, 50, 30), Some(0)); // upper right
        assert_eq!(quadrant_of(40, 10, 50, 30), Some(1)); // upper left
        assert_eq!(quadrant_of(40, 50, 50, 30), Some(2)); // lower left
        assert_eq!(quadrant_of(60, 50, 50, 30), Some(3)); // lower right
        assert_eq!(quadrant_of(50, 10, 50, 30), None);
        assert_eq!(quadrant_of(60, 30, 50, 30), None);
    }

    #[test]
    fn gate_needs_all_four_arms_above_the_floor() {
        assert_eq!(gate([10, 20, 30, 40], 5, 0), 100);
        assert_eq!(gate([10, 20, 0, 40], 0, 0), 0);
        assert_eq!(gate([10, 20, 5, 40], 5, 0), 0);
        assert_eq!(gate([u32::MAX, 1, 1, 1], 0, 0), u32::MAX);
        // balance: every arm at least 25 % of the strongest
        assert_eq!(gate([10, 20, 30, 40], 5, 25), 100);
        assert_eq!(gate([9, 20, 30, 40], 5, 25), 0);
    }

    /// A dark square's outline one pixel larger now than one frame earlier.
    fn square_outline(half: usize, cx: usize, cy: usize) -> [u8; PIXELS] {
        let mut m = [0u8; PIXELS];
        for y in cy - half..=cy + half {
            for x in cx - half..=cx + half {
                if y == cy - half || y == cy + half || x == cx - half || x == cx + half {
                    m[y * WIDTH + x] = 60;
                }
            }
        }
        m
    }

    #[test]
    fn an_expanding_outline_excites_all_quadrants_and_a_shrinking_one_none() {
        let p = Params::default();
        let sc = LmScale::new(&p);
        let zero = [0u8; PIXELS];
        let small = square_outline(8, 50, 36);
        let large = square_outline(9, 50, 36);
        let cols = (14, 86);
        let rows = (0, 71);
        // OFF channel edges: expanding = small at t−1, large at t
        let grow = Maps {
            on: &zero,
            off: &large,
            on_d: &zero,
            off_d: &small,
        };
        let l = integrate(&grow, &sc, (50, 36), cols, rows, 0, 0);
        assert!(l.quadrants.iter().all(|&q| q > 0), "{:?}", l.quadrants);
        assert_eq!(l.quadrants[0], l.quadrants[2], "symmetric stimulus");
        assert_eq!(l.response, l.quadrants.iter().sum::<u32>());
        let shrink = Maps {
            on: &zero,
            off: &small,
            on_d: &zero,
            off_d: &large,
        };
        let l = integrate(&shrink, &sc, (50, 36), cols, rows, 0, 0);
        assert_eq!(l.quadrants, [0; 4]);
        assert_eq!(l.response, 0);
    }

    #[test]
    fn one_pass_equals_per_field_integration() {
        let p = Params::default();
        let sc = LmScale::new(&p);
        // pseudo-random maps with plenty of motion in every direction
        let maps = crate::hrc::random_maps(12345);
        let m = Maps {
            on: &maps[0],
            off: &maps[1],
            on_d: &maps[2],
            off_d: &maps[3],
        };
        let regions = [
            Region {
                centre: (10, 10),
                cols: (0, 46),
                rows: (0, 46),
            },
            Region {
                centre: (60, 40),
                cols: (24, 96),
                rows: (4, 71),
            },
            Region {
                centre: (98, 0),
                cols: (62, 98),
                rows: (0, 36),
            },
        ];
        let mut all = [Lplc2::default(); 3];
        integrate_all(&m, &sc, &regions, 300, 15, &mut all);
        for (r, got) in regions.iter().zip(all.iter()) {
            assert_eq!(
                *got,
                integrate(&m, &sc, r.centre, r.cols, r.rows, 300, 15),
                "{r:?}"
            );
        }
        // the corner field at (98, 0) has no upper or right quadrant; the others see motion
        assert!(all[..2].iter().all(|l| l.quadrants.iter().all(|&q| q > 0)));
        assert_eq!(all[2].quadrants[0], 0);
    }

    #[test]
    fn the_paper_parameters_take_the_row_kernel() {
        let sc = LmScale::new(&Params::PAPER);
        let nw = Narrow::new(&sc).expect("narrow");
        assert_eq!((nw.a, nw.b, nw.shift, nw.n), (1, 16, 8, 3));
        // s > 1 and wide factors fall back to the general path
        let p = Params {
            s: 2,
            ..Params::PAPER
        };
        assert_eq!(Narrow::new(&LmScale::new(&p)), None);
        let p = Params {
            gain: 16,
            w: 4.0,
            lm_shift: 0,
            ..Params::PAPER
        };
        assert_eq!(Narrow::new(&LmScale::new(&p)), None);
    }

    /// Maps from a seed: noise, noise thinned to sparse dots, or smooth low values.
    fn maps_of(seed: u32, kind: u8) -> [[u8; PIXELS]; 4] {
        let mut maps = crate::hrc::random_maps(seed);
        for (k, m) in maps.iter_mut().enumerate() {
            for (i, v) in m.iter_mut().enumerate() {
                match kind {
                    0 => {}
                    1 => {
                        if !(i * 7 + k * 13 + seed as usize).is_multiple_of(5) {
                            *v = 0;
                        }
                    }
                    _ => *v /= 16,
                }
            }
        }
        maps
    }

    fn region() -> impl Strategy<Value = Region> {
        (
            0..WIDTH,
            0..HEIGHT,
            1u8..=99,
            any::<bool>(),
            0..WIDTH,
            0..WIDTH,
            0..HEIGHT,
            0..HEIGHT,
        )
            .prop_map(|(x, y, r, square, xa, xb, ya, yb)| {
                if square {
                    // a field's clipped square, as the network builds it
                    let r = usize::from(r);
                    Region {
                        centre: (x, y),
                        cols: (x.saturating_sub(r), (x + r).min(WIDTH - 1)),
                        rows: (y.saturating_sub(r), (y + r).min(HEIGHT - 1)),
                    }
                } else {
                    // any box on the retina, the centre anywhere (even outside it)
                    Region {
                        centre: (x, y),
                        cols: (xa.min(xb), xa.max(xb)),
                        rows: (ya.min(yb), ya.max(yb)),
                    }
                }
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]
        #[test]
        fn the_fast_pass_equals_per_field_integration(
            seed in any::<u32>(),
            kind in 0u8..3,
            n in 1u8..=4,
            s in 1u8..=2,
            gain in 1u8..=16,
            w in prop::sample::select(&[0.0f32, 0.25, 0.5, 1.0, 0.3, 2.0, 4.0][..]),
            lm_shift in 0u8..=24,
            q_floor in 0u32..2000,
            q_balance in 0u8..=100,
            regions in prop::collection::vec(region(), 0..=crate::network::MAX_AFS),
        ) {
            let maps = maps_of(seed, kind);
            let m = Maps { on: &maps[0], off: &maps[1], on_d: &maps[2], off_d: &maps[3] };
            let s = if u32::from(n) * u32::from(s) > 8 { 1 } else { s };
            let p = Params { n, s, gain, w, lm_shift, ..Params::PAPER };
            prop_assert_eq!(p.validate(), Ok(()));
            let sc = LmScale::new(&p);
            let mut all = [Lplc2::default(); crate::network::MAX_AFS];
            integrate_all(&m, &sc, &regions, q_floor, q_balance, &mut all);
            for (r, got) in regions.iter().zip(all.iter()) {
                let want = integrate(&m, &sc, r.centre, r.cols, r.rows, q_floor, q_balance);
                prop_assert_eq!(*got, want, "{:?} n{} s{} gain{} w{} shift{}", r, n, s, gain, w, lm_shift);
            }
        }
    }
}

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
//! (outward) motion (`q_arms` = 4; the authors' firmware opens at 3). A quadrant counts as
//! excited only above the noise floor `q_floor`: without it sensor noise alone opens the gate
//! now and then (`docs/model.md`).

use crate::frame::WIDTH;
use crate::model::hrc::{local_motion, Direction, LmScale, Maps};

mod rows;

pub use rows::{integrate_rows, Narrow};

/// The four quadrant sums and the LPLC2 response of one field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Lplc2 {
    /// `Q1..Q4` of Eq. (8), saturating.
    pub quadrants: [u32; 4],
    /// `LPLC2_k` of Eq. (9).
    pub response: u32,
}

impl Lplc2 {
    /// Eq. (9) on the quadrant sums of Eq. (8), each saturated to `u32`.
    fn from_sums(q: [u64; 4], g: &Gate) -> Self {
        let quadrants = q.map(|v| v.min(u64::from(u32::MAX)) as u32);
        Lplc2 {
            quadrants,
            response: gate(quadrants, g),
        }
    }
}

/// When Eq. (9)'s gate opens: how many quadrants must be excited, and what counts as excited.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Gate {
    /// A quadrant is excited only above this noise floor (`Params::q_floor`).
    pub floor: u32,
    /// … and at or above this share of the strongest quadrant, in percent (`Params::q_balance`).
    pub balance: u8,
    /// Excited quadrants needed (`Params::q_arms`): 4 is Eq. (9)'s product, 3 the authors'
    /// firmware.
    pub arms: u8,
}

impl Gate {
    /// The gate of the parameters `p`.
    pub fn of(p: &crate::model::params::Params) -> Self {
        Gate {
            floor: p.choices.q_floor,
            balance: p.choices.q_balance,
            arms: p.choices.q_arms,
        }
    }
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
/// the absolute floor `g.floor` and `g.balance` % of the strongest quadrant: an arm that sees a
/// trickle while another sees a flood is not "receiving its preferred motion" (translation and
/// gratings flood two arms and leak into the other two). The gate opens when at least
/// `g.arms` quadrants are excited (Eq. 9: all four).
pub fn gate(quadrants: [u32; 4], g: &Gate) -> u32 {
    if excited(quadrants, g) >= usize::from(g.arms) {
        drive(quadrants)
    } else {
        0
    }
}

/// `ΣQ`, saturating: what an open gate passes on, and a field's drive (`Params::q_grow_pct`).
pub fn drive(quadrants: [u32; 4]) -> u32 {
    quadrants.iter().fold(0u32, |a, &q| a.saturating_add(q))
}

/// How many quadrants are excited: above the floor and at least `g.balance` % of the
/// strongest.
pub fn excited(quadrants: [u32; 4], g: &Gate) -> usize {
    count(excited_mask(quadrants, g))
}

/// Which quadrants are excited ([`excited`]).
fn excited_mask(quadrants: [u32; 4], g: &Gate) -> [bool; 4] {
    let max = quadrants.iter().copied().max().unwrap_or(0);
    let rel = (u64::from(max) * u64::from(g.balance)) / 100;
    quadrants.map(|q| q > g.floor && u64::from(q) >= rel)
}

/// How many of four are set.
fn count(mask: [bool; 4]) -> usize {
    mask.iter().filter(|&&m| m).count()
}

/// `Params::border_arms`: which sides of a field centred on column `cx` the retina's side
/// borders cut, `(left, right)`: a side is cut when less than half of the field's half side `r`
/// lies in the picture there, or, with `crossing` (`Params::border_crossing`), when any of it
/// lies beyond the border.
pub fn cut_sides(cx: usize, r: u8, crossing: bool) -> (bool, bool) {
    let reach = if crossing {
        usize::from(r)
    } else {
        usize::from(r).div_ceil(2)
    };
    (cx < reach, cx + reach > WIDTH - 1)
}

/// `Params::short_uncut`: the response `response` of the field centred on column `cx` with half
/// side `r`, scaled to the whole square's width from the columns the retina shows of it
/// (saturating). Only a field centred `r` or more columns from both side borders is whole
/// (with Table I's 36: columns 36–62); a centre off the retina counts as one column shown.
pub fn uncut_response(response: u32, cx: usize, r: u8) -> u32 {
    let r = usize::from(r);
    let (left, right) = crate::model::attention::span(cx, r, WIDTH);
    let whole = 2 * r + 1;
    let shown = (right.saturating_sub(left) + 1).min(whole);
    let scaled = u64::from(response) * whole as u64 / shown as u64;
    u32::try_from(scaled).unwrap_or(u32::MAX)
}

/// Eq. (9)'s excited quadrants with the quadrants on a cut side (`cut`, as [`cut_sides`]) also
/// counted when their mirror image across the vertical axis is excited (`Params::border_arms`),
/// provided one of the cut side's quadrants is excited by itself. What a cut side still sees
/// of a looming object is its top and bottom edges spreading apart; an object translating
/// sideways past the border excites only the quadrants its edges move towards, all on one side
/// of the axis, so its image across the axis would be invented.
pub fn excited_at_border(quadrants: [u32; 4], g: &Gate, cut: (bool, bool)) -> usize {
    let on = excited_mask(quadrants, g);
    let mut counted = on;
    // mirror pairs: 0 (right, up) ↔ 1 (left, up), 3 (right, down) ↔ 2 (left, down)
    if cut.0 && (on[1] || on[2]) {
        counted[1] |= on[0];
        counted[2] |= on[3];
    }
    if cut.1 && (on[0] || on[3]) {
        counted[0] |= on[1];
        counted[3] |= on[2];
    }
    count(counted)
}

/// How far (pixels, Chebyshev) recentring may move a field between two frames for its drive
/// to still be the same place's ([`partial_opening_grows`]). A field that jumps, say from an
/// obstacle to a wall's flow 30 pixels away, has no history there: comparing the new place's
/// sum with the old place's would read any busier place as "growing". Arena seed 1 (built-in
/// walls, `q_arms=3`, `q_grow_pct=50`): 88.1 % with no limit (which turns towards a threat in
/// the closed-loop direction tests), 86.6 / 86.3 / 84.9 / 85.2 % at 12 / 8 / 6 / 4 pixels
/// (`docs/experiments.md`).
pub const GROW_SHIFT_PX: u8 = 8;

/// `Params::q_grow_pct`: a partial opening of the gate (fewer than four excited quadrants)
/// stands only if the field's quadrant sum grew by at least `pct` % over `last`, its sum of
/// the frame before at the same place (`None`: the field moved more than [`GROW_SHIFT_PX`],
/// so it has no such sum and a partial opening does not stand).
pub fn partial_opening_grows(quadrants: [u32; 4], g: &Gate, last: Option<u32>, pct: u8) -> bool {
    if pct == 0 || excited(quadrants, g) >= 4 {
        return true;
    }
    let Some(last) = last else {
        return false;
    };
    let sum = quadrants.iter().fold(0u64, |a, &q| a + u64::from(q));
    sum * 100 > u64::from(last) * (100 + u64::from(pct))
}

/// `Params::q_grow_run`: the frames in a row a field's drive has grown at the same place, after
/// this frame's drive `now` (`last`: the frame before's at the same place, as for
/// [`partial_opening_grows`]).
pub fn growth_run(run: u8, last: Option<u32>, now: u32) -> u8 {
    match last {
        Some(last) if now > last => run.saturating_add(1),
        _ => 0,
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
    g: &Gate,
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
    Lplc2::from_sums(q, g)
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
pub fn integrate_all(m: &Maps, sc: &LmScale, regions: &[Region], g: &Gate, out: &mut [Lplc2]) {
    match Narrow::new(sc) {
        Some(nw) => integrate_rows(m, &nw, regions, g, out),
        None => integrate_all_general(m, sc, regions, g, out),
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
    g: &Gate,
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
    let mut q = [[0u64; 4]; crate::model::MAX_AFS];
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
        *o = Lplc2::from_sums(*qk, g);
    }
}

#[cfg(test)]
mod tests;

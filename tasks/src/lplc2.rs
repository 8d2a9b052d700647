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

/// Eqs. (8)–(9) for several fields in one pass over the union of their squares: each pixel's
/// local motion is computed once per direction however many fields need it (fields overlap
/// heavily with `R_AF` = 36 on a 99x72 retina). Same result as [`integrate`] per field.
pub fn integrate_all(
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
    use crate::frame::{PIXELS, WIDTH};
    use crate::params::Params;

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
}

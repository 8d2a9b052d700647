//! The simulator validated against real recordings (`cargo alvs validate`): the LGMD2 robot in
//! the recorded arena's replica, its path's statistics beside the recorded robot's.

pub mod sim;

/// Quick statistics of a trail for exploration: (share of path within 50 mm of a wall, within
/// 100 mm, mean speed mm/s).
pub fn quick_stats(arena: &crate::arena::Arena, trail: &[(f64, f64, f64)]) -> (f64, f64, f64) {
    let (mut total, mut near50, mut near100) = (0.0, 0.0, 0.0);
    for w in trail.windows(2) {
        let d = (w[1].1 - w[0].1).hypot(w[1].2 - w[0].2);
        let wd = arena.wall_distance(w[1].1, w[1].2);
        total += d;
        if wd < 50.0 {
            near50 += d;
        }
        if wd < 100.0 {
            near100 += d;
        }
    }
    let t = trail.last().map_or(1.0, |l| l.0.max(1e-9));
    (
        near50 / total.max(1e-9),
        near100 / total.max(1e-9),
        total / t,
    )
}

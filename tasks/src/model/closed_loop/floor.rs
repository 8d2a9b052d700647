//! The floor line: how far an obstacle ahead stands, from where it meets the floor
//! (`Params::floor_row`, a closed-loop mechanism; not in the paper).
//!
//! A ground robot's camera sits at a fixed height `h` over a flat floor, so a point of the
//! floor `Z` ahead of the camera images `f·h/Z` rows below the horizon: the row where an
//! obstacle meets the floor is its distance. A wall or robot close ahead has its foot low in
//! the image, a far one near the horizon. In each column the foot is the lowest run of
//! [`FOOT_ROWS`] rows that differ from the floor's grey by more than the tolerance and step
//! away from the floor row below them by as much; the floor's grey is the median of
//! [`FLOOR_SAMPLE`] pixels of the bottom row's middle 40 columns, the tolerance [`FLOOR_TOL`]
//! or, on a floor with a grain of its own, three standard deviations of that grain
//! ([`Floor::of`]). Only columns inside
//! the robot's path count: `|h·(x − 49)/(row − 35.5)|`, the lateral offset of the foot, within
//! [`PATH_HALF_WIDTH_MM`]. Integer arithmetic, one pass over the lower half of the frame.
//!
//! Blind spot: an obstacle that covers the bottom row's middle (its foot below the frame, the
//! robot's centre within ≈ 57 mm of a wall) sets the floor's grey itself and is not found; the
//! blocked-way test (`Params::blocked_change`) covers a robot that close. [`nearest_foot`]
//! (`Params::short_row`) has the same blind spot: a driving robot that close to a wall loses
//! the short mode, and the floor line's earlier alert and the blocked way act instead.
//!
//! The geometry is the arena's camera ([`CAMERA_HEIGHT_MM`], the horizon at row 35.5, 70° over
//! 99 columns; a host test holds the renderer to it). The board's camera height is not known
//! (`docs/hardware.md`, "Geometry"), and the firmware's default runs the floor line: measure
//! the height at bring-up and set [`CAMERA_HEIGHT_MM`] (or `floor_row`) to it: a wrong height
//! moves the distance. A floor that is not one grey (a pattern) would make it fire, and the
//! robot turn, again and again, but for one thing geometry gives: whatever can touch the
//! robot stands on the floor and is taller than the camera (a Colias is 28 mm, the walls
//! higher), so its image covers the floor from its foot up to the horizon, while a mark on a
//! patterned floor is a patch of the floor itself. A foot counts only when at least
//! [`FOOT_COVER_PCT`] % of its column's rows from the foot up to the horizon differ from the
//! floor's grey (the robustness suite's textured floor, `docs/robustness.md`). Two more things
//! keep a grain on the floor from reading as feet: the tolerance grows with the grain measured
//! on the nearest floor, and a foot is a step from the floor just below it, where a drifting
//! grain is not (`docs/notes/2026-11-28-floor-grain.md`).

use crate::frame::{HEIGHT, PIXELS, WIDTH};

/// Height of the camera above the floor, mm.
pub const CAMERA_HEIGHT_MM: i32 = 20;
/// Radius of a Colias body, mm (42 mm across, `docs/hardware.md`).
pub const BODY_RADIUS_MM: i32 = 21;
/// Half the width of the path the robot sweeps driving straight, mm: its body's radius. A
/// foot farther from the path's centre line than that passes beside the body. Geometry, not
/// a score: the collision distance of the experiments (one diameter) is not used here. On the
/// tuning seeds 1–5 the radius did as well as one diameter (42) and 30, and drove faster
/// (docs/ablation.md, "The new default").
pub const PATH_HALF_WIDTH_MM: i32 = BODY_RADIUS_MM;
/// Grey levels by which an obstacle's foot differs from the floor (the camera noise is 2): the
/// least tolerance; a floor with a grain of its own raises it ([`Floor::of`]).
pub const FLOOR_TOL: i32 = 12;
/// Rows of the nearest floor, each [`GRAIN_COLS`] wide, sampled for the floor's grain.
const GRAIN_ROWS: [usize; 4] = [HEIGHT - 8, HEIGHT - 6, HEIGHT - 4, HEIGHT - 2];
/// Columns of the grain sample: 9, 19, …, 89.
const GRAIN_COLS: usize = 9;
/// Pixels in the grain sample.
const GRAIN_SAMPLES: usize = GRAIN_ROWS.len() * GRAIN_COLS;
/// Grey levels by which the floor's grey may follow the floor from one row to the next: the
/// replica's dark floor brightens by 1–3 levels a row towards the horizon, a pattern on it by a
/// few more; an obstacle's foot steps by more than the tolerance at once.
pub const FLOOR_TRACK: i32 = 2;
/// Consecutive rows, bottom up, that must differ from the floor.
pub const FOOT_ROWS: usize = 2;
/// Share of a column's rows, from a foot up to the horizon, that must differ from the floor's
/// grey for the foot to count: an obstacle taller than the camera covers them all (its
/// pattern may match the floor here and there), a mark on the floor only its own few. A
/// majority, the lenient choice between the two.
pub const FOOT_COVER_PCT: usize = 50;
/// Bottom-row pixels, 10 columns apart around the centre, whose median is the floor's grey.
pub const FLOOR_SAMPLE: usize = 5;

/// The floor as one frame shows it: its grey at the bottom row and the tolerance by which a
/// foot must differ from it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Floor {
    /// The bottom row's grey ([`FLOOR_SAMPLE`] pixels' median).
    pub grey: i32,
    /// Grey levels a foot must differ by: [`FLOOR_TOL`], or three standard deviations of the
    /// floor's grain if that is more.
    pub tol: i32,
}

impl Floor {
    /// The floor's grey, and its grain on the nearest floor: [`GRAIN_SAMPLES`] pixels of
    /// [`GRAIN_ROWS`], 10 columns apart. Their median absolute deviation from the grey, times
    /// 1.4826, estimates the grain's standard deviation robustly (a few odd pixels move it
    /// little); three of them (4.45 · MAD) is the tolerance, as a Gaussian grain stays
    /// within 3 σ but for 0.3 % of its pixels. Pixels that differ from the grey by more than
    /// twice [`FLOOR_TOL`] are an obstacle close ahead, not floor, and are left out; with
    /// fewer than half the sample left the tolerance is [`FLOOR_TOL`]. On a plain floor the
    /// sensor's noise (2 levels) keeps it at [`FLOOR_TOL`].
    pub fn of(frame: &[u8; PIXELS]) -> Floor {
        let grey = floor_grey(frame);
        // how many of the sample deviate from the grey by 0, 1, …, 2·FLOOR_TOL levels
        let mut count = [0u8; 2 * FLOOR_TOL as usize + 1];
        let mut n = 0;
        for y in GRAIN_ROWS {
            for k in 0..GRAIN_COLS {
                let d = (i32::from(frame[y * WIDTH + 9 + 10 * k]) - grey).unsigned_abs();
                if let Some(c) = count.get_mut(d as usize) {
                    *c += 1;
                    n += 1;
                }
            }
        }
        // the median deviation: the least `d` with more than half the kept sample at or below it
        let mut below = 0;
        let mad = count.iter().position(|&c| {
            below += usize::from(c);
            2 * below > n
        });
        let tol = match mad {
            Some(mad) if 2 * n >= GRAIN_SAMPLES => FLOOR_TOL.max(89 * mad as i32 / 20),
            _ => FLOOR_TOL,
        };
        Floor { grey, tol }
    }
}

/// Twice the horizon row (35.5), so that row offsets stay integers.
const HORIZON_X2: i32 = HEIGHT as i32 - 1;

/// The column of the nearest obstacle in the robot's path whose foot lies at or below
/// `near_row`, or `None`: the mean column of the feet in the path within one row of the
/// lowest, so a wall square ahead points straight ahead and a slanted one to its near side.
/// `near_row` 0 (the mechanism off), at the horizon or above, or below the frame gives `None`.
///
/// Never inlined: its locals then live only while it runs, after the motion stage, instead of
/// adding to the caller's frame under the deepest path (the firmware's stack budget).
#[inline(never)]
pub fn obstacle_ahead(frame: &[u8; PIXELS], near_row: u8) -> Option<u8> {
    let near = usize::from(near_row);
    if 2 * near as i32 <= HORIZON_X2 || near >= HEIGHT {
        return None;
    }
    let floor = Floor::of(frame);
    // (row, column sum, columns) of the lowest feet and of those one row above them
    let (mut low, mut above) = ((0usize, 0usize, 0usize), (0usize, 0usize, 0usize));
    for x in 0..WIDTH {
        let Some(row) = foot(frame, floor, x, near) else {
            continue;
        };
        if low.2 == 0 || row > low.0 + 1 {
            (low, above) = ((row, x, 1), (row - 1, 0, 0));
        } else if row == low.0 + 1 {
            (low, above) = ((row, x, 1), low);
        } else if row == low.0 {
            low = (row, low.1 + x, low.2 + 1);
        } else if row + 1 == low.0 {
            above = (row, above.1 + x, above.2 + 1);
        }
    }
    let n = low.2 + above.2;
    (n > 0).then(|| ((low.1 + above.1 + n / 2) / n) as u8)
}

/// The foot of column `x` if it lies inside the robot's path at or below `near`: the lowest
/// run of [`FOOT_ROWS`] rows that differ from `floor`, scanning up from the bottom only as far
/// as the path reaches in this column (the lateral offset `h·(x − 49)/(row − 35.5)` of a foot
/// grows as it rises towards the horizon).
fn foot(frame: &[u8; PIXELS], floor: Floor, x: usize, near: usize) -> Option<usize> {
    // in the path: |2h·(x − 49)| ≤ PATH_HALF_WIDTH_MM·(2·row − 71)
    let offset = (2 * CAMERA_HEIGHT_MM * (x as i32 - (WIDTH as i32 - 1) / 2)).unsigned_abs();
    let width = PATH_HALF_WIDTH_MM as u32;
    let top = ((offset.div_ceil(width) as i32 + HORIZON_X2 + 1) / 2) as usize;
    foot_below(frame, floor, x, near.max(top))
}

/// Columns either side of `X̄` that [`nearest_foot`] also looks at: `X̄` may fall on a stripe
/// of the threat as grey as the floor, or just beside a narrow one.
pub const FOOT_SEARCH_COLS: usize = 3;

/// The row of the nearest foot (the lowest) in the columns `x ± FOOT_SEARCH_COLS`, wherever
/// it lies below the horizon, path or not: how far the threat at column `x` stands
/// (`Params::short_row`). `None` when those columns show the floor up to the horizon or `x`
/// is out of the image.
#[inline(never)]
pub fn nearest_foot(frame: &[u8; PIXELS], x: u8) -> Option<u8> {
    let x = usize::from(x);
    if x >= WIDTH {
        return None;
    }
    let floor = Floor::of(frame);
    (x.saturating_sub(FOOT_SEARCH_COLS)..(x + FOOT_SEARCH_COLS + 1).min(WIDTH))
        .filter_map(|c| foot_below(frame, floor, c, BELOW_HORIZON))
        .max()
        .map(|row| row as u8)
}

/// The row just below the horizon: the farthest foot the floor can show.
const BELOW_HORIZON: usize = HORIZON_X2 as usize / 2 + 1;

/// The foot of column `x` at or below row `top` (≥ [`FOOT_ROWS`] − 1): scanning up from the
/// bottom, the lowest run of [`FOOT_ROWS`] rows that differ from the floor's grey by more than
/// `floor.tol`, whose top row also differs by as much from the last row taken for floor below
/// the run, and whose column above is covered up to the horizon ([`FOOT_COVER_PCT`]). The
/// floor's grey starts at `floor.grey` and follows the floor up the column, by at most
/// [`FLOOR_TRACK`] levels a row: a floor's grey drifts with distance (a dark floor seen at a
/// grazing angle brightens towards the horizon) and with its pattern, while an obstacle's
/// foot is a step, from the floor just below it as well as from the followed grey.
fn foot_below(frame: &[u8; PIXELS], floor: Floor, x: usize, top: usize) -> Option<usize> {
    // as rows, and `x` checked once: no bounds test per pixel of the column
    let rows = frame.as_chunks::<WIDTH>().0;
    if x >= WIDTH {
        return None;
    }
    let last = top + 1 - FOOT_ROWS;
    let (mut grey, mut run) = (floor.grey, 0);
    // the last row taken for floor: a foot steps away from it, a drifting grain does not
    let mut below = floor.grey;
    // the cover (differing rows, rows) of the run's last candidate foot
    let mut cover: Option<(usize, usize)> = None;
    let mut y = HEIGHT;
    while y > last.max(BELOW_HORIZON) {
        y -= 1;
        let Some(row) = rows.get(y) else {
            break;
        };
        let p = i32::from(row[x]);
        if (p - grey).abs() <= floor.tol {
            grey += (p - grey).clamp(-FLOOR_TRACK, FLOOR_TRACK);
            below = p;
            run = 0;
            cover = None;
            continue;
        }
        run += 1;
        if run >= FOOT_ROWS {
            let foot = y + FOOT_ROWS - 1;
            let stepped = (p - below).abs() > floor.tol;
            // within a run the floor's grey holds, and the candidate one row up drops the old
            // foot, a row of the run: one differing row fewer; no second scan of the column
            cover = match cover {
                Some((hits, rows)) => Some((hits - 1, rows - 1)),
                None if stepped => Some(column_cover(rows, grey, floor.tol, x, foot)),
                None => None,
            };
            if let (true, Some((hits, rows))) = (stepped, cover) {
                if 100 * hits >= FOOT_COVER_PCT * rows {
                    return Some(foot);
                }
            }
        }
    }
    None
}

/// Of column `x`'s rows from `foot` up to the row below the horizon, how many differ from the
/// floor's grey there, `grey`, and how many there are: covered when the first is at least
/// [`FOOT_COVER_PCT`] % of the second.
fn column_cover(
    rows: &[[u8; WIDTH]],
    grey: i32,
    tol: i32,
    x: usize,
    foot: usize,
) -> (usize, usize) {
    let column = rows.get(BELOW_HORIZON..=foot).unwrap_or_default();
    // `x` checked once for the whole column
    let hits = if x < WIDTH {
        column
            .iter()
            .filter(|r| (i32::from(r[x]) - grey).abs() > tol)
            .count()
    } else {
        0
    };
    (hits, (foot + 1).saturating_sub(BELOW_HORIZON))
}

/// Median grey of [`FLOOR_SAMPLE`] bottom-row pixels spread over its middle 40 columns.
fn floor_grey(frame: &[u8; PIXELS]) -> i32 {
    let bottom = (HEIGHT - 1) * WIDTH + WIDTH / 2;
    let mut sample = [0u8; FLOOR_SAMPLE];
    for (k, s) in sample.iter_mut().enumerate() {
        // columns 29, 39, 49, 59, 69
        *s = frame[bottom + 10 * k - 10 * (FLOOR_SAMPLE / 2)];
    }
    sample.sort_unstable();
    i32::from(sample[FLOOR_SAMPLE / 2])
}

#[cfg(test)]
mod tests {
    use super::*;
    extern crate std;

    const FLOOR: u8 = 110;

    /// A floor everywhere below the horizon, above it a wall of `wall` grey whose foot is at
    /// `foot` in the columns `cols`, sky elsewhere.
    fn scene(foot: usize, cols: core::ops::Range<usize>, wall: u8) -> [u8; PIXELS] {
        let mut f = [FLOOR; PIXELS];
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                if y <= foot && cols.contains(&x) {
                    f[y * WIDTH + x] = wall;
                } else if y < 36 {
                    f[y * WIDTH + x] = 200;
                }
            }
        }
        f
    }

    #[test]
    fn a_foot_exactly_on_the_row_counts() {
        assert_eq!(obstacle_ahead(&scene(55, 0..WIDTH, 40), 55), Some(49));
        assert_eq!(obstacle_ahead(&scene(55, 0..WIDTH, 40), 56), None);
    }

    #[test]
    fn a_wall_close_ahead_is_found_and_a_far_one_is_not() {
        // foot at row 55: 20·70/19.5 ≈ 72 mm from the camera
        assert_eq!(obstacle_ahead(&scene(55, 0..WIDTH, 40), 52), Some(49));
        // foot at row 45: ≈ 147 mm
        assert_eq!(obstacle_ahead(&scene(45, 0..WIDTH, 40), 52), None);
        // a bright wall is found as well as a dark one
        assert!(obstacle_ahead(&scene(60, 0..WIDTH, 220), 52).is_some());
    }

    #[test]
    fn only_the_robots_path_counts() {
        // a post 45-49 columns to the left at row 55: 46-50 mm to the side
        assert_eq!(obstacle_ahead(&scene(55, 0..5, 40), 52), None);
        // 38 columns to the left, 39 mm: beside the body (21 mm radius)
        assert_eq!(obstacle_ahead(&scene(55, 11..12, 40), 52), None);
        // 20 columns to the left, 20.5 mm: just inside its radius; 21 columns, 21.5 mm: beside it
        assert_eq!(obstacle_ahead(&scene(55, 29..30, 40), 52), Some(29));
        assert_eq!(obstacle_ahead(&scene(55, 28..29, 40), 52), None);
        // the same post 8 columns to the right: ≈ 8 mm, in the path
        assert_eq!(obstacle_ahead(&scene(55, 55..60, 40), 52), Some(57));
        // of two in the path the nearer (lower foot) wins
        let mut f = scene(55, 40..45, 40);
        for y in 0..=62 {
            for x in 52..56 {
                f[y * WIDTH + x] = 30;
            }
        }
        assert_eq!(obstacle_ahead(&f, 52), Some(54));
    }

    #[test]
    fn a_floor_brightening_towards_the_horizon_is_followed_and_a_wall_on_it_found() {
        // a dark floor seen at a grazing angle: 2 levels brighter each row up from the bottom,
        // 72 levels at the horizon, six times the tolerance
        let mut f = scene(0, 0..0, 0);
        for y in 36..HEIGHT {
            let grey = FLOOR + 2 * (HEIGHT - 1 - y) as u8;
            f[y * WIDTH..(y + 1) * WIDTH].fill(grey);
        }
        assert_eq!(obstacle_ahead(&f, 52), None);
        // a wall whose foot is at row 55 on that floor is still a step
        for y in 0..=55 {
            f[y * WIDTH..(y + 1) * WIDTH].fill(40);
        }
        assert_eq!(obstacle_ahead(&f, 52), Some(49));
    }

    #[test]
    fn a_bare_floor_noise_and_the_off_switch_find_nothing() {
        let bare = scene(0, 0..0, 0);
        assert_eq!(obstacle_ahead(&bare, 52), None);
        // noise within the tolerance
        let mut noisy = bare;
        for (i, p) in noisy.iter_mut().enumerate().skip(36 * WIDTH) {
            *p = FLOOR + (i % 5) as u8 * 2;
        }
        assert_eq!(obstacle_ahead(&noisy, 52), None);
        // off, or a row at or above the horizon
        let wall = scene(60, 0..WIDTH, 40);
        assert_eq!(obstacle_ahead(&wall, 0), None);
        assert_eq!(obstacle_ahead(&wall, 35), None);
        assert_eq!(obstacle_ahead(&wall, 80), None);
    }

    #[test]
    fn the_nearest_foot_is_found_beside_the_column_too() {
        // a wall across the view, foot at row 45: in every column, path or not
        assert_eq!(nearest_foot(&scene(45, 0..WIDTH, 40), 49), Some(45));
        assert_eq!(nearest_foot(&scene(45, 0..WIDTH, 40), 2), Some(45));
        // a post at columns 40..44 (foot at row 60) and a wall behind (foot at row 40)
        let mut f = scene(40, 0..WIDTH, 200);
        for y in 0..=60 {
            for x in 40..44 {
                f[y * WIDTH + x] = 30;
            }
        }
        assert_eq!(nearest_foot(&f, 42), Some(60));
        // 3 columns away still sees the post (X̄ beside a narrow threat), 4 do not
        assert_eq!(nearest_foot(&f, 46), Some(60));
        assert_eq!(nearest_foot(&f, 47), Some(40));
        // nothing but floor up to the horizon, and a column out of the image
        assert_eq!(nearest_foot(&scene(0, 0..0, 0), 49), None);
        assert_eq!(nearest_foot(&f, 99), None);
    }

    #[test]
    fn marks_on_a_patterned_floor_are_not_feet_and_a_wall_over_them_is_found() {
        // dark patches on the floor, each a few rows tall, in every column
        let mut f = scene(0, 0..0, 0);
        for y in (40..HEIGHT).step_by(8) {
            for x in 0..WIDTH {
                f[y * WIDTH + x] = 60;
                f[(y + 1) * WIDTH + x] = 60;
                f[(y + 2) * WIDTH + x] = 60;
            }
        }
        assert_eq!(obstacle_ahead(&f, 52), None);
        assert_eq!(nearest_foot(&f, 49), None);
        // a wall standing on that floor at row 55, its face a little patterned too
        for y in 36..=55 {
            for x in 0..WIDTH {
                f[y * WIDTH + x] = if y % 7 == 0 { FLOOR } else { 40 };
            }
        }
        assert_eq!(obstacle_ahead(&f, 52), Some(49));
        // a mark just before the wall's foot, its column above covered by the wall, reads as
        // the nearer foot: the error falls on the safe side
        assert_eq!(nearest_foot(&f, 49), Some(66));
    }

    #[test]
    fn a_single_odd_row_is_not_a_foot() {
        let mut f = scene(0, 0..0, 0);
        for x in 0..WIDTH {
            f[60 * WIDTH + x] = 20; // a line on the floor
        }
        assert_eq!(obstacle_ahead(&f, 52), None);
    }

    #[test]
    fn a_drift_up_the_column_is_not_a_foot_and_a_step_is() {
        // the floor brightens by 5 levels a row for five rows, then stays 25 above its grey up
        // to the horizon: it leaves the follower (2 a row) behind, but never steps
        let mut f = scene(0, 0..0, 0);
        for y in 36..=60 {
            let grey = FLOOR + 5 * (61 - y).min(5) as u8;
            f[y * WIDTH..(y + 1) * WIDTH].fill(grey);
        }
        assert_eq!(Floor::of(&f).tol, FLOOR_TOL);
        assert_eq!(obstacle_ahead(&f, 52), None);
        assert_eq!(nearest_foot(&f, 49), None);
        // the same rise at once is a foot
        for y in 56..=60 {
            f[y * WIDTH..(y + 1) * WIDTH].fill(FLOOR + 25);
        }
        assert_eq!(obstacle_ahead(&f, 52), Some(49));
    }

    /// `FLOOR` with a grain of ±`amp` levels in patches of 3 × 3 pixels.
    fn grained(amp: i32) -> [u8; PIXELS] {
        let mut f = scene(0, 0..0, 0);
        for y in 36..HEIGHT {
            for x in 0..WIDTH {
                // a fixed scatter of patch greys, -amp..=amp
                let h = ((y / 3) * 7 + (x / 3) * 13 + (y / 3) * (x / 3)) % 5;
                f[y * WIDTH + x] = (i32::from(FLOOR) + amp * (h as i32 - 2) / 2) as u8;
            }
        }
        f
    }

    #[test]
    fn a_grain_on_the_floor_raises_the_tolerance_and_a_wall_on_it_is_still_found() {
        // ±2 levels, the sensor's noise, keeps the least tolerance
        assert_eq!(Floor::of(&grained(2)).tol, FLOOR_TOL);
        // ±10 levels in patches that make steps of 5 and 10 up the column: at the least
        // tolerance the grain's patches read as feet, at the grain's own they do not
        let f = grained(10);
        let floor = Floor::of(&f);
        assert!(floor.tol > FLOOR_TOL, "{floor:?}");
        assert_eq!(obstacle_ahead(&f, 52), None);
        // a wall standing on it, foot at row 55, 70 levels darker
        let mut wall = f;
        for y in 0..=55 {
            wall[y * WIDTH..(y + 1) * WIDTH].fill(40);
        }
        assert_eq!(Floor::of(&wall), floor);
        assert_eq!(obstacle_ahead(&wall, 52), Some(49));
    }

    #[test]
    fn an_obstacle_close_ahead_does_not_raise_the_tolerance() {
        // a post covers the left third of the nearest floor: its pixels are not grain
        let mut f = scene(0, 0..0, 0);
        for y in 0..HEIGHT {
            f[y * WIDTH..y * WIDTH + 33].fill(40);
        }
        assert_eq!(Floor::of(&f).tol, FLOOR_TOL);
        // covering most of the sample, it leaves the least tolerance too
        for y in 0..HEIGHT {
            f[y * WIDTH..y * WIDTH + 80].fill(40);
        }
        assert_eq!(Floor::of(&f).tol, FLOOR_TOL);
    }

    /// `foot_below` as the plain definition: every candidate's column scanned again.
    fn foot_below_plain(frame: &[u8; PIXELS], floor: Floor, x: usize, top: usize) -> Option<usize> {
        let last = top + 1 - FOOT_ROWS;
        let (mut grey, mut run, mut below) = (floor.grey, 0, floor.grey);
        let mut y = HEIGHT;
        while y > last.max(BELOW_HORIZON) {
            y -= 1;
            let p = i32::from(frame[y * WIDTH + x]);
            if (p - grey).abs() <= floor.tol {
                grey += (p - grey).clamp(-FLOOR_TRACK, FLOOR_TRACK);
                below = p;
                run = 0;
                continue;
            }
            run += 1;
            let foot = y + FOOT_ROWS - 1;
            let (hits, rows) = column_cover(frame.as_chunks().0, grey, floor.tol, x, foot);
            let stepped = (p - below).abs() > floor.tol;
            if run >= FOOT_ROWS && stepped && 100 * hits >= FOOT_COVER_PCT * rows {
                return Some(foot);
            }
        }
        None
    }

    proptest::proptest! {
        /// The tolerance is three robust standard deviations: the plain definition, the
        /// median (the sorted sample's middle, upper of two) of the deviations kept.
        #[test]
        fn the_tolerance_is_the_sorted_samples_median(
            band in proptest::collection::vec(-40i32..=40, WIDTH * 8),
            grey in 40u8..200,
        ) {
            // the nearest floor's 8 rows within ±40 of `grey`: some deviations kept, some not
            let mut f = [grey; PIXELS];
            for (p, d) in f[(HEIGHT - 8) * WIDTH..].iter_mut().zip(&band) {
                *p = (i32::from(grey) + d) as u8;
            }
            let g = floor_grey(&f);
            let mut dev: std::vec::Vec<i32> = GRAIN_ROWS
                .iter()
                .flat_map(|y| (0..GRAIN_COLS).map(move |k| y * WIDTH + 9 + 10 * k))
                .map(|i| (i32::from(f[i]) - g).abs())
                .filter(|&d| d <= 2 * FLOOR_TOL)
                .collect();
            dev.sort_unstable();
            let tol = if 2 * dev.len() >= GRAIN_SAMPLES {
                FLOOR_TOL.max(89 * dev[dev.len() / 2] / 20)
            } else {
                FLOOR_TOL
            };
            proptest::prop_assert_eq!(Floor::of(&f), Floor { grey: g, tol });
        }

        /// The one-pass cover is the plain definition's, on columns of floor, blobs and walls
        /// of a few greys (so that runs, failed candidates and covered feet all occur).
        #[test]
        fn the_one_pass_cover_is_the_plain_definition(
            column in proptest::collection::vec(proptest::sample::select(&[40u8, 52, 60, 75, 120, 200][..]), HEIGHT),
            floor in proptest::sample::select(&[40i32, 52, 60][..]),
            tol in proptest::sample::select(&[FLOOR_TOL, 20][..]),
            top in FOOT_ROWS - 1..HEIGHT,
        ) {
            let mut f = [0u8; PIXELS];
            for (y, &g) in column.iter().enumerate() {
                f[y * WIDTH + 7] = g;
            }
            let floor = Floor { grey: floor, tol };
            proptest::prop_assert_eq!(foot_below(&f, floor, 7, top), foot_below_plain(&f, floor, 7, top));
        }
    }
}

//! Path statistics of a [`Track`] in a rectangular arena, the same for recorded and simulated
//! tracks, and their comparison with stated tolerances.

use serde::{Deserialize, Serialize};

use super::track::{Segment, Track};
use alvs_sim::world::ROBOT_RADIUS_MM;

/// Segment ends closer than this are one turn, mm.
const JOIN_MM: f64 = 15.0;
/// Two runs meeting at less than this change of direction are one run broken, not a turn.
const MIN_TURN_DEG: f64 = 20.0;
/// Ends of consecutive intervals this close to the robot at the snapshot between them join
/// (the skipped path under the marker leaves a gap of about its diameter), mm.
const MARKER_GAP_MM: f64 = 50.0;
/// Floor cells for the coverage, mm.
const CELL_MM: f64 = 50.0;
/// A robot this close to a wall (centre to wall) is pressed against it, mm: its radius, 5 mm
/// of slack, and the calibration's uncertainty (~5 mm).
const PRESSED_MM: f64 = ROBOT_RADIUS_MM + 10.0;
/// A robot that moved less than this between snapshots did not move, mm.
const STILL_MM: f64 = 10.0;

/// A sample, its summary, and the sample itself (for the KS test).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Distribution {
    pub n: usize,
    pub mean: f64,
    pub q1: f64,
    pub median: f64,
    pub q3: f64,
    /// Sorted ascending.
    pub sample: Vec<f64>,
}

impl Distribution {
    pub fn of(mut sample: Vec<f64>) -> Self {
        sample.retain(|v| v.is_finite());
        sample.sort_by(f64::total_cmp);
        let n = sample.len();
        let q = |p: f64| {
            if n == 0 {
                return f64::NAN;
            }
            // Linear interpolation between order statistics (type 7).
            let h = (n - 1) as f64 * p;
            let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
            sample[lo] + (sample[hi] - sample[lo]) * (h - lo as f64)
        };
        Distribution {
            n,
            mean: if n == 0 {
                f64::NAN
            } else {
                sample.iter().sum::<f64>() / n as f64
            },
            q1: q(0.25),
            median: q(0.5),
            q3: q(0.75),
            sample,
        }
    }
}

/// What a path looked like.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PathStats {
    /// From the first to the last snapshot, s.
    pub duration_s: f64,
    /// Total length of the straight runs (their chords), mm.
    pub path_mm: f64,
    /// Share of the runs' length within 50 mm of a wall (centre line to the wall's face).
    pub share_within_50mm: f64,
    /// Share within 100 mm.
    pub share_within_100mm: f64,
    /// Distance to the nearest wall at each turn, mm.
    pub turn_wall_mm: Distribution,
    /// Straight-run lengths (between turns or loose ends), mm.
    pub run_mm: Distribution,
    pub turns_per_min: f64,
    /// Share of snapshot intervals with the robot's centre within radius + 10 mm of a wall at
    /// both ends and moved less than 10 mm: stuck against a wall.
    pub pressed_share: f64,
    /// Share of the 50 mm floor cells a run crossed.
    pub coverage: f64,
    /// Mean over snapshot intervals of the runs' length drawn in it / its duration, mm/s (a
    /// run spanning two intervals is shared by its pieces' lengths).
    pub mean_speed_mm_s: f64,
}

fn wall_distance(arena: (f64, f64), p: (f64, f64)) -> f64 {
    p.0.min(arena.0 - p.0).min(p.1).min(arena.1 - p.1)
}

/// Points along a segment, one per mm or closer.
fn samples(s: &Segment) -> impl Iterator<Item = (f64, f64)> + '_ {
    let n = s.length_mm().ceil().max(1.0) as usize;
    (0..=n).map(move |i| {
        let t = i as f64 / n as f64;
        (s.a.0 + (s.b.0 - s.a.0) * t, s.a.1 + (s.b.1 - s.a.1) * t)
    })
}

/// A path's turns and straight runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Structure {
    /// Where the path turned, mm.
    pub turns: Vec<(f64, f64)>,
    /// Straight-run lengths, mm: each run's chord (its farthest two piece ends).
    pub runs: Vec<f64>,
    /// Each segment's share of its run's length, mm (pieces of one run overlap a little,
    /// so their own lengths would count the overlaps twice).
    pub segment_mm: Vec<f64>,
}

/// Distance from `p` to the segment, mm.
fn to_segment(p: (f64, f64), s: &Segment) -> f64 {
    let (dx, dy) = (s.b.0 - s.a.0, s.b.1 - s.a.1);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p.0 - s.a.0) * dx + (p.1 - s.a.1) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((p.0 - s.a.0 - t * dx).powi(2) + (p.1 - s.a.1 - t * dy).powi(2)).sqrt()
}

/// The path's turns and straight runs from its segments. Segment ends within [`JOIN_MM`]
/// (each end of the other piece, so that overlapping pieces count as touching),
/// drawn in the same or adjacent snapshot intervals (older path passing by is no join), are
/// joined, closest pairs first, each end once. Ends of consecutive intervals near the robot's
/// position at the snapshot between them join within [`MARKER_GAP_MM`]: the path under the
/// robot's marker is skipped there. A join changing direction by at least [`MIN_TURN_DEG`]
/// is a turn; a smaller one continues the run (the Hough extraction cuts a gently curving run
/// into pieces).
pub fn structure(track: &Track) -> Structure {
    let segments = &track.segments;
    let ends: Vec<(usize, (f64, f64))> = segments
        .iter()
        .enumerate()
        .flat_map(|(i, s)| [(i, s.a), (i, s.b)])
        .collect();
    let dist = |p: (f64, f64), q: (f64, f64)| ((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt();
    let near_robot = |k: usize, p: (f64, f64)| {
        track
            .snapshots
            .get(k)
            .and_then(|s| s.robot_mm)
            .is_some_and(|r| dist(r, p) <= MARKER_GAP_MM)
    };
    let mut pairs = Vec::new();
    for (x, &(i, p)) in ends.iter().enumerate() {
        for (y, &(j, q)) in ends.iter().enumerate().skip(x + 1) {
            let (si, sj) = (segments[i].snapshot, segments[j].snapshot);
            // Each end's distance to the other piece: 0 for pieces that overlap a little
            // (consecutive Hough pieces of one run), the gap for pieces that meet end to end;
            // large for the wrong pair of ends.
            let d = to_segment(p, &segments[j]).max(to_segment(q, &segments[i]));
            let joinable = d <= JOIN_MM
                || (si.abs_diff(sj) == 1
                    && d <= MARKER_GAP_MM
                    && near_robot(si.min(sj), p)
                    && near_robot(si.min(sj), q));
            if i != j && si.abs_diff(sj) <= 1 && joinable {
                pairs.push((d, x, y));
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut used = vec![false; ends.len()];
    let mut parent: Vec<usize> = (0..segments.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut turns = Vec::new();
    for (_, x, y) in pairs {
        if used[x] || used[y] {
            continue;
        }
        used[x] = true;
        used[y] = true;
        let (i, j) = (ends[x].0, ends[y].0);
        // The travel direction into the join along piece i and out of it along piece j: the
        // turn is the angle between them (a reversal is 180°, not "straight on").
        let other = |e: usize| {
            if e.is_multiple_of(2) {
                ends[e + 1].1
            } else {
                ends[e - 1].1
            }
        };
        let (px, py) = (ends[x].1, ends[y].1);
        let (ox, oy) = (other(x), other(y));
        let (vin, vout) = ((px.0 - ox.0, px.1 - ox.1), (oy.0 - py.0, oy.1 - py.1));
        let diff = (vin.0 * vout.1 - vin.1 * vout.0)
            .atan2(vin.0 * vout.0 + vin.1 * vout.1)
            .abs()
            .to_degrees();
        if diff >= MIN_TURN_DEG {
            let (p, q) = (ends[x].1, ends[y].1);
            turns.push(((p.0 + q.0) / 2.0, (p.1 + q.1) / 2.0));
        } else {
            let (a, b) = (root(&mut parent, i), root(&mut parent, j));
            parent[a] = b;
        }
    }
    let roots: Vec<usize> = (0..segments.len()).map(|i| root(&mut parent, i)).collect();
    let mut members: Vec<Vec<usize>> = vec![vec![]; segments.len()];
    for (i, &r) in roots.iter().enumerate() {
        members[r].push(i);
    }
    let mut runs = Vec::new();
    let mut segment_mm = vec![0.0; segments.len()];
    for m in members.iter().filter(|m| !m.is_empty()) {
        let pts: Vec<(f64, f64)> = m
            .iter()
            .flat_map(|&i| [segments[i].a, segments[i].b])
            .collect();
        let mut chord = 0.0f64;
        for (k, &p) in pts.iter().enumerate() {
            for &q in &pts[k + 1..] {
                chord = chord.max(dist(p, q));
            }
        }
        let sum: f64 = m.iter().map(|&i| segments[i].length_mm()).sum();
        for &i in m {
            segment_mm[i] = if sum > 0.0 {
                chord * segments[i].length_mm() / sum
            } else {
                0.0
            };
        }
        runs.push(chord);
    }
    Structure {
        turns,
        runs,
        segment_mm,
    }
}

impl PathStats {
    /// The statistics of `track` in an `arena` (inner width, height, mm) rectangle.
    pub fn of(track: &Track, arena: (f64, f64)) -> Self {
        let segs = &track.segments;
        let st = structure(track);
        let path_mm: f64 = st.segment_mm.iter().sum();
        let (mut n, mut n50, mut n100) = (0usize, 0usize, 0usize);
        let (cols, rows) = (
            (arena.0 / CELL_MM).ceil().max(1.0) as usize,
            (arena.1 / CELL_MM).ceil().max(1.0) as usize,
        );
        let mut cells = vec![false; cols * rows];
        for s in segs {
            for p in samples(s) {
                let d = wall_distance(arena, p);
                n += 1;
                n50 += usize::from(d <= 50.0);
                n100 += usize::from(d <= 100.0);
                let (cx, cy) = ((p.0 / CELL_MM).floor(), (p.1 / CELL_MM).floor());
                if cx >= 0.0 && cy >= 0.0 && (cx as usize) < cols && (cy as usize) < rows {
                    cells[cy as usize * cols + cx as usize] = true;
                }
            }
        }
        let share = |k: usize| if n == 0 { 0.0 } else { k as f64 / n as f64 };
        let snaps = &track.snapshots;
        let duration_s = match (snaps.first(), snaps.last()) {
            (Some(a), Some(b)) => b.t_s - a.t_s,
            _ => 0.0,
        };
        let (turn_points, run_lengths) = (&st.turns, st.runs.clone());
        let (mut pressed, mut intervals, mut speeds) = (0usize, 0usize, Vec::new());
        for k in 1..snaps.len() {
            let dt = snaps[k].t_s - snaps[k - 1].t_s;
            if dt <= 0.0 {
                continue;
            }
            let drawn: f64 = segs
                .iter()
                .zip(&st.segment_mm)
                .filter(|(s, _)| s.snapshot == k)
                .map(|(_, l)| l)
                .sum();
            speeds.push(drawn / dt);
            if let (Some(p), Some(q)) = (snaps[k - 1].robot_mm, snaps[k].robot_mm) {
                intervals += 1;
                let moved = ((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt();
                let at_wall =
                    wall_distance(arena, p) <= PRESSED_MM && wall_distance(arena, q) <= PRESSED_MM;
                pressed += usize::from(at_wall && moved < STILL_MM);
            }
        }
        PathStats {
            duration_s,
            path_mm,
            share_within_50mm: share(n50),
            share_within_100mm: share(n100),
            turn_wall_mm: Distribution::of(
                turn_points
                    .iter()
                    .map(|&p| wall_distance(arena, p))
                    .collect(),
            ),
            run_mm: Distribution::of(run_lengths),
            turns_per_min: if duration_s > 0.0 {
                turn_points.len() as f64 * 60.0 / duration_s
            } else {
                0.0
            },
            pressed_share: if intervals == 0 {
                0.0
            } else {
                pressed as f64 / intervals as f64
            },
            coverage: cells.iter().filter(|&&c| c).count() as f64 / cells.len() as f64,
            mean_speed_mm_s: if speeds.is_empty() {
                0.0
            } else {
                speeds.iter().sum::<f64>() / speeds.len() as f64
            },
        }
    }
}

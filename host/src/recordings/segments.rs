//! Straight runs of a drawn path: a greedy Hough extraction on the pixels a snapshot interval
//! added. The strongest line of the accumulator is refined by a total-least-squares fit of the
//! pixels near it, its longest contiguous run of pixels (gaps bridged where older path or a
//! short gap lies between) becomes a segment, its pixels leave the accumulator, and so on
//! down to a minimum length.
//!
//! Hand-written: `imageproc`'s Hough (`detect_lines`) returns infinite lines without their
//! extent and pulls in a large dependency tree; the segment runs are the point here.

use super::snapshot::Mask;

/// Angle bins over 180°.
const THETA_BINS: usize = 360;
/// Pixels within this distance of a line belong to it (the tracker's line is ~3 px wide).
const BAND_PX: f64 = 2.0;
/// A gap of up to this many px between a line's pixels is part of the run.
const GAP_PX: f64 = 8.0;

/// A straight run in px.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PxSegment {
    pub a: (f64, f64),
    pub b: (f64, f64),
    /// Pixels it took.
    pub pixels: usize,
}

impl PxSegment {
    pub fn length(&self) -> f64 {
        ((self.b.0 - self.a.0).powi(2) + (self.b.1 - self.a.1).powi(2)).sqrt()
    }
}

/// What one interval's extraction found.
#[derive(Debug, Clone, Default)]
pub struct Extraction {
    pub segments: Vec<PxSegment>,
    /// New pixels no segment took (turn marks, short wiggles, runs below the minimum).
    pub leftover: usize,
}

/// Extracts segments of at least `min_len_px` from `points` (the interval's new pixels);
/// `bridge` (all path pixels drawn so far) lets a run continue across older path that hides
/// part of it.
pub fn extract(points: &[(i32, i32)], bridge: &Mask, min_len_px: f64) -> Extraction {
    let (w, h) = (bridge.width as f64, bridge.height as f64);
    let diag = (w * w + h * h).sqrt();
    let rho_bins = (2.0 * diag / BAND_PX).ceil() as usize + 1;
    let trig: Vec<(f64, f64)> = (0..THETA_BINS)
        .map(|t| {
            let th = t as f64 * std::f64::consts::PI / THETA_BINS as f64;
            (th.cos(), th.sin())
        })
        .collect();
    let bin = |p: (i32, i32), t: usize| {
        let r = p.0 as f64 * trig[t].0 + p.1 as f64 * trig[t].1;
        ((r + diag) / BAND_PX) as usize
    };
    let mut acc = vec![0u32; THETA_BINS * rho_bins];
    for &p in points {
        for t in 0..THETA_BINS {
            acc[t * rho_bins + bin(p, t)] += 1;
        }
    }
    let mut alive = vec![true; points.len()];
    let mut out = Extraction::default();
    // A 3 px wide line of the minimum length gets about this many votes.
    let min_votes = (min_len_px * 1.5) as u32;
    while let Some((best, &votes)) = acc.iter().enumerate().max_by_key(|(_, &v)| v) {
        if votes < min_votes.max(3) {
            break;
        }
        let (t, r) = (best / rho_bins, best % rho_bins);
        let (c, s) = trig[t];
        let rho = r as f64 * BAND_PX - diag + BAND_PX / 2.0;
        match best_run(points, &alive, bridge, (c, s, rho), min_len_px) {
            Some((seg, taken)) => {
                for &i in &taken {
                    alive[i] = false;
                    for tt in 0..THETA_BINS {
                        acc[tt * rho_bins + bin(points[i], tt)] -= 1;
                    }
                }
                out.segments.push(PxSegment {
                    pixels: taken.len(),
                    ..seg
                });
            }
            // Collinear scraps of several lines: this bin holds no run; never look again.
            None => acc[best] = 0,
        }
    }
    out.leftover = alive.iter().filter(|&&a| a).count();
    out
}

/// Alive points within `band` of the line `x*c + y*s = rho`.
fn near(
    points: &[(i32, i32)],
    alive: &[bool],
    (c, s, rho): (f64, f64, f64),
    band: f64,
) -> Vec<usize> {
    (0..points.len())
        .filter(|&i| {
            alive[i] && (points[i].0 as f64 * c + points[i].1 as f64 * s - rho).abs() <= band
        })
        .collect()
}

/// Total-least-squares line through the points: (c, s, rho) with (c, s) its unit normal.
fn tls(points: &[(i32, i32)], idx: &[usize]) -> Option<(f64, f64, f64)> {
    let n = idx.len() as f64;
    if n < 2.0 {
        return None;
    }
    let (mx, my) = idx.iter().fold((0.0, 0.0), |a, &i| {
        (a.0 + points[i].0 as f64 / n, a.1 + points[i].1 as f64 / n)
    });
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for &i in idx {
        let (dx, dy) = (points[i].0 as f64 - mx, points[i].1 as f64 - my);
        sxx += dx * dx;
        syy += dy * dy;
        sxy += dx * dy;
    }
    // Direction of largest spread; the normal is perpendicular to it.
    let th = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let (c, s) = (-th.sin(), th.cos());
    Some((c, s, mx * c + my * s))
}

/// The longest run along a refined line, and the points it takes.
fn best_run(
    points: &[(i32, i32)],
    alive: &[bool],
    bridge: &Mask,
    line: (f64, f64, f64),
    min_len_px: f64,
) -> Option<(PxSegment, Vec<usize>)> {
    let mut line = line;
    let mut idx = near(points, alive, line, BAND_PX + 1.0);
    // Refine twice: the accumulator's angle is 0.5° coarse, a long line needs better.
    for _ in 0..2 {
        line = tls(points, &idx)?;
        idx = near(points, alive, line, BAND_PX);
    }
    let (c, s, rho) = line;
    let (dx, dy) = (s, -c);
    let along = |i: usize| points[i].0 as f64 * dx + points[i].1 as f64 * dy;
    idx.sort_by(|&i, &j| along(i).total_cmp(&along(j)));
    let at = |t: f64| (c * rho + dx * t, s * rho + dy * t);
    let covered = |t0: f64, t1: f64| {
        let mut t = t0;
        while t < t1 {
            let (x, y) = at(t);
            let (xi, yi) = (x.round() as i64, y.round() as i64);
            if !(-1..=1).any(|k| bridge.at(xi + k, yi) || bridge.at(xi, yi + k)) {
                return false;
            }
            t += 1.0;
        }
        true
    };
    let (mut best, mut start) = ((0usize, 0usize), 0usize);
    for k in 1..=idx.len() {
        let end_run = k == idx.len() || {
            let (t0, t1) = (along(idx[k - 1]), along(idx[k]));
            t1 - t0 > GAP_PX && !covered(t0, t1)
        };
        if end_run {
            if along(idx[k - 1]) - along(idx[start]) > along(idx[best.1]) - along(idx[best.0]) {
                best = (start, k - 1);
            }
            start = k;
        }
    }
    if idx.is_empty() {
        return None;
    }
    let (t0, t1) = (along(idx[best.0]), along(idx[best.1]));
    if t1 - t0 < min_len_px {
        return None;
    }
    let taken = idx[best.0..=best.1].to_vec();
    Some((
        PxSegment {
            a: at(t0),
            b: at(t1),
            pixels: taken.len(),
        },
        taken,
    ))
}

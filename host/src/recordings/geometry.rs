//! The arena's geometry and looks measured on a snapshot: obstacle cylinders, the walls'
//! apparent band (hence their height), grey levels and the walls' rib period.
//!
//! Heights come from perspective: a point `h` above the floor, `d` px from the nadir on the
//! floor, is seen `d * h / (H - h)` px further out, so a wall's inner face shows as a band of
//! that width and an obstacle's top ring sits that far outward of its base. That fixes
//! `k = h / (H - h)`; `h = k H / (1 + k)` needs the camera height `H`, which nothing in the
//! snapshots measures well (see docs/recordings.md), so it is an assumption with a range.

use serde::{Deserialize, Serialize};

use super::calibration::FloorQuad;
use super::snapshot::{is_drawing, luma, Rgb8};

/// Brighter than this is an obstacle's or a wall's surface (the floor is ~50-65).
const BRIGHT: f64 = 130.0;
/// An obstacle's side and top are brighter than this (its ribs' grooves too, mostly).
const BLOB: f64 = 110.0;
/// The white surround (table, wall tops) outside the walls' ribbed faces.
const WHITE: f64 = 240.0;

/// An obstacle as seen: top-ring centre and base, image px.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ObstacleSeen {
    /// Centre of the top ring, px (for an obstacle at a wall: where the blob ends at the wall).
    pub top_px: (f64, f64),
    /// Centre of the base on the floor, px.
    pub base_px: (f64, f64),
    /// Apparent diameter across the side, px.
    pub diameter_px: f64,
    /// `h / (H - h)` from the top's outward shift; `None` for obstacles at a wall, whose top
    /// is not over the floor.
    pub k: Option<f64>,
}

/// Mean luma of the floor (non-drawing pixels inside the quad, shrunk 20 px from its sides).
pub fn floor_luma(img: &Rgb8, quad: &FloorQuad) -> f64 {
    let [tl, tr, br, bl] = quad.corners;
    let (x0, x1) = (tl.0.max(bl.0) + 20.0, tr.0.min(br.0) - 20.0);
    let (y0, y1) = (tl.1.max(tr.1) + 20.0, bl.1.min(br.1) - 20.0);
    let (mut s, mut n) = (0.0, 0usize);
    for y in (y0 as usize..y1 as usize).step_by(2) {
        for x in (x0 as usize..x1 as usize).step_by(2) {
            let p = img.pixels[y * img.width + x];
            if !is_drawing(p) && luma(p) < BRIGHT {
                s += luma(p);
                n += 1;
            }
        }
    }
    s / n.max(1) as f64
}

/// The ribbed inner face of the left and right walls beside the floor: per sampled row, the
/// run of pixels outward from the floor's side until the white surround. Returns (mean luma of
/// the face, median band width px, median distance of the floor side from the nadir px,
/// luma profile along the left wall's face for the rib period).
pub fn wall_band(img: &Rgb8, quad: &FloorQuad, nadir: (f64, f64)) -> (f64, f64, f64, Vec<f64>) {
    let [tl, tr, br, bl] = quad.corners;
    let (mut sum, mut n) = (0.0, 0usize);
    let (mut widths, mut dists) = (Vec::new(), Vec::new());
    let mut profile = Vec::new();
    let (ya, yb) = (tl.1.max(tr.1), bl.1.min(br.1));
    for y in (ya as usize + 10)..(yb as usize - 10) {
        let f = (y as f64 - ya) / (yb - ya);
        // Rows beside the side obstacles (middle of each side) and the corners are skipped.
        let usable = (0.15..0.38).contains(&f) || (0.62..0.85).contains(&f);
        for (edge, dir) in [
            (tl.0 + (bl.0 - tl.0) * f, -1i64),
            (tr.0 + (br.0 - tr.0) * f, 1),
        ] {
            let x_edge = edge.round() as i64;
            let mut w = 0i64;
            let mut s = 0.0;
            while let Some(p) = img.get(x_edge + dir * (w + 1), y as i64) {
                if luma(p) >= WHITE || w > 200 {
                    break;
                }
                s += luma(p);
                w += 1;
            }
            if dir < 0 {
                // The face's middle column, for the ribs (which run across it).
                profile.push(img.get(x_edge - 12, y as i64).map_or(0.0, luma));
            }
            if usable && w > 3 {
                widths.push(w as f64);
                dists.push((edge - nadir.0).abs());
                sum += s;
                n += w as usize;
            }
        }
    }
    (
        sum / n.max(1) as f64,
        median(&mut widths),
        median(&mut dists),
        profile,
    )
}

/// Period (px) of a luma profile: the first autocorrelation peak between 3 and 60 px.
pub fn period_px(profile: &[f64]) -> Option<f64> {
    let n = profile.len();
    if n < 120 {
        return None;
    }
    let mean = profile.iter().sum::<f64>() / n as f64;
    let v: Vec<f64> = profile.iter().map(|p| p - mean).collect();
    let ac = |lag: usize| {
        let s: f64 = (0..n - lag).map(|i| v[i] * v[i + lag]).sum();
        s / (n - lag) as f64
    };
    let acs: Vec<f64> = (0..=61).map(ac).collect();
    (3..=60)
        .find(|&l| acs[l] > acs[l - 1] && acs[l] >= acs[l + 1] && acs[l] > 0.0)
        .map(|l| {
            // Parabolic interpolation of the peak.
            let (a, b, c) = (acs[l - 1], acs[l], acs[l + 1]);
            let den = a - 2.0 * b + c;
            l as f64
                + if den.abs() > 1e-12 {
                    0.5 * (a - c) / den
                } else {
                    0.0
                }
        })
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The obstacles: bright blobs on the floor (everything of an obstacle that the camera sees
/// over the floor: its side and, away from the walls, its top). The base is the slice of the
/// cylinder nearest the nadir, so its centre is the blob's near end plus a radius, the radius
/// half the blob's width across the nadir's direction. An obstacle touching the floor's edge
/// (standing at a wall) has its top over the wall, so its `k` is not measured (`None`).
/// `inside(x, y)` tells floor pixels; blobs within `exclude` (the robot) are skipped.
pub fn find_obstacles(
    img: &Rgb8,
    nadir: (f64, f64),
    inside: impl Fn(f64, f64) -> bool,
    exclude: Option<(f64, f64, f64)>,
) -> Vec<ObstacleSeen> {
    let (w, h) = (img.width, img.height);
    let floor: Vec<bool> = (0..w * h)
        .map(|i| inside((i % w) as f64, (i / w) as f64))
        .collect();
    let bright = |i: usize| {
        let p = img.pixels[i];
        floor[i] && !is_drawing(p) && luma(p) >= BLOB
    };
    let mut seen = vec![false; w * h];
    let mut out = Vec::new();
    let mut stack = Vec::new();
    for start in 0..w * h {
        if seen[start] || !bright(start) {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        let mut px = Vec::new();
        let mut at_edge = false;
        while let Some(i) = stack.pop() {
            px.push(((i % w) as f64, (i / w) as f64));
            for j in [i.wrapping_sub(1), i + 1, i.wrapping_sub(w), i + w] {
                if j >= w * h {
                    continue;
                }
                if !floor[j] {
                    at_edge = true;
                } else if !seen[j] && bright(j) {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
        if px.len() < 300 {
            continue;
        }
        let n = px.len() as f64;
        let c = px
            .iter()
            .fold((0.0, 0.0), |a, p| (a.0 + p.0 / n, a.1 + p.1 / n));
        if exclude.is_some_and(|(ex, ey, r)| (c.0 - ex).powi(2) + (c.1 - ey).powi(2) < r * r) {
            continue;
        }
        let (dx, dy) = (c.0 - nadir.0, c.1 - nadir.1);
        let d = (dx * dx + dy * dy).sqrt().max(1e-9);
        let (u, v) = ((dx / d, dy / d), (-dy / d, dx / d));
        let (mut a0, mut a1, mut b0, mut b1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for p in &px {
            let (rx, ry) = (p.0 - nadir.0, p.1 - nadir.1);
            let (a, b) = (rx * u.0 + ry * u.1, rx * v.0 + ry * v.1);
            (a0, a1, b0, b1) = (a0.min(a), a1.max(a), b0.min(b), b1.max(b));
        }
        let width = b1 - b0 + 1.0;
        let r = width / 2.0;
        let (ba, bb) = (a0 - 0.5 + r, (b0 + b1) / 2.0);
        let base = (nadir.0 + ba * u.0 + bb * v.0, nadir.1 + ba * u.1 + bb * v.1);
        // The top ring (same radius, a little magnified) ends the blob on the far side.
        let ta = a1 + 0.5 - r;
        let top = (nadir.0 + ta * u.0 + bb * v.0, nadir.1 + ta * u.1 + bb * v.1);
        out.push(ObstacleSeen {
            top_px: top,
            base_px: base,
            diameter_px: width,
            k: (!at_edge).then(|| (ta - ba) / ba),
        });
    }
    out
}

/// The obstacles' tops: dark roundish holes (the rolls' insides) enclosed by bright pixels,
/// 8-45 px across, filling over half their box; their centres, px. Holes within `exclude`
/// (the robot, whose marker encloses dark pixels too) are skipped.
pub fn find_holes(img: &Rgb8, exclude: Option<(f64, f64, f64)>) -> Vec<(f64, f64)> {
    let (w, h) = (img.width, img.height);
    let dark = |i: usize| {
        let p = img.pixels[i];
        !is_drawing(p) && luma(p) < BRIGHT
    };
    let mut seen = vec![false; w * h];
    let mut out = Vec::new();
    let mut stack = Vec::new();
    for start in 0..w * h {
        if seen[start] || !dark(start) {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        let (mut n, mut sx, mut sy, mut touches) = (0usize, 0.0, 0.0, false);
        let (mut x0, mut x1, mut y0, mut y1) = (w, 0, h, 0);
        while let Some(i) = stack.pop() {
            let (x, y) = (i % w, i / w);
            n += 1;
            sx += x as f64;
            sy += y as f64;
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
            if x == 0 || y == 0 || x + 1 == w || y + 1 == h {
                touches = true;
                continue;
            }
            for j in [i - 1, i + 1, i - w, i + w] {
                if !seen[j] && dark(j) {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
        let (bw, bh) = ((x1 - x0 + 1) as f64, (y1 - y0 + 1) as f64);
        let roundish = (8.0..=45.0).contains(&bw)
            && (8.0..=45.0).contains(&bh)
            && bw.max(bh) / bw.min(bh) < 1.8
            && n as f64 > 0.5 * bw * bh;
        let c = (sx / n as f64, sy / n as f64);
        let excluded =
            exclude.is_some_and(|(ex, ey, r)| (c.0 - ex).powi(2) + (c.1 - ey).powi(2) < r * r);
        if !touches && roundish && !excluded {
            out.push(c);
        }
    }
    out
}

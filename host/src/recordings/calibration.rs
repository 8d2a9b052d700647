//! From a snapshot's pixels to floor millimetres: the dark floor's quadrilateral (four fitted
//! sides, their intersections), a homography from image px to floor mm, and the perspective
//! correction for points above the floor (the tracked top of the robot).
//!
//! The camera looks straight down (the floor's sides come out parallel within a few px), so a
//! point at height `h` above floor point `p` is seen where floor point
//! `n + (p - n) * H / (H - h)` would be, `n` the nadir (taken as the image centre) and `H` the
//! camera's height. Points above the floor are scaled back toward the nadir by `(H - h) / H`
//! before the homography.

use anyhow::{bail, Result};
use serde::{Deserialize, Serialize};

use super::snapshot::{is_drawing, luma, Rgb8, PATH_GREEN};

/// Floor pixels are darker than this luma (the floor is ~50-65, walls and obstacles > 150).
const FLOOR_LUMA_MAX: f64 = 100.0;
/// A side's boundary samples further than this from its fit are obstacles or shadows, px.
const INLIER_PX: f64 = 2.5;

/// A projective map of the plane (row-major 3x3, last entry 1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Homography(pub [f64; 9]);

impl Homography {
    /// The map taking `from[i]` to `to[i]` (four points, no three collinear).
    pub fn from_points(from: [(f64, f64); 4], to: [(f64, f64); 4]) -> Result<Self> {
        let mut a = [[0.0f64; 9]; 8];
        for i in 0..4 {
            let ((x, y), (u, v)) = (from[i], to[i]);
            a[2 * i] = [x, y, 1.0, 0.0, 0.0, 0.0, -u * x, -u * y, u];
            a[2 * i + 1] = [0.0, 0.0, 0.0, x, y, 1.0, -v * x, -v * y, v];
        }
        // Gaussian elimination with partial pivoting on the 8x8 system (last column: rhs).
        for c in 0..8 {
            let p = (c..8)
                .max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))
                .unwrap_or(c);
            if a[p][c].abs() < 1e-12 {
                bail!("degenerate quadrilateral: three corners in a line");
            }
            a.swap(c, p);
            let pivot = a[c];
            for (r, row) in a.iter_mut().enumerate() {
                if r != c {
                    let f = row[c] / pivot[c];
                    for (v, pv) in row.iter_mut().zip(pivot.iter()).skip(c) {
                        *v -= f * pv;
                    }
                }
            }
        }
        let mut h = [1.0; 9];
        for (i, row) in a.iter().enumerate() {
            h[i] = row[8] / row[i];
        }
        Ok(Homography(h))
    }

    /// The image of (x, y).
    pub fn apply(&self, x: f64, y: f64) -> (f64, f64) {
        let h = &self.0;
        let w = h[6] * x + h[7] * y + h[8];
        (
            (h[0] * x + h[1] * y + h[2]) / w,
            (h[3] * x + h[4] * y + h[5]) / w,
        )
    }
}

/// A line `a*x + b*y = c` with `a² + b² = 1`.
#[derive(Debug, Clone, Copy)]
struct Line {
    a: f64,
    b: f64,
    c: f64,
}

impl Line {
    fn meet(self, o: Line) -> Option<(f64, f64)> {
        let d = self.a * o.b - self.b * o.a;
        (d.abs() > 1e-9).then(|| {
            (
                (self.c * o.b - self.b * o.c) / d,
                (self.a * o.c - self.c * o.a) / d,
            )
        })
    }
}

/// Least-squares `u = p + q*v` through (v, u) samples, trimmed: samples further than
/// [`INLIER_PX`] from the fit are dropped and the fit repeated, so obstacles standing on a
/// side (which move its boundary inward) and the odd shadow do not bend it. Returns the fit
/// and its inlier count.
fn trimmed_fit(samples: &[(f64, f64)]) -> Option<((f64, f64), usize)> {
    let mut keep: Vec<(f64, f64)> = samples.to_vec();
    let mut fit = (0.0, 0.0);
    for round in 0..12 {
        let n = keep.len() as f64;
        if n < 20.0 {
            return None;
        }
        let (sv, su) = keep
            .iter()
            .fold((0.0, 0.0), |s, &(v, u)| (s.0 + v, s.1 + u));
        let (mv, mu) = (sv / n, su / n);
        let (mut svv, mut svu) = (0.0, 0.0);
        for &(v, u) in &keep {
            svv += (v - mv) * (v - mv);
            svu += (v - mv) * (u - mu);
        }
        let q = if svv > 0.0 { svu / svv } else { 0.0 };
        fit = (mu - q * mv, q);
        // Early rounds drop only the worst half of the far samples, so a biased first fit
        // does not throw away the true side.
        let tol = if round < 6 {
            40.0 / (1 << round) as f64
        } else {
            INLIER_PX
        }
        .max(INLIER_PX);
        keep = samples
            .iter()
            .copied()
            .filter(|&(v, u)| (u - fit.0 - fit.1 * v).abs() <= tol)
            .collect();
    }
    Some((fit, keep.len()))
}

/// The dark floor's quadrilateral in image px.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FloorQuad {
    /// Corners: top-left, top-right, bottom-right, bottom-left (image px).
    pub corners: [(f64, f64); 4],
    /// Boundary samples that agreed with each side's fit (left, right, top, bottom).
    pub inliers: [usize; 4],
}

impl FloorQuad {
    /// Side lengths in px: top, right, bottom, left.
    pub fn sides_px(&self) -> [f64; 4] {
        let c = self.corners;
        let d = |a: (f64, f64), b: (f64, f64)| ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt();
        [d(c[0], c[1]), d(c[1], c[2]), d(c[2], c[3]), d(c[3], c[0])]
    }
}

/// Whether a pixel belongs to the floor: dark, or the path drawn on it.
fn floorish(p: [u8; 3]) -> bool {
    p == PATH_GREEN || (!is_drawing(p) && luma(p) < FLOOR_LUMA_MAX)
}

/// The largest 4-connected region of floor pixels.
fn floor_region(img: &Rgb8) -> (Vec<bool>, usize) {
    let (w, h) = (img.width, img.height);
    let mut label = vec![0u32; w * h];
    let (mut best, mut best_n, mut next) = (0u32, 0usize, 0u32);
    let mut stack = Vec::new();
    for start in 0..w * h {
        if label[start] != 0 || !floorish(img.pixels[start]) {
            continue;
        }
        next += 1;
        let mut n = 0;
        label[start] = next;
        stack.push(start);
        while let Some(i) = stack.pop() {
            n += 1;
            let (x, y) = (i % w, i / w);
            let mut visit = |j: usize| {
                if label[j] == 0 && floorish(img.pixels[j]) {
                    label[j] = next;
                    stack.push(j);
                }
            };
            if x > 0 {
                visit(i - 1);
            }
            if x + 1 < w {
                visit(i + 1);
            }
            if y > 0 {
                visit(i - w);
            }
            if y + 1 < h {
                visit(i + w);
            }
        }
        if n > best_n {
            (best, best_n) = (next, n);
        }
    }
    (
        label.iter().map(|&l| l == best && best != 0).collect(),
        best_n,
    )
}

/// Finds the floor's quadrilateral: the largest dark region, its outermost pixel per row
/// (left and right sides) and per column (top and bottom), a trimmed line fit per side over
/// the middle 80 % of the region's extent, and the sides' intersections. The corners
/// themselves are hidden under obstacles, which is why they come from the sides.
pub fn find_floor(img: &Rgb8) -> Result<FloorQuad> {
    let (w, h) = (img.width, img.height);
    let (region, n) = floor_region(img);
    if n < w * h / 10 {
        bail!("no dark floor found (largest dark region {n} px)");
    }
    let (mut x0, mut x1, mut y0, mut y1) = (w, 0, h, 0);
    for (i, _) in region.iter().enumerate().filter(|(_, &r)| r) {
        let (x, y) = (i % w, i / w);
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let band = |lo: usize, hi: usize| {
        let m = (hi - lo) / 10;
        (lo + m)..(hi - m)
    };
    let (mut left, mut right, mut top, mut bottom) = (vec![], vec![], vec![], vec![]);
    for y in band(y0, y1) {
        let row = &region[y * w..(y + 1) * w];
        if let (Some(a), Some(b)) = (row.iter().position(|&r| r), row.iter().rposition(|&r| r)) {
            left.push((y as f64, a as f64 - 0.5));
            right.push((y as f64, b as f64 + 0.5));
        }
    }
    for x in band(x0, x1) {
        let col = |y: usize| region[y * w + x];
        if let (Some(a), Some(b)) = ((0..h).find(|&y| col(y)), (0..h).rev().find(|&y| col(y))) {
            top.push((x as f64, a as f64 - 0.5));
            bottom.push((x as f64, b as f64 + 0.5));
        }
    }
    let mut lines = Vec::new();
    let mut inliers = [0; 4];
    for (k, (samples, vertical)) in [(left, true), (right, true), (top, false), (bottom, false)]
        .into_iter()
        .enumerate()
    {
        let Some(((p, q), n)) = trimmed_fit(&samples) else {
            bail!(
                "the floor's {} side could not be fitted",
                ["left", "right", "top", "bottom"][k]
            );
        };
        inliers[k] = n;
        // vertical: x = p + q*y, i.e. x - q*y = p; horizontal: y = p + q*x.
        let (a, b) = if vertical { (1.0, -q) } else { (-q, 1.0) };
        let norm = (a * a + b * b).sqrt();
        lines.push(Line {
            a: a / norm,
            b: b / norm,
            c: p / norm,
        });
    }
    let meet = |i: usize, j: usize| {
        lines[i]
            .meet(lines[j])
            .ok_or_else(|| anyhow::anyhow!("parallel floor sides"))
    };
    Ok(FloorQuad {
        corners: [meet(0, 2)?, meet(1, 2)?, meet(1, 3)?, meet(0, 3)?],
        inliers,
    })
}

/// How image px become floor mm for one run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Calibration {
    /// Image px → floor mm (floor points only).
    pub homography: Homography,
    /// The nadir (image px) points above the floor are scaled toward.
    pub nadir_px: (f64, f64),
    /// `(H - h) / H` for the tracked top of the robot (H the camera's height, h the top's).
    pub top_shrink: f64,
}

impl Calibration {
    /// Floor mm of an image point on the floor.
    pub fn floor_mm(&self, x: f64, y: f64) -> (f64, f64) {
        self.homography.apply(x, y)
    }

    /// Floor mm under an image point on the robot's top (the tracked marker and path).
    pub fn top_mm(&self, x: f64, y: f64) -> (f64, f64) {
        let (nx, ny) = self.nadir_px;
        let k = self.top_shrink;
        self.homography.apply(nx + (x - nx) * k, ny + (y - ny) * k)
    }
}

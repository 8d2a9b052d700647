//! One tracker snapshot of the LGMD2-open-source recordings: a 1920x1080 RGB PNG of the arena
//! seen from above, with the tracker's drawing on it (the path in pure green, the robot's
//! marker: a pure blue ellipse and a pure red digit). The drawing is not anti-aliased, so the
//! tracker's pixels are told from the camera's by their exact colour.

use std::path::Path;

use anyhow::{bail, Context, Result};

/// Width and height every snapshot has; another size means another camera set-up, whose
/// calibration this module does not have.
pub const SNAPSHOT_SIZE: (usize, usize) = (1920, 1080);
/// The tracker's path colour.
pub const PATH_GREEN: [u8; 3] = [0, 255, 0];
/// The tracker's robot ellipse colour.
pub const MARKER_BLUE: [u8; 3] = [0, 0, 255];
/// The tracker's robot digit colour.
pub const MARKER_RED: [u8; 3] = [255, 0, 0];

/// An 8-bit RGB image, row after row.
#[derive(Debug, Clone)]
pub struct Rgb8 {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<[u8; 3]>,
}

impl Rgb8 {
    /// A `width` x `height` image filled with `colour`.
    pub fn filled(width: usize, height: usize, colour: [u8; 3]) -> Self {
        Rgb8 {
            width,
            height,
            pixels: vec![colour; width * height],
        }
    }

    /// Decodes a PNG; a file that is not a PNG, or not of [`SNAPSHOT_SIZE`], is an error that
    /// names it.
    pub fn load_snapshot(path: &Path) -> Result<Self> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !ext.eq_ignore_ascii_case("png") {
            bail!("{}: not a PNG snapshot", path.display());
        }
        let bytes = std::fs::read(path).with_context(|| format!("{}", path.display()))?;
        let img = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
            .map_err(|e| anyhow::anyhow!("{}: not a readable PNG ({e})", path.display()))?
            .to_rgb8();
        let (w, h) = (img.width() as usize, img.height() as usize);
        if (w, h) != SNAPSHOT_SIZE {
            bail!(
                "{}: {w}x{h} px, expected {}x{} (another camera set-up)",
                path.display(),
                SNAPSHOT_SIZE.0,
                SNAPSHOT_SIZE.1
            );
        }
        let pixels = img.pixels().map(|p| p.0).collect();
        Ok(Rgb8 {
            width: w,
            height: h,
            pixels,
        })
    }

    /// The pixel at (x, y); `None` off the image.
    pub fn get(&self, x: i64, y: i64) -> Option<[u8; 3]> {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            return None;
        }
        Some(self.pixels[y as usize * self.width + x as usize])
    }

    /// Sets (x, y) if it is on the image.
    pub fn set(&mut self, x: i64, y: i64, c: [u8; 3]) {
        if x >= 0 && y >= 0 && x < self.width as i64 && y < self.height as i64 {
            self.pixels[y as usize * self.width + x as usize] = c;
        }
    }
}

/// Rec. 709 luma of an sRGB pixel (gamma-encoded values, as the camera wrote them).
pub fn luma(p: [u8; 3]) -> f64 {
    0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64
}

/// Whether a pixel is one of the tracker's drawing colours.
pub fn is_drawing(p: [u8; 3]) -> bool {
    p == PATH_GREEN || p == MARKER_BLUE || p == MARKER_RED
}

/// A pixel that looks green like the path but is not its exact colour: a camera pixel of a
/// green thing, or a path pixel altered by re-encoding. Counted, never used.
pub fn is_ambiguous_green(p: [u8; 3]) -> bool {
    p != PATH_GREEN && p[1] >= 180 && p[0] <= 90 && p[2] <= 90
}

/// A binary mask over an image grid.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mask {
    pub width: usize,
    pub height: usize,
    pub bits: Vec<bool>,
}

impl Mask {
    /// An empty mask.
    pub fn new(width: usize, height: usize) -> Self {
        Mask {
            width,
            height,
            bits: vec![false; width * height],
        }
    }

    /// Whether (x, y) is set; false off the grid.
    pub fn at(&self, x: i64, y: i64) -> bool {
        x >= 0
            && y >= 0
            && x < self.width as i64
            && y < self.height as i64
            && self.bits[y as usize * self.width + x as usize]
    }

    /// Sets (x, y) if it is on the grid.
    pub fn set(&mut self, x: i64, y: i64) {
        if x >= 0 && y >= 0 && x < self.width as i64 && y < self.height as i64 {
            self.bits[y as usize * self.width + x as usize] = true;
        }
    }

    /// Number of set pixels.
    pub fn count(&self) -> usize {
        self.bits.iter().filter(|&&b| b).count()
    }

    /// Draws a line `width` px thick from `a` to `b` (a disc stamped along it, as a tracker's
    /// thick line with round caps).
    pub fn thick_line(&mut self, a: (f64, f64), b: (f64, f64), width: f64) {
        let r = (width / 2.0).max(0.5);
        let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        let steps = (len * 2.0).ceil().max(1.0) as usize;
        let ri = r.ceil() as i64;
        for k in 0..=steps {
            let t = k as f64 / steps as f64;
            let (cx, cy) = (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t);
            for dy in -ri..=ri {
                for dx in -ri..=ri {
                    let (x, y) = (cx.round() as i64 + dx, cy.round() as i64 + dy);
                    let (ex, ey) = (x as f64 - cx, y as f64 - cy);
                    if ex * ex + ey * ey <= r * r {
                        self.set(x, y);
                    }
                }
            }
        }
    }
}

/// The path mask of a snapshot and what could not be classified.
pub struct PathPixels {
    pub mask: Mask,
    /// Green-looking pixels that are not the path's exact colour.
    pub ambiguous: usize,
}

/// The tracker's path pixels (exact [`PATH_GREEN`]).
pub fn path_pixels(img: &Rgb8) -> PathPixels {
    let mut mask = Mask::new(img.width, img.height);
    let mut ambiguous = 0;
    for (i, &p) in img.pixels.iter().enumerate() {
        if p == PATH_GREEN {
            mask.bits[i] = true;
        } else if is_ambiguous_green(p) {
            ambiguous += 1;
        }
    }
    PathPixels { mask, ambiguous }
}

/// The robot marker the tracker drew: the centre and size of its blue ellipse, px.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Marker {
    pub x: f64,
    pub y: f64,
    /// Half the diagonal of the ellipse's bounding box: every marker pixel is within it.
    pub radius: f64,
    /// The ellipse's blue pixel count (a partly hidden marker has few).
    pub pixels: usize,
}

/// The tracker's marker: the bounding box of the blue pixels (the ellipse's outline is blue
/// wherever the path and digit do not cover it, so the box holds even when they do). `None`
/// without blue pixels, or with fewer than 50 (not the tracker's ellipse).
pub fn find_marker(img: &Rgb8) -> Option<Marker> {
    let (mut x0, mut y0, mut x1, mut y1, mut n) = (usize::MAX, usize::MAX, 0, 0, 0);
    for (i, &p) in img.pixels.iter().enumerate() {
        if p == MARKER_BLUE {
            let (x, y) = (i % img.width, i / img.width);
            x0 = x0.min(x);
            y0 = y0.min(y);
            x1 = x1.max(x);
            y1 = y1.max(y);
            n += 1;
        }
    }
    if n < 50 {
        return None;
    }
    // Two robots' markers would make a box far bigger than one robot (~40 px).
    if x1 - x0 > 120 || y1 - y0 > 120 {
        return None;
    }
    let (w, h) = ((x1 - x0) as f64, (y1 - y0) as f64);
    Some(Marker {
        x: (x0 + x1) as f64 / 2.0,
        y: (y0 + y1) as f64 / 2.0,
        radius: (w * w + h * h).sqrt() / 2.0,
        pixels: n,
    })
}

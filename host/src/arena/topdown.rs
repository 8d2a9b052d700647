//! Top-down pictures of the arena for trajectory plots: floor, walls, robots (disc, heading,
//! optional field of view), trails and event markers, on a [`Canvas`].
//!
//! The picture's axes are the arena's (see `world`): `x` to the right, `y` down, so headings
//! turn clockwise in the picture when the robot turns right.

use crate::canvas::{Canvas, Rgb};

use super::render::HFOV_DEG;
use super::world::{Arena, Pose, ROBOT_RADIUS_MM};

/// Canvas pixels around the arena.
const MARGIN: i32 = 12;
/// Extra space above for a title.
const TITLE_SPACE: i32 = 14;
const OUTSIDE: Rgb = [255, 255, 255];
const FLOOR: Rgb = [236, 236, 230];
const WALL: Rgb = [60, 60, 60];
const INK: Rgb = [20, 20, 20];

/// A top-down drawing of an arena.
#[derive(Debug, Clone)]
pub struct TopDown {
    canvas: Canvas,
    px_per_mm: f64,
    origin: (i32, i32),
}

impl TopDown {
    /// An empty arena drawn at `px_per_mm` (e.g. 0.5: the default arena is 600 x 450 px).
    pub fn new(arena: &Arena, px_per_mm: f64) -> Self {
        let k = if px_per_mm.is_finite() && px_per_mm > 0.0 {
            px_per_mm
        } else {
            0.5
        };
        let (w, h) = (
            (arena.size_x_mm * k).round() as i32,
            (arena.size_y_mm * k).round() as i32,
        );
        let origin = (MARGIN, MARGIN + TITLE_SPACE);
        let mut canvas = Canvas::new(
            (w + 2 * MARGIN) as usize,
            (h + 2 * MARGIN + TITLE_SPACE) as usize,
            OUTSIDE,
        );
        canvas.fill_rect(origin.0, origin.1, w, h, FLOOR);
        for t in 1..=3 {
            canvas.rect_outline(origin.0 - t, origin.1 - t, w + 2 * t, h + 2 * t, WALL);
        }
        TopDown {
            canvas,
            px_per_mm: k,
            origin,
        }
    }

    /// Canvas pixel of the arena point (x, y) mm.
    pub fn to_px(&self, x_mm: f64, y_mm: f64) -> (i32, i32) {
        (
            self.origin.0 + (x_mm * self.px_per_mm).round() as i32,
            self.origin.1 + (y_mm * self.px_per_mm).round() as i32,
        )
    }

    /// Writes `text` above the arena.
    pub fn title(&mut self, text: &str) {
        self.canvas.text(MARGIN, 3, text, INK, 1);
    }

    /// A polyline through `points` (mm).
    pub fn trail(&mut self, points: &[(f64, f64)], colour: Rgb) {
        for w in points.windows(2) {
            let (a, b) = (self.to_px(w[0].0, w[0].1), self.to_px(w[1].0, w[1].1));
            self.canvas.line(a.0, a.1, b.0, b.1, colour);
        }
    }

    /// A robot: filled disc of the body's size, dark outline, and a line from the centre to the
    /// front along the heading.
    pub fn robot(&mut self, pose: &Pose, colour: Rgb) {
        let (cx, cy) = self.to_px(pose.x_mm, pose.y_mm);
        let r = (ROBOT_RADIUS_MM * self.px_per_mm).max(2.0);
        let ri = r.ceil() as i32;
        for dy in -ri..=ri {
            for dx in -ri..=ri {
                let d = f64::from(dx).hypot(f64::from(dy));
                if d <= r {
                    let c = if d > r - 1.0 { INK } else { colour };
                    self.canvas.set(cx + dx, cy + dy, c);
                }
            }
        }
        let (fx, fy) = pose.offset(ROBOT_RADIUS_MM, 0.0);
        let (ex, ey) = self.to_px(fx, fy);
        self.canvas.line(cx, cy, ex, ey, INK);
    }

    /// The two edges of the camera's horizontal field, `length_mm` long, from the robot's centre.
    pub fn field_of_view(&mut self, pose: &Pose, length_mm: f64, colour: Rgb) {
        let (cx, cy) = self.to_px(pose.x_mm, pose.y_mm);
        for side in [-1.0, 1.0] {
            let a = (pose.heading_deg + side * HFOV_DEG / 2.0).to_radians();
            let (ex, ey) = self.to_px(
                pose.x_mm + length_mm * a.cos(),
                pose.y_mm + length_mm * a.sin(),
            );
            self.canvas.line(cx, cy, ex, ey, colour);
        }
    }

    /// An x-shaped marker at (x, y) mm (e.g. a collision).
    pub fn mark(&mut self, x_mm: f64, y_mm: f64, colour: Rgb) {
        let (x, y) = self.to_px(x_mm, y_mm);
        for d in -3..=3 {
            self.canvas.set(x + d, y + d, colour);
            self.canvas.set(x + d, y - d, colour);
        }
    }

    /// The canvas drawn so far.
    pub fn canvas(&self) -> &Canvas {
        &self.canvas
    }

    /// The finished picture.
    pub fn into_canvas(self) -> Canvas {
        self.canvas
    }
}

//! Top-down pictures of the arena for trajectory plots: floor, walls, robots (disc, heading,
//! optional field of view), trails and event markers, on a [`Canvas`].
//!
//! The picture's axes are the arena's (see `world`): `x` to the right, `y` down, so headings
//! turn clockwise in the picture when the robot turns right.

use crate::canvas::{Canvas, Rgb};

use super::render::HFOV_DEG;
use super::world::{Arena, Obstacle, Pose, World, ROBOT_RADIUS_MM};

/// Canvas pixels around the arena.
const MARGIN: i32 = 12;
/// Extra space above for a title.
const TITLE_SPACE: i32 = 14;
const OUTSIDE: Rgb = [255, 255, 255];
const FLOOR: Rgb = [236, 236, 230];
const WALL: Rgb = [60, 60, 60];
const INK: Rgb = [20, 20, 20];
const OBSTACLE: Rgb = [120, 120, 120];

/// What a [`TopDown`] draws, and so how it is finished.
#[derive(Debug, Clone)]
enum View {
    /// The whole arena, walls drawn, the title written straight above it.
    Arena,
    /// A close-up ([`TopDown::window`]), framed with its title when finished.
    Window {
        /// The title, drawn with the frame.
        title: String,
    },
}

/// A top-down drawing of an arena.
#[derive(Debug, Clone)]
pub struct TopDown {
    canvas: Canvas,
    px_per_mm: f64,
    origin: (i32, i32),
    /// The arena point drawn at `origin`, mm ((0, 0) for the whole arena).
    corner_mm: (f64, f64),
    view: View,
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
            corner_mm: (0.0, 0.0),
            view: View::Arena,
        }
    }

    /// `world`'s arena drawn at `px_per_mm` ([`TopDown::new`]) with its obstacles.
    pub fn of_world(world: &World, px_per_mm: f64) -> Self {
        let mut td = TopDown::new(&world.arena, px_per_mm);
        td.obstacles(&world.obstacles);
        td
    }

    /// A close-up of the arena's rectangle from `(x_mm, y_mm)` (its top left corner), `w_mm`
    /// x `h_mm`, at `px_per_mm`, framed by a thin line (not a wall): whatever is drawn
    /// outside the rectangle is clipped.
    pub fn window(x_mm: f64, y_mm: f64, w_mm: f64, h_mm: f64, px_per_mm: f64) -> Self {
        let k = if px_per_mm.is_finite() && px_per_mm > 0.0 {
            px_per_mm
        } else {
            1.0
        };
        // NaN and infinities become 1 mm (sizes) or 0 (the corner); at most 4096 px a side
        let size = |mm: f64| ((mm.max(1.0) * k).round() as usize).clamp(1, 4096);
        let finite = |v: f64| if v.is_finite() { v } else { 0.0 };
        TopDown {
            canvas: Canvas::new(size(w_mm), size(h_mm), FLOOR),
            px_per_mm: k,
            origin: (0, 0),
            corner_mm: (finite(x_mm), finite(y_mm)),
            view: View::Window {
                title: String::new(),
            },
        }
    }

    /// Canvas pixel of the arena point (x, y) mm.
    pub fn to_px(&self, x_mm: f64, y_mm: f64) -> (i32, i32) {
        (
            self.origin
                .0
                .saturating_add(((x_mm - self.corner_mm.0) * self.px_per_mm).round() as i32),
            self.origin
                .1
                .saturating_add(((y_mm - self.corner_mm.1) * self.px_per_mm).round() as i32),
        )
    }

    /// Writes `text` above the arena.
    pub fn title(&mut self, text: &str) {
        match &mut self.view {
            View::Window { title } => *title = text.to_string(),
            View::Arena => self.canvas.text(MARGIN, 3, text, INK, 1),
        }
    }

    /// A polyline through `points` (mm).
    pub fn trail(&mut self, points: &[(f64, f64)], colour: Rgb) {
        self.wide_trail(points, colour, 1);
    }

    /// A polyline through `points` (mm), `width_px` pixels wide (1–9; a square pen centred
    /// on the line).
    pub fn wide_trail(&mut self, points: &[(f64, f64)], colour: Rgb, width_px: i32) {
        let w = width_px.clamp(1, 9);
        let offsets = -(w - 1) / 2..=w / 2;
        for seg in points.windows(2) {
            let (a, b) = (
                self.to_px(seg[0].0, seg[0].1),
                self.to_px(seg[1].0, seg[1].1),
            );
            for dy in offsets.clone() {
                for dx in offsets.clone() {
                    self.canvas
                        .line(a.0 + dx, a.1 + dy, b.0 + dx, b.1 + dy, colour);
                }
            }
        }
    }

    /// A filled disc of radius `radius_mm` at (x, y) mm with a dark outline.
    fn disc(&mut self, x_mm: f64, y_mm: f64, radius_mm: f64, colour: Rgb) {
        let (cx, cy) = self.to_px(x_mm, y_mm);
        let r = (radius_mm * self.px_per_mm).max(2.0);
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
    }

    /// Static obstacles: grey discs of their size.
    pub fn obstacles(&mut self, obstacles: &[Obstacle]) {
        for o in obstacles {
            self.disc(o.x_mm, o.y_mm, o.radius_mm, OBSTACLE);
        }
    }

    /// A robot: filled disc of the body's size, dark outline, and a line from the centre to the
    /// front along the heading.
    pub fn robot(&mut self, pose: &Pose, colour: Rgb) {
        self.disc(pose.x_mm, pose.y_mm, ROBOT_RADIUS_MM, colour);
        let (cx, cy) = self.to_px(pose.x_mm, pose.y_mm);
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
        let View::Window { title } = self.view else {
            return self.canvas;
        };
        let (w, h) = (self.canvas.width, self.canvas.height);
        let mut c = Canvas::new(
            w + 2 * MARGIN as usize,
            h + (2 * MARGIN + TITLE_SPACE) as usize,
            OUTSIDE,
        );
        c.blit(&self.canvas, MARGIN, MARGIN + TITLE_SPACE);
        c.rect_outline(
            MARGIN - 1,
            MARGIN + TITLE_SPACE - 1,
            w as i32 + 2,
            h as i32 + 2,
            INK,
        );
        c.text(MARGIN, 3, &title, INK, 1);
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_window_draws_its_rectangle_only_inside_a_frame() {
        // 100 x 50 mm from (200, 300) at 2 px/mm: 200 x 100 px inside the margins
        let mut td = TopDown::window(200.0, 300.0, 100.0, 50.0, 2.0);
        assert_eq!(td.to_px(200.0, 300.0), (0, 0));
        assert_eq!(td.to_px(250.0, 310.0), (100, 20));
        td.title("close-up");
        // a line from inside to far outside the rectangle stops at its edge
        td.trail(&[(250.0, 325.0), (900.0, 325.0)], [255, 0, 0]);
        let c = td.into_canvas();
        assert_eq!(
            (c.width, c.height),
            (
                200 + 2 * MARGIN as usize,
                100 + (2 * MARGIN + TITLE_SPACE) as usize
            )
        );
        let (ox, oy) = (MARGIN, MARGIN + TITLE_SPACE);
        assert_eq!(c.get(ox + 150, oy + 50), Some([255, 0, 0]));
        assert_eq!(c.get(ox - 1, oy + 50), Some(INK), "the frame");
        assert_eq!(c.get(ox + 200 + 5, oy + 50), Some(OUTSIDE), "clipped");
        assert_eq!(c.get(ox + 10, oy + 10), Some(FLOOR));
    }

    #[test]
    fn a_wide_trail_covers_its_width() {
        let mut td = TopDown::window(0.0, 0.0, 20.0, 20.0, 1.0);
        td.wide_trail(&[(2.0, 10.0), (18.0, 10.0)], [0, 0, 255], 3);
        td.trail(&[(2.0, 3.0), (18.0, 3.0)], [255, 0, 0]);
        let c = td.into_canvas();
        let (ox, oy) = (MARGIN, MARGIN + TITLE_SPACE);
        let blue = |y| c.get(ox + 10, oy + y) == Some([0, 0, 255]);
        assert_eq!(
            (blue(8), blue(9), blue(10), blue(11), blue(12)),
            (false, true, true, true, false)
        );
        let red = |y| c.get(ox + 10, oy + y) == Some([255, 0, 0]);
        assert_eq!((red(2), red(3), red(4)), (false, true, false));
    }
}

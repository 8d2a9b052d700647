//! Built-in synthetic scenes for the demo: squares that approach (expand), recede or translate
//! over a textured background, rendered with area coverage so sub-pixel motion is smooth.

use alvs_tasks::{Frame, HEIGHT, PIXELS, WIDTH};

/// A square object in the scene.
#[derive(Debug, Clone, Copy)]
pub struct Square {
    /// Centre column at t = 0.
    pub x: f32,
    /// Centre row.
    pub y: f32,
    /// Half side at t = 0, pixels.
    pub half: f32,
    /// Growth of the half side per frame (negative: receding).
    pub grow: f32,
    /// Horizontal speed, pixels per frame.
    pub vx: f32,
    /// Grey level.
    pub grey: u8,
}

/// A named scene.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Name used for files.
    pub name: &'static str,
    /// What a looming detector should do.
    pub looming: bool,
    /// Objects.
    pub squares: Vec<Square>,
    /// Frames to render.
    pub frames: u32,
}

impl Scene {
    /// Renders frame `t`: a soft vertical-stripe texture with the squares painted over it.
    pub fn render(&self, t: u32) -> Frame {
        let mut f = [0u8; PIXELS];
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                let tex =
                    170.0 + 25.0 * ((x as f32) * 0.35).sin() + 10.0 * ((y as f32) * 0.5).cos();
                f[y * WIDTH + x] = tex as u8;
            }
        }
        for s in &self.squares {
            let t = t as f32;
            let half = (s.half + s.grow * t).max(0.0);
            let cx = s.x + s.vx * t;
            let (x0, x1, y0, y1) = (cx - half, cx + half, s.y - half, s.y + half);
            for y in 0..HEIGHT {
                let cy = overlap(y as f32, y0, y1);
                if cy <= 0.0 {
                    continue;
                }
                for x in 0..WIDTH {
                    let a = cy * overlap(x as f32, x0, x1);
                    if a > 0.0 {
                        let p = &mut f[y * WIDTH + x];
                        *p = (f32::from(*p) * (1.0 - a) + f32::from(s.grey) * a).round() as u8;
                    }
                }
            }
        }
        f
    }

    /// All frames.
    pub fn frames(&self) -> Vec<Frame> {
        (0..self.frames).map(|t| self.render(t)).collect()
    }
}

/// Length of `[p, p+1) ∩ [a, b)`.
fn overlap(p: f32, a: f32, b: f32) -> f32 {
    (b.min(p + 1.0) - a.max(p)).clamp(0.0, 1.0)
}

fn sq(x: f32, y: f32, half: f32, grow: f32, vx: f32, grey: u8) -> Square {
    Square {
        x,
        y,
        half,
        grow,
        vx,
        grey,
    }
}

/// The demo's scenes (paper Fig. 3's five patterns, plus left/right approaches).
pub fn demo_scenes() -> Vec<Scene> {
    let s = |name, looming, squares| Scene {
        name,
        looming,
        squares,
        frames: 40,
    };
    vec![
        s(
            "approach_centre",
            true,
            vec![sq(49.0, 36.0, 2.0, 0.8, 0.0, 20)],
        ),
        s(
            "approach_left",
            true,
            vec![sq(20.0, 36.0, 2.0, 0.8, 0.0, 20)],
        ),
        s(
            "approach_right",
            true,
            vec![sq(79.0, 36.0, 2.0, 0.8, 0.0, 20)],
        ),
        s("recede", false, vec![sq(49.0, 36.0, 30.0, -0.8, 0.0, 20)]),
        s("translate", false, vec![sq(10.0, 36.0, 8.0, 0.0, 1.5, 20)]),
        s(
            "double_approach",
            true,
            vec![
                sq(15.0, 30.0, 2.0, 0.9, 0.0, 20),
                sq(83.0, 40.0, 2.0, 0.4, 0.0, 20),
            ],
        ),
        s(
            "triple_approach",
            true,
            vec![
                sq(14.0, 16.0, 2.0, 0.6, 0.0, 20),
                sq(84.0, 16.0, 2.0, 0.6, 0.0, 20),
                sq(49.0, 58.0, 2.0, 0.6, 0.0, 20),
            ],
        ),
    ]
}

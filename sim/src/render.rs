//! Each robot's front camera: a 99x72 grey [`Frame`] of the arena rendered by per-column ray
//! casting, the same frames the firmware's camera task hands to the model.
//!
//! # Camera model
//!
//! A pinhole camera [`CAMERA_FORWARD_MM`] ahead of the body's centre and [`CAMERA_HEIGHT_MM`]
//! above the floor, looking along the heading, optical axis level (the default
//! [`CameraMount`]; the robustness suite raises, lowers and tilts it). Pixels are square; column
//! `c` (0 = left) and row `y` (0 = top) are centred on the image points `c` and `y`, the axis
//! passes through ([`CENTRE_COLUMN`], [`CENTRE_ROW`]) = (49, 35.5). The focal length
//! [`FOCAL_PX`] = 49 / tan 35° puts the centres of the outermost columns at ±35°: a 70°
//! horizontal field (docs/hardware.md; ≈ 54° vertically). A point at bearing β (positive = right)
//! and height `z` at axial depth `s` (distance along the optical axis) is imaged at
//!
//! ```text
//! column = 49 + f · tan β          row = 35.5 − f · (z − CAMERA_HEIGHT_MM) / s
//! ```
//!
//! which is what [`column_of_bearing`] computes. A camera pitched up by `p`
//! ([`CameraMount::pitch_deg`]) is rendered as the level camera with its image shifted down by
//! `f · tan p` rows: the horizon lands exactly on [`CameraMount::horizon_row`]; what this leaves
//! out, the perspective's second-order terms, is under 0.7 px at the frame's top and bottom
//! rows for ±2° (`tan(e − p)` against `tan e − tan p` at the ±27° edges), and the keystone
//! (verticals leaning by `p · tan β`, under 0.8 px over the frame's corners) is left out as
//! every column casts one ray. Each column casts one ray through its centre;
//! along it the parameter is the axial depth, so the vertical extent of whatever the ray hits
//! comes straight from the formula above (a wall seen square-on is a horizontal band, no
//! fish-eye). Edges are anti-aliased: robots cover the columns between their silhouette
//! tangents with exact fractional coverage, and every vertical boundary (wall top, wall base,
//! robot top and bottom) covers its row fractionally, so sub-pixel motion changes the picture
//! smoothly instead of in whole-pixel jumps.
//!
//! # What is drawn
//!
//! Above the walls the bright lab ([`SKY_GREY`]); the walls with their texture
//! ([`super::texture`]), each side slightly differently lit ([`WALL_SIDE_SHADE`]) so corners
//! show; the floor as a grey gradient by distance ([`FLOOR_NEAR_GREY`] → [`FLOOR_FAR_GREY`],
//! static in the image since it has no texture), optionally times a pattern fixed to the floor
//! ([`super::floor_pattern`]) and a lighting gradient ([`super::lighting`]) on everything lit in
//! the arena ([`RenderOptions`]); robots as cylinders with their
//! [`RobotPattern`], Lambert-shaded (`AMBIENT + (1 − AMBIENT) cos i`, so their flanks are
//! darker), drawn far to near per column so nearer robots occlude farther ones. The viewer's own
//! body is behind its camera. Optionally the light is integrated over an exposure (the mean of
//! [`EXPOSURE_SAMPLES`] views along the bodies' motion during the end of the frame period, so
//! what moves is blurred); then, optionally, a global gain (per-frame flicker) and additive
//! pixel noise ([`SensorNoise`]), from the camera's own seeded stream.
//!
//! # Cost
//!
//! Nothing is allocated per frame (the per-frame lists live in the [`Camera`] and keep their
//! capacity); ray directions per column, the floor per row and the wall texture pyramid are
//! precomputed by [`Renderer::new`].

use alvs_tasks::{Frame, HEIGHT, PIXELS, WIDTH};

use crate::aec::Aec;
use crate::canvas::Canvas;

use super::floor_pattern::{FloorMap, FloorPattern};
use super::lighting::LightGradient;
use super::rng::Rng;
use super::texture::WallMap;
use super::world::{
    Arena, Obstacle, Pose, RobotPattern, Room, World, ROBOT_HEIGHT_MM, ROBOT_RADIUS_MM,
};

/// Height of the camera's optical axis above the floor, mm: the lens sits on the sense board,
/// a few mm below the top of the 28 mm body.
pub const CAMERA_HEIGHT_MM: f64 = 20.0;
/// Distance of the camera ahead of the body's centre, mm: 2 mm behind the front of the shell,
/// so that the camera stays outside any other body and in front of walls the body touches.
pub const CAMERA_FORWARD_MM: f64 = ROBOT_RADIUS_MM - 2.0;
/// Horizontal field of view between the centres of the outermost columns, degrees.
pub const HFOV_DEG: f64 = 70.0;
/// Focal length in pixels, `49 / tan 35°`.
pub const FOCAL_PX: f64 = 69.979_252_330_363_62;
/// Image column of the optical axis.
pub const CENTRE_COLUMN: f64 = 49.0;
/// Image row of the optical axis (between rows 35 and 36).
pub const CENTRE_ROW: f64 = 35.5;

/// Grey of what is seen above the walls (a bright lab ceiling).
pub const SKY_GREY: f32 = 215.0;
/// Grey of the floor just in front of the camera.
pub const FLOOR_NEAR_GREY: f32 = 95.0;
/// Grey the floor tends to far away (grazing view).
pub const FLOOR_FAR_GREY: f32 = 150.0;
/// Distance over which the floor brightens from near to far grey, mm (exponential).
pub const FLOOR_FADE_MM: f32 = 300.0;
/// Brightness of the walls at `y = 0`, `x = size_x`, `y = size_y`, `x = 0` (light from one side).
pub const WALL_SIDE_SHADE: [f32; 4] = [1.0, 0.92, 0.84, 0.92];
/// Ambient share of a robot's Lambert shading.
pub const ROBOT_AMBIENT: f32 = 0.55;

/// The image column at which a point at `bearing_deg` (positive = right) appears:
/// `49 + f·tan β` (pinhole model).
pub fn column_of_bearing(bearing_deg: f64) -> f64 {
    CENTRE_COLUMN + FOCAL_PX * bearing_deg.to_radians().tan()
}

/// The bearing of image column `column` (inverse of [`column_of_bearing`]), degrees.
pub fn bearing_of_column(column: f64) -> f64 {
    ((column - CENTRE_COLUMN) / FOCAL_PX).atan().to_degrees()
}

/// The image row at which a point `height_mm` above the floor at axial depth `depth_mm`
/// appears.
pub fn row_of_height(height_mm: f64, depth_mm: f64) -> f64 {
    CENTRE_ROW - FOCAL_PX * (height_mm - CAMERA_HEIGHT_MM) / depth_mm
}

/// A frame as a grey picture, each pixel `scale` x `scale` canvas pixels (0 counts as 1).
pub fn frame_canvas(frame: &Frame, scale: usize) -> Canvas {
    let k = scale.max(1);
    let mut c = Canvas::new(WIDTH * k, HEIGHT * k, [0; 3]);
    for (i, px) in c.pixels.iter_mut().enumerate() {
        let (x, y) = ((i % (WIDTH * k)) / k, i / (WIDTH * k) / k);
        *px = [frame[y * WIDTH + x]; 3];
    }
    c
}

/// Where the camera sits on the body. The default is the camera the model assumes (a host test
/// holds it to `floor::CAMERA_HEIGHT_MM` and the horizon at row 35.5); the robustness suite
/// moves it (docs/robustness.md).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraMount {
    /// Height of the optical centre above the floor, mm.
    pub height_mm: f64,
    /// Tilt of the optical axis, degrees, positive = up (the horizon moves down the image).
    pub pitch_deg: f64,
}

impl Default for CameraMount {
    /// [`CAMERA_HEIGHT_MM`], level.
    fn default() -> Self {
        CameraMount {
            height_mm: CAMERA_HEIGHT_MM,
            pitch_deg: 0.0,
        }
    }
}

impl CameraMount {
    /// Most pitch accepted, degrees: the shifted-image rendering (module documentation) is a
    /// small-angle one.
    pub const MAX_PITCH_DEG: f64 = 10.0;

    /// The image row of the horizon: [`CENTRE_ROW`] `+ f · tan p`.
    pub fn horizon_row(&self) -> f64 {
        CENTRE_ROW + FOCAL_PX * self.pitch_deg.to_radians().tan()
    }

    /// The image row at which a point `height_mm` above the floor at axial depth `depth_mm`
    /// appears ([`row_of_height`] for this mount).
    pub fn row_of_height(&self, height_mm: f64, depth_mm: f64) -> f64 {
        self.horizon_row() - FOCAL_PX * (height_mm - self.height_mm) / depth_mm
    }

    /// Checks the mount (one line): a height above the floor and below the walls' usual
    /// reach, a small pitch.
    pub fn check(&self) -> anyhow::Result<()> {
        anyhow::ensure!(
            self.height_mm.is_finite() && self.height_mm > 0.0 && self.height_mm <= 100.0,
            "camera height must be in (0, 100] mm, got {}",
            self.height_mm
        );
        anyhow::ensure!(
            self.pitch_deg.is_finite() && self.pitch_deg.abs() <= Self::MAX_PITCH_DEG,
            "camera pitch must be within ±{} degrees, got {}",
            Self::MAX_PITCH_DEG,
            self.pitch_deg
        );
        Ok(())
    }
}

/// How a [`Renderer`] draws a world beyond the world itself: the camera's mount, and the
/// robustness suite's floor pattern and lighting gradient. The default draws exactly what
/// [`Renderer::new`] always drew.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RenderOptions {
    /// Where the camera sits.
    pub mount: CameraMount,
    /// A pattern fixed to the floor, on top of its [`super::FloorShade`].
    pub floor_pattern: Option<FloorPattern>,
    /// Uneven light across the arena.
    pub lighting: Option<LightGradient>,
}

impl RenderOptions {
    /// Checks every part (one line).
    pub fn check(&self) -> anyhow::Result<()> {
        self.mount.check()?;
        if let Some(p) = &self.floor_pattern {
            p.check()?;
        }
        if let Some(l) = &self.lighting {
            l.check()?;
        }
        Ok(())
    }
}

/// Sensor imperfections of a [`Camera`]. Both zero (the default) gives the ideal camera.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SensorNoise {
    /// Standard deviation of the additive pixel noise, grey levels (independent per pixel and
    /// frame).
    pub pixel_sigma: f32,
    /// Standard deviation of the global gain, relative (one independent draw per frame:
    /// [`GainModel::Clips`](crate::GainModel::Clips), [`GainModel::Jitter`](crate::GainModel::Jitter)).
    pub gain_sigma: f32,
    /// The sensor's automatic exposure and gain ([`Aec`], the
    /// [`GainModel::Aec`](crate::GainModel::Aec)), on top of `gain_sigma`; `None`: the exposure
    /// holds.
    pub aec: Option<Aec>,
    /// Exposure time as a fraction of the frame period, 0..=1 (0 = an instantaneous snapshot):
    /// the picture is the mean of [`EXPOSURE_SAMPLES`] views along the bodies' straight-line
    /// motion over the last `exposure · 33 ms` of the frame, so what moves while the shutter
    /// is open is smeared. An OV7670 under lab light exposes for most of the frame period
    /// (`docs/notes/2026-11-27-closed-loop-mechanisms.md`, "Camera exposure"); 0 keeps the
    /// snapshots every figure was measured with.
    pub exposure: f32,
    /// Standard deviation of the camera's pitch jitter while its body moves, degrees (one
    /// independent draw per frame): a 4 cm robot rocks on its axle and caster as its
    /// gearmotors drive it over the floor, and a body pressed against a wall rattles. The
    /// picture shifts vertically by `FOCAL_PX · tan δ` rows (the small-angle image of a
    /// pitch). A body that neither moved nor turned over the frame does not shake. 0 = a
    /// rigidly steady camera.
    pub shake_deg: f32,
}

/// Views averaged over an exposure (see [`SensorNoise::exposure`]): at a 360°/s turn a
/// whole-period exposure sweeps 17 columns, so 4 views leave steps of about 4 columns, which
/// the correlators see as a blur, not as separate images; more cost rendering time.
pub const EXPOSURE_SAMPLES: usize = 4;

impl SensorNoise {
    /// The worlds' camera: 2 grey levels of pixel noise, and the global gain's frame-to-frame
    /// change that real cameras' frames measure, 0.3 % ([`GainModel::Clips`](crate::GainModel::Clips),
    /// [`CLIPS_GAIN_SIGMA`](crate::aec::CLIPS_GAIN_SIGMA)).
    pub fn typical() -> Self {
        SensorNoise {
            pixel_sigma: 2.0,
            gain_sigma: crate::aec::CLIPS_GAIN_SIGMA,
            aec: None,
            exposure: 0.0,
            shake_deg: 0.0,
        }
    }
}

/// Everything about a world the cameras need, precomputed (textures as look-up tables, ray
/// directions, floor shading). Immutable: one renderer serves every camera.
#[derive(Debug, Clone)]
pub struct Renderer {
    arena: Arena,
    wall_h: f32,
    map: WallMap,
    pattern: RobotPattern,
    obstacles: Vec<Obstacle>,
    obstacle_pattern: RobotPattern,
    room: Option<RoomMap>,
    /// `tan β` of each column's ray.
    col_tan: [f32; WIDTH],
    /// Floor grey of each row.
    floor: [f32; HEIGHT],
    /// Row of the horizon ([`CameraMount::horizon_row`]).
    horizon: f32,
    /// Height of the camera, mm.
    cam_h: f32,
    /// Axial depth of the floor each row sees, mm (infinite at and above the horizon).
    floor_depth: [f32; HEIGHT],
    floor_map: Option<FloorMap>,
    lighting: Option<LightGradient>,
}

/// The room around the arena, precomputed: its texture pyramid at [`Room::SCALE`] times the
/// texel size, its walls' rectangle (arena coordinates) and height.
#[derive(Debug, Clone)]
struct RoomMap {
    map: WallMap,
    margin: f32,
    height: f32,
}

/// Another robot, or an obstacle, as one camera sees it this frame.
#[derive(Debug, Clone, Copy)]
struct View {
    /// Camera minus the body's centre, mm (world axes).
    qx: f32,
    qy: f32,
    /// |q|² − R².
    c: f32,
    heading_rad: f32,
    /// Columns of the silhouette's left and right tangents.
    c_l: f32,
    c_r: f32,
    /// Radius and height of the body, mm.
    radius: f32,
    height: f32,
    pattern: RobotPattern,
    /// The light where it stands ([`LightGradient::gain`], 1 without a gradient).
    light: f32,
}

/// A robot in one column.
#[derive(Debug, Clone, Copy)]
struct Hit {
    /// Axial depth, mm.
    s: f32,
    /// Horizontal coverage of the pixel column, 0..=1.
    cov: f32,
    /// Grey before the vertical pattern (Lambert shade times stripes), or the shade alone for a
    /// banded body.
    grey: f32,
    shade: f32,
    height: f32,
    pattern: RobotPattern,
}

/// One robot's camera: its noise and its reusable per-frame lists.
#[derive(Debug, Clone)]
pub struct Camera {
    noise: SensorNoise,
    rng: Rng,
    views: Vec<View>,
    hits: Vec<Hit>,
    /// The exposure's light, row-major.
    light: Vec<f32>,
    /// The bodies at one instant of the exposure.
    poses: Vec<Pose>,
    /// The light shifted by the shake.
    shaken: Vec<f32>,
    /// The exposure [`SensorNoise::aec`] has set for the next frame, relative to the first.
    aec_gain: f32,
    /// The centre of the AEC's stable region: the first frame's mean grey.
    aec_centre: Option<f32>,
}

impl Camera {
    /// A camera with `noise`, drawing from the stream `seed`.
    pub fn new(noise: SensorNoise, seed: u64) -> Self {
        Camera {
            noise,
            rng: Rng::new(seed),
            views: Vec::new(),
            hits: Vec::new(),
            light: vec![0.0; PIXELS],
            poses: Vec::new(),
            shaken: vec![0.0; PIXELS],
            aec_gain: 1.0,
            aec_centre: None,
        }
    }

    /// The ideal camera: no noise, no flicker.
    pub fn ideal() -> Self {
        Camera::new(SensorNoise::default(), 0)
    }

    /// The camera's noise settings.
    pub fn noise(&self) -> SensorNoise {
        self.noise
    }

    /// Renders what the camera of `bodies[viewer]` sees, with this camera's noise, into
    /// `frame`, the bodies standing still. Every other body is drawn as a robot.
    /// Allocation-free once the camera has seen as many robots as `bodies` holds. Panics if
    /// `viewer` is not an index of `bodies`.
    pub fn capture(
        &mut self,
        renderer: &Renderer,
        bodies: &[Pose],
        viewer: usize,
        frame: &mut Frame,
    ) {
        self.capture_moving(renderer, bodies, bodies, viewer, frame);
    }

    /// As [`Camera::capture`], the bodies having moved from `before` (one frame period ago)
    /// to `bodies` (now): with an [`SensorNoise::exposure`], the picture integrates their
    /// motion over the end of that period. If `before` does not list as many bodies, the
    /// snapshot at `bodies` is taken.
    pub fn capture_moving(
        &mut self,
        renderer: &Renderer,
        before: &[Pose],
        bodies: &[Pose],
        viewer: usize,
        frame: &mut Frame,
    ) {
        let gain = if self.noise.gain_sigma > 0.0 {
            (1.0 + self.noise.gain_sigma * self.rng.normal()).max(0.0)
        } else {
            1.0
        } * self.aec_gain;
        let noise = (self.noise.pixel_sigma > 0.0).then_some(self.noise.pixel_sigma);
        self.light.fill(0.0);
        let e = self.noise.exposure.clamp(0.0, 1.0);
        // a snapshot is one instant (the end of the period) of weight 1
        let instants = if e > 0.0 && before.len() == bodies.len() && before != bodies {
            EXPOSURE_SAMPLES
        } else {
            1
        };
        for k in 0..instants {
            let at: &[Pose] = if instants == 1 {
                bodies
            } else {
                // instants spread evenly over the last `e` of the frame period
                let t = 1.0 - f64::from(e) * (k as f64 + 0.5) / instants as f64;
                self.poses.clear();
                self.poses
                    .extend(before.iter().zip(bodies).map(|(a, b)| a.lerp(b, t)));
                &self.poses
            };
            renderer.scene(
                at,
                viewer,
                &mut self.views,
                &mut self.hits,
                &mut self.light,
                1.0 / instants as f32,
            );
        }
        // only a shaking camera needs to know whether its body moved
        let moved = || {
            before
                .get(viewer)
                .zip(bodies.get(viewer))
                .is_some_and(|(a, b)| a != b)
        };
        let light = if self.noise.shake_deg > 0.0 && moved() {
            let pitch = f64::from(self.noise.shake_deg * self.rng.normal()).to_radians();
            shift_rows(&self.light, FOCAL_PX * pitch.tan(), &mut self.shaken);
            &self.shaken
        } else {
            &self.light
        };
        if let Some(aec) = self.noise.aec {
            // the sensor's YAVG: the mean of the clipped picture, before the pixel noise (whose
            // mean is 0); the step applies from the next frame
            let mean = light.iter().map(|&l| (l * gain).min(255.0)).sum::<f32>() / PIXELS as f32;
            let centre = *self.aec_centre.get_or_insert(mean);
            // bounded only so that a view that stays black or white cannot run it to 0 or ∞
            self.aec_gain = (self.aec_gain * aec.next(mean, centre)).clamp(1.0 / 64.0, 64.0);
        }
        Renderer::sensor(light, gain, noise.map(|s| (s, &mut self.rng)), frame);
    }
}

/// `light` moved down by `rows` (negative: up; fractional rows interpolated linearly, the
/// edge rows repeated beyond the picture) into `out`: the image of a small camera pitch.
fn shift_rows(light: &[f32], rows: f64, out: &mut [f32]) {
    let last = HEIGHT as f64 - 1.0;
    for y in 0..HEIGHT {
        let src = (y as f64 - rows).clamp(0.0, last);
        let (y0, t) = (src.floor() as usize, (src - src.floor()) as f32);
        let y1 = (y0 + 1).min(HEIGHT - 1);
        let (a, b) = (&light[y0 * WIDTH..][..WIDTH], &light[y1 * WIDTH..][..WIDTH]);
        for ((o, &p), &q) in out[y * WIDTH..][..WIDTH].iter_mut().zip(a).zip(b) {
            *o = p + (q - p) * t;
        }
    }
}

impl Renderer {
    /// Precomputes `world` for rendering (a few ms: the texture pyramid).
    pub fn new(world: &World) -> Self {
        Renderer::with_options(world, &RenderOptions::default())
    }

    /// Precomputes `world` for rendering as `options` say (unchecked: see
    /// [`RenderOptions::check`]).
    pub fn with_options(world: &World, options: &RenderOptions) -> Self {
        let f = FOCAL_PX as f32;
        let col_tan = std::array::from_fn(|c| (c as f32 - CENTRE_COLUMN as f32) / f);
        let (near, far) = (world.floor.near_grey, world.floor.far_grey);
        let horizon = options.mount.horizon_row() as f32;
        let cam_h = options.mount.height_mm as f32;
        let floor_depth: [f32; HEIGHT] = std::array::from_fn(|y| {
            let below = y as f32 - horizon;
            if below <= 0.0 {
                f32::INFINITY
            } else {
                f * cam_h / below
            }
        });
        let floor = std::array::from_fn(|y| {
            let s = floor_depth[y];
            if s.is_infinite() {
                far
            } else {
                far + (near - far) * (-s / FLOOR_FADE_MM).exp()
            }
        });
        Renderer {
            horizon,
            cam_h,
            floor_depth,
            floor_map: options
                .floor_pattern
                .map(|p| FloorMap::new(&p, &world.arena)),
            lighting: options.lighting,
            arena: world.arena,
            wall_h: world.wall_height_mm as f32,
            map: WallMap::new(world),
            pattern: world.robot_pattern,
            obstacles: world.obstacles.clone(),
            obstacle_pattern: world.obstacle_pattern,
            room: world.room.as_ref().map(|room| {
                let k = Room::SCALE;
                let a = world.arena;
                let m = room.margin_mm.max(0.0);
                // The room's texture stored at k mm texels: a world 1/k its size.
                let scaled = World {
                    arena: Arena::new((a.size_x_mm + 2.0 * m) / k, (a.size_y_mm + 2.0 * m) / k),
                    wall_height_mm: room.height_mm / k,
                    texture: room.texture.clone(),
                    ..World::default()
                };
                RoomMap {
                    map: WallMap::new(&scaled),
                    margin: m as f32,
                    height: room.height_mm as f32,
                }
            }),
            col_tan,
            floor,
        }
    }

    /// The light at `x_mm` ([`LightGradient::gain`]; 1 without a gradient).
    fn light_at(&self, x_mm: f32) -> f32 {
        self.lighting.map_or(1.0, |l| l.gain(&self.arena, x_mm))
    }

    /// The floor's grey down one column whose ray runs along (`rx`, `ry`) per mm of axial depth
    /// from the camera at (`cx`, `cy`), from row `from` down, with the floor pattern and the
    /// lighting; rows above `from` keep the plain floor.
    fn floor_column(&self, cam: (f32, f32), ray: (f32, f32), from: usize, out: &mut [f32; HEIGHT]) {
        out.copy_from_slice(&self.floor);
        let f = FOCAL_PX as f32;
        let reach = (ray.0 * ray.0 + ray.1 * ray.1).sqrt();
        let view = (ray.0 / reach, ray.1 / reach);
        for (g, &s) in out.iter_mut().zip(&self.floor_depth).skip(from) {
            if !s.is_finite() {
                continue;
            }
            let (x, y) = (cam.0 + s * ray.0, cam.1 + s * ray.1);
            *g *= self.light_at(x);
            if let Some(map) = &self.floor_map {
                // the pixel's patch of floor: s/f across, s²/(f·h) along the grazing view
                let (across, along) = (s * reach / f, s * s * reach / (f * self.cam_h));
                *g *= map.factor((x, y), view, across, along);
            }
        }
    }

    /// The arena rendered.
    pub fn arena(&self) -> Arena {
        self.arena
    }

    /// The wall texture pyramid.
    pub fn wall_map(&self) -> &WallMap {
        &self.map
    }

    /// The ideal camera's view from `bodies[viewer]` (convenience for tests and pictures; a
    /// simulation keeps a [`Camera`] per robot instead).
    pub fn render(&self, bodies: &[Pose], viewer: usize) -> Frame {
        let mut frame = [0u8; PIXELS];
        Camera::ideal().capture(self, bodies, viewer, &mut frame);
        frame
    }

    /// Adds `weight` times the light of the view from `bodies[viewer]` to `acc` (row-major,
    /// grey levels).
    fn scene(
        &self,
        bodies: &[Pose],
        viewer: usize,
        views: &mut Vec<View>,
        hits: &mut Vec<Hit>,
        acc: &mut [f32],
        weight: f32,
    ) {
        let eye = bodies[viewer];
        let (fx, fy) = eye.forward();
        let (cx, cy) = eye.offset(CAMERA_FORWARD_MM, 0.0);
        let (rx_, ry_) = (-fy, fx);
        let f = FOCAL_PX as f32;
        let ch = self.cam_h;
        // the horizon's row: the optical axis' row, moved by the pitch
        let centre_row = self.horizon;

        // The other robots' and the obstacles' silhouettes.
        views.clear();
        let robots = bodies
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != viewer)
            .map(|(_, b)| (*b, ROBOT_RADIUS_MM, ROBOT_HEIGHT_MM, self.pattern));
        let obstacles = self.obstacles.iter().map(|o| {
            (
                Pose::new(o.x_mm, o.y_mm, 0.0),
                o.radius_mm,
                o.height_mm,
                self.obstacle_pattern,
            )
        });
        for (b, radius, height, pattern) in robots.chain(obstacles) {
            let (dx, dy) = (b.x_mm - cx, b.y_mm - cy);
            let z = dx * fx + dy * fy;
            let x = dx * rx_ + dy * ry_;
            if z <= -radius {
                continue;
            }
            let dist = x.hypot(z);
            let delta = (radius / dist.max(1e-9)).min(1.0).asin();
            let beta = x.atan2(z);
            let (left, right) = (beta - delta, beta + delta);
            const EDGE: f64 = std::f64::consts::FRAC_PI_2 - 1e-4;
            if left >= EDGE || right <= -EDGE {
                continue;
            }
            let col = |a: f64| {
                if a <= -EDGE {
                    -1e9
                } else if a >= EDGE {
                    1e9
                } else {
                    CENTRE_COLUMN + FOCAL_PX * a.tan()
                }
            };
            let (c_l, c_r) = (col(left), col(right));
            if c_r <= -0.5 || c_l >= WIDTH as f64 - 0.5 {
                continue;
            }
            views.push(View {
                qx: -dx as f32,
                qy: -dy as f32,
                c: (dist * dist - radius * radius) as f32,
                heading_rad: b.heading_deg.to_radians() as f32,
                c_l: c_l as f32,
                c_r: c_r as f32,
                radius: radius as f32,
                height: height as f32,
                pattern,
                light: self.light_at(b.x_mm as f32),
            });
        }

        let (fx, fy, rx_, ry_) = (fx as f32, fy as f32, rx_ as f32, ry_ as f32);
        let (cx, cy) = (cx as f32, cy as f32);
        let (sx, sy) = (self.arena.size_x_mm as f32, self.arena.size_y_mm as f32);
        let mut col = [0f32; HEIGHT];
        for c in 0..WIDTH {
            let t = self.col_tan[c];
            let (rx, ry) = (fx + t * rx_, fy + t * ry_);
            let rr = 1.0 + t * t;

            // The wall this column's ray meets first.
            let (wx, sxh) = if rx > 1e-9 {
                (sx, (sx - cx) / rx)
            } else if rx < -1e-9 {
                (0.0, -cx / rx)
            } else {
                (0.0, f32::INFINITY)
            };
            let (wy, syh) = if ry > 1e-9 {
                (sy, (sy - cy) / ry)
            } else if ry < -1e-9 {
                (0.0, -cy / ry)
            } else {
                (0.0, f32::INFINITY)
            };
            // depth, wall coordinate, side, the ray's component across the wall, x of the hit
            let (s, u, side, normal, hit_x) = if sxh <= syh {
                let hy = (cy + sxh * ry).clamp(0.0, sy);
                if wx > 0.0 {
                    (sxh, sx + hy, 1, rx, sx)
                } else {
                    (sxh, 2.0 * sx + sy + (sy - hy), 3, rx, 0.0)
                }
            } else {
                let hx = (cx + syh * rx).clamp(0.0, sx);
                if wy > 0.0 {
                    (syh, sx + sy + (sx - hx), 2, ry, hx)
                } else {
                    (syh, hx, 0, ry, hx)
                }
            };
            let s = s.clamp(0.05, 1e7);
            let fp_v = s / f;
            let footprint = fp_v.max(fp_v / normal.abs().max(1e-3));
            let sampler = self.map.sampler(u, footprint);
            let shade = WALL_SIDE_SHADE[side] * self.light_at(hit_x);

            // Sky, wall, floor: rows [0, a) sky, (a, b) wall, (b, HEIGHT) floor; rows a and b
            // are shared.
            let y_top = centre_row - f * (self.wall_h - ch) / s;
            let y_base = centre_row + f * ch / s;
            let row_of = |yy: f32| ((yy + 0.5).floor().clamp(-1.0, HEIGHT as f32)) as i32;
            let (a, b) = (row_of(y_top), row_of(y_base));
            let a_cl = a.clamp(0, HEIGHT as i32) as usize;
            let b_cl = b.clamp(-1, HEIGHT as i32 - 1);
            // the floor down this column: the rows' greys, or with a pattern or lighting the
            // floor point each row sees
            let mut detailed = [0f32; HEIGHT];
            let floor = if self.floor_map.is_some() || self.lighting.is_some() {
                let from = b_cl.max(0) as usize;
                self.floor_column((cx, cy), (rx, ry), from, &mut detailed);
                &detailed
            } else {
                &self.floor
            };
            let wall_at = |y: usize| {
                let v = (ch + (centre_row - y as f32) * fp_v).clamp(0.0, self.wall_h);
                shade * sampler.at(v)
            };
            let room = self.room.as_ref().map(|r| {
                let (s, u) = rect_hit(
                    (cx, cy),
                    (rx, ry),
                    (-r.margin, -r.margin),
                    (sx + r.margin, sy + r.margin),
                );
                let k = Room::SCALE as f32;
                let fp = s / f;
                (r.map.sampler(u / k, fp / k), s, fp, r.height)
            });
            // What is seen above the walls at row y: the room's wall, or the ceiling.
            let above = |y: usize| match &room {
                Some((sampler, s, fp, h)) => {
                    let z = ch + (centre_row - y as f32) * fp;
                    let _ = s;
                    if z < *h {
                        sampler.at(z.max(0.0) / Room::SCALE as f32)
                    } else {
                        SKY_GREY
                    }
                }
                None => SKY_GREY,
            };
            let mixed = |y: usize| {
                let (lo, hi) = (y as f32 - 0.5, y as f32 + 0.5);
                let sky = (y_top - lo).clamp(0.0, 1.0);
                let fl = (hi - y_base).clamp(0.0, 1.0);
                let wall = (1.0 - sky - fl).max(0.0);
                let mut g = sky * above(y) + fl * floor[y];
                if wall > 0.0 {
                    g += wall * wall_at(y);
                }
                g
            };
            if room.is_some() {
                for (y, g) in col[..a_cl].iter_mut().enumerate() {
                    *g = above(y);
                }
            } else {
                col[..a_cl].fill(SKY_GREY);
            }
            if a_cl < HEIGHT {
                col[a_cl] = mixed(a_cl);
            }
            let first_wall = a_cl + 1;
            let last_wall = b_cl.max(0) as usize; // exclusive
            if first_wall < last_wall {
                let v = ch + (centre_row - first_wall as f32) * fp_v;
                sampler.fill(&mut col[first_wall..last_wall], v, fp_v, shade);
            }
            if b_cl >= 0 && b_cl as usize != a_cl {
                col[b_cl as usize] = mixed(b_cl as usize);
            }
            let floor_from = (b_cl + 1).max(a_cl as i32 + 1).max(0) as usize;
            if floor_from < HEIGHT {
                col[floor_from..].copy_from_slice(&floor[floor_from..]);
            }

            // Robots in this column, far to near.
            hits.clear();
            let (lo, hi) = (c as f32 - 0.5, c as f32 + 0.5);
            for v in views.iter() {
                let cov = hi.min(v.c_r) - lo.max(v.c_l);
                if cov <= 0.0 {
                    continue;
                }
                let bq = rx * v.qx + ry * v.qy;
                let disc = bq * bq - rr * v.c;
                let s = if disc >= 0.0 {
                    (-bq - disc.sqrt()) / rr
                } else {
                    // The column's centre ray misses (edge column): closest approach.
                    -bq / rr
                };
                let s = s.max(0.05);
                let (nx, ny) = (v.qx + s * rx, v.qy + s * ry);
                let n = (nx * nx + ny * ny).sqrt().max(1e-6);
                let cos_i = (-(nx * rx + ny * ry) / (n * rr.sqrt())).clamp(0.0, 1.0);
                let shade = (ROBOT_AMBIENT + (1.0 - ROBOT_AMBIENT) * cos_i) * v.light;
                let grey = match v.pattern {
                    RobotPattern::Stripes { count, dark, light } => {
                        let (dark, light) = (f32::from(dark), f32::from(light));
                        let k = f32::from(count);
                        let phi = ny.atan2(nx) - v.heading_rad;
                        // Phase advance of cos(kφ) per pixel: sharp square stripes up close,
                        // fading to their mean when a pixel spans a stripe.
                        let w = k * (s / f) / v.radius / cos_i.max(0.15);
                        let sharp = (std::f32::consts::FRAC_PI_2 / w.max(1e-3)).clamp(1.0, 12.0);
                        let fade = (1.0 - w / std::f32::consts::PI).max(0.0);
                        let g = ((k * phi).cos() * sharp).clamp(-1.0, 1.0) * fade;
                        0.5 * (dark + light) + 0.5 * (light - dark) * g
                    }
                    RobotPattern::Band { .. } => 1.0,
                };
                hits.push(Hit {
                    s,
                    cov: cov.min(1.0),
                    grey: shade * grey,
                    shade,
                    height: v.height,
                    pattern: v.pattern,
                });
            }
            if hits.len() > 1 {
                hits.sort_unstable_by(|p, q| q.s.total_cmp(&p.s));
            }
            for h in hits.iter() {
                let top = centre_row - f * (h.height - ch) / h.s;
                let bot = centre_row + f * ch / h.s;
                let y1 = (bot + 0.5).floor();
                if y1 < 0.0 {
                    continue;
                }
                let y0 = (top + 0.5).floor().max(0.0) as usize;
                let y1 = (y1 as usize).min(HEIGHT - 1);
                for (y, px) in col.iter_mut().enumerate().take(y1 + 1).skip(y0) {
                    let cov_v = ((y as f32 + 0.5).min(bot) - (y as f32 - 0.5).max(top)).max(0.0);
                    let alpha = h.cov * cov_v.min(1.0);
                    let g = match h.pattern {
                        RobotPattern::Stripes { .. } => h.grey,
                        RobotPattern::Band {
                            body,
                            band,
                            bottom_mm,
                            top_mm,
                        } => {
                            let z = ch + (centre_row - y as f32) * h.s / f;
                            let g = if (bottom_mm..=top_mm).contains(&z) {
                                band
                            } else {
                                body
                            };
                            h.shade * f32::from(g)
                        }
                    };
                    *px += alpha * (g - *px);
                }
            }

            for (y, g) in col.iter().enumerate() {
                acc[y * WIDTH + c] += weight * g;
            }
        }
    }

    /// The sensor: `acc` (the light of the exposure, grey levels) times the frame's `gain`,
    /// plus pixel noise, rounded into `frame`. Column by column, rows in pairs, so that the
    /// noise stream is drawn in a fixed order.
    fn sensor(acc: &[f32], gain: f32, mut noise: Option<(f32, &mut Rng)>, frame: &mut Frame) {
        for c in 0..WIDTH {
            let at = |y: usize| acc[y * WIDTH + c];
            match noise.as_mut() {
                None if gain == 1.0 => {
                    for y in 0..HEIGHT {
                        frame[y * WIDTH + c] = (at(y) + 0.5).clamp(0.0, 255.0) as u8;
                    }
                }
                None => {
                    for y in 0..HEIGHT {
                        frame[y * WIDTH + c] = (at(y) * gain + 0.5).clamp(0.0, 255.0) as u8;
                    }
                }
                Some((sigma, rng)) => {
                    // HEIGHT (72) is even: rows go in pairs.
                    for y in (0..HEIGHT).step_by(2) {
                        let (n0, n1) = rng.normal_pair();
                        let v0 = at(y) * gain + *sigma * n0;
                        let v1 = at(y + 1) * gain + *sigma * n1;
                        frame[y * WIDTH + c] = (v0 + 0.5).clamp(0.0, 255.0) as u8;
                        frame[(y + 1) * WIDTH + c] = (v1 + 0.5).clamp(0.0, 255.0) as u8;
                    }
                }
            }
        }
    }
}

/// Where a ray from `c` (inside the rectangle `lo`–`hi`) along `d` (not normalised; the
/// returned depth is in units of `d`) leaves the rectangle: the depth and the wall coordinate
/// `u`, running clockwise from the corner `lo` as on the arena's walls.
fn rect_hit(c: (f32, f32), d: (f32, f32), lo: (f32, f32), hi: (f32, f32)) -> (f32, f32) {
    let (w, h) = (hi.0 - lo.0, hi.1 - lo.1);
    let sx = if d.0 > 1e-9 {
        (hi.0 - c.0) / d.0
    } else if d.0 < -1e-9 {
        (lo.0 - c.0) / d.0
    } else {
        f32::INFINITY
    };
    let sy = if d.1 > 1e-9 {
        (hi.1 - c.1) / d.1
    } else if d.1 < -1e-9 {
        (lo.1 - c.1) / d.1
    } else {
        f32::INFINITY
    };
    let s = sx.min(sy).clamp(0.05, 1e7);
    let (x, y) = (
        (c.0 + s * d.0 - lo.0).clamp(0.0, w),
        (c.1 + s * d.1 - lo.1).clamp(0.0, h),
    );
    let u = if sx <= sy {
        if d.0 > 0.0 {
            w + y
        } else {
            2.0 * w + h + (h - y)
        }
    } else if d.1 > 0.0 {
        w + h + (w - x)
    } else {
        x
    };
    (s, u)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn focal_length_puts_35_degrees_at_the_edge_columns() {
        assert!((FOCAL_PX - 49.0 / 35f64.to_radians().tan()).abs() < 1e-6);
        assert!((column_of_bearing(35.0) - 98.0).abs() < 1e-6);
        assert!((column_of_bearing(-35.0) - 0.0).abs() < 1e-6);
        assert!((bearing_of_column(column_of_bearing(12.5)) - 12.5).abs() < 1e-9);
        assert_eq!(HFOV_DEG, 70.0);
    }

    /// The model assumes this camera in two places (`derotate::FOCAL_PX` for turns,
    /// `floor::CAMERA_HEIGHT_MM` and the horizon at row 35.5 for the floor line): the
    /// simulator must render what the model assumes.
    #[test]
    fn the_model_assumes_the_camera_this_renders() {
        use alvs_tasks::model::closed_loop::{derotate, floor};
        assert!((f64::from(derotate::FOCAL_PX) - FOCAL_PX).abs() < 1e-4);
        assert_eq!(CAMERA_HEIGHT_MM, f64::from(floor::CAMERA_HEIGHT_MM));
        assert_eq!(2.0 * CENTRE_ROW, (alvs_tasks::HEIGHT - 1) as f64);
    }
}

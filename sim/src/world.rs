//! What the simulated arena is made of: the walled rectangle, its wall texture, and the robots'
//! bodies and poses.
//!
//! # Frame convention
//!
//! Lengths are millimetres, angles degrees. The arena floor is `[0, size_x] × [0, size_y]`
//! seen **from above as a picture**: the origin is the top-left corner, `x` grows to the right
//! and `y` grows *downwards* (the rows of a top-down image, and of [`super::topdown`]).
//! A heading `h` points along `(cos h, sin h)`: 0° = +x (right in the picture), 90° = +y (down
//! in the picture). In this frame an increasing heading turns **clockwise in the picture, i.e.
//! to the robot's right**, which is the convention of `alvs_tasks::model::fsm` and of the model's
//! bearings (positive = right, wrapped to (−180°, 180°]). The robot's right-hand direction is
//! `(−sin h, cos h)`. No sign flips anywhere: `heading += (left − right)/track · dt`.
//!
//! # Defaults
//!
//! The default arena is 1200 mm × 900 mm with 250 mm walls: a table-top pen ≈ 29 × 21 robot
//! diameters that a robot crosses in 9–12 s at the paper's cruise speed (≈ 10 cm/s), so that three
//! robots meet each other and the walls every few seconds, as in the paper's 10-minute trials
//! (Sec. III-C; the paper does not give its arena's size, so this is a documented choice). Walls of
//! 250 mm fill the upper part of a 70° camera's view from anywhere in the arena (the top edge is at
//! +21° elevation from the middle of the arena, the camera sees up to +27°), so the wall texture is
//! the "visual background" of the paper's arena experiments. The default texture is procedural
//! clutter so that defaults never depend on files outside the project.

use std::path::Path;
use std::sync::Arc;

use anyhow::{bail, Context};

use super::contacts::SurfaceContact;

/// Diameter of a Colias body, mm (docs/hardware.md, community model).
pub const ROBOT_DIAMETER_MM: f64 = 42.0;
/// Radius of a Colias body, mm.
pub const ROBOT_RADIUS_MM: f64 = ROBOT_DIAMETER_MM / 2.0;
/// Height of a Colias body (sense board stack on the basic unit), mm.
pub const ROBOT_HEIGHT_MM: f64 = 28.0;

/// Default arena size along `x`, mm (see the module documentation).
pub const DEFAULT_ARENA_X_MM: f64 = 1200.0;
/// Default arena size along `y`, mm.
pub const DEFAULT_ARENA_Y_MM: f64 = 900.0;
/// Default height of the arena walls, mm.
pub const DEFAULT_WALL_HEIGHT_MM: f64 = 250.0;
/// Default seed of the procedural clutter texture.
pub const DEFAULT_CLUTTER_SEED: u64 = 1;

/// The walled rectangle `[0, size_x_mm] × [0, size_y_mm]` (walls of zero thickness on its
/// border).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arena {
    /// Extent along `x` (left to right in the top-down picture), mm.
    pub size_x_mm: f64,
    /// Extent along `y` (top to bottom in the top-down picture), mm.
    pub size_y_mm: f64,
}

impl Default for Arena {
    fn default() -> Self {
        Arena {
            size_x_mm: DEFAULT_ARENA_X_MM,
            size_y_mm: DEFAULT_ARENA_Y_MM,
        }
    }
}

impl Arena {
    /// An arena of `size_x_mm` × `size_y_mm`.
    pub fn new(size_x_mm: f64, size_y_mm: f64) -> Self {
        Arena {
            size_x_mm,
            size_y_mm,
        }
    }

    /// Distance from the point (x, y) to the nearest wall, mm (negative outside).
    pub fn wall_distance(&self, x: f64, y: f64) -> f64 {
        x.min(self.size_x_mm - x).min(y).min(self.size_y_mm - y)
    }

    /// Length of the walls all around, mm: the range of the wall texture coordinate `u`.
    pub fn perimeter_mm(&self) -> f64 {
        2.0 * (self.size_x_mm + self.size_y_mm)
    }

    /// The centre of the arena.
    pub fn centre(&self) -> (f64, f64) {
        (self.size_x_mm / 2.0, self.size_y_mm / 2.0)
    }
}

/// Where a robot is and where it faces (see the module documentation for the frame).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Pose {
    /// Centre of the body, mm.
    pub x_mm: f64,
    /// Centre of the body, mm.
    pub y_mm: f64,
    /// Heading, degrees in (−180°, 180°], positive = turned right (clockwise from above).
    pub heading_deg: f64,
}

/// `a` wrapped to (−180°, 180°].
pub fn wrap_deg(a: f64) -> f64 {
    if !a.is_finite() {
        return 0.0;
    }
    let r = a.rem_euclid(360.0);
    if r > 180.0 {
        r - 360.0
    } else {
        r
    }
}

impl Pose {
    /// A pose; the heading is wrapped.
    pub fn new(x_mm: f64, y_mm: f64, heading_deg: f64) -> Self {
        Pose {
            x_mm,
            y_mm,
            heading_deg: wrap_deg(heading_deg),
        }
    }

    /// Unit vector of the heading, `(cos h, sin h)`.
    pub fn forward(&self) -> (f64, f64) {
        let h = self.heading_deg.to_radians();
        (h.cos(), h.sin())
    }

    /// Unit vector to the robot's right, `(−sin h, cos h)`.
    pub fn right(&self) -> (f64, f64) {
        let (c, s) = self.forward();
        (-s, c)
    }

    /// The pose a fraction `t` of the way from `self` (0) to `to` (1), along the straight
    /// line and the shorter turn.
    pub fn lerp(&self, to: &Pose, t: f64) -> Pose {
        let dh = wrap_deg(to.heading_deg - self.heading_deg);
        Pose::new(
            self.x_mm + t * (to.x_mm - self.x_mm),
            self.y_mm + t * (to.y_mm - self.y_mm),
            self.heading_deg + t * dh,
        )
    }

    /// Distance between the centres, mm.
    pub fn distance_to(&self, other: &Pose) -> f64 {
        (other.x_mm - self.x_mm).hypot(other.y_mm - self.y_mm)
    }

    /// Bearing of the point (x, y) from this pose's centre, degrees in (−180°, 180°],
    /// positive = to the right.
    pub fn bearing_to(&self, x: f64, y: f64) -> f64 {
        let a = (y - self.y_mm).atan2(x - self.x_mm).to_degrees();
        wrap_deg(a - self.heading_deg)
    }

    /// The point `forward_mm` ahead and `right_mm` to the right of the centre.
    pub fn offset(&self, forward_mm: f64, right_mm: f64) -> (f64, f64) {
        let (fx, fy) = self.forward();
        let (rx, ry) = self.right();
        (
            self.x_mm + forward_mm * fx + right_mm * rx,
            self.y_mm + forward_mm * fy + right_mm * ry,
        )
    }
}

/// An 8-bit grey picture for [`WallTexture::Image`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GreyImage {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width * height` grey levels, row-major, top row first.
    pub pixels: Vec<u8>,
}

impl GreyImage {
    /// Wraps `pixels` (row-major, `width * height` of them); `None` if the sizes disagree or
    /// the picture is empty.
    pub fn new(width: usize, height: usize, pixels: Vec<u8>) -> Option<Self> {
        (width > 0 && height > 0 && pixels.len() == width * height).then_some(GreyImage {
            width,
            height,
            pixels,
        })
    }

    /// Reads a PNG or JPEG file (format from its content) and converts it to grey (Rec. 709
    /// luma, as `image` does).
    pub fn load(path: impl AsRef<Path>) -> anyhow::Result<Self> {
        let path = path.as_ref();
        let img = image::ImageReader::open(path)
            .with_context(|| format!("cannot open {}", path.display()))?
            .with_guessed_format()
            .with_context(|| format!("cannot read {}", path.display()))?
            .decode()
            .with_context(|| format!("{} is not a PNG or JPEG picture", path.display()))?
            .into_luma8();
        let (w, h) = (img.width() as usize, img.height() as usize);
        GreyImage::new(w, h, img.into_raw())
            .with_context(|| format!("{} is an empty picture", path.display()))
    }
}

/// What the inside of the walls looks like. The texture coordinate `u` runs along the walls
/// clockwise (seen from above) from the corner (0, 0), so that a picture is seen unmirrored from
/// inside the arena; `v` is the height above the floor. Texture sizes are on the wall, in mm.
#[derive(Debug, Clone, PartialEq)]
pub enum WallTexture {
    /// One grey level everywhere.
    Plain(u8),
    /// Vertical black-and-white stripes, `period_mm` for a dark and a light stripe together.
    Stripes {
        /// Period of the square wave along the wall, mm.
        period_mm: f64,
    },
    /// A black-and-white checkerboard of `size_mm` squares.
    Checker {
        /// Side of one square, mm.
        size_mm: f64,
    },
    /// Procedural clutter: overlapping rectangles and discs of many sizes and greys, like a
    /// cluttered lab seen behind a low wall; the same seed gives the same walls.
    Clutter {
        /// Seed of the layout.
        seed: u64,
    },
    /// A procedural outdoor scene with the statistics of natural photographs (the paper's
    /// arena showed two outdoor scenes): bright sky in the upper part, darker ground below,
    /// and 1/f ("pink") grey-level noise of RMS contrast ≈ 0.4 everywhere else, matched to the
    /// three outdoor photographs in `data/photos` (see `texture`).
    Outdoor {
        /// Seed of the scene.
        seed: u64,
    },
    /// A picture, scaled to the wall height with its aspect ratio kept and repeated along the
    /// walls.
    Image(Arc<GreyImage>),
    /// Vertical ribs of a corrugated sheet, as the recorded arena's walls (docs/recordings.md):
    /// a smooth (raised-cosine) profile from `dark` in the grooves to `light` on the ribs, one
    /// groove and one rib per `period_mm`.
    Ribs {
        /// Distance between two ribs, mm.
        period_mm: f64,
        /// Grey in the grooves.
        dark: u8,
        /// Grey on the ribs.
        light: u8,
    },
}

impl Default for WallTexture {
    fn default() -> Self {
        WallTexture::Clutter {
            seed: DEFAULT_CLUTTER_SEED,
        }
    }
}

impl WallTexture {
    /// The built-in textures' names in a specification.
    pub const NAMES: [&'static str; 6] =
        ["plain", "stripes", "checker", "clutter", "outdoor", "ribs"];

    /// Parses a background specification as a command line gives it: `plain[:GREY]`,
    /// `stripes[:PERIOD_MM]`, `checker[:SIZE_MM]`, `clutter[:SEED]`, `outdoor[:SEED]`,
    /// `ribs[:PERIOD_MM[:DARK:LIGHT]]`, or else the path of a PNG or JPEG picture. Defaults: grey
    /// 128, period 40 mm, squares 40 mm, seed 1, the recorded arena's ribs
    /// ([`super::replica::WALL_RIBS`]).
    pub fn from_spec(spec: &str) -> anyhow::Result<Self> {
        let (name, arg) = match spec.split_once(':') {
            Some((n, a)) => (n, Some(a)),
            None => (spec, None),
        };
        let num = |default: f64| -> anyhow::Result<f64> {
            let Some(a) = arg else { return Ok(default) };
            let v: f64 = a
                .parse()
                .with_context(|| format!("`{a}` in `{spec}` is not a number"))?;
            if !(v.is_finite() && v > 0.0) {
                bail!("`{a}` in `{spec}` must be a positive size in mm");
            }
            Ok(v)
        };
        Ok(match name {
            "plain" => WallTexture::Plain(match arg {
                None => 128,
                Some(a) => a
                    .parse()
                    .with_context(|| format!("`{a}` in `{spec}` is not a grey level 0..=255"))?,
            }),
            "stripes" => WallTexture::Stripes {
                period_mm: num(40.0)?,
            },
            "checker" => WallTexture::Checker {
                size_mm: num(40.0)?,
            },
            "outdoor" => WallTexture::Outdoor {
                seed: match arg {
                    None => DEFAULT_CLUTTER_SEED,
                    Some(a) => a
                        .parse()
                        .with_context(|| format!("`{a}` in `{spec}` is not a seed"))?,
                },
            },
            "ribs" => ribs_from_spec(arg, spec)?,
            "clutter" => WallTexture::Clutter {
                seed: match arg {
                    None => DEFAULT_CLUTTER_SEED,
                    Some(a) => a
                        .parse()
                        .with_context(|| format!("`{a}` in `{spec}` is not a seed"))?,
                },
            },
            _ => WallTexture::Image(Arc::new(GreyImage::load(spec)?)),
        })
    }

    /// A short name for titles and JSON: `plain:128`, `stripes:40`, `checker:40`, `clutter:1`,
    /// `image WxH`.
    pub fn label(&self) -> String {
        match self {
            WallTexture::Plain(g) => format!("plain:{g}"),
            WallTexture::Stripes { period_mm } => format!("stripes:{period_mm}"),
            WallTexture::Checker { size_mm } => format!("checker:{size_mm}"),
            WallTexture::Clutter { seed } => format!("clutter:{seed}"),
            WallTexture::Outdoor { seed } => format!("outdoor:{seed}"),
            WallTexture::Image(img) => format!("image {}x{}", img.width, img.height),
            WallTexture::Ribs {
                period_mm,
                dark,
                light,
            } => format!("ribs:{period_mm}:{dark}:{light}"),
        }
    }
}

/// `ribs[:PERIOD_MM[:DARK:LIGHT]]` (the part after `ribs:` is `arg`).
fn ribs_from_spec(arg: Option<&str>, spec: &str) -> anyhow::Result<WallTexture> {
    let Some(arg) = arg else {
        return Ok(super::replica::WALL_RIBS);
    };
    let WallTexture::Ribs {
        mut dark,
        mut light,
        ..
    } = super::replica::WALL_RIBS
    else {
        unreachable!("the recorded walls are ribs")
    };
    let parts: Vec<&str> = arg.split(':').collect();
    if !matches!(parts.len(), 1 | 3) {
        bail!("`{spec}`: expected ribs, ribs:PERIOD_MM or ribs:PERIOD_MM:DARK:LIGHT");
    }
    let period_mm = parts[0]
        .parse()
        .ok()
        .filter(|p: &f64| p.is_finite() && *p > 0.0)
        .with_context(|| format!("`{}` in `{spec}` is not a positive period in mm", parts[0]))?;
    if parts.len() == 3 {
        let grey = |s: &str| {
            s.parse::<u8>()
                .with_context(|| format!("`{s}` in `{spec}` is not a grey level 0..=255"))
        };
        dark = grey(parts[1])?;
        light = grey(parts[2])?;
    }
    Ok(WallTexture::Ribs {
        period_mm,
        dark,
        light,
    })
}

/// A static cylinder standing on the floor, such as the recorded arena's obstacles: seen by
/// every camera, and a body robots cannot enter (see `contacts`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Obstacle {
    /// Centre, mm.
    pub x_mm: f64,
    /// Centre, mm.
    pub y_mm: f64,
    /// Radius, mm.
    pub radius_mm: f64,
    /// Height, mm.
    pub height_mm: f64,
}

impl Obstacle {
    /// Distance from the point (x, y) to the obstacle's surface, mm (negative inside).
    pub fn surface_distance(&self, x: f64, y: f64) -> f64 {
        (x - self.x_mm).hypot(y - self.y_mm) - self.radius_mm
    }
}

/// How the floor looks to a robot's camera: a grey that changes with the viewing distance
/// (a floor seen at a grazing angle reflects more of the bright room).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FloorShade {
    /// Grey of the floor just in front of the camera.
    pub near_grey: f32,
    /// Grey the floor tends to far away.
    pub far_grey: f32,
}

impl Default for FloorShade {
    /// The built-in arena's mid-grey floor ([`super::render::FLOOR_NEAR_GREY`] →
    /// [`super::render::FLOOR_FAR_GREY`]).
    fn default() -> Self {
        FloorShade {
            near_grey: super::render::FLOOR_NEAR_GREY,
            far_grey: super::render::FLOOR_FAR_GREY,
        }
    }
}

/// The room around a low-walled arena, as a robot's camera sees it above the walls: a box
/// `margin_mm` beyond the arena's walls on every side, `height_mm` high, with its own texture;
/// above it the bright ceiling ([`super::render::SKY_GREY`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Room {
    /// Distance from the arena's walls to the room's walls, mm.
    pub margin_mm: f64,
    /// Height of the room's walls, mm.
    pub height_mm: f64,
    /// What the room's walls look like (features scaled by [`Room::SCALE`]: a clutter of
    /// 6–180 mm shapes on the arena's walls is 60–1800 mm furniture here).
    pub texture: WallTexture,
}

impl Room {
    /// How much larger the room's texture features are than the same texture on the arena's
    /// walls (it is stored at 10 mm texels).
    pub const SCALE: f64 = 10.0;
}

/// How a robot's body looks from the side (all robots look the same).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RobotPattern {
    /// `count` pairs of dark and light vertical stripes around the body; they turn with the
    /// robot, so a spinning robot shows motion.
    Stripes {
        /// Dark/light pairs around the circumference.
        count: u8,
        /// Grey of the dark stripes (before shading).
        dark: u8,
        /// Grey of the light stripes (before shading).
        light: u8,
    },
    /// A uniform body with a horizontal band.
    Band {
        /// Grey of the body.
        body: u8,
        /// Grey of the band.
        band: u8,
        /// Height of the band's lower edge above the floor, mm.
        bottom_mm: f32,
        /// Height of the band's upper edge, mm.
        top_mm: f32,
    },
}

impl Default for RobotPattern {
    /// Six dark/light stripe pairs (each stripe ≈ 11 mm wide on the Ø 42 mm body), darker than
    /// any wall texture's mean: a robot is a dark, patterned object against the background, as
    /// the black PCB stack of a Colias is.
    fn default() -> Self {
        RobotPattern::Stripes {
            count: 6,
            dark: 25,
            light: 100,
        }
    }
}

/// The static part of a simulation: arena, walls and how robots look.
#[derive(Debug, Clone, PartialEq)]
pub struct World {
    /// The walled rectangle.
    pub arena: Arena,
    /// Height of the walls, mm; above them the camera sees the bright lab ([`super::render::SKY_GREY`]).
    pub wall_height_mm: f64,
    /// The inside of the walls.
    pub texture: WallTexture,
    /// The robots' bodies.
    pub robot_pattern: RobotPattern,
    /// The floor.
    pub floor: FloorShade,
    /// Static cylinders on the floor (none in the built-in arena).
    pub obstacles: Vec<Obstacle>,
    /// How the obstacles look from the side.
    pub obstacle_pattern: RobotPattern,
    /// How a robot meets the walls and obstacles.
    pub contact: SurfaceContact,
    /// What is seen above the walls: the room, or with `None` the uniform bright lab
    /// ([`super::render::SKY_GREY`]; the built-in arena's walls are higher than the camera
    /// sees from most places).
    pub room: Option<Room>,
}

impl Default for World {
    fn default() -> Self {
        World {
            arena: Arena::default(),
            wall_height_mm: DEFAULT_WALL_HEIGHT_MM,
            texture: WallTexture::default(),
            robot_pattern: RobotPattern::default(),
            floor: FloorShade::default(),
            obstacles: Vec::new(),
            obstacle_pattern: RobotPattern::default(),
            contact: SurfaceContact::RIGID,
            room: None,
        }
    }
}

impl World {
    /// The default world with another wall texture.
    pub fn with_texture(texture: WallTexture) -> Self {
        World {
            texture,
            ..World::default()
        }
    }

    /// Distance from the point (x, y) to the nearest static surface (a wall or an obstacle),
    /// mm.
    pub fn static_distance(&self, x: f64, y: f64) -> f64 {
        static_distance(&self.arena, &self.obstacles, x, y)
    }
}

/// Distance from the point (x, y) to the nearest wall of `arena` or surface of `obstacles`, mm.
pub fn static_distance(arena: &Arena, obstacles: &[Obstacle], x: f64, y: f64) -> f64 {
    obstacles
        .iter()
        .map(|o| o.surface_distance(x, y))
        .fold(arena.wall_distance(x, y), f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headings_turn_right_clockwise_in_the_picture() {
        let p = Pose::new(100.0, 100.0, 0.0);
        // A point below (greater y) the robot facing +x is on its right.
        assert!((p.bearing_to(100.0, 200.0) - 90.0).abs() < 1e-9);
        assert!((p.bearing_to(100.0, 0.0) + 90.0).abs() < 1e-9);
        let (rx, ry) = p.right();
        assert!(rx.abs() < 1e-12 && (ry - 1.0).abs() < 1e-12);
        assert_eq!(Pose::new(0.0, 0.0, 540.0).heading_deg, 180.0);
        assert_eq!(wrap_deg(-180.0), 180.0);
    }

    #[test]
    fn specs_parse() {
        assert_eq!(
            WallTexture::from_spec("stripes:25").unwrap(),
            WallTexture::Stripes { period_mm: 25.0 }
        );
        assert_eq!(
            WallTexture::from_spec("plain").unwrap(),
            WallTexture::Plain(128)
        );
        assert_eq!(
            WallTexture::from_spec("clutter:9").unwrap(),
            WallTexture::Clutter { seed: 9 }
        );
        assert!(WallTexture::from_spec("checker:-3").is_err());
        assert!(WallTexture::from_spec("/no/such/picture.png").is_err());
    }

    #[test]
    fn wall_distance() {
        let a = Arena::default();
        assert_eq!(a.wall_distance(30.0, 450.0), 30.0);
        assert_eq!(a.wall_distance(600.0, 880.0), 20.0);
        assert_eq!(a.perimeter_mm(), 4200.0);
    }
}

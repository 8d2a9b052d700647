//! Where a staged experiment stands in a world: `stimuli`, `evasion` and `two-threats` put a
//! robot at one place and drive obstacle robots along set paths relative to it, a geometry
//! designed for the built-in 1200 x 900 mm `lab`. In another world (the replica `fu2019`, with
//! its cylinders along the walls and across the middle) the same geometry has to be put where
//! it fits.
//!
//! A [`Stage`] is that geometry in the standing robot's own frame (`forward_mm` along its
//! heading, `right_mm` to its right): the paths the robots' bodies sweep, and regions swept by
//! many possible paths (a [`Shape::Sector`]). Its **clearance** at a pose is the smallest gap
//! between a swept body (radius [`ROBOT_RADIUS_MM`]) and a wall or an obstacle's surface.
//! [`Stage::place`] keeps the experiment's designed pose when the stage fits there with at
//! least [`MIN_CLEARANCE_MM`] to spare (the `lab`: every figure measured there stays as it
//! was), and otherwise puts it where its clearance is largest: the best of a grid of every
//! position (20 mm apart) and heading (5° apart) in the arena, refined around it (2 mm, 1°).

use anyhow::{ensure, Result};

use crate::world::{wrap_deg, ROBOT_RADIUS_MM};
use crate::{BuiltinWorld, Pose, World};

/// Least gap a placed stage leaves between every swept body and every wall or obstacle, mm: a
/// pass this close is clearly not a contact (the contacts' episodes have 10 mm hysteresis
/// too).
pub const MIN_CLEARANCE_MM: f64 = 10.0;

/// Grid of the search: positions `COARSE_MM` apart, headings `COARSE_DEG` apart; then around
/// the best `±COARSE_MM` at `FINE_MM` and `±COARSE_DEG` at `FINE_DEG`.
const COARSE_MM: f64 = 20.0;
const COARSE_DEG: f64 = 5.0;
const FINE_MM: f64 = 2.0;
const FINE_DEG: f64 = 1.0;

/// A part of a stage, in the standing robot's frame (mm: forward, right; bearings in degrees,
/// positive = right), swept by a robot's body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// A robot's straight path from `from` to `to` (a point: a robot that stands).
    Path {
        /// Start, (forward, right) mm.
        from: (f64, f64),
        /// End, (forward, right) mm.
        to: (f64, f64),
    },
    /// Every straight path from a point of a circular sector to its apex, the robot's centre:
    /// the sector itself, bearings `mid_deg ± half_deg`, radius `radius_mm`.
    Sector {
        /// Its middle bearing, degrees.
        mid_deg: f64,
        /// Half its angle, degrees (under 180).
        half_deg: f64,
        /// Its radius, mm.
        radius_mm: f64,
    },
}

/// A staged experiment's geometry (see the module documentation).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Stage {
    /// Its parts.
    pub shapes: Vec<Shape>,
}

/// Where a stage stands in a world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// The standing robot's pose.
    pub pose: Pose,
    /// The stage's clearance there, mm.
    pub clearance_mm: f64,
    /// It is the experiment's designed pose (else found by the search).
    pub designed: bool,
}

/// A staged experiment's world, walls included, and where its stage stands in it.
#[derive(Debug, Clone)]
pub struct Staged {
    /// The background specification its walls show.
    pub background: String,
    /// The world.
    pub world: World,
    /// Where the stage stands.
    pub placement: Placement,
}

/// Distance from `p` to the segment `a`–`b`.
fn segment_distance(a: (f64, f64), b: (f64, f64), p: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a.0 + t * dx - p.0).hypot(a.1 + t * dy - p.1)
}

impl Shape {
    /// The smallest gap between a body swept over the shape, with the stage at `pose`, and
    /// any wall or obstacle of `world`, mm (negative: they overlap). Stops early, returning
    /// some value below `floor`, once the gap is below `floor`.
    fn clearance(&self, world: &World, pose: &Pose, floor: f64) -> f64 {
        let arena = &world.arena;
        let at = |p: (f64, f64)| pose.offset(p.0, p.1);
        match *self {
            Shape::Path { from, to } => {
                let (a, b) = (at(from), at(to));
                let mut c = arena
                    .wall_distance(a.0, a.1)
                    .min(arena.wall_distance(b.0, b.1));
                for o in &world.obstacles {
                    if c - ROBOT_RADIUS_MM < floor {
                        break;
                    }
                    c = c.min(segment_distance(a, b, (o.x_mm, o.y_mm)) - o.radius_mm);
                }
                c - ROBOT_RADIUS_MM
            }
            Shape::Sector {
                mid_deg,
                half_deg,
                radius_mm,
            } => {
                let apex = (pose.x_mm, pose.y_mm);
                let world_deg = |bearing: f64| pose.heading_deg + mid_deg + bearing;
                let arc = |deg: f64| {
                    let r = deg.to_radians();
                    (apex.0 + radius_mm * r.cos(), apex.1 + radius_mm * r.sin())
                };
                let (e1, e2) = (arc(world_deg(-half_deg)), arc(world_deg(half_deg)));
                // the sector's extremes along x and y: its apex, its arc's ends, and the arc's
                // points facing a wall squarely when they lie inside its angle
                let mut c = [apex, e1, e2]
                    .iter()
                    .map(|p| arena.wall_distance(p.0, p.1))
                    .fold(f64::INFINITY, f64::min);
                for square in [0.0, 90.0, 180.0, -90.0] {
                    if wrap_deg(square - world_deg(0.0)).abs() <= half_deg {
                        let p = arc(square);
                        c = c.min(arena.wall_distance(p.0, p.1));
                    }
                }
                for o in &world.obstacles {
                    if c - ROBOT_RADIUS_MM < floor {
                        break;
                    }
                    let (dx, dy) = (o.x_mm - apex.0, o.y_mm - apex.1);
                    let rho = dx.hypot(dy);
                    let off = wrap_deg(dy.atan2(dx).to_degrees() - world_deg(0.0));
                    let d = if off.abs() <= half_deg {
                        (rho - radius_mm).max(0.0)
                    } else {
                        segment_distance(apex, e1, (o.x_mm, o.y_mm)).min(segment_distance(
                            apex,
                            e2,
                            (o.x_mm, o.y_mm),
                        ))
                    };
                    c = c.min(d - o.radius_mm);
                }
                c - ROBOT_RADIUS_MM
            }
        }
    }
}

impl Stage {
    /// The smallest gap between any swept body of the stage, standing at `pose`, and any wall
    /// or obstacle of `world`, mm (negative: something is in the way).
    pub fn clearance(&self, world: &World, pose: &Pose) -> f64 {
        self.clearance_above(world, pose, f64::NEG_INFINITY)
    }

    /// [`Stage::clearance`], stopping early with some value below `floor` once it is below.
    fn clearance_above(&self, world: &World, pose: &Pose, floor: f64) -> f64 {
        let mut c = f64::INFINITY;
        for s in &self.shapes {
            c = c.min(s.clearance(world, pose, floor));
            if c < floor {
                break;
            }
        }
        c
    }

    /// Where the stage stands in `world`: at `design` when it fits there with
    /// [`MIN_CLEARANCE_MM`] to spare, else at the pose of largest clearance (the module
    /// documentation). The caller checks that clearance ([`Placement::check`]).
    pub fn place(&self, world: &World, design: Pose) -> Placement {
        let c = self.clearance(world, &design);
        if c >= MIN_CLEARANCE_MM {
            return Placement {
                pose: design,
                clearance_mm: c,
                designed: true,
            };
        }
        let (pose, clearance_mm) = self.clearest(world);
        Placement {
            pose,
            clearance_mm,
            designed: false,
        }
    }

    /// The pose of largest clearance in `world` and its clearance: the first best of the
    /// coarse grid (x, then y, then heading, increasing), refined around it. A pure function of
    /// the stage and the world's geometry, remembered for the process (an experiment asks for
    /// its placement when it checks, runs and reports).
    pub fn clearest(&self, world: &World) -> (Pose, f64) {
        use std::collections::HashMap;
        use std::sync::{Mutex, OnceLock};
        static SEARCHED: OnceLock<Mutex<HashMap<String, (Pose, f64)>>> = OnceLock::new();
        let key = format!("{:?} {:?} {:?}", self.shapes, world.arena, world.obstacles);
        let memo = SEARCHED.get_or_init(Mutex::default);
        let known = memo.lock().ok().and_then(|m| m.get(&key).copied());
        if let Some(hit) = known {
            return hit;
        }
        let found = self.search(world);
        if let Ok(mut m) = memo.lock() {
            m.insert(key, found);
        }
        found
    }

    /// [`Stage::clearest`] without the memory.
    fn search(&self, world: &World) -> (Pose, f64) {
        let (sx, sy) = (world.arena.size_x_mm, world.arena.size_y_mm);
        let steps = |size: f64| (size / COARSE_MM).floor() as i32;
        let headings = (360.0 / COARSE_DEG).round() as i32;
        let mut best = (Pose::default(), f64::NEG_INFINITY);
        let consider = |p: Pose, best: &mut (Pose, f64)| {
            let c = self.clearance_above(world, &p, best.1);
            if c > best.1 {
                *best = (p, c);
            }
        };
        for i in 0..=steps(sx) {
            for j in 0..=steps(sy) {
                for k in 0..headings {
                    let p = Pose::new(
                        f64::from(i) * COARSE_MM,
                        f64::from(j) * COARSE_MM,
                        -180.0 + f64::from(k) * COARSE_DEG,
                    );
                    consider(p, &mut best);
                }
            }
        }
        let centre = best.0;
        let (n, m) = (
            (COARSE_MM / FINE_MM).round() as i32,
            (COARSE_DEG / FINE_DEG).round() as i32,
        );
        for i in -n..=n {
            for j in -n..=n {
                for k in -m..=m {
                    let p = Pose::new(
                        centre.x_mm + f64::from(i) * FINE_MM,
                        centre.y_mm + f64::from(j) * FINE_MM,
                        centre.heading_deg + f64::from(k) * FINE_DEG,
                    );
                    consider(p, &mut best);
                }
            }
        }
        best
    }
}

impl Placement {
    /// The placement as JSON: `{"x_mm", "y_mm", "heading_deg", "clearance_mm", "designed"}`
    /// (rounded to 0.1).
    pub fn json(&self) -> serde_json::Value {
        let r = |v: f64| (v * 10.0).round() / 10.0;
        serde_json::json!({
            "x_mm": r(self.pose.x_mm),
            "y_mm": r(self.pose.y_mm),
            "heading_deg": r(self.pose.heading_deg),
            "clearance_mm": r(self.clearance_mm),
            "designed": self.designed,
        })
    }

    /// One line for a table: where the stage stands and why.
    pub fn describe(&self) -> String {
        format!(
            "at ({:.0}, {:.0}) mm facing {:.0} deg, {} ({:.0} mm clear of every wall and obstacle)",
            self.pose.x_mm,
            self.pose.y_mm,
            self.pose.heading_deg,
            if self.designed {
                "as designed"
            } else {
                "where the stage is clearest"
            },
            self.clearance_mm
        )
    }

    /// The placement in `world` with its walls showing `background` (its own without one,
    /// [`crate::worlds::world_with`]), checked: an unreadable background or a stage that does not fit
    /// ([`Placement::check`]) is an error of one line naming `what`.
    pub fn staged(
        self,
        world: BuiltinWorld,
        background: Option<&str>,
        what: &str,
    ) -> Result<Staged> {
        self.check(what, world.label())?;
        let (background, world) = crate::worlds::world_with(world, background)?;
        Ok(Staged {
            background,
            world,
            placement: self,
        })
    }

    /// Fails, in one line naming `what` and `world_label`, when the stage does not fit with
    /// [`MIN_CLEARANCE_MM`] to spare.
    pub fn check(&self, what: &str, world_label: &str) -> Result<()> {
        ensure!(
            self.clearance_mm >= MIN_CLEARANCE_MM,
            "{what} does not fit in the {world_label} world: wherever it stands, a path comes \
             within {:.0} mm of a wall or obstacle (at least {MIN_CLEARANCE_MM} mm needed)",
            self.clearance_mm.max(0.0)
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Arena, Obstacle};

    fn open(x: f64, y: f64) -> World {
        World {
            arena: Arena::new(x, y),
            ..World::default()
        }
    }

    #[test]
    fn a_path_and_a_sector_measure_their_gap_to_walls_and_obstacles() {
        let world = open(1000.0, 1000.0);
        let pose = Pose::new(200.0, 500.0, 0.0);
        let path = Shape::Path {
            from: (0.0, 0.0),
            to: (300.0, 0.0),
        };
        // the nearest wall is the left one, 200 mm from the start
        assert!((path.clearance(&world, &pose, f64::NEG_INFINITY) - 179.0).abs() < 1e-9);
        // a sector ahead, ±45°, 600 mm: its arc's top reaches 500 - 424.3 mm from the top wall
        let sector = Shape::Sector {
            mid_deg: 0.0,
            half_deg: 45.0,
            radius_mm: 600.0,
        };
        let c = sector.clearance(&world, &pose, f64::NEG_INFINITY);
        assert!((c - (500.0 - 600.0 * 45f64.to_radians().sin() - 21.0)).abs() < 1e-9);
        // the arc's forward point is 800 mm right of the left wall: 200 mm from the right one
        let ahead = Shape::Sector {
            mid_deg: 0.0,
            half_deg: 5.0,
            radius_mm: 600.0,
        };
        let c = ahead.clearance(&world, &pose, f64::NEG_INFINITY);
        assert!((c - (200.0 - 21.0)).abs() < 1e-9, "{c}");
        // an obstacle inside the sector overlaps it; one beside it is measured to its edge
        let mut w = world.clone();
        let post = |x, y| Obstacle {
            x_mm: x,
            y_mm: y,
            radius_mm: 20.0,
            height_mm: 50.0,
        };
        w.obstacles = vec![post(500.0, 500.0)];
        assert!(sector.clearance(&w, &pose, f64::NEG_INFINITY) < -20.0);
        w.obstacles = vec![post(200.0, 400.0)];
        let c = sector.clearance(&w, &pose, f64::NEG_INFINITY);
        // 100 mm from the apex, at -90°: 45° off the sector's edge
        let edge = 100.0 * 45f64.to_radians().sin();
        assert!((c - (edge - 20.0 - 21.0)).abs() < 1e-9, "{c}");
    }

    #[test]
    fn a_stage_keeps_its_design_where_it_fits_and_else_goes_where_it_is_clearest() {
        let stage = Stage {
            shapes: vec![Shape::Path {
                from: (400.0, 0.0),
                to: (0.0, 0.0),
            }],
        };
        let world = open(1000.0, 600.0);
        let design = Pose::new(100.0, 300.0, 0.0);
        let p = stage.place(&world, design);
        assert!(p.designed && p.pose == design);
        // a post on the designed path: the stage moves, clear of it and of the walls
        let mut w = world.clone();
        w.obstacles = vec![Obstacle {
            x_mm: 300.0,
            y_mm: 300.0,
            radius_mm: 23.0,
            height_mm: 53.0,
        }];
        let p = stage.place(&w, design);
        assert!(!p.designed, "{p:?}");
        assert!(p.clearance_mm >= MIN_CLEARANCE_MM, "{p:?}");
        assert!((stage.clearance(&w, &p.pose) - p.clearance_mm).abs() < 1e-9);
        p.check("the stage", "test").unwrap();
        // nowhere to stand
        let tiny = open(300.0, 300.0);
        let p = stage.place(&tiny, design);
        let e = p.check("the stage", "tiny").unwrap_err().to_string();
        assert!(e.contains("does not fit in the tiny world"), "{e}");
    }
}

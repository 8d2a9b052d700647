//! Contacts between bodies: physical resolution of overlaps, and the paper's counting of
//! collisions, plus the encounters that make a success rate.
//!
//! # Resolution
//!
//! Bodies are rigid discs of [`ROBOT_RADIUS_MM`] moved by their wheels. After every physics
//! step, overlapping robots are pushed apart along the line of their centres, each by half the
//! overlap (equal masses, no momentum: a Colias is light and its wheels grip, so a robot pushing
//! another moves the pair at about half its speed), and every centre is then kept at least one
//! radius from each wall (the wall stops a body dead; its wheels keep turning). This is repeated
//! [`RESOLVE_ITERATIONS`] times so that chains (robot–robot–wall) settle. Steps are short enough
//! that nothing tunnels (see `kinematics`).
//!
//! # Counting (paper Sec. III-C)
//!
//! "A collision event was defined when the distance between two robots, or between a robot and
//! the arena wall, fell below the robot's diameter." Distances are from the body's centre, as
//! the paper's overhead tracker measures them:
//!
//! * robot–robot **collision**: centre distance < [`ROBOT_COLLISION_DISTANCE_MM`] = 42 mm = one
//!   diameter, i.e. the bodies touch. The physics never lets the resolved distance drop below
//!   42 mm, so this is tested on the distance *before* resolution in each step: a collision is a
//!   step in which the bodies would interpenetrate.
//! * robot–wall **collision**: centre-to-wall distance < [`WALL_COLLISION_DISTANCE_MM`] = 42 mm,
//!   the paper's words taken literally: the gap is below one radius (21 mm), so a robot can
//!   "collide" with a wall without touching it. Physical wall contact (centre within one radius)
//!   is counted separately as a wall **touch**. The wall is one body ("the arena wall"): the
//!   distance is to the nearest of the four sides, so a corner is one wall.
//! * **encounter**: the two bodies come within two diameters of each other, surface to surface
//!   (gap < 84 mm): centre distance < [`ROBOT_ENCOUNTER_DISTANCE_MM`] = 126 mm between robots,
//!   centre-to-wall < [`WALL_ENCOUNTER_DISTANCE_MM`] = 105 mm for a wall. A collision always
//!   happens inside an encounter (the thresholds are nested), so
//!   `success rate = encounters without a collision / encounters` is well defined.
//!
//! Every one of these is counted once per **episode**, per pair of bodies (an unordered robot
//! pair, or a robot and the wall): an episode starts when the distance falls below its threshold
//! and ends only when it rises above threshold + [`EPISODE_HYSTERESIS_MM`], so that bodies
//! pressed together, or a robot hovering at a threshold, count once.

use super::kinematics::TRACK_MM;
use super::rng::Rng;
use super::world::{
    static_distance, wrap_deg, Arena, Obstacle, Pose, ROBOT_DIAMETER_MM, ROBOT_RADIUS_MM,
};

/// Robot–robot collision: centre distance below this, mm (one diameter: the bodies touch).
pub const ROBOT_COLLISION_DISTANCE_MM: f64 = ROBOT_DIAMETER_MM;
/// Robot–wall collision: centre-to-wall distance below this, mm (one diameter, as the paper
/// says; gap below one radius).
pub const WALL_COLLISION_DISTANCE_MM: f64 = ROBOT_DIAMETER_MM;
/// Robot–wall touch (physical contact): centre-to-wall distance below this, mm.
pub const WALL_TOUCH_DISTANCE_MM: f64 = ROBOT_RADIUS_MM;
/// Gap defining an encounter, mm (two diameters, surface to surface).
pub const ENCOUNTER_GAP_MM: f64 = 2.0 * ROBOT_DIAMETER_MM;
/// Robot–robot encounter: centre distance below this, mm (gap 84 mm + two radii).
pub const ROBOT_ENCOUNTER_DISTANCE_MM: f64 = ENCOUNTER_GAP_MM + ROBOT_DIAMETER_MM;
/// Robot–wall encounter: centre-to-wall distance below this, mm (gap 84 mm + one radius).
pub const WALL_ENCOUNTER_DISTANCE_MM: f64 = ENCOUNTER_GAP_MM + ROBOT_RADIUS_MM;
/// An episode ends when the distance exceeds its threshold by more than this, mm.
pub const EPISODE_HYSTERESIS_MM: f64 = 10.0;
/// [`SurfaceContact::slip_yaw`] of the recorded arena: calibrated on the 10.9 cm/s recordings
/// (docs/world.md, "Contact").
pub const SLIP_YAW: f64 = 1.0;
/// Relaxation passes of the overlap resolution per physics step.
pub const RESOLVE_ITERATIONS: usize = 4;

/// How a robot's shell meets a static surface (a wall or an obstacle), beyond being stopped by
/// it: see [`resolve_overlaps`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceContact {
    /// Heading turned toward the surface's tangent per mm of travel the surface blocks, in
    /// units of 1/radius (dimensionless): the turn the shell's friction at the contact point
    /// gives a body that slides along the surface (it holds the shell back where it touches, so
    /// the body swings round parallel to the surface). 0 = the body keeps its heading (a robot
    /// that drives straight into a wall stays there, seeing a frozen picture).
    pub turn_gain: f64,
    /// Stick-slip of the wheels while the surface blocks the body: the travel the surface
    /// blocks is lost in wheel slip, and the two wheels do not slip alike. Standard deviation
    /// of the slip difference between the wheels as a share of the blocked travel; it turns
    /// the body by `slip difference / wheel track` at random each physics step (the shell
    /// rattles and the camera's view jitters while the wheels push). 0 = the wheels slip
    /// alike and the pressed body stays still.
    pub slip_yaw: f64,
}

impl SurfaceContact {
    /// No turn, no rattle: the body only slides (the simulator's contact model before the
    /// recorded arena).
    pub const RIGID: SurfaceContact = SurfaceContact {
        turn_gain: 0.0,
        slip_yaw: 0.0,
    };
}

impl Default for SurfaceContact {
    /// The friction coefficient of a plastic shell on a plastic wall, ≈ 0.5 (docs/world.md,
    /// "Contact").
    fn default() -> Self {
        SurfaceContact {
            turn_gain: 0.5,
            slip_yaw: SLIP_YAW,
        }
    }
}

/// Pushes overlapping bodies apart and keeps them out of the walls and obstacles (see the
/// module documentation); a body pushed out of a static surface also turns toward the
/// surface's tangent by `contact.turn_gain · depth / radius` (never past the tangent) and by
/// its wheels' random slip (`contact.slip_yaw`, drawn from `rng`).
pub fn resolve_overlaps(
    arena: &Arena,
    obstacles: &[Obstacle],
    contact: SurfaceContact,
    rng: &mut Rng,
    poses: &mut [Pose],
) {
    let d2 = ROBOT_DIAMETER_MM * ROBOT_DIAMETER_MM;
    for _ in 0..RESOLVE_ITERATIONS {
        let mut moved = false;
        for j in 1..poses.len() {
            for i in 0..j {
                let (dx, dy) = (poses[j].x_mm - poses[i].x_mm, poses[j].y_mm - poses[i].y_mm);
                let dd = dx * dx + dy * dy;
                if dd >= d2 {
                    continue;
                }
                let d = dd.sqrt();
                // Coincident centres: separate along x, lower index to the left.
                let (ux, uy) = if d > 1e-9 {
                    (dx / d, dy / d)
                } else {
                    (1.0, 0.0)
                };
                let push = 0.5 * (ROBOT_DIAMETER_MM - d);
                poses[i].x_mm -= push * ux;
                poses[i].y_mm -= push * uy;
                poses[j].x_mm += push * ux;
                poses[j].y_mm += push * uy;
                moved = true;
            }
        }
        for p in poses.iter_mut() {
            moved |= push_out_of_statics(arena, obstacles, contact, rng, p);
        }
        if !moved {
            break;
        }
    }
}

/// Moves `p` out of every wall and obstacle it overlaps (along the surface's normal) and turns
/// it as `contact` says; whether it moved.
fn push_out_of_statics(
    arena: &Arena,
    obstacles: &[Obstacle],
    contact: SurfaceContact,
    rng: &mut Rng,
    p: &mut Pose,
) -> bool {
    let r = ROBOT_RADIUS_MM;
    let (hx, hy) = ((arena.size_x_mm - r).max(r), (arena.size_y_mm - r).max(r));
    // Walls: the centre is clamped exactly (a body at rest against a wall stays at one
    // radius), then turned by the depth it had.
    let (x, y) = (p.x_mm.clamp(r, hx), p.y_mm.clamp(r, hy));
    let moved = x != p.x_mm || y != p.y_mm;
    let (dx, dy) = (x - p.x_mm, y - p.y_mm);
    p.x_mm = x;
    p.y_mm = y;
    let mut blocked = dx.abs() + dy.abs();
    if dx != 0.0 {
        turn_along(p, dx.abs(), (dx.signum(), 0.0), contact);
    }
    if dy != 0.0 {
        turn_along(p, dy.abs(), (0.0, dy.signum()), contact);
    }
    let mut moved = moved;
    for o in obstacles {
        let (dx, dy) = (p.x_mm - o.x_mm, p.y_mm - o.y_mm);
        let d = dx.hypot(dy);
        let depth = o.radius_mm + r - d;
        if depth > 0.0 {
            let n = if d > 1e-9 {
                (dx / d, dy / d)
            } else {
                (1.0, 0.0)
            };
            p.x_mm += depth * n.0;
            p.y_mm += depth * n.1;
            turn_along(p, depth, n, contact);
            blocked += depth;
            moved = true;
        }
    }
    if contact.slip_yaw > 0.0 && blocked > 0.0 {
        let slip_mm = f64::from(rng.normal()) * contact.slip_yaw * blocked;
        p.heading_deg = wrap_deg(p.heading_deg + (slip_mm / TRACK_MM).to_degrees());
    }
    moved
}

/// Turns `p`, just pushed `depth` out of a surface along its unit normal `n` (pointing away
/// from the surface), toward the surface's tangent.
fn turn_along(p: &mut Pose, depth: f64, n: (f64, f64), contact: SurfaceContact) {
    if contact.turn_gain <= 0.0 {
        return;
    }
    let (fx, fy) = p.forward();
    let into = -(fx * n.0 + fy * n.1); // cos of the angle to the inward normal
    if into <= 0.0 {
        return; // facing away: the surface only stops the body
    }
    // The tangent on the heading's side: the heading with its normal part removed.
    let (tx, ty) = (fx + into * n.0, fy + into * n.1);
    if tx.hypot(ty) < 1e-9 {
        return; // square on: no sliding, no friction torque (an unstable balance)
    }
    let to_tangent = wrap_deg(ty.atan2(tx).to_degrees() - p.heading_deg);
    let turn = (contact.turn_gain * depth / ROBOT_RADIUS_MM).to_degrees();
    p.heading_deg = wrap_deg(p.heading_deg + turn.min(to_tangent.abs()) * to_tangent.signum());
}

/// What a robot met.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Other {
    /// Another robot, by index.
    Robot(usize),
    /// The arena wall.
    Wall,
}

/// Kinds of counted events.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    /// An encounter episode began.
    Encounter,
    /// A collision episode began.
    Collision,
    /// A physical wall contact began (robot–wall only).
    WallTouch,
}

/// One counted event, for plots and logs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactEvent {
    /// Simulated time, s.
    pub time_s: f64,
    /// What began.
    pub kind: EventKind,
    /// The robot (for a robot pair, the lower index).
    pub robot: usize,
    /// The other body.
    pub other: Other,
    /// Where: midway between the two centres, or the robot's centre for the wall, mm.
    pub x_mm: f64,
    /// See `x_mm`.
    pub y_mm: f64,
}

/// Counts of one kind of pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Tally {
    /// Encounter episodes.
    pub encounters: u64,
    /// Collision episodes.
    pub collisions: u64,
    /// Encounters during which at least one collision began.
    pub collided_encounters: u64,
}

impl Tally {
    /// Encounters without a collision / encounters; `None` without encounters.
    pub fn success_rate(&self) -> Option<f64> {
        (self.encounters > 0).then(|| {
            (self.encounters - self.collided_encounters.min(self.encounters)) as f64
                / self.encounters as f64
        })
    }

    /// The sum of two tallies.
    pub fn plus(&self, other: &Tally) -> Tally {
        Tally {
            encounters: self.encounters + other.encounters,
            collisions: self.collisions + other.collisions,
            collided_encounters: self.collided_encounters + other.collided_encounters,
        }
    }
}

/// All counts of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ContactCounts {
    /// Robot pairs.
    pub robot_robot: Tally,
    /// Robots and the wall (paper's threshold).
    pub robot_wall: Tally,
    /// Physical robot–wall contact episodes.
    pub wall_touches: u64,
}

impl ContactCounts {
    /// Robot–robot and robot–wall together.
    pub fn total(&self) -> Tally {
        self.robot_robot.plus(&self.robot_wall)
    }

    /// Success rate over all encounters.
    pub fn success_rate(&self) -> Option<f64> {
        self.total().success_rate()
    }
}

/// Episode state of one pair.
#[derive(Debug, Clone, Copy, Default)]
struct Episode {
    encounter: bool,
    collided: bool,
    collision: bool,
    touch: bool,
}

/// What began in one update of an episode.
#[derive(Debug, Clone, Copy, Default)]
struct Began {
    encounter: bool,
    collision: bool,
    first_collision: bool,
    touch: bool,
}

impl Episode {
    fn update(&mut self, d: f64, encounter: f64, collision: f64, touch: Option<f64>) -> Began {
        let h = EPISODE_HYSTERESIS_MM;
        let mut b = Began::default();
        if !self.encounter && d < encounter {
            *self = Episode {
                encounter: true,
                collided: false,
                ..*self
            };
            b.encounter = true;
        } else if self.encounter && d > encounter + h {
            self.encounter = false;
        }
        if !self.collision && d < collision {
            self.collision = true;
            b.collision = true;
            if self.encounter && !self.collided {
                self.collided = true;
                b.first_collision = true;
            }
        } else if self.collision && d > collision + h {
            self.collision = false;
        }
        if let Some(t) = touch {
            if !self.touch && d < t {
                self.touch = true;
                b.touch = true;
            } else if self.touch && d > t + h {
                self.touch = false;
            }
        }
        b
    }
}

/// Counts encounters, collisions and wall touches as bodies move (see the module
/// documentation). Feed it every physics step with [`ContactTracker::observe`].
#[derive(Debug, Clone, Default)]
pub struct ContactTracker {
    /// `pairs[j][i]` for robots `i < j`.
    pairs: Vec<Vec<Episode>>,
    walls: Vec<Episode>,
    counts: ContactCounts,
    events: Vec<ContactEvent>,
}

impl ContactTracker {
    /// A tracker with nothing counted.
    pub fn new() -> Self {
        ContactTracker::default()
    }

    /// Updates every pair's episodes with the bodies at `poses` at `time_s`. The number of
    /// bodies may grow between calls (new bodies start with no episode).
    pub fn observe(&mut self, time_s: f64, arena: &Arena, obstacles: &[Obstacle], poses: &[Pose]) {
        while self.pairs.len() < poses.len() {
            let j = self.pairs.len();
            self.pairs.push(vec![Episode::default(); j]);
            self.walls.push(Episode::default());
        }
        for j in 1..poses.len() {
            for i in 0..j {
                let (a, b) = (&poses[i], &poses[j]);
                let d = a.distance_to(b);
                let began = self.pairs[j][i].update(
                    d,
                    ROBOT_ENCOUNTER_DISTANCE_MM,
                    ROBOT_COLLISION_DISTANCE_MM,
                    None,
                );
                let at = (0.5 * (a.x_mm + b.x_mm), 0.5 * (a.y_mm + b.y_mm));
                record(
                    &mut self.counts.robot_robot,
                    &mut self.events,
                    began,
                    (time_s, i, Other::Robot(j), at),
                );
            }
        }
        for (i, p) in poses.iter().enumerate() {
            let d = static_distance(arena, obstacles, p.x_mm, p.y_mm);
            let began = self.walls[i].update(
                d,
                WALL_ENCOUNTER_DISTANCE_MM,
                WALL_COLLISION_DISTANCE_MM,
                Some(WALL_TOUCH_DISTANCE_MM),
            );
            if began.touch {
                self.counts.wall_touches += 1;
                self.events.push(ContactEvent {
                    time_s,
                    kind: EventKind::WallTouch,
                    robot: i,
                    other: Other::Wall,
                    x_mm: p.x_mm,
                    y_mm: p.y_mm,
                });
            }
            record(
                &mut self.counts.robot_wall,
                &mut self.events,
                began,
                (time_s, i, Other::Wall, (p.x_mm, p.y_mm)),
            );
        }
    }

    /// The counts so far (ongoing episodes included).
    pub fn counts(&self) -> ContactCounts {
        self.counts
    }

    /// Every event so far, in order.
    pub fn events(&self) -> &[ContactEvent] {
        &self.events
    }

    /// Whether robots `i` and `j` are in a collision episode now.
    pub fn in_collision(&self, i: usize, j: usize) -> bool {
        let (i, j) = (i.min(j), i.max(j));
        self.pairs
            .get(j)
            .and_then(|row| row.get(i))
            .is_some_and(|e| e.collision)
    }
}

fn record(
    tally: &mut Tally,
    events: &mut Vec<ContactEvent>,
    began: Began,
    (time_s, robot, other, (x_mm, y_mm)): (f64, usize, Other, (f64, f64)),
) {
    let mut push = |kind| {
        events.push(ContactEvent {
            time_s,
            kind,
            robot,
            other,
            x_mm,
            y_mm,
        })
    };
    if began.encounter {
        tally.encounters += 1;
        push(EventKind::Encounter);
    }
    if began.collision {
        tally.collisions += 1;
        push(EventKind::Collision);
    }
    if began.first_collision {
        tally.collided_encounters += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thresholds_nest() {
        assert_eq!(ROBOT_ENCOUNTER_DISTANCE_MM, 126.0);
        assert_eq!(WALL_ENCOUNTER_DISTANCE_MM, 105.0);
        const {
            assert!(
                ROBOT_COLLISION_DISTANCE_MM + EPISODE_HYSTERESIS_MM < ROBOT_ENCOUNTER_DISTANCE_MM
            );
            assert!(
                WALL_COLLISION_DISTANCE_MM + EPISODE_HYSTERESIS_MM < WALL_ENCOUNTER_DISTANCE_MM
            );
            assert!(WALL_TOUCH_DISTANCE_MM < WALL_COLLISION_DISTANCE_MM);
        }
    }

    #[test]
    fn hovering_at_a_threshold_counts_once() {
        let arena = Arena::default();
        let mut t = ContactTracker::new();
        for k in 0..100 {
            let d = 41.0 + 4.0 * ((k as f64) * 0.7).sin(); // 37..45: in and out of 42
            let poses = [
                Pose::new(500.0, 450.0, 0.0),
                Pose::new(500.0 + d, 450.0, 0.0),
            ];
            t.observe(k as f64, &arena, &[], &poses);
        }
        let c = t.counts().robot_robot;
        assert_eq!(
            (c.encounters, c.collisions, c.collided_encounters),
            (1, 1, 1)
        );
        assert_eq!(c.success_rate(), Some(0.0));
        // Leaving and coming back is a new episode.
        let far = [Pose::new(500.0, 450.0, 0.0), Pose::new(800.0, 450.0, 0.0)];
        t.observe(101.0, &arena, &[], &far);
        let near = [Pose::new(500.0, 450.0, 0.0), Pose::new(600.0, 450.0, 0.0)];
        t.observe(102.0, &arena, &[], &near);
        let c = t.counts();
        assert_eq!(c.robot_robot.encounters, 2);
        assert_eq!(c.robot_robot.success_rate(), Some(0.5));
        assert_eq!(c.robot_wall, Tally::default());
        assert!(!t.in_collision(0, 1) && !t.in_collision(1, 0));
    }

    #[test]
    fn resolution_separates_and_contains() {
        let arena = Arena::new(200.0, 200.0);
        let mut p = [
            Pose::new(100.0, 100.0, 0.0),
            Pose::new(100.0, 100.0, 0.0),
            Pose::new(5.0, 250.0, 0.0),
        ];
        resolve_overlaps(&arena, &[], SurfaceContact::RIGID, &mut Rng::new(1), &mut p);
        assert!((p[0].distance_to(&p[1]) - 42.0).abs() < 1e-9);
        assert!(p[0].x_mm < p[1].x_mm);
        assert_eq!((p[2].x_mm, p[2].y_mm), (21.0, 179.0));
    }
}

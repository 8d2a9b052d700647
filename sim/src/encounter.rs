//! The open-loop encounter behind experiments 2 (`evasion`) and 3 (`two-threats`), paper
//! Sec. III-B, Fig. 4: a tested robot stands at a fixed place, one or more obstacle robots start
//! at given bearings and distances from it and drive straight at its starting point at constant
//! speeds; the tested robot's controller takes over at its first alert.
//!
//! # Geometry
//!
//! The tested robot starts at [`TESTED_START`] facing +x (towards the far, right-hand wall of
//! the `lab` arena, 750 mm away), so that obstacles up to 550 mm away at ±35° fit in the arena
//! and it has 450 mm of floor behind it to escape into. That is the design; the experiment
//! puts its stage ([`tested_stage`]: the obstacles' paths, the tested robot and
//! [`ESCAPE_ROOM_MM`] behind it) where it fits in its world ([`super::stage`]), which in the
//! `lab` is there. Obstacle `k` starts `distance_mm` away at
//! `bearing_deg` (positive = right of the tested robot's heading, inside its 70° field of view),
//! faces the tested robot's start and drives at `speed_mm_s` until its centre reaches that point,
//! where it stops: it does not chase an evader. The trial lasts until the last obstacle has
//! arrived plus [`AFTER_ARRIVAL_S`].
//!
//! # Outcome
//!
//! - **collided**: a robot–robot collision (centre distance < 42 mm, the arena's counting)
//!   between the tested robot and an obstacle at any time of the trial;
//! - **escape turn**: the direction the tested robot chose, as in the paper's Fig. 4d: its
//!   heading change from the start to the end of its first takeoff (the first frame its
//!   controller leaves the state it entered at its first alert, or [`TURN_WINDOW_S`] after the
//!   first alert if it stays). It turned left or right when the change exceeds [`TURN_MIN_DEG`], else it took no
//!   side. Where it ended (`lateral_mm`, its displacement along its initial right-hand
//!   direction) is reported too, but a collision can push a robot anywhere, so the side is the
//!   chosen turn.

use alvs_tasks::Params;

use super::stage::{Shape, Stage};
use crate::controller::{Approach, Controller, HoldUntilAlert};
use crate::{
    Command, ContactEvent, EventKind, GyroParams, Kind, MotorParams, Other, Pose, Rng, Seen,
    SensorNoise, Sim, World, FRAME_DT_S,
};

/// Start distance of `cargo alvs evasion`'s obstacle (and the virtual board's closed-loop
/// evasion), mm (centre to centre): about 12 robot diameters, so the
/// obstacle first appears about 7 pixels wide and looms for several seconds.
pub const DEFAULT_DISTANCE_MM: f64 = 500.0;
/// Speed of `cargo alvs evasion`'s obstacle, mm/s: the paper's robots move at about 10 cm/s. (Slower or faster
/// obstacles do not change the outcome much: the model alerts when the obstacle is 100–150 mm
/// away whatever its speed; see docs/experiments.md.)
pub const DEFAULT_SPEED_MM_S: f64 = 100.0;
/// Where the tested robot starts (x mm, y mm, heading °) as designed, in the `lab` arena.
pub const TESTED_START: (f64, f64, f64) = (450.0, 450.0, 0.0);
/// Floor the tested robot keeps free behind it to escape into, mm, within ±35° of straight
/// back (where the escape from an obstacle in its view goes): one second of the escape at its
/// top speed, 200 mm/s (`FsmParams::max_escape_mm_s`), the least an escape lasts.
pub const ESCAPE_ROOM_MM: f64 = 200.0;
/// Simulated time after the last obstacle's arrival, s: long enough for a takeoff and an
/// escape to play out.
pub const AFTER_ARRIVAL_S: f64 = 2.0;
/// A turn smaller than this, degrees, takes no side.
pub const TURN_MIN_DEG: f64 = 5.0;
/// The escape turn is read when the first takeoff ends, or this long after the first alert.
pub const TURN_WINDOW_S: f64 = 1.5;
/// Camera frames between two trail samples (10 per second).
pub const TRAIL_EVERY: u64 = 3;

/// Random stream of the tested controller's seed (LGMD2's random turns).
const CONTROLLER_STREAM: u64 = 0x007e_57ed;

/// One obstacle robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Threat {
    /// Bearing of its start from the tested robot, degrees, positive = right.
    pub bearing_deg: f64,
    /// Centre distance of its start from the tested robot's centre, mm.
    pub distance_mm: f64,
    /// Its constant speed, mm/s.
    pub speed_mm_s: f64,
}

impl Threat {
    /// Frames it drives before it reaches the tested robot's start.
    pub fn frames_to_arrive(&self) -> u64 {
        (self.distance_mm / self.speed_mm_s / FRAME_DT_S).ceil() as u64
    }

    /// Its start pose: `distance_mm` from `tested` at `bearing_deg`, facing `tested`.
    pub fn start_pose(&self, tested: &Pose) -> Pose {
        let b = self.bearing_deg.to_radians();
        let (x, y) = tested.offset(self.distance_mm * b.cos(), self.distance_mm * b.sin());
        let towards = (tested.y_mm - y).atan2(tested.x_mm - x).to_degrees();
        Pose::new(x, y, towards)
    }
}

/// Which way the tested robot turned to escape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// Turned left by more than [`TURN_MIN_DEG`].
    Left,
    /// Turned right by more than [`TURN_MIN_DEG`].
    Right,
    /// Neither.
    None,
}

impl Side {
    /// The side of a heading change (negative = left).
    pub fn of(turn_deg: f64) -> Side {
        if turn_deg < -TURN_MIN_DEG {
            Side::Left
        } else if turn_deg > TURN_MIN_DEG {
            Side::Right
        } else {
            Side::None
        }
    }

    /// The side away from a threat at `bearing_deg` (`None` for a threat dead ahead).
    pub fn away_from(bearing_deg: f64) -> Side {
        if bearing_deg > 0.0 {
            Side::Left
        } else if bearing_deg < 0.0 {
            Side::Right
        } else {
            Side::None
        }
    }
}

/// One encounter to run.
#[derive(Debug, Clone)]
pub struct Encounter {
    /// The tested robot's controller.
    pub kind: Kind,
    /// The obstacles.
    pub threats: Vec<Threat>,
    /// Seed of the noise and of the controller.
    pub seed: u64,
    /// ALVS model parameters.
    pub params: Params,
    /// Motion parameters of the controllers (`--fsm NAME=VALUE`).
    pub fsm: alvs_tasks::model::fsm::FsmParams,
    /// The world, its walls included.
    pub world: World,
    /// Where the tested robot starts ([`tested_start`] as designed; the experiment's
    /// placement of its stage in `world`).
    pub start: Pose,
    /// Realistic motors, gyro and camera (as the arena); `false` = ideal.
    pub noise: bool,
    /// The tested robot's camera exposure as a fraction of the 33 ms frame period (0 =
    /// instantaneous snapshots, the default; 1 = the whole period): motion during the exposure
    /// blurs the picture ([`crate::SensorNoise::exposure`]).
    pub exposure: f32,
    /// How the tested robot's camera gain moves from frame to frame ([`crate::GainModel`]).
    pub gain: crate::GainModel,
    /// Record a [`TraceRow`] per frame.
    pub trace: bool,
}

impl Encounter {
    /// The encounter every trial of a run shares, with the tested robot's controller, the
    /// threats and the seed still to set (`Encounter { kind, threats, seed, ..base }`): the
    /// staged world and start, the model, realistic noise, the camera's `exposure` and `gain`,
    /// `trace`.
    pub fn staged(
        staged: super::stage::Staged,
        params: Params,
        fsm: alvs_tasks::model::fsm::FsmParams,
        exposure: f32,
        gain: crate::GainModel,
        trace: bool,
    ) -> Encounter {
        Encounter {
            kind: Kind::Alvs,
            threats: Vec::new(),
            seed: 0,
            params,
            fsm,
            world: staged.world,
            start: staged.placement.pose,
            noise: true,
            exposure,
            gain,
            trace,
        }
    }
}

/// Where an encounter experiment ran, as its report says it: the world, the background its
/// walls showed (`None`: their own), the seed and where the tested robot stood.
#[derive(Debug, Clone)]
pub struct Setting {
    /// The world.
    pub world: crate::BuiltinWorld,
    /// The background given, if any.
    pub background: Option<String>,
    /// The seed.
    pub seed: u64,
    /// Where the stage stood.
    pub placement: super::stage::Placement,
}

impl Setting {
    /// `config` (a JSON object) with `seed`, `world`, `background` and `start` (the
    /// placement) added.
    pub fn json(&self, mut config: serde_json::Value) -> serde_json::Value {
        if let Some(m) = config.as_object_mut() {
            m.insert("seed".into(), self.seed.into());
            m.insert("world".into(), self.world.label().into());
            let background = self.world.background(self.background.as_deref());
            m.insert("background".into(), background.into());
            m.insert("start".into(), self.placement.json());
        }
        config
    }

    /// The end of the table's title line (`world W, background B, seed S, T s`) and the
    /// line after it, where the tested robot stood.
    pub fn title(&self, wall_clock_s: f64) -> String {
        format!(
            "world {}, background {}, seed {}, {wall_clock_s:.1} s\ntested robot {}\n",
            self.world.label(),
            self.world.background(self.background.as_deref()),
            self.seed,
            self.placement.describe()
        )
    }
}

/// A trial's outcome and its `--trace` rows with their CSV leading fields. Only the outcome
/// goes into a shard file (a sharded run keeps no trace).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Traced<T> {
    /// What the experiment reports of the trial.
    pub outcome: T,
    /// The leading CSV fields and the rows (none unless the run traces).
    #[serde(skip)]
    pub trace: (String, Vec<TraceRow>),
}

/// One camera frame of the tested robot, for `--trace` (CSV: [`TRACE_HEADER`]).
#[derive(Debug, Clone, PartialEq)]
pub struct TraceRow {
    /// Camera frame, from 0.
    pub frame: u64,
    /// Pose after the frame's physics.
    pub pose: Pose,
    /// Controller state.
    pub state: &'static str,
    /// The controller's alert.
    pub alert: bool,
    /// What its perception reported.
    pub seen: Seen,
    /// Centre distance to each obstacle, mm.
    pub distance_mm: Vec<f64>,
}

macro_rules! frame_header {
    () => {
        "frame,t_s,x_mm,y_mm,heading_deg,state,alert,short_mode,response,threat_x,fields"
    };
}

/// The columns every frame-by-frame trace shares ([`frame_csv`]).
pub const FRAME_HEADER: &str = frame_header!();

/// Columns of a trace row ([`TraceRow::csv`]), after the caller's own leading columns.
pub const TRACE_HEADER: &str = concat!(frame_header!(), ",distance_mm");

/// One robot's camera frame `frame` as the CSV fields of [`FRAME_HEADER`]: its pose after
/// the frame's physics and what its controller did and saw.
pub fn frame_csv(frame: u64, pose: &Pose, state: &str, alert: bool, seen: &Seen) -> String {
    format!(
        "{},{:.4},{:.1},{:.1},{:.1},{},{},{},{},{},{}",
        frame,
        (frame + 1) as f64 * FRAME_DT_S,
        pose.x_mm,
        pose.y_mm,
        pose.heading_deg,
        state,
        u8::from(alert),
        u8::from(seen.short_mode),
        seen.response,
        seen.threat_x.map_or(String::new(), |x| format!("{x:.1}")),
        seen.fields,
    )
}

impl TraceRow {
    /// The row as CSV fields ([`TRACE_HEADER`]); distances to several obstacles are joined by `;`.
    pub fn csv(&self) -> String {
        let d: Vec<String> = self.distance_mm.iter().map(|d| format!("{d:.1}")).collect();
        let head = frame_csv(self.frame, &self.pose, self.state, self.alert, &self.seen);
        format!("{head},{}", d.join(";"))
    }
}

impl std::fmt::Display for TraceRow {
    /// [`TraceRow::csv`].
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.csv())
    }
}

/// What happened.
#[derive(Debug, Clone, PartialEq)]
pub struct EncounterResult {
    /// The tested robot collided with obstacle `k` (one flag per threat).
    pub collided_with: Vec<bool>,
    /// Its final displacement to its initial right, mm (negative = left).
    pub lateral_mm: f64,
    /// Its final displacement along its initial heading, mm.
    pub forward_mm: f64,
    /// Its heading change from the start to the end of its first takeoff, degrees (positive =
    /// turned right; 0 if it never alerted), unwrapped: a turn of 182° to the left is −182°,
    /// not +178°.
    pub escape_turn_deg: f64,
    /// Simulated time of its first alert, s.
    pub first_alert_s: Option<f64>,
    /// The state its first alert put it in (ALVS: `long_takeoff`, or `short_takeoff`, the γ
    /// path); `None` if it never alerted.
    pub first_reaction: Option<&'static str>,
    /// Smallest centre distance to each obstacle, mm (after the physics resolved overlaps).
    pub min_distance_mm: Vec<f64>,
    /// Camera frames simulated.
    pub frames: u64,
    /// Positions of the tested robot (index 0) and the obstacles, every [`TRAIL_EVERY`]
    /// frames, mm.
    pub trails: Vec<Vec<(f64, f64)>>,
    /// Final poses (tested robot first).
    pub end_poses: Vec<Pose>,
    /// The tested robot frame by frame (empty unless [`Encounter::trace`]).
    pub trace: Vec<TraceRow>,
}

impl EncounterResult {
    /// It collided with any obstacle.
    pub fn collided(&self) -> bool {
        self.collided_with.iter().any(|&c| c)
    }

    /// The side it turned to.
    pub fn side(&self) -> Side {
        Side::of(self.escape_turn_deg)
    }
}

/// The heading change since a start, unwrapped frame by frame (a frame turns far less than
/// 180°), so that a turn past 180° keeps the side it turned to: 182° to the left is −182°.
#[derive(Debug, Clone, Copy)]
pub struct Turned {
    /// The change so far, degrees, positive = right.
    pub total_deg: f64,
    last_deg: f64,
}

impl Turned {
    /// Nothing turned yet, facing `start_deg`.
    pub fn new(start_deg: f64) -> Self {
        Turned {
            total_deg: 0.0,
            last_deg: start_deg,
        }
    }

    /// The next frame's heading.
    pub fn observe(&mut self, heading_deg: f64) {
        self.total_deg += crate::world::wrap_deg(heading_deg - self.last_deg);
        self.last_deg = heading_deg;
    }
}

/// Writes traces as CSV: a header `lead_header,`[`TRACE_HEADER`], then every trial's rows,
/// each prefixed by that trial's leading fields (e.g. `alvs,-35.00`).
pub fn write_trace(
    path: &std::path::Path,
    lead_header: &str,
    trials: &[(String, Vec<TraceRow>)],
) -> anyhow::Result<()> {
    write_csv(
        path,
        &format!("{lead_header},{TRACE_HEADER}"),
        trials
            .iter()
            .map(|(lead, rows)| (lead.as_str(), rows.as_slice())),
    )
}

/// Writes a CSV trace: `header`, then per trial each of its lines prefixed by the trial's
/// leading fields (`lead,line`). Every trace of the experiments is written by it.
pub fn write_csv<'a, L: std::fmt::Display + 'a>(
    path: &std::path::Path,
    header: &str,
    trials: impl IntoIterator<Item = (&'a str, &'a [L])>,
) -> anyhow::Result<()> {
    use anyhow::Context;
    use std::io::Write;
    let file =
        std::fs::File::create(path).with_context(|| format!("cannot write {}", path.display()))?;
    let mut out = std::io::BufWriter::new(file);
    let write = || -> std::io::Result<()> {
        writeln!(out, "{header}")?;
        for (lead, lines) in trials {
            for line in lines {
                writeln!(out, "{lead},{line}")?;
            }
        }
        out.flush()
    };
    write().with_context(|| format!("cannot write {}", path.display()))
}

/// The tested robot's start pose as designed (in the `lab`).
pub fn tested_start() -> Pose {
    Pose::new(TESTED_START.0, TESTED_START.1, TESTED_START.2)
}

/// The stage of an encounter whose obstacles drive along `approaches` (shapes in the tested
/// robot's frame): those, the tested robot standing, and [`ESCAPE_ROOM_MM`] behind it within
/// ±35° of straight back.
pub fn tested_stage(approaches: impl IntoIterator<Item = Shape>) -> Stage {
    let mut shapes: Vec<Shape> = approaches.into_iter().collect();
    shapes.push(Shape::Path {
        from: (0.0, 0.0),
        to: (0.0, 0.0),
    });
    shapes.push(Shape::Sector {
        mid_deg: 180.0,
        half_deg: 35.0,
        radius_mm: ESCAPE_ROOM_MM,
    });
    Stage { shapes }
}

/// The path of an obstacle starting `distance_mm` away at `bearing_deg` towards the tested
/// robot, in its frame.
pub fn approach_path(bearing_deg: f64, distance_mm: f64) -> Shape {
    let b = bearing_deg.to_radians();
    Shape::Path {
        from: (distance_mm * b.cos(), distance_mm * b.sin()),
        to: (0.0, 0.0),
    }
}

/// Camera frames an encounter with `threats` lasts.
pub fn frames_of(threats: &[Threat]) -> u64 {
    let arrive = threats
        .iter()
        .map(Threat::frames_to_arrive)
        .max()
        .unwrap_or(0);
    arrive + (AFTER_ARRIVAL_S / FRAME_DT_S).round() as u64
}

/// Runs one encounter and keeps what the experiment reports of it (`outcome`) with its
/// trace, whose CSV rows `lead` leads; `progress` is told of simulated frames.
pub fn run_traced<T>(
    e: &Encounter,
    lead: String,
    progress: &(dyn Fn(u64) + Sync),
    outcome: impl FnOnce(&EncounterResult) -> T,
) -> Traced<T> {
    let r = run(e, progress);
    Traced {
        outcome: outcome(&r),
        trace: (lead, r.trace),
    }
}

/// Runs one encounter; `progress` is told of simulated frames.
pub fn run(e: &Encounter, progress: &(dyn Fn(u64) + Sync)) -> EncounterResult {
    let controller_seed = Rng::new(e.seed).fork(CONTROLLER_STREAM).next_u64();
    run_with(e, e.kind.make(e.params, e.fsm, controller_seed), progress)
}

/// [`run`] with the tested robot's controller given (e.g. the firmware on the virtual board);
/// `e.kind`, `e.params` and `e.fsm` are then not used.
pub fn run_with(
    e: &Encounter,
    controller: Box<dyn Controller>,
    progress: &(dyn Fn(u64) + Sync),
) -> EncounterResult {
    let mut sim = Sim::new(&e.world, e.seed);
    let (motor, gyro, mut noise) = crate::robot_noise(e.noise);
    noise.exposure = e.exposure;
    if e.noise {
        e.gain.apply(&mut noise);
    }
    let start = e.start;
    let tested = HoldUntilAlert::new(controller);
    sim.add(start, Box::new(tested), motor, gyro, noise);
    for t in &e.threats {
        let obstacle = Approach {
            speed_mm_s: t.speed_mm_s as f32,
            frames_left: t.frames_to_arrive().min(u64::from(u32::MAX)) as u32,
        };
        // Obstacles drive ideally: they are the stimulus, the same in every trial.
        sim.add(
            t.start_pose(&start),
            Box::new(obstacle),
            MotorParams::ideal(),
            GyroParams::ideal(),
            SensorNoise::default(),
        );
    }
    let frames = frames_of(&e.threats);
    let n = e.threats.len();
    let mut min_distance = vec![f64::INFINITY; n];
    let mut trails: Vec<Vec<(f64, f64)>> = sim
        .physics
        .poses()
        .iter()
        .map(|p| vec![(p.x_mm, p.y_mm)])
        .collect();
    let mut first_alert = None;
    let mut takeoff_state = "";
    let mut escape_turn = None;
    let mut turned = Turned::new(start.heading_deg);
    let window = (TURN_WINDOW_S / FRAME_DT_S).round() as u64;
    let mut trace = Vec::new();
    for f in 0..frames {
        let mut tested = Command::default();
        sim.step_with(|i, _, cmd| {
            if i == 0 {
                if cmd.alert && first_alert.is_none() {
                    first_alert = Some(f);
                    takeoff_state = cmd.state;
                }
                tested = *cmd;
            }
        });
        let state = tested.state;
        let poses = sim.physics.poses();
        if e.trace {
            trace.push(TraceRow {
                frame: f,
                pose: poses[0],
                state,
                alert: tested.alert,
                seen: tested.seen,
                distance_mm: poses[1..].iter().map(|p| poses[0].distance_to(p)).collect(),
            });
        }
        turned.observe(poses[0].heading_deg);
        if let (Some(a), None) = (first_alert, escape_turn) {
            if state != takeoff_state || f >= a + window {
                escape_turn = Some(turned.total_deg);
            }
        }
        for (k, d) in min_distance.iter_mut().enumerate() {
            *d = d.min(poses[0].distance_to(&poses[k + 1]));
        }
        if (f + 1) % TRAIL_EVERY == 0 {
            for (trail, p) in trails.iter_mut().zip(poses) {
                trail.push((p.x_mm, p.y_mm));
            }
        }
        if (f + 1) % 30 == 0 {
            progress(30);
        }
    }
    progress(frames % 30);
    let mut collided_with = vec![false; n];
    for ev in sim.physics.contacts().events() {
        if let ContactEvent {
            kind: EventKind::Collision,
            robot: 0,
            other: Other::Robot(j),
            ..
        } = *ev
        {
            collided_with[j - 1] = true;
        }
    }
    let end = sim.physics.poses()[0];
    let (dx, dy) = (end.x_mm - start.x_mm, end.y_mm - start.y_mm);
    let (fx, fy) = start.forward();
    let (rx, ry) = start.right();
    EncounterResult {
        collided_with,
        lateral_mm: dx * rx + dy * ry,
        forward_mm: dx * fx + dy * fy,
        escape_turn_deg: escape_turn.unwrap_or(if first_alert.is_some() {
            turned.total_deg
        } else {
            0.0
        }),
        first_alert_s: first_alert.map(|f| (f + 1) as f64 * FRAME_DT_S),
        first_reaction: first_alert.map(|_| takeoff_state),
        min_distance_mm: min_distance,
        frames,
        trails,
        end_poses: sim.physics.poses().to_vec(),
        trace,
    }
}

#[cfg(test)]
mod turned_tests {
    use super::Turned;

    #[test]
    fn a_turn_past_180_keeps_its_side() {
        // evasion, seed 2, 8.75°: the robot turned left from −100° through ±180° to 78°, 182°
        // in all (from −106.9°, 175°): the wrapped difference called it +178° to the right
        let mut t = Turned::new(-106.9);
        for h in [
            -122.1, -141.7, -163.6, 173.5, 150.2, 126.3, 104.7, 88.3, 78.3,
        ] {
            t.observe(h);
        }
        assert!((t.total_deg - -174.8).abs() < 1e-9, "{}", t.total_deg);
        let mut right = Turned::new(170.0);
        right.observe(-170.0);
        assert!((right.total_deg - 20.0).abs() < 1e-9);
    }
}

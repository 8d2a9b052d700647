//! Experiment 4, `arena` (paper Sec. III-C, Figs. 5–6): a few robots run the same controller in
//! the walled arena for minutes; we count their encounters and collisions with each other and
//! with the wall, and the time each spends in each controller state.
//!
//! # Trials
//!
//! One trial is one (controller, background) pair: [`ArenaConfig::robots`] robots, all running
//! that controller, in the default arena ([`World::with_texture`]) whose walls show that
//! background, for [`ArenaConfig::minutes`] of simulated time. Trials are independent and run in
//! parallel; each is a pure function of the configuration, so thread scheduling never changes a
//! number (only `wall_clock_s`).
//!
//! **Pairing.** Every trial of a run starts from the same robot poses ([`start_poses`], drawn
//! from the seed alone) and uses the same simulation seed (motor noise, gyro, camera noise) and
//! the same per-robot controller seeds (LGMD2's random escape turns). ALVS and LGMD2 therefore
//! meet the same initial situation on every background; they part ways only through what their
//! controllers do.
//!
//! **Start poses** are uniform in the arena at least [`START_WALL_CLEARANCE_MM`] from the walls
//! and [`START_SEPARATION_MM`] from each other (centre to centre), with uniform headings: no
//! robot starts inside an encounter (more than two diameters from every other body).
//!
//! # Counting
//!
//! The counts are those of [`crate::arena::contacts`] (collision: centre distance below one
//! diameter, 42 mm, for a robot pair and for a robot and the wall; encounter: bodies within two
//! diameters, surface to surface; success rate = encounters without a collision / encounters;
//! each counted once per episode). Collisions per minute are for the whole arena (all robots
//! together) per simulated minute. Aggregates over backgrounds pool the counts (sums), so an
//! aggregate success rate weighs each encounter equally.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use alvs_tasks::Params;
use anyhow::{bail, ensure, Context, Result};
use serde::Serialize;

use super::encounter;
use super::parallel::default_jobs;
use crate::arena::contacts::{
    EPISODE_HYSTERESIS_MM, ROBOT_ENCOUNTER_DISTANCE_MM, WALL_ENCOUNTER_DISTANCE_MM,
};
use crate::arena::world::ROBOT_RADIUS_MM;
use crate::arena::{
    Arena, EventKind, GyroParams, Kind, MotorParams, Other, Pose, Rng, SensorNoise, Sim, Tally,
    TopDown, WallTexture, World, FRAME_DT_S,
};
use crate::canvas::{colour_cycle, Canvas, Rgb, BLACK, RED, WHITE};

/// The backgrounds of a default run: procedural clutter, vertical stripes and a checkerboard
/// (built in, so a default run needs no file).
pub const DEFAULT_BACKGROUNDS: [&str; 3] = ["clutter:1", "stripes:40", "checker:60"];

/// The paper's success rates (Sec. III-C) for reference in reports.
pub const PAPER_SUCCESS_RATE: [(&str, f64); 2] = [("alvs", 0.961), ("lgmd2", 0.937)];

/// Smallest centre distance between two robots at the start, mm: outside a robot–robot
/// encounter (126 mm) with its hysteresis, i.e. more than two diameters apart.
pub const START_SEPARATION_MM: f64 = ROBOT_ENCOUNTER_DISTANCE_MM + EPISODE_HYSTERESIS_MM;

/// Smallest centre-to-wall distance at the start, mm: outside a robot–wall encounter (105 mm)
/// with its hysteresis.
pub const START_WALL_CLEARANCE_MM: f64 = WALL_ENCOUNTER_DISTANCE_MM + EPISODE_HYSTERESIS_MM;

/// Longest trial accepted, simulated minutes (a week of wall time at worst).
pub const MAX_MINUTES: f64 = 10_000.0;

/// Most lines a `--trace` may hold (robot-frames over all trials): ≈ 1.7 GB of memory and
/// file, 60 times the default run's 324,000.
pub const MAX_TRACE_LINES: u64 = 20_000_000;

/// Typical length of a trace line, bytes (for the messages).
const TRACE_LINE_BYTES: u64 = 85;

/// A robot whose body is within this of a wall, mm, is pressed against it (the physics keeps
/// the centre exactly one radius from a wall it pushes).
pub const WALL_CONTACT_SLACK_MM: f64 = 1.0;

/// Camera frames between two progress reports of a trial (one simulated second).
const PROGRESS_EVERY: u64 = 30;

/// Random stream of the start poses (forked from the seed).
const START_STREAM: u64 = 0x57a7_1e55;
/// Random stream of the controllers' seeds (robot `i` takes sub-stream `i`).
const CONTROLLER_STREAM: u64 = 0xc0_7e01;

/// The paper's success rate for a controller, if it gives one.
pub fn paper_success_rate(controller: &str) -> Option<f64> {
    PAPER_SUCCESS_RATE
        .iter()
        .find(|(n, _)| *n == controller)
        .map(|(_, r)| *r)
}

/// What to run.
#[derive(Debug, Clone)]
pub struct ArenaConfig {
    /// Robots in the arena (all running the trial's controller).
    pub robots: usize,
    /// Simulated minutes per trial.
    pub minutes: f64,
    /// Wall textures, as [`WallTexture::from_spec`] reads them; one trial per background and
    /// controller.
    pub backgrounds: Vec<String>,
    /// Controllers to compare.
    pub controllers: Vec<Kind>,
    /// Seed of everything random (start poses, noise, LGMD2's turns).
    pub seed: u64,
    /// ALVS model parameters (ALVS and swarm).
    pub params: Params,
    /// Motion parameters of the controllers (`--fsm NAME=VALUE`).
    pub fsm: alvs_tasks::model::fsm::FsmParams,
    /// Realistic sensors and motors ([`SensorNoise::typical`], default motor lag and noise,
    /// default gyro); `false` gives ideal ones.
    pub noise: bool,
    /// Keep every robot's frame-by-frame trace ([`Trial::trace`]) for `--trace`.
    pub trace: bool,
}

impl Default for ArenaConfig {
    /// The paper's setting: 3 robots, 10 minutes, 3 backgrounds, ALVS and LGMD2, seed 1, noise.
    fn default() -> Self {
        ArenaConfig {
            robots: 3,
            minutes: 10.0,
            backgrounds: DEFAULT_BACKGROUNDS.iter().map(|s| s.to_string()).collect(),
            controllers: vec![Kind::Alvs, Kind::Lgmd2],
            seed: 1,
            params: Params::default(),
            fsm: alvs_tasks::model::fsm::FsmParams::default(),
            noise: true,
            trace: false,
        }
    }
}

impl ArenaConfig {
    /// Camera frames per trial.
    pub fn frames(&self) -> u64 {
        ((self.minutes * 60.0 / FRAME_DT_S).round() as u64).max(1)
    }

    /// Checks the configuration (backgrounds readable, robots placeable, ...); the error is one
    /// line. [`run`] checks too; this is for failing before anything else starts.
    pub fn validate(&self) -> Result<()> {
        self.prepare().map(|_| ())
    }

    /// Checks the configuration and parses the backgrounds (one error line per problem).
    fn prepare(&self) -> Result<Prepared> {
        ensure!(self.robots >= 1, "--robots must be at least 1");
        ensure!(
            self.minutes.is_finite() && self.minutes > 0.0,
            "--minutes must be a positive number of minutes, got {}",
            self.minutes
        );
        ensure!(
            self.minutes <= MAX_MINUTES,
            "--minutes must be at most {MAX_MINUTES}, got {}",
            self.minutes
        );
        ensure!(!self.backgrounds.is_empty(), "no background to run on");
        ensure!(!self.controllers.is_empty(), "no controller to run");
        self.params
            .validate()
            .map_err(|e| anyhow::anyhow!("invalid model parameters: {e}"))?;
        let mut backgrounds: Vec<(String, WallTexture)> = Vec::new();
        for spec in &self.backgrounds {
            if backgrounds.iter().any(|(s, _)| s == spec) {
                continue;
            }
            let name = spec.split_once(':').map_or(spec.as_str(), |(n, _)| n);
            let known = WallTexture::NAMES.contains(&name);
            if !known && !Path::new(spec).exists() {
                bail!(
                    "--background {spec}: neither plain[:GREY], stripes[:PERIOD_MM], \
                     checker[:SIZE_MM], clutter[:SEED], outdoor[:SEED] nor an existing \
                     PNG/JPEG file"
                );
            }
            let texture =
                WallTexture::from_spec(spec).with_context(|| format!("--background {spec}"))?;
            backgrounds.push((spec.clone(), texture));
        }
        let mut controllers: Vec<Kind> = Vec::new();
        for &k in &self.controllers {
            if !controllers.contains(&k) {
                controllers.push(k);
            }
        }
        if self.trace {
            // the trace is kept in memory until the run ends (trials run in parallel)
            let lines = self
                .frames()
                .saturating_mul(self.robots as u64)
                .saturating_mul((backgrounds.len() * controllers.len()) as u64);
            ensure!(
                lines <= MAX_TRACE_LINES,
                "--trace: {lines} lines (≈ {} MB) is more than the {MAX_TRACE_LINES} a run may \
                 trace; shorten --minutes or trace fewer robots, backgrounds or controllers",
                lines.saturating_mul(TRACE_LINE_BYTES) / 1_000_000
            );
        }
        let arena = World::default().arena;
        let starts = start_poses(&arena, self.robots, self.seed)?;
        let (motor, gyro, noise) = crate::arena::robot_noise(self.noise);
        let root = Rng::new(self.seed).fork(CONTROLLER_STREAM);
        let controller_seeds = (0..self.robots as u64)
            .map(|i| root.fork(i).next_u64())
            .collect();
        Ok(Prepared {
            backgrounds,
            controllers,
            starts,
            controller_seeds,
            motor,
            gyro,
            noise,
            frames: self.frames(),
        })
    }
}

/// A checked configuration.
struct Prepared {
    backgrounds: Vec<(String, WallTexture)>,
    controllers: Vec<Kind>,
    starts: Vec<Pose>,
    controller_seeds: Vec<u64>,
    motor: MotorParams,
    gyro: GyroParams,
    noise: SensorNoise,
    frames: u64,
}

/// `robots` start poses in `arena` for `seed`: uniform positions at least
/// [`START_WALL_CLEARANCE_MM`] from the walls and [`START_SEPARATION_MM`] from each other,
/// uniform headings. Fails (one line) when that many robots do not fit.
pub fn start_poses(arena: &Arena, robots: usize, seed: u64) -> Result<Vec<Pose>> {
    let m = START_WALL_CLEARANCE_MM;
    let sep = START_SEPARATION_MM;
    let (w, h) = (arena.size_x_mm - 2.0 * m, arena.size_y_mm - 2.0 * m);
    let too_many = || {
        anyhow::anyhow!(
            "cannot place {robots} robots in the {} x {} mm arena ({sep} mm apart, {m} mm from \
             the walls); use fewer robots",
            arena.size_x_mm,
            arena.size_y_mm
        )
    };
    if w < 0.0 || h < 0.0 {
        return Err(too_many());
    }
    // Discs of diameter `sep` around the centres fit in the free rectangle grown by sep/2; no
    // packing is denser than the hexagonal one.
    let disc = std::f64::consts::PI * sep * sep / 4.0;
    let most = 0.9069 * (w + sep) * (h + sep) / disc;
    if robots as f64 > most {
        return Err(too_many());
    }
    let root = Rng::new(seed).fork(START_STREAM);
    for attempt in 0..20 {
        let mut rng = root.fork(attempt);
        let mut poses: Vec<Pose> = Vec::with_capacity(robots);
        'robot: while poses.len() < robots {
            for _ in 0..2000 {
                let (x, y) = (m + w * rng.uniform(), m + h * rng.uniform());
                let heading = rng.range(-180.0, 180.0);
                let p = Pose::new(x, y, heading);
                if poses.iter().all(|q| q.distance_to(&p) >= sep) {
                    poses.push(p);
                    continue 'robot;
                }
            }
            break;
        }
        if poses.len() == robots {
            return Ok(poses);
        }
    }
    Err(too_many())
}

/// Counts of one kind of contact in a trial or an aggregate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TallyStats {
    /// Encounter episodes.
    pub encounters: u64,
    /// Collision episodes.
    pub collisions: u64,
    /// Encounters in which a collision happened.
    pub collided_encounters: u64,
    /// Encounters without a collision / encounters; `null` without encounters.
    pub success_rate: Option<f64>,
    /// Collisions per simulated minute, whole arena.
    pub collisions_per_minute: f64,
}

impl TallyStats {
    fn new(t: &Tally, minutes: f64) -> Self {
        TallyStats {
            encounters: t.encounters,
            collisions: t.collisions,
            collided_encounters: t.collided_encounters,
            success_rate: t.success_rate(),
            collisions_per_minute: t.collisions as f64 / minutes,
        }
    }

    fn tally(&self) -> Tally {
        Tally {
            encounters: self.encounters,
            collisions: self.collisions,
            collided_encounters: self.collided_encounters,
        }
    }
}

/// A pose for JSON.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PoseJson {
    /// mm.
    pub x_mm: f64,
    /// mm.
    pub y_mm: f64,
    /// Degrees, positive = clockwise seen from above.
    pub heading_deg: f64,
}

impl From<Pose> for PoseJson {
    fn from(p: Pose) -> Self {
        PoseJson {
            x_mm: p.x_mm,
            y_mm: p.y_mm,
            heading_deg: p.heading_deg,
        }
    }
}

/// A collision, where and when it began.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CollisionMark {
    /// Simulated time, s.
    pub time_s: f64,
    /// The robot (the lower index of a pair).
    pub robot: usize,
    /// The other robot; `null` for the wall.
    pub other_robot: Option<usize>,
    /// Midway between the two centres, or the robot's centre for the wall, mm.
    pub x_mm: f64,
    /// See `x_mm`.
    pub y_mm: f64,
}

/// The outcome of one trial.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Trial {
    /// "alvs", "lgmd2" or "swarm".
    pub controller: &'static str,
    /// The background specification.
    pub background: String,
    /// Seed of the run.
    pub seed: u64,
    /// Robots in the arena.
    pub robots: usize,
    /// Camera frames simulated (per robot).
    pub frames: u64,
    /// Simulated minutes.
    pub minutes: f64,
    /// Success rate over all encounters (robot–robot and robot–wall); `null` without any.
    pub success_rate: Option<f64>,
    /// All encounters.
    pub encounters: u64,
    /// All collisions.
    pub collisions: u64,
    /// All encounters with a collision.
    pub collided_encounters: u64,
    /// All collisions per simulated minute.
    pub collisions_per_minute: f64,
    /// Between robots.
    pub robot_robot: TallyStats,
    /// Between robots and the wall.
    pub robot_wall: TallyStats,
    /// Physical wall contacts (centre within one radius of a wall).
    pub wall_touches: u64,
    /// Fraction of robot-frames spent pressed against a wall (body within
    /// [`WALL_CONTACT_SLACK_MM`] of it): time a robot is stuck rather than exploring.
    pub wall_contact_fraction: f64,
    /// Mean speed of the robots over the trial, mm/s (distance from frame to frame).
    pub mean_speed_mm_s: f64,
    /// Fraction of robot-frames spent in each controller state (sums to 1).
    pub state_fraction: BTreeMap<String, f64>,
    /// Robot-frames spent in each controller state (summed over robots).
    pub state_frames: BTreeMap<String, u64>,
    /// Wall-clock time of the trial, s (the only number that changes between runs).
    pub wall_clock_s: f64,
    /// Where the robots started (the same in every trial of a run).
    pub start_poses: Vec<PoseJson>,
    /// Where they ended.
    pub end_poses: Vec<PoseJson>,
    /// Every collision.
    pub collision_events: Vec<CollisionMark>,
    /// Each robot's positions (x, y) mm, five per simulated second, rounded to 0.1 mm.
    pub trails: Vec<Vec<[f64; 2]>>,
    /// With [`ArenaConfig::trace`]: one CSV line per robot and camera frame, frame-major
    /// (the columns of [`trace_header`] after `controller,background,`); empty otherwise. Not
    /// in the JSON.
    #[serde(skip)]
    pub trace: Vec<String>,
}

/// Columns of an arena trace: the trial, the robot (index from 0), the frame's
/// [`encounter::FRAME_HEADER`] columns, and the centre's distance to the nearest wall and to
/// the nearest other robot (empty with one robot), mm.
pub fn trace_header() -> String {
    format!(
        "controller,background,robot,{},wall_mm,nearest_robot_mm",
        encounter::FRAME_HEADER
    )
}

/// `s` as one CSV field: quoted (inner quotes doubled) if it holds a comma, quote or newline.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// One controller over all backgrounds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ControllerSummary {
    /// "alvs", "lgmd2" or "swarm".
    pub controller: &'static str,
    /// Trials pooled (one per background).
    pub trials: usize,
    /// Simulated minutes pooled.
    pub minutes: f64,
    /// Success rate over all encounters; `null` without any.
    pub success_rate: Option<f64>,
    /// All encounters.
    pub encounters: u64,
    /// All collisions.
    pub collisions: u64,
    /// All encounters with a collision.
    pub collided_encounters: u64,
    /// All collisions per simulated minute (per arena).
    pub collisions_per_minute: f64,
    /// Between robots.
    pub robot_robot: TallyStats,
    /// Between robots and the wall.
    pub robot_wall: TallyStats,
    /// Physical wall contacts.
    pub wall_touches: u64,
    /// Fraction of robot-frames pressed against a wall.
    pub wall_contact_fraction: f64,
    /// Mean speed of the robots, mm/s.
    pub mean_speed_mm_s: f64,
    /// Fraction of robot-frames in each controller state.
    pub state_fraction: BTreeMap<String, f64>,
    /// Success rate per background.
    pub success_rate_by_background: BTreeMap<String, Option<f64>>,
    /// The paper's success rate (Sec. III-C), for reference.
    pub paper_success_rate: Option<f64>,
    /// Wall-clock seconds of its trials, summed.
    pub wall_clock_s: f64,
}

/// Everything a run produced.
#[derive(Debug, Clone)]
pub struct ArenaReport {
    /// What ran.
    pub config: ArenaConfig,
    /// Trials, controller-major in the order of the configuration.
    pub trials: Vec<Trial>,
    /// One per controller, in the order of the configuration.
    pub summaries: Vec<ControllerSummary>,
    /// Wall-clock seconds of the whole run.
    pub wall_clock_s: f64,
    /// Worker threads used.
    pub jobs: usize,
}

/// Total camera frames (per robot) a run of `config` simulates, for a progress bar; 0 if the
/// configuration is invalid.
pub fn total_frames(config: &ArenaConfig) -> u64 {
    let mut bgs = config.backgrounds.clone();
    bgs.sort();
    bgs.dedup();
    let mut ks: Vec<&str> = config.controllers.iter().map(|k| k.name()).collect();
    ks.sort();
    ks.dedup();
    config
        .frames()
        .saturating_mul((bgs.len() * ks.len()) as u64)
}

/// Runs every trial of `config` on `jobs` threads (0 = [`default_jobs`]). `progress` is told
/// of simulated camera frames as they complete (from any thread).
pub fn run(
    config: &ArenaConfig,
    jobs: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ArenaReport> {
    let prep = config.prepare()?;
    let t0 = Instant::now();
    let plan: Vec<(Kind, usize)> = prep
        .controllers
        .iter()
        .flat_map(|&k| (0..prep.backgrounds.len()).map(move |b| (k, b)))
        .collect();
    let jobs = if jobs == 0 { default_jobs() } else { jobs }.clamp(1, plan.len());
    let trials: Vec<Trial> = super::parallel::map(plan.len(), jobs, |i| {
        let (kind, b) = plan[i];
        run_trial(config, &prep, kind, b, progress)
    });
    let summaries = prep
        .controllers
        .iter()
        .map(|k| {
            let mine: Vec<&Trial> = trials.iter().filter(|t| t.controller == k.name()).collect();
            summarise(k.name(), &mine)
        })
        .collect();
    Ok(ArenaReport {
        config: config.clone(),
        trials,
        summaries,
        wall_clock_s: t0.elapsed().as_secs_f64(),
        jobs,
    })
}

fn round1(v: f64) -> f64 {
    (v * 10.0).round() / 10.0
}

fn run_trial(
    config: &ArenaConfig,
    prep: &Prepared,
    kind: Kind,
    background: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Trial {
    let t0 = Instant::now();
    let (spec, texture) = &prep.backgrounds[background];
    let world = World::with_texture(texture.clone());
    let mut sim = Sim::new(&world, config.seed);
    for (pose, &seed) in prep.starts.iter().zip(&prep.controller_seeds) {
        sim.add(
            *pose,
            kind.make(config.params, config.fsm, seed),
            prep.motor,
            prep.gyro,
            prep.noise,
        );
    }
    let arena = world.arena;
    let mut last: Vec<(f64, f64)> = prep.starts.iter().map(|p| (p.x_mm, p.y_mm)).collect();
    let (mut contact_frames, mut distance_mm) = (0u64, 0.0f64);
    let mut reported = 0;
    let mut trace = Vec::new();
    for f in 1..=prep.frames {
        sim.step();
        if config.trace {
            trace_frame(&sim, &arena, f - 1, &mut trace);
        }
        for (p, q) in sim.physics.poses().iter().zip(last.iter_mut()) {
            if arena.wall_distance(p.x_mm, p.y_mm) < ROBOT_RADIUS_MM + WALL_CONTACT_SLACK_MM {
                contact_frames += 1;
            }
            distance_mm += (p.x_mm - q.0).hypot(p.y_mm - q.1);
            *q = (p.x_mm, p.y_mm);
        }
        if f % PROGRESS_EVERY == 0 {
            progress(f - reported);
            reported = f;
        }
    }
    progress(prep.frames - reported);

    let minutes = prep.frames as f64 * FRAME_DT_S / 60.0;
    let counts = sim.physics.counts();
    let total = counts.total();
    let mut state_frames: BTreeMap<String, u64> = BTreeMap::new();
    for robot in sim.state_frames() {
        for (state, n) in robot {
            *state_frames.entry((*state).to_string()).or_insert(0) += n;
        }
    }
    let robot_frames: u64 = state_frames.values().sum();
    let state_fraction = state_frames
        .iter()
        .map(|(s, &n)| (s.clone(), n as f64 / robot_frames.max(1) as f64))
        .collect();
    let collision_events = sim
        .physics
        .contacts()
        .events()
        .iter()
        .filter(|e| e.kind == EventKind::Collision)
        .map(|e| CollisionMark {
            time_s: e.time_s,
            robot: e.robot,
            other_robot: match e.other {
                Other::Robot(j) => Some(j),
                Other::Wall => None,
            },
            x_mm: round1(e.x_mm),
            y_mm: round1(e.y_mm),
        })
        .collect();
    let trails = sim
        .trails()
        .iter()
        .map(|t| t.iter().map(|&(x, y)| [round1(x), round1(y)]).collect())
        .collect();
    Trial {
        controller: kind.name(),
        background: spec.clone(),
        seed: config.seed,
        robots: prep.starts.len(),
        frames: prep.frames,
        minutes,
        success_rate: total.success_rate(),
        encounters: total.encounters,
        collisions: total.collisions,
        collided_encounters: total.collided_encounters,
        collisions_per_minute: total.collisions as f64 / minutes,
        robot_robot: TallyStats::new(&counts.robot_robot, minutes),
        robot_wall: TallyStats::new(&counts.robot_wall, minutes),
        wall_touches: counts.wall_touches,
        wall_contact_fraction: contact_frames as f64 / robot_frames.max(1) as f64,
        mean_speed_mm_s: distance_mm / (robot_frames.max(1) as f64 * FRAME_DT_S),
        state_fraction,
        state_frames,
        wall_clock_s: t0.elapsed().as_secs_f64(),
        start_poses: prep.starts.iter().map(|&p| p.into()).collect(),
        end_poses: sim.physics.poses().iter().map(|&p| p.into()).collect(),
        collision_events,
        trails,
        trace,
    }
}

/// Appends the trace lines of camera frame `frame` (just simulated), one per robot.
fn trace_frame(sim: &Sim, arena: &Arena, frame: u64, out: &mut Vec<String>) {
    let poses = sim.physics.poses();
    for (i, (p, cmd)) in poses.iter().zip(sim.commands()).enumerate() {
        let nearest = poses
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != i)
            .map(|(_, q)| p.distance_to(q))
            .reduce(f64::min)
            .map_or(String::new(), |d| format!("{d:.1}"));
        out.push(format!(
            "{i},{},{:.1},{nearest}",
            encounter::frame_csv(frame, p, cmd.state, cmd.alert, &cmd.seen),
            arena.wall_distance(p.x_mm, p.y_mm),
        ));
    }
}

/// Pools the trials of one controller.
fn summarise(controller: &'static str, trials: &[&Trial]) -> ControllerSummary {
    let minutes: f64 = trials.iter().map(|t| t.minutes).sum();
    let (mut rr, mut rw) = (Tally::default(), Tally::default());
    let mut state_frames: BTreeMap<String, u64> = BTreeMap::new();
    for t in trials {
        rr = rr.plus(&t.robot_robot.tally());
        rw = rw.plus(&t.robot_wall.tally());
        for (s, n) in &t.state_frames {
            *state_frames.entry(s.clone()).or_insert(0) += n;
        }
    }
    let robot_frames: u64 = state_frames.values().sum();
    let total = rr.plus(&rw);
    let per_min = |n: u64| {
        if minutes > 0.0 {
            n as f64 / minutes
        } else {
            0.0
        }
    };
    ControllerSummary {
        controller,
        trials: trials.len(),
        minutes,
        success_rate: total.success_rate(),
        encounters: total.encounters,
        collisions: total.collisions,
        collided_encounters: total.collided_encounters,
        collisions_per_minute: per_min(total.collisions),
        robot_robot: TallyStats {
            collisions_per_minute: per_min(rr.collisions),
            ..TallyStats::new(&rr, 1.0)
        },
        robot_wall: TallyStats {
            collisions_per_minute: per_min(rw.collisions),
            ..TallyStats::new(&rw, 1.0)
        },
        wall_touches: trials.iter().map(|t| t.wall_touches).sum(),
        // every trial has as many robot-frames, so plain means pool them
        wall_contact_fraction: mean(trials.iter().map(|t| t.wall_contact_fraction)),
        mean_speed_mm_s: mean(trials.iter().map(|t| t.mean_speed_mm_s)),
        state_fraction: state_frames
            .iter()
            .map(|(s, &n)| (s.clone(), n as f64 / robot_frames.max(1) as f64))
            .collect(),
        success_rate_by_background: trials
            .iter()
            .map(|t| (t.background.clone(), t.success_rate))
            .collect(),
        paper_success_rate: paper_success_rate(controller),
        wall_clock_s: trials.iter().map(|t| t.wall_clock_s).sum(),
    }
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (n, sum) = v.fold((0usize, 0.0), |(n, s), x| (n + 1, s + x));
    if n == 0 {
        0.0
    } else {
        sum / n as f64
    }
}

/// Controller states in the order tables and pictures list them.
const STATE_ORDER: [&str; 5] = ["wander", "long_takeoff", "escape", "short_takeoff", "spin"];

/// Short column heads of the states.
fn state_head(s: &str) -> &str {
    match s {
        "long_takeoff" => "long_to",
        "short_takeoff" => "short_to",
        other => other,
    }
}

fn pct(r: Option<f64>) -> String {
    r.map_or("n/a".into(), |r| format!("{:.1} %", 100.0 * r))
}

fn slug(s: &str) -> String {
    let name = Path::new(s)
        .file_stem()
        .filter(|_| s.contains('/') || s.contains('.'))
        .map_or(s.to_string(), |f| f.to_string_lossy().into_owned());
    name.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect()
}

impl ArenaReport {
    /// The states that occur anywhere in the run, in [`STATE_ORDER`] then alphabetical order.
    fn states(&self) -> Vec<String> {
        let mut all: Vec<String> = self
            .trials
            .iter()
            .flat_map(|t| t.state_frames.keys().cloned())
            .collect();
        all.sort_by_key(|s| {
            (
                STATE_ORDER
                    .iter()
                    .position(|o| o == s)
                    .unwrap_or(usize::MAX),
                s.clone(),
            )
        });
        all.dedup();
        all
    }

    /// `{"alvs": {...}, "lgmd2": {...}, "trials": [...]}`: one key per controller run (its
    /// [`ControllerSummary`]) and every [`Trial`].
    pub fn json(&self) -> serde_json::Value {
        let mut map = serde_json::Map::new();
        for s in &self.summaries {
            map.insert(
                s.controller.to_string(),
                serde_json::to_value(s).expect("summaries serialise"),
            );
        }
        map.insert(
            "trials".into(),
            serde_json::to_value(&self.trials).expect("trials serialise"),
        );
        serde_json::Value::Object(map)
    }

    /// The human summary: one line per trial, then one per controller with the paper's figure.
    pub fn table(&self) -> String {
        use std::fmt::Write;
        let c = &self.config;
        let states = self.states();
        let mut out = String::new();
        let frames = self.trials.first().map_or(0, |t| t.frames);
        let _ = writeln!(
            out,
            "arena: {} robots, {} min per trial ({} camera frames per robot), seed {}, {} trials on {} threads, {:.1} s",
            c.robots,
            c.minutes,
            frames,
            c.seed,
            self.trials.len(),
            self.jobs,
            self.wall_clock_s
        );
        let _ = writeln!(
            out,
            "collision: centre distance < 42 mm (robot-robot and robot-wall); encounter: bodies \
             within 2 diameters; success = encounters without collision / encounters"
        );
        let _ = writeln!(out);
        let mut head = format!(
            "{:<10} {:<14} {:>6} {:>6} {:>9}  {:>16} {:>16}  {:>7} {:>7} {:>7} {:>8} {:>6}",
            "controller",
            "background",
            "enc",
            "coll",
            "success",
            "robot-robot",
            "robot-wall",
            "rr/min",
            "rw/min",
            "touches",
            "at wall",
            "mm/s"
        );
        for s in &states {
            let _ = write!(head, " {:>8}", state_head(s));
        }
        let _ = write!(head, " {:>7}", "wall s");
        let rule = "-".repeat(head.len());
        let _ = writeln!(out, "{head}");
        let _ = writeln!(
            out,
            "{:51}{:>16} {:>16}  {:23} {:>8} {:>6} (% of time per state)",
            "", "enc/coll/succ", "enc/coll/succ", "", "% time", "speed"
        );
        let _ = writeln!(out, "{rule}");
        let tally = |t: &TallyStats| {
            format!(
                "{}/{}/{}",
                t.encounters,
                t.collided_encounters,
                t.success_rate
                    .map_or("-".into(), |r| format!("{:.1}", 100.0 * r))
            )
        };
        let line = |out: &mut String,
                    name: &str,
                    bg: &str,
                    (enc, coll, succ): (u64, u64, Option<f64>),
                    (rr, rw): (&TallyStats, &TallyStats),
                    (touches, at_wall, speed): (u64, f64, f64),
                    fractions: &BTreeMap<String, f64>,
                    wall_s: f64| {
            let _ = write!(
                out,
                "{:<10} {:<14} {:>6} {:>6} {:>9}  {:>16} {:>16}  {:>7.2} {:>7.2} {:>7} {:>8.1} {:>6.0}",
                name,
                bg,
                enc,
                coll,
                pct(succ),
                tally(rr),
                tally(rw),
                rr.collisions_per_minute,
                rw.collisions_per_minute,
                touches,
                100.0 * at_wall,
                speed
            );
            for s in &states {
                let f = fractions.get(s).copied().unwrap_or(0.0);
                let _ = write!(out, " {:>8.1}", 100.0 * f);
            }
            let _ = writeln!(out, " {wall_s:>7.1}");
        };
        for t in &self.trials {
            line(
                &mut out,
                t.controller,
                &t.background,
                (t.encounters, t.collisions, t.success_rate),
                (&t.robot_robot, &t.robot_wall),
                (t.wall_touches, t.wall_contact_fraction, t.mean_speed_mm_s),
                &t.state_fraction,
                t.wall_clock_s,
            );
        }
        let _ = writeln!(out, "{rule}");
        for s in &self.summaries {
            line(
                &mut out,
                s.controller,
                &format!("all ({})", s.trials),
                (s.encounters, s.collisions, s.success_rate),
                (&s.robot_robot, &s.robot_wall),
                (s.wall_touches, s.wall_contact_fraction, s.mean_speed_mm_s),
                &s.state_fraction,
                s.wall_clock_s,
            );
        }
        let _ = writeln!(out);
        let _ = writeln!(
            out,
            "{:<10} {:>9} {:>9}  {:>12} {:>12}",
            "controller", "success", "paper", "rr coll/min", "rw coll/min"
        );
        for s in &self.summaries {
            let _ = writeln!(
                out,
                "{:<10} {:>9} {:>9}  {:>12.2} {:>12.2}",
                s.controller,
                pct(s.success_rate),
                pct(s.paper_success_rate),
                s.robot_robot.collisions_per_minute,
                s.robot_wall.collisions_per_minute
            );
        }
        let _ = writeln!(
            out,
            "(enc/coll/succ: encounters / encounters with a collision / success %; coll: collision \
             episodes; at wall: % of robot time pressed against a wall; speed: mean robot speed)"
        );
        out
    }

    /// Writes every trial's trace as CSV ([`trace_header`], then the trials in order; empty
    /// unless the run had [`ArenaConfig::trace`]).
    pub fn write_trace(&self, path: &Path) -> Result<()> {
        let leads: Vec<String> = self
            .trials
            .iter()
            .map(|t| format!("{},{}", t.controller, csv_field(&t.background)))
            .collect();
        encounter::write_csv(
            path,
            &trace_header(),
            leads
                .iter()
                .zip(&self.trials)
                .map(|(lead, t)| (lead.as_str(), t.trace.as_slice())),
        )
    }

    /// Writes one top-down trajectory picture per trial (`<controller>_<background>.png`) and
    /// `summary.png` into `dir` (created); returns their paths.
    pub fn write_pictures(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let mut paths = Vec::new();
        for t in &self.trials {
            let path = dir.join(format!("{}_{}.png", t.controller, slug(&t.background)));
            trial_picture(t)
                .save_png(&path)
                .with_context(|| format!("cannot write {}", path.display()))?;
            paths.push(path);
        }
        let path = dir.join("summary.png");
        self.summary_picture()
            .save_png(&path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        paths.push(path);
        Ok(paths)
    }

    /// The side-by-side comparison of the controllers: success rates, success per background,
    /// collisions per minute and time per state.
    pub fn summary_picture(&self) -> Canvas {
        let (pw, ph, top): (i32, i32, i32) = (440, 300, 44);
        let mut c = Canvas::new(3 * pw as usize, (top + 2 * ph) as usize, WHITE);
        let cfg = &self.config;
        let names: Vec<&str> = self.summaries.iter().map(|s| s.controller).collect();
        let title = format!(
            "Arena: {} robots, {} min x {} backgrounds, seed {} - {}",
            cfg.robots,
            cfg.minutes,
            self.summaries.first().map_or(0, |s| s.trials),
            cfg.seed,
            names
                .iter()
                .map(|n| n.to_uppercase())
                .collect::<Vec<_>>()
                .join(" vs ")
        );
        let (tw, _) = Canvas::text_size(&title, 2);
        c.text((3 * pw - tw as i32) / 2, 6, &title, BLACK, 2);
        // legend
        let mut x = 12;
        let series: Vec<(String, Rgb)> = names
            .iter()
            .enumerate()
            .map(|(i, n)| (n.to_string(), colour_cycle(i)))
            .collect();
        for (n, col) in &series {
            c.fill_rect(x, 28, 10, 7, *col);
            c.text(x + 14, 28, n, BLACK, 1);
            x += 14 + Canvas::text_size(n, 1).0 as i32 + 16;
        }
        c.fill_rect(x, 28, 10, 7, lighten(colour_cycle(0)));
        c.text(x + 14, 28, "light: the paper's figure", BLACK, 1);

        let pct_of = |r: Option<f64>| r.map(|r| 100.0 * r);
        // 1: success rates
        let mut groups = vec![
            "all".to_string(),
            "robot-robot".to_string(),
            "robot-wall".to_string(),
        ];
        let mut values: Vec<Vec<Option<f64>>> = vec![
            self.summaries
                .iter()
                .map(|s| pct_of(s.success_rate))
                .collect(),
            self.summaries
                .iter()
                .map(|s| pct_of(s.robot_robot.success_rate))
                .collect(),
            self.summaries
                .iter()
                .map(|s| pct_of(s.robot_wall.success_rate))
                .collect(),
        ];
        let paper: Vec<Option<f64>> = self
            .summaries
            .iter()
            .map(|s| pct_of(s.paper_success_rate))
            .collect();
        if paper.iter().any(Option::is_some) {
            groups.push("paper".into());
            values.push(paper);
        }
        let paper_group = (groups.len() == 4).then_some(3);
        draw_bars(
            &mut c,
            (0, top, pw, ph),
            &Bars {
                title: "Success rate (%), all backgrounds",
                groups,
                series: &series,
                values,
                y_max: 100.0,
                light_group: paper_group,
                decimals: 1,
            },
        );
        // 2: success per background
        let bgs: Vec<String> = self
            .summaries
            .first()
            .map(|s| {
                self.trials
                    .iter()
                    .filter(|t| t.controller == s.controller)
                    .map(|t| t.background.clone())
                    .collect()
            })
            .unwrap_or_default();
        let per_background = |of: &dyn Fn(&Trial) -> Option<f64>| -> Vec<Vec<Option<f64>>> {
            bgs.iter()
                .map(|b| {
                    self.summaries
                        .iter()
                        .map(|s| {
                            self.trials
                                .iter()
                                .find(|t| t.controller == s.controller && &t.background == b)
                                .and_then(of)
                        })
                        .collect()
                })
                .collect()
        };
        let bg_labels: Vec<String> = bgs.iter().map(|b| short_label(b)).collect();
        let values = per_background(&|t| pct_of(t.success_rate));
        draw_bars(
            &mut c,
            (pw, top, pw, ph),
            &Bars {
                title: "Success rate (%) per background",
                groups: bg_labels.clone(),
                series: &series,
                values,
                y_max: 100.0,
                light_group: None,
                decimals: 1,
            },
        );
        // 3: collisions per minute
        let values: Vec<Vec<Option<f64>>> = vec![
            self.summaries
                .iter()
                .map(|s| Some(s.robot_robot.collisions_per_minute))
                .collect(),
            self.summaries
                .iter()
                .map(|s| Some(s.robot_wall.collisions_per_minute))
                .collect(),
        ];
        let most = values
            .iter()
            .flatten()
            .flatten()
            .fold(0.0f64, |a, &b| a.max(b));
        draw_bars(
            &mut c,
            (2 * pw, top, pw, ph),
            &Bars {
                title: "Collisions per minute (whole arena)",
                groups: vec!["robot-robot".into(), "robot-wall".into()],
                series: &series,
                values,
                y_max: nice_ceiling(most),
                light_group: None,
                decimals: 2,
            },
        );
        // 4: time per state
        let states = self.states();
        let values = states
            .iter()
            .map(|st| {
                self.summaries
                    .iter()
                    .map(|s| Some(100.0 * s.state_fraction.get(st).copied().unwrap_or(0.0)))
                    .collect()
            })
            .collect();
        draw_bars(
            &mut c,
            (0, top + ph, pw, ph),
            &Bars {
                title: "Time per controller state (%)",
                groups: states,
                series: &series,
                values,
                y_max: 100.0,
                light_group: None,
                decimals: 1,
            },
        );
        // 5: time pressed against a wall
        let values = per_background(&|t| Some(100.0 * t.wall_contact_fraction));
        draw_bars(
            &mut c,
            (pw, top + ph, pw, ph),
            &Bars {
                title: "Time pressed against a wall (%)",
                groups: bg_labels.clone(),
                series: &series,
                values,
                y_max: 100.0,
                light_group: None,
                decimals: 1,
            },
        );
        // 6: mean speed
        let values = per_background(&|t| Some(t.mean_speed_mm_s));
        let most = values
            .iter()
            .flatten()
            .flatten()
            .fold(0.0f64, |a, &b| a.max(b));
        draw_bars(
            &mut c,
            (2 * pw, top + ph, pw, ph),
            &Bars {
                title: "Mean robot speed (mm/s)",
                groups: bg_labels,
                series: &series,
                values,
                y_max: nice_ceiling(most),
                light_group: None,
                decimals: 0,
            },
        );
        c
    }
}

/// A background's name for a picture: the file name of a picture path, else the spec.
fn short_label(spec: &str) -> String {
    if spec.contains('/') || spec.contains('.') {
        Path::new(spec)
            .file_name()
            .map_or(spec.to_string(), |f| f.to_string_lossy().into_owned())
    } else {
        spec.to_string()
    }
}

/// A colour halfway to white.
fn lighten(c: Rgb) -> Rgb {
    c.map(|v| ((u16::from(v) + 255) / 2) as u8)
}

/// The smallest 1, 2 or 5 times a power of ten at or above `v` (1 for `v <= 0`).
fn nice_ceiling(v: f64) -> f64 {
    if !(v.is_finite() && v > 0.0) {
        return 1.0;
    }
    let mag = 10f64.powf(v.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|k| k * mag)
        .find(|&c| c >= v * 1.0001)
        .unwrap_or(10.0 * mag)
}

/// A grouped bar chart.
struct Bars<'a> {
    title: &'a str,
    groups: Vec<String>,
    series: &'a [(String, Rgb)],
    /// `values[group][series]`.
    values: Vec<Vec<Option<f64>>>,
    y_max: f64,
    /// A group drawn in lighter colours (reference values).
    light_group: Option<usize>,
    decimals: usize,
}

const INK: Rgb = [30, 30, 30];
const GRID: Rgb = [225, 225, 225];

/// Draws `bars` in the `(x, y, w, h)` box of `c`.
fn draw_bars(c: &mut Canvas, (x, y, w, h): (i32, i32, i32, i32), bars: &Bars) {
    let (tw, _) = Canvas::text_size(bars.title, 1);
    c.text(x + (w - tw as i32) / 2, y + 6, bars.title, INK, 1);
    let (left, right, top, bottom) = (x + 44, x + w - 12, y + 36, y + h - 22);
    let ph = (bottom - top).max(1);
    let y_max = if bars.y_max > 0.0 { bars.y_max } else { 1.0 };
    let py = |v: f64| bottom - ((v / y_max).clamp(0.0, 1.0) * f64::from(ph)).round() as i32;
    for k in 0..=5 {
        let v = y_max * f64::from(k) / 5.0;
        let yy = py(v);
        c.fill_rect(left, yy, right - left, 1, if k == 0 { INK } else { GRID });
        let label = if y_max >= 10.0 {
            format!("{v:.0}")
        } else {
            format!("{v:.1}")
        };
        let (lw, _) = Canvas::text_size(&label, 1);
        c.text(left - 4 - lw as i32, yy - 3, &label, INK, 1);
    }
    c.fill_rect(left, top, 1, bottom - top + 1, INK);
    let n = bars.groups.len().max(1) as i32;
    let gw = (right - left) / n;
    let ns = bars.series.len().max(1) as i32;
    let bw = ((gw * 4 / 5) / ns).max(2);
    for (g, name) in bars.groups.iter().enumerate() {
        let gx = left + g as i32 * gw;
        let (lw, _) = Canvas::text_size(name, 1);
        c.text(gx + (gw - lw as i32) / 2, bottom + 6, name, INK, 1);
        let x0 = gx + (gw - bw * ns) / 2;
        for (s, (_, colour)) in bars.series.iter().enumerate() {
            let bx = x0 + s as i32 * bw;
            let colour = if bars.light_group == Some(g) {
                lighten(*colour)
            } else {
                *colour
            };
            match bars.values.get(g).and_then(|v| v.get(s)).copied().flatten() {
                Some(v) if v.is_finite() => {
                    let yy = py(v);
                    c.fill_rect(bx + 1, yy, bw - 2, bottom - yy, colour);
                    let label = format!("{v:.*}", bars.decimals);
                    let (lw, _) = Canvas::text_size(&label, 1);
                    c.text(bx + (bw - lw as i32) / 2, yy - 10, &label, INK, 1);
                }
                _ => {
                    let (lw, _) = Canvas::text_size("n/a", 1);
                    c.text(bx + (bw - lw as i32) / 2, bottom - 10, "n/a", INK, 1);
                }
            }
        }
    }
}

/// The top-down picture of one trial: each robot's trail in its own colour from a small cross
/// (start) to its body (end), robot–robot collisions as red x, robot–wall collisions as black x.
pub fn trial_picture(t: &Trial) -> Canvas {
    let arena = World::default().arena;
    let mut td = TopDown::new(&arena, 0.5);
    td.title(&format!(
        "{} on {} - success {} ({} encounters, {} with a collision)",
        t.controller.to_uppercase(),
        short_label(&t.background),
        pct(t.success_rate),
        t.encounters,
        t.collided_encounters
    ));
    for (i, trail) in t.trails.iter().enumerate() {
        let pts: Vec<(f64, f64)> = trail.iter().map(|p| (p[0], p[1])).collect();
        td.trail(&pts, colour_cycle(i));
    }
    let starts: Vec<(i32, i32)> = t
        .start_poses
        .iter()
        .map(|p| td.to_px(p.x_mm, p.y_mm))
        .collect();
    for (i, p) in t.end_poses.iter().enumerate() {
        td.robot(&Pose::new(p.x_mm, p.y_mm, p.heading_deg), colour_cycle(i));
    }
    for e in &t.collision_events {
        let colour = if e.other_robot.is_some() { RED } else { BLACK };
        td.mark(e.x_mm, e.y_mm, colour);
    }
    let mut arena_pic = td.into_canvas();
    for (i, &(x, y)) in starts.iter().enumerate() {
        arena_pic.cross(x, y, 5, INK);
        arena_pic.cross(x, y, 4, colour_cycle(i));
    }
    let legend = format!(
        "{} robots, {:.1} min, seed {}; {:.0} % of the time pressed against a wall, mean speed {:.0} mm/s\n\
         robot-robot: {} encounters, {} collisions, success {};  robot-wall: {} encounters, {} collisions, success {}\n\
         + start, disc = end; red x = robot-robot collision, black x = robot-wall collision (centre < 42 mm from it)",
        t.robots,
        t.minutes,
        t.seed,
        100.0 * t.wall_contact_fraction,
        t.mean_speed_mm_s,
        t.robot_robot.encounters,
        t.robot_robot.collisions,
        pct(t.robot_robot.success_rate),
        t.robot_wall.encounters,
        t.robot_wall.collisions,
        pct(t.robot_wall.success_rate),
    );
    let (lw, lh) = Canvas::text_size(&legend, 1);
    let width = arena_pic.width.max(lw + 24);
    let mut c = Canvas::new(width, arena_pic.height + lh + 8, WHITE);
    c.blit(&arena_pic, 0, 0);
    c.text(12, arena_pic.height as i32, &legend, INK, 1);
    c
}

//! Running the trials (in parallel, each a pure function of the configuration) and the
//! frame-by-frame trace.

use super::*;

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
pub(super) fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Total camera frames (per robot) a run of `config` simulates, for a progress bar; 0 if the
/// configuration is invalid.
pub fn total_frames(config: &ArenaConfig) -> u64 {
    let bgs = config.background_specs();
    let mut ks: Vec<&str> = config.controllers.iter().map(|k| k.name()).collect();
    ks.sort();
    ks.dedup();
    config
        .frames()
        .saturating_mul((bgs.len() * ks.len()) as u64)
}

/// Runs every trial of `config` on `jobs` threads (0 = [`parallel::default_jobs`]). `progress` is told
/// of simulated camera frames as they complete (from any thread).
pub fn run(
    config: &ArenaConfig,
    jobs: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ArenaReport> {
    sweep::run_all(config, jobs, progress)
}

/// The controllers of `config` without repeats, in its order.
fn controllers(config: &ArenaConfig) -> Vec<Kind> {
    let mut v: Vec<Kind> = Vec::new();
    for &k in &config.controllers {
        if !v.contains(&k) {
            v.push(k);
        }
    }
    v
}

/// Trial `k` is (controller `k / backgrounds`, background `k mod backgrounds`).
impl Sweep for ArenaConfig {
    const NAME: &'static str = "arena";
    type Trial = Trial;
    type Report = ArenaReport;

    fn trial_count(&self) -> usize {
        controllers(self).len() * self.background_specs().len()
    }

    fn run_slice(
        &self,
        jobs: usize,
        shard: Option<Shard>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<(usize, Trial)>> {
        let prep = self.prepare()?;
        let nb = prep.backgrounds.len();
        parallel::slice(self.trial_count(), jobs, shard, |k| {
            run_trial(self, &prep, prep.controllers[k / nb], k % nb, progress)
        })
    }

    fn report(&self, trials: Vec<Trial>, wall_clock_s: f64, jobs: usize) -> ArenaReport {
        let summaries = controllers(self)
            .iter()
            .map(|k| {
                let mine: Vec<&Trial> =
                    trials.iter().filter(|t| t.controller == k.name()).collect();
                summarise(k.name(), &mine)
            })
            .collect();
        ArenaReport {
            config: self.clone(),
            trials,
            summaries,
            wall_clock_s,
            jobs,
        }
    }
}

pub(super) fn round1(v: f64) -> f64 {
    (v * 10.0).round() / 10.0
}

pub(super) fn run_trial(
    config: &ArenaConfig,
    prep: &Prepared,
    kind: Kind,
    background: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Trial {
    let (spec, texture) = &prep.backgrounds[background];
    run_world_trial(
        &TrialSetup {
            world: &config.world.with_walls(texture.clone()),
            background: spec,
            kind,
            params: config.params,
            fsm: config.fsm,
            seed: config.seed,
            starts: &prep.starts,
            controller_seeds: &prep.controller_seeds,
            motor: prep.motor,
            gyro: prep.gyro,
            noise: prep.noise,
            options: SimOptions::default(),
            frames: prep.frames,
            trace: config.trace,
        },
        progress,
    )
}

/// Everything one trial needs, whichever experiment plans it (the arena, the robustness
/// suite): the world, the robots and their controller, their motors, gyros and cameras, and
/// how the loop differs from the ideal one.
pub struct TrialSetup<'a> {
    /// The world the robots drive in.
    pub world: &'a World,
    /// Its label in [`Trial::background`].
    pub background: &'a str,
    /// The controller every robot runs.
    pub kind: Kind,
    /// ALVS model parameters.
    pub params: Params,
    /// Motion parameters.
    pub fsm: alvs_tasks::model::fsm::FsmParams,
    /// Seed of the simulation (motor, gyro and camera noise).
    pub seed: u64,
    /// Where the robots start ([`start_poses_among`]).
    pub starts: &'a [Pose],
    /// One controller seed per robot.
    pub controller_seeds: &'a [u64],
    /// Every robot's motors.
    pub motor: MotorParams,
    /// Every robot's gyro.
    pub gyro: GyroParams,
    /// Every robot's camera noise.
    pub noise: SensorNoise,
    /// The loop's perturbations (none by default).
    pub options: SimOptions,
    /// Camera frames per robot.
    pub frames: u64,
    /// Keep the frame-by-frame trace.
    pub trace: bool,
}

/// Runs one trial as `setup` says: the arena experiment's counting (contacts, time pressed
/// against a wall or obstacle, mean speed, states, short takeoffs). `progress` is told of
/// simulated camera frames.
pub fn run_world_trial(setup: &TrialSetup, progress: &(dyn Fn(u64) + Sync)) -> Trial {
    let t0 = Instant::now();
    let world = setup.world;
    let mut sim = Sim::with_options(world, setup.seed, &setup.options);
    for (pose, &seed) in setup.starts.iter().zip(setup.controller_seeds) {
        sim.add(
            *pose,
            setup.kind.make(setup.params, setup.fsm, seed),
            setup.motor,
            setup.gyro,
            setup.noise,
        );
    }
    let mut last: Vec<(f64, f64)> = setup.starts.iter().map(|p| (p.x_mm, p.y_mm)).collect();
    let (mut contact_frames, mut distance_mm) = (0u64, 0.0f64);
    let mut reported = 0;
    let mut trace = Vec::new();
    let mut starts = ShortStarts::new(setup.starts.len());
    for f in 1..=setup.frames {
        sim.step();
        if setup.trace {
            trace_frame(&sim, world, f - 1, &mut trace);
        }
        starts.observe(&sim, world);
        for (p, q) in sim.physics.poses().iter().zip(last.iter_mut()) {
            if world.static_distance(p.x_mm, p.y_mm) < ROBOT_RADIUS_MM + WALL_CONTACT_SLACK_MM {
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
    progress(setup.frames - reported);

    let minutes = setup.frames as f64 * FRAME_DT_S / 60.0;
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
        controller: setup.kind.name(),
        background: setup.background.to_string(),
        seed: setup.seed,
        robots: setup.starts.len(),
        frames: setup.frames,
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
        short_takeoffs: starts.total,
        short_takeoffs_in_encounter: starts.in_encounter,
        mean_speed_mm_s: distance_mm / (robot_frames.max(1) as f64 * FRAME_DT_S),
        state_fraction,
        state_frames,
        wall_clock_s: t0.elapsed().as_secs_f64(),
        start_poses: setup.starts.iter().map(|&p| p.into()).collect(),
        end_poses: sim.physics.poses().iter().map(|&p| p.into()).collect(),
        collision_events,
        trails,
        trace,
    }
}

/// Counts the short takeoffs the robots start, and how many of them start inside an
/// encounter: a wall or obstacle within [`WALL_ENCOUNTER_DISTANCE_MM`] or another robot within
/// [`ROBOT_ENCOUNTER_DISTANCE_MM`] of the robot's centre (the paper's short mode is for a
/// threat that is already close; issue "short takeoff only around real threats").
pub(super) struct ShortStarts {
    last: Vec<&'static str>,
    /// Short takeoffs started.
    pub total: u64,
    /// … of them inside an encounter.
    pub in_encounter: u64,
}

impl ShortStarts {
    /// No robot in short takeoff yet.
    pub fn new(robots: usize) -> Self {
        ShortStarts {
            last: vec![""; robots],
            total: 0,
            in_encounter: 0,
        }
    }

    /// Looks at the frame just simulated.
    pub fn observe(&mut self, sim: &Sim, world: &World) {
        let poses = sim.physics.poses();
        for (i, (p, cmd)) in poses.iter().zip(sim.commands()).enumerate() {
            let Some(last) = self.last.get_mut(i) else {
                continue;
            };
            if cmd.state == SHORT_TAKEOFF && *last != SHORT_TAKEOFF {
                self.total += 1;
                let near_robot = poses
                    .iter()
                    .enumerate()
                    .any(|(j, q)| j != i && p.distance_to(q) < ROBOT_ENCOUNTER_DISTANCE_MM);
                if near_robot || world.static_distance(p.x_mm, p.y_mm) < WALL_ENCOUNTER_DISTANCE_MM
                {
                    self.in_encounter += 1;
                }
            }
            *last = cmd.state;
        }
    }
}

/// The short takeoff's state name in [`alvs_sim::controller::Command::state`].
const SHORT_TAKEOFF: &str = alvs_tasks::model::fsm::State::ShortTakeoff.name();

/// Appends the trace lines of camera frame `frame` (just simulated), one per robot.
pub(super) fn trace_frame(sim: &Sim, world: &World, frame: u64, out: &mut Vec<String>) {
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
            world.static_distance(p.x_mm, p.y_mm),
        ));
    }
}

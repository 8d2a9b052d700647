//! Experiment 5, `swarm` (paper Sec. IV-D, Fig. 7): six robots whose ALVS perception makes
//! them spin in place on an approaching object instead of escaping; how does the spread of the
//! group evolve? The same robots with the escape behaviour, from the same start poses and seed,
//! are the reference.
//!
//! # Measures
//!
//! Once per simulated second: the group's **spread** (root-mean-square distance of the robots
//! from their centroid, mm) and the **mean nearest-neighbour distance** (centre to centre, mm).
//! Per trial: both at the start and averaged over the first and the last minute (or the whole
//! trial if shorter), the time per controller state, and robot–robot collisions per minute
//! (the arena's counting). The paper's swarm moved "toward a swarm leader and eventually
//! clustered together"; it does not say how the leader was designated or what it did. By
//! default there is none; `leader` adds one more robot that spins in place for the whole run
//! (a robot the others can see move), at a free place among the others' start poses, and
//! measures the others' distance to it. The spread, nearest neighbours, collisions and states are the others'.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use alvs_tasks::Params;
use anyhow::{ensure, Context, Result};
use serde::{Deserialize, Serialize};

use super::arena::start_poses_among;
use super::sweep::{self, Shard, Sweep};
use super::{parallel, Report};
use alvs_sim::canvas::{colour_cycle, Plot, BLACK};
use alvs_sim::controller::Scripted;
use alvs_sim::{
    frames_in, BuiltinWorld, GyroParams, Kind, MotorParams, Obstacle, Pose, Rng, SensorNoise, Sim,
    TopDown, FRAME_DT_S,
};

/// Random stream of the controllers' seeds (robot `i` takes sub-stream `i`).
const CONTROLLER_STREAM: u64 = 0x5aa2;
/// Camera frames between two trail samples (5 per second).
const TRAIL_EVERY: u64 = 6;
/// Camera frames between two spread samples (1 per second).
const SAMPLE_EVERY: u64 = 30;

/// What to run.
#[derive(Debug, Clone)]
pub struct SwarmConfig {
    /// Robots in the arena (without the leader).
    pub robots: usize,
    /// One more robot, the leader, spins in place at the swarm's spin rate the whole run.
    pub leader: bool,
    /// Simulated minutes per trial.
    pub minutes: f64,
    /// Controllers compared (one trial each).
    pub controllers: Vec<Kind>,
    /// Seed of the start poses, the noise and the controllers.
    pub seed: u64,
    /// ALVS model parameters.
    pub params: Params,
    /// Motion parameters of the controllers (`--fsm NAME=VALUE`).
    pub fsm: alvs_tasks::model::fsm::FsmParams,
    /// The world; the robots start clear of its walls and obstacles.
    pub world: BuiltinWorld,
    /// Wall texture specification; `None`: the world's own walls.
    pub background: Option<String>,
    /// Camera exposure as a fraction of the 33 ms frame period (0 = instantaneous snapshots,
    /// the default; 1 = the whole period): motion during the exposure blurs the picture
    /// ([`alvs_sim::SensorNoise::exposure`]).
    pub exposure: f32,
    /// How the camera's gain moves from frame to frame (`--camera-gain`, [`alvs_sim::GainModel`]).
    pub gain: alvs_sim::GainModel,
}

impl Default for SwarmConfig {
    /// The paper's six robots, 5 simulated minutes, swarm against escape.
    fn default() -> Self {
        SwarmConfig {
            robots: 6,
            leader: false,
            minutes: 5.0,
            controllers: vec![Kind::Swarm, Kind::Alvs],
            seed: 1,
            params: Params::default(),
            fsm: alvs_tasks::model::fsm::FsmParams::default(),
            world: BuiltinWorld::Fu2019,
            background: None,
            exposure: 0.0,
            gain: alvs_sim::GainModel::default(),
        }
    }
}

impl SwarmConfig {
    /// Camera frames per trial.
    pub fn frames(&self) -> u64 {
        frames_in(self.minutes)
    }

    /// Camera frames of the whole run (for a progress bar).
    pub fn total_frames(&self) -> u64 {
        self.frames() * self.controllers.len() as u64
    }

    /// The background the walls show.
    pub fn background(&self) -> &str {
        self.world.background(self.background.as_deref())
    }

    /// Checks the configuration and reads the background (one error line).
    pub fn validate(&self) -> Result<alvs_sim::World> {
        ensure!(
            (2..=30).contains(&self.robots),
            "--robots must be 2..=30 for a swarm, got {}",
            self.robots
        );
        ensure!(
            self.minutes.is_finite() && self.minutes > 0.0 && self.minutes <= 1000.0,
            "--minutes must be a positive number up to 1000, got {}",
            self.minutes
        );
        super::validate_setup(&self.controllers, &self.params)?;
        Ok(alvs_sim::worlds::world_with(self.world, self.background.as_deref())?.1)
    }
}

/// One trial's outcome.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SwarmTrial {
    /// "swarm", "alvs", "lgmd2".
    #[serde(deserialize_with = "sweep::static_name")]
    pub controller: sweep::StaticName,
    /// Robots.
    pub robots: usize,
    /// Simulated minutes.
    pub minutes: f64,
    /// Spread (RMS distance from the centroid), mm, once per second from t = 0.
    pub spread_mm: Vec<f64>,
    /// Mean nearest-neighbour distance, mm, once per second from t = 0.
    pub nearest_mm: Vec<f64>,
    /// Spread at the start, mm.
    pub spread_start_mm: f64,
    /// Mean spread over the first minute, mm.
    pub spread_first_minute_mm: f64,
    /// Mean spread over the last minute, mm.
    pub spread_last_minute_mm: f64,
    /// Mean nearest-neighbour distance over the first minute, mm.
    pub nearest_first_minute_mm: f64,
    /// Mean nearest-neighbour distance over the last minute, mm.
    pub nearest_last_minute_mm: f64,
    /// With a leader: the robots' mean distance to it, mm, once per second from t = 0.
    pub leader_mm: Vec<f64>,
    /// With a leader: that distance over the first minute, mm.
    pub leader_first_minute_mm: Option<f64>,
    /// With a leader: that distance over the last minute, mm.
    pub leader_last_minute_mm: Option<f64>,
    /// Robot–robot collision episodes per simulated minute.
    pub robot_collisions_per_minute: f64,
    /// Fraction of robot-frames in each state.
    pub state_fraction: BTreeMap<String, f64>,
    /// Positions, five per second, mm: the robots', then the leader's (if any).
    pub trails: Vec<Vec<[f64; 2]>>,
    /// Wall-clock seconds.
    pub wall_clock_s: f64,
}

/// Everything a run produced.
#[derive(Debug, Clone)]
pub struct SwarmReport {
    /// What ran.
    pub config: SwarmConfig,
    /// One per controller.
    pub trials: Vec<SwarmTrial>,
    /// Wall-clock seconds.
    pub wall_clock_s: f64,
}

/// Spread (RMS distance from the centroid) and mean nearest-neighbour distance of `points`.
pub fn spread(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len().max(1) as f64;
    let (cx, cy) = points
        .iter()
        .fold((0.0, 0.0), |(x, y), p| (x + p.0 / n, y + p.1 / n));
    let rms = (points
        .iter()
        .map(|p| (p.0 - cx).powi(2) + (p.1 - cy).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    let nearest = points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            points
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, q)| (p.0 - q.0).hypot(p.1 - q.1))
                .fold(f64::INFINITY, f64::min)
        })
        .filter(|d| d.is_finite())
        .sum::<f64>()
        / n;
    (rms, nearest)
}

/// Runs one trial per controller on `jobs` threads (0 = all cores).
pub fn run(
    config: &SwarmConfig,
    jobs: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<SwarmReport> {
    sweep::run_all(config, jobs, progress)
}

/// Trial `k` is controller `k`.
impl Sweep for SwarmConfig {
    const NAME: &'static str = "swarm";
    type Trial = SwarmTrial;
    type Report = SwarmReport;

    fn trial_count(&self) -> usize {
        self.controllers.len()
    }

    fn run_slice(
        &self,
        jobs: usize,
        shard: Option<Shard>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<(usize, SwarmTrial)>> {
        run_slice(self, jobs, shard, progress)
    }

    fn report(&self, trials: Vec<SwarmTrial>, wall_clock_s: f64, _jobs: usize) -> SwarmReport {
        SwarmReport {
            config: self.clone(),
            trials,
            wall_clock_s,
        }
    }
}

/// The trials of `shard` (all without one), in index order.
fn run_slice(
    config: &SwarmConfig,
    jobs: usize,
    shard: Option<Shard>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<(usize, SwarmTrial)>> {
    let world = config.validate()?;
    let (arena, obstacles) = (&world.arena, &world.obstacles);
    // the others start where they would without a leader; the leader finds room among them
    let starts = start_poses_among(arena, obstacles, config.robots, config.seed)?;
    let leader_pose = if config.leader {
        Some(leader_pose(arena, obstacles, &starts, config.seed)?)
    } else {
        None
    };
    let all_starts: Vec<Pose> = starts.iter().copied().chain(leader_pose).collect();
    let (spin_left, spin_right) = leader_wheels_mm_s(&config.fsm);
    parallel::slice(config.controllers.len(), jobs, shard, |c| {
        let t = std::time::Instant::now();
        let kind = config.controllers[c];
        let mut sim = Sim::new(&world, config.seed);
        let root = Rng::new(config.seed).fork(CONTROLLER_STREAM);
        for (i, p) in starts.iter().enumerate() {
            sim.add(
                *p,
                kind.make(config.params, config.fsm, root.fork(i as u64).next_u64()),
                MotorParams::default(),
                GyroParams::default(),
                config.gain.camera(config.exposure),
            );
        }
        if let Some(p) = leader_pose {
            sim.add(
                p,
                Box::new(Scripted {
                    left_mm_s: spin_left,
                    right_mm_s: spin_right,
                }),
                MotorParams::default(),
                GyroParams::default(),
                SensorNoise::typical(),
            );
        }
        // the robots (the leader, if any, is the last body)
        let points = |sim: &Sim| -> Vec<(f64, f64)> {
            sim.physics.poses()[..config.robots]
                .iter()
                .map(|p| (p.x_mm, p.y_mm))
                .collect()
        };
        let to_leader = |sim: &Sim| -> Option<f64> {
            let l = sim
                .physics
                .poses()
                .get(config.robots)
                .filter(|_| config.leader)?;
            let pts = points(sim);
            Some(
                pts.iter()
                    .map(|p| (p.0 - l.x_mm).hypot(p.1 - l.y_mm))
                    .sum::<f64>()
                    / pts.len() as f64,
            )
        };
        let (s0, n0) = spread(&points(&sim));
        let (s0, n0) = (round1(s0), round1(n0));
        let (mut spreads, mut nearest) = (vec![s0], vec![n0]);
        let mut leader_mm: Vec<f64> = to_leader(&sim).map(round1).into_iter().collect();
        let mut trails: Vec<Vec<[f64; 2]>> =
            all_starts.iter().map(|p| vec![[p.x_mm, p.y_mm]]).collect();
        let frames = config.frames();
        for f in 1..=frames {
            sim.step();
            if f % SAMPLE_EVERY == 0 {
                let (s, n) = spread(&points(&sim));
                spreads.push(round1(s));
                nearest.push(round1(n));
                leader_mm.extend(to_leader(&sim).map(round1));
                progress(SAMPLE_EVERY);
            }
            if f % TRAIL_EVERY == 0 {
                for (tr, p) in trails.iter_mut().zip(sim.physics.poses()) {
                    tr.push([round1(p.x_mm), round1(p.y_mm)]);
                }
            }
        }
        progress(frames % SAMPLE_EVERY);
        let minutes = frames as f64 * FRAME_DT_S / 60.0;
        let window = 60.min(spreads.len());
        let head = |v: &[f64]| v[..window].iter().sum::<f64>() / window as f64;
        let tail = |v: &[f64]| v[v.len() - window..].iter().sum::<f64>() / window as f64;
        let mut states: BTreeMap<String, u64> = BTreeMap::new();
        for robot in sim.state_frames().iter().take(config.robots) {
            for (s, n) in robot {
                *states.entry((*s).to_string()).or_insert(0) += n;
            }
        }
        let total: u64 = states.values().sum::<u64>().max(1);
        SwarmTrial {
            controller: kind.name(),
            robots: config.robots,
            minutes,
            spread_start_mm: round1(s0),
            spread_first_minute_mm: round1(head(&spreads)),
            spread_last_minute_mm: round1(tail(&spreads)),
            nearest_first_minute_mm: round1(head(&nearest)),
            nearest_last_minute_mm: round1(tail(&nearest)),
            leader_first_minute_mm: (!leader_mm.is_empty()).then(|| round1(head(&leader_mm))),
            leader_last_minute_mm: (!leader_mm.is_empty()).then(|| round1(tail(&leader_mm))),
            leader_mm,
            robot_collisions_per_minute: robot_collisions(&sim, config.robots) as f64 / minutes,
            state_fraction: states
                .iter()
                .map(|(s, &n)| (s.clone(), n as f64 / total as f64))
                .collect(),
            spread_mm: spreads,
            nearest_mm: nearest,
            trails,
            wall_clock_s: t.elapsed().as_secs_f64(),
        }
    })
}

/// Wheel speeds of a spin in place at the swarm's spin rate, mm/s, as the swarm robots spin
/// (`FsmParams::spin_deg_s` through the FSM's wheel limit).
fn leader_wheels_mm_s(fsm: &alvs_tasks::model::fsm::FsmParams) -> (f32, f32) {
    alvs_tasks::model::fsm::mix(0.0, fsm.swarm.spin_deg_s.to_radians(), fsm)
}

/// Random stream of the leader's start pose.
const LEADER_STREAM: u64 = 0x1ead;

/// A start pose for the leader as far from the walls, the `obstacles` and the robots at
/// `starts` as the arena's start poses are from each other
/// ([`super::arena::START_SEPARATION_MM`], [`super::arena::START_WALL_CLEARANCE_MM`]); the
/// first of 20,000 random tries that fits.
pub fn leader_pose(
    arena: &alvs_sim::Arena,
    obstacles: &[Obstacle],
    starts: &[Pose],
    seed: u64,
) -> Result<Pose> {
    let (m, sep) = (
        super::arena::START_WALL_CLEARANCE_MM,
        super::arena::START_SEPARATION_MM,
    );
    let (w, h) = (arena.size_x_mm - 2.0 * m, arena.size_y_mm - 2.0 * m);
    let mut rng = Rng::new(seed).fork(LEADER_STREAM);
    for _ in 0..20_000 {
        let p = Pose::new(
            m + w * rng.uniform(),
            m + h * rng.uniform(),
            rng.range(-180.0, 180.0),
        );
        let clear = obstacles
            .iter()
            .all(|o| o.surface_distance(p.x_mm, p.y_mm) >= m);
        if w >= 0.0 && h >= 0.0 && clear && starts.iter().all(|q| q.distance_to(&p) >= sep) {
            return Ok(p);
        }
    }
    anyhow::bail!(
        "no room for the leader among {} robots ({sep} mm apart, {m} mm from the walls and \
         obstacles); use fewer robots",
        starts.len()
    )
}

/// Robot–robot collision episodes among the first `robots` bodies (not with the leader).
fn robot_collisions(sim: &Sim, robots: usize) -> usize {
    use alvs_sim::{EventKind, Other};
    sim.physics
        .contacts()
        .events()
        .iter()
        .filter(|e| {
            e.kind == EventKind::Collision
                && matches!(e.other, Other::Robot(j) if j < robots)
                && e.robot < robots
        })
        .count()
}

fn round1(v: f64) -> f64 {
    (v * 10.0).round() / 10.0
}

impl Report for SwarmReport {
    /// `{"swarm":{...},"alvs":{...}}`: one key per controller.
    fn json(&self) -> serde_json::Value {
        let c = &self.config;
        super::per_controller_json(
            self.trials.iter().map(|t| (t.controller.to_string(), t)),
            serde_json::json!({"robots": c.robots, "leader": c.leader, "minutes": c.minutes, "seed": c.seed,
                               "world": c.world.label(), "background": c.background()}),
        )
    }

    /// One line per controller.
    fn table(&self) -> String {
        use std::fmt::Write;
        let c = &self.config;
        let mut out = String::new();
        let _ = writeln!(
            out,
            "swarm: {} robots{}, {} min, world {}, background {}, seed {}, {:.1} s",
            c.robots,
            if c.leader {
                " and a spinning leader"
            } else {
                ""
            },
            c.minutes,
            c.world.label(),
            c.background(),
            c.seed,
            self.wall_clock_s
        );
        let _ = writeln!(
            out,
            "{:<8} {:>12} {:>12} {:>12} {:>12} {:>12} {:>9} {:>7} {:>7}",
            "ctrl",
            "spread t=0",
            "1st min",
            "last min",
            "nn 1st min",
            "nn last min",
            "rr/min",
            "spin %",
            "look %"
        );
        for t in &self.trials {
            let _ = writeln!(
                out,
                "{:<8} {:>12.0} {:>12.0} {:>12.0} {:>12.0} {:>12.0} {:>9.2} {:>7.1} {:>7.1}",
                t.controller,
                t.spread_start_mm,
                t.spread_first_minute_mm,
                t.spread_last_minute_mm,
                t.nearest_first_minute_mm,
                t.nearest_last_minute_mm,
                t.robot_collisions_per_minute,
                100.0 * t.state_fraction.get("spin").copied().unwrap_or(0.0),
                100.0 * t.state_fraction.get("look").copied().unwrap_or(0.0)
            );
        }
        for t in &self.trials {
            if let (Some(a), Some(b)) = (t.leader_first_minute_mm, t.leader_last_minute_mm) {
                let _ = writeln!(
                    out,
                    "{:<8} mean distance to the leader: {a:.0} mm over the first minute, {b:.0} mm over the last",
                    t.controller
                );
            }
        }
        let _ = writeln!(
            out,
            "(spread: RMS distance from the group's centroid, mm; nn: mean nearest-neighbour distance, mm)"
        );
        out
    }

    /// `swarm_spread.png` (spread and nearest-neighbour distance over time per controller)
    /// and `swarm_<controller>.png` (trails) in `dir`.
    fn write_pictures(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let mut plot = Plot::new(&format!(
            "{} robots: spread (RMS distance from the centroid) and nearest neighbour, mm",
            self.config.robots
        ))
        .x_label("simulated seconds");
        for t in &self.trials {
            let s: Vec<f32> = t.spread_mm.iter().map(|&v| v as f32).collect();
            let n: Vec<f32> = t.nearest_mm.iter().map(|&v| v as f32).collect();
            plot = plot
                .series(&format!("{} spread", t.controller), &s)
                .series(&format!("{} nearest", t.controller), &n);
            if !t.leader_mm.is_empty() {
                let l: Vec<f32> = t.leader_mm.iter().map(|&v| v as f32).collect();
                plot = plot.series(&format!("{} to the leader", t.controller), &l);
            }
        }
        let mut paths = Vec::new();
        let path = dir.join("swarm_spread.png");
        plot.render(900, 450)
            .save_png(&path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        paths.push(path);
        let world = self.config.world.world();
        for t in &self.trials {
            let mut td = TopDown::of_world(&world, 0.5);
            td.title(&format!(
                "{}: {} robots{}, {:.1} min; spread {:.0} mm at the start, {:.0} mm over the last minute",
                t.controller.to_uppercase(),
                t.robots,
                if t.leader_mm.is_empty() { "" } else { " and a leader (black)" },
                t.minutes,
                t.spread_start_mm,
                t.spread_last_minute_mm
            ));
            for (i, tr) in t.trails.iter().enumerate() {
                let pts: Vec<(f64, f64)> = tr.iter().map(|p| (p[0], p[1])).collect();
                // the leader, the last trail, in black
                let colour = if i < t.robots { colour_cycle(i) } else { BLACK };
                td.trail(&pts, colour);
                if let Some(e) = pts.last() {
                    td.robot(&alvs_sim::Pose::new(e.0, e.1, 0.0), colour);
                }
            }
            let c = td.into_canvas();
            let path = dir.join(format!("swarm_{}.png", t.controller));
            c.save_png(&path)
                .with_context(|| format!("cannot write {}", path.display()))?;
            paths.push(path);
        }
        Ok(paths)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alvs_tasks::model::fsm::{FsmParams, Motion};

    #[test]
    fn the_leader_spins_in_place_at_the_swarms_rate_within_the_wheel_limit() {
        let p = FsmParams::default();
        let (l, r) = leader_wheels_mm_s(&p);
        assert_eq!(l, -r, "in place");
        let yaw_deg_s = ((l - r) / p.motion.track_mm).to_degrees();
        assert!((yaw_deg_s - p.swarm.spin_deg_s).abs() < 1e-3, "{yaw_deg_s}");
        let slow = FsmParams {
            motion: Motion {
                max_wheel_mm_s: 20.0,
                ..p.motion
            },
            ..p
        };
        assert_eq!(leader_wheels_mm_s(&slow), (20.0, -20.0));
    }

    #[test]
    fn the_leader_finds_room_among_the_robots_or_says_why_not() {
        let world = BuiltinWorld::Fu2019.world();
        let (arena, obstacles) = (&world.arena, &world.obstacles[..]);
        let starts = start_poses_among(arena, obstacles, 20, 2).unwrap();
        let l = leader_pose(arena, obstacles, &starts, 2).unwrap();
        let sep = super::super::arena::START_SEPARATION_MM;
        assert!(starts.iter().all(|q| q.distance_to(&l) >= sep));
        let m = super::super::arena::START_WALL_CLEARANCE_MM;
        assert!(world.static_distance(l.x_mm, l.y_mm) >= m, "{l:?}");
        // a robot everywhere: no room
        let crowd: Vec<Pose> = (0..40)
            .flat_map(|i| (0..30).map(move |j| Pose::new(30.0 * i as f64, 30.0 * j as f64, 0.0)))
            .collect();
        let e = leader_pose(arena, obstacles, &crowd, 2)
            .unwrap_err()
            .to_string();
        assert!(e.contains("no room for the leader"), "{e}");
    }
}

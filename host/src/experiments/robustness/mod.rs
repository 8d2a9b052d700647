//! The robustness suite (`cargo alvs robustness`, issue 29 item 4, docs/robustness.md): every
//! controller in the validated world under each thing a real lab or robot changes — a textured
//! or shaded floor, the camera higher, lower or tilted, a lighting gradient, a weaker motor, the
//! firmware's odometry in place of the gyro, lost frames — over several seeds.
//!
//! # Trials
//!
//! One trial is one (perturbation, controller, seed): the arena experiment's trial
//! ([`arena::run_world_trial`]: its robots, start poses, noise and counting, so success,
//! encounters and time at a wall are exactly the arena's) in the chosen world with the
//! perturbation applied ([`Perturbation::apply`]). Within a seed every perturbation and
//! controller starts from the same poses with the same noise streams (paired, as the arena's
//! controllers are). Trials are independent: they run on `--jobs` threads and shard with
//! `--shard I/N` like every experiment (docs/sweeps.md).
//!
//! # Rows
//!
//! One row per (perturbation, controller) pools its seeds as the arena pools backgrounds
//! ([`arena::summarise`]: counts summed, so the success rate weighs each encounter equally;
//! speed and time at a wall are means over the trials), with the spread over seeds and the
//! difference from the reference row (`none`) of the same controller. A controller whose mean
//! speed is below [`SLOW_SHARE`] of its cruise speed is flagged: a robot that avoids collisions
//! by crawling or turning in place has not shown that it copes.

mod perturbation;
mod report;

use anyhow::{ensure, Result};
use serde::{Deserialize, Serialize};

use alvs_tasks::model::fsm::FsmParams;
use alvs_tasks::Params;

use super::arena::{self, Trial, TrialSetup};
use super::parallel;
use super::sweep::{Shard, Sweep};
use alvs_sim::{frames_in, BuiltinWorld, Kind, Pose, SimOptions, World};

pub use perturbation::*;
pub use report::*;

/// A mean speed below this share of the cruise speed is flagged in the table.
pub const SLOW_SHARE: f64 = 0.8;

/// The seeds of every reported figure (issue 29: seeds 1–5 are for tuning, 11–20 for reports).
pub const REPORT_SEEDS: std::ops::RangeInclusive<u64> = 11..=20;

/// A controller the suite compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SuiteController {
    /// ALVS with the default model (`--model alvs`: `Params::ALVS`, `FsmParams::ALVS`).
    Alvs,
    /// ALVS with the paper's model exactly (`--model paper`: `Params::PAPER`,
    /// `FsmParams::PAPER`).
    Paper,
    /// ALVS with what the authors' public firmware runs (`--model firmware`:
    /// `Params::FIRMWARE`, `FsmParams::FIRMWARE`). Not in [`SuiteController::DEFAULT`].
    Firmware,
    /// The LGMD2 baseline, with the motion parameters the arena gives it by default.
    Lgmd2,
}

impl SuiteController {
    /// All four, in the table's order.
    pub const ALL: [SuiteController; 4] = [
        SuiteController::Alvs,
        SuiteController::Paper,
        SuiteController::Firmware,
        SuiteController::Lgmd2,
    ];

    /// The suite's controllers when none is asked for (docs/robustness.md's tables).
    pub const DEFAULT: [SuiteController; 3] = [
        SuiteController::Alvs,
        SuiteController::Paper,
        SuiteController::Lgmd2,
    ];

    /// Its name on the command line and in tables.
    pub const fn name(self) -> &'static str {
        match self {
            SuiteController::Alvs => "alvs",
            SuiteController::Paper => "paper",
            SuiteController::Firmware => "firmware",
            SuiteController::Lgmd2 => "lgmd2",
        }
    }

    /// The arena's controller kind.
    pub const fn kind(self) -> Kind {
        match self {
            SuiteController::Alvs | SuiteController::Paper | SuiteController::Firmware => {
                Kind::Alvs
            }
            SuiteController::Lgmd2 => Kind::Lgmd2,
        }
    }

    /// The model parameters (unused by LGMD2).
    pub const fn params(self) -> Params {
        match self {
            SuiteController::Paper => Params::PAPER,
            SuiteController::Firmware => Params::FIRMWARE,
            SuiteController::Alvs | SuiteController::Lgmd2 => Params::ALVS,
        }
    }

    /// The motion parameters (LGMD2's cruise, turn and alignment come from them).
    pub const fn fsm(self) -> FsmParams {
        match self {
            SuiteController::Paper => FsmParams::PAPER,
            SuiteController::Firmware => FsmParams::FIRMWARE,
            SuiteController::Alvs | SuiteController::Lgmd2 => FsmParams::ALVS,
        }
    }
}

/// What to run.
#[derive(Debug, Clone, PartialEq)]
pub struct RobustnessConfig {
    /// The world (the validated replica by default).
    pub world: BuiltinWorld,
    /// Seeds; every (perturbation, controller) runs each.
    pub seeds: Vec<u64>,
    /// Perturbations, in the table's order.
    pub perturbations: Vec<Perturbation>,
    /// Controllers, in the table's order.
    pub controllers: Vec<SuiteController>,
    /// Robots in the arena (all running the trial's controller).
    pub robots: usize,
    /// Simulated minutes per trial.
    pub minutes: f64,
}

impl Default for RobustnessConfig {
    /// The replica, seeds 11–20, every perturbation and controller, the arena's 3 robots for
    /// 10 minutes.
    fn default() -> Self {
        RobustnessConfig {
            world: BuiltinWorld::Fu2019,
            seeds: REPORT_SEEDS.collect(),
            perturbations: Perturbation::ALL.to_vec(),
            controllers: SuiteController::DEFAULT.to_vec(),
            robots: 3,
            minutes: 10.0,
        }
    }
}

/// `v` without repeats, in its order.
fn unique<T: PartialEq + Copy>(v: &[T]) -> Vec<T> {
    let mut out: Vec<T> = Vec::new();
    for &x in v {
        if !out.contains(&x) {
            out.push(x);
        }
    }
    out
}

/// Arena trials paired across the rows of a sweep: in one world, for one length, each seed's
/// start poses and controller seeds are the same whatever the perturbation or controller (the
/// suite's trials, and the ablation's arena part).
pub struct PairedArena {
    world: World,
    label: &'static str,
    seeds: Vec<u64>,
    starts: Vec<Vec<Pose>>,
    controller_seeds: Vec<Vec<u64>>,
    frames: u64,
}

impl PairedArena {
    /// `robots` robots on each of `seeds` in `world`, `minutes` a trial; the error is one line.
    pub fn new(world: BuiltinWorld, seeds: &[u64], robots: usize, minutes: f64) -> Result<Self> {
        ensure!(robots >= 1, "--robots must be at least 1");
        ensure!(
            minutes.is_finite() && minutes > 0.0 && minutes <= arena::MAX_MINUTES,
            "--minutes must be a positive number of minutes up to {}, got {minutes}",
            arena::MAX_MINUTES,
        );
        ensure!(!seeds.is_empty(), "no seed to run");
        let (label, world) = (world.label(), world.world());
        let starts = seeds
            .iter()
            .map(|&s| arena::start_poses_among(&world.arena, &world.obstacles, robots, s))
            .collect::<Result<Vec<_>>>()?;
        Ok(PairedArena {
            controller_seeds: seeds
                .iter()
                .map(|&s| arena::controller_seeds(s, robots))
                .collect(),
            world,
            label,
            seeds: seeds.to_vec(),
            starts,
            frames: frames_in(minutes),
        })
    }

    /// The seeds, in order.
    pub fn seeds(&self) -> &[u64] {
        &self.seeds
    }

    /// The arena's trial on seed `s` (an index into [`PairedArena::seeds`]) with `kind`
    /// running `params` and `fsm` on every robot, `perturbation` applied, the realistic noise.
    pub fn trial(
        &self,
        s: usize,
        perturbation: Perturbation,
        kind: Kind,
        (params, fsm): (Params, FsmParams),
        progress: &(dyn Fn(u64) + Sync),
    ) -> Trial {
        let seed = self.seeds[s];
        let (mut motor, gyro, mut noise) = alvs_sim::robot_noise(true);
        let mut options = SimOptions::default();
        perturbation.apply(seed, &mut motor, &mut noise, &mut options);
        arena::run_world_trial(
            &TrialSetup {
                world: &self.world,
                background: self.label,
                kind,
                params,
                fsm,
                seed,
                starts: &self.starts[s],
                controller_seeds: &self.controller_seeds[s],
                motor,
                gyro,
                noise,
                options,
                frames: self.frames,
                trace: false,
            },
            progress,
        )
    }
}

/// A checked configuration: the paired trials, the rows.
struct Prepared {
    paired: PairedArena,
    perturbations: Vec<Perturbation>,
    controllers: Vec<SuiteController>,
}

impl RobustnessConfig {
    /// Camera frames per trial.
    pub fn frames(&self) -> u64 {
        frames_in(self.minutes)
    }

    /// Trials in the plan: (perturbation, controller, seed), perturbation-major.
    fn plan(&self) -> (usize, usize, usize) {
        (
            unique(&self.perturbations).len(),
            unique(&self.controllers).len(),
            unique(&self.seeds).len(),
        )
    }

    /// Camera frames (per robot) of the whole run, for a progress bar.
    pub fn total_frames(&self) -> u64 {
        self.frames().saturating_mul(self.trial_count() as u64)
    }

    /// Checks the configuration; the error is one line.
    pub fn validate(&self) -> Result<()> {
        self.prepare().map(|_| ())
    }

    fn prepare(&self) -> Result<Prepared> {
        let paired = PairedArena::new(self.world, &unique(&self.seeds), self.robots, self.minutes)?;
        ensure!(!self.perturbations.is_empty(), "no perturbation to run");
        ensure!(!self.controllers.is_empty(), "no controller to run");
        Ok(Prepared {
            paired,
            perturbations: unique(&self.perturbations),
            controllers: unique(&self.controllers),
        })
    }
}

/// One trial's outcome: which perturbation and controller, and the arena's trial (its trails
/// dropped: the suite draws none, and a full run keeps hundreds of trials).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RobustTrial {
    /// The perturbation.
    pub perturbation: Perturbation,
    /// The controller.
    pub controller: SuiteController,
    /// The arena's trial (its `seed` is the trial's).
    pub trial: Trial,
}

/// Trial `k` is (perturbation `k / (C·S)`, controller `(k / S) mod C`, seed `k mod S`).
impl Sweep for RobustnessConfig {
    const NAME: &'static str = "robustness";
    type Trial = RobustTrial;
    type Report = RobustnessReport;

    fn trial_count(&self) -> usize {
        let (p, c, s) = self.plan();
        p * c * s
    }

    fn run_slice(
        &self,
        jobs: usize,
        shard: Option<Shard>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<(usize, RobustTrial)>> {
        let prep = self.prepare()?;
        let (_, nc, ns) = self.plan();
        parallel::slice(self.trial_count(), jobs, shard, |k| {
            let (perturbation, controller) = (
                prep.perturbations[k / (nc * ns)],
                prep.controllers[(k / ns) % nc],
            );
            let s = k % ns;
            let mut trial = prep.paired.trial(
                s,
                perturbation,
                controller.kind(),
                (controller.params(), controller.fsm()),
                progress,
            );
            trial.trails.clear();
            RobustTrial {
                perturbation,
                controller,
                trial,
            }
        })
    }

    fn report(&self, trials: Vec<RobustTrial>, wall_clock_s: f64, jobs: usize) -> RobustnessReport {
        RobustnessReport::new(self.clone(), trials, wall_clock_s, jobs)
    }
}

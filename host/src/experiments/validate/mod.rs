//! The simulator validated against real recordings (`cargo alvs validate`): for each recorded
//! LGMD2 Colias run, one LGMD2 robot alone in a world (by default the recorded arena's replica)
//! drives for the run's duration; its trail is drawn and extracted exactly like the recording
//! (`recordings::track_from_trail`) and its path statistics are compared with the real ones,
//! each with its tolerance (`recordings::compare`).
//!
//! The 10.9 cm/s runs are the calibration runs (what the world may be fitted to); the others
//! are held out. The robot's cruise speed is estimated from the run's measured mean path speed
//! and turn rate ([`cruise_mm_s`]; the folder names' speeds disagree with the tracked paths,
//! docs/recordings.md).

pub mod approach;
pub mod sim;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde::Serialize;

use crate::experiments::{parallel, Report};
use crate::recordings::{
    self, compare, track_from_trail, ArenaGeometry, PathStats, RunFile, Verdict,
};
use alvs_sim::World;

/// The runs the world may be calibrated on: the 10.9 cm/s ones (issue 29).
pub const CALIBRATION_SPEED_CM_S: f64 = 10.9;

/// Straight driving each turn costs the simulated LGMD2 robot, s (turning in place and
/// accelerating again): calibrated on the 10.9 cm/s runs (seeds 1–5), where the simulated robot
/// driving at the real mean path speed made 0.75–0.90 s less progress per extracted turn
/// (docs/world.md, "Cruise speed").
pub const TURN_COST_S: f64 = 0.8;

/// The cruise speed that gives a robot the recorded run's mean path speed if each of its
/// turns costs `turn_cost_s` of straight driving: the real robot's mean path speed includes
/// its turns, its forward speed is higher. `turn_cost_s` 0 gives the mean path speed itself;
/// the turns are capped at 90 % of the time.
pub fn cruise_mm_s(real: &PathStats, turn_cost_s: f64) -> f64 {
    let turning = (real.turns_per_min * turn_cost_s / 60.0).clamp(0.0, 0.9);
    real.mean_speed_mm_s / (1.0 - turning)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recordings::stats::Distribution;

    fn stats(mean_speed_mm_s: f64, turns_per_min: f64) -> PathStats {
        PathStats {
            duration_s: 600.0,
            path_mm: 0.0,
            share_within_50mm: 0.0,
            share_within_100mm: 0.0,
            turn_wall_mm: Distribution::of(Vec::new()),
            run_mm: Distribution::of(Vec::new()),
            turns_per_min,
            pressed_share: 0.0,
            coverage: 0.0,
            mean_speed_mm_s,
        }
    }

    #[test]
    fn the_cruise_speed_makes_up_for_the_time_spent_turning() {
        // 15 turns a minute at 0.8 s each: a fifth of the time turning
        assert!((cruise_mm_s(&stats(120.0, 15.0), 0.8) - 150.0).abs() < 1e-9);
        assert_eq!(cruise_mm_s(&stats(120.0, 15.0), 0.0), 120.0);
        // a robot that would do nothing but turn is capped at 90 % of the time
        assert!((cruise_mm_s(&stats(10.0, 600.0), 1.0) - 100.0).abs() < 1e-9);
    }
}

/// What to validate.
#[derive(Debug, Clone)]
pub struct ValidateConfig {
    /// The world the simulated robot drives in.
    pub world: World,
    /// Its name in tables.
    pub world_label: String,
    /// One simulated run per recorded run and seed.
    pub seeds: Vec<u64>,
    /// Worker threads (0 = all cores).
    pub jobs: usize,
    /// Which recorded runs to simulate.
    pub runs: RunSet,
    /// The simulated robot's camera noise ([`alvs_sim::SensorNoise::typical`] unless
    /// calibrating its exposure or shake).
    pub noise: alvs_sim::SensorNoise,
    /// Where the simulated robot's camera sits (level at 20 mm unless calibrating the mount).
    pub mount: alvs_sim::CameraMount,
    /// A diagnostic, not the baseline: a forward proximity sensor of this range (mm from the
    /// body's front) whose alert starts the LGMD2's turn (docs/world.md, "What is left").
    pub proximity_mm: Option<f64>,
    /// Straight driving a turn costs, s ([`TURN_COST_S`]; 0: cruise at the mean path speed).
    pub turn_cost_s: f64,
}

/// A choice of recorded runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RunSet {
    /// All of them.
    #[default]
    All,
    /// The 10.9 cm/s runs, which the world may be calibrated on.
    Calibration,
    /// The others.
    HeldOut,
}

impl RunSet {
    /// Whether a run at `speed_cm_s` belongs to the set.
    pub fn holds(self, speed_cm_s: f64) -> bool {
        let calibration = is_calibration(speed_cm_s);
        match self {
            RunSet::All => true,
            RunSet::Calibration => calibration,
            RunSet::HeldOut => !calibration,
        }
    }
}

/// Whether a run at `speed_cm_s` is a calibration run.
pub fn is_calibration(speed_cm_s: f64) -> bool {
    (speed_cm_s - CALIBRATION_SPEED_CM_S).abs() < 1e-9
}

/// One simulated run of a recorded run.
#[derive(Debug, Clone, Serialize)]
pub struct SimResult {
    pub seed: u64,
    pub stats: PathStats,
    /// Share of camera frames pressed against a wall or obstacle (exact, from the simulation).
    pub pressed_frames_share: f64,
    /// LGMD2 collision alerts (random turns) per minute.
    pub alerts_per_min: f64,
    pub verdicts: Vec<Verdict>,
    #[serde(skip)]
    pub run_file: RunFile,
}

/// One recorded run beside its simulations.
#[derive(Debug, Clone, Serialize)]
pub struct RunComparison {
    pub run: String,
    pub speed_cm_s: f64,
    /// Calibration run (10.9 cm/s) or held out.
    pub calibration: bool,
    pub cruise_mm_s: f64,
    pub real: PathStats,
    pub sims: Vec<SimResult>,
    #[serde(skip)]
    pub real_file: RunFile,
}

impl RunComparison {
    /// How many simulations pass every statistic.
    pub fn passing(&self) -> usize {
        self.sims
            .iter()
            .filter(|s| s.verdicts.iter().all(|v| v.pass))
            .count()
    }
}

/// The whole validation.
#[derive(Debug, Clone, Serialize)]
pub struct ValidateReport {
    pub world: String,
    pub seeds: Vec<u64>,
    /// The diagnostic proximity sensor's range, if the robots had one.
    pub proximity_mm: Option<f64>,
    /// Straight driving a turn costs in the cruise estimate, s.
    pub turn_cost_s: f64,
    pub runs: Vec<RunComparison>,
    #[serde(skip)]
    pub arena: Option<ArenaGeometry>,
}

/// Runs every recorded run's simulations; `progress` is told of each finished simulation.
pub fn validate(config: &ValidateConfig, progress: &(dyn Fn() + Sync)) -> Result<ValidateReport> {
    let arena = recordings::arena()?;
    let runs: Vec<RunFile> = recordings::all_runs()?
        .into_iter()
        .filter(|r| config.runs.holds(r.speed_cm_s))
        .collect();
    let plan: Vec<(usize, u64)> = (0..runs.len())
        .flat_map(|r| config.seeds.iter().map(move |&s| (r, s)))
        .collect();
    let sims = parallel::slice(plan.len(), config.jobs, None, |i| {
        let (r, seed) = plan[i];
        let run = &runs[r];
        let real = run.stats(&arena);
        let cruise = cruise_mm_s(&real, config.turn_cost_s);
        let out = sim::simulate(
            &config.world,
            cruise as f32,
            real.duration_s,
            seed,
            config.noise,
            config.mount,
            config.proximity_mm,
        );
        let track = track_from_trail(&out.trail, &arena.drawing(run.snapshot_every_s()));
        let stats = PathStats::of(&track, arena.size());
        let verdicts = compare(&real, &stats);
        progress();
        SimResult {
            seed,
            pressed_frames_share: out.pressed_share,
            alerts_per_min: out.alerts as f64 / (real.duration_s / 60.0).max(1e-9),
            verdicts,
            stats,
            run_file: RunFile {
                run: format!("simulated {} (seed {seed})", run.run),
                track,
                ..run.clone()
            },
        }
    })?;
    let mut by_run: Vec<Vec<SimResult>> = vec![Vec::new(); runs.len()];
    for ((r, _), (_, s)) in plan.iter().zip(sims) {
        by_run[*r].push(s);
    }
    let comparisons = runs
        .iter()
        .zip(by_run)
        .map(|(run, sims)| {
            let real = run.stats(&arena);
            RunComparison {
                run: run.run.clone(),
                speed_cm_s: run.speed_cm_s,
                calibration: is_calibration(run.speed_cm_s),
                cruise_mm_s: cruise_mm_s(&real, config.turn_cost_s),
                real,
                sims,
                real_file: run.clone(),
            }
        })
        .collect();
    Ok(ValidateReport {
        world: config.world_label.clone(),
        seeds: config.seeds.clone(),
        proximity_mm: config.proximity_mm,
        turn_cost_s: config.turn_cost_s,
        runs: comparisons,
        arena: Some(arena),
    })
}

/// Mean of `f` over a run's simulations that give a finite value (a run without turns has no
/// wall distance at turns: its mean is over the others).
fn mean(sims: &[SimResult], f: impl Fn(&SimResult) -> f64) -> f64 {
    let v: Vec<f64> = sims.iter().map(f).filter(|v| v.is_finite()).collect();
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

impl Report for ValidateReport {
    fn table(&self) -> String {
        let robot = match self.proximity_mm {
            None => "LGMD2 robot".to_string(),
            Some(r) => format!("LGMD2 robot with a {r:.0} mm proximity sensor (a diagnostic)"),
        };
        let mut s = format!(
            "world {}, seeds {:?}: real vs simulated {robot}, cruising at the mean path speed \
             plus {} s of driving a turn (simulated: mean over seeds; pass = simulations \
             inside every tolerance)\n\n",
            self.world, self.seeds, self.turn_cost_s
        );
        s += "| run | role | ≤50 mm real/sim | ≤100 mm | turns/min | run mm (median) | wall mm at turns (median) | pressed | coverage | speed mm/s | pass |\n";
        s += "|---|---|---|---|---|---|---|---|---|---|---|\n";
        for r in &self.runs {
            let m = |f: &dyn Fn(&PathStats) -> f64| mean(&r.sims, |x| f(&x.stats));
            s += &format!(
                "| {} | {} | {:.2} / {:.2} | {:.2} / {:.2} | {:.1} / {:.1} | {:.0} / {:.0} | {:.0} / {:.0} | {:.2} / {:.2} | {:.2} / {:.2} | {:.0} / {:.0} | {} of {} |\n",
                r.run,
                if r.calibration { "calibration" } else { "held out" },
                r.real.share_within_50mm,
                m(&|p| p.share_within_50mm),
                r.real.share_within_100mm,
                m(&|p| p.share_within_100mm),
                r.real.turns_per_min,
                m(&|p| p.turns_per_min),
                r.real.run_mm.median,
                m(&|p| p.run_mm.median),
                r.real.turn_wall_mm.median,
                m(&|p| p.turn_wall_mm.median),
                r.real.pressed_share,
                m(&|p| p.pressed_share),
                r.real.coverage,
                m(&|p| p.coverage),
                r.real.mean_speed_mm_s,
                m(&|p| p.mean_speed_mm_s),
                r.passing(),
                r.sims.len()
            );
        }
        s += "\nper statistic, simulations inside the tolerance:\n\n| run |";
        let names: Vec<String> = self
            .runs
            .first()
            .and_then(|r| r.sims.first())
            .map(|x| x.verdicts.iter().map(|v| v.statistic.clone()).collect())
            .unwrap_or_default();
        for n in &names {
            s += &format!(" {n} |");
        }
        s += "\n|---|";
        s += &"---|".repeat(names.len());
        s += "\n";
        for r in &self.runs {
            s += &format!("| {} |", r.run);
            for k in 0..names.len() {
                let ok = r
                    .sims
                    .iter()
                    .filter(|x| x.verdicts.get(k).is_some_and(|v| v.pass))
                    .count();
                s += &format!(" {ok}/{} |", r.sims.len());
            }
            s += "\n";
        }
        s += "\nsimulation only (exact): cruise speed, time pressed against a wall or obstacle, \
              alerts/min\n\n";
        for r in &self.runs {
            s += &format!(
                "{}: cruise {:.0} mm/s, pressed {:.0} % of frames, {:.1} alerts/min\n",
                r.run,
                r.cruise_mm_s,
                100.0 * mean(&r.sims, |x| x.pressed_frames_share),
                mean(&r.sims, |x| x.alerts_per_min)
            );
        }
        s
    }

    fn json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or(serde_json::Value::Null)
    }

    fn write_pictures(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let Some(arena) = &self.arena else {
            return Ok(Vec::new());
        };
        let mut out = Vec::new();
        for r in &self.runs {
            let Some(first) = r.sims.first() else {
                continue;
            };
            let real = recordings::report::run_picture(&r.real_file, arena, &r.real);
            let sim = recordings::report::run_picture(&first.run_file, arena, &first.stats);
            let pic = alvs_sim::canvas::Canvas::side_by_side(&[real, sim]);
            let path = dir.join(format!("{}.png", r.run));
            pic.save_png(&path)
                .with_context(|| format!("cannot write {}", path.display()))?;
            out.push(path);
        }
        Ok(out)
    }
}

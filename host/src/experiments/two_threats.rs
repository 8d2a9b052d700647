//! Experiment 3, `two-threats` (paper Sec. III-B, Fig. 4b): two obstacle robots approach the
//! standing tested robot at the same time from opposite sides of its view at unequal constant
//! speeds; over many runs, how often does it evade away from the faster one?
//!
//! Run `r` draws from the seed's stream `r`: which side the faster obstacle comes from (left or
//! right, equally likely), each obstacle's bearing (uniform 10°..35° on its side, so both are in
//! view and on different sides) and start distance (uniform 450..550 mm). The faster obstacle
//! drives at [`TwoThreatConfig::fast_mm_s`], the slower at [`TwoThreatConfig::slow_mm_s`].
//!
//! The tested robot stands at the same place in every run: as designed in the `lab`
//! ([`encounter::TESTED_START`]), elsewhere where the stage (every path the draws allow, the
//! tested robot and its escape room) fits with the most room ([`alvs_sim::stage`]).
//!
//! A run **evades away from the faster** when the tested robot's escape turn goes to the side
//! away from the faster obstacle ([`alvs_sim::encounter`]: its heading change over its first
//! takeoff, beyond 5°). The paper's robot
//! "identified the faster of the two incoming robots as the more imminent threat and executed
//! an evasion maneuver opposite to its approach".

use std::path::{Path, PathBuf};

use alvs_tasks::Params;
use anyhow::{ensure, Context, Result};
use serde::{Deserialize, Serialize};

use super::sweep::{self, Shard, Sweep};
use super::{parallel, Report};
use alvs_sim::canvas::{colour_cycle, Canvas, Rgb, BLACK, WHITE};
use alvs_sim::encounter::{self, Encounter, EncounterResult, Side, Threat, Traced};
use alvs_sim::stage::{Placement, Shape, Stage, Staged};
use alvs_sim::{BuiltinWorld, Kind, Rng, TopDown};

/// Random stream of the runs' geometry.
const GEOMETRY_STREAM: u64 = 0x0002_7417;
/// An obstacle's bearing is uniform over this on its side, degrees.
pub const BEARINGS_DEG: (f64, f64) = (10.0, 35.0);
/// An obstacle's start distance is uniform over this, mm.
pub const DISTANCES_MM: (f64, f64) = (450.0, 550.0);

/// What to run.
#[derive(Debug, Clone)]
pub struct TwoThreatConfig {
    /// Runs per controller.
    pub runs: usize,
    /// Speed of the faster obstacle, mm/s.
    pub fast_mm_s: f64,
    /// Speed of the slower obstacle, mm/s.
    pub slow_mm_s: f64,
    /// Controllers of the tested robot.
    pub controllers: Vec<Kind>,
    /// Seed of the geometry, the noise and LGMD2's turns.
    pub seed: u64,
    /// ALVS model parameters.
    pub params: Params,
    /// Motion parameters of the controllers (`--fsm NAME=VALUE`).
    pub fsm: alvs_tasks::model::fsm::FsmParams,
    /// Keep every trial's frame-by-frame trace ([`encounter::TraceRow`]) for `--trace`.
    pub trace: bool,
    /// The world.
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

impl Default for TwoThreatConfig {
    fn default() -> Self {
        TwoThreatConfig {
            runs: 20,
            fast_mm_s: 200.0,
            slow_mm_s: 100.0,
            controllers: vec![Kind::Alvs, Kind::Lgmd2],
            seed: 1,
            params: Params::default(),
            fsm: alvs_tasks::model::fsm::FsmParams::default(),
            trace: false,
            world: BuiltinWorld::Fu2019,
            background: None,
            exposure: 0.0,
            gain: alvs_sim::GainModel::default(),
        }
    }
}

/// The geometry of one run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pair {
    /// The faster obstacle.
    pub fast: ThreatJson,
    /// The slower obstacle.
    pub slow: ThreatJson,
}

/// An obstacle for JSON.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ThreatJson {
    /// Bearing, degrees, positive = right.
    pub bearing_deg: f64,
    /// Start distance, mm.
    pub distance_mm: f64,
    /// Speed, mm/s.
    pub speed_mm_s: f64,
}

impl From<ThreatJson> for Threat {
    fn from(t: ThreatJson) -> Threat {
        Threat {
            bearing_deg: t.bearing_deg,
            distance_mm: t.distance_mm,
            speed_mm_s: t.speed_mm_s,
        }
    }
}

impl TwoThreatConfig {
    /// The stage: every path an obstacle may drive (the sectors of [`BEARINGS_DEG`] on both
    /// sides out to the longest of [`DISTANCES_MM`]), the tested robot and its escape room.
    pub fn stage() -> Stage {
        let (b0, b1) = BEARINGS_DEG;
        encounter::tested_stage([-1.0, 1.0].map(|side| Shape::Sector {
            mid_deg: side * (b0 + b1) / 2.0,
            half_deg: (b1 - b0) / 2.0,
            radius_mm: DISTANCES_MM.1,
        }))
    }

    /// Where the stage stands in the world (whether it fits is [`TwoThreatConfig::validate`]'s).
    pub fn placement(&self) -> Placement {
        Self::stage().place(&self.world.world(), encounter::tested_start())
    }

    /// Checks the configuration, the background and that the stage fits (one error line);
    /// gives the world with its walls and where the stage stands.
    pub fn validate(&self) -> Result<Staged> {
        ensure!(
            (1..=100_000).contains(&self.runs),
            "--runs must be 1..=100000, got {}",
            self.runs
        );
        for (name, v) in [("--fast", self.fast_mm_s), ("--slow", self.slow_mm_s)] {
            ensure!(
                v.is_finite() && (10.0..=400.0).contains(&v),
                "{name} must be 10..=400 mm/s, got {v}"
            );
        }
        ensure!(
            self.fast_mm_s > self.slow_mm_s,
            "--fast ({}) must be faster than --slow ({})",
            self.fast_mm_s,
            self.slow_mm_s
        );
        super::validate_setup(&self.controllers, &self.params)?;
        let what = "the two threats' stage";
        self.placement()
            .staged(self.world, self.background.as_deref(), what)
    }

    /// The geometry of run `r`.
    pub fn pair(&self, r: usize) -> Pair {
        let mut rng = Rng::new(self.seed).fork(GEOMETRY_STREAM).fork(r as u64);
        let fast_side = if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
        let mut draw = |side: f64, speed: f64| {
            let b = rng.range(BEARINGS_DEG.0, BEARINGS_DEG.1);
            let d = rng.range(DISTANCES_MM.0, DISTANCES_MM.1);
            ThreatJson {
                bearing_deg: (side * b * 100.0).round() / 100.0,
                distance_mm: d.round(),
                speed_mm_s: speed,
            }
        };
        let fast = draw(fast_side, self.fast_mm_s);
        let slow = draw(-fast_side, self.slow_mm_s);
        Pair { fast, slow }
    }

    /// Camera frames of the whole run, approximately (for a progress bar).
    pub fn total_frames(&self) -> u64 {
        (0..self.runs)
            .map(|r| {
                let p = self.pair(r);
                encounter::frames_of(&[p.fast.into(), p.slow.into()])
            })
            .sum::<u64>()
            * self.controllers.len() as u64
    }
}

/// One run's outcome.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunOutcome {
    /// The geometry.
    pub threats: Pair,
    /// The side the robot turned to.
    pub side: Side,
    /// Turned to the side away from the faster obstacle.
    pub away_from_faster: bool,
    /// Collided with the faster obstacle.
    pub collided_fast: bool,
    /// Collided with the slower obstacle.
    pub collided_slow: bool,
    /// First alert, s; `null` without one.
    pub first_alert_s: Option<f64>,
    /// Tested robot's positions, 10 per second, mm.
    pub trail: Vec<[f64; 2]>,
}

impl RunOutcome {
    fn new(threats: Pair, r: &EncounterResult) -> Self {
        let side = r.side();
        RunOutcome {
            threats,
            side,
            away_from_faster: side == Side::away_from(threats.fast.bearing_deg),
            collided_fast: r.collided_with[0],
            collided_slow: r.collided_with[1],
            first_alert_s: r.first_alert_s.map(|s| (s * 1000.0).round() / 1000.0),
            trail: r.trails[0]
                .iter()
                .map(|&(x, y)| [(x * 10.0).round() / 10.0, (y * 10.0).round() / 10.0])
                .collect(),
        }
    }
}

/// One controller's runs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ControllerTwoThreats {
    /// "alvs", "lgmd2", "swarm".
    pub controller: &'static str,
    /// Runs.
    pub runs: usize,
    /// Runs that turned away from the faster obstacle.
    pub away_from_faster: usize,
    /// `away_from_faster / runs`.
    pub fraction: f64,
    /// Runs that turned away from the slower obstacle, i.e. towards the faster one's side.
    pub towards_faster: usize,
    /// Runs with a collision (either obstacle).
    pub collisions: usize,
    /// Per run.
    pub per_run: Vec<RunOutcome>,
}

/// Everything a run produced.
#[derive(Debug, Clone)]
pub struct TwoThreatReport {
    /// What ran.
    pub config: TwoThreatConfig,
    /// Where it ran, the stage's placement included.
    pub setting: encounter::Setting,
    /// One per controller.
    pub controllers: Vec<ControllerTwoThreats>,
    /// Wall-clock seconds.
    pub wall_clock_s: f64,
    /// Per trial, its CSV leading fields and its trace (empty rows unless the config's `trace`).
    pub traces: Vec<(String, Vec<encounter::TraceRow>)>,
}

/// Runs every (controller, run) trial on `jobs` threads (0 = all cores).
pub fn run(
    config: &TwoThreatConfig,
    jobs: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<TwoThreatReport> {
    sweep::run_all(config, jobs, progress)
}

/// Trial `k` is (controller `k / runs`, run `k mod runs`).
impl Sweep for TwoThreatConfig {
    const NAME: &'static str = "two-threats";
    type Trial = Traced<RunOutcome>;
    type Report = TwoThreatReport;

    fn trial_count(&self) -> usize {
        self.controllers.len() * self.runs
    }

    fn run_slice(
        &self,
        jobs: usize,
        shard: Option<Shard>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<(usize, Self::Trial)>> {
        let base = Encounter::staged(
            self.validate()?,
            self.params,
            self.fsm,
            self.exposure,
            self.gain,
            self.trace,
        );
        let n = self.runs;
        parallel::slice(self.trial_count(), jobs, shard, |i| {
            let (kind, r) = (self.controllers[i / n], i % n);
            let pair = self.pair(r);
            let e = Encounter {
                kind,
                threats: vec![pair.fast.into(), pair.slow.into()],
                // every controller meets the same noise in run r
                seed: Rng::new(self.seed).fork(r as u64).next_u64(),
                ..base.clone()
            };
            let lead = format!("{},{r}", kind.name());
            encounter::run_traced(&e, lead, progress, |res| RunOutcome::new(pair, res))
        })
    }

    fn report(&self, trials: Vec<Self::Trial>, wall_clock_s: f64, _jobs: usize) -> TwoThreatReport {
        let (results, traces): (Vec<RunOutcome>, Vec<_>) =
            trials.into_iter().map(|t| (t.outcome, t.trace)).unzip();
        let n = self.runs;
        let controllers = self
            .controllers
            .iter()
            .enumerate()
            .map(|(c, &kind)| {
                let per_run: Vec<RunOutcome> = results[c * n..(c + 1) * n].to_vec();
                let away = per_run.iter().filter(|o| o.away_from_faster).count();
                ControllerTwoThreats {
                    controller: kind.name(),
                    runs: n,
                    away_from_faster: away,
                    fraction: away as f64 / n as f64,
                    towards_faster: per_run
                        .iter()
                        .filter(|o| o.side == Side::away_from(o.threats.slow.bearing_deg))
                        .count(),
                    collisions: per_run
                        .iter()
                        .filter(|o| o.collided_fast || o.collided_slow)
                        .count(),
                    per_run,
                }
            })
            .collect();
        TwoThreatReport {
            config: self.clone(),
            setting: encounter::Setting {
                world: self.world,
                background: self.background.clone(),
                seed: self.seed,
                placement: self.placement(),
            },
            controllers,
            wall_clock_s,
            traces,
        }
    }
}

impl Report for TwoThreatReport {
    /// `{"alvs":{"runs":..,"away_from_faster":..,"fraction":..,...},"lgmd2":{...}}`.
    fn json(&self) -> serde_json::Value {
        let cfg = &self.config;
        super::per_controller_json(
            self.controllers
                .iter()
                .map(|c| (c.controller.to_string(), c)),
            self.setting.json(serde_json::json!({
                "runs": cfg.runs,
                "fast_mm_s": cfg.fast_mm_s,
                "slow_mm_s": cfg.slow_mm_s,
            })),
        )
    }

    /// One line per controller.
    fn table(&self) -> String {
        use std::fmt::Write;
        let c = &self.config;
        let mut out = String::new();
        let _ = write!(
            out,
            "two-threats: {} runs, faster {} mm/s vs slower {} mm/s from opposite sides, {}",
            c.runs,
            c.fast_mm_s,
            c.slow_mm_s,
            self.setting.title(self.wall_clock_s)
        );
        let _ = writeln!(
            out,
            "{:<8} {:>6} {:>18} {:>16} {:>11}",
            "ctrl", "runs", "away from faster", "towards faster", "collisions"
        );
        for ce in &self.controllers {
            let _ = writeln!(
                out,
                "{:<8} {:>6} {:>11} ({:>3.0} %) {:>16} {:>11}",
                ce.controller,
                ce.runs,
                ce.away_from_faster,
                100.0 * ce.fraction,
                ce.towards_faster,
                ce.collisions
            );
        }
        out
    }

    /// Writes the trials' traces as CSV (`controller,run,` + [`encounter::TRACE_HEADER`]).
    fn write_trace(&self, path: &Path) -> Result<()> {
        encounter::write_trace(path, "controller,run", &self.traces)
    }

    /// `two_threats.png` in `dir`: per controller, the tested robot's paths of the first runs
    /// (up to 12), green when it turned away from the faster obstacle, red otherwise.
    fn write_pictures(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let panels: Vec<Canvas> = self
            .controllers
            .iter()
            .map(|ce| panel(ce, &self.setting))
            .collect();
        let c = Canvas::side_by_side(&panels);
        let path = dir.join("two_threats.png");
        c.save_png(&path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        Ok(vec![path])
    }
}

const GOOD: Rgb = [30, 150, 60];
const BAD: Rgb = [210, 40, 40];
const FAST: Rgb = [40, 90, 200];
const SLOW: Rgb = [160, 160, 160];

fn panel(ce: &ControllerTwoThreats, setting: &encounter::Setting) -> Canvas {
    let (world, start) = (setting.world.world(), &setting.placement.pose);
    let mut td = TopDown::of_world(&world, 0.6);
    td.title(&format!(
        "{}: away from the faster in {}/{} runs ({:.0} %), {} with a collision",
        ce.controller.to_uppercase(),
        ce.away_from_faster,
        ce.runs,
        100.0 * ce.fraction,
        ce.collisions
    ));
    for o in ce.per_run.iter().take(12) {
        for (t, colour) in [(o.threats.fast, FAST), (o.threats.slow, SLOW)] {
            let p = Threat::from(t).start_pose(start);
            td.trail(&[(p.x_mm, p.y_mm), (start.x_mm, start.y_mm)], colour);
            td.mark(p.x_mm, p.y_mm, colour);
        }
    }
    for o in ce.per_run.iter().take(12) {
        let pts: Vec<(f64, f64)> = o.trail.iter().map(|p| (p[0], p[1])).collect();
        td.trail(&pts, if o.away_from_faster { GOOD } else { BAD });
    }
    td.robot(start, colour_cycle(0));
    let pic = td.into_canvas();
    let legend = "blue: faster obstacle's path, grey: slower; tested robot's path green when it \
                  turned away from the faster, red otherwise (first 12 runs)";
    let (lw, lh) = Canvas::text_size(legend, 1);
    let mut c = Canvas::new(pic.width.max(lw + 16), pic.height + lh + 8, WHITE);
    c.blit(&pic, 0, 0);
    c.text(8, pic.height as i32 + 2, legend, BLACK, 1);
    c
}

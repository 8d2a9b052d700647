//! Experiment 2, `evasion` (paper Sec. III-B, Fig. 4a,c,d): one obstacle robot approaches the
//! standing tested robot at a constant speed from each of nine bearings, −35°..35° (the edges
//! and seven evenly spaced bearings in between, 8.75° apart); per bearing: did the tested robot
//! escape to the side away from the obstacle, and did it collide? ALVS and LGMD2 meet the same
//! obstacles with the same seeds.
//!
//! The geometry and outcome are [`alvs_sim::encounter`]'s. The stage (the nine paths, the tested
//! robot and its escape room) stands as designed in the `lab`; in another world where it fits
//! with the most room ([`alvs_sim::stage`]), with the obstacle [`DEFAULT_DISTANCE_MM`] away or,
//! where that does not fit, the longest distance in [`DISTANCE_STEP_MM`] steps that does.
//!
//! The **correct side** for an obstacle on
//! the right (positive bearing) is an escape turn to the left and vice versa; for the obstacle
//! dead ahead (0°) both sides are away from it, and the trial counts as correct when the robot
//! turned at least 90° either way (it faces away from the threat).

use std::path::{Path, PathBuf};

use alvs_tasks::model::fsm::State;
use alvs_tasks::Params;
use anyhow::{ensure, Context, Result};
use serde::{Deserialize, Serialize};

use super::sweep::{self, Shard, Sweep};
use super::{parallel, Report};
use alvs_sim::canvas::{colour_cycle, Canvas, Rgb, BLACK, WHITE};
use alvs_sim::encounter::{self, Encounter, EncounterResult, Side, Threat, Traced};
use alvs_sim::stage::{Placement, Stage, Staged, MIN_CLEARANCE_MM};
use alvs_sim::{BuiltinWorld, Kind, Rng, TopDown};

pub use alvs_sim::encounter::{DEFAULT_DISTANCE_MM, DEFAULT_SPEED_MM_S};
/// Widest bearing, degrees: the edge of the 70° field of view (paper: −35°..35°).
pub const MAX_BEARING_DEG: f64 = 35.0;
/// Steps of the start distance when [`DEFAULT_DISTANCE_MM`] does not fit in the world, mm.
pub const DISTANCE_STEP_MM: f64 = 10.0;
/// Shortest start distance, mm (`--distance`).
pub const MIN_DISTANCE_MM: f64 = 60.0;

/// What to run.
#[derive(Debug, Clone)]
pub struct EvasionConfig {
    /// Bearings, evenly spaced over −35°..35° (9 in the paper).
    pub angles: usize,
    /// Start distance of the obstacle, mm; `None`: [`DEFAULT_DISTANCE_MM`] where the stage
    /// fits, else the longest that fits ([`EvasionConfig::placement`]).
    pub distance_mm: Option<f64>,
    /// Speed of the obstacle, mm/s.
    pub speed_mm_s: f64,
    /// Controllers of the tested robot.
    pub controllers: Vec<Kind>,
    /// Seed of the noise and of LGMD2's turns.
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

impl Default for EvasionConfig {
    fn default() -> Self {
        EvasionConfig {
            angles: 9,
            distance_mm: None,
            speed_mm_s: DEFAULT_SPEED_MM_S,
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

impl EvasionConfig {
    /// The bearings, degrees.
    pub fn bearings(&self) -> Vec<f64> {
        bearings(self.angles)
    }

    /// The stage of an obstacle `distance_mm` away from every bearing.
    pub fn stage(&self, distance_mm: f64) -> Stage {
        encounter::tested_stage(
            self.bearings()
                .into_iter()
                .map(|b| encounter::approach_path(b, distance_mm)),
        )
    }

    /// The obstacle's start distance and where the stage stands in the world: at `distance_mm`
    /// if given, else at [`DEFAULT_DISTANCE_MM`] or, where that does not fit with
    /// [`MIN_CLEARANCE_MM`] to spare, the longest distance in [`DISTANCE_STEP_MM`] steps that
    /// does (down to [`MIN_DISTANCE_MM`]). Whether it fits is [`EvasionConfig::validate`]'s.
    pub fn placement(&self) -> (f64, Placement) {
        let world = self.world.world();
        let place = |d: f64| self.stage(d).place(&world, encounter::tested_start());
        if let Some(d) = self.distance_mm {
            return (d, place(d));
        }
        let mut d = DEFAULT_DISTANCE_MM;
        loop {
            let p = place(d);
            if p.clearance_mm >= MIN_CLEARANCE_MM || d - DISTANCE_STEP_MM < MIN_DISTANCE_MM {
                return (d, p);
            }
            d -= DISTANCE_STEP_MM;
        }
    }

    /// Checks the configuration, the background and that the stage fits (one error line);
    /// gives the start distance and the world with its walls and where the stage stands.
    pub fn validate(&self) -> Result<(f64, Staged)> {
        ensure!(
            (1..=181).contains(&self.angles),
            "--angles must be 1..=181, got {}",
            self.angles
        );
        if let Some(d) = self.distance_mm {
            ensure!(
                d.is_finite() && (MIN_DISTANCE_MM..=550.0).contains(&d),
                "--distance must be 60..=550 mm (the obstacle must start clear of the tested \
                 robot and inside the arena), got {d}"
            );
        }
        ensure!(
            self.speed_mm_s.is_finite() && (10.0..=400.0).contains(&self.speed_mm_s),
            "--speed must be 10..=400 mm/s, got {}",
            self.speed_mm_s
        );
        super::validate_setup(&self.controllers, &self.params)?;
        let (d, p) = self.placement();
        let what = format!("the evasion's stage (the obstacle {d} mm away)");
        let staged = p.staged(self.world, self.background.as_deref(), &what)?;
        Ok((d, staged))
    }

    /// Camera frames of one controller's trials (for a progress bar).
    pub fn total_frames(&self) -> u64 {
        let t = self.threat(0.0, self.placement().0);
        encounter::frames_of(&[t]) * self.angles as u64 * self.controllers.len() as u64
    }

    fn threat(&self, bearing_deg: f64, distance_mm: f64) -> Threat {
        Threat {
            bearing_deg,
            distance_mm,
            speed_mm_s: self.speed_mm_s,
        }
    }
}

/// `n` bearings evenly spaced over −35°..35° (0° alone for `n` = 1).
pub fn bearings(n: usize) -> Vec<f64> {
    if n <= 1 {
        return vec![0.0; n];
    }
    (0..n)
        .map(|i| -MAX_BEARING_DEG + 2.0 * MAX_BEARING_DEG * i as f64 / (n - 1) as f64)
        .map(|b| (b * 1e6).round() / 1e6 + 0.0)
        .collect()
}

/// One bearing's outcome.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AngleOutcome {
    /// Bearing of the obstacle, degrees, positive = right.
    pub angle_deg: f64,
    /// The side away from the obstacle (`none` dead ahead).
    pub away: Side,
    /// The side the robot turned to.
    pub side: Side,
    /// Escaped to the correct side (see the module documentation).
    pub correct_side: bool,
    /// Collided with the obstacle.
    pub collided: bool,
    /// Final displacement to the initial right, mm.
    pub lateral_mm: f64,
    /// Final displacement along the initial heading, mm.
    pub forward_mm: f64,
    /// Heading change from the start to the end of the first takeoff, degrees.
    pub escape_turn_deg: f64,
    /// First alert, s after the start; `null` if it never alerted.
    pub first_alert_s: Option<f64>,
    /// The state the first alert started: ALVS `long_takeoff` (turn, then run) or
    /// `short_takeoff` (the γ path); `null` if it never alerted.
    #[serde(deserialize_with = "sweep::static_name_opt")]
    pub reaction: Option<sweep::StaticName>,
    /// Closest centre distance to the obstacle, mm.
    pub min_distance_mm: f64,
    /// Tested robot's positions, 10 per second, mm.
    pub trail: Vec<[f64; 2]>,
    /// Obstacle's positions, mm.
    pub obstacle_trail: Vec<[f64; 2]>,
}

impl AngleOutcome {
    fn new(angle_deg: f64, r: &EncounterResult) -> Self {
        let away = Side::away_from(angle_deg);
        let collided = r.collided();
        let side = r.side();
        let correct_side = match away {
            Side::None => r.escape_turn_deg.abs() >= 90.0,
            s => s == side,
        };
        let round = |t: &Vec<(f64, f64)>| -> Vec<[f64; 2]> {
            t.iter().map(|&(x, y)| [round1(x), round1(y)]).collect()
        };
        AngleOutcome {
            angle_deg,
            away,
            side,
            correct_side,
            collided,
            lateral_mm: round1(r.lateral_mm),
            forward_mm: round1(r.forward_mm),
            escape_turn_deg: round1(r.escape_turn_deg),
            first_alert_s: r.first_alert_s.map(|s| (s * 1000.0).round() / 1000.0),
            reaction: r.first_reaction,
            min_distance_mm: round1(r.min_distance_mm[0]),
            trail: round(&r.trails[0]),
            obstacle_trail: round(&r.trails[1]),
        }
    }
}

fn round1(v: f64) -> f64 {
    (v * 10.0).round() / 10.0
}

/// One controller's trials.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ControllerEvasion {
    /// "alvs", "lgmd2", "swarm".
    pub controller: &'static str,
    /// Bearings tried.
    pub angles: usize,
    /// Bearings escaped to the correct side.
    pub correct_side: usize,
    /// Bearings with a collision.
    pub collisions: usize,
    /// Bearings at which it alerted at all.
    pub alerted: usize,
    /// Per bearing, from −35° to 35°.
    pub per_angle: Vec<AngleOutcome>,
}

impl ControllerEvasion {
    /// Bearings whose first alert started a short takeoff (the γ path); `None` for a
    /// controller without one (LGMD2's escape has no short mode).
    pub fn gamma_paths(&self) -> Option<usize> {
        let short = State::ShortTakeoff.name();
        (self.controller != Kind::Lgmd2.name()).then(|| {
            self.per_angle
                .iter()
                .filter(|o| o.reaction == Some(short))
                .count()
        })
    }
}

/// Everything a run produced.
#[derive(Debug, Clone)]
pub struct EvasionReport {
    /// What ran.
    pub config: EvasionConfig,
    /// The obstacle's start distance, mm.
    pub distance_mm: f64,
    /// Where it ran, the stage's placement included.
    pub setting: encounter::Setting,
    /// One per controller, in the configuration's order.
    pub controllers: Vec<ControllerEvasion>,
    /// Wall-clock seconds.
    pub wall_clock_s: f64,
    /// Per trial, its CSV leading fields and its trace (empty rows unless the config's `trace`).
    pub traces: Vec<(String, Vec<encounter::TraceRow>)>,
}

/// Runs every (controller, bearing) trial on `jobs` threads (0 = all cores).
pub fn run(
    config: &EvasionConfig,
    jobs: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<EvasionReport> {
    sweep::run_all(config, jobs, progress)
}

/// Trial `k` is (controller `k / bearings`, bearing `k mod bearings`).
impl Sweep for EvasionConfig {
    const NAME: &'static str = "evasion";
    type Trial = Traced<AngleOutcome>;
    type Report = EvasionReport;

    fn trial_count(&self) -> usize {
        self.controllers.len() * self.angles
    }

    fn run_slice(
        &self,
        jobs: usize,
        shard: Option<Shard>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<(usize, Self::Trial)>> {
        let (distance, staged) = self.validate()?;
        let base = Encounter::staged(
            staged,
            self.params,
            self.fsm,
            self.exposure,
            self.gain,
            self.trace,
        );
        let bearings = self.bearings();
        parallel::slice(self.trial_count(), jobs, shard, |i| {
            let (kind, b) = (
                self.controllers[i / bearings.len()],
                bearings[i % bearings.len()],
            );
            let e = Encounter {
                kind,
                threats: vec![self.threat(b, distance)],
                // each bearing its own noise and LGMD2 turn, the same for every controller
                seed: Rng::new(self.seed)
                    .fork((i % bearings.len()) as u64)
                    .next_u64(),
                ..base.clone()
            };
            let lead = format!("{},{b:.2}", kind.name());
            encounter::run_traced(&e, lead, progress, |r| AngleOutcome::new(b, r))
        })
    }

    fn report(&self, trials: Vec<Self::Trial>, wall_clock_s: f64, _jobs: usize) -> EvasionReport {
        let (results, traces): (Vec<AngleOutcome>, Vec<_>) =
            trials.into_iter().map(|t| (t.outcome, t.trace)).unzip();
        let n = self.angles;
        let controllers = self
            .controllers
            .iter()
            .enumerate()
            .map(|(c, &kind)| {
                let per_angle: Vec<AngleOutcome> = results[c * n..(c + 1) * n].to_vec();
                ControllerEvasion {
                    controller: kind.name(),
                    angles: per_angle.len(),
                    correct_side: per_angle.iter().filter(|o| o.correct_side).count(),
                    collisions: per_angle.iter().filter(|o| o.collided).count(),
                    alerted: per_angle
                        .iter()
                        .filter(|o| o.first_alert_s.is_some())
                        .count(),
                    per_angle,
                }
            })
            .collect();
        let (distance_mm, placement) = self.placement();
        EvasionReport {
            config: self.clone(),
            distance_mm,
            setting: encounter::Setting {
                world: self.world,
                background: self.background.clone(),
                seed: self.seed,
                placement,
            },
            controllers,
            wall_clock_s,
            traces,
        }
    }
}

impl Report for EvasionReport {
    /// `{"alvs":{"angles":9,"correct_side":k,"collisions":c,...},"lgmd2":{...}}`.
    fn json(&self) -> serde_json::Value {
        let cfg = &self.config;
        super::per_controller_json(
            self.controllers
                .iter()
                .map(|c| (c.controller.to_string(), c)),
            self.setting.json(serde_json::json!({
                "distance_mm": self.distance_mm,
                "speed_mm_s": cfg.speed_mm_s,
            })),
        )
    }

    /// One line per bearing and controller, then the totals.
    fn table(&self) -> String {
        use std::fmt::Write;
        let c = &self.config;
        let mut out = String::new();
        let _ = write!(
            out,
            "evasion: obstacle from {} bearings, {} mm away at {} mm/s, {}",
            c.angles,
            self.distance_mm,
            c.speed_mm_s,
            self.setting.title(self.wall_clock_s)
        );
        let _ = writeln!(
            out,
            "{:<8} {:>8} {:>6} {:>6} {:>6} {:>8} {:>9} {:>8} {:>9} {:>8}  reaction",
            "ctrl",
            "bearing",
            "away",
            "turn",
            "deg",
            "correct",
            "collided",
            "alert s",
            "lateral",
            "min mm"
        );
        for ce in &self.controllers {
            for o in &ce.per_angle {
                let _ = writeln!(
                    out,
                    "{:<8} {:>8.2} {:>6} {:>6} {:>6.0} {:>8} {:>9} {:>8} {:>9.0} {:>8.0}  {}",
                    ce.controller,
                    o.angle_deg,
                    side_name(o.away),
                    side_name(o.side),
                    o.escape_turn_deg,
                    yes(o.correct_side),
                    yes(o.collided),
                    o.first_alert_s.map_or("-".into(), |s| format!("{s:.2}")),
                    o.lateral_mm,
                    o.min_distance_mm,
                    o.reaction.unwrap_or("-")
                );
            }
        }
        for ce in &self.controllers {
            let gamma = ce.gamma_paths().map_or(String::new(), |g| {
                format!(", γ paths (short takeoff first) {g}/{}", ce.angles)
            });
            let _ = writeln!(
                out,
                "{:<8} correct side {}/{}, collisions {}/{}, alerted {}/{}{gamma}",
                ce.controller,
                ce.correct_side,
                ce.angles,
                ce.collisions,
                ce.angles,
                ce.alerted,
                ce.angles,
            );
        }
        out
    }

    /// Writes the trials' traces as CSV (`controller,bearing_deg,` + [`encounter::TRACE_HEADER`]).
    fn write_trace(&self, path: &Path) -> Result<()> {
        encounter::write_trace(path, "controller,bearing_deg", &self.traces)
    }

    /// `evasion.png` in `dir`: per controller, a row of two top-down panels (the arena, and a
    /// close-up around the start) with the tested robot's path for every bearing (one colour
    /// per bearing) and the obstacles' paths in grey.
    fn write_pictures(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let rows: Vec<Canvas> = self
            .controllers
            .iter()
            .map(|ce| panel(ce, &self.setting))
            .collect();
        let c = Canvas::stacked(&rows);
        let path = dir.join("evasion.png");
        c.save_png(&path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        Ok(vec![path])
    }
}

fn side_name(s: Side) -> &'static str {
    match s {
        Side::Left => "left",
        Side::Right => "right",
        Side::None => "-",
    }
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

const OBSTACLE: Rgb = [150, 150, 150];

/// Side of the close-up square, mm, and its scale.
const CLOSE_UP_MM: f64 = 240.0;
const CLOSE_UP_PX_PER_MM: f64 = 2.5;

/// One controller's trials: the arena from above, and a close-up around the start where the
/// shapes of the escapes show (a γ path: reversing while turning, then forward).
fn panel(ce: &ControllerEvasion, setting: &encounter::Setting) -> Canvas {
    let (world, start) = (setting.world.world(), &setting.placement.pose);
    let mut whole = TopDown::of_world(&world, 0.6);
    whole.title(&format!(
        "{}: correct side {}/{}, collisions {}/{}",
        ce.controller.to_uppercase(),
        ce.correct_side,
        ce.angles,
        ce.collisions,
        ce.angles
    ));
    // the robot flees away from the obstacles, which come from ahead: the square reaches
    // two thirds of its side behind the start
    let (cx, cy) = start.offset(-CLOSE_UP_MM / 6.0, 0.0);
    let mut close = TopDown::window(
        cx - 0.5 * CLOSE_UP_MM,
        cy - 0.5 * CLOSE_UP_MM,
        CLOSE_UP_MM,
        CLOSE_UP_MM,
        CLOSE_UP_PX_PER_MM,
    );
    close.obstacles(&world.obstacles);
    close.title(&match ce.gamma_paths() {
        Some(g) => format!(
            "close-up, {CLOSE_UP_MM:.0} mm square: first reaction a short takeoff (gamma path) \
             on {g}/{}",
            ce.angles
        ),
        None => format!("close-up, {CLOSE_UP_MM:.0} mm square"),
    });
    // the start pose under the paths, which begin inside it
    whole.robot(start, [255, 255, 255]);
    close.robot(start, [255, 255, 255]);
    draw_trials(&mut whole, ce);
    draw_trials(&mut close, ce);
    let pic = Canvas::side_by_side(&[whole.into_canvas(), close.into_canvas()]);
    let legend = "grey: obstacle paths (x = start); colours: tested robot per bearing, -35 deg \
                  first, wide: its first reaction a gamma path; x = its end (black: collided)";
    let (lw, lh) = Canvas::text_size(legend, 1);
    let mut c = Canvas::new(pic.width.max(lw + 16), pic.height + lh + 8, WHITE);
    c.blit(&pic, 0, 0);
    c.text(8, pic.height as i32 + 2, legend, BLACK, 1);
    c
}

/// The obstacles' paths in grey, then the tested robot's per bearing, ends marked.
fn draw_trials(td: &mut TopDown, ce: &ControllerEvasion) {
    for o in &ce.per_angle {
        let pts: Vec<(f64, f64)> = o.obstacle_trail.iter().map(|p| (p[0], p[1])).collect();
        td.trail(&pts, OBSTACLE);
        if let Some(s) = pts.first() {
            td.mark(s.0, s.1, OBSTACLE);
        }
    }
    let short = State::ShortTakeoff.name();
    for (k, o) in ce.per_angle.iter().enumerate() {
        let pts: Vec<(f64, f64)> = o.trail.iter().map(|p| (p[0], p[1])).collect();
        // a γ path (the first reaction a short takeoff) drawn wide
        let width = if o.reaction == Some(short) { 3 } else { 1 };
        td.wide_trail(&pts, colour_cycle(k), width);
        if let Some(e) = pts.last() {
            td.mark(e.0, e.1, if o.collided { BLACK } else { colour_cycle(k) });
        }
    }
}

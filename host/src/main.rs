//! `alvs`: host tools for the attention-driven LPLC2 visuomotor system.
//! Run through the cargo alias: `cargo alvs <subcommand> --help`.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use alvs_host::experiments::ablation::{AblationConfig, Variant};
use alvs_host::experiments::arena::{self, ArenaConfig};
use alvs_host::experiments::robustness::{Perturbation, RobustnessConfig, SuiteController};
use alvs_host::experiments::sweep::{Shard, Sweep};
use alvs_host::experiments::{evasion, parallel, stimuli, swarm, two_threats, Report};
use alvs_host::{clip, replay, scenes};
use alvs_sim::{BuiltinWorld, Kind};
use alvs_tasks::model::fsm::{Behaviour, FsmParams};
use alvs_tasks::{Params, HEIGHT, WIDTH};
use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};

mod log_command;
mod shards;

#[derive(Parser)]
#[command(
    name = "alvs",
    version,
    about = "Host tools for the ALVS firmware: the exact task code on recorded or synthetic video"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run the perception and motor-control tasks on a clip; one JSON object per frame on stdout.
    Replay(ReplayArgs),
    /// Run the built-in synthetic scenes (approach left/centre/right, recede, translate, double
    /// and triple approach) and write their pictures.
    Demo {
        /// Where the pictures go.
        #[arg(long, default_value = "out/demo")]
        png: PathBuf,
        #[command(flatten)]
        model: ModelArgs,
    },
    /// Experiment 4 (paper Figs. 5-6): robots wander in the walled arena; success rate,
    /// collisions per minute, time per state and trajectory pictures per controller and
    /// background.
    ///
    /// One trial is one controller on one background: all robots run that controller for
    /// --minutes of simulated time. A collision is a centre distance below one robot diameter
    /// (42 mm) between two robots or between a robot and the wall; an encounter is two bodies
    /// within two diameters of each other (surface to surface); success rate = encounters
    /// without a collision / encounters. Every controller starts from the same poses with the
    /// same seed (a paired comparison). Trials run in parallel; results depend only on the
    /// options, never on --jobs.
    ///
    /// With no option: 3 robots, 10 minutes, backgrounds clutter:1, stripes:40 and checker:60,
    /// controllers alvs and lgmd2, seed 1; a table on stdout, pictures in out/arena.
    Arena(ArenaArgs),
    /// The firmware's frame budget on the Cortex-M4 cycle model: cycles per stage, RAM.
    ///
    /// Builds the firmware, times its perception + control step on worst cases and clips,
    /// prints the table; `--json` for tooling. Runs `alvs-budget` of the crate alvs-cycles,
    /// which needs cmake and libclang-dev (./test.sh installs them); `cargo alvs budget --help`
    /// lists its options.
    #[command(disable_help_flag = true)]
    Budget {
        /// Options of alvs-budget (e.g. --json, --all-clips, --write-doc docs/budget.md).
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
    /// The unmodified firmware ELF on a virtual Colias board: RTT tabs and a timing report.
    ///
    /// Boots the release firmware from its reset vector on the Cortex-M4 model with a host
    /// NVIC and models of the camera (OV7670 over SCCB, DCMI, DMA), UART4, watchdog and RTT;
    /// prints the log and telemetry tabs as `cargo embed` shows them, then frame complete →
    /// first motor byte latency, CPU load per interrupt, dropped frames. Runs `alvs-virtual`
    /// of the crate alvs-cycles (cmake and libclang-dev, as for `budget`); `cargo alvs virtual
    /// --help` lists its options (--clip, --seconds, --blanking, --sweep-blanking, ...).
    #[command(disable_help_flag = true)]
    Virtual {
        /// Options of alvs-virtual (e.g. --clip data/clips/real_bird_attack.y8 --seconds 3).
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
    /// Experiment 1 (paper Fig. 3): a standing ALVS robot watches obstacle robots translate,
    /// recede, approach, and two and three approach at once; attention-field tracks, LPLC2
    /// traces and layer pictures per scene.
    Stimuli(StimuliArgs),
    /// Experiment 2 (paper Fig. 4a,c,d): one obstacle robot approaches the standing tested
    /// robot at a constant speed from 9 bearings, -35..35 deg; per bearing, did it escape to
    /// the side away from the obstacle, and did it collide? ALVS and LGMD2 with the same seed.
    Evasion(EvasionArgs),
    /// Experiment 3 (paper Fig. 4b): two obstacle robots approach at once from opposite sides
    /// at unequal speeds; over --runs random geometries, how often does the tested robot end
    /// on the side away from the faster one?
    TwoThreats(TwoThreatArgs),
    /// Experiment 5 (paper Fig. 7): robots in the spin-on-approach (swarm) mode wander in the
    /// arena; the spread of the group over time, against the same robots escaping.
    Swarm(SwarmArgs),
    /// The simulator against the real recordings: one LGMD2 robot per recorded run, alone in
    /// the recorded arena's replica at the run's speed; its path's statistics beside the real
    /// one's, each with its tolerance (the 10.9 cm/s runs calibrate, the rest are held out).
    ///
    /// The simulated trail is drawn and extracted exactly as the tracker's snapshots are
    /// (`cargo alvs recordings`). Pictures: real and simulated path side by side per run.
    Validate(ValidateArgs),
    /// The robustness suite (issue 29): every controller (alvs, paper, lgmd2) in the validated
    /// world under each perturbation a real lab or robot brings (textured and shaded floor,
    /// camera height +-5 mm and pitch +-2 deg, a lighting gradient, a 5 % weaker motor, the
    /// firmware's odometry heading, lost frames), over seeds 11-20 by default.
    ///
    /// One trial is the arena experiment's (its robots, counting and noise) with one
    /// perturbation, one controller and one seed. One row per (perturbation, controller): the
    /// success rate with its encounters (seeds pooled) and one seed's lowest-highest, the mean
    /// speed and its share of the cruise speed (SLOW below 80 %), the time pressed against a
    /// wall or obstacle, and the change from the unperturbed row. docs/robustness.md gives
    /// each perturbation's magnitude and its source.
    Robustness(RobustnessArgs),
    /// The ablation (issue 30): every mechanism of the default removed one at a time, and
    /// added to the paper's model one at a time, beside the default, the paper's model and
    /// LGMD2, on the same seeds (11-20 by default) in the validated world: the arena (success
    /// with its encounters, mean speed, time at a wall, time escaping), evasion on three walls
    /// (correct side, collisions, seeds at the goal of 9/9 correct with at most one
    /// collision) and two threats (away from the faster, collisions). docs/ablation.md.
    Ablation(AblationArgs),
    /// The headline figures of stimuli, evasion, two-threats, arena and swarm in one world over
    /// several seeds (the report seeds 11-20 by default), printed as the markdown tables of
    /// docs/experiments.md: each row is the experiment's own default run in that world with
    /// that seed (and the arena's paper row with --model paper), so one command regenerates a
    /// table when the world changes. All five in fu2019 take about 25 minutes on one core.
    Tables(TablesArgs),
    /// The real Colias recordings (fuqinbing/LGMD2-open-source, issue 29): extract the arena
    /// and the tracks from the tracker's snapshots, or show the committed statistics.
    Recordings {
        #[command(subcommand)]
        cmd: RecordingsCmd,
    },
    /// Pool the shard files of a sweep (an experiment run as `--shard I/N --json FILE` for
    /// I = 1..N, on one machine or many) into the report an unsharded run gives: the same
    /// table, JSON and pictures (docs/sweeps.md).
    ///
    /// The shards carry their command line, configuration and program version, so nothing
    /// about the run is given again here (nor are its background pictures needed); shards of
    /// different runs or builds, a missing or repeated shard and an unreadable file are
    /// refused. A merged `stimuli` draws its tracks pictures only: the layer pictures replay
    /// camera frames the shard files do not carry.
    Merge(shards::MergeArgs),
    /// Read back a saved RTT session of the firmware (what Embed.toml's `log_enabled` makes
    /// `cargo embed` write, or a tab's text piped in) and summarise it: frames, drops, cycles
    /// per frame against the 33 ms period, time per FSM state, alerts, attention fields, each
    /// boot and what reset it, the boot self-test's `bench:` cycles next to the cycle model's
    /// for this build, and every line that could not be read (docs/log.md).
    Log(log_command::LogArgs),
}

/// The simulated worlds every experiment can run in.
#[derive(Clone, Copy, ValueEnum)]
enum WorldChoice {
    /// The recorded arena's replica (`arena::replica`): its size, low ribbed walls, dark
    /// floor, 15 obstacles, the room above the walls, the contact turn.
    Fu2019,
    /// The built-in 1200 x 900 mm arena with 250 mm clutter walls, no obstacles, rigid walls.
    Lab,
}

/// `--world`, which every experiment takes.
#[derive(clap::Args)]
struct WorldArgs {
    /// The world: fu2019, the replica of the recorded LGMD2 arena (1309 x 751 mm, 72 mm ribbed
    /// walls, a dark floor, 15 cylinder obstacles, the calibrated contact), or lab, the
    /// built-in 1200 x 900 mm arena with 250 mm walls and rigid contact (docs/world.md).
    #[arg(long, value_enum, default_value = "fu2019")]
    world: WorldChoice,
}

impl WorldArgs {
    fn builtin(&self) -> BuiltinWorld {
        match self.world {
            WorldChoice::Fu2019 => BuiltinWorld::Fu2019,
            WorldChoice::Lab => BuiltinWorld::Lab,
        }
    }
}

#[derive(clap::Args)]
struct ValidateArgs {
    #[command(flatten)]
    world: WorldArgs,
    /// Seeds of the simulations (repeatable); one simulation per recorded run and seed.
    /// Default: 11, 12, 13 (report seeds: tuning uses 1-5).
    #[arg(long = "seed", value_name = "S")]
    seeds: Vec<u64>,
    /// Threads (default: all cores); results do not depend on it.
    #[arg(long, value_name = "J", default_value_t = 0)]
    jobs: usize,
    /// Write the results as JSON.
    #[arg(long, value_name = "PATH")]
    json: Option<PathBuf>,
    /// Where the pictures go.
    #[arg(long, value_name = "DIR", default_value = "out/validate")]
    png: PathBuf,
    /// Which recorded runs: all, the 10.9 cm/s calibration runs, or the held-out others.
    #[arg(long, value_enum, default_value = "all")]
    runs: RunsArg,
    /// Override the world's wheel slip against walls and obstacles (`SurfaceContact::
    /// slip_yaw`, a share of the blocked travel), to repeat its calibration (docs/world.md).
    #[arg(long, value_name = "K")]
    slip_yaw: Option<f64>,
    /// Override the world's wall texture (a `--background` form, e.g. ribs:5.6:120:230), to
    /// repeat the calibration of the walls' look (docs/world.md).
    #[arg(long, value_name = "SPEC")]
    walls: Option<String>,
    /// Override the texture of the room seen above the walls (a `--background` form, e.g.
    /// plain:120 or outdoor:1), to repeat the calibration of the room's look (docs/world.md).
    #[arg(long, value_name = "SPEC")]
    room: Option<String>,
    #[command(flatten)]
    camera: CameraArgs,
    /// Standard deviation of the camera's pitch jitter while the robot moves, degrees
    /// (`SensorNoise::shake_deg`).
    #[arg(long, value_name = "DEG", default_value_t = 0.0)]
    shake_deg: f32,
    /// Height of the simulated robot's camera above the floor, mm, to calibrate the mount
    /// (docs/world.md).
    #[arg(long, value_name = "MM", default_value_t = alvs_sim::render::CAMERA_HEIGHT_MM)]
    camera_height: f64,
    /// Pitch of the simulated robot's camera, degrees, positive = up.
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pitch: f64,
    /// A diagnostic, not the baseline: give the simulated LGMD2 robot a forward proximity
    /// sensor of this range (mm ahead of its front, ±30°) whose alert starts the same random
    /// turn, to test whether the real robots' bottom-board infrared explains their turns
    /// (docs/world.md, "What is left").
    #[arg(long, value_name = "MM")]
    proximity_mm: Option<f64>,
    /// Straight driving each turn costs the simulated robot, s: its cruise speed is the run's
    /// mean path speed / (1 − turns a second × this); 0 drives at the mean path speed.
    #[arg(long, value_name = "S", default_value_t = alvs_host::experiments::validate::TURN_COST_S)]
    turn_cost_s: f64,
    /// Instead of the runs: straight open-loop approaches to the wall at the recordings' mean
    /// speeds, and where the LGMD2 first alerts (docs/world.md, "What is left").
    #[arg(long)]
    approaches: bool,
}

#[derive(clap::Args)]
struct TablesArgs {
    #[command(flatten)]
    world: WorldArgs,
    /// Seeds (repeatable); one run of each experiment per seed. Default: 11-20 (the report
    /// seeds; tuning uses 1-5).
    #[arg(long = "seed", value_name = "S")]
    seeds: Vec<u64>,
    /// Experiment to tabulate (repeatable). Default: all five.
    #[arg(long = "experiment", value_enum, value_name = "NAME")]
    experiments: Vec<ExperimentArg>,
    /// Simulated minutes of an arena trial (the arena's default: 10).
    #[arg(
        long,
        default_value_t = 10.0,
        value_name = "M",
        allow_negative_numbers = true
    )]
    arena_minutes: f64,
    /// Simulated minutes of a swarm trial (the swarm's default: 5).
    #[arg(
        long,
        default_value_t = 5.0,
        value_name = "M",
        allow_negative_numbers = true
    )]
    swarm_minutes: f64,
    /// Add a column for the authors' firmware (--model firmware) to the arena's table, beside
    /// the paper's model (one more arena run per seed).
    #[arg(long)]
    firmware: bool,
    /// Threads of each run (default: the available parallelism); results do not depend on it.
    #[arg(long, value_name = "J")]
    jobs: Option<usize>,
}

/// The experiments `tables` covers.
#[derive(Clone, Copy, ValueEnum)]
enum ExperimentArg {
    Stimuli,
    Evasion,
    TwoThreats,
    Arena,
    Swarm,
}

impl ExperimentArg {
    fn experiment(self) -> alvs_host::experiments::tables::Experiment {
        use alvs_host::experiments::tables::Experiment;
        match self {
            ExperimentArg::Stimuli => Experiment::Stimuli,
            ExperimentArg::Evasion => Experiment::Evasion,
            ExperimentArg::TwoThreats => Experiment::TwoThreats,
            ExperimentArg::Arena => Experiment::Arena,
            ExperimentArg::Swarm => Experiment::Swarm,
        }
    }
}

/// Which recorded runs `validate` simulates.
#[derive(Clone, Copy, ValueEnum)]
enum RunsArg {
    All,
    Calibration,
    HeldOut,
}

#[derive(clap::Args)]
struct RobustnessArgs {
    #[command(flatten)]
    world: WorldArgs,
    /// Seeds (repeatable); every perturbation and controller runs each. Default: 11-20 (the
    /// report seeds; tuning uses 1-5).
    #[arg(long = "seed", value_name = "S")]
    seeds: Vec<u64>,
    /// Perturbation to run (repeatable). Default: all, `none` (the reference) first.
    #[arg(long = "perturbation", value_name = "NAME", value_parser = perturbation_parser())]
    perturbations: Vec<Perturbation>,
    /// Controller to run (repeatable): alvs, paper, firmware, lgmd2. Default: alvs, paper and
    /// lgmd2.
    #[arg(long = "controller", value_enum, value_name = "NAME")]
    controllers: Vec<SuiteArg>,
    #[command(flatten)]
    trial: TrialArgs,
    #[command(flatten)]
    sweep: SweepArgs,
    /// Write the rows and trials as JSON (with --shard: the shard file).
    #[arg(long, value_name = "PATH")]
    json: Option<PathBuf>,
    /// Where summary.png goes.
    #[arg(long, default_value = "out/robustness", value_name = "DIR")]
    png: PathBuf,
}

#[derive(clap::Args)]
struct AblationArgs {
    #[command(flatten)]
    world: WorldArgs,
    /// Seeds (repeatable). Default: 11-20 (the report seeds; tuning uses 1-5).
    #[arg(long = "seed", value_name = "S")]
    seeds: Vec<u64>,
    /// Variant to run (repeatable): alvs, paper, lgmd2, alvs-M (the default without its
    /// mechanism M), alvs+O (the default with option O) or paper+M (the paper's model with
    /// mechanism or option M). Default: all of them; the mechanisms and options are listed
    /// under the table and in docs/ablation.md.
    #[arg(long = "variant", value_name = "NAME", value_parser = Variant::from_name)]
    variants: Vec<Variant>,
    /// Perturbation of the robustness suite the arena part runs under (repeatable). Default:
    /// none.
    #[arg(long = "perturbation", value_name = "NAME", value_parser = perturbation_parser())]
    perturbations: Vec<Perturbation>,
    /// Wall of the evasion part (repeatable): `world` (the world's own) or a --background
    /// specification. Default: world, outdoor:11 and data/photos/outdoor_2.jpg.
    #[arg(long = "wall", value_name = "SPEC")]
    walls: Vec<String>,
    /// Simulated minutes of an arena trial.
    #[arg(
        long,
        default_value_t = 5.0,
        allow_negative_numbers = true,
        value_name = "M"
    )]
    minutes: f64,
    /// Robots in the arena.
    #[arg(long, default_value_t = 3, value_name = "N")]
    robots: usize,
    /// Two-threat runs per seed (0: leave the part out).
    #[arg(long, default_value_t = 50, value_name = "N")]
    two_threat_runs: usize,
    /// Leave out the replay of the recorded clips (run once per variant).
    #[arg(long)]
    no_clips: bool,
    #[command(flatten)]
    sweep: SweepArgs,
    /// Write the rows as JSON (with --shard: the shard file).
    #[arg(long, value_name = "PATH")]
    json: Option<PathBuf>,
    /// Where summary.png goes.
    #[arg(long, default_value = "out/ablation", value_name = "DIR")]
    png: PathBuf,
}

/// The controllers the robustness suite compares.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum SuiteArg {
    /// ALVS, the default model (--model alvs).
    Alvs,
    /// ALVS with the paper's model exactly (--model paper).
    Paper,
    /// ALVS with what the authors' public firmware runs (--model firmware); not in the default
    /// set.
    Firmware,
    /// The LGMD2 baseline.
    Lgmd2,
}

impl SuiteArg {
    fn controller(self) -> SuiteController {
        match self {
            SuiteArg::Alvs => SuiteController::Alvs,
            SuiteArg::Paper => SuiteController::Paper,
            SuiteArg::Firmware => SuiteController::Firmware,
            SuiteArg::Lgmd2 => SuiteController::Lgmd2,
        }
    }
}

/// `--perturbation NAME`: one of the suite's names (listed in the help and in errors).
fn perturbation_parser() -> impl clap::builder::TypedValueParser<Value = Perturbation> {
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(Perturbation::ALL.map(Perturbation::name))
        .try_map(|s| Perturbation::from_name(&s).map_err(|e| e.to_string()))
}

#[derive(Subcommand)]
enum RecordingsCmd {
    /// Read the 7 runs' snapshot PNGs from a clone of LGMD2-open-source and write the arena's
    /// geometry and one track per run as JSON (what host/data/fu2019 holds).
    Extract {
        /// The clone of https://github.com/fuqinbing/LGMD2-open-source (commit 141e7e5).
        #[arg(long, value_name = "DIR")]
        from: PathBuf,
        /// Where the JSON goes.
        #[arg(long, value_name = "DIR", default_value = "host/data/fu2019")]
        out: PathBuf,
    },
    /// The committed runs' statistics as a table; with --png, a picture per run (path in
    /// floor mm coloured by time, obstacles, turns; histograms of straight runs and of wall
    /// distance at turns).
    Stats {
        /// Where the pictures go.
        #[arg(long, value_name = "DIR")]
        png: Option<PathBuf>,
        /// Print the statistics as JSON instead of the table.
        #[arg(long)]
        json: bool,
    },
}

/// How long a multi-robot trial runs and with how many robots (`arena`, `robustness`).
#[derive(clap::Args)]
struct TrialArgs {
    /// Simulated minutes per trial (30 camera frames per second).
    #[arg(
        long,
        default_value_t = 10.0,
        allow_negative_numbers = true,
        value_name = "M"
    )]
    minutes: f64,
    /// Robots in the arena, all running the trial's controller.
    #[arg(long, default_value_t = 3, value_name = "N")]
    robots: usize,
}

/// How a sweep's trials run: on how many threads, and which shard of them.
#[derive(clap::Args)]
struct SweepArgs {
    /// Independent trials run in parallel on this many threads (default: the available
    /// parallelism); results do not depend on it.
    #[arg(long, value_name = "J")]
    jobs: Option<usize>,
    /// Run only shard I of N (1 <= I <= N) of the trials: trial k (from 0, in plan order) is
    /// shard (k mod N) + 1's. Its trials go to --json PATH as a shard file; `alvs merge` pools
    /// the N files into the whole run's report (docs/sweeps.md).
    #[arg(long, value_name = "I/N")]
    shard: Option<Shard>,
}

impl SweepArgs {
    /// Runs `config` on these threads, whole or this shard ([`shards::execute`]); `frames` is
    /// the whole run's camera frames (for the progress bar).
    fn execute<S: Sweep>(&self, config: &S, out: &Outputs, frames: u64) -> Result<()> {
        shards::execute(config, jobs(self.jobs)?, self.shard, out, frames)
    }
}

/// Options every experiment has.
#[derive(clap::Args)]
struct CommonArgs {
    /// Seed of everything random (noise, geometry, LGMD2's turns).
    #[arg(long, default_value_t = 1, value_name = "S")]
    seed: u64,
    #[command(flatten)]
    world: WorldArgs,
    /// Wall texture: plain:GREY, stripes:PERIOD_MM, checker:SIZE_MM, clutter:SEED,
    /// outdoor:SEED, ribs[:PERIOD_MM[:DARK:LIGHT]], or a PNG/JPEG picture's path. Default: the
    /// world's own walls (fu2019: its ribs; lab: clutter:1). A texture given replaces the
    /// world's walls and keeps the rest of it (size, wall height, floor, obstacles, contact).
    #[arg(long, value_name = "SPEC")]
    background: Option<String>,
    #[command(flatten)]
    sweep: SweepArgs,
    /// Write the results as JSON (with --shard: the shard file).
    #[arg(long, value_name = "PATH")]
    json: Option<PathBuf>,
    /// The model: alvs (the default: the paper's model plus the closed-loop
    /// mechanisms that earn their place, docs/model.md), paper (the paper's model exactly) or firmware
    /// (what the authors' public firmware runs); it sets both the perception and the motion
    /// (FSM) parameters. --param and --fsm overrides apply on top.
    #[arg(long, value_enum, default_value_t = Model::Alvs)]
    model: Model,
    /// Override an ALVS model parameter, NAME=VALUE (repeatable), e.g. --param t_a=120 or
    /// --param table1.t_a=120; names and spellings in docs/model.md, "Parameter names".
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Override a motion (FSM) parameter, NAME=VALUE (repeatable), e.g. --fsm settle_frames=6
    /// or --fsm suppression.settle_frames=6; names and spellings in docs/model.md, "Parameter
    /// names".
    #[arg(long = "fsm", value_name = "NAME=VALUE")]
    fsm: Vec<String>,
    #[command(flatten)]
    camera: CameraArgs,
}

/// The simulated camera's options.
#[derive(clap::Args)]
struct CameraArgs {
    /// Camera exposure as a fraction of the 33 ms frame period, 0..=1: what moves while the
    /// shutter is open is blurred (an OV7670 under lab light exposes for most of the frame
    /// period). Default 0: instantaneous snapshots.
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "F",
        value_parser = exposure_fraction,
        allow_negative_numbers = true
    )]
    exposure: f32,
}

/// Parses `--exposure`: a fraction of the frame period in 0..=1.
fn exposure_fraction(s: &str) -> std::result::Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(x) if (0.0..=1.0).contains(&x) => Ok(x),
        _ => Err(format!(
            "{s:?} is not a fraction of the frame period in 0..=1"
        )),
    }
}

impl CommonArgs {
    fn outputs<'a>(&'a self, png: &'a Path, trace: Option<&'a Path>) -> Outputs<'a> {
        Outputs {
            png,
            json: self.json.as_deref(),
            trace,
        }
    }
}

#[derive(clap::Args)]
struct StimuliArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Where the pictures go.
    #[arg(long, default_value = "out/stimuli", value_name = "DIR")]
    png: PathBuf,
}

#[derive(clap::Args)]
struct EvasionArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Start distance of the obstacle, mm (centre to centre). Default: 500 where the stage
    /// (the nine paths, the tested robot, its escape room) fits in the world, else the longest
    /// in 10 mm steps that fits (fu2019: 450).
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    distance: Option<f64>,
    /// Speed of the obstacle, mm/s.
    #[arg(long, default_value_t = evasion::DEFAULT_SPEED_MM_S, value_name = "MM_S")]
    speed: f64,
    /// Controller of the tested robot (repeatable). Default: alvs and lgmd2.
    #[arg(long = "controller", value_enum, value_name = "NAME")]
    controllers: Vec<ControllerArg>,
    /// Where the picture goes.
    #[arg(long, default_value = "out/evasion", value_name = "DIR")]
    png: PathBuf,
    /// Write every trial's tested robot frame by frame as CSV (pose, state, alert, ΣLPLC2 or
    /// LGMD2 spikes, X̄, fields, distance to each obstacle).
    #[arg(long, value_name = "PATH")]
    trace: Option<PathBuf>,
}

#[derive(clap::Args)]
struct TwoThreatArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Random geometries per controller.
    #[arg(long, default_value_t = 20, value_name = "N")]
    runs: usize,
    /// Speed of the faster obstacle, mm/s.
    #[arg(long, default_value_t = 200.0, value_name = "MM_S")]
    fast: f64,
    /// Speed of the slower obstacle, mm/s.
    #[arg(long, default_value_t = 100.0, value_name = "MM_S")]
    slow: f64,
    /// Controller of the tested robot (repeatable). Default: alvs and lgmd2.
    #[arg(long = "controller", value_enum, value_name = "NAME")]
    controllers: Vec<ControllerArg>,
    /// Where the picture goes.
    #[arg(long, default_value = "out/two-threats", value_name = "DIR")]
    png: PathBuf,
    /// Write every trial's tested robot frame by frame as CSV (pose, state, alert, ΣLPLC2 or
    /// LGMD2 spikes, X̄, fields, distance to each obstacle).
    #[arg(long, value_name = "PATH")]
    trace: Option<PathBuf>,
}

#[derive(clap::Args)]
struct SwarmArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Simulated minutes per trial.
    #[arg(
        long,
        default_value_t = 5.0,
        allow_negative_numbers = true,
        value_name = "M"
    )]
    minutes: f64,
    /// Robots in the arena (not counting the leader).
    #[arg(long, default_value_t = 6, value_name = "N")]
    robots: usize,
    /// One more robot, a leader, spins in place the whole run (the paper's robots "moved
    /// toward a swarm leader" but it does not say what the leader did); the others' mean
    /// distance to it is reported.
    #[arg(long)]
    leader: bool,
    /// Controller (repeatable; one trial each). Default: swarm, and alvs as the reference.
    #[arg(long = "controller", value_enum, value_name = "NAME")]
    controllers: Vec<ControllerArg>,
    /// Where the pictures go.
    #[arg(long, default_value = "out/swarm", value_name = "DIR")]
    png: PathBuf,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum ControllerArg {
    /// aLPLC2 perception + escape FSM (the paper's model).
    Alvs,
    /// LGMD2 perception + direction-blind escape (the paper's baseline).
    Lgmd2,
    /// aLPLC2 perception + spin on approach (paper IV-D).
    Swarm,
}

impl ControllerArg {
    fn kind(self) -> Kind {
        match self {
            ControllerArg::Alvs => Kind::Alvs,
            ControllerArg::Lgmd2 => Kind::Lgmd2,
            ControllerArg::Swarm => Kind::Swarm,
        }
    }
}

#[derive(clap::Args)]
struct ArenaArgs {
    #[command(flatten)]
    trial: TrialArgs,
    #[command(flatten)]
    world: WorldArgs,
    /// Wall texture (repeatable; one trial per background and controller): plain:GREY,
    /// stripes:PERIOD_MM, checker:SIZE_MM, clutter:SEED, outdoor:SEED,
    /// ribs[:PERIOD_MM[:DARK:LIGHT]] (the number may be left out: grey 128, 40 mm, 40 mm, seed
    /// 1, the replica's ribs), or a PNG/JPEG picture's path. A texture replaces the world's
    /// walls and keeps the rest of it. Default: the world's own walls: fu2019 its ribs (one
    /// background); lab clutter:1, stripes:40, checker:60.
    #[arg(long = "background", value_name = "SPEC")]
    backgrounds: Vec<String>,
    /// Controller to run (repeatable). Default: alvs and lgmd2.
    #[arg(long = "controller", value_enum, value_name = "NAME")]
    controllers: Vec<ControllerArg>,
    /// Seed of everything random: start poses, motor, gyro and camera noise, LGMD2's turns.
    #[arg(long, default_value_t = 1, value_name = "S")]
    seed: u64,
    #[command(flatten)]
    sweep: SweepArgs,
    /// Write the results as JSON: {"alvs":{...},"lgmd2":{...},"trials":[...]} (with --shard:
    /// the shard file).
    #[arg(long, value_name = "PATH")]
    json: Option<PathBuf>,
    /// Where the trajectory pictures (one per trial) and summary.png go.
    #[arg(long, default_value = "out/arena", value_name = "DIR")]
    png: PathBuf,
    /// Write every robot of every trial frame by frame as CSV (pose, state, alert, ΣLPLC2 or
    /// LGMD2 spikes, X̄, fields, distance to the nearest wall and robot): about 85 bytes per
    /// robot and frame, 28 MB for the default run.
    #[arg(long, value_name = "PATH")]
    trace: Option<PathBuf>,
    /// The model: alvs (the default: the paper's model plus the closed-loop
    /// mechanisms that earn their place, docs/model.md), paper (the paper's model exactly) or firmware
    /// (what the authors' public firmware runs); it sets both the perception and the motion
    /// (FSM) parameters. --param and --fsm overrides apply on top.
    #[arg(long, value_enum, default_value_t = Model::Alvs)]
    model: Model,
    /// Override an ALVS model parameter, NAME=VALUE (repeatable), e.g. --param t_a=120 or
    /// --param table1.t_a=120; names and spellings in docs/model.md, "Parameter names".
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Override a motion (FSM) parameter, NAME=VALUE (repeatable), e.g. --fsm settle_frames=6
    /// or --fsm suppression.settle_frames=6; names and spellings in docs/model.md, "Parameter
    /// names".
    #[arg(long = "fsm", value_name = "NAME=VALUE")]
    fsm: Vec<String>,
    #[command(flatten)]
    camera: CameraArgs,
}

#[derive(clap::Args)]
struct ModelArgs {
    /// The model: alvs (the default: the paper's model plus the closed-loop
    /// mechanisms that earn their place, docs/model.md), paper (the paper's model exactly) or firmware
    /// (what the authors' public firmware runs); it sets both the perception and the motion
    /// (FSM) parameters. --param and --fsm overrides apply on top.
    #[arg(long, value_enum, default_value_t = Model::Alvs)]
    model: Model,
    /// Override a model parameter, NAME=VALUE (repeatable), e.g. --param t_a=120 or
    /// --param table1.t_a=120; names and spellings in docs/model.md, "Parameter names".
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Override a motion (FSM) parameter, NAME=VALUE (repeatable), e.g. --fsm settle_frames=6
    /// or --fsm suppression.settle_frames=6; names and spellings in docs/model.md, "Parameter
    /// names".
    #[arg(long = "fsm", value_name = "NAME=VALUE")]
    fsm: Vec<String>,
    /// Motor behaviour: escape (paper II-B) or swarm (spin on approach, paper IV-D).
    #[arg(long, value_enum, default_value_t = Mode::Escape)]
    mode: Mode,
}

/// A preset of the model: its perception (`Params::preset`) and its motion (`FsmParams`).
#[derive(Clone, Copy, ValueEnum)]
enum Model {
    /// The paper's model plus the closed-loop mechanisms and a lower `T_s` (`Params::ALVS`,
    /// `FsmParams::ALVS`), the firmware's.
    Alvs,
    /// The paper's model exactly (`Params::PAPER`, `FsmParams::PAPER`).
    Paper,
    /// What the authors' public firmware runs (`Params::FIRMWARE`, `FsmParams::FIRMWARE`;
    /// docs/model.md, "The authors' firmware").
    Firmware,
}

impl Model {
    fn params(self) -> Params {
        match self {
            Model::Alvs => Params::ALVS,
            Model::Paper => Params::PAPER,
            Model::Firmware => Params::FIRMWARE,
        }
    }

    fn fsm(self) -> FsmParams {
        match self {
            Model::Alvs => FsmParams::ALVS,
            Model::Paper => FsmParams::PAPER,
            Model::Firmware => FsmParams::FIRMWARE,
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum Mode {
    Escape,
    Swarm,
}

#[derive(clap::Args)]
struct ReplayArgs {
    /// A raw Y8 clip (frames of 99x72, row-major, no header) or a directory of binary PGM frames.
    clip: PathBuf,
    /// Frame width of the clip (the model takes only 99).
    #[arg(long, default_value_t = WIDTH)]
    width: usize,
    /// Frame height of the clip (the model takes only 72).
    #[arg(long, default_value_t = HEIGHT)]
    height: usize,
    /// Write layer pictures and an LPLC2 trace into this directory.
    #[arg(long, value_name = "DIR")]
    png: Option<PathBuf>,
    /// Frames to draw layers for (comma-separated); default: first alert and peak response.
    #[arg(long, value_delimiter = ',', value_name = "N,...")]
    frames: Vec<u32>,
    #[command(flatten)]
    model: ModelArgs,
}

/// `--jobs`: at least 1, default the available parallelism.
fn jobs(jobs: Option<usize>) -> Result<usize> {
    match jobs {
        Some(0) => anyhow::bail!("--jobs must be at least 1"),
        Some(j) => Ok(j),
        None => Ok(parallel::default_jobs()),
    }
}

/// Applies `--FLAG NAME=VALUE` overrides through `set`; a malformed pair or a refused value is
/// an error naming the flag and the pair.
fn apply_overrides<E: std::fmt::Display>(
    flag: &str,
    overrides: &[String],
    mut set: impl FnMut(&str, &str) -> Result<(), E>,
) -> Result<()> {
    for kv in overrides {
        let (k, v) = kv
            .split_once('=')
            .with_context(|| format!("--{flag} {kv}: expected NAME=VALUE"))?;
        set(k.trim(), v).map_err(|e| anyhow::anyhow!("--{flag} {kv}: {e}"))?;
    }
    Ok(())
}

/// The model parameters of `model` with `--param NAME=VALUE` overrides applied.
fn parse_params(model: Model, overrides: &[String]) -> Result<Params> {
    let mut p = model.params();
    apply_overrides("param", overrides, |k, v| p.set(k, v))?;
    Ok(p)
}

/// The motion parameters of `model` with `--fsm NAME=VALUE` overrides applied.
fn parse_fsm(model: Model, overrides: &[String]) -> Result<FsmParams> {
    let mut p = model.fsm();
    apply_overrides("fsm", overrides, |k, v| p.set(k, v))?;
    Ok(p)
}

impl ModelArgs {
    fn params(&self) -> Result<Params> {
        parse_params(self.model, &self.params)
    }

    fn fsm(&self) -> Result<FsmParams> {
        parse_fsm(self.model, &self.fsm)
    }

    fn behaviour(&self) -> Behaviour {
        match self.mode {
            Mode::Escape => Behaviour::Escape,
            Mode::Swarm => Behaviour::Swarm,
        }
    }
}

/// A command-line error as one line: clap's message without its usage and help hints.
fn one_line(e: &clap::Error) -> String {
    let text = e.to_string();
    let parts: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| {
            !l.is_empty() && !l.starts_with("Usage:") && !l.starts_with("For more information")
        })
        .collect();
    let line = parts.join(" ");
    line.strip_prefix("error: ").unwrap_or(&line).to_string()
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => {
            // --help, --version
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            eprintln!("alvs: error: {}", one_line(&e));
            return ExitCode::from(2);
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        // a closed pipe (`alvs replay clip.y8 | head`) is the reader's choice, not an error
        Err(e)
            if e.chain().any(|c| {
                c.downcast_ref::<std::io::Error>()
                    .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
            }) =>
        {
            ExitCode::SUCCESS
        }
        Err(e) => match e.downcast_ref::<Exit>() {
            Some(Exit(code)) => ExitCode::from(*code),
            None => {
                eprintln!("alvs: error: {e:#}");
                ExitCode::FAILURE
            }
        },
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.cmd {
        Cmd::Replay(a) => {
            let params = a.model.params()?;
            let frames = clip::load(&a.clip, a.width, a.height)?;
            let name = a
                .clip
                .file_stem()
                .map_or("clip".into(), |s| s.to_string_lossy().into_owned());
            let stdout = std::io::stdout();
            let mut out = std::io::BufWriter::new(stdout.lock());
            let png = a
                .png
                .as_deref()
                .map(|d| (d, a.frames.as_slice(), name.as_str()));
            replay::run(
                &frames,
                params,
                a.model.fsm()?,
                a.model.behaviour(),
                png,
                |j| {
                    let mut line = serde_json::to_vec(j)?;
                    line.push(b'\n');
                    out.write_all(&line)?;
                    Ok(())
                },
            )?;
            out.flush()?;
            if let Some(d) = &a.png {
                eprintln!("pictures in {}", d.display());
            }
            Ok(())
        }
        Cmd::Demo { png, model } => {
            let params = model.params()?;
            let mut out = std::io::stdout().lock();
            writeln!(
                out,
                "{:<18} {:>7} {:>6} {:>6} {:>8} {:>7}  first alert",
                "scene", "looming", "frames", "alerts", "max AFs", "mean X"
            )?;
            for s in scenes::demo_scenes() {
                let frames = s.frames();
                let recs = replay::run(
                    &frames,
                    params,
                    model.fsm()?,
                    model.behaviour(),
                    Some((&png, &[], s.name)),
                    |_| Ok(()),
                )?;
                let alerts: Vec<&replay::FrameJson> = recs.iter().filter(|r| r.alert).collect();
                let xs: Vec<f32> = alerts.iter().filter_map(|r| r.threat_x).collect();
                let mean_x = if xs.is_empty() {
                    "-".to_string()
                } else {
                    format!("{:.1}", xs.iter().sum::<f32>() / xs.len() as f32)
                };
                let max_afs = recs.iter().map(|r| r.afs.len()).max().unwrap_or(0);
                let first = alerts.first().map_or("-".into(), |r| r.frame.to_string());
                writeln!(
                    out,
                    "{:<18} {:>7} {:>6} {:>6} {:>8} {:>7}  {first}",
                    s.name,
                    s.looming,
                    recs.len(),
                    alerts.len(),
                    max_afs,
                    mean_x
                )?;
            }
            writeln!(out, "pictures in {}", png.display())?;
            Ok(())
        }
        Cmd::Arena(a) => run_arena(a),
        Cmd::Stimuli(a) => run_stimuli(a),
        Cmd::Evasion(a) => run_evasion(a),
        Cmd::TwoThreats(a) => run_two_threats(a),
        Cmd::Swarm(a) => run_swarm(a),
        Cmd::Recordings { cmd } => run_recordings(cmd),
        Cmd::Validate(a) => run_validate(a),
        Cmd::Robustness(a) => run_robustness(a),
        Cmd::Ablation(a) => run_ablation(a),
        Cmd::Tables(a) => run_tables(a),
        Cmd::Merge(a) => shards::merge(a),
        Cmd::Budget { args } => run_cycles_bin("alvs-budget", &args),
        Cmd::Virtual { args } => run_cycles_bin("alvs-virtual", &args),
        Cmd::Log(a) => log_command::run(a, cycles_bin),
    }
}

/// Runs a binary of the crate alvs-cycles (`alvs-budget`, `alvs-virtual`) through cargo, so that
/// the host tools themselves never need the emulator's C build. It runs in the caller's folder
/// (its relative paths are the caller's); when it fails it has said why on stderr, in one line,
/// and `alvs` exits with its status without a second message.
fn run_cycles_bin(bin: &str, args: &[String]) -> Result<()> {
    let status = cycles_bin(bin, args).status().context("running cargo")?;
    if !status.success() {
        return Err(Exit(status.code().unwrap_or(1).clamp(1, 255) as u8).into());
    }
    Ok(())
}

/// `cargo run` of a binary of alvs-cycles, from the workspace's manifest, in the current folder.
fn cycles_bin(bin: &str, args: &[String]) -> std::process::Command {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap_or(Path::new(".."))
        .join("Cargo.toml");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut c = std::process::Command::new(cargo);
    c.args([
        "run",
        "--quiet",
        "--target",
        "host-tuple",
        "--manifest-path",
    ])
    .arg(manifest)
    .args(["-p", "alvs-cycles", "--bin", bin, "--"])
    .args(args);
    c
}

/// The exit status of a failed child that reported its own error: `alvs` exits with it and
/// prints nothing more.
#[derive(Debug)]
struct Exit(u8);

impl std::fmt::Display for Exit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "exit status {}", self.0)
    }
}

impl std::error::Error for Exit {}

/// A progress bar on stderr for `total` camera frames (hidden by indicatif when stderr is not
/// a terminal: CI logs, pipes).
fn progress_bar(name: &str, total: u64) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(total);
    bar.set_style(
        indicatif::ProgressStyle::with_template(&format!(
            "{name} {{elapsed_precise}} [{{bar:40}}] {{percent:>3}}% of {{len}} frames, eta {{eta}}"
        ))
        .expect("a valid template")
        .progress_chars("=> "),
    );
    bar
}

fn kinds(args: &[ControllerArg], default: &[Kind]) -> Vec<Kind> {
    if args.is_empty() {
        default.to_vec()
    } else {
        let mut v: Vec<Kind> = Vec::new();
        for k in args.iter().map(|c| c.kind()) {
            if !v.contains(&k) {
                v.push(k);
            }
        }
        v
    }
}

/// Where an experiment's results go: `--png`, `--json`, `--trace`.
struct Outputs<'a> {
    png: &'a Path,
    json: Option<&'a Path>,
    trace: Option<&'a Path>,
}

impl Outputs<'_> {
    /// Fails before a long run, not after it, when the pictures' folder cannot be made or the
    /// JSON or trace file cannot be written. An existing file keeps its contents until the run
    /// has new ones; a file made only for the check is removed again.
    fn check(&self) -> Result<()> {
        std::fs::create_dir_all(self.png)
            .with_context(|| format!("cannot create {}", self.png.display()))?;
        self.check_files()
    }

    /// [`Outputs::check`] of the JSON and trace files only.
    fn check_files(&self) -> Result<()> {
        for path in self.json.iter().chain(self.trace.iter()) {
            let existed = path.exists();
            std::fs::OpenOptions::new()
                .append(true)
                .create(true)
                .open(path)
                .with_context(|| format!("cannot write {}", path.display()))?;
            if !existed {
                let _ = std::fs::remove_file(path);
            }
        }
        Ok(())
    }

    /// Writes the pictures, the trace and the JSON, then prints the table and where each went.
    fn publish(&self, r: &impl Report) -> Result<()> {
        let pictures = r.write_pictures(self.png)?;
        if let Some(path) = self.trace {
            r.write_trace(path)?;
        }
        if let Some(path) = self.json {
            let text = serde_json::to_string(&r.json())?;
            std::fs::write(path, text + "\n")
                .with_context(|| format!("cannot write {}", path.display()))?;
        }
        let mut out = std::io::stdout().lock();
        write!(out, "{}", r.table())?;
        writeln!(out, "{} pictures in {}", pictures.len(), self.png.display())?;
        if let Some(path) = self.json {
            writeln!(out, "JSON in {}", path.display())?;
        }
        if let Some(path) = self.trace {
            writeln!(out, "trace in {}", path.display())?;
        }
        Ok(())
    }
}

fn run_validate(a: ValidateArgs) -> Result<()> {
    use alvs_host::experiments::validate::{self, ValidateConfig};
    let builtin = a.world.builtin();
    let (mut world, world_label) = (builtin.world(), builtin.label());
    if let Some(k) = a.slip_yaw {
        if !(k.is_finite() && k >= 0.0) {
            anyhow::bail!("--slip-yaw {k}: must be a finite number >= 0");
        }
        world.contact.slip_yaw = k;
    }
    if let Some(spec) = &a.walls {
        world.texture = alvs_sim::WallTexture::from_spec(spec)?;
    }
    if let Some(spec) = &a.room {
        let Some(room) = world.room.as_mut() else {
            anyhow::bail!("--room: the {world_label} world has no room above its walls");
        };
        room.texture = alvs_sim::WallTexture::from_spec(spec)?;
    }
    let mount = alvs_sim::CameraMount {
        height_mm: a.camera_height,
        pitch_deg: a.pitch,
    };
    mount.check()?;
    if a.approaches {
        use alvs_host::experiments::validate::approach;
        let arena = alvs_host::recordings::arena()?;
        let runs = alvs_host::recordings::all_runs()?;
        let speeds: Vec<f64> = runs
            .iter()
            .map(|r| r.stats(&arena).mean_speed_mm_s.round())
            .collect();
        let angles: String = approach::ANGLES_DEG
            .iter()
            .map(|a| format!(" {a:.0}° |"))
            .collect();
        println!(
            "| run | speed mm/s | approaches | alerted before touching | median gap at the alert (mm) |{angles}"
        );
        println!(
            "|---|---|---|---|---|{}",
            "---|".repeat(approach::ANGLES_DEG.len())
        );
        for (run, r) in runs
            .iter()
            .zip(approach::approaches(&world, mount, &speeds))
        {
            let gap = r.median_gap_mm.map_or("-".into(), |g| format!("{g:.0}"));
            let per: String = r
                .alerted_by_angle
                .iter()
                .map(|k| format!(" {k}/{} |", approach::AIM_X_MM.len()))
                .collect();
            println!(
                "| {} | {:.0} | {} | {} | {gap} |{per}",
                run.run, r.speed_mm_s, r.approaches, r.alerted
            );
        }
        return Ok(());
    }
    let seeds = if a.seeds.is_empty() {
        vec![11, 12, 13]
    } else {
        a.seeds
    };
    let config = ValidateConfig {
        world,
        world_label: world_label.into(),
        seeds,
        jobs: a.jobs,
        runs: match a.runs {
            RunsArg::All => validate::RunSet::All,
            RunsArg::Calibration => validate::RunSet::Calibration,
            RunsArg::HeldOut => validate::RunSet::HeldOut,
        },
        noise: alvs_sim::SensorNoise {
            exposure: a.camera.exposure,
            shake_deg: a.shake_deg,
            ..alvs_sim::SensorNoise::typical()
        },
        mount,
        proximity_mm: a.proximity_mm,
        turn_cost_s: a.turn_cost_s,
    };
    if !(a.turn_cost_s.is_finite() && (0.0..=10.0).contains(&a.turn_cost_s)) {
        anyhow::bail!("--turn-cost-s {}: must be in [0, 10] s", a.turn_cost_s);
    }
    if let Some(r) = a.proximity_mm {
        if !(r.is_finite() && r > 0.0 && r <= 500.0) {
            anyhow::bail!("--proximity-mm {r}: must be in (0, 500] mm");
        }
    }
    if !(a.shake_deg.is_finite() && a.shake_deg >= 0.0) {
        anyhow::bail!("--shake-deg {}: must be a finite number >= 0", a.shake_deg);
    }
    let out = Outputs {
        png: &a.png,
        json: a.json.as_deref(),
        trace: None,
    };
    out.check()?;
    let total = (alvs_host::recordings::runs::RUNS.len() * config.seeds.len()) as u64;
    let bar = progress_bar("validate", total);
    let r = validate::validate(&config, &|| bar.inc(1));
    bar.finish_and_clear();
    out.publish(&r?)
}

fn stimuli_config(a: &StimuliArgs) -> Result<stimuli::StimuliConfig> {
    Ok(stimuli::StimuliConfig {
        seed: a.common.seed,
        params: parse_params(a.common.model, &a.common.params)?,
        fsm: parse_fsm(a.common.model, &a.common.fsm)?,
        world: a.common.world.builtin(),
        background: a.common.background.clone(),
        exposure: a.common.camera.exposure,
    })
}

fn run_stimuli(a: StimuliArgs) -> Result<()> {
    let config = stimuli_config(&a)?;
    config.validate()?;
    let out = a.common.outputs(&a.png, None);
    a.common.sweep.execute(&config, &out, 0)
}

fn evasion_config(a: &EvasionArgs) -> Result<evasion::EvasionConfig> {
    Ok(evasion::EvasionConfig {
        distance_mm: a.distance,
        speed_mm_s: a.speed,
        controllers: kinds(&a.controllers, &[Kind::Alvs, Kind::Lgmd2]),
        seed: a.common.seed,
        params: parse_params(a.common.model, &a.common.params)?,
        fsm: parse_fsm(a.common.model, &a.common.fsm)?,
        world: a.common.world.builtin(),
        background: a.common.background.clone(),
        exposure: a.common.camera.exposure,
        trace: a.trace.is_some(),
        ..evasion::EvasionConfig::default()
    })
}

fn run_evasion(a: EvasionArgs) -> Result<()> {
    let config = evasion_config(&a)?;
    config.validate()?;
    let out = a.common.outputs(&a.png, a.trace.as_deref());
    a.common.sweep.execute(&config, &out, config.total_frames())
}

fn two_threats_config(a: &TwoThreatArgs) -> Result<two_threats::TwoThreatConfig> {
    Ok(two_threats::TwoThreatConfig {
        runs: a.runs,
        fast_mm_s: a.fast,
        slow_mm_s: a.slow,
        controllers: kinds(&a.controllers, &[Kind::Alvs, Kind::Lgmd2]),
        seed: a.common.seed,
        params: parse_params(a.common.model, &a.common.params)?,
        fsm: parse_fsm(a.common.model, &a.common.fsm)?,
        world: a.common.world.builtin(),
        background: a.common.background.clone(),
        exposure: a.common.camera.exposure,
        trace: a.trace.is_some(),
    })
}

fn run_two_threats(a: TwoThreatArgs) -> Result<()> {
    let config = two_threats_config(&a)?;
    config.validate()?;
    let out = a.common.outputs(&a.png, a.trace.as_deref());
    a.common.sweep.execute(&config, &out, config.total_frames())
}

fn swarm_config(a: &SwarmArgs) -> Result<swarm::SwarmConfig> {
    Ok(swarm::SwarmConfig {
        robots: a.robots,
        leader: a.leader,
        minutes: a.minutes,
        controllers: kinds(&a.controllers, &[Kind::Swarm, Kind::Alvs]),
        seed: a.common.seed,
        params: parse_params(a.common.model, &a.common.params)?,
        fsm: parse_fsm(a.common.model, &a.common.fsm)?,
        world: a.common.world.builtin(),
        background: a.common.background.clone(),
        exposure: a.common.camera.exposure,
    })
}

fn run_swarm(a: SwarmArgs) -> Result<()> {
    let config = swarm_config(&a)?;
    config.validate()?;
    let out = a.common.outputs(&a.png, None);
    a.common.sweep.execute(&config, &out, config.total_frames())
}

fn arena_config(a: &ArenaArgs) -> Result<ArenaConfig> {
    Ok(ArenaConfig {
        robots: a.trial.robots,
        minutes: a.trial.minutes,
        world: a.world.builtin(),
        backgrounds: a.backgrounds.clone(),
        controllers: if a.controllers.is_empty() {
            vec![Kind::Alvs, Kind::Lgmd2]
        } else {
            a.controllers.iter().map(|c| c.kind()).collect()
        },
        seed: a.seed,
        params: parse_params(a.model, &a.params)?,
        fsm: parse_fsm(a.model, &a.fsm)?,
        trace: a.trace.is_some(),
        exposure: a.camera.exposure,
        ..ArenaConfig::default()
    })
}

fn run_arena(a: ArenaArgs) -> Result<()> {
    let config = arena_config(&a)?;
    config.validate()?;
    let out = Outputs {
        png: &a.png,
        json: a.json.as_deref(),
        trace: a.trace.as_deref(),
    };
    a.sweep.execute(&config, &out, arena::total_frames(&config))
}

fn robustness_config(a: &RobustnessArgs) -> Result<RobustnessConfig> {
    let d = RobustnessConfig::default();
    Ok(RobustnessConfig {
        world: a.world.builtin(),
        seeds: if a.seeds.is_empty() {
            d.seeds
        } else {
            a.seeds.clone()
        },
        perturbations: if a.perturbations.is_empty() {
            d.perturbations
        } else {
            a.perturbations.clone()
        },
        controllers: if a.controllers.is_empty() {
            d.controllers
        } else {
            a.controllers.iter().map(|c| c.controller()).collect()
        },
        robots: a.trial.robots,
        minutes: a.trial.minutes,
    })
}

fn run_robustness(a: RobustnessArgs) -> Result<()> {
    let config = robustness_config(&a)?;
    config.validate()?;
    let out = Outputs {
        png: &a.png,
        json: a.json.as_deref(),
        trace: None,
    };
    a.sweep.execute(&config, &out, config.total_frames())
}

/// A repeatable option's values, or the default when none was given.
fn given_or<T: Clone>(given: &[T], default: Vec<T>) -> Vec<T> {
    if given.is_empty() {
        default
    } else {
        given.to_vec()
    }
}

fn ablation_config(a: &AblationArgs) -> Result<AblationConfig> {
    let d = AblationConfig::default();
    Ok(AblationConfig {
        world: a.world.builtin(),
        seeds: given_or(&a.seeds, d.seeds),
        variants: given_or(&a.variants, d.variants),
        perturbations: given_or(&a.perturbations, d.perturbations),
        walls: if a.walls.is_empty() {
            d.walls
        } else {
            a.walls
                .iter()
                .map(|w| (w != "world").then(|| w.clone()))
                .collect()
        },
        robots: a.robots,
        minutes: a.minutes,
        two_threat_runs: a.two_threat_runs,
        clips: !a.no_clips,
    })
}

fn run_ablation(a: AblationArgs) -> Result<()> {
    let config = ablation_config(&a)?;
    config.validate()?;
    let out = Outputs {
        png: &a.png,
        json: a.json.as_deref(),
        trace: None,
    };
    a.sweep.execute(&config, &out, config.total_frames())
}

fn run_tables(a: TablesArgs) -> Result<()> {
    use alvs_host::experiments::tables::{self, TablesConfig};
    let d = TablesConfig::default();
    let config = TablesConfig {
        world: a.world.builtin(),
        seeds: if a.seeds.is_empty() { d.seeds } else { a.seeds },
        experiments: if a.experiments.is_empty() {
            d.experiments
        } else {
            a.experiments.iter().map(|e| e.experiment()).collect()
        },
        arena_minutes: a.arena_minutes,
        swarm_minutes: a.swarm_minutes,
        firmware: a.firmware,
    };
    config.validate()?;
    let jobs = jobs(a.jobs)?;
    let t0 = std::time::Instant::now();
    let text = tables::tables(&config, jobs, &|what| {
        eprintln!("tables: {what} ({:.0} s)", t0.elapsed().as_secs_f64());
    })?;
    let mut out = std::io::stdout().lock();
    write!(out, "{text}")?;
    writeln!(
        out,
        "({:.0} s on {jobs} thread{})",
        t0.elapsed().as_secs_f64(),
        if jobs == 1 { "" } else { "s" }
    )?;
    Ok(())
}

fn run_recordings(cmd: RecordingsCmd) -> Result<()> {
    use alvs_host::recordings::{self, runs::RUNS};
    match cmd {
        RecordingsCmd::Extract { from, out } => {
            if !from.is_dir() {
                bail!("{}: no such folder", from.display());
            }
            let total: usize = RUNS
                .iter()
                .map(|r| recordings::runs::list_snapshots(&from, r).map(|l| l.len()))
                .sum::<Result<usize>>()?;
            let bar = progress_bar("recordings", 2 * total as u64);
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "{msg:>14} {elapsed_precise} [{bar:40}] {pos}/{len} snapshot reads, eta {eta}",
                )
                .expect("a valid template")
                .progress_chars("=> "),
            );
            let command = format!(
                "cargo alvs recordings extract --from <clone> --out {}",
                out.display()
            );
            let got = recordings::extract::extract_all(&from, &command, |name| {
                bar.set_message(name.to_string());
                bar.inc(1);
            })?;
            bar.finish_and_clear();
            std::fs::create_dir_all(&out).with_context(|| format!("{}", out.display()))?;
            let write = |name: &str, json: String| -> Result<()> {
                let path = out.join(format!("{name}.json"));
                std::fs::write(&path, json + "\n")
                    .with_context(|| format!("{}", path.display()))?;
                writeln!(std::io::stdout(), "wrote {}", path.display())?;
                Ok(())
            };
            write("arena", serde_json::to_string_pretty(&got.arena)?)?;
            for r in &got.runs {
                write(&r.run, serde_json::to_string(r)?)?;
            }
            Ok(())
        }
        RecordingsCmd::Stats { png, json } => {
            let arena = recordings::arena()?;
            let runs = recordings::all_runs()?;
            let stats: Vec<_> = runs.iter().map(|r| (r, r.stats(&arena))).collect();
            // write! rather than print!: a closed pipe (`| head`) is an error main lets pass,
            // not a panic.
            let mut stdout = std::io::stdout().lock();
            if json {
                let named: Vec<_> = stats.iter().map(|(r, s)| (&r.run, s)).collect();
                writeln!(stdout, "{}", serde_json::to_string_pretty(&named)?)?;
            } else {
                write!(stdout, "{}", recordings::report::table(&stats))?;
            }
            if let Some(dir) = png {
                std::fs::create_dir_all(&dir).with_context(|| format!("{}", dir.display()))?;
                for (r, s) in &stats {
                    let path = dir.join(format!("{}.png", r.run));
                    recordings::report::run_picture(r, &arena, s)
                        .save_png(&path)
                        .with_context(|| format!("{}", path.display()))?;
                    eprintln!("wrote {}", path.display());
                }
            }
            Ok(())
        }
    }
}

//! The option groups several subcommands share (`--world`, the model, the camera, a trial's
//! length, threads and shards, the experiments' common options) and how their values are read.

use std::path::{Path, PathBuf};

use alvs_host::experiments::parallel;
use alvs_host::experiments::sweep::Shard;
use alvs_sim::BuiltinWorld;
use alvs_tasks::model::fsm::FsmParams;
use alvs_tasks::Params;
use anyhow::{Context, Result};
use clap::ValueEnum;

use super::runner::Outputs;

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
pub struct WorldArgs {
    /// The world: fu2019, the replica of the recorded LGMD2 arena (1309 x 751 mm, 72 mm ribbed
    /// walls, a dark floor, 15 cylinder obstacles, the calibrated contact), or lab, the
    /// built-in 1200 x 900 mm arena with 250 mm walls and rigid contact (docs/world.md).
    #[arg(long, value_enum, default_value = "fu2019")]
    world: WorldChoice,
}

impl WorldArgs {
    pub fn builtin(&self) -> BuiltinWorld {
        match self.world {
            WorldChoice::Fu2019 => BuiltinWorld::Fu2019,
            WorldChoice::Lab => BuiltinWorld::Lab,
        }
    }
}

/// How long a multi-robot trial runs and with how many robots (`arena`, `robustness`).
#[derive(clap::Args)]
pub struct TrialArgs {
    /// Simulated minutes per trial (30 camera frames per second).
    #[arg(
        long,
        default_value_t = 10.0,
        allow_negative_numbers = true,
        value_name = "M"
    )]
    pub minutes: f64,
    /// Robots in the arena, all running the trial's controller.
    #[arg(long, default_value_t = 3, value_name = "N")]
    pub robots: usize,
}

/// How a sweep's trials run: on how many threads, and which shard of them.
#[derive(clap::Args)]
pub struct SweepArgs {
    /// Independent trials run in parallel on this many threads (default: the available
    /// parallelism); results do not depend on it.
    #[arg(long, value_name = "J")]
    pub jobs: Option<usize>,
    /// Run only shard I of N (1 <= I <= N) of the trials: trial k (from 0, in plan order) is
    /// shard (k mod N) + 1's. Its trials go to --json PATH as a shard file; `alvs merge` pools
    /// the N files into the whole run's report (docs/sweeps.md).
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
}

/// Options every experiment has.
#[derive(clap::Args)]
pub struct CommonArgs {
    /// Seed of everything random (noise, geometry, LGMD2's turns).
    #[arg(long, default_value_t = 1, value_name = "S")]
    pub seed: u64,
    #[command(flatten)]
    pub world: WorldArgs,
    /// Wall texture: plain:GREY, stripes:PERIOD_MM, checker:SIZE_MM, clutter:SEED,
    /// outdoor:SEED, ribs[:PERIOD_MM[:DARK:LIGHT]], or a PNG/JPEG picture's path. Default: the
    /// world's own walls (fu2019: its ribs; lab: clutter:1). A texture given replaces the
    /// world's walls and keeps the rest of it (size, wall height, floor, obstacles, contact).
    #[arg(long, value_name = "SPEC")]
    pub background: Option<String>,
    #[command(flatten)]
    pub sweep: SweepArgs,
    /// Write the results as JSON (with --shard: the shard file).
    #[arg(long, value_name = "PATH")]
    json: Option<PathBuf>,
    #[command(flatten)]
    pub model: ModelOptions,
    #[command(flatten)]
    pub camera: CameraArgs,
}

/// The simulated camera's options.
#[derive(clap::Args)]
pub struct CameraArgs {
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
    pub exposure: f32,
    /// How the camera's global gain moves from frame to frame: `clips`, an independent 0.3 %
    /// draw every frame, what the recorded real clips' cameras measure (the worlds' camera);
    /// `jitter`, an independent 2 % draw, the worlds' camera before that measurement (a figure
    /// no recording measures); `steady`, no change (automatic exposure and gain off, steady
    /// light); `aec`, the OV7670's documented automatic exposure: it holds while the view's mean
    /// grey stays within ±8.3 % of the first view's and steps by 1/16 a frame when it leaves
    /// (docs/world.md, "The camera's gain").
    #[arg(long = "camera-gain", default_value_t = alvs_sim::GainModel::default(), value_name = "MODEL")]
    pub gain: alvs_sim::GainModel,
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
    /// Where the results go: `--json` with the experiment's own `--png` and `--trace`.
    pub fn outputs<'a>(&'a self, png: &'a Path, trace: Option<&'a Path>) -> Outputs<'a> {
        Outputs {
            png,
            json: self.json.as_deref(),
            trace,
        }
    }
}

/// The model an experiment runs and its overrides: `--model`, `--param`, `--fsm`.
#[derive(clap::Args)]
pub struct ModelOptions {
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
}

impl ModelOptions {
    /// The model parameters: `--model` with the `--param` overrides.
    pub fn params(&self) -> Result<Params> {
        parse_params(self.model, &self.params)
    }

    /// The motion parameters: `--model` with the `--fsm` overrides.
    pub fn fsm(&self) -> Result<FsmParams> {
        parse_fsm(self.model, &self.fsm)
    }
}

/// A preset of the model: its perception (`Params::preset`) and its motion (`FsmParams`).
#[derive(Clone, Copy, ValueEnum)]
pub enum Model {
    /// The paper's model plus the closed-loop mechanisms that earn their place (`Params::ALVS`,
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

/// `--jobs`: at least 1, default the available parallelism.
pub fn jobs(jobs: Option<usize>) -> Result<usize> {
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
pub fn parse_params(model: Model, overrides: &[String]) -> Result<Params> {
    let mut p = model.params();
    apply_overrides("param", overrides, |k, v| p.set(k, v))?;
    Ok(p)
}

/// The motion parameters of `model` with `--fsm NAME=VALUE` overrides applied.
pub fn parse_fsm(model: Model, overrides: &[String]) -> Result<FsmParams> {
    let mut p = model.fsm();
    apply_overrides("fsm", overrides, |k, v| p.set(k, v))?;
    Ok(p)
}

/// A repeatable option's values, or the default when none was given.
pub fn given_or<T: Clone>(given: &[T], default: Vec<T>) -> Vec<T> {
    if given.is_empty() {
        default
    } else {
        given.to_vec()
    }
}

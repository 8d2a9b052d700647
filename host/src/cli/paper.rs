//! The paper's five experiments (`stimuli`, `evasion`, `two-threats`, `swarm`, `arena`): their
//! options and the configuration each builds; [`runner::run`](super::runner::run) does the rest.

use std::path::PathBuf;

use alvs_host::experiments::arena::{self, ArenaConfig};
use alvs_host::experiments::{evasion, stimuli, swarm, two_threats};
use alvs_sim::Kind;
use anyhow::Result;
use clap::ValueEnum;

use super::options::{CameraArgs, CommonArgs, ModelOptions, SweepArgs, TrialArgs, WorldArgs};
use super::runner::{Experiment, Outputs};

#[derive(clap::Args)]
pub struct StimuliArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Where the pictures go.
    #[arg(long, default_value = "out/stimuli", value_name = "DIR")]
    png: PathBuf,
}

impl Experiment for StimuliArgs {
    type Config = stimuli::StimuliConfig;

    fn config(&self) -> Result<Self::Config> {
        Ok(stimuli::StimuliConfig {
            seed: self.common.seed,
            params: self.common.model.params()?,
            fsm: self.common.model.fsm()?,
            world: self.common.world.builtin(),
            background: self.common.background.clone(),
            exposure: self.common.camera.exposure,
            gain: self.common.camera.gain,
        })
    }

    fn check(config: &Self::Config) -> Result<u64> {
        config.validate()?;
        // its scenes tell the progress bar of no frames
        Ok(0)
    }

    fn sweep(&self) -> &SweepArgs {
        &self.common.sweep
    }

    fn outputs(&self) -> Outputs<'_> {
        self.common.outputs(&self.png, None)
    }
}

#[derive(clap::Args)]
pub struct EvasionArgs {
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

impl Experiment for EvasionArgs {
    type Config = evasion::EvasionConfig;

    fn config(&self) -> Result<Self::Config> {
        Ok(evasion::EvasionConfig {
            distance_mm: self.distance,
            speed_mm_s: self.speed,
            controllers: kinds(&self.controllers, &[Kind::Alvs, Kind::Lgmd2]),
            seed: self.common.seed,
            params: self.common.model.params()?,
            fsm: self.common.model.fsm()?,
            world: self.common.world.builtin(),
            background: self.common.background.clone(),
            exposure: self.common.camera.exposure,
            gain: self.common.camera.gain,
            trace: self.trace.is_some(),
            ..evasion::EvasionConfig::default()
        })
    }

    fn check(config: &Self::Config) -> Result<u64> {
        config.validate()?;
        Ok(config.total_frames())
    }

    fn sweep(&self) -> &SweepArgs {
        &self.common.sweep
    }

    fn outputs(&self) -> Outputs<'_> {
        self.common.outputs(&self.png, self.trace.as_deref())
    }
}

#[derive(clap::Args)]
pub struct TwoThreatArgs {
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

impl Experiment for TwoThreatArgs {
    type Config = two_threats::TwoThreatConfig;

    fn config(&self) -> Result<Self::Config> {
        Ok(two_threats::TwoThreatConfig {
            runs: self.runs,
            fast_mm_s: self.fast,
            slow_mm_s: self.slow,
            controllers: kinds(&self.controllers, &[Kind::Alvs, Kind::Lgmd2]),
            seed: self.common.seed,
            params: self.common.model.params()?,
            fsm: self.common.model.fsm()?,
            world: self.common.world.builtin(),
            background: self.common.background.clone(),
            exposure: self.common.camera.exposure,
            gain: self.common.camera.gain,
            trace: self.trace.is_some(),
        })
    }

    fn check(config: &Self::Config) -> Result<u64> {
        config.validate()?;
        Ok(config.total_frames())
    }

    fn sweep(&self) -> &SweepArgs {
        &self.common.sweep
    }

    fn outputs(&self) -> Outputs<'_> {
        self.common.outputs(&self.png, self.trace.as_deref())
    }
}

#[derive(clap::Args)]
pub struct SwarmArgs {
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

impl Experiment for SwarmArgs {
    type Config = swarm::SwarmConfig;

    fn config(&self) -> Result<Self::Config> {
        Ok(swarm::SwarmConfig {
            robots: self.robots,
            leader: self.leader,
            minutes: self.minutes,
            controllers: kinds(&self.controllers, &[Kind::Swarm, Kind::Alvs]),
            seed: self.common.seed,
            params: self.common.model.params()?,
            fsm: self.common.model.fsm()?,
            world: self.common.world.builtin(),
            background: self.common.background.clone(),
            exposure: self.common.camera.exposure,
            gain: self.common.camera.gain,
        })
    }

    fn check(config: &Self::Config) -> Result<u64> {
        config.validate()?;
        Ok(config.total_frames())
    }

    fn sweep(&self) -> &SweepArgs {
        &self.common.sweep
    }

    fn outputs(&self) -> Outputs<'_> {
        self.common.outputs(&self.png, None)
    }
}

#[derive(clap::Args)]
pub struct ArenaArgs {
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
    #[command(flatten)]
    model: ModelOptions,
    #[command(flatten)]
    camera: CameraArgs,
}

impl Experiment for ArenaArgs {
    type Config = ArenaConfig;

    fn config(&self) -> Result<ArenaConfig> {
        Ok(ArenaConfig {
            robots: self.trial.robots,
            minutes: self.trial.minutes,
            world: self.world.builtin(),
            backgrounds: self.backgrounds.clone(),
            controllers: if self.controllers.is_empty() {
                vec![Kind::Alvs, Kind::Lgmd2]
            } else {
                self.controllers.iter().map(|c| c.kind()).collect()
            },
            seed: self.seed,
            params: self.model.params()?,
            fsm: self.model.fsm()?,
            trace: self.trace.is_some(),
            exposure: self.camera.exposure,
            gain: self.camera.gain,
            ..ArenaConfig::default()
        })
    }

    fn check(config: &ArenaConfig) -> Result<u64> {
        config.validate()?;
        Ok(arena::total_frames(config))
    }

    fn sweep(&self) -> &SweepArgs {
        &self.sweep
    }

    fn outputs(&self) -> Outputs<'_> {
        Outputs {
            png: &self.png,
            json: self.json.as_deref(),
            trace: self.trace.as_deref(),
        }
    }
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

/// The controllers given, each once in the order given, or `default` when none was.
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

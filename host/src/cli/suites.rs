//! `alvs robustness` and `alvs ablation`: the suites over seeds, perturbations and controllers
//! or model variants, run through [`runner::run`](super::runner::run).

use std::path::PathBuf;

use alvs_host::experiments::ablation::{AblationConfig, Variant};
use alvs_host::experiments::robustness::{Perturbation, RobustnessConfig, SuiteController};
use anyhow::Result;
use clap::ValueEnum;

use super::options::{given_or, SweepArgs, TrialArgs, WorldArgs};
use super::runner::{Experiment, Outputs};

#[derive(clap::Args)]
pub struct RobustnessArgs {
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

impl Experiment for RobustnessArgs {
    type Config = RobustnessConfig;

    fn config(&self) -> Result<RobustnessConfig> {
        let d = RobustnessConfig::default();
        Ok(RobustnessConfig {
            world: self.world.builtin(),
            seeds: given_or(&self.seeds, d.seeds),
            perturbations: given_or(&self.perturbations, d.perturbations),
            controllers: if self.controllers.is_empty() {
                d.controllers
            } else {
                self.controllers.iter().map(|c| c.controller()).collect()
            },
            robots: self.trial.robots,
            minutes: self.trial.minutes,
        })
    }

    fn check(config: &RobustnessConfig) -> Result<u64> {
        config.validate()?;
        Ok(config.total_frames())
    }

    fn sweep(&self) -> &SweepArgs {
        &self.sweep
    }

    fn outputs(&self) -> Outputs<'_> {
        Outputs {
            png: &self.png,
            json: self.json.as_deref(),
            trace: None,
        }
    }
}

#[derive(clap::Args)]
pub struct AblationArgs {
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
    /// Wall of the evasion with the obstacle first seen close, 100 mm away (repeatable), as
    /// --wall. Default: the same three walls.
    #[arg(long = "close-wall", value_name = "SPEC", conflicts_with = "no_close")]
    close_walls: Vec<String>,
    /// Leave out the evasion with the obstacle first seen close.
    #[arg(long)]
    no_close: bool,
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

impl Experiment for AblationArgs {
    type Config = AblationConfig;

    fn config(&self) -> Result<AblationConfig> {
        let d = AblationConfig::default();
        Ok(AblationConfig {
            world: self.world.builtin(),
            seeds: given_or(&self.seeds, d.seeds),
            variants: given_or(&self.variants, d.variants),
            perturbations: given_or(&self.perturbations, d.perturbations),
            walls: walls_or(&self.walls, d.walls),
            close_walls: if self.no_close {
                Vec::new()
            } else {
                walls_or(&self.close_walls, d.close_walls)
            },
            robots: self.robots,
            minutes: self.minutes,
            two_threat_runs: self.two_threat_runs,
            clips: !self.no_clips,
        })
    }

    fn check(config: &AblationConfig) -> Result<u64> {
        config.validate()?;
        Ok(config.total_frames())
    }

    fn sweep(&self) -> &SweepArgs {
        &self.sweep
    }

    fn outputs(&self) -> Outputs<'_> {
        Outputs {
            png: &self.png,
            json: self.json.as_deref(),
            trace: None,
        }
    }
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

/// The walls given (`world`: the world's own), or the default's.
fn walls_or(given: &[String], default: Vec<Option<String>>) -> Vec<Option<String>> {
    if given.is_empty() {
        default
    } else {
        given
            .iter()
            .map(|w| (w != "world").then(|| w.clone()))
            .collect()
    }
}

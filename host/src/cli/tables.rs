//! `alvs tables`: the headline figures of five experiments as the docs' markdown tables.

use std::io::Write;

use anyhow::Result;
use clap::ValueEnum;

use super::options::{jobs, WorldArgs};

#[derive(clap::Args)]
pub struct TablesArgs {
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
    /// How the camera's global gain moves from frame to frame in every run, as each
    /// experiment's `--camera-gain`: `clips` (the worlds' camera), `jitter`, `steady` or `aec`.
    #[arg(long = "camera-gain", default_value_t = alvs_sim::GainModel::default(), value_name = "MODEL")]
    gain: alvs_sim::GainModel,
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

/// Runs `alvs tables`. Not through the experiments' runner: it runs whole experiments one after
/// another, writes no files and reports its progress as lines.
pub fn run(a: TablesArgs) -> Result<()> {
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
        gain: a.gain,
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

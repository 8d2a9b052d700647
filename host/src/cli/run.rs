//! Which subcommand runs what.

use anyhow::Result;

use super::args::{Cli, Cmd};
use super::cycles::{cycles_bin, run_cycles_bin};
use super::{log, multi, recordings, replay, runner, shards, tables, validate};

/// Runs the command `cli` gives.
pub fn run(cli: Cli) -> Result<()> {
    match cli.cmd {
        Cmd::Replay(a) => replay::run_replay(a),
        Cmd::Demo { png, model } => replay::run_demo(png, model),
        Cmd::Arena(a) => runner::run(&a),
        Cmd::Stimuli(a) => runner::run(&a),
        Cmd::MultiTarget(a) => multi::run(a),
        Cmd::Evasion(a) => runner::run(&a),
        Cmd::TwoThreats(a) => runner::run(&a),
        Cmd::Swarm(a) => runner::run(&a),
        Cmd::Recordings { cmd } => recordings::run(cmd),
        Cmd::Validate(a) => validate::run(a),
        Cmd::Robustness(a) => runner::run(&a),
        Cmd::Ablation(a) => runner::run(&a),
        Cmd::Tables(a) => tables::run(a),
        Cmd::Merge(a) => shards::merge(a),
        Cmd::Budget { args } => run_cycles_bin("alvs-budget", &args),
        Cmd::Virtual { args } => run_cycles_bin("alvs-virtual", &args),
        Cmd::Log(a) => log::run(a, cycles_bin),
    }
}

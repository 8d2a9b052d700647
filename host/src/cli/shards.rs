//! The CLI's side of sweeps: an experiment run whole or as one shard (`--shard I/N`), and
//! `alvs merge`, which rebuilds the shards' configuration from the command line they carry and
//! prints the unsharded report.

use std::path::{Path, PathBuf};

use alvs_host::experiments::sweep::{self, Shard, ShardFile, Sweep};
use anyhow::{bail, Context, Result};
use clap::Parser;

use super::args::{Cli, Cmd};
use super::runner::{self, progress_bar, Experiment, Outputs};

/// `alvs merge`'s options.
#[derive(clap::Args)]
pub struct MergeArgs {
    /// The shard files of one run (`--shard I/N --json FILE`), all N of them, in any order.
    #[arg(required = true, value_name = "FILE")]
    files: Vec<PathBuf>,
    /// Write the pooled results as JSON (the same as an unsharded run's --json).
    #[arg(long, value_name = "PATH")]
    json: Option<PathBuf>,
    /// Where the pictures go (default: the experiment's own, out/<experiment>).
    #[arg(long, value_name = "DIR")]
    png: Option<PathBuf>,
}

/// Runs `config` whole (table, JSON, pictures, trace as `out` says) or, with `shard`, only that
/// slice, written as a shard file to `out.json`. `frames` is the whole run's camera frames (for
/// the progress bar).
pub fn execute<S: Sweep>(
    config: &S,
    jobs: usize,
    shard: Option<Shard>,
    out: &Outputs,
    frames: u64,
) -> Result<()> {
    let Some(shard) = shard else {
        return runner::whole(S::NAME, frames, out, |progress| {
            sweep::run_all(config, jobs, progress)
        });
    };
    if out.trace.is_some() {
        bail!("--trace cannot be sharded (every robot-frame would go into the shard file); run without --shard");
    }
    let Some(path) = out.json else {
        bail!("--shard {shard} needs --json PATH: the shard's trials go there, for `alvs merge`");
    };
    Outputs {
        png: out.png,
        json: Some(path),
        trace: None,
    }
    .check_files()?;
    let n = config.trial_count();
    let mine = (0..n).filter(|&k| shard.owns(k)).count();
    let bar = progress_bar(
        &format!("{} {shard}", S::NAME),
        frames * mine as u64 / n.max(1) as u64,
    );
    // the command line after the subcommand: the merge rebuilds the configuration from it
    let args: Vec<String> = std::env::args().skip(2).collect();
    let v = sweep::run_shard(config, &args, shard, jobs, &|k| bar.inc(k));
    bar.finish_and_clear();
    let v = v?;
    std::fs::write(path, serde_json::to_string(&v)? + "\n")
        .with_context(|| format!("cannot write {}", path.display()))?;
    println!(
        "{} shard {shard}: {mine} of {n} trials; shard file {} (pool the shards with `alvs merge`)",
        S::NAME,
        path.display()
    );
    Ok(())
}

/// `alvs merge FILE...`: checks the shard files, rebuilds their configuration and prints (and
/// writes) the report of the whole run.
pub fn merge(a: MergeArgs) -> Result<()> {
    let files: Vec<ShardFile> = a
        .files
        .iter()
        .map(|p| sweep::read(p))
        .collect::<Result<_>>()?;
    let head = sweep::check(&files)?.clone();
    let line = || format!("alvs {} {}", head.experiment, head.args.join(" "));
    let cli = Cli::try_parse_from(
        ["alvs".to_string(), head.experiment.clone()]
            .into_iter()
            .chain(head.args.iter().cloned()),
    )
    .map_err(|e| {
        anyhow::anyhow!(
            "the shards' command line `{}` does not parse: {}",
            line(),
            super::one_line(&e)
        )
    })?;
    let png = a
        .png
        .unwrap_or_else(|| Path::new("out").join(&head.experiment));
    let out = Outputs {
        png: &png,
        json: a.json.as_deref(),
        trace: None,
    };
    out.check()?;
    match cli.cmd {
        Cmd::Arena(x) => pool(&x, &files, &out),
        Cmd::Evasion(x) => pool(&x, &files, &out),
        Cmd::TwoThreats(x) => pool(&x, &files, &out),
        Cmd::Swarm(x) => pool(&x, &files, &out),
        Cmd::Stimuli(x) => pool(&x, &files, &out),
        Cmd::Robustness(x) => pool(&x, &files, &out),
        Cmd::Ablation(x) => pool(&x, &files, &out),
        _ => bail!("`{}` is not an experiment that can be sharded", line()),
    }
}

/// Prints and writes what an unsharded run of the experiment `args` describe would, from the
/// shards' trials.
fn pool<E: Experiment>(args: &E, files: &[ShardFile], out: &Outputs) -> Result<()> {
    out.publish(&sweep::merge(&args.config()?, files)?)
}

//! The one way an experiment runs. Its options build its configuration ([`Experiment`]);
//! [`run`] checks the configuration, then runs it whole or as one shard on `--jobs` threads,
//! with a progress bar, and publishes its report ([`Outputs`]): an experiment added to the CLI
//! writes its options → configuration and nothing of this.

use std::io::Write;
use std::path::Path;

use alvs_host::experiments::sweep::Sweep;
use alvs_host::experiments::Report;
use anyhow::{Context, Result};

use super::options::{jobs, SweepArgs};
use super::shards;

/// An experiment's command-line options: what they make of it. Running it is [`run`]'s.
pub trait Experiment {
    /// The configuration the options describe, which runs (and shards) as a [`Sweep`].
    type Config: Sweep;

    /// The configuration these options give (also how `alvs merge` rebuilds a sharded run's
    /// from the command line its shards carry).
    fn config(&self) -> Result<Self::Config>;

    /// Refuses a configuration that cannot run, before anything is written or run; returns
    /// the whole run's camera frames (the progress bar's length).
    fn check(config: &Self::Config) -> Result<u64>;

    /// `--jobs` and `--shard`.
    fn sweep(&self) -> &SweepArgs;

    /// `--png`, `--json` and, where the experiment keeps one, `--trace`.
    fn outputs(&self) -> Outputs<'_>;
}

/// Runs the experiment `args` describe: the configuration checked, then run whole or as the
/// shard `--shard` names ([`shards::execute`]).
pub fn run<E: Experiment>(args: &E) -> Result<()> {
    let config = args.config()?;
    let frames = E::check(&config)?;
    let sweep = args.sweep();
    shards::execute(
        &config,
        jobs(sweep.jobs)?,
        sweep.shard,
        &args.outputs(),
        frames,
    )
}

/// A whole run of `total` progress steps: `out` checked first (a bad path fails before the
/// run, not after), `run` told of each step through a progress bar named `name`, its report
/// published. What every unsharded run does, sweep or not (`validate`).
pub fn whole<R: Report>(
    name: &str,
    total: u64,
    out: &Outputs,
    run: impl FnOnce(&(dyn Fn(u64) + Sync)) -> Result<R>,
) -> Result<()> {
    out.check()?;
    let bar = progress_bar(name, total);
    let r = run(&|n| bar.inc(n));
    bar.finish_and_clear();
    out.publish(&r?)
}

/// A progress bar on stderr for `total` camera frames (hidden by indicatif when stderr is not
/// a terminal: CI logs, pipes).
pub fn progress_bar(name: &str, total: u64) -> indicatif::ProgressBar {
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

/// Where an experiment's results go: `--png`, `--json`, `--trace`.
pub struct Outputs<'a> {
    pub png: &'a Path,
    pub json: Option<&'a Path>,
    pub trace: Option<&'a Path>,
}

impl Outputs<'_> {
    /// Fails before a long run, not after it, when the pictures' folder cannot be made or the
    /// JSON or trace file cannot be written. An existing file keeps its contents until the run
    /// has new ones; a file made only for the check is removed again.
    pub fn check(&self) -> Result<()> {
        std::fs::create_dir_all(self.png)
            .with_context(|| format!("cannot create {}", self.png.display()))?;
        self.check_files()
    }

    /// [`Outputs::check`] of the JSON and trace files only.
    pub fn check_files(&self) -> Result<()> {
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
    pub fn publish(&self, r: &impl Report) -> Result<()> {
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

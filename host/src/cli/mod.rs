//! The `alvs` command line (the binary's own modules, not the library's).
//!
//! - [`args`]: `alvs` and its subcommands (their `--help` texts);
//! - [`options`]: the option groups several subcommands share, and how their values are read;
//! - [`runner`]: the one way an experiment runs ([`runner::Experiment`], [`runner::run`]):
//!   outputs checked, whole or one shard, progress bar, report published; [`shards`]: the
//!   `--shard` side of it and `alvs merge`;
//! - one module per group of subcommands: [`paper`] (the paper's five experiments), [`suites`]
//!   (robustness, ablation), [`validate`], [`tables`], [`replay`] (replay, demo),
//!   [`recordings`], [`log`], [`cycles`] (budget, virtual), [`multi`] (multi-target);
//! - [`run`](mod@run): which subcommand runs what.

mod args;
mod cycles;
mod log;
mod multi;
mod options;
mod paper;
mod recordings;
mod replay;
mod run;
mod runner;
mod shards;
mod suites;
mod tables;
mod validate;

pub use args::Cli;
pub use cycles::Exit;
pub use run::run;

/// A command-line error as one line: clap's message without its usage and help hints.
pub fn one_line(e: &clap::Error) -> String {
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

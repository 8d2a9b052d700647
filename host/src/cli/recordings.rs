//! `alvs recordings`: the real Colias runs, extracted from the tracker's snapshots or shown.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Subcommand;

use super::runner::progress_bar;

#[derive(Subcommand)]
pub enum RecordingsCmd {
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

/// Runs `alvs recordings extract` or `alvs recordings stats`.
pub fn run(cmd: RecordingsCmd) -> Result<()> {
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

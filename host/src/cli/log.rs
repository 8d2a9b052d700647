//! `alvs log`: a saved RTT session read back (`alvs_host::rtt_log`), summarised, compared with
//! the cycle model, drawn.

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Stdio};

use alvs_host::rtt_log::{self, report, source, Log, LogReport, Prediction};
use anyhow::Result;

#[derive(clap::Args)]
pub struct LogArgs {
    /// A cargo-embed log file (the session's other tab comes too), a folder of them (its newest
    /// session), another text file, or - for text on standard input (either tab, or both).
    #[arg(default_value = "logs", value_name = "PATH|-")]
    path: PathBuf,
    /// Write timeline.png, fields.png and cycles.png into this folder.
    #[arg(long, value_name = "DIR")]
    png: Option<PathBuf>,
    /// Print the summary as JSON instead of text.
    #[arg(long)]
    json: bool,
    /// Leave out the cycle model's prediction (which builds and runs `alvs-budget --boot`:
    /// cmake and libclang-dev, as for `cargo alvs budget`).
    #[arg(long)]
    no_model: bool,
}

/// Runs the command; `cycles_bin` makes the `cargo run` of a binary of alvs-cycles.
pub fn run(a: LogArgs, cycles_bin: impl Fn(&str, &[String]) -> Command) -> Result<()> {
    let sources = if a.path.as_os_str() == "-" {
        vec![source::read_stdin()?]
    } else if a.path.as_os_str() == "logs" && !a.path.exists() {
        anyhow::bail!(
            "no logs/ folder here: cargo embed saves its sessions there when Embed.toml sets \
             log_enabled = true (docs/log.md); or give a log's path, or - for standard input"
        );
    } else {
        source::read_files(&source::locate(&a.path)?)?
    };
    let bytes: usize = sources.iter().map(|s| s.text.len()).sum();
    let bar = indicatif::ProgressBar::new(bytes as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "log {elapsed_precise} [{bar:40}] {bytes}/{total_bytes}, eta {eta}",
        )
        .expect("a valid template")
        .progress_chars("=> "),
    );
    let log = Log::parse(&sources, &mut |n| bar.inc(n));
    bar.finish_and_clear();
    report::check(&log)?;
    let model = if a.no_model {
        Err("left out (--no-model)".to_owned())
    } else {
        prediction(&cycles_bin)
    };
    let report = LogReport::of(&log, model)?;
    let mut out = std::io::stdout().lock();
    if a.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&report)?)?;
    } else {
        write!(out, "{report}")?;
    }
    if let Some(dir) = &a.png {
        let files = rtt_log::pictures::write(&log, &report, dir)?;
        eprintln!("{} pictures in {}", files.len(), dir.display());
    }
    Ok(())
}

/// The cycle model's self-test for this working tree's release build, or why not (one line).
fn prediction(cycles_bin: &impl Fn(&str, &[String]) -> Command) -> Result<Prediction, String> {
    let spinner = indicatif::ProgressBar::new_spinner();
    spinner.set_message("the cycle model's self-test (cargo alvs budget --boot; the first time it builds the emulator)");
    spinner.enable_steady_tick(std::time::Duration::from_millis(200));
    let out = cycles_bin("alvs-budget", &["--boot".into(), "--json".into()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .output();
    spinner.finish_and_clear();
    let out = out.map_err(|e| format!("cannot run cargo: {e}"))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let last = err
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("");
        return Err(format!("cargo alvs budget --boot failed: {}", last.trim()));
    }
    Prediction::from_json(&String::from_utf8_lossy(&out.stdout)).map_err(|e| format!("{e:#}"))
}

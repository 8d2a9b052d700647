//! `alvs`: host tools for the attention-driven LPLC2 visuomotor system.
//! Run through the cargo alias: `cargo alvs <subcommand> --help`.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use alvs_host::{clip, replay, scenes};
use alvs_tasks::fsm::Behaviour;
use alvs_tasks::{Params, HEIGHT, WIDTH};
use anyhow::{Context, Result};
use clap::{Parser, Subcommand, ValueEnum};

#[derive(Parser)]
#[command(
    name = "alvs",
    version,
    about = "Host tools for the ALVS firmware: the exact task code on recorded or synthetic video"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run the perception and motor-control tasks on a clip; one JSON object per frame on stdout.
    Replay(ReplayArgs),
    /// Run the built-in synthetic scenes (approach left/centre/right, recede, translate, double
    /// and triple approach) and write their pictures.
    Demo {
        /// Where the pictures go.
        #[arg(long, default_value = "out/demo")]
        png: PathBuf,
        #[command(flatten)]
        model: ModelArgs,
    },
}

#[derive(clap::Args)]
struct ModelArgs {
    /// Override a model parameter, NAME=VALUE (repeatable), e.g. --param t_a=120.
    /// Names: w n r_af t_a t_d d w_s alpha t_s c_d s gain lm_shift r_c c_frac q_floor q_balance.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Motor behaviour: escape (paper II-B) or swarm (spin on approach, paper IV-D).
    #[arg(long, value_enum, default_value_t = Mode::Escape)]
    mode: Mode,
}

#[derive(Clone, Copy, ValueEnum)]
enum Mode {
    Escape,
    Swarm,
}

#[derive(clap::Args)]
struct ReplayArgs {
    /// A raw Y8 clip (frames of 99x72, row-major, no header) or a directory of binary PGM frames.
    clip: PathBuf,
    /// Frame width of the clip (the model takes only 99).
    #[arg(long, default_value_t = WIDTH)]
    width: usize,
    /// Frame height of the clip (the model takes only 72).
    #[arg(long, default_value_t = HEIGHT)]
    height: usize,
    /// Write layer pictures and an LPLC2 trace into this directory.
    #[arg(long, value_name = "DIR")]
    png: Option<PathBuf>,
    /// Frames to draw layers for (comma-separated); default: first alert and peak response.
    #[arg(long, value_delimiter = ',', value_name = "N,...")]
    frames: Vec<u32>,
    #[command(flatten)]
    model: ModelArgs,
}

impl ModelArgs {
    fn params(&self) -> Result<Params> {
        let mut p = Params::default();
        for kv in &self.params {
            let (k, v) = kv
                .split_once('=')
                .with_context(|| format!("--param {kv}: expected NAME=VALUE"))?;
            p.set(k.trim(), v)
                .map_err(|e| anyhow::anyhow!("--param {kv}: {e}"))?;
        }
        Ok(p)
    }

    fn behaviour(&self) -> Behaviour {
        match self.mode {
            Mode::Escape => Behaviour::Escape,
            Mode::Swarm => Behaviour::Swarm,
        }
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        // a closed pipe (`alvs replay clip.y8 | head`) is the reader's choice, not an error
        Err(e)
            if e.chain().any(|c| {
                c.downcast_ref::<std::io::Error>()
                    .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
            }) =>
        {
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("alvs: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.cmd {
        Cmd::Replay(a) => {
            let params = a.model.params()?;
            let frames = clip::load(&a.clip, a.width, a.height)?;
            let name = a
                .clip
                .file_stem()
                .map_or("clip".into(), |s| s.to_string_lossy().into_owned());
            let stdout = std::io::stdout();
            let mut out = std::io::BufWriter::new(stdout.lock());
            let png = a
                .png
                .as_deref()
                .map(|d| (d, a.frames.as_slice(), name.as_str()));
            replay::run(&frames, params, a.model.behaviour(), png, |j| {
                let mut line = serde_json::to_vec(j)?;
                line.push(b'\n');
                out.write_all(&line)?;
                Ok(())
            })?;
            out.flush()?;
            if let Some(d) = &a.png {
                eprintln!("pictures in {}", d.display());
            }
            Ok(())
        }
        Cmd::Demo { png, model } => {
            let params = model.params()?;
            let mut out = std::io::stdout().lock();
            writeln!(
                out,
                "{:<18} {:>7} {:>6} {:>6} {:>8} {:>7}  first alert",
                "scene", "looming", "frames", "alerts", "max AFs", "mean X"
            )?;
            for s in scenes::demo_scenes() {
                let frames = s.frames();
                let recs = replay::run(
                    &frames,
                    params,
                    model.behaviour(),
                    Some((&png, &[], s.name)),
                    |_| Ok(()),
                )?;
                let alerts: Vec<&replay::FrameJson> = recs.iter().filter(|r| r.alert).collect();
                let xs: Vec<f32> = alerts.iter().filter_map(|r| r.threat_x).collect();
                let mean_x = if xs.is_empty() {
                    "-".to_string()
                } else {
                    format!("{:.1}", xs.iter().sum::<f32>() / xs.len() as f32)
                };
                let max_afs = recs.iter().map(|r| r.afs.len()).max().unwrap_or(0);
                let first = alerts.first().map_or("-".into(), |r| r.frame.to_string());
                writeln!(
                    out,
                    "{:<18} {:>7} {:>6} {:>6} {:>8} {:>7}  {first}",
                    s.name,
                    s.looming,
                    recs.len(),
                    alerts.len(),
                    max_afs,
                    mean_x
                )?;
            }
            writeln!(out, "pictures in {}", png.display())?;
            Ok(())
        }
    }
}

//! `alvs replay` and `alvs demo`: the perception and motor tasks on a clip or on the built-in
//! scenes, frame by frame (no simulated world, so not through the experiments' runner).

use std::io::Write;
use std::path::PathBuf;

use alvs_host::{clip, replay, scenes};
use alvs_tasks::model::fsm::{Behaviour, FsmParams};
use alvs_tasks::{Params, HEIGHT, WIDTH};
use anyhow::Result;
use clap::ValueEnum;

use super::options::{parse_fsm, parse_params, Model};

#[derive(clap::Args)]
pub struct ModelArgs {
    /// The model: alvs (the default: the paper's model plus the closed-loop
    /// mechanisms that earn their place, docs/model.md), paper (the paper's model exactly) or firmware
    /// (what the authors' public firmware runs); it sets both the perception and the motion
    /// (FSM) parameters. --param and --fsm overrides apply on top.
    #[arg(long, value_enum, default_value_t = Model::Alvs)]
    model: Model,
    /// Override a model parameter, NAME=VALUE (repeatable), e.g. --param t_a=120 or
    /// --param table1.t_a=120; names and spellings in docs/model.md, "Parameter names".
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Override a motion (FSM) parameter, NAME=VALUE (repeatable), e.g. --fsm settle_frames=6
    /// or --fsm suppression.settle_frames=6; names and spellings in docs/model.md, "Parameter
    /// names".
    #[arg(long = "fsm", value_name = "NAME=VALUE")]
    fsm: Vec<String>,
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
pub struct ReplayArgs {
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
        parse_params(self.model, &self.params)
    }

    fn fsm(&self) -> Result<FsmParams> {
        parse_fsm(self.model, &self.fsm)
    }

    fn behaviour(&self) -> Behaviour {
        match self.mode {
            Mode::Escape => Behaviour::Escape,
            Mode::Swarm => Behaviour::Swarm,
        }
    }
}

/// `alvs replay`: one JSON object per frame on stdout.
pub fn run_replay(a: ReplayArgs) -> Result<()> {
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
    replay::run(
        &frames,
        params,
        a.model.fsm()?,
        a.model.behaviour(),
        png,
        |j| {
            let mut line = serde_json::to_vec(j)?;
            line.push(b'\n');
            out.write_all(&line)?;
            Ok(())
        },
    )?;
    out.flush()?;
    if let Some(d) = &a.png {
        eprintln!("pictures in {}", d.display());
    }
    Ok(())
}

/// `alvs demo`: the built-in scenes' table and pictures.
pub fn run_demo(png: PathBuf, model: ModelArgs) -> Result<()> {
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
            model.fsm()?,
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

//! `alvs multi-target`: Fig. 3 (e)–(f) on the authors' two multi-target clips, the paper's
//! model beside the default and beside the authors' own record ([`alvs_host::multi_target`]).

use std::io::Write;
use std::path::PathBuf;

use alvs_host::multi_target::{self as mt, Summary};
use alvs_host::{clip, replay};
use alvs_tasks::model::fsm::Behaviour;
use alvs_tasks::{HEIGHT, WIDTH};
use anyhow::{Context, Result};
use serde::Serialize;

use super::options::{parse_fsm, parse_params, Model};

#[derive(clap::Args)]
pub struct MultiArgs {
    /// Where the clips are (`outdoor_3_black_expand_multi_3.y8` and `_multi_6.y8`).
    #[arg(long, default_value = "data/clips", value_name = "DIR")]
    clips: PathBuf,
    /// The authors' record of their offline model's fields on the same clips.
    #[arg(
        long,
        default_value = "data/authors/multi_target_fields.csv",
        value_name = "FILE"
    )]
    authors: PathBuf,
    /// Override a model parameter in both models, NAME=VALUE (repeatable), e.g. --param
    /// r_af=23; names and spellings in docs/model.md, "Parameter names".
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Where the pictures go: per clip the fields over time, and each model's layers at the
    /// frame with most objects drawn.
    #[arg(long, default_value = "out/multi-target", value_name = "DIR")]
    png: PathBuf,
    /// Write the results as JSON.
    #[arg(long, value_name = "PATH")]
    json: Option<PathBuf>,
}

/// One clip's results.
#[derive(Serialize)]
struct ClipReport {
    clip: mt::MultiClip,
    models: Vec<(String, Summary)>,
    authors_fields: Option<Vec<usize>>,
    authors_first_field: Vec<Option<u32>>,
}

/// Runs `alvs multi-target`.
pub fn run(a: MultiArgs) -> Result<()> {
    // every option is checked before the first clip is read
    let mut models = Vec::new();
    for (name, m) in [("paper", Model::Paper), ("alvs", Model::Alvs)] {
        models.push((name, parse_params(m, &a.params)?, parse_fsm(m, &[])?));
    }
    let mut out = std::io::stdout().lock();
    let mut reports = Vec::new();
    for c in mt::clips() {
        let path = a.clips.join(format!("{}.y8", c.name));
        let frames = clip::load(&path, WIDTH, HEIGHT)?;
        let theirs = mt::read_authors(&a.authors, c.name)?;
        if reports.is_empty() {
            let head = ["clip", "model", "max AFs", "own (fr)", "alerts"];
            row(&mut out, head, "first field on each object (its onset)")?;
        }
        let at = mt::busiest_frame(&c, frames.len());
        let mut runs = Vec::new();
        for &(name, params, fsm) in &models {
            let records = replay::run(
                &frames,
                params,
                fsm,
                Behaviour::Escape,
                Some((&a.png, &[at], &format!("{}_{name}", c.name))),
                |_| Ok(()),
            )?;
            runs.push((name.to_string(), mt::summarise(&c, &records)));
        }
        let alive = mt::authors_alive(&theirs, frames.len());
        let onsets = |first: &[Option<u32>]| -> String {
            let cell = |(k, f): (usize, &Option<u32>)| {
                let t = f.map_or("-".into(), |f| f.to_string());
                format!("{t} ({})", c.squares[k].appear)
            };
            first
                .iter()
                .enumerate()
                .map(cell)
                .collect::<Vec<_>>()
                .join(", ")
        };
        for (name, s) in &runs {
            let most = s.max_fields.to_string();
            let own = format!("{}/{}", s.own_all_frames, s.object_frames);
            let alerts = s.alert_frames.to_string();
            let cells = [c.name, name, &most, &own, &alerts];
            row(&mut out, cells, &onsets(&s.first_field))?;
        }
        let authors_first = mt::authors_first_field(&c, &theirs);
        let most = alive
            .as_ref()
            .map_or("-".into(), |v| v.iter().max().unwrap_or(&0).to_string());
        let cells = [c.name, "authors", &most, "-", "-"];
        row(&mut out, cells, &onsets(&authors_first))?;
        let summaries: Vec<(&str, &Summary)> = runs.iter().map(|(n, s)| (n.as_str(), s)).collect();
        let picture = a.png.join(format!("{}_fields.png", c.name));
        mt::fields_plot(&c, &summaries, alive.as_deref())
            .save_png(&picture)
            .with_context(|| format!("{}: cannot write", picture.display()))?;
        reports.push(ClipReport {
            clip: c,
            models: runs,
            authors_fields: alive,
            authors_first_field: authors_first,
        });
    }
    writeln!(
        out,
        "own (fr): frames in which every object drawn has a field of its own / frames with an object drawn; \
         authors: their offline model (320x240), fields standing at most, and the first born on each object"
    )?;
    writeln!(out, "pictures in {}", a.png.display())?;
    if let Some(p) = &a.json {
        let f =
            std::fs::File::create(p).with_context(|| format!("{}: cannot write", p.display()))?;
        serde_json::to_writer_pretty(f, &reports)?;
        writeln!(out, "JSON in {}", p.display())?;
    }
    Ok(())
}

/// One line of the table: clip, model, most fields, own frames, alerts, then `first`.
fn row(
    out: &mut impl Write,
    [clip, model, most, own, alerts]: [&str; 5],
    first: &str,
) -> Result<()> {
    writeln!(
        out,
        "{clip:<32} {model:<8} {most:>7} {own:>10} {alerts:>7}  {first}"
    )?;
    Ok(())
}

//! The paper's experiments on the simulated arena (`cargo alvs <experiment>`): each one builds
//! its trials from a configuration, runs them (in parallel where they are independent), and
//! reports a summary table, JSON and pictures.
//!
//! | experiment | paper | module |
//! |---|---|---|
//! | `stimuli`: a standing robot watches one, two, three robots move; AF tracks and layers | Fig. 3, Sec. III-A | [`stimuli`] |
//! | `evasion`: one obstacle from nine bearings; escape side and collisions | Fig. 4a,c,d, Sec. III-B | [`evasion`] |
//! | `two-threats`: two obstacles at unequal speeds; evading away from the faster | Fig. 4b, Sec. III-B | [`two_threats`] |
//! | `arena`: robots wandering among each other and the walls, success rate and collisions | Figs. 5–6, Sec. III-C | [`arena`] |
//! | `swarm`: six robots spinning on approach; spread of the group over time | Fig. 7, Sec. IV-D | [`swarm`] |
//! | `robustness`: every controller in the validated world under a lab's and a robot's perturbations | issue 29 | [`robustness`] |
//! | `tables`: the headline figures of experiments 1–5 in one world over seeds, as docs' markdown | issue 29 | [`tables`] |
//!
//! Every experiment runs in a built-in world (`--world`: the recorded arena's replica `fu2019`
//! by default, or the `lab`; [`alvs_sim::BuiltinWorld`]), its walls the world's own unless a
//! background is given, which replaces them and keeps the rest of the world
//! ([`alvs_sim::worlds::world_with`]). The staged experiments (`stimuli`, `evasion`,
//! `two-threats`) stand where their geometry fits ([`alvs_sim::stage`]); the wandering ones start
//! clear of the walls and obstacles.
//!
//! [`alvs_sim::encounter`] is the open-loop set-up shared by `evasion` and `two-threats`;
//! [`parallel`] runs independent trials on worker threads; [`sweep`] splits a run into shards
//! (`--shard I/N`) and pools them again (`alvs merge`).

use std::path::{Path, PathBuf};

use alvs_tasks::Params;
use anyhow::{bail, ensure, Context, Result};

use alvs_sim::Kind;

pub mod ablation;
pub mod arena;
pub mod evasion;
pub mod parallel;
pub mod robustness;
pub mod stimuli;
pub mod swarm;
pub mod sweep;
pub mod tables;
pub mod two_threats;
pub mod validate;

/// What every experiment's result gives the CLI: a table, JSON, pictures and, for the
/// experiments that keep one, a frame-by-frame trace.
pub trait Report {
    /// The summary table printed on stdout.
    fn table(&self) -> String;

    /// The results as one JSON document (`--json`).
    fn json(&self) -> serde_json::Value;

    /// Writes the pictures into `dir` (created) and returns their paths.
    fn write_pictures(&self, dir: &Path) -> Result<Vec<PathBuf>>;

    /// Writes the frame-by-frame trace as CSV (`--trace`).
    fn write_trace(&self, path: &Path) -> Result<()> {
        bail!(
            "this experiment keeps no trace, so {} was not written",
            path.display()
        )
    }
}

/// Writes `picture` as `dir/summary.png` (the folder created) and returns its path: the one
/// picture of a sweep whose report is a table.
pub fn write_summary(dir: &Path, picture: &alvs_sim::canvas::Canvas) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let path = dir.join("summary.png");
    picture
        .save_png(&path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(vec![path])
}

/// The checks every experiment's configuration shares: something to run and valid model
/// parameters.
pub fn validate_setup(controllers: &[Kind], params: &Params) -> Result<()> {
    ensure!(!controllers.is_empty(), "no controller to run");
    params
        .validate()
        .map_err(|e| anyhow::anyhow!("invalid model parameters: {e}"))
}

/// The JSON of an experiment: one key per controller (its serialised outcome), plus `config`.
/// A value that cannot be serialised (never, for these plain structs) becomes `null` rather
/// than a panic.
pub fn per_controller_json<'a, T: serde::Serialize + 'a>(
    outcomes: impl IntoIterator<Item = (String, &'a T)>,
    config: serde_json::Value,
) -> serde_json::Value {
    let mut map = serde_json::Map::new();
    for (name, outcome) in outcomes {
        map.insert(
            name,
            serde_json::to_value(outcome).unwrap_or(serde_json::Value::Null),
        );
    }
    map.insert("config".into(), config);
    serde_json::Value::Object(map)
}

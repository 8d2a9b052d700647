//! The seven recorded runs of `fuqinbing/LGMD2-open-source` and how their snapshot folders
//! are read: file names are frame numbers, every file must be a PNG of the snapshot size.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

/// The repository the recordings come from, and the commit read.
pub const SOURCE_REPO: &str = "https://github.com/fuqinbing/LGMD2-open-source";
pub const SOURCE_COMMIT: &str = "141e7e5";

/// One recorded run: its folder in the repository and what the folder's name says.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSpec {
    /// Name of the run's JSON (`host/data/fu2019/<name>.json`).
    pub name: &'static str,
    /// Snapshot folder, relative to the repository's root.
    pub folder: &'static str,
    /// The robot's nominal forward speed, cm/s (from the folder's name).
    pub speed_cm_s: f64,
    /// The recording's duration, s (from the folder's name).
    pub duration_s: f64,
}

/// Every run, in the order the tables list them.
pub const RUNS: [RunSpec; 7] = [
    RunSpec {
        name: "v10.9_9m43s",
        folder: "robot-10.9cms-duration-9min43sec/tracking & frame number",
        speed_cm_s: 10.9,
        duration_s: 583.0,
    },
    RunSpec {
        name: "v10.9_10m08s",
        folder: "robot trajectory-more other results/speed-10.9-duration-10min08sec",
        speed_cm_s: 10.9,
        duration_s: 608.0,
    },
    RunSpec {
        name: "v10.9_11m16s",
        folder: "robot trajectory-more other results/speed-10.9-duration-11min16sec",
        speed_cm_s: 10.9,
        duration_s: 676.0,
    },
    RunSpec {
        name: "v7.1_10m09s",
        folder: "robot-7.1cms-duration-10min9sec/tracking & frame number",
        speed_cm_s: 7.1,
        duration_s: 609.0,
    },
    RunSpec {
        name: "v7.1_10m53s",
        folder: "robot trajectory-more other results/speed-7.1-duration-10min53sec",
        speed_cm_s: 7.1,
        duration_s: 653.0,
    },
    RunSpec {
        name: "v3.5_10m09s",
        folder: "robot-3.5cms-duration-10min9sec/tracking & frame number",
        speed_cm_s: 3.5,
        duration_s: 609.0,
    },
    RunSpec {
        name: "v1.5_9m51s",
        folder: "robot-1.5cms-duration-9min51sec/tracking & frame number",
        speed_cm_s: 1.5,
        duration_s: 591.0,
    },
];

/// A snapshot file: its frame number and path.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct SnapshotFile {
    pub frame: u64,
    pub path: PathBuf,
    /// Path relative to the repository's root (for provenance).
    pub source: String,
}

/// The run's snapshots in frame order. A missing folder, a file that is not `<frame>.png`,
/// or an empty folder is a one-line error.
pub fn list_snapshots(repo: &Path, run: &RunSpec) -> Result<Vec<SnapshotFile>> {
    let dir = repo.join(run.folder);
    if !dir.is_dir() {
        bail!(
            "{}: no such folder (is {} a clone of {SOURCE_REPO}?)",
            dir.display(),
            repo.display()
        );
    }
    let mut out = Vec::new();
    for entry in std::fs::read_dir(&dir).with_context(|| format!("{}", dir.display()))? {
        let path = entry?.path();
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let frame = name
            .strip_suffix(".png")
            .and_then(|stem| stem.parse::<u64>().ok())
            .with_context(|| format!("{}: not a <frame number>.png snapshot", path.display()))?;
        out.push(SnapshotFile {
            frame,
            source: format!("{}/{name}", run.folder),
            path,
        });
    }
    if out.is_empty() {
        bail!("{}: no snapshots", dir.display());
    }
    out.sort();
    Ok(out)
}

/// The tracker's frame rate for a run, frames/s, and its bounds. The last snapshot's frame
/// was drawn before the recording ended and the next one (900 frames on) was not, so the
/// duration holds between `last` and `last + 900` frames; the estimate is the middle.
pub fn tracker_fps(run: &RunSpec, frames: &[u64]) -> (f64, f64, f64) {
    let last = frames.iter().copied().max().unwrap_or(0) as f64;
    let step = snapshot_step(frames) as f64;
    let (lo, hi) = (last / run.duration_s, (last + step) / run.duration_s);
    ((lo + hi) / 2.0, lo, hi)
}

/// The usual frame step between snapshots (900 in every run).
pub fn snapshot_step(frames: &[u64]) -> u64 {
    let mut steps: Vec<u64> = frames.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_unstable();
    steps.get(steps.len() / 2).copied().unwrap_or(900)
}

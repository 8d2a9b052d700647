//! The real Colias recordings of `fuqinbing/LGMD2-open-source` (Fu et al. 2019, LGMD2 robot
//! arena runs) turned into numbers: the arena's calibration and geometry, each run's track
//! (straight runs and timed robot positions), and path statistics that simulated trails are
//! compared with through the same code.
//!
//! | concern | module |
//! |---|---|
//! | one snapshot PNG: tracker colours, path mask, robot marker | [`snapshot`] |
//! | floor quadrilateral, homography, perspective of things above the floor | [`calibration`] |
//! | obstacles, wall band and height, greys, rib period | [`geometry`] |
//! | the seven runs, snapshot folders, tracker fps | [`runs`] |
//! | Hough extraction of straight runs | [`segments`] |
//! | tracks; simulated trails drawn like a recording | [`track`] |
//! | path statistics: wall shares, turns, straight runs, coverage, speed | [`stats`] |
//! | real against simulated: KS and ±20 % tolerances, pass/fail | [`compare`] |
//! | the whole extraction and its provenance | [`extract`] |
//! | pictures and the table of `recordings stats` | [`report`] |
//!
//! The committed data lives in `host/data/fu2019/` and is compiled in: [`arena`] and
//! [`run`] / [`all_runs`] load it.

pub mod calibration;
pub mod compare;
pub mod extract;
pub mod geometry;
pub mod report;
pub mod runs;
pub mod segments;
pub mod snapshot;
pub mod stats;
pub mod track;

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};

pub use compare::{compare, Verdict};
pub use extract::{Provenance, RunFile};
pub use stats::PathStats;
pub use track::{track_from_trail, Drawing, Segment, SnapshotFix, Track};

/// An obstacle cylinder, floor mm (arena frame: origin top-left, x right, y down).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Obstacle {
    /// Centre of its base.
    pub x_mm: f64,
    pub y_mm: f64,
    /// Diameter measured across its side (slightly magnified: the side's top is nearer the
    /// camera), or the others' median for one seen only by its top.
    pub diameter_mm: f64,
    /// `h / (H - h)` from its top's outward shift (h its height, H the camera's), when its
    /// top's hole was found beside its side.
    pub k: Option<f64>,
    /// Its top's centre (the hole in the roll), image px, when found.
    pub top_px: Option<(f64, f64)>,
    /// Its base's centre, image px.
    pub base_px: (f64, f64),
    /// How it was found: "side" (its side over the floor) or "top" (only its top's hole, the
    /// base placed back toward the nadir with the median k).
    pub seen_as: String,
}

/// The recorded arena, as measured (docs/recordings.md says how and how well).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ArenaGeometry {
    /// Inner floor size, mm (x: image left to right, y: image top to bottom).
    pub size_x_mm: f64,
    pub size_y_mm: f64,
    /// Floor scale, image px per mm.
    pub px_per_mm: f64,
    /// The robot's top disc diameter over all snapshots, px: (q1, median, q3).
    pub robot_disc_px: (f64, f64, f64),
    /// The assumed camera height, mm.
    pub camera_height_mm: f64,
    /// The floor's corners in the first run's first snapshot (TL, TR, BR, BL), px.
    pub floor_corners_px: [(f64, f64); 4],
    /// The largest corner shift of any run's floor against the first, px (camera movement).
    pub camera_shift_px: f64,
    /// Obstacles found (those merged with a wall's bright foot or in a corner are missing:
    /// see docs/recordings.md).
    pub obstacles: Vec<Obstacle>,
    /// Bright blobs on the floor too wide to be one obstacle, skipped.
    pub skipped_blobs: usize,
    /// Median obstacle diameter, mm.
    pub obstacle_diameter_mm: f64,
    /// Median obstacle `k` (over those whose top and side were both found) and the height it
    /// gives with `camera_height_mm`; `None` with fewer than 3 such obstacles.
    pub obstacle_k: Option<f64>,
    pub obstacle_height_mm: Option<f64>,
    /// Dark roundish holes matched to no obstacle and not placed as one (outside the arena).
    pub holes_unused: usize,
    /// Median width of the left and right walls' inner-face band, px.
    pub wall_band_px: f64,
    /// `h / (H - h)` of the walls, and their height with `camera_height_mm`.
    pub wall_k: f64,
    pub wall_height_mm: f64,
    /// Mean sRGB luma (Rec. 709 weights, 0-255) of the floor and of the walls' inner face.
    pub floor_luma: f64,
    pub wall_luma: f64,
    pub wall_to_floor: f64,
    /// The walls' rib period, mm (`None` if not found).
    pub rib_period_mm: Option<f64>,
    pub provenance: Provenance,
}

const ARENA_JSON: &str = include_str!("../../data/fu2019/arena.json");
const RUN_JSONS: [(&str, &str); 7] = [
    (
        "v10.9_9m43s",
        include_str!("../../data/fu2019/v10.9_9m43s.json"),
    ),
    (
        "v10.9_10m08s",
        include_str!("../../data/fu2019/v10.9_10m08s.json"),
    ),
    (
        "v10.9_11m16s",
        include_str!("../../data/fu2019/v10.9_11m16s.json"),
    ),
    (
        "v7.1_10m09s",
        include_str!("../../data/fu2019/v7.1_10m09s.json"),
    ),
    (
        "v7.1_10m53s",
        include_str!("../../data/fu2019/v7.1_10m53s.json"),
    ),
    (
        "v3.5_10m09s",
        include_str!("../../data/fu2019/v3.5_10m09s.json"),
    ),
    (
        "v1.5_9m51s",
        include_str!("../../data/fu2019/v1.5_9m51s.json"),
    ),
];

/// The committed arena geometry (`host/data/fu2019/arena.json`).
pub fn arena() -> Result<ArenaGeometry> {
    serde_json::from_str(ARENA_JSON).context("host/data/fu2019/arena.json")
}

/// The committed run named `name` (see [`runs::RUNS`]).
pub fn run(name: &str) -> Result<RunFile> {
    let (_, json) = RUN_JSONS
        .iter()
        .find(|(n, _)| *n == name)
        .with_context(|| format!("no recorded run {name:?}"))?;
    serde_json::from_str(json).with_context(|| format!("host/data/fu2019/{name}.json"))
}

/// Every committed run, in [`runs::RUNS`] order.
pub fn all_runs() -> Result<Vec<RunFile>> {
    RUN_JSONS.iter().map(|(n, _)| run(n)).collect()
}

impl ArenaGeometry {
    /// The arena's inner size, mm.
    pub fn size(&self) -> (f64, f64) {
        (self.size_x_mm, self.size_y_mm)
    }

    /// How a simulated trail is drawn to be extracted like these recordings.
    pub fn drawing(&self, snapshot_every_s: f64) -> Drawing {
        Drawing {
            arena_mm: self.size(),
            px_per_mm: self.px_per_mm,
            snapshot_every_s,
            marker_radius_px: 25.0,
        }
    }
}

impl RunFile {
    /// The run's statistics in the recorded arena.
    pub fn stats(&self, arena: &ArenaGeometry) -> PathStats {
        PathStats::of(&self.track, arena.size())
    }

    /// Median time between snapshots, s.
    pub fn snapshot_every_s(&self) -> f64 {
        let mut d: Vec<f64> = self
            .track
            .snapshots
            .windows(2)
            .map(|w| w[1].t_s - w[0].t_s)
            .collect();
        d.sort_by(f64::total_cmp);
        d.get(d.len() / 2).copied().unwrap_or(30.0)
    }
}

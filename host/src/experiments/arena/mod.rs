//! Experiment 4, `arena` (paper Sec. III-C, Figs. 5–6): a few robots run the same controller in
//! the walled arena for minutes; we count their encounters and collisions with each other and
//! with the wall, and the time each spends in each controller state.
//!
//! # Trials
//!
//! One trial is one (controller, background) pair: [`ArenaConfig::robots`] robots, all running
//! that controller, in the configuration's world ([`ArenaConfig::world`]: the recorded arena's
//! replica by default, or the `lab`) whose walls show that background
//! ([`BuiltinWorld::with_walls`]; by default the world's own), for [`ArenaConfig::minutes`] of
//! simulated time. Trials are independent and run in
//! parallel; each is a pure function of the configuration, so thread scheduling never changes a
//! number (only `wall_clock_s`).
//!
//! **Pairing.** Every trial of a run starts from the same robot poses ([`start_poses`], drawn
//! from the seed alone) and uses the same simulation seed (motor noise, gyro, camera noise) and
//! the same per-robot controller seeds (LGMD2's random escape turns). ALVS and LGMD2 therefore
//! meet the same initial situation on every background; they part ways only through what their
//! controllers do.
//!
//! **Start poses** are uniform in the arena at least [`START_WALL_CLEARANCE_MM`] from the walls
//! and obstacles ([`start_poses_among`]) and [`START_SEPARATION_MM`] from each other (centre to centre), with uniform headings: no
//! robot starts inside an encounter (more than two diameters from every other body).
//!
//! # Counting
//!
//! The counts are those of [`alvs_sim::contacts`] (collision: centre distance below one
//! diameter, 42 mm, for a robot pair and for a robot and the wall; encounter: bodies within two
//! diameters, surface to surface; success rate = encounters without a collision / encounters;
//! each counted once per episode). Collisions per minute are for the whole arena (all robots
//! together) per simulated minute. Aggregates over backgrounds pool the counts (sums), so an

//! aggregate success rate weighs each encounter equally.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use alvs_tasks::Params;
use anyhow::{ensure, Context, Result};
use serde::{Deserialize, Serialize};

use super::parallel;
use super::sweep::{self, Shard, Sweep};
use alvs_sim::canvas::{colour_cycle, Canvas, Rgb, BLACK, RED, WHITE};
use alvs_sim::contacts::{
    EPISODE_HYSTERESIS_MM, ROBOT_ENCOUNTER_DISTANCE_MM, WALL_ENCOUNTER_DISTANCE_MM,
};
use alvs_sim::encounter;
use alvs_sim::world::ROBOT_RADIUS_MM;
use alvs_sim::{
    frames_in, Arena, BuiltinWorld, EventKind, GyroParams, Kind, MotorParams, Obstacle, Other,
    Pose, Rng, SensorNoise, Sim, SimOptions, Tally, TopDown, WallTexture, World, FRAME_DT_S,
};

mod config;
mod pictures;
mod report;
mod results;
mod run;

pub use config::*;
pub use pictures::*;
use report::*;
pub use results::*;
pub use run::*;

/// The backgrounds of a default run in the `lab`: procedural clutter, vertical stripes and a
/// checkerboard (built in, so a default run needs no file).
pub const DEFAULT_BACKGROUNDS: [&str; 3] = alvs_sim::worlds::LAB_BACKGROUNDS;

/// The paper's success rates (Sec. III-C) for reference in reports.
pub const PAPER_SUCCESS_RATE: [(&str, f64); 2] = [("alvs", 0.961), ("lgmd2", 0.937)];

/// Smallest centre distance between two robots at the start, mm: outside a robot–robot
/// encounter (126 mm) with its hysteresis, i.e. more than two diameters apart.
pub const START_SEPARATION_MM: f64 = ROBOT_ENCOUNTER_DISTANCE_MM + EPISODE_HYSTERESIS_MM;

/// Smallest centre-to-wall distance at the start, mm: outside a robot–wall encounter (105 mm)
/// with its hysteresis.
pub const START_WALL_CLEARANCE_MM: f64 = WALL_ENCOUNTER_DISTANCE_MM + EPISODE_HYSTERESIS_MM;

/// Longest trial accepted, simulated minutes (a week of wall time at worst).
pub const MAX_MINUTES: f64 = 10_000.0;

/// Most lines a `--trace` may hold (robot-frames over all trials): ≈ 1.7 GB of memory and
/// file, 60 times the default run's 324,000.
pub const MAX_TRACE_LINES: u64 = 20_000_000;

/// Typical length of a trace line, bytes (for the messages).
const TRACE_LINE_BYTES: u64 = 85;

/// A robot whose body is within this of a wall (or an obstacle), mm, is pressed against it
/// (the physics keeps the centre exactly one radius from a wall it pushes).
pub const WALL_CONTACT_SLACK_MM: f64 = 1.0;

/// Camera frames between two progress reports of a trial (one simulated second).
const PROGRESS_EVERY: u64 = 30;

/// Random stream of the start poses (forked from the seed).
const START_STREAM: u64 = 0x57a7_1e55;
/// Random stream of the controllers' seeds (robot `i` takes sub-stream `i`).
const CONTROLLER_STREAM: u64 = 0xc0_7e01;

/// The paper's success rate for a controller, if it gives one.
pub fn paper_success_rate(controller: &str) -> Option<f64> {
    PAPER_SUCCESS_RATE
        .iter()
        .find(|(n, _)| *n == controller)
        .map(|(_, r)| *r)
}

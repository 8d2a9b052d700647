//! `alvs validate`: the simulator against the real recordings. It is not a sweep (one report
//! of runs and seeds, no shards), so it calls [`runner::whole`] itself; `--approaches` is a
//! table of its own.

use std::path::PathBuf;

use anyhow::Result;
use clap::ValueEnum;

use super::options::{CameraArgs, WorldArgs};
use super::runner::{self, Outputs};

#[derive(clap::Args)]
pub struct ValidateArgs {
    #[command(flatten)]
    world: WorldArgs,
    /// Seeds of the simulations (repeatable); one simulation per recorded run and seed.
    /// Default: 11, 12, 13 (report seeds: tuning uses 1-5).
    #[arg(long = "seed", value_name = "S")]
    seeds: Vec<u64>,
    /// Threads (default: all cores); results do not depend on it.
    #[arg(long, value_name = "J", default_value_t = 0)]
    jobs: usize,
    /// Write the results as JSON.
    #[arg(long, value_name = "PATH")]
    json: Option<PathBuf>,
    /// Where the pictures go.
    #[arg(long, value_name = "DIR", default_value = "out/validate")]
    png: PathBuf,
    /// Which recorded runs: all, the 10.9 cm/s calibration runs, or the held-out others.
    #[arg(long, value_enum, default_value = "all")]
    runs: RunsArg,
    /// Override the world's wheel slip against walls and obstacles (`SurfaceContact::
    /// slip_yaw`, a share of the blocked travel), to repeat its calibration (docs/world.md).
    #[arg(long, value_name = "K")]
    slip_yaw: Option<f64>,
    /// Override the world's wall texture (a `--background` form, e.g. ribs:5.6:120:230), to
    /// repeat the calibration of the walls' look (docs/world.md).
    #[arg(long, value_name = "SPEC")]
    walls: Option<String>,
    /// Override the texture of the room seen above the walls (a `--background` form, e.g.
    /// plain:120 or outdoor:1), to repeat the calibration of the room's look (docs/world.md).
    #[arg(long, value_name = "SPEC")]
    room: Option<String>,
    #[command(flatten)]
    camera: CameraArgs,
    /// Standard deviation of the camera's pitch jitter while the robot moves, degrees
    /// (`SensorNoise::shake_deg`).
    #[arg(long, value_name = "DEG", default_value_t = 0.0)]
    shake_deg: f32,
    /// Height of the simulated robot's camera above the floor, mm, to calibrate the mount
    /// (docs/world.md).
    #[arg(long, value_name = "MM", default_value_t = alvs_sim::render::CAMERA_HEIGHT_MM)]
    camera_height: f64,
    /// Pitch of the simulated robot's camera, degrees, positive = up.
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pitch: f64,
    /// A diagnostic, not the baseline: give the simulated LGMD2 robot a forward proximity
    /// sensor of this range (mm ahead of its front, ±30°) whose alert starts the same random
    /// turn, to test whether the real robots' bottom-board infrared explains their turns
    /// (docs/world.md, "What is left").
    #[arg(long, value_name = "MM")]
    proximity_mm: Option<f64>,
    /// Straight driving each turn costs the simulated robot, s: its cruise speed is the run's
    /// mean path speed / (1 − turns a second × this); 0 drives at the mean path speed.
    #[arg(long, value_name = "S", default_value_t = alvs_host::experiments::validate::TURN_COST_S)]
    turn_cost_s: f64,
    /// Instead of the runs: straight open-loop approaches to the wall at the recordings' mean
    /// speeds, and where the LGMD2 first alerts (docs/world.md, "What is left").
    #[arg(long)]
    approaches: bool,
}

/// Which recorded runs `validate` simulates.
#[derive(Clone, Copy, ValueEnum)]
enum RunsArg {
    All,
    Calibration,
    HeldOut,
}

/// Runs `alvs validate`: the world with the calibration's overrides, then the approaches' table
/// or the report of the runs.
pub fn run(a: ValidateArgs) -> Result<()> {
    use alvs_host::experiments::validate::{self, ValidateConfig};
    let builtin = a.world.builtin();
    let (mut world, world_label) = (builtin.world(), builtin.label());
    if let Some(k) = a.slip_yaw {
        if !(k.is_finite() && k >= 0.0) {
            anyhow::bail!("--slip-yaw {k}: must be a finite number >= 0");
        }
        world.contact.slip_yaw = k;
    }
    if let Some(spec) = &a.walls {
        world.texture = alvs_sim::WallTexture::from_spec(spec)?;
    }
    if let Some(spec) = &a.room {
        let Some(room) = world.room.as_mut() else {
            anyhow::bail!("--room: the {world_label} world has no room above its walls");
        };
        room.texture = alvs_sim::WallTexture::from_spec(spec)?;
    }
    let mount = alvs_sim::CameraMount {
        height_mm: a.camera_height,
        pitch_deg: a.pitch,
    };
    mount.check()?;
    if a.approaches {
        use alvs_host::experiments::validate::approach;
        let arena = alvs_host::recordings::arena()?;
        let runs = alvs_host::recordings::all_runs()?;
        let speeds: Vec<f64> = runs
            .iter()
            .map(|r| r.stats(&arena).mean_speed_mm_s.round())
            .collect();
        let angles: String = approach::ANGLES_DEG
            .iter()
            .map(|a| format!(" {a:.0}° |"))
            .collect();
        println!(
            "| run | speed mm/s | approaches | alerted before touching | median gap at the alert (mm) |{angles}"
        );
        println!(
            "|---|---|---|---|---|{}",
            "---|".repeat(approach::ANGLES_DEG.len())
        );
        for (run, r) in runs
            .iter()
            .zip(approach::approaches(&world, mount, &speeds))
        {
            let gap = r.median_gap_mm.map_or("-".into(), |g| format!("{g:.0}"));
            let per: String = r
                .alerted_by_angle
                .iter()
                .map(|k| format!(" {k}/{} |", approach::AIM_X_MM.len()))
                .collect();
            println!(
                "| {} | {:.0} | {} | {} | {gap} |{per}",
                run.run, r.speed_mm_s, r.approaches, r.alerted
            );
        }
        return Ok(());
    }
    let seeds = if a.seeds.is_empty() {
        vec![11, 12, 13]
    } else {
        a.seeds
    };
    let config = ValidateConfig {
        world,
        world_label: world_label.into(),
        seeds,
        jobs: a.jobs,
        runs: match a.runs {
            RunsArg::All => validate::RunSet::All,
            RunsArg::Calibration => validate::RunSet::Calibration,
            RunsArg::HeldOut => validate::RunSet::HeldOut,
        },
        noise: alvs_sim::SensorNoise {
            shake_deg: a.shake_deg,
            ..a.camera.gain.camera(a.camera.exposure)
        },
        mount,
        proximity_mm: a.proximity_mm,
        turn_cost_s: a.turn_cost_s,
    };
    if !(a.turn_cost_s.is_finite() && (0.0..=10.0).contains(&a.turn_cost_s)) {
        anyhow::bail!("--turn-cost-s {}: must be in [0, 10] s", a.turn_cost_s);
    }
    if let Some(r) = a.proximity_mm {
        if !(r.is_finite() && r > 0.0 && r <= 500.0) {
            anyhow::bail!("--proximity-mm {r}: must be in (0, 500] mm");
        }
    }
    if !(a.shake_deg.is_finite() && a.shake_deg >= 0.0) {
        anyhow::bail!("--shake-deg {}: must be a finite number >= 0", a.shake_deg);
    }
    let out = Outputs {
        png: &a.png,
        json: a.json.as_deref(),
        trace: None,
    };
    let total = (alvs_host::recordings::runs::RUNS.len() * config.seeds.len()) as u64;
    runner::whole("validate", total, &out, |progress| {
        validate::validate(&config, &|| progress(1))
    })
}

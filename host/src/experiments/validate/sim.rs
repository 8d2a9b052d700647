//! The simulated counterpart of a recorded run: one LGMD2 robot alone in a world, driving at
//! the recorded cruise speed, its path sampled as the overhead tracker samples the real one.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use alvs_tasks::model::fsm::{FsmParams, Motion};
use alvs_tasks::Frame;

use alvs_sim::controller::{Command, Controller, Lgmd2Controller};
use alvs_sim::lgmd2::Lgmd2Params;

use alvs_sim::world::ROBOT_RADIUS_MM;
use alvs_sim::{
    CameraMount, Kind, Pose, RenderOptions, Rng, SensorNoise, Sim, SimOptions, World, FRAME_DT_S,
};

/// A robot's centre counts as pressed against a surface within this gap of touching it, mm
/// (the same slack as the arena experiment's time at a wall).
pub const PRESSED_GAP_MM: f64 = 5.0;
/// Clearance of a start pose from every wall and obstacle, mm.
pub const START_CLEARANCE_MM: f64 = 100.0;

/// What one simulated run gives the statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct SimRun {
    /// The robot's centre every camera frame: (time s, x mm, y mm).
    pub trail: Vec<(f64, f64, f64)>,
    /// Share of frames the robot was pressed against a wall or obstacle.
    pub pressed_share: f64,
    /// Collision alerts (each starts a random turn).
    pub alerts: u64,
}

/// A start pose clear of the walls and obstacles, drawn from `seed`.
pub fn start_pose(world: &World, seed: u64) -> Pose {
    let mut rng = Rng::new(seed).fork(0x5747);
    let a = world.arena;
    for _ in 0..10_000 {
        let (x, y) = (rng.range(0.0, a.size_x_mm), rng.range(0.0, a.size_y_mm));
        let h = rng.range(-180.0, 180.0);
        if world.static_distance(x, y) >= START_CLEARANCE_MM {
            return Pose::new(x, y, h);
        }
    }
    let (x, y) = a.centre();
    Pose::new(x, y, 0.0)
}

/// Runs one LGMD2 robot (the paper's baseline, its published parameters) for `seconds` at
/// `speed_mm_s` in `world`, with realistic motor and gyro noise and the camera's `noise`
/// (e.g. [`SensorNoise::typical`] with an exposure or a shake), its camera at `mount`.
pub fn simulate(
    world: &World,
    speed_mm_s: f32,
    seconds: f64,
    seed: u64,
    noise: SensorNoise,
    mount: CameraMount,
    proximity_mm: Option<f64>,
) -> SimRun {
    let fsm = FsmParams {
        motion: Motion {
            cruise_mm_s: speed_mm_s,
            ..FsmParams::PAPER.motion
        },
        ..FsmParams::PAPER
    };
    let (motor, gyro, _) = alvs_sim::robot_noise(true);
    let options = SimOptions {
        render: RenderOptions {
            mount,
            ..RenderOptions::default()
        },
        ..SimOptions::default()
    };
    let mut sim = Sim::with_options(world, seed, &options);
    let controller_seed = Rng::new(seed).fork(0x1a9d).next_u64();
    let near = Arc::new(AtomicBool::new(false));
    let controller: Box<dyn Controller> = match proximity_mm {
        None => Kind::Lgmd2.make(alvs_tasks::Params::PAPER, fsm, controller_seed),
        Some(_) => Box::new(WithProximity {
            inner: Lgmd2Controller::new(Lgmd2Params::default(), fsm, controller_seed),
            near: near.clone(),
        }),
    };
    sim.add(start_pose(world, seed), controller, motor, gyro, noise);
    let frames = (seconds / FRAME_DT_S).round() as u64;
    let mut trail = Vec::with_capacity(frames as usize + 1);
    let p0 = sim.physics.poses()[0];
    trail.push((0.0, p0.x_mm, p0.y_mm));
    let (mut pressed, mut alerts) = (0u64, 0u64);
    let mut state = "";
    for f in 1..=frames {
        if let Some(range) = proximity_mm {
            let p = sim.physics.poses()[0];
            near.store(surface_ahead(world, p, range), Ordering::Relaxed);
        }
        sim.step();
        let now = sim.commands()[0].state;
        alerts += u64::from(now == "long_takeoff" && state != "long_takeoff");
        state = now;
        let p = sim.physics.poses()[0];
        trail.push((f as f64 * FRAME_DT_S, p.x_mm, p.y_mm));
        if world.static_distance(p.x_mm, p.y_mm) < ROBOT_RADIUS_MM + PRESSED_GAP_MM {
            pressed += 1;
        }
    }
    SimRun {
        trail,
        pressed_share: pressed as f64 / frames.max(1) as f64,
        alerts,
    }
}

/// Half-width of a forward proximity sensor's cone, degrees.
const PROXIMITY_HALF_CONE_DEG: f64 = 30.0;

/// Whether a wall or obstacle lies within `range_mm` of the body's front inside the cone.
fn surface_ahead(world: &World, p: Pose, range_mm: f64) -> bool {
    (-3..=3).any(|k| {
        let a = (p.heading_deg + PROXIMITY_HALF_CONE_DEG * f64::from(k) / 3.0).to_radians();
        let (dx, dy) = (a.cos(), a.sin());
        let mut s = ROBOT_RADIUS_MM;
        while s <= ROBOT_RADIUS_MM + range_mm {
            if world.static_distance(p.x_mm + s * dx, p.y_mm + s * dy) <= 0.5 {
                return true;
            }
            s += 2.0;
        }
        false
    })
}

/// The LGMD2 robot with a forward proximity sensor whose alert starts the same turn (the
/// diagnostic of `cargo alvs validate --proximity-mm`).
struct WithProximity {
    inner: Lgmd2Controller,
    near: Arc<AtomicBool>,
}

impl Controller for WithProximity {
    fn name(&self) -> &'static str {
        "lgmd2+proximity"
    }

    fn step(&mut self, frame: &Frame, heading_deg: f32) -> Command {
        let near = self.near.load(Ordering::Relaxed);
        self.inner.step_with(frame, heading_deg, near)
    }
}

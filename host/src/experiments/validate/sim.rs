//! The simulated counterpart of a recorded run: one LGMD2 robot alone in a world, driving at
//! the recorded cruise speed, its path sampled as the overhead tracker samples the real one.

use alvs_tasks::model::fsm::FsmParams;

use crate::arena::world::ROBOT_RADIUS_MM;
use crate::arena::{Kind, Pose, Rng, SensorNoise, Sim, World, FRAME_DT_S};

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
/// (e.g. [`SensorNoise::typical`] with an exposure or a shake).
pub fn simulate(
    world: &World,
    speed_mm_s: f32,
    seconds: f64,
    seed: u64,
    noise: SensorNoise,
) -> SimRun {
    let fsm = FsmParams {
        cruise_mm_s: speed_mm_s,
        ..FsmParams::PAPER
    };
    let (motor, gyro, _) = crate::arena::robot_noise(true);
    let mut sim = Sim::new(world, seed);
    let controller_seed = Rng::new(seed).fork(0x1a9d).next_u64();
    sim.add(
        start_pose(world, seed),
        Kind::Lgmd2.make(alvs_tasks::Params::PAPER, fsm, controller_seed),
        motor,
        gyro,
        noise,
    );
    let frames = (seconds / FRAME_DT_S).round() as u64;
    let mut trail = Vec::with_capacity(frames as usize + 1);
    let p0 = sim.physics.poses()[0];
    trail.push((0.0, p0.x_mm, p0.y_mm));
    let (mut pressed, mut alerts) = (0u64, 0u64);
    let mut state = "";
    for f in 1..=frames {
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

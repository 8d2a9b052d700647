//! The closed loop: every camera frame, each robot's camera renders the arena from its pose, its
//! controller (the firmware's task code for ALVS) turns frame and gyro heading into wheel speeds,
//! and the physics advances all robots together at its finer step.

use std::collections::BTreeMap;

use alvs_tasks::{Frame, PIXELS};

use crate::arena::controller::{Command, Controller};
use crate::arena::gyro::GyroParams;
use crate::arena::kinematics::MotorParams;
use crate::arena::physics::Physics;
use crate::arena::render::{Camera, Renderer, SensorNoise};
use crate::arena::world::{Pose, World};

/// Camera frames between two trail samples (5 per second).
pub const TRAIL_EVERY: u64 = 6;

/// One robot's brain and eye.
struct Robot {
    controller: Box<dyn Controller>,
    camera: Camera,
}

/// Robots, arena and physics, stepped one camera frame at a time.
pub struct Sim {
    /// Bodies, motors, gyros, contacts.
    pub physics: Physics,
    renderer: Renderer,
    robots: Vec<Robot>,
    frame: Frame,
    frames: u64,
    /// The bodies one frame period ago (the start of the exposures).
    before: Vec<Pose>,
    last: Vec<Command>,
    state_frames: Vec<BTreeMap<&'static str, u64>>,
    trails: Vec<Vec<(f64, f64)>>,
    seed: u64,
}

impl Sim {
    /// An empty arena; `seed` drives every random choice of the run.
    pub fn new(world: &World, seed: u64) -> Self {
        Sim {
            physics: Physics::of_world(world, seed),
            renderer: Renderer::new(world),
            robots: Vec::new(),
            frame: [0; PIXELS],
            frames: 0,
            before: Vec::new(),
            last: Vec::new(),
            state_frames: Vec::new(),
            trails: Vec::new(),
            seed,
        }
    }

    /// Adds a robot; returns its index.
    pub fn add(
        &mut self,
        pose: Pose,
        controller: Box<dyn Controller>,
        motor: MotorParams,
        gyro: GyroParams,
        noise: SensorNoise,
    ) -> usize {
        let i = self.physics.add_robot(pose, motor, gyro);
        let cam_seed = self.seed ^ (0x9e37_79b9_7f4a_7c15u64.wrapping_mul(i as u64 + 1));
        self.robots.push(Robot {
            controller,
            camera: Camera::new(noise, cam_seed),
        });
        self.before.push(pose);
        self.last.push(Command::default());
        self.state_frames.push(BTreeMap::new());
        self.trails.push(vec![(pose.x_mm, pose.y_mm)]);
        i
    }

    /// One camera frame for every robot, then the physics of that frame. `see` is called with
    /// each robot's index, its frame and its command (for pictures and per-frame records); a
    /// blind controller's ([`Controller::sees`]) frame is not rendered (it is whatever the
    /// previous robot saw).
    pub fn step_with(&mut self, mut see: impl FnMut(usize, &Frame, &Command)) {
        for (i, robot) in self.robots.iter_mut().enumerate() {
            if robot.controller.sees() {
                robot.camera.capture_moving(
                    &self.renderer,
                    &self.before,
                    self.physics.poses(),
                    i,
                    &mut self.frame,
                );
            }
            let heading = self.physics.gyro(i).heading() as f32;
            let cmd = robot.controller.step(&self.frame, heading);
            see(i, &self.frame, &cmd);
            *self.state_frames[i].entry(cmd.state).or_insert(0) += 1;
            self.last[i] = cmd;
        }
        for (i, cmd) in self.last.iter().enumerate() {
            self.physics
                .set_wheels(i, f64::from(cmd.left_mm_s), f64::from(cmd.right_mm_s));
        }
        self.before.clear();
        self.before.extend_from_slice(self.physics.poses());
        self.physics.step_frame();
        self.frames += 1;
        if self.frames.is_multiple_of(TRAIL_EVERY) {
            for (trail, p) in self.trails.iter_mut().zip(self.physics.poses()) {
                trail.push((p.x_mm, p.y_mm));
            }
        }
    }

    /// One camera frame for every robot.
    pub fn step(&mut self) {
        self.step_with(|_, _, _| {});
    }

    /// Camera frames simulated so far.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// The commands of the last frame.
    pub fn commands(&self) -> &[Command] {
        &self.last
    }

    /// Frames each robot spent in each controller state.
    pub fn state_frames(&self) -> &[BTreeMap<&'static str, u64>] {
        &self.state_frames
    }

    /// Each robot's positions, sampled every [`TRAIL_EVERY`] frames.
    pub fn trails(&self) -> &[Vec<(f64, f64)>] {
        &self.trails
    }

    /// The controller of robot `i`.
    pub fn controller(&self, i: usize) -> &dyn Controller {
        self.robots[i].controller.as_ref()
    }

    /// The renderer (for extra pictures).
    pub fn renderer(&self) -> &Renderer {
        &self.renderer
    }
}

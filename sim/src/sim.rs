//! The closed loop: every camera frame, each robot's camera renders the arena from its pose, its
//! controller (the firmware's task code for ALVS) turns frame and gyro heading into wheel speeds,
//! and the physics advances all robots together at its finer step.
//!
//! [`SimOptions`] perturb the loop for the robustness suite (docs/robustness.md): the camera's
//! mount, a floor pattern and lighting ([`RenderOptions`]), the firmware's odometry in place of
//! the gyro ([`HeadingSource`]) and lost camera frames ([`SimOptions::frame_loss`]). The
//! default is the loop every other experiment runs.

use std::collections::BTreeMap;

use alvs_tasks::model::fsm::{HeadingEstimator, Odometry};
use alvs_tasks::{Frame, PIXELS};

use crate::controller::{Command, Controller};
use crate::gyro::GyroParams;
use crate::kinematics::MotorParams;
use crate::kinematics::FRAME_DT_S;
use crate::physics::Physics;
use crate::render::{Camera, RenderOptions, Renderer, SensorNoise};
use crate::rng::Rng;
use crate::world::{Pose, World};

/// Camera frames between two trail samples (5 per second).
pub const TRAIL_EVERY: u64 = 6;

/// Random stream of the lost frames (robot `i` takes sub-stream `i`).
const FRAME_LOSS_STREAM: u64 = 0xf7a3_e105;

/// Where each robot's controller gets its heading.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HeadingSource {
    /// The simulated gyro ([`super::gyro`], the MPU9250 of the 2025 Colias firmware): the
    /// body's actual rotation, contact turns included, with the gyro's own errors.
    #[default]
    Gyro,
    /// The firmware's heading as it stands (`robot::control::Control` with
    /// `model::fsm::Odometry`, until the IMU is wired): the commanded wheel speeds integrated
    /// over one frame period per processed frame. Blind to wheel slip, contact turns, motor
    /// errors and asymmetry, and to the time a lost frame's command ran on.
    Odometry,
}

impl HeadingSource {
    /// Robot `i`'s heading from this source, degrees.
    fn read(self, physics: &Physics, i: usize, odometry: &Odometry) -> f32 {
        match self {
            HeadingSource::Gyro => physics.gyro(i).heading() as f32,
            HeadingSource::Odometry => odometry.heading_deg(),
        }
    }
}

/// How the closed loop differs from the ideal one (the robustness suite's perturbations of
/// the camera and the firmware); the default is every other experiment's loop.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SimOptions {
    /// The camera's mount, a floor pattern, a lighting gradient.
    pub render: RenderOptions,
    /// The controllers' heading.
    pub heading: HeadingSource,
    /// Chance that a camera frame following a processed one is lost, as the firmware loses a
    /// frame that begins while perception still runs (`robot::camera::Capture`'s drop):
    /// perception and motor control skip it whole, the bottom board keeps driving the last
    /// wheel powers, the odometry does not advance, and the next frame's `P(t−1)` is the frame
    /// before the lost one. A lost frame gives perception a whole extra period, so the next
    /// frame is never lost (and the firmware's 100 ms stall rule never trips). `None`: no frame
    /// is lost.
    pub frame_loss: Option<f64>,
}

/// One robot's brain and eye.
struct Robot {
    controller: Box<dyn Controller>,
    camera: Camera,
    /// The firmware's odometry, fed the commands (read with [`HeadingSource::Odometry`]).
    odometry: Odometry,
    /// Draws of the lost frames (with [`SimOptions::frame_loss`]).
    losses: Rng,
    /// The last frame was processed (only a frame after a processed one can be lost; the first
    /// is never).
    processed_last: bool,
    /// Frames lost so far.
    lost: u64,
}

impl Robot {
    /// Whether this frame is lost (see [`SimOptions::frame_loss`]).
    fn loses_frame(&mut self, frame_loss: Option<f64>) -> bool {
        let lost = match frame_loss {
            Some(p) if self.processed_last => self.losses.uniform() < p,
            _ => false,
        };
        self.processed_last = !lost;
        self.lost += u64::from(lost);
        lost
    }
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
    options: SimOptions,
}

impl Sim {
    /// An empty arena; `seed` drives every random choice of the run.
    pub fn new(world: &World, seed: u64) -> Self {
        Sim::with_options(world, seed, &SimOptions::default())
    }

    /// An empty arena whose loop differs from the ideal one as `options` say (unchecked: see
    /// [`RenderOptions::check`]).
    pub fn with_options(world: &World, seed: u64, options: &SimOptions) -> Self {
        Sim {
            physics: Physics::of_world(world, seed),
            renderer: Renderer::with_options(world, &options.render),
            robots: Vec::new(),
            frame: [0; PIXELS],
            frames: 0,
            before: Vec::new(),
            last: Vec::new(),
            state_frames: Vec::new(),
            trails: Vec::new(),
            seed,
            options: *options,
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
            odometry: Odometry::new(motor.track_mm as f32, pose.heading_deg as f32),
            losses: Rng::new(self.seed).fork(FRAME_LOSS_STREAM).fork(i as u64),
            processed_last: false,
            lost: 0,
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
    /// previous robot saw). A robot whose frame is lost ([`SimOptions::frame_loss`]) is not
    /// stepped nor seen: its wheels keep the last command, which also counts for its state.
    pub fn step_with(&mut self, mut see: impl FnMut(usize, &Frame, &Command)) {
        for (i, robot) in self.robots.iter_mut().enumerate() {
            if robot.loses_frame(self.options.frame_loss) {
                *self.state_frames[i].entry(self.last[i].state).or_insert(0) += 1;
                continue;
            }
            if robot.controller.sees() {
                robot.camera.capture_moving(
                    &self.renderer,
                    &self.before,
                    self.physics.poses(),
                    i,
                    &mut self.frame,
                );
            }
            let heading = self.options.heading.read(&self.physics, i, &robot.odometry);
            let cmd = robot.controller.step(&self.frame, heading);
            // as the firmware's motor control: the heading advances with the command just given
            robot
                .odometry
                .update(cmd.left_mm_s, cmd.right_mm_s, FRAME_DT_S as f32);
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

    /// The heading robot `i`'s controller is given next, degrees ([`SimOptions::heading`]).
    pub fn heading_estimate(&self, i: usize) -> f32 {
        self.options
            .heading
            .read(&self.physics, i, &self.robots[i].odometry)
    }

    /// The firmware odometry's heading of robot `i`, degrees (whatever the heading source).
    pub fn odometry_heading(&self, i: usize) -> f32 {
        self.robots[i].odometry.heading_deg()
    }

    /// Camera frames robot `i` lost so far ([`SimOptions::frame_loss`]).
    pub fn frames_lost(&self, i: usize) -> u64 {
        self.robots[i].lost
    }

    /// The loop's options.
    pub fn options(&self) -> &SimOptions {
        &self.options
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

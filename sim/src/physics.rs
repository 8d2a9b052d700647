//! The moving part of a simulation: every robot's pose, motors and gyro, stepped together with
//! the contacts between them (see `kinematics`, `gyro`, `contacts` for the models).
//!
//! A physics step is: each robot's motors respond to its command and move it; its gyro senses
//! the rotation; the contact tracker counts on the moved (possibly overlapping) bodies; then
//! overlaps are resolved. [`Physics::step_frame`] takes the [`PHYSICS_SUBSTEPS`] steps of one
//! camera frame with the commands held, as the firmware holds its wheel powers between frames.
//!
//! Each robot draws its noise from streams forked from the seed by its index, so a run is
//! reproducible and a robot's noise does not depend on how many others there are.

use alvs_tasks::model::fsm::MotorCommand;

use super::contacts::{resolve_overlaps, ContactCounts, ContactTracker, SurfaceContact};
use super::gyro::{GyroParams, SimGyro};
use super::kinematics::{advance, body_rates, Drive, MotorParams, PHYSICS_DT_S, PHYSICS_SUBSTEPS};
use super::rng::Rng;
use super::world::{wrap_deg, Arena, Obstacle, Pose, World};

/// Stream of the contacts' noise, forked from the seed (robots use 0, 1, 2, ...).
const CONTACT_STREAM: u64 = 0xC0_47AC7;

/// Robots in an arena, their motors, gyros and contacts.
#[derive(Debug, Clone)]
pub struct Physics {
    arena: Arena,
    obstacles: Vec<Obstacle>,
    contact: SurfaceContact,
    rng: Rng,
    /// The contacts' own stream (wheel slip against walls and obstacles).
    contact_rng: Rng,
    poses: Vec<Pose>,
    drives: Vec<Drive>,
    gyros: Vec<SimGyro>,
    contacts: ContactTracker,
    steps: u64,
    /// Per robot this step: the wheels' yaw rate and the heading before contacts (kept to
    /// avoid allocating every step).
    turning: Vec<(f64, f64)>,
}

impl Physics {
    /// An empty arena without obstacles, its walls rigid ([`SurfaceContact::RIGID`]); `seed`
    /// determines every robot's noise.
    pub fn new(arena: Arena, seed: u64) -> Self {
        Physics {
            arena,
            obstacles: Vec::new(),
            contact: SurfaceContact::RIGID,
            rng: Rng::new(seed),
            contact_rng: Rng::new(seed).fork(CONTACT_STREAM),
            poses: Vec::new(),
            drives: Vec::new(),
            gyros: Vec::new(),
            contacts: ContactTracker::new(),
            steps: 0,
            turning: Vec::new(),
        }
    }

    /// The moving part of `world`: its arena, obstacles and contact model, no robots yet.
    pub fn of_world(world: &World, seed: u64) -> Self {
        Physics {
            obstacles: world.obstacles.clone(),
            contact: world.contact,
            ..Physics::new(world.arena, seed)
        }
    }

    /// The static cylinders robots cannot enter.
    pub fn obstacles(&self) -> &[Obstacle] {
        &self.obstacles
    }

    /// Adds a stopped robot at `pose`; returns its index.
    pub fn add_robot(&mut self, pose: Pose, motor: MotorParams, gyro: GyroParams) -> usize {
        let i = self.poses.len() as u64;
        self.poses.push(pose);
        self.drives.push(Drive::new(motor, self.rng.fork(2 * i)));
        self.gyros.push(SimGyro::new(
            gyro,
            pose.heading_deg,
            self.rng.fork(2 * i + 1),
        ));
        self.poses.len() - 1
    }

    /// The arena.
    pub fn arena(&self) -> &Arena {
        &self.arena
    }

    /// Number of robots.
    pub fn len(&self) -> usize {
        self.poses.len()
    }

    /// No robots yet.
    pub fn is_empty(&self) -> bool {
        self.poses.is_empty()
    }

    /// Every robot's pose (what the cameras render).
    pub fn poses(&self) -> &[Pose] {
        &self.poses
    }

    /// Moves robot `i` to `pose` (scripted motion); its gyro is not told.
    pub fn set_pose(&mut self, i: usize, pose: Pose) {
        self.poses[i] = pose;
    }

    /// Sets robot `i`'s wheel commands, mm/s, until the next call.
    pub fn set_wheels(&mut self, i: usize, left_mm_s: f64, right_mm_s: f64) {
        self.drives[i].command(left_mm_s, right_mm_s);
    }

    /// Sets robot `i`'s wheel commands from the FSM's output.
    pub fn command(&mut self, i: usize, cmd: &MotorCommand) {
        self.set_wheels(i, f64::from(cmd.left_mm_s), f64::from(cmd.right_mm_s));
    }

    /// Robot `i`'s motors.
    pub fn drive(&self, i: usize) -> &Drive {
        &self.drives[i]
    }

    /// Robot `i`'s gyro.
    pub fn gyro(&self, i: usize) -> &SimGyro {
        &self.gyros[i]
    }

    /// Robot `i`'s gyro, to call `HeadingEstimator::update` on.
    pub fn gyro_mut(&mut self, i: usize) -> &mut SimGyro {
        &mut self.gyros[i]
    }

    /// The contact tracker.
    pub fn contacts(&self) -> &ContactTracker {
        &self.contacts
    }

    /// The counts so far.
    pub fn counts(&self) -> ContactCounts {
        self.contacts.counts()
    }

    /// Simulated time, s.
    pub fn time_s(&self) -> f64 {
        self.steps as f64 * PHYSICS_DT_S
    }

    /// One physics step of [`PHYSICS_DT_S`]. Each gyro senses its body's rotation: the
    /// wheels' and the turn a contact with a wall or obstacle gave it.
    pub fn step(&mut self) {
        let dt = PHYSICS_DT_S;
        self.turning.clear();
        for (pose, drive) in self.poses.iter_mut().zip(&mut self.drives) {
            let (l, r) = drive.step(dt);
            let (v, omega) = body_rates(l, r, drive.params().track_mm);
            advance(pose, v, omega, dt);
            self.turning.push((omega, pose.heading_deg));
        }
        self.steps += 1;
        self.contacts
            .observe(self.time_s(), &self.arena, &self.obstacles, &self.poses);
        resolve_overlaps(
            &self.arena,
            &self.obstacles,
            self.contact,
            &mut self.contact_rng,
            &mut self.poses,
        );
        for ((gyro, &(omega, before)), pose) in
            self.gyros.iter_mut().zip(&self.turning).zip(&self.poses)
        {
            let contact_turn = wrap_deg(pose.heading_deg - before).to_radians();
            gyro.sense(omega + contact_turn / dt, dt);
        }
    }

    /// The [`PHYSICS_SUBSTEPS`] steps of one camera frame.
    pub fn step_frame(&mut self) {
        for _ in 0..PHYSICS_SUBSTEPS {
            self.step();
        }
    }
}

//! The simulated Colias world, shared by the host tools (`alvs-host`: the experiments) and the
//! virtual board (`alvs-cycles`: the firmware in closed loop): simulated Colias robots whose
//! cameras see a rendered arena, so that the firmware's own task code (`alvs_tasks`) can drive
//! them in closed loop. Everything here is a pure function of its seed.
//!
//! | concern | module |
//! |---|---|
//! | arena, walls, textures, robot bodies, poses and the frame convention | [`world`] |
//! | wall textures as mip-mapped look-up tables; `--background` specifications | [`texture`] |
//! | each robot's front camera (99x72, 70°, pinhole), its mount, noise | [`render`] |
//! | the sensor's automatic exposure and gain; the camera's gain models | [`aec`] |
//! | a pattern fixed to the floor (textured and shaded floors) | [`floor_pattern`] |
//! | uneven light across the arena | [`lighting`] |
//! | the replica of the recorded arena of Fu et al. 2019 | [`replica`] |
//! | top-down pictures for trajectory plots | [`topdown`] |
//! | differential drive, motor lag and noise, time steps | [`kinematics`] |
//! | simulated gyro behind `HeadingEstimator` | [`gyro`] |
//! | overlap resolution, collision and encounter counting | [`contacts`] |
//! | all robots stepped together | [`physics`] |
//! | seeded random numbers | [`rng`] |
//! | the controllers (ALVS, swarm, LGMD2, scripted) behind one trait | [`controller`] |
//! | the LGMD2 baseline, one module per layer (docs/lgmd2.md) | [`lgmd2`] |
//! | the closed loop: render, control, physics per camera frame | [`sim`] |
//! | the built-in worlds a command names (`--world`) | [`worlds`] |
//! | where a staged experiment stands in a world | [`stage`] |
//! | the open-loop encounter of experiments 2 and 3 (obstacles driving at a robot) | [`encounter`] |
//! | pictures: a canvas, charts and labels | [`canvas`] |
//!
//! A closed-loop frame of robot `i` is: `Camera::capture` its frame from `Physics::poses`, run
//! the perception on it, `Physics::gyro_mut(i).update(..)` for the heading, `Fsm::step`,
//! `Physics::command(i, &cmd)`; once every robot has its command, `Physics::step_frame`.

pub mod aec;
pub mod canvas;
pub mod contacts;
pub mod controller;
pub mod encounter;
pub mod floor_pattern;
pub mod gyro;
pub mod kinematics;
pub mod lgmd2;
pub mod lighting;
pub mod physics;
pub mod render;
pub mod replica;
pub mod rng;
pub mod sim;
pub mod stage;
pub mod texture;
pub mod topdown;
pub mod world;
pub mod worlds;

pub use aec::{Aec, GainModel};
pub use contacts::{
    ContactCounts, ContactEvent, ContactTracker, EventKind, Other, SurfaceContact, Tally,
};
pub use controller::{Command, Controller, Kind, Seen};
pub use floor_pattern::FloorPattern;
pub use gyro::{GyroParams, SimGyro};
pub use kinematics::{
    frames_in, MotorParams, FRAME_DT_S, PHYSICS_DT_S, PHYSICS_SUBSTEPS, TRACK_MM,
};
pub use lighting::LightGradient;
pub use physics::Physics;
pub use render::{Camera, CameraMount, RenderOptions, Renderer, SensorNoise};
pub use rng::Rng;
pub use sim::{HeadingSource, Sim, SimOptions};
pub use topdown::TopDown;
pub use world::{
    Arena, FloorShade, GreyImage, Obstacle, Pose, RobotPattern, Room, WallTexture, World,
};
pub use worlds::BuiltinWorld;

/// A robot's motors, gyro and camera noise: realistic (default motor lag and noise, default
/// gyro drift, [`SensorNoise::typical`]) or, with `realistic` false, ideal.
pub fn robot_noise(realistic: bool) -> (MotorParams, GyroParams, SensorNoise) {
    if realistic {
        (
            MotorParams::default(),
            GyroParams::default(),
            SensorNoise::typical(),
        )
    } else {
        (
            MotorParams::ideal(),
            GyroParams::ideal(),
            SensorNoise::default(),
        )
    }
}

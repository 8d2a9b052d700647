//! The robustness suite (`cargo alvs robustness`, docs/robustness.md): each perturbation of the
//! world, the camera, the motors or the loop changes what it should, and with every perturbation
//! off the simulator is bit for bit what it was before they existed.
//!
//! `cargo test --target host-tuple -p alvs-host --test robustness`.

use alvs_host::arena::*;
use alvs_tasks::model::fsm::FsmParams;
use alvs_tasks::Params;

/// FNV-1a, 64 bits: a digest that is the same on every platform and Rust release (std's
/// `DefaultHasher` promises neither).
fn fnv(bytes: impl IntoIterator<Item = u8>) -> u64 {
    bytes.into_iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

fn pose_bytes(p: &Pose) -> impl Iterator<Item = u8> {
    [p.x_mm, p.y_mm, p.heading_deg]
        .into_iter()
        .flat_map(f64::to_le_bytes)
}

/// Three robots (ALVS, the paper's model, LGMD2) for 90 frames with every noise on, the camera
/// exposing half the frame: a digest of every frame they saw, every command and the final
/// poses and gyro headings.
fn closed_loop_digest(world: &World) -> u64 {
    let mut sim = Sim::new(world, 7);
    let (motor, gyro, mut noise) = robot_noise(true);
    noise.exposure = 0.5;
    let c = world.arena.centre();
    let robots = [
        (
            Kind::Alvs,
            Params::ALVS,
            FsmParams::ALVS,
            -250.0,
            -120.0,
            20.0,
        ),
        (
            Kind::Alvs,
            Params::PAPER,
            FsmParams::PAPER,
            200.0,
            60.0,
            170.0,
        ),
        (
            Kind::Lgmd2,
            Params::ALVS,
            FsmParams::ALVS,
            -40.0,
            200.0,
            -80.0,
        ),
    ];
    for (k, (kind, params, fsm, dx, dy, h)) in robots.into_iter().enumerate() {
        sim.add(
            Pose::new(c.0 + dx, c.1 + dy, h),
            kind.make(params, fsm, 100 + k as u64),
            motor,
            gyro,
            noise,
        );
    }
    let mut bytes = Vec::new();
    for _ in 0..90 {
        sim.step_with(|i, frame, cmd| {
            bytes.push(i as u8);
            bytes.extend_from_slice(frame);
            bytes.extend_from_slice(&cmd.left_mm_s.to_le_bytes());
            bytes.extend_from_slice(&cmd.right_mm_s.to_le_bytes());
            bytes.extend_from_slice(cmd.state.as_bytes());
        });
    }
    for (i, p) in sim.physics.poses().iter().enumerate() {
        bytes.extend(pose_bytes(p));
        bytes.extend_from_slice(&sim.physics.gyro(i).heading().to_le_bytes());
    }
    fnv(bytes)
}

/// Ideal frames from a few poses (near a wall, among obstacles, in a corner): a digest.
fn frames_digest(world: &World) -> u64 {
    let r = Renderer::new(world);
    let a = world.arena;
    let bodies = [
        Pose::new(a.size_x_mm * 0.3, a.size_y_mm * 0.5, 10.0),
        Pose::new(a.size_x_mm * 0.5, a.size_y_mm * 0.45, 200.0),
        Pose::new(60.0, 60.0, -135.0),
        Pose::new(a.size_x_mm - 80.0, a.size_y_mm * 0.5, 5.0),
    ];
    let mut bytes = Vec::new();
    for viewer in 0..bodies.len() {
        bytes.extend_from_slice(&r.render(&bodies, viewer));
    }
    fnv(bytes)
}

/// With every perturbation off, the renderer, the physics and the closed loop give exactly what
/// they gave before the perturbations existed (digests recorded on that code, commit 92d0d27).
#[test]
fn defaults_are_bit_identical_to_before_the_perturbations() {
    let lab = World::default();
    let fu = replica::world();
    let got = [
        frames_digest(&lab),
        frames_digest(&fu),
        closed_loop_digest(&lab),
        closed_loop_digest(&fu),
    ];
    let want = [
        0xa9c5_e65f_ef6f_651b,
        0xe3b0_0816_bbe3_9c30,
        0x5d03_5b9c_ed9c_6f66,
        0xa743_ba80_084a_c4ae,
    ];
    assert_eq!(
        got, want,
        "lab frames, fu2019 frames, lab loop, fu2019 loop"
    );
}

//! The robustness suite (`cargo alvs robustness`, docs/robustness.md): each perturbation of the
//! world, the camera, the motors or the loop changes what it should, and with every perturbation
//! off the simulator is bit for bit what it was before they existed.
//!
//! `cargo test --target host-tuple -p alvs-host --test robustness`.

use alvs_sim::*;
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
/// they gave before the perturbations existed (digests recorded on that code: `lab` at commit
/// 92d0d27; `fu2019` after the replica's calibration, commit fdc03cc, which moved two obstacles
/// and added the wheels' slip). The two loop digests were recorded again when the default
/// controller changed (issue 30: brisk takeoff turns, the floor line's covered foot); the frame
/// digests, which hold the world, did not change. The fu2019 loop again for the default
/// re-judged on the held-out seeds (issue 30: the options that did not earn their place off,
/// the floor line's path the body's width), and both loops when the worlds' camera became the
/// real clips' (a 0.3 % gain draw every frame instead of 2 %; the ideal frames held).
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
        0x156a_65f2_a5c3_7264,
        0x5d06_00ef_1d13_3573,
        0x40a0_a815_df7f_97e0,
    ];
    assert_eq!(
        got, want,
        "lab frames, fu2019 frames, lab loop, fu2019 loop"
    );
}

// ---------------------------------------------------------------------------------------------
// The camera's mount, the floor and the light.

use alvs_sim::render::{CAMERA_FORWARD_MM, FOCAL_PX, SKY_GREY};
use alvs_tasks::{Frame, HEIGHT, WIDTH};

/// Grey of the plain walls and of the plain floor in the picture tests.
const WALL: f64 = 40.0;
const FLOOR: f64 = 120.0;

/// A 60 mm plain wall and a plain floor: every edge in the picture is a wall's top or base.
fn plain_world() -> World {
    World {
        texture: WallTexture::Plain(WALL as u8),
        wall_height_mm: 60.0,
        floor: FloorShade {
            near_grey: FLOOR as f32,
            far_grey: FLOOR as f32,
        },
        ..World::default()
    }
}

/// Facing the `y = 0` wall (fully lit) square on, 300 mm from it.
fn facing_the_wall() -> Pose {
    Pose::new(600.0, 300.0, -90.0)
}

/// The rows of the wall's top and base edges in column `c`, to a fraction of a row, from the
/// anti-aliased rows: the sky's share of the rows above the wall and the floor's below it.
fn wall_edges(f: &Frame, c: usize) -> (f64, f64) {
    let g = |y: usize| f64::from(f[y * WIDTH + c]);
    let sky: f64 = (0..HEIGHT / 2)
        .map(|y| ((g(y) - WALL) / (f64::from(SKY_GREY) - WALL)).clamp(0.0, 1.0))
        .sum();
    let floor: f64 = (HEIGHT / 2..HEIGHT)
        .map(|y| ((g(y) - WALL) / (FLOOR - WALL)).clamp(0.0, 1.0))
        .sum();
    (sky - 0.5, HEIGHT as f64 - 0.5 - floor)
}

/// Raising or lowering the camera moves a wall's base by `f·Δh/s` and its top by the same the
/// other way; pitching it up by `p` moves both down by `f·tan p` (2.44 rows for 2°): the
/// edges land where [`CameraMount::row_of_height`] says, in every column.
#[test]
fn camera_height_and_pitch_move_the_wall_edges_to_the_pinhole_rows() {
    let world = plain_world();
    let s = 300.0 - CAMERA_FORWARD_MM;
    let mut tops = Vec::new();
    for (height_mm, pitch_deg) in [
        (20.0, 0.0),
        (25.0, 0.0),
        (15.0, 0.0),
        (20.0, 2.0),
        (20.0, -2.0),
    ] {
        let mount = CameraMount {
            height_mm,
            pitch_deg,
        };
        let r = Renderer::with_options(
            &world,
            &RenderOptions {
                mount,
                ..RenderOptions::default()
            },
        );
        let f = r.render(&[facing_the_wall()], 0);
        let (top, base) = (mount.row_of_height(60.0, s), mount.row_of_height(0.0, s));
        for c in [0, 30, 49, 70, 98] {
            let (t, b) = wall_edges(&f, c);
            assert!(
                (t - top).abs() < 0.02,
                "{mount:?} column {c}: top {t} vs {top}"
            );
            assert!(
                (b - base).abs() < 0.02,
                "{mount:?} column {c}: base {b} vs {base}"
            );
        }
        tops.push(wall_edges(&f, 49).0);
    }
    let shift = FOCAL_PX * 2f64.to_radians().tan();
    assert!((shift - 2.444).abs() < 0.001);
    assert!(
        (tops[3] - tops[0] - shift).abs() < 0.03,
        "pitch up: {tops:?}"
    );
    assert!(
        (tops[0] - tops[4] - shift).abs() < 0.03,
        "pitch down: {tops:?}"
    );
    // 5 mm higher: the top 5·f/s rows lower, as the base
    assert!(
        (tops[1] - tops[0] - 5.0 * FOCAL_PX / s).abs() < 0.03,
        "{tops:?}"
    );
    assert!(CameraMount::default().check().is_ok());
    for bad in [(0.0, 0.0), (20.0, 45.0), (f64::NAN, 0.0)] {
        let m = CameraMount {
            height_mm: bad.0,
            pitch_deg: bad.1,
        };
        assert_eq!(m.check().unwrap_err().to_string().lines().count(), 1);
    }
}

fn render_with(world: &World, options: RenderOptions, eye: Pose) -> Frame {
    Renderer::with_options(world, &options).render(&[eye], 0)
}

/// A pattern on the floor changes the floor and nothing else; up close it has its contrast,
/// far away (where a pixel spans its features) it fades to the plain floor.
#[test]
fn a_floor_pattern_changes_the_floor_only_and_fades_with_distance() {
    let world = plain_world();
    let eye = Pose::new(600.0, 700.0, -90.0); // 700 mm from the wall ahead
    let plain = render_with(&world, RenderOptions::default(), eye);
    let pattern = FloorPattern {
        contrast: 0.1,
        finest_mm: 5.0,
        coarsest_mm: 80.0,
        seed: 4,
    };
    let textured = render_with(
        &world,
        RenderOptions {
            floor_pattern: Some(pattern),
            ..RenderOptions::default()
        },
        eye,
    );
    let rel = |y: usize, c: usize| {
        let i = y * WIDTH + c;
        f64::from(textured[i]) / f64::from(plain[i]) - 1.0
    };
    let rms = |rows: std::ops::Range<usize>| {
        let v: Vec<f64> = rows
            .flat_map(|y| (0..WIDTH).map(move |c| (y, c)))
            .map(|(y, c)| rel(y, c))
            .collect();
        (v.iter().map(|d| d * d).sum::<f64>() / v.len() as f64).sqrt()
    };
    // the wall's base is at row 37.56: the sky and the wall above it are untouched
    for y in 0..=37 {
        for c in 0..WIDTH {
            assert_eq!(textured[y * WIDTH + c], plain[y * WIDTH + c], "({c}, {y})");
        }
    }
    let near = rms(62..HEIGHT);
    let far = rms(39..42);
    assert!((0.06..0.14).contains(&near), "near rows' contrast {near}");
    assert!(far < near / 2.0, "far rows {far} against near {near}");
}

/// The floor line (`floor_row`) on the textured floor: of the replica's poses (a 12 × 6 grid,
/// 12 headings, clear of the obstacles, three floor seeds), the grain makes it find a foot
/// where the plain floor shows none on at most 2 % of them (13 % before its tolerance followed
/// the grain and a foot had to step from the floor below it:
/// docs/notes/2026-11-28-floor-grain.md), and hides a foot the plain floor shows on at most 1 %.
#[test]
fn the_floor_line_finds_few_feet_in_a_floor_grain_and_hides_few() {
    use alvs_tasks::model::closed_loop::floor::obstacle_ahead;
    let world = BuiltinWorld::Fu2019.world();
    let (sx, sy) = (world.arena.size_x_mm, world.arena.size_y_mm);
    let plain = Renderer::with_options(&world, &RenderOptions::default());
    let (mut poses, mut added, mut hidden) = (0, 0, 0);
    for seed in 1..=3 {
        let mut options = SimOptions::default();
        Perturbation::FloorTexture.apply(
            seed,
            &mut MotorParams::default(),
            &mut SensorNoise::typical(),
            &mut options,
        );
        let grained = Renderer::with_options(&world, &options.render);
        for (i, j) in (0..12).flat_map(|i| (0..6).map(move |j| (i, j))) {
            let (x, y) = (sx * (i as f64 + 0.5) / 12.0, sy * (j as f64 + 0.5) / 6.0);
            if world::static_distance(&world.arena, &world.obstacles, x, y) < 30.0 {
                continue;
            }
            for h in 0..12 {
                let eye = Pose::new(x, y, f64::from(h) * 30.0);
                let a = obstacle_ahead(&plain.render(&[eye], 0), 52).is_some();
                let b = obstacle_ahead(&grained.render(&[eye], 0), 52).is_some();
                poses += 1;
                added += usize::from(b && !a);
                hidden += usize::from(a && !b);
            }
        }
    }
    println!("{added} feet added and {hidden} hidden by the grain, of {poses} poses");
    assert!(poses > 2000, "{poses} poses");
    assert!(50 * added <= poses, "{added} feet added of {poses} poses");
    assert!(
        100 * hidden <= poses,
        "{hidden} feet hidden of {poses} poses"
    );
}

/// The lighting gradient brightens what stands near `x = 0` and darkens what stands near the
/// far end, by its gain there; the lab above the walls keeps its grey.
#[test]
fn the_lighting_gradient_scales_walls_and_floor_by_their_place() {
    let world = plain_world();
    let light = LightGradient { amplitude: 0.25 };
    let lit = RenderOptions {
        lighting: Some(light),
        ..RenderOptions::default()
    };
    let a = world.arena;
    // near each end, facing it (the x = 0 and x = size_x walls are both shaded 0.92)
    for (eye, wall_gain) in [
        (Pose::new(200.0, 450.0, 180.0), 1.25),
        (Pose::new(a.size_x_mm - 200.0, 450.0, 0.0), 0.75),
    ] {
        let plain = render_with(&world, RenderOptions::default(), eye);
        let f = render_with(&world, lit, eye);
        let px = |fr: &Frame, y: usize| f64::from(fr[y * WIDTH + 49]);
        assert_eq!(px(&f, 5), px(&plain, 5), "the lab above");
        let wall = px(&f, 34) / px(&plain, 34);
        assert!(
            (wall - wall_gain).abs() < 0.02,
            "wall {wall} vs {wall_gain}"
        );
        // the bottom row's floor point: its gain is the gradient's at its own x
        let s = 20.0 * FOCAL_PX / (70.0 - 35.5);
        let x = eye.offset(CAMERA_FORWARD_MM + s, 0.0).0;
        let want = f64::from(light.gain(&a, x as f32));
        let floor = px(&f, 70) / px(&plain, 70);
        assert!((floor - want).abs() < 0.01, "floor {floor} vs {want}");
    }
}

// ---------------------------------------------------------------------------------------------
// The motors, the heading and the frames.

use alvs_sim::controller::{Command, Controller, Scripted};
use alvs_sim::kinematics::FRAME_DT_S;
use std::sync::{Arc, Mutex};

/// An arena large enough to drive in circles without meeting a wall.
fn open_field() -> World {
    World {
        arena: Arena::new(6000.0, 6000.0),
        ..World::default()
    }
}

/// A robot whose right motor is 5 % weaker, both wheels told 100 mm/s: it circles to the right
/// on the radius `track · (2 − a)/(2a)` = 936 mm, turning `v·a/track` = 5.97°/s.
#[test]
fn an_asymmetric_robot_told_to_go_straight_drives_a_circle_of_the_expected_radius() {
    let motor = MotorParams {
        asymmetry: 0.05,
        ..MotorParams::ideal()
    };
    let r = motor.open_loop_radius_mm();
    assert!((r - 936.0).abs() < 1e-9, "{r}");
    assert_eq!(MotorParams::default().open_loop_radius_mm(), f64::INFINITY);
    let start = Pose::new(3000.0, 3000.0, 0.0);
    let mut p = Physics::of_world(&open_field(), 1);
    p.add_robot(start, motor, GyroParams::ideal());
    p.set_wheels(0, 100.0, 100.0);
    let seconds = 10.0;
    for _ in 0..(seconds / FRAME_DT_S).round() as usize {
        p.step_frame();
    }
    let end = p.poses()[0];
    // turning right from +x in the y-down frame: the centre is on the +y side
    let centre = (start.x_mm, start.y_mm + r);
    let d = (end.x_mm - centre.0).hypot(end.y_mm - centre.1);
    assert!((d - r).abs() < 0.5, "{d} mm from the centre, not {r}");
    let rate = 100.0 * 0.05 / 48.0_f64;
    assert!(
        (end.heading_deg - (rate * seconds).to_degrees()).abs() < 0.01,
        "{}",
        end.heading_deg
    );
}

/// A controller that drives a constant command and keeps every frame and heading it is given.
struct Recorder {
    left_mm_s: f32,
    right_mm_s: f32,
    seen: Arc<Mutex<Vec<(Frame, f32)>>>,
}

impl Controller for Recorder {
    fn name(&self) -> &'static str {
        "recorder"
    }

    fn step(&mut self, frame: &Frame, heading_deg: f32) -> Command {
        self.seen.lock().unwrap().push((*frame, heading_deg));
        Command {
            left_mm_s: self.left_mm_s,
            right_mm_s: self.right_mm_s,
            state: "recorded",
            ..Command::default()
        }
    }
}

type Seen = Arc<Mutex<Vec<(Frame, f32)>>>;

/// One robot at `start` in `world` driving (`left`, `right`) with ideal motors, gyro and
/// camera; the frames and headings it is given.
fn recorded(
    world: &World,
    options: SimOptions,
    start: Pose,
    wheels: (f32, f32),
    motor: MotorParams,
) -> (Sim, Seen) {
    let seen: Seen = Arc::default();
    let mut sim = Sim::with_options(world, 3, &options);
    sim.add(
        start,
        Box::new(Recorder {
            left_mm_s: wheels.0,
            right_mm_s: wheels.1,
            seen: seen.clone(),
        }),
        motor,
        GyroParams::ideal(),
        SensorNoise::default(),
    );
    (sim, seen)
}

/// Driving 10° off square into a wall that turns a sliding body (the recorded arena's contact):
/// the body swings round parallel to the wall and the gyro says so; the firmware's odometry,
/// which only integrates the equal wheel commands, still says 10°. And a robot with a weaker
/// motor drifts off its odometry by the turn its asymmetry makes.
#[test]
fn the_odometry_heading_drifts_under_slip_and_asymmetry_and_the_gyro_does_not() {
    let world = World {
        contact: SurfaceContact::default(),
        ..World::default()
    };
    let start = Pose::new(1100.0, 450.0, 10.0);
    for heading in [HeadingSource::Gyro, HeadingSource::Odometry] {
        let options = SimOptions {
            heading,
            ..SimOptions::default()
        };
        let (mut sim, seen) =
            recorded(&world, options, start, (100.0, 100.0), MotorParams::ideal());
        for _ in 0..120 {
            sim.step();
        }
        let truth = sim.physics.poses()[0].heading_deg;
        assert!((truth - 90.0).abs() < 1.0, "the wall turned it: {truth}");
        assert!((sim.physics.gyro(0).heading() - truth).abs() < 1e-6);
        assert!(
            (sim.odometry_heading(0) - 10.0).abs() < 1e-4,
            "odometry {}",
            sim.odometry_heading(0)
        );
        let given = seen.lock().unwrap().last().unwrap().1;
        let want = match heading {
            HeadingSource::Gyro => truth as f32,
            HeadingSource::Odometry => 10.0,
        };
        assert!(
            (given - want).abs() < 0.5,
            "{heading:?}: given {given}, want {want}"
        );
        assert_eq!(
            sim.heading_estimate(0),
            match heading {
                HeadingSource::Gyro => sim.physics.gyro(0).heading() as f32,
                HeadingSource::Odometry => sim.odometry_heading(0),
            }
        );
    }
    // 5 % asymmetry, 10 s: the body turns 59.7°, the odometry not at all
    let motor = MotorParams {
        asymmetry: 0.05,
        ..MotorParams::ideal()
    };
    let options = SimOptions {
        heading: HeadingSource::Odometry,
        ..SimOptions::default()
    };
    let (mut sim, _) = recorded(
        &open_field(),
        options,
        Pose::new(3000.0, 3000.0, 0.0),
        (100.0, 100.0),
        motor,
    );
    for _ in 0..300 {
        sim.step();
    }
    let drift = sim.physics.poses()[0].heading_deg - f64::from(sim.heading_estimate(0));
    assert!((drift - 59.68).abs() < 0.1, "drift {drift}");
}

/// With every processed frame followed by a lost one (`frame_loss` 1), the controller runs on
/// every other frame (the first is never lost) and sees exactly the frames the camera takes
/// then, never a repeat; its command drives on through the lost frames, which count for its
/// state; the odometry advances only on processed frames, as the firmware's does.
#[test]
fn a_lost_frame_is_skipped_whole_and_the_wheels_drive_on() {
    let world = World::default();
    let start = Pose::new(300.0, 450.0, 0.0);
    let wheels = (120.0, 80.0); // a gentle right turn: every frame differs
    let (mut every, all) = recorded(
        &world,
        SimOptions::default(),
        start,
        wheels,
        MotorParams::ideal(),
    );
    let lossy = SimOptions {
        frame_loss: Some(1.0),
        heading: HeadingSource::Odometry,
        ..SimOptions::default()
    };
    let (mut half, some) = recorded(&world, lossy, start, wheels, MotorParams::ideal());
    for _ in 0..60 {
        every.step();
        half.step();
    }
    let (all, some) = (all.lock().unwrap(), some.lock().unwrap());
    assert_eq!((all.len(), some.len(), half.frames_lost(0)), (60, 30, 30));
    for (k, (frame, _)) in some.iter().enumerate() {
        assert!(
            frame == &all[2 * k].0,
            "processed frame {k} is frame {}",
            2 * k
        );
    }
    assert!(
        some.windows(2).all(|w| w[0].0 != w[1].0),
        "no frame repeats"
    );
    assert_eq!(half.state_frames()[0].values().sum::<u64>(), 60);
    // the wheels never stopped: both robots are in the same place
    assert_eq!(every.physics.poses()[0], half.physics.poses()[0]);
    // the odometry integrated 30 frames of the turn, the body turned 60 frames' worth
    let per_frame = ((120.0 - 80.0) / 48.0 * FRAME_DT_S).to_degrees();
    let odo = f64::from(half.odometry_heading(0));
    assert!((odo - 30.0 * per_frame).abs() < 1e-3, "{odo}");
    let truth = half.physics.poses()[0].heading_deg;
    assert!((truth - 60.0 * per_frame).abs() < 1e-6, "{truth}");
}

/// At a loss rate `p` a processed frame is followed by a lost one with chance `p` and a lost
/// one never: `p/(1 + p)` of the frames are lost, never two in a row.
#[test]
fn frames_are_lost_at_their_rate_and_never_two_in_a_row() {
    let world = World::default();
    let options = SimOptions {
        frame_loss: Some(0.2),
        ..SimOptions::default()
    };
    let mut sim = Sim::with_options(&world, 5, &options);
    sim.add(
        Pose::new(600.0, 450.0, 0.0),
        Box::new(Scripted {
            left_mm_s: 0.0,
            right_mm_s: 0.0,
        }),
        MotorParams::ideal(),
        GyroParams::ideal(),
        SensorNoise::default(),
    );
    let mut lost = Vec::new();
    for _ in 0..3000 {
        let before = sim.frames_lost(0);
        sim.step();
        lost.push(sim.frames_lost(0) > before);
    }
    assert!(!lost[0], "the first frame is processed");
    assert!(lost.windows(2).all(|w| !(w[0] && w[1])), "two in a row");
    let share = lost.iter().filter(|&&l| l).count() as f64 / 3000.0;
    assert!((share - 0.2 / 1.2).abs() < 0.02, "{share}");
}

/// `camera-steady` and `camera-aec` take the camera's per-frame gain draw away and nothing else,
/// `camera-jitter` draws it at 2 % instead of 0.3 %: a robot standing before the replica's wall
/// sees the frame's mean grey jump by about 0.3 % of itself from frame to frame with the typical
/// camera, about 2 % with `camera-jitter`, and by the pixel noise's share only without the draw
/// (0.03 grey levels).
#[test]
fn the_steady_camera_has_no_gain_draw() {
    let world = BuiltinWorld::Fu2019.world();
    let r = Renderer::with_options(&world, &RenderOptions::default());
    let eye = Pose::new(300.0, 300.0, 0.0);
    let spread = |noise: SensorNoise| {
        let mut cam = Camera::new(noise, 5);
        let mut frame = [0u8; alvs_tasks::PIXELS];
        let means: Vec<f64> = (0..30)
            .map(|_| {
                cam.capture(&r, &[eye], 0, &mut frame);
                frame.iter().map(|&v| f64::from(v)).sum::<f64>() / frame.len() as f64
            })
            .collect();
        let m = means.iter().sum::<f64>() / means.len() as f64;
        let sd = (means.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / means.len() as f64).sqrt();
        (m, sd)
    };
    let typical = SensorNoise::typical();
    let perturbed = |p: Perturbation| {
        let mut noise = typical;
        p.apply(
            1,
            &mut MotorParams::default(),
            &mut noise,
            &mut SimOptions::default(),
        );
        noise
    };
    let steady = perturbed(Perturbation::CameraSteady);
    assert_eq!(
        steady,
        SensorNoise {
            gain_sigma: 0.0,
            ..typical
        }
    );
    let ((m, sd_typical), (_, sd_steady)) = (spread(typical), spread(steady));
    assert!(
        (0.001 * m..0.006 * m).contains(&sd_typical),
        "typical: mean {m:.1}, sd {sd_typical:.2}"
    );
    assert!(sd_steady < 0.1, "steady: sd {sd_steady:.3}");
    let jitter = perturbed(Perturbation::CameraJitter);
    assert_eq!(
        jitter,
        SensorNoise {
            gain_sigma: 0.02,
            ..typical
        }
    );
    let sd_jitter = spread(jitter).1;
    assert!(
        sd_jitter > 0.01 * m,
        "jitter: mean {m:.1}, sd {sd_jitter:.2}"
    );
    // `camera-aec`: the documented auto exposure in place of the draw, which in this steady
    // view holds the exposure (its steps are tested in sim/tests/camera_aec.rs)
    let aec = perturbed(Perturbation::CameraAec);
    assert_eq!(
        aec,
        SensorNoise {
            gain_sigma: 0.0,
            aec: Some(alvs_sim::Aec::OV7670),
            ..typical
        }
    );
    assert!(spread(aec).1 < 0.1, "aec: sd {:.3}", spread(aec).1);
}

// ---------------------------------------------------------------------------------------------
// The suite.

use alvs_host::experiments::robustness::{
    Perturbation, RobustnessConfig, SuiteController, SLOW_SHARE,
};
use alvs_host::experiments::sweep::{self, Shard, Sweep};
use alvs_host::experiments::Report;

mod common;
use common::{alvs, succeed, tmp};

/// The reference and one perturbation, every controller, one seed, 6 simulated seconds.
fn tiny_suite() -> RobustnessConfig {
    RobustnessConfig {
        seeds: vec![11],
        perturbations: vec![Perturbation::None, Perturbation::DroppedFrames],
        minutes: 0.1,
        ..RobustnessConfig::default()
    }
}

/// A tiny run gives one row per (perturbation, controller), in order, each with the arena's
/// pooled counts, its speed against the cruise speed (flagged below 80 %), and the change from
/// the reference; a 2-shard run merges into the same JSON.
#[test]
fn a_tiny_suite_gives_a_row_for_every_controller_and_shards_merge_to_it() {
    let config = tiny_suite();
    assert_eq!(config.trial_count(), 6);
    let r = sweep::run_all(&config, 2, &|_| {}).unwrap();
    let names: Vec<(&str, &str)> = r
        .rows
        .iter()
        .map(|r| (r.perturbation.name(), r.controller.name()))
        .collect();
    assert_eq!(
        names,
        [
            ("none", "alvs"),
            ("none", "paper"),
            ("none", "lgmd2"),
            ("dropped-frames", "alvs"),
            ("dropped-frames", "paper"),
            ("dropped-frames", "lgmd2"),
        ]
    );
    for row in &r.rows {
        let mine: Vec<_> = r
            .trials
            .iter()
            .filter(|t| t.perturbation == row.perturbation && t.controller == row.controller)
            .collect();
        assert_eq!(mine.len(), 1);
        let t = &mine[0].trial;
        assert_eq!((t.seed, t.robots, t.frames), (11, 3, 180));
        assert_eq!(t.background, "fu2019");
        assert_eq!(row.encounters, t.encounters);
        assert_eq!(row.success_rate, t.success_rate);
        assert!(row.mean_speed_mm_s > 0.0);
        assert_eq!(row.cruise_mm_s, 100.0);
        assert_eq!(
            row.slow,
            row.mean_speed_mm_s < SLOW_SHARE * 100.0,
            "{row:?}"
        );
        let base = r
            .rows
            .iter()
            .find(|b| b.perturbation == Perturbation::None && b.controller == row.controller)
            .unwrap();
        let change = row.mean_speed_mm_s / base.mean_speed_mm_s - 1.0;
        assert!((row.speed_change.unwrap() - change).abs() < 1e-12);
    }
    let table = r.table();
    for c in SuiteController::DEFAULT {
        assert!(table.contains(c.name()), "{table}");
    }
    assert_eq!(
        table.contains("SLOW"),
        r.rows.iter().any(|r| r.slow),
        "{table}"
    );
    let json = r.json();
    assert_eq!(json["rows"].as_array().map(Vec::len), Some(6));
    assert_eq!(json["trials"].as_array().map(Vec::len), Some(6));

    let dir = tmp("robustness-shards");
    let files: Vec<_> = (1..=2)
        .map(|index| {
            let shard = Shard { index, count: 2 };
            let v = sweep::run_shard(&config, &[], shard, 1, &|_| {}).unwrap();
            let path = dir.join(format!("{index}.json"));
            std::fs::write(&path, serde_json::to_string(&v).unwrap()).unwrap();
            sweep::read(&path).unwrap()
        })
        .collect();
    let merged = sweep::merge(&config, &files).unwrap();
    let strip = |mut v: serde_json::Value| {
        v["wall_clock_s"] = 0.into();
        v["jobs"] = 0.into();
        for t in v["trials"].as_array_mut().unwrap() {
            t["trial"]["wall_clock_s"] = 0.into();
        }
        v
    };
    assert_eq!(strip(merged.json()), strip(json));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The command line: bad input is one line; a sharded run merges with `alvs merge` into the
/// table of that perturbation and controller.
#[test]
fn the_command_refuses_bad_input_in_one_line_and_its_shards_merge() {
    for (args, expect) in [
        (&["--perturbation", "fog"][..], "possible values"),
        (&["--minutes", "0"][..], "--minutes"),
        (&["--robots", "40"][..], "cannot place 40 robots"),
        (&["--controller", "swarm"][..], "possible values"),
    ] {
        let out = alvs().arg("robustness").args(args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(expect), "{args:?}: {err}");
    }
    let dir = tmp("robustness-cli");
    let args = [
        "robustness",
        "--perturbation",
        "lighting",
        "--controller",
        "lgmd2",
        "--seed",
        "11",
        "--seed",
        "12",
        "--minutes",
        "0.05",
        "--jobs",
        "1",
    ];
    let shards: Vec<_> = (1..=2)
        .map(|i| {
            let path = dir.join(format!("{i}.json"));
            succeed(
                alvs()
                    .args(args)
                    .args(["--shard", &format!("{i}/2"), "--json"])
                    .arg(&path),
            );
            path
        })
        .collect();
    let out = succeed(
        alvs()
            .arg("merge")
            .args(&shards)
            .arg("--png")
            .arg(dir.join("png")),
    );
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains("seeds 11,12"), "{table}");
    let rows: Vec<&str> = table
        .lines()
        .filter(|l| l.starts_with("lighting "))
        .collect();
    assert_eq!(rows.len(), 2, "the row and the legend: {table}");
    assert!(rows[0].contains("lgmd2"), "{table}");
    assert!(dir.join("png/summary.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

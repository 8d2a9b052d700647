//! The simulated arena's foundations: camera geometry (pinhole bearing → column, size ∝ 1 /
//! distance, occlusion, walls everywhere), differential-drive kinematics (straight line, turn
//! rate and direction, motor lag), contact counting on scripted runs (head-on, passing, into a
//! wall), and determinism by seed.
//!
//! `cargo test --target host-tuple -p alvs-host --test arena_geometry`. Two `#[ignore]`d tests
//! are tools: `example_pictures` writes frames and a top-down view to `/tmp/arena_*.png`, and
//! `bench_render` prints the renderer's speed (run it with `--release -- --ignored --nocapture`).

use alvs_sim::canvas::{colour_cycle, Canvas, RED};
use alvs_sim::contacts::{
    ROBOT_COLLISION_DISTANCE_MM, ROBOT_ENCOUNTER_DISTANCE_MM, WALL_COLLISION_DISTANCE_MM,
};
use alvs_sim::kinematics::{FRAME_DT_S, PHYSICS_DT_S};
use alvs_sim::render::{
    column_of_bearing, frame_canvas, row_of_height, CAMERA_FORWARD_MM, SKY_GREY,
};
use alvs_sim::world::{ROBOT_DIAMETER_MM, ROBOT_RADIUS_MM};
use alvs_sim::{
    Arena, Camera, GyroParams, MotorParams, Physics, Pose, Renderer, RobotPattern, SensorNoise,
    TopDown, WallTexture, World,
};
use alvs_tasks::model::fsm::HeadingEstimator;
use alvs_tasks::{Frame, HEIGHT, WIDTH};

/// Grey of the plain walls in the geometry tests.
const WALL: u8 = 200;
/// Grey of the uniform dark robots in the geometry tests.
const BODY: u8 = 10;

/// Plain walls, uniformly dark robots: a robot is wherever the picture is dark.
fn plain_world() -> World {
    World {
        texture: WallTexture::Plain(WALL),
        robot_pattern: RobotPattern::Band {
            body: BODY,
            band: BODY,
            bottom_mm: 0.0,
            top_mm: 0.0,
        },
        ..World::default()
    }
}

/// The viewer used by the geometry tests, facing +x from the left part of the arena.
fn viewer() -> Pose {
    Pose::new(300.0, 450.0, 0.0)
}

/// A robot's pose at `bearing_deg` and `distance_mm` from `eye`'s camera.
fn at_bearing(eye: &Pose, bearing_deg: f64, distance_mm: f64) -> Pose {
    let (cx, cy) = eye.offset(CAMERA_FORWARD_MM, 0.0);
    let a = (eye.heading_deg + bearing_deg).to_radians();
    Pose::new(cx + distance_mm * a.cos(), cy + distance_mm * a.sin(), 0.0)
}

/// Coverage of a dark robot in each column of row `y`: `(background − pixel)/(background −
/// body)`, from a frame with the robot and the same view without it.
fn coverage(with: &Frame, without: &Frame, y: usize) -> Vec<f64> {
    (0..WIDTH)
        .map(|x| {
            let bg = f64::from(without[y * WIDTH + x]);
            let px = f64::from(with[y * WIDTH + x]);
            ((bg - px) / (bg - f64::from(BODY))).clamp(0.0, 1.0)
        })
        .collect()
}

/// (centre column, width in columns) of the coverage.
fn centre_and_width(cov: &[f64]) -> (f64, f64) {
    let w: f64 = cov.iter().sum();
    let c = cov
        .iter()
        .enumerate()
        .map(|(x, v)| x as f64 * v)
        .sum::<f64>()
        / w;
    (c, w)
}

#[test]
fn a_robot_appears_at_the_pinhole_column_of_its_bearing() {
    let r = Renderer::new(&plain_world());
    let eye = viewer();
    let empty = r.render(&[eye], 0);
    // At 250 mm and ±30° the body still fits in the ±35.4° of the image.
    for bearing in [-30.0, -22.5, -15.0, -7.5, 0.0, 5.0, 12.5, 20.0, 30.0] {
        for distance in [250.0, 400.0] {
            let other = at_bearing(&eye, bearing, distance);
            let frame = r.render(&[eye, other], 0);
            let (centre, width) = centre_and_width(&coverage(&frame, &empty, 36));
            let want = column_of_bearing(bearing);
            // Exactly, a cylinder's silhouette spans the tangent bearings β ± asin(R/d), whose
            // midpoint in the image lies slightly outward of the centre's column.
            let delta = (ROBOT_RADIUS_MM / distance).asin().to_degrees();
            let (left, right) = (
                column_of_bearing(bearing - delta),
                column_of_bearing(bearing + delta),
            );
            println!(
                "β {bearing:6.1}° d {distance} mm: column {centre:6.2} (pinhole {want:6.2}, \
                 silhouette {:6.2}), width {width:5.2} (silhouette {:5.2})",
                (left + right) / 2.0,
                right - left
            );
            assert!(
                (centre - want).abs() <= 1.0,
                "robot at {bearing}° {distance} mm seen at column {centre:.2}, pinhole says {want:.2}"
            );
            assert!((centre - (left + right) / 2.0).abs() < 0.15);
            assert!((width - (right - left)).abs() < 0.15);
        }
    }
    // Right is right: a robot at +20° is right of the centre column.
    let frame = r.render(&[eye, at_bearing(&eye, 20.0, 300.0)], 0);
    let (centre, _) = centre_and_width(&coverage(&frame, &empty, 36));
    assert!(centre > 49.0 + 20.0);
}

#[test]
fn apparent_size_falls_as_one_over_distance() {
    let r = Renderer::new(&plain_world());
    let eye = viewer();
    let empty = r.render(&[eye], 0);
    let mut products = Vec::new();
    for d in [100.0, 150.0, 200.0, 300.0, 400.0, 600.0] {
        let frame = r.render(&[eye, at_bearing(&eye, 0.0, d)], 0);
        let (_, width) = centre_and_width(&coverage(&frame, &empty, 36));
        // Height: rows whose centre column is covered more than half.
        let rows = (0..HEIGHT)
            .filter(|&y| frame[y * WIDTH + 49] < (WALL / 2).min(empty[y * WIDTH + 49] / 2))
            .count() as f64;
        // The centre column sees the body's front, one radius nearer than its centre.
        let s = d - ROBOT_RADIUS_MM;
        let want_rows = row_of_height(0.0, s) - row_of_height(28.0, s);
        println!("d {d:5} mm: width {width:6.2} px, width·d {:7.0}, rows {rows} (pinhole {want_rows:.1})", width * d);
        assert!(
            (rows - want_rows).abs() <= 1.5,
            "height {rows} rows at {d} mm, want {want_rows:.1}"
        );
        products.push(width * d);
    }
    // Pinhole: width = 2 f tan(asin(R/d)) ≈ 2 f R / d.
    let ideal = 2.0 * alvs_sim::render::FOCAL_PX * ROBOT_RADIUS_MM;
    for p in &products {
        assert!(
            (p / ideal - 1.0).abs() < 0.06,
            "width·distance {p:.0}, want ≈ {ideal:.0}"
        );
    }
}

#[test]
fn a_robot_behind_another_is_occluded() {
    let r = Renderer::new(&plain_world());
    let eye = viewer();
    let near = at_bearing(&eye, 0.0, 150.0);
    let far = at_bearing(&eye, 1.0, 400.0);
    let both = r.render(&[eye, near, far], 0);
    let near_only = r.render(&[eye, near], 0);
    let far_only = r.render(&[eye, far], 0);
    let empty = r.render(&[eye], 0);
    assert_eq!(both, near_only, "the far robot shows through the near one");
    assert_ne!(far_only, empty, "the far robot alone is visible");
    // Order in the list does not matter.
    assert_eq!(r.render(&[eye, far, near], 0), both);
    // Partial occlusion: the far robot's right part shows beside the near one.
    let far_right = at_bearing(&eye, 9.0, 400.0);
    let partial = r.render(&[eye, near, far_right], 0);
    assert_ne!(partial, near_only);
    let cov_near = coverage(&near_only, &empty, 36);
    let cov_partial = coverage(&partial, &empty, 36);
    let extra: f64 = cov_partial.iter().zip(&cov_near).map(|(a, b)| a - b).sum();
    let far_width: f64 = coverage(&r.render(&[eye, far_right], 0), &empty, 36)
        .iter()
        .sum();
    assert!(
        extra > 0.5 && extra < far_width - 0.5,
        "visible part {extra:.2} of {far_width:.2}"
    );
}

#[test]
fn walls_are_seen_from_everywhere() {
    let world = World {
        texture: WallTexture::Plain(77),
        ..World::default()
    };
    let r = Renderer::new(&world);
    let a = world.arena;
    let m = ROBOT_RADIUS_MM;
    let mut xs = vec![m, a.size_x_mm - m];
    let mut ys = vec![m, a.size_y_mm - m];
    xs.extend((1..8).map(|k| a.size_x_mm * k as f64 / 8.0));
    ys.extend((1..6).map(|k| a.size_y_mm * k as f64 / 6.0));
    for &x in &xs {
        for &y in &ys {
            for h in (0..24).map(|k| -180.0 + 15.0 * k as f64) {
                let f = r.render(&[Pose::new(x, y, h)], 0);
                for row in [35, 36] {
                    for c in 0..WIDTH {
                        let g = f[row * WIDTH + c];
                        assert!(
                            (62..=78).contains(&g),
                            "no wall at ({c}, {row}) from ({x}, {y}, {h}°): grey {g}"
                        );
                    }
                }
            }
        }
    }
}

/// Sum of |grey difference| between neighbouring columns: the picture's vertical edges.
fn edge_energy(f: &Frame) -> u64 {
    f.chunks_exact(WIDTH)
        .flat_map(|row| row.windows(2))
        .map(|w| u64::from(w[0].abs_diff(w[1])))
        .sum()
}

#[test]
fn an_exposure_blurs_what_moves_and_nothing_else() {
    let world = World::with_texture(WallTexture::Checker { size_mm: 40.0 });
    let r = Renderer::new(&world);
    let before = [Pose::new(600.0, 450.0, 0.0), Pose::new(800.0, 450.0, 90.0)];
    // a turn of 6° in one frame (180°/s): the walls sweep about 8 columns
    let after = [Pose::new(600.0, 450.0, 6.0), Pose::new(800.0, 450.0, 90.0)];
    let shot = |exposure: f32, from: &[Pose], to: &[Pose]| {
        let noise = SensorNoise {
            exposure,
            ..SensorNoise::default()
        };
        let mut f = [0u8; alvs_tasks::PIXELS];
        Camera::new(noise, 1).capture_moving(&r, from, to, 0, &mut f);
        f
    };
    // nothing moved: the exposure changes nothing
    assert_eq!(shot(1.0, &after, &after), r.render(&after, 0));
    // no exposure: the picture at the end of the frame period
    assert_eq!(shot(0.0, &before, &after), r.render(&after, 0));
    // the longer the exposure, the softer the edges, and the light is kept
    let e: Vec<u64> = [0.0, 0.5, 1.0]
        .iter()
        .map(|&x| edge_energy(&shot(x, &before, &after)))
        .collect();
    assert!(e[0] > e[1] && e[1] > e[2], "edge energy {e:?}");
    assert!(e[2] * 10 < e[0] * 8, "a whole-period blur keeps {e:?}");
    let mean = |f: &Frame| f.iter().map(|&g| f64::from(g)).sum::<f64>() / f.len() as f64;
    let (sharp, blurred) = (shot(0.0, &before, &after), shot(1.0, &before, &after));
    assert!((mean(&sharp) - mean(&blurred)).abs() < 2.0);
}

#[test]
fn a_pose_between_two_takes_the_shorter_turn() {
    let m = Pose::new(0.0, 10.0, 170.0).lerp(&Pose::new(10.0, 30.0, -170.0), 0.5);
    assert_eq!((m.x_mm, m.y_mm), (5.0, 20.0));
    assert!(
        (m.heading_deg.abs() - 180.0).abs() < 1e-9,
        "{}",
        m.heading_deg
    );
    let q = Pose::new(0.0, 0.0, -10.0).lerp(&Pose::new(0.0, 0.0, 30.0), 0.25);
    assert!((q.heading_deg - 0.0).abs() < 1e-9);
}

#[test]
fn a_wall_seen_square_on_is_a_level_band_at_the_pinhole_rows() {
    // 60 mm wall, camera 281 mm from it: top at row 25.54, base at row 40.48, in every column.
    let world = World {
        texture: WallTexture::Plain(77),
        wall_height_mm: 60.0,
        ..World::default()
    };
    let r = Renderer::new(&world);
    let eye = Pose::new(600.0, 300.0, -90.0);
    let f = r.render(&[eye], 0);
    let s = 300.0 - CAMERA_FORWARD_MM;
    let (top, base) = (row_of_height(60.0, s), row_of_height(0.0, s));
    assert!((top - 25.54).abs() < 0.01 && (base - 40.48).abs() < 0.01);
    let wall = 77.0; // the y = 0 wall is fully lit
    for c in 0..WIDTH {
        let g = |y: usize| f64::from(f[y * WIDTH + c]);
        for y in 0..=25 {
            assert_eq!(g(y), f64::from(SKY_GREY), "sky at ({c}, {y})");
        }
        for y in 27..=39 {
            assert_eq!(g(y), wall, "wall at ({c}, {y})");
        }
        // Row 26 is 4 % sky, row 40 is 2 % floor: fractional coverage.
        let sky = top - 25.5;
        assert!((g(26) - (sky * f64::from(SKY_GREY) + (1.0 - sky) * wall)).abs() <= 1.0);
        assert!((g(40) - wall).abs() <= 2.0);
        for y in 41..HEIGHT {
            assert!(g(y) > wall + 20.0, "floor at ({c}, {y}) is {}", g(y));
        }
        // Every column identical: no fish-eye.
        assert!((0..HEIGHT).all(|y| f[y * WIDTH + c] == f[y * WIDTH]));
    }
}

fn ideal_physics(poses: &[Pose]) -> Physics {
    let mut p = Physics::new(Arena::default(), 1);
    for &pose in poses {
        p.add_robot(pose, MotorParams::ideal(), GyroParams::ideal());
    }
    p
}

fn run_s(p: &mut Physics, seconds: f64) {
    let steps = (seconds / PHYSICS_DT_S).round() as usize;
    for _ in 0..steps {
        p.step();
    }
}

#[test]
fn straight_line_travels_v_times_t() {
    for (heading, v) in [(0.0, 100.0), (30.0, 150.0), (-135.0, 80.0)] {
        let start = Pose::new(600.0, 450.0, heading);
        let mut p = ideal_physics(&[start]);
        p.set_wheels(0, v, v);
        run_s(&mut p, 3.0);
        let end = p.poses()[0];
        let d = start.distance_to(&end);
        assert!((d - v * 3.0).abs() < 0.05, "{d} mm, want {}", v * 3.0);
        assert!((end.heading_deg - start.heading_deg).abs() < 1e-9);
        let along = start.bearing_to(end.x_mm, end.y_mm);
        assert!(along.abs() < 1e-6, "drifted {along}° off the heading");
    }
}

#[test]
fn opposite_wheels_turn_in_place_at_l_minus_r_over_track() {
    // left − right = 48 mm/s on a 48 mm track: 1 rad/s to the right (heading grows).
    let start = Pose::new(600.0, 450.0, 10.0);
    let mut p = ideal_physics(&[start]);
    p.set_wheels(0, 24.0, -24.0);
    run_s(&mut p, 1.0);
    let end = p.poses()[0];
    assert!(
        (end.heading_deg - (10.0 + 1f64.to_degrees())).abs() < 1e-6,
        "{end:?}"
    );
    assert!(start.distance_to(&end) < 1e-9);
    // The gyro saw the same turn, and says so through the firmware's interface.
    let h = p.gyro_mut(0).update(24.0, -24.0, FRAME_DT_S as f32);
    assert!((f64::from(h) - end.heading_deg).abs() < 1e-3);
    // The other way round turns left.
    let mut p = ideal_physics(&[start]);
    p.set_wheels(0, -60.0, 60.0);
    run_s(&mut p, 0.5);
    let want = 10.0 - (120.0f64 / 48.0 * 0.5).to_degrees();
    assert!((p.poses()[0].heading_deg - want).abs() < 1e-6);
    // Left faster than right while driving: the path bends right (clockwise from above,
    // towards +y when heading +x).
    let mut p = ideal_physics(&[Pose::new(300.0, 300.0, 0.0)]);
    p.set_wheels(0, 110.0, 90.0);
    run_s(&mut p, 1.0);
    assert!(p.poses()[0].y_mm > 300.0 + 5.0);
}

#[test]
fn motor_lag_is_a_first_order_step_response() {
    let tau = 0.1;
    let motor = MotorParams {
        lag_s: tau,
        ..MotorParams::ideal()
    };
    let mut p = Physics::new(Arena::default(), 1);
    p.add_robot(Pose::new(300.0, 450.0, 0.0), motor, GyroParams::ideal());
    p.set_wheels(0, 100.0, 100.0);
    for (t, want) in [(tau, 63.212), (2.0 * tau, 86.466), (5.0 * tau, 99.326)] {
        while p.time_s() < t - 1e-9 {
            p.step();
        }
        let (l, r) = p.drive(0).speeds();
        assert!(
            (l - want).abs() < 0.05 && l == r,
            "at {t} s: {l}, want {want}"
        );
    }
    // Distance: v (t − τ (1 − e^(−t/τ))) after t = 0.5 s.
    let x = p.poses()[0].x_mm - 300.0;
    let want = 100.0 * (0.5 - tau * (1.0 - (-5.0f64).exp()));
    assert!((x - want).abs() < 0.1, "{x} mm, want {want}");
}

#[test]
fn head_on_robots_count_one_encounter_and_one_collision() {
    let mut p = ideal_physics(&[Pose::new(400.0, 450.0, 0.0), Pose::new(800.0, 450.0, 180.0)]);
    p.set_wheels(0, 100.0, 100.0);
    p.set_wheels(1, 100.0, 100.0);
    run_s(&mut p, 4.0);
    let c = p.counts();
    assert_eq!(
        (c.robot_robot.encounters, c.robot_robot.collisions),
        (1, 1),
        "{c:?}"
    );
    assert_eq!(c.robot_robot.success_rate(), Some(0.0));
    assert_eq!((c.robot_wall.encounters, c.wall_touches), (0, 0));
    // Pressed together, not through each other.
    let d = p.poses()[0].distance_to(&p.poses()[1]);
    assert!((d - ROBOT_DIAMETER_MM).abs() < 0.01, "{d}");
    assert!(p.poses()[0].x_mm < p.poses()[1].x_mm);
    // The collision began when the bodies met: 2 s in, 200 mm apart from each start − 21 mm.
    let first = p
        .contacts()
        .events()
        .iter()
        .find(|e| e.kind == alvs_sim::EventKind::Collision);
    let t = first.expect("a collision event").time_s;
    let want = (400.0 - ROBOT_COLLISION_DISTANCE_MM) / 200.0;
    assert!((t - want).abs() < 0.01, "collision at {t} s, want {want}");
    let enc = p.contacts().events()[0];
    let want = (400.0 - ROBOT_ENCOUNTER_DISTANCE_MM) / 200.0;
    assert!((enc.time_s - want).abs() < 0.01);
}

#[test]
fn passing_at_100_mm_is_an_encounter_without_collision() {
    let mut p = ideal_physics(&[Pose::new(400.0, 400.0, 0.0), Pose::new(800.0, 500.0, 180.0)]);
    p.set_wheels(0, 100.0, 100.0);
    p.set_wheels(1, 100.0, 100.0);
    run_s(&mut p, 5.0);
    let c = p.counts();
    assert_eq!(
        (c.robot_robot.encounters, c.robot_robot.collisions),
        (1, 0),
        "{c:?}"
    );
    assert_eq!(c.success_rate(), Some(1.0));
    assert!((p.poses()[0].x_mm - 900.0).abs() < 0.01 && (p.poses()[0].y_mm - 400.0).abs() < 1e-9);
}

#[test]
fn a_robot_driving_into_a_wall_collides_once_and_is_stopped() {
    for speed in [100.0, 300.0] {
        let mut p = ideal_physics(&[Pose::new(600.0, 450.0, 0.0)]);
        p.set_wheels(0, speed, speed);
        let mut max_x: f64 = 0.0;
        for _ in 0..(8.0 / FRAME_DT_S) as usize {
            p.step_frame();
            max_x = max_x.max(p.poses()[0].x_mm);
        }
        let c = p.counts();
        assert_eq!(
            (
                c.robot_wall.encounters,
                c.robot_wall.collisions,
                c.wall_touches
            ),
            (1, 1, 1),
            "{c:?}"
        );
        assert_eq!(c.robot_robot.encounters, 0);
        let wall_x = Arena::default().size_x_mm - ROBOT_RADIUS_MM;
        assert!(max_x <= wall_x + 1e-9, "went through the wall: {max_x}");
        assert!((p.poses()[0].x_mm - wall_x).abs() < 1e-9);
        // The paper's wall threshold is reached before contact.
        let ev = p.contacts().events();
        let col = ev
            .iter()
            .find(|e| e.kind == alvs_sim::EventKind::Collision)
            .unwrap();
        let want = (Arena::default().size_x_mm - WALL_COLLISION_DISTANCE_MM - 600.0) / speed;
        assert!((col.time_s - want).abs() < 0.01, "{} vs {want}", col.time_s);
    }
}

/// Three robots with every noise on, their cameras noisy: a digest of all frames and poses.
fn noisy_run(seed: u64) -> (Vec<Frame>, Vec<Pose>) {
    let world = World::with_texture(WallTexture::Clutter { seed: 3 });
    let r = Renderer::new(&world);
    let mut p = Physics::new(world.arena, seed);
    let starts = [
        Pose::new(300.0, 300.0, 20.0),
        Pose::new(800.0, 500.0, 170.0),
        Pose::new(600.0, 700.0, -100.0),
    ];
    let mut cams: Vec<Camera> = (0..3)
        .map(|i| Camera::new(SensorNoise::typical(), seed * 10 + i))
        .collect();
    for s in starts {
        p.add_robot(s, MotorParams::default(), GyroParams::default());
    }
    let mut frames = Vec::new();
    for k in 0..60 {
        for (i, cam) in cams.iter_mut().enumerate() {
            let mut f = [0u8; alvs_tasks::PIXELS];
            cam.capture(&r, p.poses(), i, &mut f);
            if k % 10 == 0 {
                frames.push(f);
            }
            let turn = if (k / 15 + i) % 2 == 0 { 20.0 } else { -20.0 };
            p.set_wheels(i, 100.0 + turn, 100.0 - turn);
        }
        p.step_frame();
    }
    let mut poses = p.poses().to_vec();
    poses.extend((0..3).map(|i| Pose::new(p.gyro(i).heading(), p.gyro(i).bias_deg_s(), 0.0)));
    (frames, poses)
}

#[test]
fn same_seed_same_run() {
    let (f1, p1) = noisy_run(5);
    let (f2, p2) = noisy_run(5);
    assert!(f1 == f2, "frames differ for the same seed");
    assert_eq!(p1, p2);
    let (f3, p3) = noisy_run(6);
    assert!(f1 != f3);
    assert_ne!(p1, p3);
}

fn save(c: &Canvas, path: &str) {
    c.save_png(path).unwrap();
    println!("wrote {path}");
}

fn frame_picture(f: &Frame) -> Canvas {
    frame_canvas(f, 4)
}

#[test]
#[ignore = "writes /tmp/arena_*.png for a visual check"]
fn example_pictures() {
    let stripes = World::with_texture(WallTexture::Stripes { period_mm: 40.0 });
    let r = Renderer::new(&stripes);
    let eye = Pose::new(400.0, 450.0, 0.0);
    let ahead = at_bearing(&eye, 0.0, 150.0);
    let right = at_bearing(&eye, 30.0, 250.0);
    save(
        &frame_picture(&r.render(&[eye, ahead], 0)),
        "/tmp/arena_stripes_ahead_150.png",
    );
    save(
        &frame_picture(&r.render(&[eye, right], 0)),
        "/tmp/arena_stripes_right_30.png",
    );
    save(
        &frame_picture(&r.render(&[eye, ahead, right, at_bearing(&eye, -20.0, 500.0)], 0)),
        "/tmp/arena_stripes_three.png",
    );
    let photo = alvs_host::data::photo_path(1);
    let outdoor = World::with_texture(WallTexture::from_spec(&photo.to_string_lossy()).unwrap());
    let r = Renderer::new(&outdoor);
    save(
        &frame_picture(&r.render(&[eye, ahead, right], 0)),
        "/tmp/arena_outdoor_1.png",
    );
    let corner = Pose::new(150.0, 150.0, -135.0);
    save(
        &frame_picture(&r.render(&[corner], 0)),
        "/tmp/arena_outdoor_1_corner.png",
    );
    let unrolled = r.wall_map().unrolled();
    let mut strip = Canvas::new(unrolled.width.min(1600), unrolled.height, [0; 3]);
    for (i, px) in strip.pixels.iter_mut().enumerate() {
        let (x, y) = (i % strip.width, i / strip.width);
        *px = [unrolled.pixels[y * unrolled.width + x]; 3];
    }
    save(&strip, "/tmp/arena_outdoor_1_walls.png");
    let clutter = World::default();
    let r = Renderer::new(&clutter);
    let noisy = {
        let mut cam = Camera::new(SensorNoise::typical(), 1);
        let mut f = [0u8; alvs_tasks::PIXELS];
        cam.capture(&r, &[eye, ahead, right], 0, &mut f);
        f
    };
    save(&frame_picture(&noisy), "/tmp/arena_clutter_noisy.png");
    let checker = World::with_texture(WallTexture::Checker { size_mm: 40.0 });
    let r = Renderer::new(&checker);
    save(
        &frame_picture(&r.render(
            &[Pose::new(600.0, 450.0, 30.0), Pose::new(700.0, 520.0, 0.0)],
            0,
        )),
        "/tmp/arena_checker.png",
    );
    // Top-down: three noisy robots wandering in circles for 20 s.
    let mut p = Physics::new(clutter.arena, 3);
    for s in [
        Pose::new(300.0, 300.0, 20.0),
        Pose::new(800.0, 500.0, 170.0),
        Pose::new(600.0, 700.0, -100.0),
    ] {
        p.add_robot(s, MotorParams::default(), GyroParams::default());
    }
    let mut trails = vec![Vec::new(); 3];
    for k in 0..600 {
        for (i, trail) in trails.iter_mut().enumerate() {
            let pose = p.poses()[i];
            trail.push((pose.x_mm, pose.y_mm));
            let turn = if (k / 90 + i) % 3 == 0 { 15.0 } else { 0.0 };
            p.set_wheels(i, 100.0 + turn, 100.0 - turn);
        }
        p.step_frame();
    }
    let mut td = TopDown::new(&clutter.arena, 0.5);
    let c = p.counts();
    td.title(&format!(
        "3 robots, 20 s: robot-robot {}/{} (collisions/encounters), wall {}/{}",
        c.robot_robot.collisions,
        c.robot_robot.encounters,
        c.robot_wall.collisions,
        c.robot_wall.encounters
    ));
    for (i, t) in trails.iter().enumerate() {
        td.trail(t, colour_cycle(i));
    }
    for e in p.contacts().events() {
        if e.kind == alvs_sim::EventKind::Collision {
            td.mark(e.x_mm, e.y_mm, RED);
        }
    }
    for (i, pose) in p.poses().iter().enumerate() {
        td.field_of_view(pose, 150.0, colour_cycle(i));
        td.robot(pose, colour_cycle(i));
    }
    save(&td.into_canvas(), "/tmp/arena_topdown.png");
}

#[test]
#[ignore = "micro-benchmark: cargo test --release ... -- --ignored --nocapture bench_render"]
fn bench_render() {
    for (name, world, noise) in [
        (
            "clutter, ideal camera",
            World::default(),
            SensorNoise::default(),
        ),
        (
            "clutter, noisy camera",
            World::default(),
            SensorNoise::typical(),
        ),
        (
            "stripes, ideal camera",
            World::with_texture(WallTexture::Stripes { period_mm: 40.0 }),
            SensorNoise::default(),
        ),
    ] {
        let r = Renderer::new(&world);
        let mut p = Physics::new(world.arena, 1);
        for s in [
            Pose::new(300.0, 300.0, 20.0),
            Pose::new(800.0, 500.0, 170.0),
            Pose::new(600.0, 700.0, -100.0),
        ] {
            p.add_robot(s, MotorParams::default(), GyroParams::default());
        }
        let mut cams: Vec<Camera> = (0..3).map(|i| Camera::new(noise, i)).collect();
        let mut f = [0u8; alvs_tasks::PIXELS];
        let mut sum = 0u64;
        let frames = 3 * 9000;
        let t0 = std::time::Instant::now();
        let mut render_time = std::time::Duration::ZERO;
        for k in 0..frames / 3 {
            let t = std::time::Instant::now();
            for (i, cam) in cams.iter_mut().enumerate() {
                cam.capture(&r, p.poses(), i, &mut f);
                sum += u64::from(f[k % alvs_tasks::PIXELS]);
            }
            render_time += t.elapsed();
            for i in 0..3 {
                let turn = if (k / 60 + i) % 3 == 0 { 30.0 } else { 0.0 };
                p.set_wheels(i, 100.0 + turn, 100.0 - turn);
            }
            p.step_frame();
        }
        let total = t0.elapsed();
        println!(
            "{name}: {frames} frames in {:.3} s rendering = {:.0} frames/s ({:.1} µs/frame); \
             with physics {:.3} s; 54,000 frames ≈ {:.2} s [{sum}]",
            render_time.as_secs_f64(),
            frames as f64 / render_time.as_secs_f64(),
            render_time.as_secs_f64() * 1e6 / frames as f64,
            total.as_secs_f64(),
            total.as_secs_f64() * 54_000.0 / frames as f64,
        );
    }
}

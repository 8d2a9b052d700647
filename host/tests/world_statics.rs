//! What the recorded arena added to the simulated world: obstacles (drawn, solid, counted as
//! the wall), the contact turn at walls and obstacles (and the gyro sensing it), the room seen
//! above low walls, the ribbed wall texture and the replica itself.
//!
//! `cargo test --target host-tuple -p alvs-host --test world_statics`.

use alvs_sim::kinematics::{PHYSICS_DT_S, TRACK_MM};
use alvs_sim::render::{column_of_bearing, row_of_height, CAMERA_FORWARD_MM, SKY_GREY};
use alvs_sim::world::ROBOT_RADIUS_MM;
use alvs_sim::{
    replica, Arena, GyroParams, MotorParams, Obstacle, Physics, Pose, Renderer, Room,
    SurfaceContact, WallTexture, World,
};
use alvs_tasks::WIDTH;

fn world_with(obstacles: Vec<Obstacle>, contact: SurfaceContact) -> World {
    World {
        obstacles,
        contact,
        ..World::default()
    }
}

/// The default contact without the wheels' slip: the friction turn alone, deterministic.
fn turn_only() -> SurfaceContact {
    SurfaceContact {
        slip_yaw: 0.0,
        ..SurfaceContact::default()
    }
}

fn physics(world: &World, start: Pose) -> Physics {
    let mut p = Physics::of_world(world, 1);
    p.add_robot(start, MotorParams::ideal(), GyroParams::ideal());
    p
}

fn run_s(p: &mut Physics, seconds: f64) {
    for _ in 0..(seconds / PHYSICS_DT_S).round() as usize {
        p.step();
    }
}

/// Driving at 80° into the right-hand wall (10° off square): the rigid wall only stops the
/// body, which keeps its heading and slides; with the contact turn it swings round parallel to
/// the wall and drives along it.
#[test]
fn a_wall_turns_a_body_that_slides_along_it() {
    let start = Pose::new(1100.0, 450.0, 10.0);
    for (contact, turned) in [(SurfaceContact::RIGID, false), (turn_only(), true)] {
        let w = world_with(Vec::new(), contact);
        let mut p = physics(&w, start);
        p.set_wheels(0, 100.0, 100.0);
        run_s(&mut p, 4.0);
        let end = p.poses()[0];
        assert!(
            (end.x_mm - (1200.0 - ROBOT_RADIUS_MM)).abs() < 1e-6,
            "at the wall"
        );
        if turned {
            assert!(
                (end.heading_deg - 90.0).abs() < 1.0,
                "parallel: {}",
                end.heading_deg
            );
            // ~2.8 s of the 4 s along the wall at up to 100 mm/s
            assert!(end.y_mm > 600.0, "slid along the wall to y = {}", end.y_mm);
        } else {
            assert!((end.heading_deg - 10.0).abs() < 1e-9, "{}", end.heading_deg);
            assert!(end.y_mm < 520.0, "crept at sin 10° · v: y = {}", end.y_mm);
        }
    }
}

/// Square on, nothing turns the body (an unstable balance the motors' noise breaks); facing
/// away from the wall it turns nothing either.
#[test]
fn square_on_and_facing_away_do_not_turn() {
    let w = world_with(Vec::new(), turn_only());
    let mut p = physics(&w, Pose::new(1100.0, 450.0, 0.0));
    p.set_wheels(0, 100.0, 100.0);
    run_s(&mut p, 3.0);
    assert_eq!(p.poses()[0].heading_deg, 0.0);
    let mut p = physics(&w, Pose::new(1195.0, 450.0, 170.0));
    p.set_wheels(0, -20.0, -20.0);
    run_s(&mut p, 1.0);
    assert_eq!(p.poses()[0].heading_deg, 170.0);
}

/// The gyro feels the turn a contact gives the body, so the firmware's heading follows it.
#[test]
fn the_gyro_senses_a_contact_turn() {
    let w = world_with(Vec::new(), SurfaceContact::default());
    let mut p = physics(&w, Pose::new(1100.0, 450.0, 20.0));
    p.set_wheels(0, 100.0, 100.0);
    run_s(&mut p, 4.0);
    let truth = p.poses()[0].heading_deg;
    assert!((truth - 90.0).abs() < 1.0, "turned parallel: {truth}");
    let sensed = p.gyro(0).heading();
    assert!((sensed - truth).abs() < 1e-6, "gyro {sensed} vs {truth}");
}

/// A body whose wheels push it square on into a wall rattles: the wheels' unequal slip turns
/// it at random, about `slip_yaw · blocked travel / track` per step, so its view does not
/// freeze; without slip, or with the wheels stopped, it stays exactly still.
#[test]
fn wheels_pushing_into_a_wall_rattle_the_body() {
    let pushing = |contact: SurfaceContact, wheels: f64| {
        let w = world_with(Vec::new(), contact);
        let mut p = physics(&w, Pose::new(1100.0, 450.0, 0.0));
        p.set_wheels(0, wheels, wheels);
        run_s(&mut p, 1.0);
        let mut headings = Vec::new();
        for _ in 0..30 {
            run_s(&mut p, 1.0 / 30.0);
            headings.push(p.poses()[0].heading_deg);
        }
        headings
    };
    let still = pushing(turn_only(), 100.0);
    assert!(still.iter().all(|&h| h == 0.0), "{still:?}");
    let rattle = SurfaceContact {
        turn_gain: 0.0,
        slip_yaw: 0.5,
    };
    let stopped = pushing(rattle, 0.0);
    assert!(stopped.iter().all(|&h| h == 0.0), "{stopped:?}");
    let h = pushing(rattle, 100.0);
    // Square on, a physics step blocks 100 mm/s · dt; a random walk of that many steps.
    let per_step_deg = (0.5 * 100.0 * PHYSICS_DT_S / TRACK_MM).to_degrees();
    let steps_per_frame = (1.0 / 30.0 / PHYSICS_DT_S).round();
    let frame_rms = per_step_deg * steps_per_frame.sqrt();
    let moves: Vec<f64> = h.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    let mean_move = moves.iter().sum::<f64>() / moves.len() as f64;
    assert!(
        mean_move > 0.3 * frame_rms && mean_move < 3.0 * frame_rms,
        "frame-to-frame turn {mean_move:.3}° vs random walk rms {frame_rms:.3}°"
    );
    // The gyro feels the rattle, as it feels every contact turn.
    let w = world_with(Vec::new(), rattle);
    let mut p = physics(&w, Pose::new(1150.0, 450.0, 0.0));
    p.set_wheels(0, 100.0, 100.0);
    run_s(&mut p, 2.0);
    let (truth, sensed) = (p.poses()[0].heading_deg, p.gyro(0).heading());
    assert!(
        truth != 0.0 && (sensed - truth).abs() < 1e-6,
        "{sensed} vs {truth}"
    );
}

/// An obstacle is solid (the centre stays one radius outside it), and a robot near it counts
/// as near the wall: its surface is part of "the arena wall" of the paper's counting.
#[test]
fn obstacles_are_solid_and_count_as_the_wall() {
    let o = Obstacle {
        x_mm: 600.0,
        y_mm: 450.0,
        radius_mm: 20.0,
        height_mm: 50.0,
    };
    let w = world_with(vec![o], SurfaceContact::RIGID);
    let mut p = physics(&w, Pose::new(400.0, 450.0, 0.0));
    p.set_wheels(0, 100.0, 100.0);
    run_s(&mut p, 4.0);
    let end = p.poses()[0];
    assert!(
        (end.x_mm - (600.0 - 20.0 - ROBOT_RADIUS_MM)).abs() < 1e-6,
        "{end:?}"
    );
    let c = p.counts();
    assert_eq!((c.robot_wall.encounters, c.robot_wall.collisions), (1, 1));
    assert_eq!(c.wall_touches, 1);
    assert_eq!(w.static_distance(end.x_mm, end.y_mm), ROBOT_RADIUS_MM);
}

/// An obstacle ahead is drawn between its silhouette's tangents, up to its height; the
/// columns beside it show the wall.
#[test]
fn an_obstacle_is_drawn_where_and_as_high_as_it_stands() {
    let eye = Pose::new(300.0, 450.0, 0.0);
    let (cx, _) = eye.offset(CAMERA_FORWARD_MM, 0.0);
    let (d, r, h) = (300.0, 40.0, 60.0);
    let o = Obstacle {
        x_mm: cx + d,
        y_mm: 450.0,
        radius_mm: r,
        height_mm: h,
    };
    let plain = |obstacles| World {
        texture: WallTexture::Plain(200),
        obstacles,
        obstacle_pattern: alvs_sim::RobotPattern::Band {
            body: 10,
            band: 10,
            bottom_mm: 0.0,
            top_mm: 0.0,
        },
        ..World::default()
    };
    let with = Renderer::new(&plain(vec![o])).render(&[eye], 0);
    let without = Renderer::new(&plain(Vec::new())).render(&[eye], 0);
    let half = (r / d).asin().to_degrees();
    let (c_l, c_r) = (column_of_bearing(-half), column_of_bearing(half));
    let row = 36; // just below the horizon: the obstacle's middle
    for c in 0..WIDTH {
        let (a, b) = (with[row * WIDTH + c], without[row * WIDTH + c]);
        let inside = (c as f64) > c_l + 1.0 && (c as f64) < c_r - 1.0;
        let outside = (c as f64) < c_l - 1.0 || (c as f64) > c_r + 1.0;
        if inside {
            assert!(a < 30, "column {c}: {a}");
        } else if outside {
            assert_eq!(a, b, "column {c}");
        }
    }
    // Its top: the front of the cylinder is at d − r.
    let top = row_of_height(h, d - r);
    let c = 49;
    let above = (top - 1.5).floor() as usize;
    let below = (top + 1.5).ceil() as usize;
    assert_eq!(with[above * WIDTH + c], without[above * WIDTH + c]);
    assert!(with[below * WIDTH + c] < 30);
}

/// Above low walls the camera sees the room (its texture), and above the room's walls the
/// ceiling; without a room, the uniform bright lab.
#[test]
fn the_room_shows_above_low_walls() {
    let low = |room| World {
        wall_height_mm: 40.0,
        texture: WallTexture::Plain(200),
        room,
        ..World::default()
    };
    let eye = Pose::new(600.0, 450.0, 0.0);
    let bare = Renderer::new(&low(None)).render(&[eye], 0);
    let room = Room {
        margin_mm: 500.0,
        height_mm: 800.0,
        texture: WallTexture::Plain(60),
    };
    let with = Renderer::new(&low(Some(room))).render(&[eye], 0);
    let (cx, _) = eye.offset(CAMERA_FORWARD_MM, 0.0);
    let to_wall = 1200.0 - cx;
    let wall_top = row_of_height(40.0, to_wall);
    let room_top = row_of_height(800.0, to_wall + 500.0);
    let c = 49;
    let between = ((room_top + wall_top) / 2.0) as usize;
    assert_eq!(f32::from(bare[between * WIDTH + c]), SKY_GREY);
    assert_eq!(with[between * WIDTH + c], 60, "room at row {between}");
    let ceiling = (room_top - 2.0).floor();
    if ceiling >= 0.0 {
        assert_eq!(f32::from(with[ceiling as usize * WIDTH + c]), SKY_GREY);
    }
}

#[test]
fn ribs_parse_and_alternate() {
    assert_eq!(
        WallTexture::from_spec("ribs:6:100:200").unwrap(),
        WallTexture::Ribs {
            period_mm: 6.0,
            dark: 100,
            light: 200
        }
    );
    assert_eq!(WallTexture::from_spec("ribs").unwrap(), replica::WALL_RIBS);
    for bad in ["ribs:0", "ribs:5:1", "ribs:5:1:300", "ribs:x"] {
        assert!(WallTexture::from_spec(bad).is_err(), "{bad}");
    }
    let w = World::with_texture(WallTexture::Ribs {
        period_mm: 8.0,
        dark: 100,
        light: 200,
    });
    let tex = alvs_sim::texture::WallMap::new(&w).unrolled();
    let row = &tex.pixels[tex.width * 10..tex.width * 10 + 16];
    // 1 mm texels: a groove at u = 0 and 8, a rib at u = 4 and 12.
    assert!(row[0] < 110 && row[8] < 110, "{row:?}");
    assert!(row[4] > 190 && row[12] > 190, "{row:?}");
}

/// The replica is the measured arena: its size, wall and obstacle heights and the obstacles
/// found in the snapshots agree with host/data/fu2019/arena.json.
#[test]
fn the_replica_matches_the_measured_arena() {
    let m = alvs_host::recordings::arena().expect("committed arena.json");
    let w = replica::world();
    assert!((w.arena.size_x_mm - m.size_x_mm).abs() < 1.0);
    assert!((w.arena.size_y_mm - m.size_y_mm).abs() < 1.0);
    assert!((w.wall_height_mm - m.wall_height_mm).abs() < 1.0);
    let h = m.obstacle_height_mm.expect("measured obstacle height");
    assert_eq!(m.obstacles.len(), replica::MEASURED_OBSTACLES);
    for (o, found) in w.obstacles.iter().zip(&m.obstacles) {
        assert!((o.x_mm - found.x_mm).abs() < 1.0 && (o.y_mm - found.y_mm).abs() < 1.0);
        assert!((2.0 * o.radius_mm - m.obstacle_diameter_mm).abs() < 1.0);
        assert!((o.height_mm - h).abs() < 1.0);
    }
    // The two placed by symmetry stand where no measured one does.
    for o in &w.obstacles[replica::MEASURED_OBSTACLES..] {
        let nearest = m
            .obstacles
            .iter()
            .map(|f| (o.x_mm - f.x_mm).hypot(o.y_mm - f.y_mm))
            .fold(f64::INFINITY, f64::min);
        assert!(nearest > 200.0, "{o:?} is {nearest} mm from a measured one");
    }
}

/// The replica's obstacles stand inside the arena and leave room to drive between them.
#[test]
fn the_replica_is_a_drivable_arena() {
    let w = replica::world();
    let a: Arena = w.arena;
    assert!(!w.obstacles.is_empty());
    for o in &w.obstacles {
        assert!(a.wall_distance(o.x_mm, o.y_mm) >= -1e-9, "{o:?} outside");
    }
    // Most of the floor is free.
    let mut free = 0;
    let n = 100;
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (
                (i as f64 + 0.5) * a.size_x_mm / n as f64,
                (j as f64 + 0.5) * a.size_y_mm / n as f64,
            );
            free += usize::from(w.static_distance(x, y) > ROBOT_RADIUS_MM);
        }
    }
    assert!(free > n * n * 8 / 10, "{free} of {}", n * n);
}

/// A shaking camera's picture moves up and down from frame to frame while its body moves (the
/// wall's top edge changes row), never while it stands; without shake a moving camera's
/// picture of the same pose is the steady one.
#[test]
fn a_moving_camera_shakes_and_a_standing_one_does_not() {
    use alvs_sim::{Camera, SensorNoise};
    let w = World::default();
    let r = Renderer::new(&w);
    let (from, to) = (
        [Pose::new(600.0, 450.0, 0.0)],
        [Pose::new(600.5, 450.0, 0.0)],
    );
    let shaky = SensorNoise {
        shake_deg: 1.0,
        ..SensorNoise::default()
    };
    let column = |f: &[u8]| {
        (0..alvs_tasks::HEIGHT)
            .map(|y| f[y * WIDTH + 49])
            .collect::<Vec<_>>()
    };
    let shots = |noise: SensorNoise, from: &[Pose], to: &[Pose]| {
        let mut cam = Camera::new(noise, 3);
        (0..8)
            .map(|_| {
                let mut f = [0u8; alvs_tasks::PIXELS];
                cam.capture_moving(&r, from, to, 0, &mut f);
                column(&f)
            })
            .collect::<Vec<_>>()
    };
    let mut steady = [0u8; alvs_tasks::PIXELS];
    Camera::ideal().capture(&r, &to, 0, &mut steady);
    let steady = column(&steady);
    assert!(shots(SensorNoise::default(), &from, &to)
        .iter()
        .all(|c| *c == steady));
    assert!(shots(shaky, &to, &to).iter().all(|c| *c == steady));
    let moving = shots(shaky, &from, &to);
    let differing = moving.iter().filter(|c| **c != steady).count();
    assert!(differing >= 6, "{differing} of 8 shaken frames differ");
}

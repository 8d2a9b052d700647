//! The swarm's look (`Params::look_change`, `alvs_tasks::model::closed_loop::movers`) on rendered views
//! with the camera's noise: a standing robot finds another robot that spins or drives, at its
//! bearing, and nothing in a still scene of walls and standing robots.
//!
//! `cargo test --target host-tuple -p alvs-host --test swarm_look`.

use alvs_sim::render::CAMERA_FORWARD_MM;
use alvs_sim::{Camera, Pose, Renderer, SensorNoise, WallTexture, World};
use alvs_tasks::model::closed_loop::movers::{Movers, Sighting, SETTLE_FRAMES, SPAN_FRAMES};
use alvs_tasks::Params;

/// A viewer in the arena's middle, facing +x.
fn eye() -> Pose {
    Pose::new(600.0, 450.0, 0.0)
}

/// Where a robot at `bearing_deg` and `distance_mm` from the viewer's camera stands.
fn at_bearing(eye: &Pose, bearing_deg: f64, distance_mm: f64, heading_deg: f64) -> Pose {
    let (cx, cy) = eye.offset(CAMERA_FORWARD_MM, 0.0);
    let a = (eye.heading_deg + bearing_deg).to_radians();
    Pose::new(
        cx + distance_mm * a.cos(),
        cy + distance_mm * a.sin(),
        heading_deg,
    )
}

/// The first look of a robot standing at `viewer` (index 0 of the bodies), the other bodies
/// at frame `i` given by `others(i)`, through a noisy camera.
fn first_look(world: &World, others: impl Fn(usize) -> Vec<Pose>) -> Sighting {
    let r = Renderer::new(world);
    let mut cam = Camera::new(SensorNoise::typical(), 7);
    let mut movers = Movers::new();
    let change = alvs_tasks::model::param_table::off0(Params::default().swarm.look_change);
    let mut frame = [0u8; alvs_tasks::PIXELS];
    for i in 0..usize::from(SETTLE_FRAMES + SPAN_FRAMES) {
        let mut bodies = vec![eye()];
        bodies.extend(others(i));
        cam.capture(&r, &bodies, 0, &mut frame);
        if let Some(s) = movers.step(&frame, true, change) {
            return s;
        }
    }
    panic!("a standing robot must look once the settle and the span have passed");
}

fn column_near(s: Sighting, bearing_deg: f32) {
    let b = s.bearing_deg().unwrap_or_else(|| panic!("no mover: {s:?}"));
    assert!((b - bearing_deg).abs() <= 4.0, "{b} against {bearing_deg}");
}

#[test]
fn a_spinning_robot_is_a_mover_at_its_bearing() {
    // (700 mm away its 11 mm stripes are a pixel wide or less, and a spin shows nothing)
    for (bearing, distance) in [(10.0, 200.0), (20.0, 300.0), (-10.0, 400.0), (-25.0, 500.0)] {
        let s = first_look(&World::default(), |i| {
            // spinning at 180°/s, the swarm's spin
            vec![at_bearing(&eye(), bearing, distance, 6.0 * i as f64)]
        });
        column_near(s, bearing as f32);
    }
}

#[test]
fn a_driving_robot_is_a_mover_on_the_photographs_walls_too() {
    let photo = WallTexture::from_spec(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../data/photos/outdoor_1.jpg"
    ))
    .expect("the photograph");
    for world in [World::default(), World::with_texture(photo)] {
        // crossing the view 400 mm ahead at 100 mm/s
        let s = first_look(&world, |i| {
            let p = at_bearing(&eye(), -15.0, 400.0, 90.0);
            vec![Pose::new(p.x_mm, p.y_mm + 100.0 * i as f64 / 30.0, 90.0)]
        });
        let b = s.bearing_deg().expect("a mover");
        // it moved from −15° towards the right during the look
        assert!((-16.0..=0.0).contains(&b), "{b}");
    }
}

#[test]
fn walls_and_standing_robots_are_nothing() {
    for texture in [
        WallTexture::Plain(200),
        WallTexture::Checker { size_mm: 40.0 },
        World::default().texture,
    ] {
        let world = World::with_texture(texture);
        let s = first_look(&world, |_| {
            vec![
                at_bearing(&eye(), 10.0, 250.0, 30.0),
                at_bearing(&eye(), -20.0, 150.0, 0.0),
            ]
        });
        assert_eq!(s, Sighting::Nothing);
    }
}

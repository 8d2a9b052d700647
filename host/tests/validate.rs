//! The calibrated contact of the recorded arena's replica (docs/world.md, "Calibration"): an
//! LGMD2 robot that reaches a wall or an obstacle gets away again, as the real one always
//! does, because its wheels' slip rattles its view; with the wheels slipping alike (the model
//! before the calibration) it stays pressed, seeing a frozen picture.
//!
//! `cargo test --target host-tuple -p alvs-host --test validate`.

use alvs_host::experiments::validate::sim::simulate;
use alvs_sim::{replica, CameraMount, SensorNoise, SurfaceContact, World};

fn replica_with_slip(slip_yaw: f64) -> World {
    let w = replica::world();
    World {
        contact: SurfaceContact {
            slip_yaw,
            ..w.contact
        },
        ..w
    }
}

/// Two simulated minutes at the 10.9 cm/s runs' mean path speed, seeds 1–3 (tuning seeds).
#[test]
fn a_robot_at_a_wall_gets_away_with_the_calibrated_slip_and_not_without() {
    for seed in 1..=3 {
        let calibrated = simulate(
            &replica::world(),
            140.0,
            120.0,
            seed,
            SensorNoise::typical(),
            CameraMount::default(),
            None,
        );
        let frozen = simulate(
            &replica_with_slip(0.0),
            140.0,
            120.0,
            seed,
            SensorNoise::typical(),
            CameraMount::default(),
            None,
        );
        let per_min = |alerts: u64| alerts as f64 / 2.0;
        assert!(
            calibrated.pressed_share < 0.6 && per_min(calibrated.alerts) > 8.0,
            "seed {seed}: calibrated pressed {:.2}, {:.1} alerts/min",
            calibrated.pressed_share,
            per_min(calibrated.alerts)
        );
        assert!(
            frozen.pressed_share > 0.5 && frozen.pressed_share > calibrated.pressed_share + 0.3,
            "seed {seed}: without slip pressed {:.2} (calibrated {:.2})",
            frozen.pressed_share,
            calibrated.pressed_share
        );
    }
}

/// Driving straight at the replica's ribbed wall at the fastest run's speed, the LGMD2 alerts
/// before touching in most approaches, at gaps like the real robot's turns (38–77 mm median
/// gap, centre to wall minus one radius, over the seven runs).
#[test]
fn straight_approaches_alert_at_the_real_turns_distances() {
    use alvs_host::experiments::validate::approach::approaches;
    let row = &approaches(&replica::world(), CameraMount::default(), &[159.0])[0];
    assert!(
        row.alerted * 3 >= row.approaches * 2,
        "{} of {}",
        row.alerted,
        row.approaches
    );
    let gap = row.median_gap_mm.expect("some alerted");
    assert!((38.0..=77.0).contains(&gap), "median gap {gap} mm");
}

/// Square on at the slowest run's speed the LGMD2 does not see the replica's bright wall coming
/// at all, and at the next slowest it misses some of it (docs/world.md, "What is left": 0 and
/// 3 of 5 approaches alerted, against 5 of 5 at the fastest): the real robots turn as far from
/// it at every speed.
#[test]
fn slow_square_on_approaches_go_unseen() {
    use alvs_host::experiments::validate::approach::{approaches, ANGLES_DEG};
    assert_eq!(ANGLES_DEG[0], 90.0);
    let rows = approaches(&replica::world(), CameraMount::default(), &[84.0, 51.0]);
    let square_on: Vec<usize> = rows.iter().map(|r| r.alerted_by_angle[0]).collect();
    let per_angle = rows[0].approaches / ANGLES_DEG.len();
    assert!(square_on[0] < per_angle, "{square_on:?}");
    assert_eq!(square_on[1], 0, "{square_on:?}");
}

/// The diagnostic `--proximity-mm`: a forward proximity sensor 30 mm deep keeps a slow LGMD2
/// robot off the walls that its vision misses (two simulated minutes at the 3.5 cm/s run's
/// speed, tuning seeds).
#[test]
fn a_proximity_sensor_keeps_a_slow_robot_off_the_walls() {
    for seed in 1..=2 {
        let run = |proximity| {
            simulate(
                &replica::world(),
                84.0,
                120.0,
                seed,
                SensorNoise::typical(),
                CameraMount::default(),
                proximity,
            )
            .pressed_share
        };
        let (with, without) = (run(Some(30.0)), run(None));
        assert!(
            with < 0.03 && without > 0.1,
            "seed {seed}: pressed {with:.3} with the sensor, {without:.3} without"
        );
    }
}

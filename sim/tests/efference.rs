//! Efference copy of turns (`Params::derotate`, `alvs_tasks::model::closed_loop::derotate`) on the arena's
//! rendered camera: a robot turning in place on a still scene.

use alvs_sim::render::Renderer;
use alvs_sim::world::{Pose, WallTexture, World};
use alvs_tasks::model::params::{Efference, Mechanisms, ShortGates};
use alvs_tasks::{Network, Params};
use core::num::NonZeroU8;

/// Mean `on + off` of the newest means, grey levels per pixel.
fn change(net: &Network) -> f64 {
    let cells = net.maps().cells;
    let s: u64 = cells
        .iter()
        .map(|c| u64::from(c & 0xFF) + u64::from((c >> 8) & 0xFF))
        .sum();
    s as f64 / cells.len() as f64
}

/// Turns in place at `deg_s` for 36 frames from (600, 450) mm facing 10°, the network told
/// each frame's turn; returns (mean change, peak ΣLPLC2, alert frames) over the frames after
/// the first 6 (priming and warm-up).
fn turn(derotate: u8, deg_s: f64, texture: &str) -> (f64, u32, u32) {
    let world = World::with_texture(WallTexture::from_spec(texture).unwrap());
    let r = Renderer::new(&world);
    let mut net = Network::new(Params {
        efference: Efference {
            derotate: derotate != 0,
            ..Params::ALVS.efference
        },
        ..Params::ALVS
    })
    .unwrap();
    let (mut sum, mut peak, mut alerts, mut n) = (0.0, 0, 0, 0);
    let step = deg_s / 30.0;
    for i in 0..36 {
        let pose = Pose::new(600.0, 450.0, 10.0 + step * i as f64);
        if i > 0 {
            assert!(net.turned(step as f32));
        }
        let p = net.step(&r.render(&[pose], 0));
        if i > 5 {
            sum += change(&net);
            peak = peak.max(p.vm.lplc2_sum);
            alerts += u32::from(p.vm.alert);
            n += 1;
        }
    }
    (sum / f64::from(n), peak, alerts)
}

#[test]
fn a_turn_in_place_leaves_a_fraction_of_its_motion_signal() {
    for tex in ["clutter:1", "stripes:40", "checker:60"] {
        for rate in [45.0, 90.0, 180.0, 360.0] {
            let (c0, p0, a0) = turn(0, rate, tex);
            let (c1, p1, a1) = turn(1, rate, tex);
            println!("{tex} {rate}°/s: change {c0:.1} -> {c1:.1}, peak ΣLPLC2 {p0} -> {p1}, alerts {a0} -> {a1}");
            // what is left is the camera's sideways motion (19 mm ahead of the axis) and
            // interpolation
            assert!(c1 < 0.4 * c0, "{tex} {rate}: change {c0} -> {c1}");
            assert!(p1 < p0 / 10, "{tex} {rate}: ΣLPLC2 {p0} -> {p1}");
            assert!(a0 >= 24, "without it the turn alerts: {a0}");
            if tex == "clutter:1" && rate <= 180.0 {
                assert!(p1 < Params::ALVS.table1.t_s, "no short mode: {p1}");
            }
        }
    }
}

#[test]
fn the_paper_model_ignores_turns_and_a_half_frame_refuses_one() {
    let world = World::default();
    let r = Renderer::new(&world);
    let frame = r.render(&[Pose::new(600.0, 450.0, 0.0)], 0);
    let mut paper = Network::new(Params::PAPER).unwrap();
    paper.step(&frame);
    let other = paper.clone();
    assert!(paper.turned(10.0));
    assert_eq!(
        paper.digest(),
        other.digest(),
        "the paper's model: nothing moves"
    );
    let mut alvs = Network::new(Params::ALVS).unwrap();
    alvs.step(&frame);
    let before = alvs.digest();
    assert!(alvs.turned(10.0));
    assert_ne!(alvs.digest(), before, "the memory was re-registered");
    // half a frame in: refused, nothing changes
    alvs.push_row(frame[..alvs_tasks::WIDTH].try_into().unwrap())
        .unwrap();
    let mid = alvs.digest();
    assert!(!alvs.turned(10.0));
    assert_eq!(alvs.digest(), mid);
    // too far to re-register: the next frame primes again
    alvs.abort_frame();
    alvs.step(&frame);
    assert!(alvs.turned(f32::NAN));
    assert_eq!(alvs.step(&frame).frame, 0, "primes again");
}

/// `Params::q_grow_pct` compares a field's quadrant sum with its sum at the same place: a turn
/// moves the place with the view, so it is not a jump, while recentring onto something else
/// is ([`alvs_tasks::model::lplc2::GROW_SHIFT_PX`]).
#[test]
fn a_turn_moves_where_each_field_drive_was_measured() {
    let world = World::default();
    let r = Renderer::new(&world);
    let mut net = Network::new(Params::ALVS).unwrap();
    let mut moved = 0;
    for i in 0..12 {
        if i > 0 {
            let before: Vec<(u8, u8)> = net.fields().iter().map(|f| (f.x, f.y)).collect();
            assert!(net.turned(5.0));
            for (f, b) in net.fields().iter().zip(before) {
                assert_eq!(f.shift_since_drive(), 0, "field {} left its drive", f.id);
                moved += usize::from((f.x, f.y) != b);
            }
        }
        net.step(&r.render(&[Pose::new(600.0, 450.0, 5.0 * i as f64)], 0));
        for f in net.fields().iter() {
            assert_eq!(
                f.drive_at,
                (f.x, f.y),
                "a frame measures the drive where it is"
            );
        }
    }
    assert!(moved > 5, "fields the turns moved: {moved}");
}

/// `Params::t_a_quiet`: a standing robot on plain walls sees a robot driving at it (100 mm/s
/// from 500 mm, dead ahead). Its edges grow by a fraction of a pixel a frame, so their
/// salience stays under Table I's `T_a` until the robot is close; in a scene where nothing
/// else changes the threshold is lower and the first alert comes earlier (143 against 123 mm
/// when measured).
#[test]
fn a_quiet_scene_lowers_the_attention_threshold() {
    let world = World::with_texture(WallTexture::from_spec("plain:200").unwrap());
    let r = Renderer::new(&world);
    let first_alert = |p: Params| {
        let mut net = Network::new(p).unwrap();
        (0..140).find_map(|i| {
            let d = 500.0 - 100.0 * f64::from(i) / 30.0;
            let obstacle = Pose::new(450.0 + d, 450.0, 180.0);
            let out = net.step(&r.render(&[Pose::new(450.0, 450.0, 0.0), obstacle], 0));
            out.vm.alert.then_some(d)
        })
    };
    let quiet = first_alert(Params::ALVS).expect("alerts");
    let table_i = first_alert(Params {
        mechanisms: Mechanisms {
            t_a_quiet: None,
            ..Params::ALVS.mechanisms
        },
        ..Params::ALVS
    })
    .expect("alerts");
    println!("first alert at {quiet:.0} mm (T_a {table_i:.0} mm)");
    assert!(quiet > table_i + 10.0, "{quiet} against {table_i}");
}

/// A dark square centred at `(49, cy)` growing from 4 to 40 px over 24 frames on mid-grey:
/// the number of alert frames of a network told before each frame that it drives at
/// `forward_mm_s`.
fn looming_alerts(cy: usize, forward_mm_s: f32) -> u32 {
    looming(49, cy, forward_mm_s).0
}

/// The same square centred at `(cx, cy)`: (alert frames, short-mode frames). The floor line
/// and the foot's row for the short mode are off (the square has no floor below it).
fn looming(cx: usize, cy: usize, forward_mm_s: f32) -> (u32, u32) {
    looming_with(cx, cy, forward_mm_s, 0)
}

/// [`looming`] with `Params::short_row` = `short_row`, on a floor (the mid-grey ground). The
/// option `Params::short_cols` is on, at the 23 columns it had in the default.
fn looming_with(cx: usize, cy: usize, forward_mm_s: f32, short_row: u8) -> (u32, u32) {
    use alvs_tasks::{HEIGHT, PIXELS, WIDTH};
    let mut net = Network::new(Params {
        efference: Efference {
            band_row: NonZeroU8::new(27),
            floor_row: None,
            ..Params::ALVS.efference
        },
        short: ShortGates {
            short_cols: NonZeroU8::new(23),
            short_row: NonZeroU8::new(short_row),
            ..Params::ALVS.short
        },
        ..Params::ALVS
    })
    .unwrap();
    let (mut alerts, mut short) = (0, 0);
    for i in 0..24 {
        let half = 2 + (18 * i) / 23;
        let mut f = [128u8; PIXELS];
        for y in cy.saturating_sub(half)..(cy + half).min(HEIGHT) {
            for x in cx.saturating_sub(half)..(cx + half).min(WIDTH) {
                f[y * WIDTH + x] = 30;
            }
        }
        net.driving(forward_mm_s);
        let vm = net.step(&f).vm;
        alerts += u32::from(vm.alert);
        short += u32::from(vm.short_mode);
    }
    (alerts, short)
}

#[test]
fn driving_only_a_threat_in_the_path_is_imminent() {
    // `Params::short_cols` 23: the square 33 columns right of the centre, then in the path
    let (off_standing, off_driving) = (looming(82, 40, 0.0), looming(82, 40, 100.0));
    let (on_standing, on_driving) = (looming(60, 40, 0.0), looming(60, 40, 100.0));
    println!("off {off_standing:?} -> {off_driving:?}, on {on_standing:?} -> {on_driving:?}");
    assert_short_mode_held_back(off_standing, off_driving);
    assert!(on_standing.1 >= 2, "{on_standing:?}");
    assert_eq!(on_driving, on_standing, "in the path nothing changes");
}

/// Standing, the (alert frames, short-mode frames) of [`looming`] include the short mode;
/// driving, none of it, and the same alerts.
fn assert_short_mode_held_back(standing: (u32, u32), driving: (u32, u32)) {
    assert!(standing.1 >= 2, "standing, the short mode: {standing:?}");
    assert_eq!(driving.1, 0, "driving, not imminent: {driving:?}");
    assert_eq!(driving.0, standing.0, "the alerts stay");
}

/// `Params::short_row` 50: driving, a threat whose foot is far ahead (above row 50, more than
/// a second's travel) is not imminent; one whose foot reaches row 50 is, from then on.
#[test]
fn driving_only_a_threat_within_a_seconds_travel_is_imminent() {
    // centred on row 30: the square's lowest row reaches 49, never the row of 97 mm
    let (far_standing, far_driving) = (
        looming_with(49, 30, 0.0, 50),
        looming_with(49, 30, 100.0, 50),
    );
    // centred on row 44: its lowest row passes row 50 from the 8th of 24 frames
    let (near_standing, near_driving) = (
        looming_with(49, 44, 0.0, 50),
        looming_with(49, 44, 100.0, 50),
    );
    println!("far {far_standing:?} -> {far_driving:?}, near {near_standing:?} -> {near_driving:?}");
    assert_short_mode_held_back(far_standing, far_driving);
    assert!(near_standing.1 >= 2, "{near_standing:?}");
    assert!(
        near_driving.1 >= 1 && near_driving.1 < near_standing.1,
        "imminent once close enough, not before: {near_driving:?}"
    );
    // off the centre (X̄ in the path, its column searched for the foot) the same holds
    assert_short_mode_held_back(
        looming_with(60, 30, 0.0, 50),
        looming_with(60, 30, 100.0, 50),
    );
    assert!(looming_with(60, 44, 100.0, 50).1 >= 1);
    // off, the row changes nothing
    assert_eq!(looming_with(49, 30, 100.0, 0), far_standing);
}

#[test]
fn driving_silences_the_fields_above_the_band_only() {
    let (high_standing, high_driving) = (looming_alerts(14, 0.0), looming_alerts(14, 100.0));
    let (low_standing, low_driving) = (looming_alerts(40, 0.0), looming_alerts(40, 100.0));
    println!("high {high_standing} -> {high_driving}, low {low_standing} -> {low_driving}");
    assert!(
        high_standing >= 8,
        "a standing robot sees it: {high_standing}"
    );
    assert_eq!(
        high_driving, 0,
        "driving, the scene above the band is its own flow"
    );
    assert!(low_standing >= 8, "{low_standing}");
    assert_eq!(low_driving, low_standing, "in the band nothing changes");
    // driving slower than DRIVING_MM_S is standing
    assert_eq!(looming_alerts(14, 10.0), high_standing);
}

/// Drives straight at the plain wall at y = 900 mm from `from` to `to` mm (centre to wall) at
/// 100 mm/s; per frame (distance, alert, X̄).
fn drive_at_wall(
    floor_row: u8,
    driving: bool,
    from: f64,
    to: f64,
) -> Vec<(f64, bool, Option<f32>)> {
    let world = World::with_texture(WallTexture::from_spec("plain:200").unwrap());
    let r = Renderer::new(&world);
    let mut net = Network::new(Params {
        efference: Efference {
            floor_row: NonZeroU8::new(floor_row),
            ..Params::ALVS.efference
        },
        ..Params::ALVS
    })
    .unwrap();
    let mut out = Vec::new();
    let mut d = from;
    while d >= to {
        net.driving(if driving { 100.0 } else { 0.0 });
        let p = net.step(&r.render(&[Pose::new(600.0, 900.0 - d, 90.0)], 0));
        out.push((d, p.vm.alert, p.vm.threat_x));
        d -= 100.0 / 30.0;
    }
    out
}

#[test]
fn driving_at_a_wall_the_floor_line_alerts_within_its_distance() {
    let driving = drive_at_wall(52, true, 300.0, 60.0);
    let first = driving.iter().find(|(_, a, _)| *a).map(|(d, _, _)| *d);
    println!("first alert at {first:?} mm");
    // row 52 lies 20·70/16.5 ≈ 85 mm ahead of the camera, which is 19 mm ahead of the centre
    let first = first.expect("the wall ahead alerts");
    assert!((90.0..=115.0).contains(&first), "{first} mm");
    for (d, alert, x) in &driving {
        if *d < first {
            assert!(*alert, "{d} mm: every closer frame alerts");
            assert!(
                x.is_some_and(|x| (x - 49.0).abs() <= 3.0),
                "{d} mm: dead ahead, {x:?}"
            );
        }
    }
    // standing, or with the mechanism off, the floor line says nothing
    for (floor_row, drives) in [(52, false), (0, true)] {
        let quiet = drive_at_wall(floor_row, drives, 300.0, 60.0);
        let alerts = quiet.iter().filter(|(_, a, _)| *a).count();
        assert!(
            alerts < first_alerts(&driving) / 2,
            "{floor_row} {drives}: {alerts}"
        );
    }
}

fn first_alerts(v: &[(f64, bool, Option<f32>)]) -> usize {
    v.iter().filter(|(_, a, _)| *a).count()
}

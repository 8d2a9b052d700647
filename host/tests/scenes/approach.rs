//! Approaching objects.

use super::*;

/// A dark square (40 on 200) expanding 1 px/frame per edge, half size 2 → 18 px, at the
/// left, centre and right of the field.
#[test]
fn dark_square_approaching_left_centre_and_right() {
    let bg = Canvas::plain(200.0);
    for cx in POSITIONS {
        let obj = Looming::square(cx, 36.0, 1.0, 40.0);
        let outs = run(&looming_scene(&bg, &[obj], 16));
        check_approach(&format!("dark square at x = {cx}"), &outs, &obj, 16);
    }
}

/// The same over a textured background (blocks of 150 ± 20), square at 20.
#[test]
fn dark_square_approaching_over_texture() {
    let bg = Canvas::textured(150.0, 20, 6, 7);
    for cx in POSITIONS {
        let obj = Looming::square(cx, 36.0, 1.0, 20.0);
        let outs = run(&looming_scene(&bg, &[obj], 16));
        check_approach(
            &format!("dark square over texture at x = {cx}"),
            &outs,
            &obj,
            16,
        );
    }
}

/// A bright square (220 on 20) seen by the ON channel alone (weight `w` = 0.25), expanding
/// 2 px/frame per edge, half size 2 → 18 px. (At 1 px/frame the ON channel cannot reach `T_a`:
/// see `slow_bright_approach_alerts` below.)
#[test]
fn bright_square_approaching_on_a_dark_background() {
    let bg = Canvas::plain(20.0);
    for cx in POSITIONS {
        let obj = Looming::square(cx, 36.0, 2.0, 220.0);
        let outs = run(&looming_scene(&bg, &[obj], 8));
        check_approach(&format!("bright square at x = {cx}"), &outs, &obj, 8);
    }
}

/// An approach is still seen, in the right place, through ±10 grey levels of sensor noise.
#[test]
fn approach_through_sensor_noise() {
    let bg = Canvas::plain(200.0);
    for (cx, seed) in [(20.0, 1), (49.0, 2), (78.0, 3)] {
        let obj = Looming::square(cx, 30.0, 1.0, 40.0);
        let outs = run(&add_noise(&looming_scene(&bg, &[obj], 16), 10, seed));
        check_approach(&format!("noisy dark square at x = {cx}"), &outs, &obj, 16);
    }
}

/// A dark disc of radius 10 cm approaching at constant speed from 2 m to 0.3 m (its image
/// grows hyperbolically, 4 → 27 px in radius): the alert starts well before the end, never
/// stops once started, `ΣLPLC2` and `S` grow towards contact and the threat is on the left.
#[test]
fn disc_approaching_at_constant_speed() {
    let bg = Canvas::plain(200.0);
    let cx = 32.0;
    for speed in [1.0, 2.0] {
        let outs = run(&looming_disc(&bg, cx, 36.0, 40.0, 0.1, speed, 2.0, 0.3));
        let name = format!("disc at {speed} m/s");
        report(&name, &outs);
        assert_eq!(alerts(&outs[..LEAD]), 0, "{name}");
        let first = outs.iter().position(|o| o.alert()).expect("no alert");
        let before_end = outs.len() - first;
        let d_first = 2.0 - speed * moving(first) / 30.0;
        println!("  first alert {before_end} frames before the end, at {d_first:.2} m");
        assert!(
            before_end >= 10,
            "{name}: first alert only {before_end} frames before the end"
        );
        assert!(
            outs[first..].iter().all(|o| o.alert()),
            "{name}: the alert drops out"
        );
        let (start, end) = (&outs[first].vm, &outs[outs.len() - 1].vm);
        println!(
            "  ΣLPLC2 {} → {}, S {} → {}",
            start.lplc2_sum, end.lplc2_sum, start.strength, end.strength
        );
        assert!(end.lplc2_sum > 10 * start.lplc2_sum, "{name}");
        assert!(end.strength > 0.99 && end.short_mode, "{name}");
        for o in &outs[first..] {
            let x = o.vm.threat_x.unwrap();
            assert!((x - cx).abs() <= 6.0, "{name}, frame {}: X̄ {x}", o.frame);
            assert!(
                o.vm.theta_long.unwrap() > 145.0,
                "{name}, frame {}",
                o.frame
            );
        }
    }
}

/// A bright square (235 on 20) expanding 1 px/frame: its ON salience (a 1 px edge,
/// `gain·w·contrast/3` ≤ 85) stays under Table I's `T_a` = 100, so the paper's model makes no
/// field at all (it was a known limitation). On a still scene the default's attention
/// threshold is lower (`Params::t_a_quiet`), and it alerts.
#[test]
fn slow_bright_approach_alerts() {
    let bg = Canvas::plain(20.0);
    let obj = Looming::square(49.0, 36.0, 1.0, 235.0);
    let frames = looming_scene(&bg, &[obj], 16);
    check_approach("slow bright square", &run(&frames), &obj, 16);
    let mut paper = Network::new(Params::PAPER).unwrap();
    let outs: Vec<Perception> = frames.iter().map(|f| paper.step(f)).collect();
    assert_eq!(alerts(&outs), 0, "the paper's T_a sees nothing");
    assert!(outs.iter().all(|o| o.afs.is_empty()), "no field");
}

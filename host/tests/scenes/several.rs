//! Several threats.

use super::*;

/// Fields stimulated in a frame, as (x, y).
fn stimulated(o: &Perception) -> Vec<(u8, u8)> {
    o.afs
        .iter()
        .filter(|a| a.lplc2 > 0)
        .map(|a| (a.x, a.y))
        .collect()
}

/// Whether every object has a stimulated field within 6 px of its centre.
fn each_has_a_field(o: &Perception, objs: &[Looming]) -> bool {
    let fields = stimulated(o);
    objs.iter().all(|b| {
        fields
            .iter()
            .any(|&(x, y)| (f32::from(x) - b.cx).abs() <= 6.0 && (f32::from(y) - b.cy).abs() <= 6.0)
    })
}

/// Two squares 68 px apart expanding together: two fields, one on each, stimulated at once
/// for most of the approach; the symmetric pair puts `X̄` straight ahead.
#[test]
fn two_simultaneous_approaches() {
    let bg = Canvas::plain(200.0);
    let objs = [
        Looming::square(15.0, 36.0, 1.0, 40.0),
        Looming::square(83.0, 36.0, 1.0, 40.0),
    ];
    let n = 12;
    let outs = run(&looming_scene(&bg, &objs, n));
    report("two squares", &outs);
    let both = outs.iter().filter(|o| each_has_a_field(o, &objs)).count();
    println!("  frames with a stimulated field on each square: {both}/{n}");
    if both < n / 2 {
        trace(&outs);
    }
    assert!(both >= n / 2, "{both}/{n}");
    assert!(outs.iter().all(|o| o.afs.len() <= 2));
    for o in outs.iter().filter(|o| stimulated(o).len() == 2) {
        let x = o.vm.threat_x.unwrap();
        assert!((x - CENTRE).abs() <= 3.0, "frame {}: X̄ {x}", o.frame);
    }
}

/// Three squares at the upper left, upper right and lower middle, more than R_AF + their
/// size apart: three fields stimulated at once.
#[test]
fn three_simultaneous_approaches() {
    let bg = Canvas::plain(200.0);
    let objs = [
        Looming::square(12.0, 12.0, 1.0, 40.0),
        Looming::square(86.0, 12.0, 1.0, 40.0),
        Looming::square(49.0, 62.0, 1.0, 40.0),
    ];
    let n = 8;
    let outs = run(&looming_scene(&bg, &objs, n));
    report("three squares", &outs);
    let all = outs.iter().filter(|o| each_has_a_field(o, &objs)).count();
    println!("  frames with a stimulated field on each square: {all}/{n}");
    if all < n / 2 {
        trace(&outs);
    }
    assert!(all >= n / 2, "{all}/{n}");
    for o in outs.iter().filter(|o| each_has_a_field(o, &objs)) {
        let x = o.vm.threat_x.unwrap();
        assert!((x - CENTRE).abs() <= 3.0, "frame {}: X̄ {x}", o.frame);
    }
}

/// Of two simultaneous approaches the faster (2 vs 0.5 px/frame) or the larger (closer: half
/// size 6 vs 2 px at the same 1 px/frame) pulls `X̄` to its side on at least 80 % of the alert
/// frames, whichever side it is on.
#[test]
fn the_closer_of_two_threats_dominates_the_centroid() {
    let bg = Canvas::plain(200.0);
    for (left, right) in [(15.0, 83.0), (83.0, 15.0)] {
        let fast = Looming::square(left, 36.0, 2.0, 40.0);
        let slow = Looming::square(right, 36.0, 0.5, 40.0);
        let large = Looming {
            h0: 6.0,
            ..Looming::square(left, 36.0, 1.0, 40.0)
        };
        let small = Looming::square(right, 36.0, 1.0, 40.0);
        for (what, objs) in [("faster", [fast, slow]), ("larger", [large, small])] {
            let outs = run(&looming_scene(&bg, &objs, 8));
            let name = format!("{what} square at x = {left}, other at {right}");
            report(&name, &outs);
            let xs: Vec<f32> = outs.iter().filter_map(|o| o.vm.threat_x).collect();
            let on_side = xs
                .iter()
                .filter(|&&x| (x < CENTRE) == (left < CENTRE))
                .count();
            println!("  X̄ on its side {on_side}/{}: {xs:.1?}", xs.len());
            assert!(xs.len() >= 5, "{name}");
            assert!(
                5 * on_side >= 4 * xs.len(),
                "{name}: {on_side}/{}",
                xs.len()
            );
        }
    }
}

//! The swarm variant: spin in place on approach.

use super::*;

#[test]
fn swarm_spins_in_place_and_never_escapes() {
    let p = params();
    let mut f = swarm_wander(0.0);
    // a burst of threats, short mode included, then calm
    let input = |i: usize| match i {
        5..=9 => long(LEFT_X),
        10..=19 => short(RIGHT_X),
        25 => long(RIGHT_X),
        _ => quiet(),
    };
    let run = closed_loop(&mut f, 0.0, 120, input);
    for (i, (c, _)) in run.iter().enumerate() {
        assert!(matches!(c.state, State::Wander | State::Spin), "{i}");
        assert_eq!(c.short_phase, None);
        if c.state == State::Spin {
            // in place, turning right at the spin rate
            let omega = (c.left_mm_s - c.right_mm_s) / p.track_mm;
            assert!((c.left_mm_s + c.right_mm_s).abs() < 1e-3);
            assert!((omega - p.spin_deg_s.to_radians()).abs() < 1e-3);
        } else {
            assert!(c.left_mm_s > 0.0 && c.right_mm_s > 0.0, "{i}");
        }
    }
    let spin: Vec<usize> = (0..run.len())
        .filter(|&i| run[i].0.state == State::Spin)
        .collect();
    // spins from the first alert until `spin_frames` after the last one, without a break
    let (first, last) = (spin[0], *spin.last().unwrap());
    assert_eq!(first, 5);
    assert_eq!(last, 25 + p.spin_frames as usize - 1);
    assert_eq!(spin.len(), last - first + 1);
    // it did turn: about (spin length) · rate
    let (_, h_end) = run[last];
    let (_, h_start) = run[first - 1];
    let turned = (spin.len() as f32) * p.spin_deg_s * DT;
    assert!(err(h_end, h_start + turned) < 1.0);
}

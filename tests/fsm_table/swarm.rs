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

#[test]
fn swarm_without_looks_never_looks_and_a_look_needs_look_every() {
    // the paper (`look_every` 0): 200 quiet frames of wandering
    let mut f = swarm_wander(0.0);
    assert!(closed_loop(&mut f, 0.0, 200, |_| quiet())
        .iter()
        .all(|(c, _)| c.state == State::Wander));
    // looks every 45 frames: wanders 44 more frames after the first, then stands to look
    let mut f = swarm_looking(45);
    let run = closed_loop(&mut f, 0.0, 60, |_| quiet());
    let first_look = run.iter().position(|(c, _)| c.state == State::Look);
    assert_eq!(first_look, Some(44));
    assert!(run[44..].iter().all(|(c, _)| stopped(c)));
}

#[test]
fn after_a_spin_the_robot_looks_and_heads_for_the_mover() {
    let p = params();
    let mut f = swarm_looking(1000);
    // an alert at frame 5, then a look that reports a mover on the right at frame 60
    let mover = Sighting::Mover { x: RIGHT_X };
    let run = closed_loop(&mut f, 0.0, 150, |i| match i {
        5 => long(LEFT_X),
        60 => saw(mover),
        _ => quiet(),
    });
    let spin_end = 5 + p.spin_frames as usize;
    assert!(run[5..spin_end].iter().all(|(c, _)| c.state == State::Spin));
    // the look follows the spin at once and stands while it looks
    assert!(run[spin_end..60]
        .iter()
        .all(|(c, _)| c.state == State::Look));
    assert!(run[spin_end + 5..60].iter().all(|(c, _)| stopped(c)));
    // then it wanders towards the mover's bearing (about 29° right of where it stood)
    let (stood, _) = run[59];
    let (c, _) = run[60];
    assert_eq!(c.state, State::Wander);
    let b = mover.bearing_deg().unwrap();
    assert!((b - 29.1).abs() < 0.2, "{b}");
    assert!(err(c.heading_setpoint_deg, stood.heading_setpoint_deg + b) < 0.5);
    let (_, h_end) = run[149];
    assert!(
        err(h_end, stood.heading_setpoint_deg + b) < tol(),
        "{h_end}"
    );
    assert!(c.left_mm_s > c.right_mm_s, "turning right while it drives");
}

#[test]
fn a_look_that_sees_nothing_turns_90_and_looks_again_up_to_look_scans_times() {
    let p = params();
    assert_eq!(p.look_scans, 3);
    let mut f = swarm_look(0.0);
    let mut odo = Odometry::new(p.track_mm, 0.0);
    let (mut looks, mut stood) = (Vec::new(), false);
    for _ in 0..400 {
        let h = odo.heading_deg();
        // the network reports nothing once the robot has stood a frame
        let vm = if stood && f.state() == State::Look {
            looks.push(h);
            saw(Sighting::Nothing)
        } else {
            quiet()
        };
        let c = f.step(&vm, h);
        stood = stopped(&c);
        odo.update(c.left_mm_s, c.right_mm_s, DT);
        if c.state == State::Wander {
            break;
        }
    }
    // four looks, each about 90° right of the last, then it wanders on
    assert_eq!(looks.len(), 4, "{looks:?}");
    for w in looks.windows(2) {
        assert!(err(w[1], w[0] + 90.0) <= p.align_tol_deg, "{looks:?}");
    }
    assert_eq!(f.state(), State::Wander);
}

#[test]
fn a_look_the_network_never_answers_ends_after_the_takeoff_timeout() {
    let p = params();
    let mut f = swarm_look(0.0);
    let run = closed_loop(&mut f, 0.0, 200, |_| quiet());
    let end = run.iter().position(|(c, _)| c.state == State::Wander);
    assert_eq!(end, Some(p.takeoff_timeout_frames as usize - 1));
}

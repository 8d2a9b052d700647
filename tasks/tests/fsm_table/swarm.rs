//! The swarm variant: spin in place on approach.

use super::*;
use alvs_tasks::model::param_table::off0;

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
            let omega = (c.left_mm_s - c.right_mm_s) / p.motion.track_mm;
            assert!((c.left_mm_s + c.right_mm_s).abs() < 1e-3);
            assert!((omega - p.swarm.spin_deg_s.to_radians()).abs() < 1e-3);
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
    assert_eq!(last, 25 + p.swarm.spin_frames as usize - 1);
    assert_eq!(spin.len(), last - first + 1);
    // it did turn: about (spin length) · rate
    let (_, h_end) = run[last];
    let (_, h_start) = run[first - 1];
    let turned = (spin.len() as f32) * p.swarm.spin_deg_s * DT;
    assert!(err(h_end, h_start + turned) < 1.0);
}

#[test]
fn swarm_without_looks_never_looks_and_a_look_needs_look_every() {
    // the paper (`look_every` 0): 200 quiet frames of wandering
    let mut f = swarm_wander(0.0);
    assert!(closed_loop(&mut f, 0.0, 200, |_| quiet())
        .iter()
        .all(|(c, _)| c.state == State::Wander));
    // looks every 45 frames: the first step latches the heading and counts, so the first look
    // starts on the 45th step, after 44 frames of wandering (later ones after 45)
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
    let spin_end = 5 + p.swarm.spin_frames as usize;
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
    assert_eq!(p.swarm.look_scans, 3);
    let mut f = swarm_look(0.0);
    let mut odo = Odometry::new(p.motion.track_mm, 0.0);
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
    // four looks 90° apart (each within the alignment tolerance of its direction, the
    // shortfalls not adding up), then it wanders on
    assert_eq!(looks.len(), 4, "{looks:?}");
    for (k, h) in looks.iter().enumerate() {
        assert!(
            err(*h, looks[0] + 90.0 * k as f32) <= p.motion.align_tol_deg,
            "{looks:?}"
        );
    }
    assert_eq!(f.state(), State::Wander);
}

#[test]
fn a_look_nothing_answers_ends_after_its_own_timeout() {
    // the escape's takeoff timeout does not shorten a look
    let mut f = Fsm::new(
        FsmParams {
            swarm: Swarm {
                look_every: NonZeroU32::new(1),
                ..params().swarm
            },
            timing: Timing {
                takeoff_timeout_frames: 20,
                ..params().timing
            },
            ..params()
        },
        Behaviour::Swarm,
    );
    let run = closed_loop(&mut f, 0.0, 200, |_| quiet());
    assert_eq!(run[0].0.state, State::Look);
    let end = run.iter().position(|(c, _)| c.state == State::Wander);
    assert_eq!(end, Some(LOOK_TIMEOUT_FRAMES as usize));
}

/// The default's swarm FSM (saccadic suppression on) with the look beside it, in closed loop
/// with odometry, in a still scene with one small object that jiggles (a mover) behind the
/// robot: the looks go round until the object is in view, and the robot sets off towards it.
#[test]
fn the_default_swarm_finds_a_mover_behind_it_by_looking_round() {
    let p = FsmParams::default();
    let mover_deg = 200.0f32;
    let mut f = Fsm::new(p, Behaviour::Swarm);
    let mut movers = Movers::new();
    let mut odo = Odometry::new(p.motion.track_mm, 0.0);
    let (mut standing, mut states) = (false, Vec::new());
    for i in 0..400usize {
        let h = odo.heading_deg();
        // the object's column from the heading, 2 columns to and fro every 4 frames
        let mut frame = [120u8; PIXELS];
        let rel = wrap_deg(mover_deg - h).to_radians();
        if rel.abs() < 0.6 {
            let x = 49.0 + FOCAL_PX * rel.tan() + if i % 8 < 4 { 0.0 } else { 2.0 };
            let x = x.round().clamp(0.0, 94.0) as usize;
            for y in 34..38 {
                for c in x..x + 4 {
                    frame[y * WIDTH + c] = 30;
                }
            }
        }
        let vm = Visuomotor {
            sighting: movers.step(&frame, standing, off0(Params::default().swarm.look_change)),
            ..quiet()
        };
        let c = f.step(&vm, h);
        standing = stopped(&c);
        states.push(c.state);
        odo.update(c.left_mm_s, c.right_mm_s, DT);
        if i > 45 && c.state == State::Wander {
            break;
        }
    }
    // wandered 44 frames, then looked until it saw the object and set off towards it
    assert!(states[..44].iter().all(|&s| s == State::Wander));
    assert_eq!(*states.last().unwrap(), State::Wander, "{states:?}");
    assert!(
        states.len() < 200,
        "found within three looks: {}",
        states.len()
    );
    let h = odo.heading_deg();
    for _ in 0..30 {
        let c = f.step(&quiet(), odo.heading_deg());
        odo.update(c.left_mm_s, c.right_mm_s, DT);
    }
    assert!(
        err(odo.heading_deg(), mover_deg) < 8.0,
        "from {h} to {}",
        odo.heading_deg()
    );
}

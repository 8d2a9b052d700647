//! The short-mode override, the γ path and the long takeoff in closed loop with odometry.

use super::*;

#[test]
fn short_mode_overrides_every_escape_state_with_the_latched_gamma_headings() {
    for h in [0.0, 40.0, -170.0, 175.0] {
        let (wander, long_f, escape, late) = (
            in_wander(h),
            in_long(h).0,
            in_escape(h).0,
            in_escape_late(h).0,
        );
        for (what, mut f) in [
            ("wander", wander),
            ("long takeoff", long_f),
            ("escape", escape),
            ("late escape", late),
        ] {
            for x in [LEFT_X, RIGHT_X] {
                let mut f2 = f.clone();
                let vm = short(x);
                let [t1, t2] = vm.theta_short.unwrap();
                let c = f2.step(&vm, h);
                assert_eq!(c.state, State::ShortTakeoff, "{what} {h} {x}");
                assert_eq!(c.short_phase, Some(ShortPhase::Retreat));
                assert!(err(c.heading_setpoint_deg, h + t1) < 1e-3, "{what} {h} {x}");
                // phase 1 is a retreat
                assert!(c.left_mm_s + c.right_mm_s < 0.0, "{what} {h} {x}");
                // sp¹ is 90° off the threat, on the side away from it
                assert!((err(c.heading_setpoint_deg, threat_abs(x, h)) - 90.0).abs() < 1e-3);
                // sp² shows once phase 1 is done: 180° opposite the threat
                let c = f2.step(&quiet(), wrap_deg(h + t1));
                assert_eq!(c.short_phase, Some(ShortPhase::Turn));
                assert!(err(c.heading_setpoint_deg, h + t2) < 1e-3);
                assert!((err(c.heading_setpoint_deg, threat_abs(x, h)) - 180.0).abs() < 1e-3);
                assert!(c.left_mm_s + c.right_mm_s > 0.0, "phase 2 moves forward");
            }
            // and the original is untouched by the clones
            assert_ne!(f.step(&quiet(), h).state, State::ShortTakeoff);
        }
    }
}

#[test]
fn gamma_path_in_closed_loop_turns_away_from_the_threat() {
    for (x, side) in [(LEFT_X, -1.0f32), (RIGHT_X, 1.0)] {
        for h0 in [0.0f32, 120.0, -150.0] {
            let mut f = in_wander(h0);
            let vm = short(x);
            let [t1, t2] = vm.theta_short.unwrap();
            let threat = threat_abs(x, h0);
            // the threat stays in short mode for a while: no re-latch while on the path
            let run = closed_loop(&mut f, h0, 150, |i| if i < 10 { vm } else { quiet() });

            let mut h_prev = h0;
            let mut turned = 0.0f32;
            let mut phase1 = 0;
            let mut phase2 = 0;
            let mut escape_at = None;
            for (i, (c, h)) in run.iter().enumerate() {
                match (c.state, c.short_phase) {
                    (State::ShortTakeoff, Some(ShortPhase::Retreat)) => {
                        assert_eq!(phase2, 0, "phase 1 comes first");
                        if (i as u32) < f.params().timing.retreat_frames {
                            assert!(c.left_mm_s + c.right_mm_s < 0.0, "retreat at frame {i}");
                        } else {
                            // bounded retreat: then it turns in place
                            let sum = c.left_mm_s + c.right_mm_s;
                            assert!(sum.abs() < 1e-3, "in place at frame {i}: {sum}");
                        }
                        assert!(err(c.heading_setpoint_deg, h0 + t1) < 1e-3, "no re-latch");
                        phase1 += 1;
                    }
                    (State::ShortTakeoff, Some(ShortPhase::Turn)) => {
                        assert!(c.left_mm_s + c.right_mm_s > 0.0, "forward at frame {i}");
                        assert!(err(c.heading_setpoint_deg, h0 + t2) < 1e-3);
                        if phase2 == 0 {
                            // entered phase 2 on reaching θ¹
                            assert!(err(h_prev, h0 + t1) <= tol(), "{x} {h0}");
                        }
                        phase2 += 1;
                    }
                    (State::Escape, None) => {
                        if escape_at.is_none() {
                            assert!(phase1 > 0 && phase2 > 0, "{x} {h0}");
                            // aligned with θ², not timed out
                            assert!(i < f.params().timing.takeoff_timeout_frames as usize);
                            assert!(err(h_prev, threat + 180.0) <= tol(), "{x} {h0} {h_prev}");
                            assert!(err(c.heading_setpoint_deg, threat + 180.0) < 1e-3);
                            escape_at = Some(i);
                        }
                    }
                    other => {
                        assert!(
                            escape_at.is_some() && other.0 == State::Wander,
                            "{other:?} at {i}"
                        )
                    }
                }
                // the heading only ever turns away from the threat side on the way
                let d = wrap_deg(h - h_prev);
                if escape_at.is_none() {
                    assert!(d * side <= 1e-3, "turned toward the threat at {i}: {d}");
                }
                turned += d;
                h_prev = *h;
            }
            assert!(escape_at.is_some(), "{x} {h0}: never escaped");
            // total turn ≈ θ²: more than 90° and away from the threat
            assert!(-turned * side > 90.0, "{turned}");
            assert!((turned - t2).abs() <= 2.0 * tol(), "{turned} vs {t2}");
            // final heading 180° from the threat, and the robot is escaping or wandering forward
            let (c, h) = run.last().unwrap();
            assert!(err(*h, threat + 180.0) <= tol(), "{x} {h0} {h}");
            assert!(c.left_mm_s > 0.0 && c.right_mm_s > 0.0);
        }
    }
}

#[test]
fn long_takeoff_turns_away_from_the_threat_side_and_escapes_at_s_times_max() {
    let p = FsmParams::default();
    for (x, expect_right) in [(LEFT_X, true), (RIGHT_X, false)] {
        let h0 = 30.0;
        let vm = long(x);
        let threat = threat_abs(x, h0);
        let mut f = in_wander(h0);
        let run = closed_loop(&mut f, h0, 45, |i| if i == 0 { vm } else { quiet() });
        let (first, _) = run[0];
        assert_eq!(first.state, State::LongTakeoff);
        assert!(err(first.heading_setpoint_deg, threat + 180.0) < 1e-3);
        // in place: the wheels cancel
        assert!((first.left_mm_s + first.right_mm_s).abs() < 1e-3);
        assert_eq!(first.left_mm_s > first.right_mm_s, expect_right, "x = {x}");
        let i_escape = run
            .iter()
            .position(|(c, _)| c.state == State::Escape)
            .expect("escapes");
        assert!(i_escape < p.timing.takeoff_timeout_frames as usize);
        for (c, _) in &run[..i_escape] {
            assert_eq!(c.state, State::LongTakeoff);
            assert_eq!(c.left_mm_s > c.right_mm_s, expect_right);
        }
        // escape straight ahead at S·max once the heading has settled
        let (c, h) = run.last().unwrap();
        assert_eq!(c.state, State::Escape);
        assert!(err(*h, threat + 180.0) <= 1.0);
        let v = (c.left_mm_s + c.right_mm_s) / 2.0;
        assert!(
            (v - vm.strength * p.motion.max_escape_mm_s).abs() < 1e-2,
            "{v}"
        );
        // only a residual correction (1° of error is 4°/s, i.e. 3.4 mm/s of wheel difference)
        assert!((c.left_mm_s - c.right_mm_s).abs() < 5.0, "{c:?}");
    }
}

#[test]
fn the_retreat_reverses_for_retreat_frames_then_turns_in_place() {
    for (frames, reversing) in [(0u32, 0usize), (3, 3), (u32::MAX, usize::MAX)] {
        let mut p = FsmParams::default();
        p.set("retreat_frames", &frames.to_string()).unwrap();
        let mut f = Fsm::new(p, Behaviour::Escape);
        f.step(&quiet(), 0.0);
        // the robot does not turn (heading held at 0): phase 1 never ends
        let back: Vec<bool> = (0..10)
            .map(|_| {
                let c = f.step(&short(RIGHT_X), 0.0);
                assert_eq!(c.short_phase, Some(ShortPhase::Retreat));
                c.left_mm_s + c.right_mm_s < 0.0
            })
            .collect();
        let n = back.iter().take_while(|&&b| b).count();
        assert_eq!(n, reversing.min(10), "retreat_frames {frames}: {back:?}");
        assert!(back[n..].iter().all(|&b| !b), "never reverses again");
    }
    assert_eq!(
        FsmParams::default().timing.retreat_frames,
        u32::MAX,
        "the paper's γ path"
    );
}

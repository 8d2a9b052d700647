//! Behaviour of the escape FSM (paper Sec. II-B, Eqs. 13–15) and its swarm variant (Sec. IV-D):
//! the transition table, the short-mode override, the γ path and the long takeoff in closed
//! loop with odometry, the quiet period, the takeoff timeout and robustness to bad input.

use alvs_tasks::model::fsm::{
    Behaviour, Fsm, FsmParamError, FsmParams, HeadingEstimator, MotorCommand, Odometry, ShortPhase,
    State,
};
use alvs_tasks::model::visuomotor::{bearing, wrap_deg, Visuomotor};
use alvs_tasks::Params;
use proptest::prelude::*;

const DT: f32 = 1.0 / 30.0;
/// Image columns of a threat on the left and on the right of the 99-pixel horizon.
const LEFT_X: u8 = 10;
const RIGHT_X: u8 = 88;
/// LPLC2 sums below and above `T_s` = 7000.
const LONG_R: u32 = 4000;
const SHORT_R: u32 = 8000;

fn quiet() -> Visuomotor {
    Visuomotor::from_fields(core::iter::empty(), &Params::default())
}

fn threat(x: u8, r: u32) -> Visuomotor {
    Visuomotor::from_fields([(x, r)].into_iter(), &Params::default())
}

fn long(x: u8) -> Visuomotor {
    let v = threat(x, LONG_R);
    assert!(v.alert && !v.short_mode);
    v
}

fn short(x: u8) -> Visuomotor {
    let v = threat(x, SHORT_R);
    assert!(v.alert && v.short_mode);
    v
}

/// Absolute bearing of a threat at column `x` seen from heading `h`.
fn threat_abs(x: u8, h: f32) -> f32 {
    wrap_deg(h + bearing(f32::from(x), Params::default().alpha))
}

fn err(a: f32, b: f32) -> f32 {
    wrap_deg(a - b).abs()
}

fn stopped(c: &MotorCommand) -> bool {
    c.left_mm_s == 0.0 && c.right_mm_s == 0.0
}

fn tol() -> f32 {
    FsmParams::default().align_tol_deg
}

// ---- getting an FSM into each state (heading frozen unless said otherwise) ----

/// The transition logic itself, without saccadic suppression (tested on its own below): these
/// tests freeze or script the heading, so a commanded turn never happens.
fn params() -> FsmParams {
    FsmParams {
        saccade_yaw_deg_s: f32::INFINITY,
        ..FsmParams::default()
    }
}

fn fsm(b: Behaviour) -> Fsm {
    Fsm::new(params(), b)
}

/// Wander at heading `h`.
fn in_wander(h: f32) -> Fsm {
    let mut f = fsm(Behaviour::Escape);
    assert_eq!(f.step(&quiet(), h).state, State::Wander);
    f
}

/// LongTakeoff from heading `h` for a right threat; returns the set-point.
fn in_long(h: f32) -> (Fsm, f32) {
    let mut f = in_wander(h);
    let c = f.step(&long(RIGHT_X), h);
    assert_eq!(c.state, State::LongTakeoff);
    (f, c.heading_setpoint_deg)
}

/// Escape, just entered (aligned with the long-takeoff set-point); returns the escape heading.
fn in_escape(h: f32) -> (Fsm, f32) {
    let (mut f, sp) = in_long(h);
    assert_eq!(f.step(&quiet(), sp).state, State::Escape);
    (f, sp)
}

/// Escape past its minimum duration with an alert on the last frame (quiet count at 0).
fn in_escape_late(h: f32) -> (Fsm, f32) {
    let (mut f, sp) = in_escape(h);
    // alerts before the minimum duration are ignored (but reset the quiet count); the next
    // frame is the first that may act
    for _ in 1..FsmParams::default().min_escape_frames {
        assert_eq!(f.step(&long(LEFT_X), sp).state, State::Escape);
    }
    (f, sp)
}

/// ShortTakeoff, phase Retreat, from heading `h` for a right threat; returns (sp¹, sp²).
fn in_short(h: f32) -> (Fsm, [f32; 2]) {
    let mut f = in_wander(h);
    let vm = short(RIGHT_X);
    let c = f.step(&vm, h);
    assert_eq!(
        (c.state, c.short_phase),
        (State::ShortTakeoff, Some(ShortPhase::Retreat))
    );
    let [t1, t2] = vm.theta_short.unwrap();
    (f, [wrap_deg(h + t1), wrap_deg(h + t2)])
}

/// ShortTakeoff, phase Turn.
fn in_short_turn(h: f32) -> (Fsm, [f32; 2]) {
    let (mut f, sp) = in_short(h);
    let c = f.step(&quiet(), sp[0]);
    assert_eq!(
        (c.state, c.short_phase),
        (State::ShortTakeoff, Some(ShortPhase::Turn))
    );
    (f, sp)
}

fn swarm_wander(h: f32) -> Fsm {
    let mut f = fsm(Behaviour::Swarm);
    assert_eq!(f.step(&quiet(), h).state, State::Wander);
    f
}

fn swarm_spin(h: f32) -> Fsm {
    let mut f = swarm_wander(h);
    assert_eq!(f.step(&long(LEFT_X), h).state, State::Spin);
    f
}

#[test]
fn transition_table_covers_every_state() {
    const H: f32 = 20.0;
    // (description, FSM in the start state, input, heading of the frame, next state, next phase)
    type Row = (
        &'static str,
        Fsm,
        Visuomotor,
        f32,
        State,
        Option<ShortPhase>,
    );
    let retreat = Some(ShortPhase::Retreat);
    let turn = Some(ShortPhase::Turn);
    let mut rows: Vec<Row> = vec![
        (
            "wander, none",
            in_wander(H),
            quiet(),
            H,
            State::Wander,
            None,
        ),
        (
            "wander, alert",
            in_wander(H),
            long(LEFT_X),
            H,
            State::LongTakeoff,
            None,
        ),
        (
            "wander, short",
            in_wander(H),
            short(LEFT_X),
            H,
            State::ShortTakeoff,
            retreat,
        ),
    ];
    let (f, _) = in_long(H);
    rows.push((
        "long, none, not aligned",
        f,
        quiet(),
        H,
        State::LongTakeoff,
        None,
    ));
    let (f, _) = in_long(H);
    rows.push((
        "long, alert, not aligned (alerts do not interrupt the turn)",
        f,
        long(LEFT_X),
        H,
        State::LongTakeoff,
        None,
    ));
    let (f, sp) = in_long(H);
    rows.push(("long, none, aligned", f, quiet(), sp, State::Escape, None));
    let (f, sp) = in_long(H);
    rows.push((
        "long, none, within tolerance",
        f,
        quiet(),
        sp + 0.9 * tol(),
        State::Escape,
        None,
    ));
    let (f, sp) = in_long(H);
    rows.push((
        "long, none, just outside tolerance",
        f,
        quiet(),
        sp + 1.1 * tol(),
        State::LongTakeoff,
        None,
    ));
    let (f, _) = in_long(H);
    rows.push((
        "long, short",
        f,
        short(LEFT_X),
        H,
        State::ShortTakeoff,
        retreat,
    ));
    let (f, sp) = in_escape(H);
    rows.push(("escape early, none", f, quiet(), sp, State::Escape, None));
    let (f, sp) = in_escape(H);
    rows.push((
        "escape early, alert (minimum duration)",
        f,
        long(LEFT_X),
        sp,
        State::Escape,
        None,
    ));
    let (f, sp) = in_escape(H);
    rows.push((
        "escape early, short",
        f,
        short(LEFT_X),
        sp,
        State::ShortTakeoff,
        retreat,
    ));
    let (f, sp) = in_escape_late(H);
    rows.push((
        "escape late, alert",
        f,
        long(LEFT_X),
        sp,
        State::LongTakeoff,
        None,
    ));
    let (f, sp) = in_escape_late(H);
    rows.push((
        "escape late, none, not yet quiet",
        f,
        quiet(),
        sp,
        State::Escape,
        None,
    ));
    let (f, _) = in_short(H);
    rows.push((
        "short retreat, none, not aligned",
        f,
        quiet(),
        H,
        State::ShortTakeoff,
        retreat,
    ));
    let (f, sp) = in_short(H);
    rows.push((
        "short retreat, none, aligned with sp1",
        f,
        quiet(),
        sp[0],
        State::ShortTakeoff,
        turn,
    ));
    let (f, _) = in_short(H);
    rows.push((
        "short retreat, short again (no re-latch)",
        f,
        short(LEFT_X),
        H,
        State::ShortTakeoff,
        retreat,
    ));
    let (f, sp) = in_short_turn(H);
    rows.push((
        "short turn, none, not aligned",
        f,
        quiet(),
        sp[0],
        State::ShortTakeoff,
        turn,
    ));
    let (f, sp) = in_short_turn(H);
    rows.push((
        "short turn, alert, not aligned",
        f,
        long(LEFT_X),
        sp[0],
        State::ShortTakeoff,
        turn,
    ));
    let (f, sp) = in_short_turn(H);
    rows.push((
        "short turn, none, aligned with sp2",
        f,
        quiet(),
        sp[1],
        State::Escape,
        None,
    ));
    rows.push((
        "swarm wander, none",
        swarm_wander(H),
        quiet(),
        H,
        State::Wander,
        None,
    ));
    rows.push((
        "swarm wander, alert",
        swarm_wander(H),
        long(RIGHT_X),
        H,
        State::Spin,
        None,
    ));
    rows.push((
        "swarm wander, short",
        swarm_wander(H),
        short(RIGHT_X),
        H,
        State::Spin,
        None,
    ));
    rows.push((
        "swarm spin, none",
        swarm_spin(H),
        quiet(),
        H,
        State::Spin,
        None,
    ));
    rows.push((
        "swarm spin, alert",
        swarm_spin(H),
        long(RIGHT_X),
        H,
        State::Spin,
        None,
    ));
    rows.push((
        "swarm spin, short",
        swarm_spin(H),
        short(RIGHT_X),
        H,
        State::Spin,
        None,
    ));

    let mut seen = [false; 5];
    for (what, mut f, vm, h, next, phase) in rows {
        seen[f.state() as usize] = true;
        let c = f.step(&vm, h);
        assert_eq!((c.state, c.short_phase), (next, phase), "{what}");
        assert_eq!(f.state(), next, "{what}");
        assert_eq!(f.short_phase(), phase, "{what}");
    }
    assert!(seen.iter().all(|&s| s), "every state is a start state");
}

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

/// Runs the FSM in closed loop with odometry from heading `h0`; `vm_at(frame)` gives the input.
/// Returns the commands and the heading after each of them.
fn closed_loop(
    f: &mut Fsm,
    h0: f32,
    frames: usize,
    vm_at: impl Fn(usize) -> Visuomotor,
) -> Vec<(MotorCommand, f32)> {
    let mut odo = Odometry::new(f.params().track_mm, h0);
    (0..frames)
        .map(|i| {
            let c = f.step(&vm_at(i), odo.heading_deg());
            (c, odo.update(c.left_mm_s, c.right_mm_s, DT))
        })
        .collect()
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
                        assert!(c.left_mm_s + c.right_mm_s < 0.0, "retreat at frame {i}");
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
                            assert!(i < f.params().takeoff_timeout_frames as usize);
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
        assert!(i_escape < p.takeoff_timeout_frames as usize);
        for (c, _) in &run[..i_escape] {
            assert_eq!(c.state, State::LongTakeoff);
            assert_eq!(c.left_mm_s > c.right_mm_s, expect_right);
        }
        // escape straight ahead at S·max once the heading has settled
        let (c, h) = run.last().unwrap();
        assert_eq!(c.state, State::Escape);
        assert!(err(*h, threat + 180.0) <= 1.0);
        let v = (c.left_mm_s + c.right_mm_s) / 2.0;
        assert!((v - vm.strength * p.max_escape_mm_s).abs() < 1e-2, "{v}");
        // only a residual correction (1° of error is 4°/s, i.e. 3.4 mm/s of wheel difference)
        assert!((c.left_mm_s - c.right_mm_s).abs() < 5.0, "{c:?}");
    }
}

#[test]
fn escape_strength_is_latched_at_the_trigger() {
    let (mut f, sp) = in_escape(0.0);
    let s = long(RIGHT_X).strength;
    // a stronger (but not short-mode) alert during the minimum escape changes nothing
    let c = f.step(&threat(LEFT_X, 6000), sp);
    assert!(((c.left_mm_s + c.right_mm_s) / 2.0 - s * 200.0).abs() < 1e-2);
}

#[test]
fn escape_returns_to_wander_after_the_quiet_period() {
    let p = FsmParams::default();
    // no alert at all: Wander after max(min_escape, quiet) frames
    let (mut f, sp) = in_escape(0.0);
    let n = p.min_escape_frames.max(p.quiet_frames);
    for i in 1..n {
        assert_eq!(f.step(&quiet(), sp).state, State::Escape, "frame {i}");
    }
    let c = f.step(&quiet(), sp);
    assert_eq!(c.state, State::Wander);
    assert_eq!(
        c.heading_setpoint_deg, sp,
        "wander holds the heading at entry"
    );
    assert_eq!((c.left_mm_s, c.right_mm_s), (p.cruise_mm_s, p.cruise_mm_s));

    // an alert late in the minimum escape delays it: `quiet` frames after the last alert
    let (mut f, sp) = in_escape(0.0);
    let last_alert = p.min_escape_frames - 2;
    for i in 1..=last_alert {
        let vm = if i == last_alert {
            long(LEFT_X)
        } else {
            quiet()
        };
        assert_eq!(f.step(&vm, sp).state, State::Escape);
    }
    for i in 1..p.quiet_frames {
        assert_eq!(f.step(&quiet(), sp).state, State::Escape, "quiet frame {i}");
    }
    assert_eq!(f.step(&quiet(), sp).state, State::Wander);
}

#[test]
fn takeoff_times_out_into_escape_when_the_heading_never_aligns() {
    let p = FsmParams::default();
    // long takeoff with the wheels stuck
    let (mut f, sp) = in_long(0.0);
    for i in 1..p.takeoff_timeout_frames {
        assert_eq!(f.step(&quiet(), 0.0).state, State::LongTakeoff, "frame {i}");
    }
    let c = f.step(&quiet(), 0.0);
    assert_eq!(c.state, State::Escape);
    assert_eq!(c.heading_setpoint_deg, sp);

    // short takeoff stuck in phase 1: escape holding θ²
    let (mut f, [_, sp2]) = in_short(0.0);
    for _ in 1..p.takeoff_timeout_frames {
        assert_eq!(f.step(&quiet(), 0.0).short_phase, Some(ShortPhase::Retreat));
    }
    let c = f.step(&quiet(), 0.0);
    assert_eq!((c.state, c.heading_setpoint_deg), (State::Escape, sp2));

    // short takeoff stuck in phase 2: the timeout counts from the trigger
    let (mut f, [sp1, sp2]) = in_short_turn(0.0);
    for _ in 2..p.takeoff_timeout_frames {
        assert_eq!(f.step(&quiet(), sp1).short_phase, Some(ShortPhase::Turn));
    }
    let c = f.step(&quiet(), sp1);
    assert_eq!((c.state, c.heading_setpoint_deg), (State::Escape, sp2));
}

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
fn non_finite_inputs_stop_the_wheels_without_a_transition() {
    let bad_vms = {
        let base = short(RIGHT_X);
        [
            Visuomotor {
                strength: f32::NAN,
                ..base
            },
            Visuomotor {
                threat_x: Some(f32::INFINITY),
                ..base
            },
            Visuomotor {
                theta_long: Some(f32::NAN),
                ..base
            },
            Visuomotor {
                theta_short: Some([10.0, f32::NEG_INFINITY]),
                ..base
            },
        ]
    };
    let starts: Vec<(&str, Fsm, f32)> = vec![
        ("wander", in_wander(10.0), 10.0),
        ("long", in_long(10.0).0, 10.0),
        ("escape", in_escape(10.0).0, 10.0),
        ("short", in_short(10.0).0, 10.0),
        ("short turn", in_short_turn(10.0).0, 10.0),
        ("swarm wander", swarm_wander(10.0), 10.0),
        ("swarm spin", swarm_spin(10.0), 10.0),
        ("fresh", fsm(Behaviour::Escape), 10.0),
    ];
    for (what, f, h) in starts {
        let inputs = bad_vms
            .iter()
            .map(|v| (*v, h))
            .chain([f32::NAN, f32::INFINITY, f32::NEG_INFINITY].map(|bad| (short(LEFT_X), bad)));
        for (vm, heading) in inputs {
            let mut g = f.clone();
            let (state, phase) = (g.state(), g.short_phase());
            let c = g.step(&vm, heading);
            assert!(stopped(&c), "{what}: {c:?}");
            assert_eq!((c.state, c.short_phase), (state, phase), "{what}");
            assert_eq!((g.state(), g.short_phase()), (state, phase), "{what}");
            // and nothing was counted: the next valid frame acts as it would have
            let mut reference = f.clone();
            assert_eq!(g.step(&quiet(), h), reference.step(&quiet(), h), "{what}");
        }
    }
}

fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        -400.0f32..400.0,
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(f32::NEG_INFINITY),
        proptest::num::f32::ANY,
    ]
}

fn any_vm() -> impl Strategy<Value = Visuomotor> {
    (
        any::<u32>(),
        any_f32(),
        proptest::option::of(any_f32()),
        any::<bool>(),
        any::<bool>(),
        proptest::option::of(any_f32()),
        proptest::option::of((any_f32(), any_f32())),
    )
        .prop_map(|(sum, s, x, alert, short_mode, tl, ts)| Visuomotor {
            lplc2_sum: sum,
            strength: s,
            threat_x: x,
            alert,
            short_mode,
            theta_long: tl,
            theta_short: ts.map(|(a, b)| [a, b]),
        })
}

proptest! {
    /// Whatever the input, no panic, finite wheel speeds within the wheel limit, and a
    /// non-finite input always stops the robot.
    #[test]
    fn any_input_gives_bounded_speeds(
        swarm in any::<bool>(),
        frames in proptest::collection::vec((any_vm(), any_f32()), 1..200),
    ) {
        let p = FsmParams::default();
        let mut f = fsm(if swarm { Behaviour::Swarm } else { Behaviour::Escape });
        for (vm, h) in frames {
            let c = f.step(&vm, h);
            prop_assert!(c.left_mm_s.is_finite() && c.right_mm_s.is_finite());
            prop_assert!(c.left_mm_s.abs() <= p.max_wheel_mm_s + 1e-3);
            prop_assert!(c.right_mm_s.abs() <= p.max_wheel_mm_s + 1e-3);
            prop_assert!(c.heading_setpoint_deg.is_finite());
            let finite = h.is_finite()
                && vm.strength.is_finite()
                && vm.threat_x.is_none_or(f32::is_finite)
                && vm.theta_long.is_none_or(f32::is_finite)
                && vm.theta_short.is_none_or(|t| t.iter().all(|a| a.is_finite()));
            if !finite {
                prop_assert!(stopped(&c));
            }
            if swarm {
                prop_assert!(matches!(c.state, State::Wander | State::Spin));
            }
        }
    }

    /// Nonsensical parameters must not panic either.
    #[test]
    fn any_params_do_not_panic(
        vals in proptest::collection::vec(any_f32(), 10),
        counts in proptest::collection::vec(any::<u32>(), 6),
        frames in proptest::collection::vec((any_vm(), any_f32()), 1..50),
    ) {
        let p = FsmParams {
            cruise_mm_s: vals[0],
            max_escape_mm_s: vals[1],
            retreat_mm_s: vals[2],
            max_wheel_mm_s: vals[3],
            track_mm: vals[4],
            heading_gain: vals[5],
            max_yaw_deg_s: vals[6],
            align_tol_deg: vals[7],
            spin_deg_s: vals[8],
            min_escape_frames: counts[0],
            quiet_frames: counts[1],
            takeoff_timeout_frames: counts[2],
            spin_frames: counts[3],
            saccade_yaw_deg_s: vals[9],
            settle_frames: counts[4],
            alert_frames: counts[5],
        };
        let mut f = Fsm::new(p, Behaviour::Escape);
        for (vm, h) in frames {
            let c = f.step(&vm, h);
            prop_assert!(c.left_mm_s.is_finite() && c.right_mm_s.is_finite());
        }
    }
}

#[test]
fn perception_is_ignored_while_the_robot_turns_fast() {
    // default parameters: suppression above 45 °/s of commanded yaw
    let mut f = Fsm::new(FsmParams::default(), Behaviour::Escape);
    f.step(&quiet(), 0.0);
    // a threat on the right: long takeoff, turning left at the rate limit
    let c = f.step(&long(RIGHT_X), 0.0);
    assert_eq!(c.state, State::LongTakeoff);
    assert!(
        f.suppressed(),
        "turning at {} mm/s differential",
        c.right_mm_s - c.left_mm_s
    );
    // the self-motion makes the scene 'loom' on the left: ignored, the takeoff goes on
    let c = f.step(&short(LEFT_X), -10.0);
    assert_eq!(c.state, State::LongTakeoff);
    // close to the set-point the turn slows below 45 °/s and perception counts again
    let sp = c.heading_setpoint_deg;
    let c = f.step(&quiet(), sp + 5.0);
    assert!(!f.suppressed(), "{c:?}");
    let c = f.step(&short(LEFT_X), sp + 4.0);
    assert_eq!(
        c.state,
        State::ShortTakeoff,
        "a fierce stimulus still interrupts"
    );
}

#[test]
fn the_settle_period_extends_the_suppression_after_a_fast_turn() {
    let p = FsmParams {
        settle_frames: 3,
        ..FsmParams::default()
    };
    let mut f = Fsm::new(p, Behaviour::Escape);
    f.step(&quiet(), 0.0);
    let c = f.step(&long(RIGHT_X), 0.0);
    assert_eq!(c.state, State::LongTakeoff);
    // the turn slows below 45 °/s close to the set-point ...
    let sp = c.heading_setpoint_deg;
    f.step(&quiet(), sp + 5.0);
    // ... but for 3 more frames a fierce stimulus is taken for the turn's after-image
    for k in 0..3 {
        assert!(f.suppressed(), "settle frame {k}");
        let c = f.step(&short(LEFT_X), sp + 4.0);
        assert_ne!(c.state, State::ShortTakeoff, "settle frame {k}");
    }
    assert!(!f.suppressed());
    let c = f.step(&short(LEFT_X), sp + 4.0);
    assert_eq!(c.state, State::ShortTakeoff);
}

#[test]
fn alert_frames_ask_for_consecutive_alerts() {
    let p = FsmParams {
        alert_frames: 2,
        ..FsmParams::default()
    };
    let mut f = Fsm::new(p, Behaviour::Escape);
    f.step(&quiet(), 0.0);
    // a single alert frame, then a quiet one: nothing happens
    assert_eq!(f.step(&long(RIGHT_X), 0.0).state, State::Wander);
    assert_eq!(f.step(&quiet(), 0.0).state, State::Wander);
    // two in a row: the second one acts
    assert_eq!(f.step(&long(RIGHT_X), 0.0).state, State::Wander);
    assert_eq!(f.step(&long(RIGHT_X), 0.0).state, State::LongTakeoff);
    // the short mode waits for its second frame as well
    let mut f = Fsm::new(p, Behaviour::Escape);
    f.step(&quiet(), 0.0);
    assert_eq!(f.step(&short(LEFT_X), 0.0).state, State::Wander);
    assert_eq!(f.step(&short(LEFT_X), 0.0).state, State::ShortTakeoff);
    // 0 behaves as 1
    let mut f = Fsm::new(
        FsmParams {
            alert_frames: 0,
            ..FsmParams::default()
        },
        Behaviour::Escape,
    );
    f.step(&quiet(), 0.0);
    assert_eq!(f.step(&quiet(), 0.0).state, State::Wander);
    assert_eq!(f.step(&long(RIGHT_X), 0.0).state, State::LongTakeoff);
}

#[test]
fn fsm_parameters_are_set_by_name_with_checked_values() {
    let mut p = FsmParams::default();
    assert_eq!(p.set("settle_frames", "4"), Ok(()));
    assert_eq!(p.set("heading_gain", " 8.5 "), Ok(()));
    assert_eq!(p.set("saccade_yaw_deg_s", "inf"), Ok(()));
    assert_eq!((p.settle_frames, p.heading_gain), (4, 8.5));
    assert_eq!(p.saccade_yaw_deg_s, f32::INFINITY);
    assert_eq!(p.set("warp", "1"), Err(FsmParamError::Unknown));
    for (name, bad) in [
        ("heading_gain", "-1"),
        ("heading_gain", "inf"),
        ("cruise_mm_s", "NaN"),
        ("settle_frames", "1.5"),
        ("alert_frames", "-2"),
    ] {
        assert_eq!(
            p.set(name, bad),
            Err(FsmParamError::Invalid { name }),
            "{name}={bad}"
        );
    }
    // refused values leave the parameters as they were
    assert_eq!((p.settle_frames, p.heading_gain), (4, 8.5));
    assert!(FsmParamError::Unknown.to_string().contains("settle_frames"));
    // a refusal says what is allowed
    let msg = |name: &str, v: &str| FsmParams::default().set(name, v).unwrap_err().to_string();
    assert_eq!(
        msg("alert_frames", "-2"),
        "FSM parameter alert_frames must be a whole number of frames in 0..=4294967295"
    );
    assert_eq!(
        msg("cruise_mm_s", "-1"),
        "FSM parameter cruise_mm_s must be a finite number ≥ 0"
    );
    assert_eq!(
        msg("saccade_yaw_deg_s", "x"),
        "FSM parameter saccade_yaw_deg_s must be a number ≥ 0, or inf (no suppression)"
    );
    // every name is accepted
    for name in FsmParams::NAMES {
        assert_eq!(FsmParams::default().set(name, "1"), Ok(()), "{name}");
    }
}

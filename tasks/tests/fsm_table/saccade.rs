//! `FsmParams::escape_saccade`: short mode during an escape turns the robot 90° away from the
//! threat's side (a saccade) instead of starting a γ path.

use super::*;

fn with_saccade() -> FsmParams {
    FsmParams {
        escape: Escape {
            escape_saccade: true,
            ..params().escape
        },
        ..params()
    }
}

/// An FSM escaping from heading `h` (from a threat on the right); its set-point.
fn escaping(p: FsmParams, h: f32) -> (Fsm, f32) {
    let mut f = Fsm::new(p, Behaviour::Escape);
    f.step(&quiet(), h);
    let sp = f.step(&long(RIGHT_X), h).heading_setpoint_deg;
    assert_eq!(f.step(&quiet(), sp).state, State::Escape);
    (f, sp)
}

/// `c`, the answer at heading `sp` to `vm` (something on the right), is a saccade in place to
/// θ¹ of `vm`: 90° away from it, to the left. Returns θ¹.
fn saccade_left(c: &MotorCommand, sp: f32, vm: &Visuomotor) -> f32 {
    // θ¹ = α·(88 − 49) − 90 ≈ −62°
    let [t1, _] = vm.theta_short.unwrap();
    assert!(t1 < -45.0 && t1 > -90.0, "{t1}");
    assert_eq!((c.state, c.short_phase), (State::LongTakeoff, None));
    assert!(err(c.heading_setpoint_deg, wrap_deg(sp + t1)) < 1e-3);
    // in place: the wheels turn left against each other, no retreat
    assert!((c.left_mm_s + c.right_mm_s).abs() < 1e-3);
    assert!(c.left_mm_s < 0.0 && c.right_mm_s > 0.0);
    t1
}

#[test]
fn short_mode_during_an_escape_starts_a_saccade_to_theta_1() {
    let (mut f, sp) = escaping(with_saccade(), 20.0);
    // a fierce threat on the right of the new heading
    let vm = short(RIGHT_X);
    let t1 = saccade_left(&f.step(&vm, sp), sp, &vm);
    // aligned: the escape goes on at the saccade's heading
    let c = f.step(&quiet(), wrap_deg(sp + t1));
    assert_eq!(c.state, State::Escape);
    assert!(err(c.heading_setpoint_deg, wrap_deg(sp + t1)) < 1e-3);
    assert!(c.left_mm_s > 0.0 && c.right_mm_s > 0.0);
}

#[test]
fn short_mode_during_the_saccade_starts_a_new_saccade_not_a_gamma_path() {
    let mut f = Fsm::new(with_saccade(), Behaviour::Escape);
    f.step(&quiet(), 0.0);
    let sp = f.step(&long(RIGHT_X), 0.0).heading_setpoint_deg;
    assert_eq!(f.step(&quiet(), sp).state, State::Escape);
    let first = f.step(&short(RIGHT_X), sp);
    assert_eq!(first.state, State::LongTakeoff);
    // still turning (the heading is frozen here) when a fierce threat comes from the left:
    // a new saccade, 90° away from it (to the right), latched from the current heading
    let vm = short(LEFT_X);
    let [t1, _] = vm.theta_short.unwrap();
    assert!(t1 > 45.0, "{t1}");
    let c = f.step(&vm, sp);
    assert_eq!((c.state, c.short_phase), (State::LongTakeoff, None));
    assert!(err(c.heading_setpoint_deg, wrap_deg(sp + t1)) < 1e-3);
    // a long takeoff that is not a saccade still yields to the γ path
    let mut f = Fsm::new(with_saccade(), Behaviour::Escape);
    f.step(&quiet(), 0.0);
    assert_eq!(f.step(&long(RIGHT_X), 0.0).state, State::LongTakeoff);
    let c = f.step(&short(LEFT_X), 0.0);
    assert_eq!(c.short_phase, Some(ShortPhase::Retreat));
}

#[test]
fn short_mode_outside_an_escape_is_still_the_gamma_path() {
    for state in ["wander", "long takeoff"] {
        let mut f = Fsm::new(with_saccade(), Behaviour::Escape);
        f.step(&quiet(), 0.0);
        if state == "long takeoff" {
            assert_eq!(f.step(&long(LEFT_X), 0.0).state, State::LongTakeoff);
        }
        let c = f.step(&short(RIGHT_X), 0.0);
        assert_eq!(
            (c.state, c.short_phase),
            (State::ShortTakeoff, Some(ShortPhase::Retreat)),
            "{state}"
        );
    }
    // and without the parameter, an escape's short mode is the γ path too
    let (mut f, sp) = in_escape(0.0);
    let c = f.step(&short(RIGHT_X), sp);
    assert_eq!(c.short_phase, Some(ShortPhase::Retreat));
}

#[test]
fn a_saccade_turns_in_place_while_a_takeoff_drives() {
    let p = FsmParams {
        escape: Escape {
            takeoff_drive: 1.0,
            ..with_saccade().escape
        },
        ..with_saccade()
    };
    // the takeoff from Wander, its set-point behind: it backs away while it turns
    let mut f = Fsm::new(p, Behaviour::Escape);
    f.step(&quiet(), 0.0);
    let c = f.step(&long(RIGHT_X), 0.0);
    assert_eq!(c.state, State::LongTakeoff);
    assert!(c.left_mm_s + c.right_mm_s < 0.0, "{c:?}");
    // the saccade of an escape: in place, whatever takeoff_drive says
    let mut f = Fsm::new(p, Behaviour::Escape);
    f.step(&quiet(), 0.0);
    let sp = f.step(&long(RIGHT_X), 0.0).heading_setpoint_deg;
    assert_eq!(f.step(&quiet(), sp).state, State::Escape);
    let c = f.step(&short(RIGHT_X), sp);
    assert_eq!(c.state, State::LongTakeoff);
    assert!((c.left_mm_s + c.right_mm_s).abs() < 1e-3, "{c:?}");
}

/// The floor line's obstacle as the network reports it on a frame no field alerts on
/// (`Visuomotor::ahead`): an alert at column `x`, ΣLPLC2 0.
fn obstacle(x: u8) -> Visuomotor {
    let mut vm = quiet();
    vm.ahead(x, &Params::default());
    assert!(vm.obstacle.is_some() && vm.alert && !vm.short_mode && vm.lplc2_sum == 0);
    vm
}

#[test]
fn an_obstacle_close_ahead_cuts_the_escape_short_with_a_saccade() {
    for p in [params(), with_saccade()] {
        let (mut f, sp) = escaping(p, 0.0);
        // a field's alert in the escape's first second is ignored ...
        assert_eq!(f.step(&long(RIGHT_X), sp).state, State::Escape);
        // ... an obstacle on the right of the path is not
        let vm = obstacle(RIGHT_X);
        let t1 = saccade_left(&f.step(&vm, sp), sp, &vm);
        // aligned: the escape goes on at the new heading
        let c = f.step(&quiet(), wrap_deg(sp + t1));
        assert_eq!(c.state, State::Escape);
    }
    // wandering, an obstacle is an alert like any other: a long takeoff 180° from it
    let mut f = in_wander(0.0);
    let vm = obstacle(RIGHT_X);
    let c = f.step(&vm, 0.0);
    assert_eq!(c.state, State::LongTakeoff);
    assert!(err(c.heading_setpoint_deg, vm.theta_long.unwrap()) < 1e-3);
}

#[test]
fn the_obstacle_sets_the_saccade_whatever_the_fields_report() {
    // a field alerts on the left, the floor line finds an obstacle on the right of the path:
    // the fields keep X̄, the saccade turns away from the obstacle (left)
    let (mut f, sp) = escaping(params(), 0.0);
    let mut vm = long(LEFT_X);
    vm.ahead(RIGHT_X, &Params::default());
    assert!(vm.threat_x.unwrap() < 49.0, "the fields' X̄ stands");
    let c = f.step(&vm, sp);
    saccade_left(&c, sp, &obstacle(RIGHT_X));
}

#[test]
fn the_defaults_takeoff_turns_at_the_wheels_limit_and_the_papers_at_360_deg_s() {
    // the first frame of a long takeoff from a threat on the right: ~150° to turn left
    let first = |p: FsmParams| {
        let mut f = Fsm::new(p, Behaviour::Escape);
        f.step(&quiet(), 0.0);
        let c = f.step(&long(RIGHT_X), 0.0);
        assert_eq!(c.state, State::LongTakeoff);
        assert!(
            c.heading_setpoint_deg < -120.0,
            "{}",
            c.heading_setpoint_deg
        );
        c
    };
    let paper = first(FsmParams {
        escape: Escape {
            takeoff_drive: 0.0,
            ..FsmParams::PAPER.escape
        },
        ..FsmParams::PAPER
    });
    let half_track = FsmParams::PAPER.motion.track_mm / 2.0;
    assert!((paper.right_mm_s - 360f32.to_radians() * half_track).abs() < 0.1);
    assert!(
        (paper.left_mm_s + paper.right_mm_s).abs() < 1e-3,
        "in place"
    );
    // the default: the wheels at their limit, the turn first (it drives backwards only with
    // what the limit leaves, here nothing)
    let alvs = first(FsmParams::ALVS);
    let max = FsmParams::ALVS.motion.max_wheel_mm_s;
    assert!((alvs.right_mm_s - max).abs() < 0.1 && (alvs.left_mm_s + max).abs() < 0.1);
    // wander keeps its gentle steering: 4/s on a 20° error, under both
    for p in [FsmParams::PAPER, FsmParams::ALVS] {
        let mut f = Fsm::new(p, Behaviour::Escape);
        f.step(&quiet(), 0.0);
        let c = f.step(&quiet(), 20.0);
        assert_eq!(c.state, State::Wander);
        let turn = (c.right_mm_s - c.left_mm_s) / 2.0;
        assert!(
            (turn - 80f32.to_radians() * half_track).abs() < 0.1,
            "{turn}"
        );
    }
}

#[test]
fn the_defaults_saccades_turn_three_times_as_briskly() {
    let turn = |p: FsmParams| {
        let (mut f, sp) = escaping(p, 0.0);
        // 20° to go: 4/s · 20° = 80°/s, or 240°/s with the gain of 3
        let c = f.step(&obstacle(RIGHT_X), sp);
        let sp2 = c.heading_setpoint_deg;
        let c = f.step(&quiet(), wrap_deg(sp2 + 20.0));
        assert_eq!(c.state, State::LongTakeoff);
        (c.right_mm_s - c.left_mm_s) / 2.0
    };
    let plain = turn(params());
    let brisk = turn(FsmParams {
        escape: Escape {
            takeoff_gain: FsmParams::ALVS.escape.takeoff_gain,
            ..params().escape
        },
        ..params()
    });
    assert!((plain - 80f32.to_radians() * 24.0).abs() < 0.1, "{plain}");
    assert!((brisk - 3.0 * plain).abs() < 0.1, "{brisk}");
}

//! Escape timing: the latched strength, the quiet period, the takeoff timeout.

use super::*;

#[test]
fn escape_strength_is_latched_at_the_trigger() {
    let (mut f, sp) = in_escape(0.0);
    let s = long(RIGHT_X).strength;
    // a stronger (but not short-mode) alert during the minimum escape changes nothing
    let stronger = threat(LEFT_X, Params::default().table1.t_s - 500);
    assert!(!stronger.short_mode && stronger.strength > s);
    let c = f.step(&stronger, sp);
    assert!(((c.left_mm_s + c.right_mm_s) / 2.0 - s * 200.0).abs() < 1e-2);
}

#[test]
fn escape_returns_to_wander_after_the_quiet_period() {
    let p = FsmParams::default();
    // no alert at all: Wander after max(min_escape, quiet) frames
    let (mut f, sp) = in_escape(0.0);
    let n = p.timing.min_escape_frames.max(p.timing.quiet_frames);
    for i in 1..n {
        assert_eq!(f.step(&quiet(), sp).state, State::Escape, "frame {i}");
    }
    let c = f.step(&quiet(), sp);
    assert_eq!(c.state, State::Wander);
    assert_eq!(
        c.heading_setpoint_deg, sp,
        "wander holds the heading at entry"
    );
    assert_eq!(
        (c.left_mm_s, c.right_mm_s),
        (p.motion.cruise_mm_s, p.motion.cruise_mm_s)
    );

    // an alert late in the minimum escape delays it: `quiet` frames after the last alert
    let (mut f, sp) = in_escape(0.0);
    let last_alert = p.timing.min_escape_frames - 2;
    for i in 1..=last_alert {
        let vm = if i == last_alert {
            long(LEFT_X)
        } else {
            quiet()
        };
        assert_eq!(f.step(&vm, sp).state, State::Escape);
    }
    for i in 1..p.timing.quiet_frames {
        assert_eq!(f.step(&quiet(), sp).state, State::Escape, "quiet frame {i}");
    }
    assert_eq!(f.step(&quiet(), sp).state, State::Wander);
}

#[test]
fn takeoff_times_out_into_escape_when_the_heading_never_aligns() {
    let p = FsmParams::default();
    // long takeoff with the wheels stuck
    let (mut f, sp) = in_long(0.0);
    for i in 1..p.timing.takeoff_timeout_frames {
        assert_eq!(f.step(&quiet(), 0.0).state, State::LongTakeoff, "frame {i}");
    }
    let c = f.step(&quiet(), 0.0);
    assert_eq!(c.state, State::Escape);
    assert_eq!(c.heading_setpoint_deg, sp);

    // short takeoff stuck in phase 1: escape holding θ²
    let (mut f, [_, sp2]) = in_short(0.0);
    for _ in 1..p.timing.takeoff_timeout_frames {
        assert_eq!(f.step(&quiet(), 0.0).short_phase, Some(ShortPhase::Retreat));
    }
    let c = f.step(&quiet(), 0.0);
    assert_eq!((c.state, c.heading_setpoint_deg), (State::Escape, sp2));

    // short takeoff stuck in phase 2: the timeout counts from the trigger
    let (mut f, [sp1, sp2]) = in_short_turn(0.0);
    for _ in 2..p.timing.takeoff_timeout_frames {
        assert_eq!(f.step(&quiet(), sp1).short_phase, Some(ShortPhase::Turn));
    }
    let c = f.step(&quiet(), sp1);
    assert_eq!((c.state, c.heading_setpoint_deg), (State::Escape, sp2));
}

//! FSM parameters set by name.

use super::*;

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
    assert_eq!(
        msg("live_strength", "3"),
        "FSM parameter live_strength must be 0 (latched), 1 (escape) or 2 (escape and γ path)"
    );
    assert_eq!(
        msg("escape_saccade", "2"),
        "FSM parameter escape_saccade must be 0 (γ path, the paper) or 1 (saccade to θ¹)"
    );
    assert_eq!(
        msg("short_from_long", "2"),
        "FSM parameter short_from_long must be 0 (short mode from every state, the paper) or 1 \
         (only in a long takeoff)"
    );
    assert_eq!(
        msg("wander_stop_frames", "never"),
        "FSM parameter wander_stop_frames must be a whole number of frames in 0..=4294967295 \
         or none"
    );
    let mut q = FsmParams::default();
    assert_eq!(q.set("wander_stop_frames", "1000"), Ok(()));
    assert_eq!(q.wander_stop_frames, Some(1000));
    assert_eq!(q.set("wander_stop_frames", " none "), Ok(()));
    assert_eq!(q.wander_stop_frames, None);
    assert_eq!(q.set("short_from_long", "1"), Ok(()));
    assert!(q.short_from_long);
    // every name is accepted
    for name in FsmParams::NAMES {
        assert_eq!(FsmParams::default().set(name, "1"), Ok(()), "{name}");
    }
}

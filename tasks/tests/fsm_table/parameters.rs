//! FSM parameters set by name (`group.field`, or the field alone).

use super::*;

#[test]
fn fsm_parameters_are_set_by_name_with_checked_values() {
    let mut p = FsmParams::default();
    assert_eq!(p.set("suppression.settle_frames", "4"), Ok(()));
    assert_eq!(p.set("heading_gain", " 8.5 "), Ok(()));
    assert_eq!(p.set("saccade_yaw_deg_s", "inf"), Ok(()));
    assert_eq!(
        (p.suppression.settle_frames, p.motion.heading_gain),
        (4, 8.5)
    );
    assert_eq!(p.suppression.saccade_yaw_deg_s, f32::INFINITY);
    assert_eq!(p.set("warp", "1"), Err(FsmParamError::Unknown));
    assert_eq!(
        p.set("timing.heading_gain", "1"),
        Err(FsmParamError::Unknown)
    );
    for (name, bad, full) in [
        ("heading_gain", "-1", "motion.heading_gain"),
        ("motion.heading_gain", "inf", "motion.heading_gain"),
        ("cruise_mm_s", "NaN", "motion.cruise_mm_s"),
        ("settle_frames", "1.5", "suppression.settle_frames"),
        ("alert_frames", "-2", "timing.alert_frames"),
    ] {
        assert_eq!(
            p.set(name, bad),
            Err(FsmParamError::Invalid { name: full }),
            "{name}={bad}"
        );
    }
    // refused values leave the parameters as they were
    assert_eq!(
        (p.suppression.settle_frames, p.motion.heading_gain),
        (4, 8.5)
    );
    assert!(FsmParamError::Unknown
        .to_string()
        .contains("suppression.settle_frames"));
    // a refusal says what is allowed, in one line
    let msg = |name: &str, v: &str| FsmParams::default().set(name, v).unwrap_err().to_string();
    assert_eq!(
        msg("alert_frames", "-2"),
        "FSM parameter timing.alert_frames must be a whole number in 0..=4294967295"
    );
    assert_eq!(
        msg("cruise_mm_s", "-1"),
        "FSM parameter motion.cruise_mm_s must be a finite number ≥ 0"
    );
    assert_eq!(
        msg("saccade_yaw_deg_s", "x"),
        "FSM parameter suppression.saccade_yaw_deg_s must be a number ≥ 0, or inf"
    );
    assert_eq!(
        msg("live_strength", "3"),
        "FSM parameter escape.live_strength must be a whole number in 0..=2"
    );
    assert_eq!(
        msg("escape_saccade", "2"),
        "FSM parameter escape.escape_saccade must be a whole number in 0..=1 (or true/false)"
    );
    assert_eq!(
        msg("firmware.short_from_long", "2"),
        "FSM parameter firmware.short_from_long must be a whole number in 0..=1 (or true/false)"
    );
    assert_eq!(
        msg("wander_stop_frames", "never"),
        "FSM parameter firmware.wander_stop_frames must be a whole number in 0..=4294967295 \
         or none"
    );
    assert_eq!(
        msg("look_every", "-1"),
        "FSM parameter swarm.look_every must be a whole number in 0..=4294967295 (0, none or \
         off: off)"
    );
    let mut q = FsmParams::default();
    assert_eq!(q.set("wander_stop_frames", "1000"), Ok(()));
    assert_eq!(q.firmware.wander_stop_frames, Some(1000));
    assert_eq!(q.set("firmware.wander_stop_frames", " none "), Ok(()));
    assert_eq!(q.firmware.wander_stop_frames, None);
    assert_eq!(q.set("short_from_long", "1"), Ok(()));
    assert!(q.firmware.short_from_long);
    assert_eq!(q.set("escape.escape_saccade", "false"), Ok(()));
    assert!(!q.escape.escape_saccade);
    assert_eq!(q.set("escape_saccade", "on"), Ok(()));
    assert!(q.escape.escape_saccade);
    assert_eq!(q.set("look_every", "0"), Ok(()));
    assert_eq!(q.swarm.look_every, None);
    assert_eq!(q.set("swarm.look_every", "45"), Ok(()));
    assert_eq!(q.swarm.look_every, FsmParams::ALVS.swarm.look_every);
    assert_eq!(q.set("look_every", "off"), Ok(()));
    assert_eq!(q.swarm.look_every, None);
    // every name, either spelling, is accepted; the field names are unique
    assert_eq!(FsmParams::NAMES.len(), FsmParams::FIELDS.len());
    for (name, field) in FsmParams::NAMES.iter().zip(FsmParams::FIELDS) {
        assert_eq!(FsmParams::default().set(name, "1"), Ok(()), "{name}");
        assert_eq!(FsmParams::default().set(field, "1"), Ok(()), "{field}");
        assert_eq!(FsmParams::position(field), FsmParams::position(name));
        assert!(name.ends_with(&format!(".{field}")), "{name}");
    }
    // every preset lies within the ranges
    for p in [FsmParams::PAPER, FsmParams::ALVS, FsmParams::FIRMWARE] {
        assert_eq!(p.validate(), Ok(()), "{}", p.preset_name());
    }
}

//! The escape FSM's unit tests: presets, the wheels' mixing, the heading controller and the
//! states' transitions (`tasks/tests/fsm_table` holds the table-driven ones).

use core::num::NonZeroU32;

use super::*;

fn close(a: f32, b: f32, tol: f32) -> bool {
    (a - b).abs() <= tol
}

fn quiet() -> Visuomotor {
    Visuomotor {
        strength: 0.5,
        ..Visuomotor::default()
    }
}

#[test]
fn the_groups_cost_no_ram() {
    // the flat struct before the groups took 120 bytes; the groups saved 4, which the jump
    // (`jump_frames`) took back
    assert_eq!(core::mem::size_of::<FsmParams>(), 120);
}

#[test]
fn the_papers_motion_has_none_of_the_fsm_mechanisms() {
    // the default is the paper's plus the escape saccade, the moving takeoff, brisk
    // saccades, the takeoff's jump, the brisk γ path and the swarm's looks, nothing else
    assert_eq!(
        FsmParams {
            escape: Escape {
                escape_saccade: false,
                takeoff_drive: 0.0,
                takeoff_gain: 1.0,
                takeoff_yaw_deg_s: 360.0,
                jump_frames: None,
                gamma_turn: false,
                ..FsmParams::default().escape
            },
            swarm: Swarm {
                look_every: None,
                ..FsmParams::default().swarm
            },
            ..FsmParams::default()
        },
        FsmParams::PAPER
    );
    let a = FsmParams::ALVS;
    assert_eq!(
        (
            a.escape.escape_saccade,
            a.escape.takeoff_drive,
            a.escape.takeoff_gain,
            a.escape.takeoff_yaw_deg_s,
            a.escape.jump_frames,
            a.swarm.look_every
        ),
        (
            true,
            0.5,
            3.0,
            f32::INFINITY,
            NonZeroU32::new(6),
            NonZeroU32::new(45)
        )
    );
    let p = FsmParams::PAPER;
    // γ paths from every state, S latched at the trigger, a turn in place, an unbounded
    // retreat: the paper's FSM (docs/model.md)
    assert_eq!(
        (
            p.escape.escape_saccade,
            p.escape.live_strength,
            p.escape.takeoff_drive,
            p.timing.retreat_frames
        ),
        (false, 0, 0.0, u32::MAX)
    );
}

#[test]
fn the_firmware_is_the_papers_motion_with_the_documented_values_only() {
    let (p, fw) = (FsmParams::PAPER, FsmParams::FIRMWARE);
    // docs/notes/2026-11-27-authors-firmware.md: each value and its source line
    assert_eq!(
        (
            fw.motion.max_escape_mm_s,
            fw.motion.retreat_mm_s,
            fw.motion.max_wheel_mm_s
        ),
        (180.0, 180.0, 180.0)
    );
    assert_eq!(
        (
            fw.motion.heading_gain,
            fw.motion.max_yaw_deg_s,
            fw.escape.takeoff_yaw_deg_s
        ),
        (6.2, 239.0, 239.0)
    );
    assert_eq!(
        (fw.timing.min_escape_frames, fw.timing.quiet_frames),
        (0, 0)
    );
    assert_eq!(fw.timing.takeoff_timeout_frames, u32::MAX);
    assert_eq!(fw.suppression.saccade_yaw_deg_s, f32::INFINITY);
    assert_eq!(fw.timing.alert_frames, 3);
    assert!(fw.firmware.short_from_long);
    assert_eq!(fw.firmware.wander_stop_frames, Some(1000));
    assert_eq!(
        (p.firmware.short_from_long, p.firmware.wander_stop_frames),
        (false, None)
    );
    assert_eq!(
        (
            FsmParams::ALVS.firmware.short_from_long,
            FsmParams::ALVS.firmware.wander_stop_frames
        ),
        (false, None)
    );
    assert_eq!(
        FsmParams {
            motion: Motion {
                max_escape_mm_s: p.motion.max_escape_mm_s,
                retreat_mm_s: p.motion.retreat_mm_s,
                max_wheel_mm_s: p.motion.max_wheel_mm_s,
                heading_gain: p.motion.heading_gain,
                max_yaw_deg_s: p.motion.max_yaw_deg_s,
                ..fw.motion
            },
            escape: Escape {
                takeoff_yaw_deg_s: p.escape.takeoff_yaw_deg_s,
                ..fw.escape
            },
            timing: Timing {
                min_escape_frames: p.timing.min_escape_frames,
                quiet_frames: p.timing.quiet_frames,
                takeoff_timeout_frames: p.timing.takeoff_timeout_frames,
                alert_frames: p.timing.alert_frames,
                ..fw.timing
            },
            suppression: Suppression {
                saccade_yaw_deg_s: p.suppression.saccade_yaw_deg_s,
                ..fw.suppression
            },
            firmware: FirmwareFsm {
                short_from_long: p.firmware.short_from_long,
                wander_stop_frames: p.firmware.wander_stop_frames
            },
            ..fw
        },
        p
    );
    assert_eq!(fw.preset_name(), "firmware");
    assert_eq!(
        FsmParams {
            timing: Timing {
                alert_frames: 1,
                ..fw.timing
            },
            ..fw
        }
        .preset_name(),
        "custom"
    );
}

#[test]
fn mixing_follows_the_right_positive_convention() {
    let p = FsmParams::default();
    // straight
    assert_eq!(mix(100.0, 0.0, &p), (100.0, 100.0));
    // 1 rad/s right in place: left wheel forward by track/2
    let (l, r) = mix(0.0, 1.0, &p);
    assert!(close(l, 24.0, 1e-4) && close(r, -24.0, 1e-4));
    // reversing while turning left
    let (l, r) = mix(-50.0, -1.0, &p);
    assert!(close(l, -74.0, 1e-4) && close(r, -26.0, 1e-4));
}

#[test]
fn mixing_saturates_with_turn_priority() {
    let p = FsmParams {
        motion: Motion {
            max_wheel_mm_s: 100.0,
            ..FsmParams::default().motion
        },
        ..FsmParams::default()
    };
    // 2 rad/s · 24 mm = 48 mm/s of turn leaves 52 mm/s of forward speed
    let (l, r) = mix(500.0, 2.0, &p);
    assert!(close(l, 100.0, 1e-3) && close(r, 4.0, 1e-3), "{l} {r}");
    // the turn alone is limited too
    let (l, r) = mix(0.0, 100.0, &p);
    assert!(close(l, 100.0, 1e-3) && close(r, -100.0, 1e-3));
    // garbage gives zero, not a panic
    assert_eq!(mix(f32::NAN, f32::NAN, &p), (0.0, 0.0));
    let bad = FsmParams {
        motion: Motion {
            max_wheel_mm_s: f32::NAN,
            track_mm: -1.0,
            ..p.motion
        },
        ..p
    };
    assert_eq!(mix(100.0, 1.0, &bad), (0.0, 0.0));
}

#[test]
fn yaw_rate_is_a_clamped_p_controller() {
    let p = FsmParams::default();
    assert!(close(yaw_rate_rad_s(10.0, &p), 40f32.to_radians(), 1e-5));
    assert!(close(
        yaw_rate_rad_s(-170.0, &p),
        -(360f32.to_radians()),
        1e-5
    ));
    assert_eq!(yaw_rate_rad_s(f32::NAN, &p), 0.0);
}

#[test]
fn heading_error_takes_the_short_way_across_180() {
    assert!(close(heading_error_deg(170.0, -170.0), -20.0, 1e-4));
    assert!(close(heading_error_deg(-170.0, 170.0), 20.0, 1e-4));
    assert!(close(heading_error_deg(180.0, 0.0), 180.0, 1e-4));
    assert!(close(heading_error_deg(-90.0, 90.0), 180.0, 1e-4));
}

#[test]
fn odometry_integrates_and_wraps() {
    let mut o = Odometry::new(48.0, 0.0);
    // left − right = 48 mm/s over track 48 mm: 1 rad/s to the right
    for _ in 0..30 {
        o.update(24.0, -24.0, 1.0 / 30.0);
    }
    assert!(
        close(o.heading_deg(), 57.295_78, 1e-2),
        "{}",
        o.heading_deg()
    );
    // past 180° it wraps to negative
    let mut o = Odometry::new(48.0, 170.0);
    let h = o.update(48.0, 0.0, 20f32.to_radians());
    assert!(close(h, -170.0, 1e-3), "{h}");
    // straight motion does not turn; bad input is ignored
    assert_eq!(o.update(100.0, 100.0, 0.1), h);
    assert_eq!(o.update(f32::NAN, 0.0, 0.1), h);
    assert_eq!(o.update(10.0, 0.0, -0.1), h);
    assert_eq!(Odometry::new(0.0, 5.0).update(10.0, 0.0, 0.1), 5.0);
    assert_eq!(Odometry::new(48.0, 540.0).heading_deg(), 180.0);
}

#[test]
fn wander_holds_the_heading_latched_at_the_first_frame() {
    let mut f = Fsm::new(FsmParams::default(), Behaviour::Escape);
    let c = f.step(&quiet(), 30.0);
    assert_eq!((c.state, c.heading_setpoint_deg), (State::Wander, 30.0));
    assert_eq!((c.left_mm_s, c.right_mm_s), (100.0, 100.0));
    // drifted right: steer left
    let c = f.step(&quiet(), 35.0);
    assert!(c.left_mm_s < c.right_mm_s);
    assert_eq!(c.heading_setpoint_deg, 30.0);
}

#[test]
fn set_points_are_wrapped_absolute_headings() {
    // the paper's turn in place (the default's moving takeoff: the next test)
    let mut f = Fsm::new(FsmParams::PAPER, Behaviour::Escape);
    let vm = Visuomotor {
        alert: true,
        strength: 0.6,
        theta_long: Some(145.0),
        ..Visuomotor::default()
    };
    let c = f.step(&vm, 100.0);
    assert_eq!(c.state, State::LongTakeoff);
    assert!(close(c.heading_setpoint_deg, -115.0, 1e-4));
    // in place: wheels opposite
    assert!(close(c.left_mm_s, -c.right_mm_s, 1e-4) && c.left_mm_s > 0.0);
}

#[test]
fn a_long_takeoff_can_move_away_while_it_turns() {
    // the paper's turn rate: the default's brisk turn takes all the wheels' speed at first
    let p = FsmParams {
        escape: Escape {
            takeoff_drive: 1.0,
            takeoff_gain: 1.0,
            takeoff_yaw_deg_s: 360.0,
            ..FsmParams::default().escape
        },
        ..FsmParams::default()
    };
    let mut f = Fsm::new(p, Behaviour::Escape);
    let vm = Visuomotor {
        alert: true,
        strength: 0.6,
        theta_long: Some(-145.0),
        ..Visuomotor::default()
    };
    // the set-point is 145° to the left, behind: reverse while turning left, at
    // 0.6 · 200 · cos 145° = −98 mm/s
    let c = f.step(&vm, 0.0);
    assert_eq!(c.state, State::LongTakeoff);
    let v = (c.left_mm_s + c.right_mm_s) / 2.0;
    assert!(close(v, -98.3, 0.5), "{v}");
    assert!(c.left_mm_s < c.right_mm_s, "turning left");
    // 30° to go: forward at 0.6 · 200 · cos 30° = 104 mm/s, still turning left
    let c = f.step(&quiet(), -115.0);
    assert_eq!(c.state, State::LongTakeoff);
    let v = (c.left_mm_s + c.right_mm_s) / 2.0;
    assert!(close(v, 103.9, 0.5), "{v}");
    assert!(c.left_mm_s < c.right_mm_s);
}

#[test]
fn the_gamma_path_turns_like_the_takeoff_with_gamma_turn() {
    // the first frame of a γ path from a threat at −35°: θ¹ 55° to the right
    let first = |gamma_turn: bool| {
        let p = FsmParams {
            escape: Escape {
                gamma_turn,
                ..FsmParams::ALVS.escape
            },
            ..FsmParams::ALVS
        };
        let mut f = Fsm::new(p, Behaviour::Escape);
        let vm = Visuomotor {
            alert: true,
            short_mode: true,
            strength: 0.9,
            theta_long: Some(145.0),
            theta_short: Some([55.0, 145.0]),
            ..Visuomotor::default()
        };
        let c = f.step(&vm, 0.0);
        assert_eq!(c.state, State::ShortTakeoff);
        let yaw = (c.left_mm_s - c.right_mm_s) / p.motion.track_mm;
        (yaw.to_degrees(), (c.left_mm_s + c.right_mm_s) / 2.0)
    };
    let (slow, brisk) = (first(false), first(true));
    // heading_gain 4/s: 220°/s; three times that, held to the paper's 360°/s
    assert!(close(slow.0, 220.0, 1.0), "{slow:?}");
    assert!(close(brisk.0, 360.0, 1.0), "{brisk:?}");
    // the limit leaves the retreat its speed, S · 150 mm/s, in both
    assert!(
        close(slow.1, -135.0, 0.5) && close(brisk.1, -135.0, 0.5),
        "{slow:?} {brisk:?}"
    );
}

#[test]
fn a_takeoff_from_standing_on_a_looming_response_starts_its_escape_with_the_jump() {
    // the escape's forward speed on each of its first 8 frames, after an alert that comes
    // to a robot standing (held) or wandering
    let speeds = |p: FsmParams, standing: bool, lplc2_sum: u32, strength: f32| {
        let mut f = Fsm::new(p, Behaviour::Escape);
        f.step(&quiet(), 0.0);
        if standing {
            f.command_not_applied();
        }
        let vm = Visuomotor {
            alert: true,
            lplc2_sum,
            strength,
            theta_long: Some(180.0),
            ..Visuomotor::default()
        };
        f.step(&vm, 0.0);
        let mut v = [0.0f32; 8];
        for x in &mut v {
            let c = f.step(&quiet(), 180.0);
            assert_eq!(c.state, State::Escape);
            *x = (c.left_mm_s + c.right_mm_s) / 2.0;
        }
        v
    };
    let alvs = FsmParams::default();
    // standing, a field's response: 6 frames at full strength, then S · 200
    let v = speeds(alvs, true, 2000, 0.6);
    assert!(v[..6].iter().all(|&x| close(x, 200.0, 0.5)), "{v:?}");
    assert!(v[6..].iter().all(|&x| close(x, 120.0, 0.5)), "{v:?}");
    // wandering: no takeoff to make, S from the start
    let v = speeds(alvs, false, 2000, 0.6);
    assert!(v.iter().all(|&x| close(x, 120.0, 0.5)), "{v:?}");
    // the floor line's alert (ΣLPLC2 0, S 0.5) is a distance, not a looming threat
    let v = speeds(alvs, true, 0, 0.5);
    assert!(v.iter().all(|&x| close(x, 100.0, 0.5)), "{v:?}");
    // the paper's model has no jump
    let v = speeds(FsmParams::PAPER, true, 2000, 0.6);
    assert!(v.iter().all(|&x| close(x, 120.0, 0.5)), "{v:?}");
}

#[test]
fn non_finite_input_stops_without_transition() {
    let mut f = Fsm::new(FsmParams::default(), Behaviour::Escape);
    f.step(&quiet(), 0.0);
    let alert = Visuomotor {
        alert: true,
        theta_long: Some(f32::NAN),
        strength: 0.7,
        ..Visuomotor::default()
    };
    let c = f.step(&alert, 0.0);
    assert_eq!(
        (c.state, c.left_mm_s, c.right_mm_s),
        (State::Wander, 0.0, 0.0)
    );
    let c = f.step(&quiet(), f32::INFINITY);
    assert_eq!(
        (c.state, c.left_mm_s, c.right_mm_s),
        (State::Wander, 0.0, 0.0)
    );
}

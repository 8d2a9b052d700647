//! The authors' firmware's state machine (`FsmParams::FIRMWARE`, docs/model.md "The
//! authors' firmware"): three alert frames before it acts, the γ path only out of a long
//! takeoff, one frame of escape after it, the stop after 1000 quiet frames of wandering.

use super::*;

fn firmware() -> Fsm {
    Fsm::new(FsmParams::FIRMWARE, Behaviour::Escape)
}

/// Its spike count: an alert acts on its third frame in a row; a gap starts the count again.
#[test]
fn the_firmware_acts_on_the_third_alert_frame_in_a_row() {
    let mut f = firmware();
    let h = 0.0;
    assert_eq!(f.step(&quiet(), h).state, State::Wander);
    assert_eq!(f.step(&long(RIGHT_X), h).state, State::Wander);
    assert_eq!(f.step(&long(RIGHT_X), h).state, State::Wander);
    assert_eq!(f.step(&quiet(), h).state, State::Wander, "a gap");
    assert_eq!(f.step(&long(RIGHT_X), h).state, State::Wander);
    assert_eq!(f.step(&long(RIGHT_X), h).state, State::Wander);
    assert_eq!(f.step(&long(RIGHT_X), h).state, State::LongTakeoff);
}

/// Short mode in Wander starts a long takeoff; in the long takeoff, a short one. The paper's
/// FSM with the same spike count goes straight to the γ path.
#[test]
fn the_firmware_takes_the_gamma_path_only_out_of_a_long_takeoff() {
    let h = 0.0;
    let mut f = firmware();
    f.step(&quiet(), h);
    for _ in 0..2 {
        assert_eq!(f.step(&short(RIGHT_X), h).state, State::Wander);
    }
    assert_eq!(f.step(&short(RIGHT_X), h).state, State::LongTakeoff);
    let c = f.step(&short(RIGHT_X), h);
    assert_eq!(
        (c.state, c.short_phase),
        (State::ShortTakeoff, Some(ShortPhase::Retreat))
    );
    // reversing while it turns, no wheel beyond the firmware's 180 mm/s (4.5 of its units)
    assert!(c.left_mm_s + c.right_mm_s < 0.0, "{c:?}");
    assert!(
        c.left_mm_s.abs().max(c.right_mm_s.abs()) <= 180.0 + 1e-3,
        "{c:?}"
    );

    let mut paper = Fsm::new(
        FsmParams {
            timing: Timing {
                alert_frames: 3,
                ..params().timing
            },
            ..params()
        },
        Behaviour::Escape,
    );
    paper.step(&quiet(), h);
    paper.step(&short(RIGHT_X), h);
    paper.step(&short(RIGHT_X), h);
    assert_eq!(paper.step(&short(RIGHT_X), h).state, State::ShortTakeoff);
}

/// Aligned, the long takeoff escapes for one frame at `S · 180` mm/s, then wanders at the
/// cruise speed: the firmware's escape holds the heading it turned to and ends at once.
#[test]
fn after_a_long_takeoff_the_firmware_escapes_for_one_frame() {
    let mut f = firmware();
    let h = 0.0;
    f.step(&quiet(), h);
    let mut c = f.step(&long(RIGHT_X), h);
    for _ in 0..2 {
        c = f.step(&long(RIGHT_X), h);
    }
    assert_eq!(c.state, State::LongTakeoff);
    // turning in place, at most 239°/s
    assert!((c.left_mm_s + c.right_mm_s).abs() < 1e-3, "{c:?}");
    let yaw = (c.left_mm_s - c.right_mm_s) / FsmParams::FIRMWARE.motion.track_mm;
    assert!(yaw.abs().to_degrees() <= 239.0 + 1e-3, "{c:?}");
    let sp = c.heading_setpoint_deg;
    let c = f.step(&quiet(), sp);
    assert_eq!(c.state, State::Escape);
    let s = long(RIGHT_X).strength;
    assert!(
        ((c.left_mm_s + c.right_mm_s) / 2.0 - s * 180.0).abs() < 0.5,
        "{c:?}"
    );
    let c = f.step(&quiet(), sp);
    assert_eq!(c.state, State::Wander);
    assert_eq!((c.left_mm_s, c.right_mm_s), (100.0, 100.0));
}

/// 1000 frames of wandering without an alert, then it stands, until a threat (three alert
/// frames) starts a long takeoff.
#[test]
fn the_firmware_stops_after_1000_quiet_frames_until_a_threat() {
    let mut f = firmware();
    let h = 30.0;
    for i in 0..1000 {
        assert_eq!(f.step(&quiet(), h).state, State::Wander, "frame {i}");
    }
    let c = f.step(&quiet(), h);
    assert_eq!(c.state, State::Stop);
    assert!(stopped(&c));
    for _ in 0..100 {
        assert!(stopped(&f.step(&quiet(), h)));
    }
    for _ in 0..2 {
        assert_eq!(f.step(&long(LEFT_X), h).state, State::Stop);
    }
    assert_eq!(f.step(&long(LEFT_X), h).state, State::LongTakeoff);
    // an alert before the 1000th frame starts the count again
    let mut f = firmware();
    for _ in 0..900 {
        f.step(&quiet(), h);
    }
    for _ in 0..3 {
        f.step(&long(LEFT_X), h);
    }
    let sp = f.step(&quiet(), h).heading_setpoint_deg;
    assert_eq!(f.step(&quiet(), sp).state, State::Escape);
    // the frame that ends the escape is not yet one of the wander's 1000
    for i in 0..=1000 {
        assert_eq!(f.step(&quiet(), sp).state, State::Wander, "frame {i}");
    }
    assert_eq!(f.step(&quiet(), sp).state, State::Stop);
}

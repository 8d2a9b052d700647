//! Saccadic suppression, the settle period and consecutive alerts.

use super::*;

#[test]
fn perception_is_ignored_while_the_robot_turns_fast() {
    // suppression above 45 °/s of commanded yaw; the paper's FSM, whose short mode during the
    // escape that follows is a γ path (the default's saccade: saccade.rs)
    let mut f = Fsm::new(FsmParams::PAPER, Behaviour::Escape);
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
        suppression: Suppression {
            settle_frames: 3,
            ..FsmParams::PAPER.suppression
        },
        ..FsmParams::PAPER
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
        timing: Timing {
            alert_frames: 2,
            ..FsmParams::default().timing
        },
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
            timing: Timing {
                alert_frames: 0,
                ..FsmParams::default().timing
            },
            ..FsmParams::default()
        },
        Behaviour::Escape,
    );
    f.step(&quiet(), 0.0);
    assert_eq!(f.step(&quiet(), 0.0).state, State::Wander);
    assert_eq!(f.step(&long(RIGHT_X), 0.0).state, State::LongTakeoff);
}

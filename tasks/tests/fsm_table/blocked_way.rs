//! The blocked-way test (efference copy, `model::closed_loop::progress`): forward travel commanded, view
//! unchanged → turn around; a changing view, a turning robot or no views → nothing.

use super::*;
use alvs_tasks::model::closed_loop::progress::{View, VIEW_CELLS};

/// A quiet frame with a view whose cells are all `level`, and the threshold 6.
fn seeing(level: u8) -> Visuomotor {
    Visuomotor {
        view: Some(([level; VIEW_CELLS] as View, 6)),
        ..quiet()
    }
}

/// Steps a wandering FSM (heading 0) through `views`; the state after each.
fn wander_through(views: impl Iterator<Item = Visuomotor>) -> Vec<MotorCommand> {
    let mut f = Fsm::new(FsmParams::default(), Behaviour::Escape);
    views.map(|vm| f.step(&vm, 0.0)).collect()
}

#[test]
fn a_still_view_while_driving_forward_turns_the_robot_around() {
    // frame 0 takes the first view; 15 frames of cruise (100 mm/s: 50 mm) later, the same view
    let c = wander_through((0..17).map(|_| seeing(120)));
    assert!(c[..15].iter().all(|c| c.state == State::Wander));
    assert_eq!(c[15].state, State::LongTakeoff);
    assert!(
        err(c[15].heading_setpoint_deg, 180.0) < 1e-3,
        "{}",
        c[15].heading_setpoint_deg
    );
}

#[test]
fn a_changing_view_no_view_or_too_little_travel_do_nothing() {
    // the view changes by 6 levels between comparisons: the way is free
    let c = wander_through((0..40).map(|k| seeing(100 + 6 * (k as u8 / 15))));
    assert!(c.iter().all(|c| c.state == State::Wander));
    // the paper's model reports no views
    let c = wander_through((0..40).map(|_| quiet()));
    assert!(c.iter().all(|c| c.state == State::Wander));
    // 40 mm in 15 frames needs 80 mm/s; at a 60 mm/s cruise the test never fires
    let mut slow = FsmParams::default();
    slow.set("cruise_mm_s", "60").unwrap();
    let mut f = Fsm::new(slow, Behaviour::Escape);
    assert!((0..40).all(|_| f.step(&seeing(120), 0.0).state == State::Wander));
}

#[test]
fn a_held_robot_is_not_blocked() {
    // the same still view, but the wheels never carried out the commands (motors disabled or
    // the robot held): no travel, so no turning round
    let mut f = Fsm::new(FsmParams::default(), Behaviour::Escape);
    for _ in 0..40 {
        assert_eq!(f.step(&seeing(120), 0.0).state, State::Wander);
        f.command_not_applied();
    }
    // released, it drives: within two comparison periods the still view turns it round
    let states: Vec<State> = (0..31).map(|_| f.step(&seeing(120), 0.0).state).collect();
    assert!(states.contains(&State::LongTakeoff), "{states:?}");
}

#[test]
fn the_blocked_way_parameters_are_set_by_name() {
    let mut p = FsmParams::default();
    assert_eq!(
        (
            p.blocked.blocked_frames,
            p.blocked.blocked_travel_mm,
            p.blocked.blocked_yaw_deg
        ),
        (15, 40.0, 10.0)
    );
    p.set("blocked_frames", "0").unwrap();
    p.set("blocked_travel_mm", "25").unwrap();
    p.set("blocked_yaw_deg", "5").unwrap();
    assert_eq!(
        (
            p.blocked.blocked_frames,
            p.blocked.blocked_travel_mm,
            p.blocked.blocked_yaw_deg
        ),
        (0, 25.0, 5.0)
    );
    // blocked_frames 0 turns the test off
    let mut f = Fsm::new(p, Behaviour::Escape);
    assert!((0..40).all(|_| f.step(&seeing(120), 0.0).state == State::Wander));
}

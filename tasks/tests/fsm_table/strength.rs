//! The escape strength `S(t)` of Eq. (11): latched at the trigger (the default) or live
//! (`FsmParams::live_strength`).

use super::*;
use alvs_tasks::model::visuomotor::strength;

fn forward(c: &MotorCommand) -> f32 {
    (c.left_mm_s + c.right_mm_s) / 2.0
}

fn with_live(live: u8) -> Fsm {
    Fsm::new(
        FsmParams {
            escape: Escape {
                live_strength: live,
                ..params().escape
            },
            ..params()
        },
        Behaviour::Escape,
    )
}

/// Escape speeds of the first three frames of an escape from a long takeoff (S = S(4000)),
/// with nothing looming and then a weak threat (Σ = 2000, ignored before the minimum escape).
fn escape_speeds(live: u8) -> [f32; 3] {
    let mut f = with_live(live);
    f.step(&quiet(), 0.0);
    let sp = f.step(&long(RIGHT_X), 0.0).heading_setpoint_deg;
    let first = f.step(&quiet(), sp);
    assert_eq!(first.state, State::Escape);
    let second = f.step(&quiet(), sp);
    let third = f.step(&threat(LEFT_X, 2000), sp);
    assert_eq!((second.state, third.state), (State::Escape, State::Escape));
    [forward(&first), forward(&second), forward(&third)]
}

#[test]
fn the_escape_runs_at_the_latched_strength_unless_it_is_live() {
    let max = FsmParams::default().motion.max_escape_mm_s;
    let latched = strength(LONG_R, Params::default().table1.w_s) * max;
    for v in escape_speeds(0) {
        assert!((v - latched).abs() < 0.1, "{v} vs {latched}");
    }
    // live: the frame that enters the escape still runs at the trigger's strength; then S
    // follows the response, 0.5 with nothing looming, S(2000) on the weak threat
    let [a, b, c] = escape_speeds(1);
    assert!((a - latched).abs() < 0.1, "{a}");
    assert!((b - 0.5 * max).abs() < 0.1, "{b}");
    let weak = strength(2000, Params::default().table1.w_s) * max;
    assert!((c - weak).abs() < 0.1 && c > b, "{c}");
}

#[test]
fn a_live_strength_of_2_also_sets_the_retreat_speed() {
    let retreat = FsmParams::default().motion.retreat_mm_s;
    let s_short = strength(SHORT_R, Params::default().table1.w_s);
    for (live, s) in [(0, s_short), (1, s_short), (2, 0.5)] {
        let mut f = with_live(live);
        f.step(&quiet(), 0.0);
        let c = f.step(&short(RIGHT_X), 0.0);
        assert_eq!(c.short_phase, Some(ShortPhase::Retreat));
        assert!((forward(&c) + s_short * retreat).abs() < 0.1);
        // one frame later, still reversing, nothing looming
        let c = f.step(&quiet(), 0.0);
        assert_eq!(c.short_phase, Some(ShortPhase::Retreat), "live {live}");
        assert!(
            (forward(&c) + s * retreat).abs() < 0.1,
            "live {live}: {}",
            forward(&c)
        );
    }
}

#[test]
fn a_suppressed_frame_keeps_the_strength() {
    // saccadic suppression on (45°/s) against off: the escape steers back from 30° off its
    // set-point at 4 · 30 = 120°/s, so the next frame's perception is ignored and S stays
    let max = FsmParams::default().motion.max_escape_mm_s;
    let w_s = Params::default().table1.w_s;
    for (saccade, s) in [(45.0, 0.5), (f32::INFINITY, strength(2000, w_s))] {
        let mut f = Fsm::new(
            FsmParams {
                escape: Escape {
                    live_strength: 1,
                    ..FsmParams::default().escape
                },
                suppression: Suppression {
                    saccade_yaw_deg_s: saccade,
                    ..FsmParams::default().suppression
                },
                ..FsmParams::default()
            },
            Behaviour::Escape,
        );
        f.step(&quiet(), 0.0);
        let sp = f.step(&long(RIGHT_X), 0.0).heading_setpoint_deg;
        assert_eq!(f.step(&quiet(), sp).state, State::Escape);
        // aligned on the frame before: live, nothing looming
        let c = f.step(&quiet(), sp + 30.0);
        assert!((forward(&c) - 0.5 * max).abs() < 0.1, "{}", forward(&c));
        assert_eq!(f.suppressed(), saccade == 45.0);
        let c = f.step(&threat(LEFT_X, 2000), sp + 30.0);
        assert_eq!(c.state, State::Escape);
        assert!(
            (forward(&c) - s * max).abs() < 0.1,
            "{saccade}: {}",
            forward(&c)
        );
    }
}

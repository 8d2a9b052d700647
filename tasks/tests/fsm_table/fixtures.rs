//! Fixtures: inputs, tolerances and an FSM in each state.

use super::*;

pub(crate) const DT: f32 = 1.0 / 30.0;
/// Image columns of a threat on the left and on the right of the 99-pixel horizon.
pub(crate) const LEFT_X: u8 = 10;
pub(crate) const RIGHT_X: u8 = 88;
/// LPLC2 sums below and above `T_s` (Table I 7000, the default 5500).
pub(crate) const LONG_R: u32 = 4000;
pub(crate) const SHORT_R: u32 = 8000;

pub(crate) fn quiet() -> Visuomotor {
    Visuomotor::from_fields(core::iter::empty(), &Params::default())
}

pub(crate) fn threat(x: u8, r: u32) -> Visuomotor {
    Visuomotor::from_fields([(x, r)].into_iter(), &Params::default())
}

pub(crate) fn long(x: u8) -> Visuomotor {
    let v = threat(x, LONG_R);
    assert!(v.alert && !v.short_mode);
    v
}

pub(crate) fn short(x: u8) -> Visuomotor {
    let v = threat(x, SHORT_R);
    assert!(v.alert && v.short_mode);
    v
}

/// Absolute bearing of a threat at column `x` seen from heading `h`.
pub(crate) fn threat_abs(x: u8, h: f32) -> f32 {
    wrap_deg(h + bearing(f32::from(x), Params::default().table1.alpha))
}

pub(crate) fn err(a: f32, b: f32) -> f32 {
    wrap_deg(a - b).abs()
}

pub(crate) fn stopped(c: &MotorCommand) -> bool {
    c.stands()
}

pub(crate) fn tol() -> f32 {
    FsmParams::default().motion.align_tol_deg
}

// ---- getting an FSM into each state (heading frozen unless said otherwise) ----

/// The transition logic itself, the paper's (`FsmParams::PAPER`: a γ path from every state;
/// the default's escape saccade has its own tests, `saccade.rs`), without saccadic
/// suppression (tested on its own below): these tests freeze or script the heading, so a
/// commanded turn never happens.
pub(crate) fn params() -> FsmParams {
    FsmParams {
        suppression: Suppression {
            saccade_yaw_deg_s: f32::INFINITY,
            ..FsmParams::PAPER.suppression
        },
        ..FsmParams::PAPER
    }
}

pub(crate) fn fsm(b: Behaviour) -> Fsm {
    Fsm::new(params(), b)
}

/// Wander at heading `h`.
pub(crate) fn in_wander(h: f32) -> Fsm {
    let mut f = fsm(Behaviour::Escape);
    assert_eq!(f.step(&quiet(), h).state, State::Wander);
    f
}

/// LongTakeoff from heading `h` for a right threat; returns the set-point.
pub(crate) fn in_long(h: f32) -> (Fsm, f32) {
    let mut f = in_wander(h);
    let c = f.step(&long(RIGHT_X), h);
    assert_eq!(c.state, State::LongTakeoff);
    (f, c.heading_setpoint_deg)
}

/// Escape, just entered (aligned with the long-takeoff set-point); returns the escape heading.
pub(crate) fn in_escape(h: f32) -> (Fsm, f32) {
    let (mut f, sp) = in_long(h);
    assert_eq!(f.step(&quiet(), sp).state, State::Escape);
    (f, sp)
}

/// Escape past its minimum duration with an alert on the last frame (quiet count at 0).
pub(crate) fn in_escape_late(h: f32) -> (Fsm, f32) {
    let (mut f, sp) = in_escape(h);
    // alerts before the minimum duration are ignored (but reset the quiet count); the next
    // frame is the first that may act
    for _ in 1..FsmParams::default().timing.min_escape_frames {
        assert_eq!(f.step(&long(LEFT_X), sp).state, State::Escape);
    }
    (f, sp)
}

/// ShortTakeoff, phase Retreat, from heading `h` for a right threat; returns (sp¹, sp²).
pub(crate) fn in_short(h: f32) -> (Fsm, [f32; 2]) {
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
pub(crate) fn in_short_turn(h: f32) -> (Fsm, [f32; 2]) {
    let (mut f, sp) = in_short(h);
    let c = f.step(&quiet(), sp[0]);
    assert_eq!(
        (c.state, c.short_phase),
        (State::ShortTakeoff, Some(ShortPhase::Turn))
    );
    (f, sp)
}

/// Stop at heading `h`: after 2 quiet frames of wandering (`FsmParams::wander_stop_frames`).
pub(crate) fn in_stop(h: f32) -> Fsm {
    let mut f = Fsm::new(
        FsmParams {
            firmware: FirmwareFsm {
                wander_stop_frames: Some(2),
                ..params().firmware
            },
            ..params()
        },
        Behaviour::Escape,
    );
    for _ in 0..2 {
        assert_eq!(f.step(&quiet(), h).state, State::Wander);
    }
    assert_eq!(f.step(&quiet(), h).state, State::Stop);
    f
}

pub(crate) fn swarm_wander(h: f32) -> Fsm {
    let mut f = fsm(Behaviour::Swarm);
    assert_eq!(f.step(&quiet(), h).state, State::Wander);
    f
}

pub(crate) fn swarm_spin(h: f32) -> Fsm {
    let mut f = swarm_wander(h);
    assert_eq!(f.step(&long(LEFT_X), h).state, State::Spin);
    f
}

/// The swarm with looks every `every` frames of wandering (`FsmParams::look_every`).
pub(crate) fn swarm_looking(every: u32) -> Fsm {
    Fsm::new(
        FsmParams {
            swarm: Swarm {
                look_every: NonZeroU32::new(every),
                ..params().swarm
            },
            ..params()
        },
        Behaviour::Swarm,
    )
}

/// Look, standing at heading `h` (looks after every frame of wandering).
pub(crate) fn swarm_look(h: f32) -> Fsm {
    let mut f = swarm_looking(1);
    assert_eq!(f.step(&quiet(), h).state, State::Look);
    f
}

/// [`quiet`] with what a look saw.
pub(crate) fn saw(s: Sighting) -> Visuomotor {
    Visuomotor {
        sighting: Some(s),
        ..quiet()
    }
}

/// Runs the FSM in closed loop with odometry from heading `h0`; `vm_at(frame)` gives the input.
/// Returns the commands and the heading after each of them.
pub(crate) fn closed_loop(
    f: &mut Fsm,
    h0: f32,
    frames: usize,
    vm_at: impl Fn(usize) -> Visuomotor,
) -> Vec<(MotorCommand, f32)> {
    let mut odo = Odometry::new(f.params().motion.track_mm, h0);
    (0..frames)
        .map(|i| {
            let c = f.step(&vm_at(i), odo.heading_deg());
            (c, odo.update(c.left_mm_s, c.right_mm_s, DT))
        })
        .collect()
}

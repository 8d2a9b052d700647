//! Bad input: non-finite values stop the wheels, any input keeps the outputs finite.

use super::*;
use alvs_tasks::model::closed_loop::progress::VIEW_CELLS;

#[test]
fn non_finite_inputs_stop_the_wheels_without_a_transition() {
    let bad_vms = {
        let base = short(RIGHT_X);
        [
            Visuomotor {
                strength: f32::NAN,
                ..base
            },
            Visuomotor {
                threat_x: Some(f32::INFINITY),
                ..base
            },
            Visuomotor {
                theta_long: Some(f32::NAN),
                ..base
            },
            Visuomotor {
                theta_short: Some([10.0, f32::NEG_INFINITY]),
                ..base
            },
        ]
    };
    let starts: Vec<(&str, Fsm, f32)> = vec![
        ("wander", in_wander(10.0), 10.0),
        ("long", in_long(10.0).0, 10.0),
        ("escape", in_escape(10.0).0, 10.0),
        ("short", in_short(10.0).0, 10.0),
        ("short turn", in_short_turn(10.0).0, 10.0),
        ("swarm wander", swarm_wander(10.0), 10.0),
        ("swarm spin", swarm_spin(10.0), 10.0),
        ("fresh", fsm(Behaviour::Escape), 10.0),
    ];
    for (what, f, h) in starts {
        let inputs = bad_vms
            .iter()
            .map(|v| (*v, h))
            .chain([f32::NAN, f32::INFINITY, f32::NEG_INFINITY].map(|bad| (short(LEFT_X), bad)));
        for (vm, heading) in inputs {
            let mut g = f.clone();
            let (state, phase) = (g.state(), g.short_phase());
            let c = g.step(&vm, heading);
            assert!(stopped(&c), "{what}: {c:?}");
            assert_eq!((c.state, c.short_phase), (state, phase), "{what}");
            assert_eq!((g.state(), g.short_phase()), (state, phase), "{what}");
            // and nothing was counted: the next valid frame acts as it would have
            let mut reference = f.clone();
            assert_eq!(g.step(&quiet(), h), reference.step(&quiet(), h), "{what}");
        }
    }
}

fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        -400.0f32..400.0,
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(f32::NEG_INFINITY),
        proptest::num::f32::ANY,
    ]
}

fn any_vm() -> impl Strategy<Value = Visuomotor> {
    (
        any::<u32>(),
        any_f32(),
        proptest::option::of(any_f32()),
        any::<bool>(),
        any::<bool>(),
        proptest::option::of(any_f32()),
        proptest::option::of((any_f32(), any_f32())),
        proptest::option::of((
            proptest::collection::vec(any::<u8>(), VIEW_CELLS),
            any::<u8>(),
        )),
        proptest::option::of(any_f32()),
        proptest::option::of(proptest::option::of(any::<u8>())),
    )
        .prop_map(
            |(sum, s, x, alert, short_mode, tl, ts, view, obstacle, sighting)| Visuomotor {
                lplc2_sum: sum,
                strength: s,
                threat_x: x,
                alert,
                short_mode,
                theta_long: tl,
                theta_short: ts.map(|(a, b)| [a, b]),
                view: view.map(|(v, level)| {
                    let mut cells = [0u8; VIEW_CELLS];
                    cells.copy_from_slice(&v);
                    (cells, level)
                }),
                obstacle,
                sighting: sighting.map(|m| m.map_or(Sighting::Nothing, |x| Sighting::Mover { x })),
            },
        )
}

proptest! {
    /// Whatever the input, no panic, finite wheel speeds within the wheel limit, and a
    /// non-finite input always stops the robot.
    #[test]
    fn any_input_gives_bounded_speeds(
        swarm in any::<bool>(),
        frames in proptest::collection::vec((any_vm(), any_f32()), 1..200),
    ) {
        let p = FsmParams::default();
        // the swarm looks every third frame of wandering (`FsmParams::look_every`)
        let mut f = if swarm {
            Fsm::new(FsmParams { swarm: Swarm { look_every: NonZeroU32::new(3), ..params().swarm }, ..params() }, Behaviour::Swarm)
        } else {
            fsm(Behaviour::Escape)
        };
        for (vm, h) in frames {
            let c = f.step(&vm, h);
            prop_assert!(c.left_mm_s.is_finite() && c.right_mm_s.is_finite());
            prop_assert!(c.left_mm_s.abs() <= p.motion.max_wheel_mm_s + 1e-3);
            prop_assert!(c.right_mm_s.abs() <= p.motion.max_wheel_mm_s + 1e-3);
            prop_assert!(c.heading_setpoint_deg.is_finite());
            let finite = h.is_finite()
                && vm.strength.is_finite()
                && vm.threat_x.is_none_or(f32::is_finite)
                && vm.theta_long.is_none_or(f32::is_finite)
                && vm.theta_short.is_none_or(|t| t.iter().all(|a| a.is_finite()));
            if !finite {
                prop_assert!(stopped(&c));
            }
            if swarm {
                prop_assert!(matches!(c.state, State::Wander | State::Spin | State::Look));
            }
        }
    }

    /// Nonsensical parameters must not panic either.
    #[test]
    fn any_params_do_not_panic(
        vals in proptest::collection::vec(any_f32(), 14),
        counts in proptest::collection::vec(any::<u32>(), 13),
        short_from_long in any::<bool>(),
        gamma_turn in any::<bool>(),
        wander_stop_frames in proptest::option::of(0u32..100),
        swarm in any::<bool>(),
        frames in proptest::collection::vec((any_vm(), any_f32()), 1..50),
    ) {
        let p = FsmParams {
            motion: Motion {
                cruise_mm_s: vals[0],
                max_escape_mm_s: vals[1],
                retreat_mm_s: vals[2],
                max_wheel_mm_s: vals[3],
                track_mm: vals[4],
                heading_gain: vals[5],
                max_yaw_deg_s: vals[6],
                align_tol_deg: vals[7],
            },
            timing: Timing {
                retreat_frames: counts[7],
                min_escape_frames: counts[0],
                quiet_frames: counts[1],
                takeoff_timeout_frames: counts[2],
                alert_frames: counts[5],
            },
            suppression: Suppression {
                saccade_yaw_deg_s: vals[9],
                settle_frames: counts[4],
            },
            blocked: Blocked {
                blocked_frames: counts[6],
                blocked_travel_mm: vals[10],
                blocked_yaw_deg: vals[11],
            },
            escape: Escape {
                takeoff_drive: vals[12],
                takeoff_gain: vals[13],
                takeoff_yaw_deg_s: vals[6],
                live_strength: counts[8] as u8,
                escape_saccade: counts[9] != 0,
                jump_frames: NonZeroU32::new(counts[12]),
                gamma_turn,
            },
            swarm: Swarm {
                spin_frames: counts[3],
                spin_deg_s: vals[8],
                look_every: NonZeroU32::new(counts[10]),
                look_scans: counts[11],
            },
            firmware: FirmwareFsm {
                short_from_long,
                wander_stop_frames,
            },
        };
        let mut f = Fsm::new(p, if swarm { Behaviour::Swarm } else { Behaviour::Escape });
        for (vm, h) in frames {
            let c = f.step(&vm, h);
            prop_assert!(c.left_mm_s.is_finite() && c.right_mm_s.is_finite());
        }
    }
}

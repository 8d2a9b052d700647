//! Properties of the network run on generated frames and parameters: bounded and consistent
//! outputs, a standing robot's looks, the field capacity, what `short_uncut` and
//! `border_crossing` change,
//! determinism; and the regression of
//! the threat's centroid under saturated responses.

use super::*;
use alvs_tasks::model::closed_loop::derotate::MAX_TURN_DEG;
use alvs_tasks::model::closed_loop::floor::nearest_foot;
use alvs_tasks::model::closed_loop::movers::{Movers, Sighting, SETTLE_FRAMES, SPAN_FRAMES};
use alvs_tasks::model::network::DRIVING_MM_S;
use alvs_tasks::model::params::{Choices, Mechanisms, ShortGates, TableOne};
use std::cell::Cell;

/// Turns reported between frames (`Network::turned`): mostly what a robot turns in a frame,
/// some beyond the limit, some not numbers at all.
fn turns() -> impl Strategy<Value = Vec<f32>> {
    let turn = prop_oneof![
        6 => -15.0f32..15.0,
        1 => -60.0f32..60.0,
        1 => prop_oneof![Just(f32::NAN), Just(f32::INFINITY), Just(-0.0), any::<f32>()],
    ];
    prop::collection::vec(turn, 1..16)
}

/// Arbitrary valid parameters, frame sequences and turns between the frames: no panic, every
/// output invariant holds. The run must also exercise alerts, short mode and several fields,
/// or it proves little.
#[test]
fn outputs_stay_bounded_and_consistent() {
    let (alert_cases, short_cases, multi_cases) = (Cell::new(0), Cell::new(0), Cell::new(0));
    let mut runner = TestRunner::new(config(256));
    let result = runner.run(
        &(valid_params(), sequence(), turns()),
        |(p, specs, turns)| {
            let mut net = Network::new(p).map_err(|e| TestCaseError::fail(format!("{e}")))?;
            let (mut alert, mut short, mut multi) = (false, false, false);
            // frames since the network last (re)started: a turn it cannot re-register restarts it
            let mut k = 0;
            for (i, f) in render(&specs).iter().enumerate() {
                let turn = turns[i % turns.len()];
                prop_assert!(net.turned(turn), "between frames");
                // the efference copy of forward motion: driving on most frames, any value
                let driving = i % 4 != 0;
                net.driving(if driving { 150.0 } else { turn });
                let driving = driving || turn > 20.0;
                if p.efference.derotate && !(turn.is_finite() && turn.abs() <= MAX_TURN_DEG) {
                    k = 0;
                }
                let out = net.step(f);
                check(&p, k, &out, driving)?;
                // `Params::short_row`: a driving robot's short mode has its foot close enough
                // (the network drives when told more than DRIVING_MM_S: 150, or the turn)
                let told = if i % 4 != 0 { 150.0 } else { turn };
                if told > DRIVING_MM_S && off0(p.short.short_row) > 0 && out.vm.short_mode {
                    let x = out.vm.threat_x.map_or(0, |x| x as u8);
                    prop_assert!(
                        nearest_foot(f, x).is_some_and(|row| row >= off0(p.short.short_row)),
                        "frame {i}: {:?}",
                        out.vm
                    );
                }
                k += 1;
                alert |= out.alert();
                short |= out.short_mode();
                multi |= out.afs.len() > 1;
            }
            alert_cases.set(alert_cases.get() + usize::from(alert));
            short_cases.set(short_cases.get() + usize::from(short));
            multi_cases.set(multi_cases.get() + usize::from(multi));
            Ok(())
        },
    );
    if let Err(e) = result {
        panic!("{e}");
    }
    let (a, s, m) = (alert_cases.get(), short_cases.get(), multi_cases.get());
    println!("cases with an alert {a}, with short mode {s}, with several fields {m}");
    assert!(
        a >= 10 && s >= 5 && m >= 5,
        "too few interesting cases: {a} {s} {m}"
    );
}

/// A standing robot's looks (`Params::look_change`, [`Movers`]) on any frames: no panic; none
/// before the settle and the span have passed, none closer than a span apart, each a column of
/// the image; none with the look off or while the robot moves.
#[test]
fn a_standing_robots_looks_come_no_sooner_than_due_and_inside_the_view() {
    let looks = Cell::new(0);
    let mut runner = TestRunner::new(config(64));
    let result = runner.run(
        &(sequence(), any::<u8>(), 0usize..60),
        |(specs, change, moves_at)| {
            let frames = render(&specs);
            let mut movers = Movers::new();
            let mut since: Option<usize> = None;
            for i in 0..60 {
                let standing = i != moves_at;
                let seen = movers.step(&frames[i % frames.len()], standing, change);
                // frames stood since the robot stopped (or the last look)
                since = standing.then(|| since.map_or(1, |n| n + 1));
                let Some(s) = seen else { continue };
                looks.set(looks.get() + 1);
                prop_assert!(change > 0, "frame {i}: {s:?} with the look off");
                let n = since.unwrap_or(0);
                prop_assert!(
                    n >= usize::from(SETTLE_FRAMES + SPAN_FRAMES),
                    "frame {i}: {n}"
                );
                if let Sighting::Mover { x } = s {
                    prop_assert!(usize::from(x) < WIDTH);
                    prop_assert!(s.bearing_deg().is_some_and(|b| b.abs() < 35.5));
                }
                since = Some(usize::from(SETTLE_FRAMES));
            }
            Ok(())
        },
    );
    if let Err(e) = result {
        panic!("{e}");
    }
    assert!(looks.get() >= 20, "too few looks: {}", looks.get());
}

/// The field capacity holds when the parameters would create fields everywhere: tiny fields,
/// no spawn threshold, fresh noise each frame (with `noise_pct` off, which would see those
/// frames as no image and leave nothing salient). The limit is reached, never passed.
#[test]
fn the_field_capacity_is_reached_but_never_exceeded() {
    let mut runner = TestRunner::new(config(24));
    let strategy = (
        1u8..=6,
        1u8..=4,
        prop::collection::vec(any::<u64>(), 16..=24),
    );
    let result = runner.run(&strategy, |(r, d, seeds)| {
        let p = Params {
            table1: TableOne {
                r_af: r,
                t_a: 0,
                t_d: 0,
                d,
                ..Params::default().table1
            },
            choices: Choices {
                r_c: r,
                ..Params::default().choices
            },
            mechanisms: Mechanisms {
                noise_pct: None,
                ..Params::default().mechanisms
            },
            ..Params::default()
        };
        let mut net = Network::new(p).unwrap();
        let mut most = 0;
        for (i, seed) in seeds.into_iter().enumerate() {
            let out = net.step(
                &Spec::Noise {
                    seed,
                    lo: 0,
                    hi: 255,
                }
                .render(),
            );
            check(&p, i, &out, false)?;
            most = most.max(out.afs.len());
        }
        prop_assert_eq!(most, MAX_AFS);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// Runs `frames` through a network with `on` and one with `off` at `speed`: their outputs
/// differ only in `short_mode`, which `on` turns on, never off, only while standing and only
/// on an output `why` accepts; each such frame counts in `widened`.
fn only_widens(
    on: Params,
    off: Params,
    frames: &[alvs_tasks::Frame],
    speed: f32,
    widened: &Cell<u32>,
    why: impl Fn(&Perception) -> bool,
) -> Result<(), TestCaseError> {
    let (mut on, mut off) = (Network::new(on).unwrap(), Network::new(off).unwrap());
    for f in frames {
        on.driving(speed);
        off.driving(speed);
        let (mut a, b) = (on.step(f), off.step(f));
        prop_assert!(a.short_mode() || !b.short_mode(), "{:?} {:?}", a.vm, b.vm);
        if a.short_mode() != b.short_mode() {
            prop_assert!(speed == 0.0 && why(&a), "{a:?}");
            widened.set(widened.get() + 1);
        }
        a.vm.short_mode = b.vm.short_mode;
        prop_assert_eq!(a, b);
    }
    Ok(())
}

/// `Params::short_uncut` widens the short mode and changes nothing else: on any frames and
/// parameters, driving or not, the outputs with and without it differ only in `short_mode`,
/// which it turns on, never off, and only while the robot does not drive forward. The run must
/// also see it widen, or it proves little.
#[test]
fn counting_cut_fields_whole_only_widens_the_short_mode() {
    let widened = Cell::new(0);
    let mut runner = TestRunner::new(config(128));
    let result = runner.run(
        &(valid_params(), sequence(), any::<bool>()),
        |(p, specs, driving)| {
            let with = |short_uncut, t_s| Params {
                table1: TableOne { t_s, ..p.table1 },
                short: ShortGates {
                    short_uncut,
                    ..p.short
                },
                ..p
            };
            let frames = render(&specs);
            let speed = if driving { 150.0 } else { 0.0 };
            // `T_s` at the first frame's ΣLPLC2 whose cut fields counted whole are more, so
            // that the option has something to widen (`T_s` changes nothing but the short mode)
            let mut probe = Network::new(with(false, p.table1.t_s)).unwrap();
            let t_s = frames
                .iter()
                .find_map(|f| {
                    probe.driving(speed);
                    let o = probe.step(f);
                    (uncut_sum(&o, p.table1.r_af) > o.vm.lplc2_sum).then_some(o.vm.lplc2_sum)
                })
                .unwrap_or(p.table1.t_s);
            only_widens(
                with(true, t_s),
                with(false, t_s),
                &frames,
                speed,
                &widened,
                |_| true,
            )
        },
    );
    if let Err(e) = result {
        panic!("{e}");
    }
    let widened = widened.get();
    assert!(widened >= 3, "widened on {widened} frames only");
}

/// `Params::short_young` widens the short mode and changes nothing else: on any frames and
/// parameters, driving or not, the outputs with and without it differ only in `short_mode`,
/// which it turns on, never off, only while the robot does not drive forward, and only on a
/// frame where a field in its first `d` frames after the warm-up alerts. The run must also see
/// it widen, or it proves little.
#[test]
fn a_young_fields_alert_only_widens_a_standing_robots_short_mode() {
    let widened = Cell::new(0);
    let config = config(128);
    let rng = TestRng::deterministic_rng(config.rng_algorithm);
    let mut runner = TestRunner::new_with_rng(config, rng);
    let result = runner.run(
        &(valid_params(), sequence(), any::<bool>()),
        |(p, specs, driving)| {
            // `T_s` out of reach, so that the option has something to widen (`T_s` changes
            // nothing but the short mode)
            let with = |short_young| Params {
                table1: TableOne {
                    t_s: u32::MAX,
                    ..p.table1
                },
                short: ShortGates {
                    short_young,
                    ..p.short
                },
                ..p
            };
            let speed = if driving { 150.0 } else { 0.0 };
            let frames = render(&specs);
            only_widens(with(true), with(false), &frames, speed, &widened, |a| {
                a.afs.iter().any(|f| f.alerts_young(a.frame, &p))
            })
        },
    );
    if let Err(e) = result {
        panic!("{e}");
    }
    let widened = widened.get();
    assert!(widened >= 10, "widened on {widened} frames only");
}

/// Any sequence, or a square growing with its centre within `R_AF` columns of a side border
/// (where `border_crossing` reads a side as cut) for long enough to be past the warm-up.
fn near_a_side() -> impl Strategy<Value = Vec<Spec>> {
    let column = prop_oneof![0u8..36, 63u8..99];
    let growing = growing_square(column, 10u8..62, 1u8..=3, 12usize..=24);
    prop_oneof![1 => sequence(), 3 => growing]
}

/// `Params::border_crossing` only widens `border_arms`' test of a cut side: with the mirror off,
/// or while the robot drives forward (the mirror is for a standing robot), the outputs with and
/// without it are identical on any frames and parameters. The run must also see it change a
/// standing robot's outputs with the mirror on, or it proves little.
#[test]
fn border_crossing_acts_only_through_a_standing_robots_mirror() {
    let changed = Cell::new(0);
    // a fixed draw, large and half of it on the default's parameters: the mirror opens rarely
    // (on arbitrary parameters none in about half of the random 128-case runs; 512 cases gave
    // 22 changed outputs, then 2 once the parameters' draw took one more field), and a vacuous
    // pass must not depend on luck
    let config = config(2048);
    let rng = TestRng::deterministic_rng(config.rng_algorithm);
    let mut runner = TestRunner::new_with_rng(config, rng);
    let params = prop_oneof![1 => Just(Params::default()), 1 => valid_params()];
    let result = runner.run(
        &(params, near_a_side(), any::<bool>(), any::<bool>()),
        |(p, specs, arms, driving)| {
            let with = |border_crossing| Params {
                mechanisms: Mechanisms {
                    border_arms: arms,
                    border_crossing,
                    ..p.mechanisms
                },
                ..p
            };
            let speed = if driving { 150.0 } else { 0.0 };
            let mut on = Network::new(with(true)).unwrap();
            let mut off = Network::new(with(false)).unwrap();
            for f in &render(&specs) {
                on.driving(speed);
                off.driving(speed);
                let (a, b) = (on.step(f), off.step(f));
                if a != b {
                    prop_assert!(arms && !driving, "{:?} {:?}", a.vm, b.vm);
                    changed.set(changed.get() + 1);
                }
            }
            Ok(())
        },
    );
    if let Err(e) = result {
        panic!("{e}");
    }
    let changed = changed.get();
    assert!(
        changed >= 10,
        "border_crossing changed {changed} outputs only"
    );
}

/// Two fresh networks fed the same frames give identical outputs; so do a clone taken midway
/// and its original, and a network after `reset` compared with a fresh one (up to field ids,
/// which keep counting across a reset).
#[test]
fn the_network_is_deterministic() {
    let mut runner = TestRunner::new(config(48));
    let result = runner.run(
        &(valid_params(), sequence(), sequence()),
        |(p, first, second)| {
            let (a, b) = (render(&first), render(&second));
            let mut n1 = Network::new(p).unwrap();
            let mut n2 = Network::new(p).unwrap();
            for f in &a {
                prop_assert_eq!(n1.step(f), n2.step(f));
            }
            let mut n3 = n1.clone();
            for f in &b {
                prop_assert_eq!(n1.step(f), n3.step(f));
            }
            // field ids stay unique over the whole run, across a reset: compare without them
            n1.reset();
            let mut fresh = Network::new(p).unwrap();
            let anonymous = |mut o: Perception| {
                o.afs.iter_mut().for_each(|a| a.id = 0);
                o
            };
            for f in a.iter().chain(&b) {
                prop_assert_eq!(anonymous(n1.step(f)), anonymous(fresh.step(f)));
            }
            Ok(())
        },
    );
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// Regression (found by `outputs_stay_bounded_and_consistent`): with extreme but valid parameters
/// (`w` 4, `gain` 16, `lm_shift` 0, no quadrant floor) two fields on a flickering checkerboard
/// both reach `LPLC2 = u32::MAX`; `ΣLPLC2` saturates but the numerator of Eq. (12) does not, so
/// `X̄` was 70 + 81 = 151, off the retina, and the escape angles followed it.
#[test]
fn threat_centroid_survives_saturated_responses() {
    let p = Params {
        table1: TableOne {
            w: 4.0,
            n: 4,
            r_af: 10,
            t_a: 0,
            t_d: 0,
            ..Params::default().table1
        },
        choices: Choices {
            gain: 16,
            lm_shift: 0,
            s: 2,
            r_c: 10,
            q_floor: 0,
            q_balance: 0,
            c_d: 1.0,
            ..Params::default().choices
        },
        ..Params::default()
    };
    let mut net = Network::new(p).unwrap();
    for i in 0..12 {
        // a checkerboard inverting every frame on columns 60..99, mid grey elsewhere
        let mut f = Spec::Checker {
            cell: 2,
            a: 0,
            b: 255,
            phase: i % 2 == 1,
        }
        .render();
        for row in f.chunks_mut(WIDTH) {
            row[..60].fill(128);
        }
        let out = net.step(&f);
        let fields: Vec<(u8, u32)> = out.afs.iter().map(|a| (a.x, a.lplc2)).collect();
        println!("frame {i}: X̄ {:?}, fields {fields:?}", out.vm.threat_x);
        if let Some(x) = out.vm.threat_x {
            assert!((60.0..=98.0).contains(&x), "frame {i}: X̄ {x}, {fields:?}");
        }
    }
}

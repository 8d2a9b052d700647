//! Properties of the aLPLC2 network that hold for every frame sequence and every parameter set
//! `Params::validate` accepts: no panic, outputs within their documented ranges and consistent
//! with each other (Eqs. 9, 11–15), invalid parameters refused with an error, determinism.
//!
//! Frames are generated from small descriptions (uniform, noise, checkerboards, squares,
//! gradients) so that cases stay cheap and shrink to readable counterexamples. Failures are
//! not persisted to disk (the seed is printed instead).

use alvs_tasks::model::param_table::off0;
use std::cell::Cell;

use alvs_tasks::model::closed_loop::derotate::MAX_TURN_DEG;
use alvs_tasks::model::closed_loop::floor::nearest_foot;
use alvs_tasks::model::closed_loop::movers::{Movers, Sighting, SETTLE_FRAMES, SPAN_FRAMES};
use alvs_tasks::model::network::DRIVING_MM_S;
use alvs_tasks::model::params::{
    Choices, Efference, FirmwareVariant, Mechanisms, ShortGates, SwarmLook, TableOne,
};
use alvs_tasks::model::params::{MAX_D, MAX_N, MAX_REACH};
use alvs_tasks::{Network, ParamError, Params, Perception, HEIGHT, MAX_AFS, PIXELS, WIDTH};
use core::num::{NonZeroU32, NonZeroU8};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRunner};

type Frame = [u8; PIXELS];

fn config(cases: u32) -> Config {
    Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    }
}

// ---------------------------------------------------------------------------------------------
// Frames
// ---------------------------------------------------------------------------------------------

/// A frame, described compactly.
#[derive(Debug, Clone)]
enum Spec {
    Uniform(u8),
    /// Uniform noise in `lo..=hi` from a seed.
    Noise {
        seed: u64,
        lo: u8,
        hi: u8,
    },
    /// Checkerboard of `cell`-pixel squares of `a` and `b`, swapped when `phase`.
    Checker {
        cell: u8,
        a: u8,
        b: u8,
        phase: bool,
    },
    /// Square of half side `h` and grey `fg` centred on `(cx, cy)` over `bg`.
    Square {
        cx: u8,
        cy: u8,
        h: u8,
        fg: u8,
        bg: u8,
    },
    /// Linear ramp 0 → 255 across the frame.
    Gradient {
        horizontal: bool,
        invert: bool,
    },
}

impl Spec {
    fn render(&self) -> Frame {
        let mut f = [0u8; PIXELS];
        match *self {
            Spec::Uniform(v) => f = [v; PIXELS],
            Spec::Noise { seed, lo, hi } => {
                let (lo, hi) = (lo.min(hi), lo.max(hi));
                let mut s = seed | 1;
                for v in f.iter_mut() {
                    s ^= s << 13;
                    s ^= s >> 7;
                    s ^= s << 17;
                    *v = lo + (s % (u64::from(hi - lo) + 1)) as u8;
                }
            }
            Spec::Checker { cell, a, b, phase } => {
                let cell = usize::from(cell.max(1));
                for y in 0..HEIGHT {
                    for x in 0..WIDTH {
                        let odd = ((x / cell + y / cell) % 2 == 1) ^ phase;
                        f[y * WIDTH + x] = if odd { b } else { a };
                    }
                }
            }
            Spec::Square { cx, cy, h, fg, bg } => {
                f = [bg; PIXELS];
                let (cx, cy, h) = (usize::from(cx), usize::from(cy), usize::from(h));
                for y in cy.saturating_sub(h)..(cy + h + 1).min(HEIGHT) {
                    for x in cx.saturating_sub(h)..(cx + h + 1).min(WIDTH) {
                        f[y * WIDTH + x] = fg;
                    }
                }
            }
            Spec::Gradient { horizontal, invert } => {
                for y in 0..HEIGHT {
                    for x in 0..WIDTH {
                        let v = if horizontal {
                            x * 255 / (WIDTH - 1)
                        } else {
                            y * 255 / (HEIGHT - 1)
                        } as u8;
                        f[y * WIDTH + x] = if invert { 255 - v } else { v };
                    }
                }
            }
        }
        f
    }
}

fn spec() -> impl Strategy<Value = Spec> {
    prop_oneof![
        prop_oneof![Just(0u8), Just(255u8), any::<u8>()].prop_map(Spec::Uniform),
        (any::<u64>(), any::<u8>(), any::<u8>()).prop_map(|(seed, lo, hi)| Spec::Noise {
            seed,
            lo,
            hi
        }),
        (1u8..=16, any::<u8>(), any::<u8>(), any::<bool>())
            .prop_map(|(cell, a, b, phase)| Spec::Checker { cell, a, b, phase }),
        (0u8..99, 0u8..72, 0u8..60, any::<u8>(), any::<u8>())
            .prop_map(|(cx, cy, h, fg, bg)| Spec::Square { cx, cy, h, fg, bg }),
        (any::<bool>(), any::<bool>())
            .prop_map(|(horizontal, invert)| Spec::Gradient { horizontal, invert }),
    ]
}

/// Frame sequences: 2–6 arbitrary frames, or adversarial runs of up to 16 frames (all-0/all-255
/// alternation, inverting checkerboards, fresh full-range noise, an expanding square).
fn sequence() -> impl Strategy<Value = Vec<Spec>> {
    prop_oneof![
        3 => prop::collection::vec(spec(), 2..=6),
        1 => (2usize..=16, any::<bool>()).prop_map(|(n, start)| {
            (0..n)
                .map(|i| Spec::Uniform(if (i % 2 == 0) ^ start { 0 } else { 255 }))
                .collect()
        }),
        1 => (1u8..=12, 2usize..=16).prop_map(|(cell, n)| {
            (0..n)
                .map(|i| Spec::Checker { cell, a: 0, b: 255, phase: i % 2 == 1 })
                .collect()
        }),
        1 => prop::collection::vec(any::<u64>(), 2..=16).prop_map(|seeds| {
            seeds
                .into_iter()
                .map(|seed| Spec::Noise { seed, lo: 0, hi: 255 })
                .collect()
        }),
        2 => (0u8..99, 0u8..72, 1u8..=4, 2usize..=16, any::<u8>(), any::<u8>()).prop_map(
            |(cx, cy, rate, n, fg, bg)| {
                (0..n)
                    .map(|i| Spec::Square { cx, cy, h: 1 + rate * i as u8, fg, bg })
                    .collect()
            }
        ),
    ]
}

fn render(specs: &[Spec]) -> Vec<Frame> {
    specs.iter().map(Spec::render).collect()
}

// ---------------------------------------------------------------------------------------------
// Parameters
// ---------------------------------------------------------------------------------------------

/// A threshold: small values (where things happen) or any `u32`.
fn threshold() -> impl Strategy<Value = u32> {
    prop_oneof![3 => 0u32..20_000, 1 => any::<u32>(), 1 => Just(u32::MAX)]
}

/// A threshold of Table I (`T_a`, `T_d`, `u16`s): small values or any `u16`.
fn threshold16() -> impl Strategy<Value = u16> {
    prop_oneof![3 => 0u16..20_000, 1 => any::<u16>(), 1 => Just(u16::MAX)]
}

/// A float in `lo..=hi`, its bounds included on purpose.
fn float_in(lo: f32, hi: f32) -> impl Strategy<Value = f32> {
    prop_oneof![1 => Just(lo), 1 => Just(hi), 4 => lo..=hi]
}

/// Every field within the range `Params::validate` accepts (and `n·s ≤ MAX_REACH`).
fn valid_params() -> impl Strategy<Value = Params> {
    let first = (
        float_in(0.0, 4.0),
        1u8..=MAX_N,
        1u8..=99,
        threshold16(),
        threshold16(),
        1u8..=MAX_D,
    );
    let second = (
        // w_s, log-uniform over its twelve decades
        prop_oneof![
            Just(1e-3f32),
            Just(1e9f32),
            (-3.0f32..=9.0).prop_map(|e| 10f32.powf(e).clamp(1e-3, 1e9))
        ],
        float_in(-10.0, 10.0),
        threshold(),
        float_in(1.0, 16.0),
        1u8..=MAX_REACH,
        1u8..=16,
    );
    let third = (
        0u8..=24,
        1u8..=99,
        0u8..=100,
        threshold(),
        0u8..=100,
        1u8..=4,
    );
    // warm-up frames, whole-field luminance events, blocked-way threshold, efference copy,
    // adaptation, growth of partial openings, the quiet scene's attention threshold
    let fourth = (
        prop_oneof![3 => 0u8..=8, 1 => any::<u8>()],
        0u8..=100,
        any::<u8>(),
        0u8..=1,
        prop_oneof![3 => Just(0u8), 1 => any::<u8>()],
        prop_oneof![1 => Just(0u8), 1 => any::<u8>()],
        prop_oneof![1 => Just(0u32), 1 => threshold()],
    );
    // the efference copy of forward motion's band, the floor line, the path's columns, the
    // foot's row of an imminent threat
    let fifth = (
        prop_oneof![1 => Just(0u8), 1 => 0u8..=71],
        prop_oneof![1 => Just(0u8), 1 => 0u8..=71],
        prop_oneof![1 => Just(0u8), 1 => 0u8..=49],
        prop_oneof![1 => Just(0u8), 1 => 0u8..=71],
        prop_oneof![1 => Just(0u8), 1 => any::<u8>()],
    );
    // the authors' firmware's switches: fields alive at once, its output threshold, its
    // retirement, its correlator; and the blind arms at the side borders
    let sixth = (
        prop_oneof![1 => Just(MAX_AFS as u8), 1 => 1u8..=MAX_AFS as u8],
        prop_oneof![1 => Just(0u32), 1 => threshold()],
        any::<bool>(),
        prop_oneof![3 => Just(true), 1 => Just(false)],
        any::<bool>(),
    );
    let random = (first, second, third, fourth, fifth, sixth).prop_map(
        |(
            (w, n, r_af, t_a, t_d, d),
            (w_s, alpha, t_s, c_d, s, gain),
            (lm_shift, r_c, c_frac, q_floor, q_balance, q_arms),
            (warmup, flicker_pct, blocked_change, derotate, adapt_frames, q_grow_pct, t_a_quiet),
            (band_row, floor_row, short_cols, short_row, look_change),
            (max_fields, t_lplc2, strict_retire, opponent, border_arms),
        )| Params {
            table1: TableOne {
                w,
                n,
                r_af,
                t_a,
                t_d,
                d,
                w_s,
                alpha,
                t_s,
            },
            choices: Choices {
                c_d,
                s: s.min(MAX_REACH / n),
                gain,
                lm_shift,
                r_c,
                c_frac,
                q_floor,
                q_balance,
                q_arms,
            },
            mechanisms: Mechanisms {
                warmup: NonZeroU8::new(warmup),
                flicker_pct: NonZeroU8::new(flicker_pct),
                q_grow_pct: NonZeroU8::new(q_grow_pct),
                t_a_quiet: NonZeroU32::new(t_a_quiet),
                border_arms,
            },
            efference: Efference {
                blocked_change: NonZeroU8::new(blocked_change),
                derotate: derotate != 0,
                band_row: NonZeroU8::new(band_row),
                floor_row: NonZeroU8::new(floor_row),
            },
            short: ShortGates {
                adapt_frames: NonZeroU8::new(adapt_frames),
                short_cols: NonZeroU8::new(short_cols),
                short_row: NonZeroU8::new(short_row),
            },
            swarm: SwarmLook {
                look_change: NonZeroU8::new(look_change),
            },
            firmware: FirmwareVariant {
                max_fields,
                t_lplc2: NonZeroU32::new(t_lplc2),
                strict_retire,
                opponent,
            },
        },
    );
    prop_oneof![
        1 => Just(Params::default()),
        1 => Just(Params::PAPER),
        1 => Just(Params::FIRMWARE),
        3 => random
    ]
}

// ---------------------------------------------------------------------------------------------
// The output invariants
// ---------------------------------------------------------------------------------------------

/// `a` and `b` are the same angle up to `tol` degrees.
fn same_angle(a: f32, b: f32, tol: f32) -> bool {
    let d = (a - b).rem_euclid(360.0);
    d <= tol || d >= 360.0 - tol
}

fn in_half_open_circle(a: f32) -> bool {
    a.is_finite() && a > -180.0 && a <= 180.0
}

/// Every documented bound and relation of one output, for the `index`-th frame.
fn check(p: &Params, index: usize, out: &Perception, driving: bool) -> Result<(), TestCaseError> {
    let vm = &out.vm;
    let ctx = || format!("frame {index}: {out:?}");
    prop_assert_eq!(out.frame as usize, index);
    prop_assert!(
        out.afs.len() <= usize::from(p.firmware.max_fields),
        "{}",
        ctx()
    );
    if index == 0 {
        // the priming frame never alerts (its `strength` is not a sigmoid value: see the report)
        prop_assert!(
            out.afs.is_empty() && !out.alert() && vm.lplc2_sum == 0,
            "{}",
            ctx()
        );
        prop_assert!(
            vm.threat_x.is_none() && vm.theta_long.is_none(),
            "{}",
            ctx()
        );
        return Ok(());
    }
    // `Params::band_row`: driving, no field centred above the band responds
    if driving {
        prop_assert!(
            out.afs
                .iter()
                .all(|a| a.y >= off0(p.efference.band_row) || a.lplc2 == 0),
            "{}",
            ctx()
        );
    }
    let mut ids: Vec<u32> = out.afs.iter().map(|a| a.id).collect();
    ids.sort_unstable();
    ids.dedup();
    prop_assert_eq!(ids.len(), out.afs.len(), "duplicate ids: {}", ctx());
    for af in &out.afs {
        prop_assert!(
            usize::from(af.x) < WIDTH && usize::from(af.y) < HEIGHT,
            "{}",
            ctx()
        );
        prop_assert!(af.age >= 1, "{}", ctx());
        // Eq. (9): zero, or the (saturating) sum of four quadrants, at least `q_arms` of them
        // above the floor (all four with the paper's gate); with `t_lplc2`, zero or a mean
        // over frames above it
        let sum = af.quadrants.iter().fold(0u32, |a, &q| a.saturating_add(q));
        if off0(p.firmware.t_lplc2) > 0 {
            prop_assert!(
                af.lplc2 == 0 || af.lplc2 > off0(p.firmware.t_lplc2),
                "{}",
                ctx()
            );
        } else {
            prop_assert!(af.lplc2 == 0 || af.lplc2 == sum, "{}", ctx());
        }
        if af.lplc2 > 0 && off0(p.firmware.t_lplc2) == 0 {
            let excited = af
                .quadrants
                .iter()
                .filter(|&&q| q > p.choices.q_floor)
                .count();
            prop_assert!(excited >= usize::from(p.choices.q_arms), "{}", ctx());
        }
    }
    let total = out.afs.iter().fold(0u32, |a, f| a.saturating_add(f.lplc2));
    prop_assert_eq!(vm.lplc2_sum, total, "{}", ctx());
    prop_assert_eq!(out.alert(), vm.alert);
    prop_assert_eq!(out.short_mode(), vm.short_mode);
    // an alert comes from the fields, or else from the floor line of a driving robot
    let floor_alert = vm.alert && vm.lplc2_sum == 0;
    prop_assert!(
        !floor_alert || (driving && off0(p.efference.floor_row) > 0 && !vm.short_mode),
        "{}",
        ctx()
    );
    prop_assert!(vm.alert || vm.lplc2_sum == 0, "{}", ctx());
    // the floor line reports only for a driving robot
    prop_assert!(
        vm.obstacle.is_none() || (driving && off0(p.efference.floor_row) > 0),
        "{}",
        ctx()
    );
    // alone, its saccade is the θ¹ of the threat it reports
    if vm.alert && vm.lplc2_sum == 0 {
        prop_assert_eq!(vm.obstacle, vm.theta_short.map(|[t1, _]| t1), "{}", ctx());
    }
    let in_path = |x: f32| (x - 49.0).abs() <= f32::from(off0(p.short.short_cols));
    let off_path = driving && off0(p.short.short_cols) > 0 && !vm.threat_x.is_some_and(in_path);
    // a driving robot's threat whose foot is far (`Params::short_row`) is not imminent either
    let far_gate = driving && off0(p.short.short_row) > 0;
    if off0(p.short.adapt_frames) == 0 && !off_path && !far_gate {
        prop_assert_eq!(vm.short_mode, vm.lplc2_sum > p.table1.t_s, "{}", ctx());
    } else {
        // motion adaptation, a threat off the path of a driving robot (`Params::short_cols`)
        // and one far ahead of it (`Params::short_row`) can only hold the short mode back
        prop_assert!(!vm.short_mode || vm.lplc2_sum > p.table1.t_s, "{}", ctx());
        prop_assert!(!vm.short_mode || !off_path, "{}", ctx());
    }
    prop_assert!(!vm.short_mode || vm.alert, "{}", ctx());
    prop_assert!(
        vm.strength.is_finite() && (0.5..=1.0).contains(&vm.strength),
        "{}",
        ctx()
    );
    prop_assert_eq!(vm.threat_x.is_some(), vm.alert, "{}", ctx());
    prop_assert_eq!(vm.theta_long.is_some(), vm.alert, "{}", ctx());
    prop_assert_eq!(vm.theta_short.is_some(), vm.alert, "{}", ctx());
    if let Some(x) = vm.threat_x {
        prop_assert!(x.is_finite(), "{}", ctx());
        // On the retina, and a weighted mean of the stimulated fields' columns, even when
        // ΣLPLC2 saturates (see `threat_centroid_survives_saturated_responses`); the floor
        // line's column when it alone alerts.
        prop_assert!((0.0..=98.0).contains(&x), "{}", ctx());
        if !floor_alert {
            let xs = out
                .afs
                .iter()
                .filter(|a| a.lplc2 > 0)
                .map(|a| f32::from(a.x));
            let lo = xs.clone().fold(f32::INFINITY, f32::min);
            let hi = xs.fold(f32::NEG_INFINITY, f32::max);
            prop_assert!(x >= lo - 1e-3 && x <= hi + 1e-3, "{}", ctx());
        }
        // Eq. (13): turn to face away from the threat
        let long = vm.theta_long.unwrap();
        prop_assert!(in_half_open_circle(long), "{}", ctx());
        let expect = p.table1.alpha * (x - 49.0) + 180.0;
        prop_assert!(
            same_angle(long, expect, 1e-2),
            "{} vs {}: {}",
            long,
            expect,
            ctx()
        );
        // Eqs. (14)–(15): the second heading is 90° further than the first, same direction
        let [s1, s2] = vm.theta_short.unwrap();
        prop_assert!(
            in_half_open_circle(s1) && in_half_open_circle(s2),
            "{}",
            ctx()
        );
        prop_assert!(
            same_angle(s2 - s1, 90.0, 1e-2) || same_angle(s2 - s1, -90.0, 1e-2),
            "{}",
            ctx()
        );
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Properties
// ---------------------------------------------------------------------------------------------

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
/// no spawn threshold, fresh noise each frame. The limit is reached, never passed.
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

/// One field set to a value `Params::validate` must refuse.
#[derive(Debug, Clone)]
enum Bad {
    F32(&'static str, f32),
    U8(&'static str, u8),
    /// `s` such that `n·s > MAX_REACH`.
    Reach(u8, u8),
}

fn bad_float(lo: f32, hi: f32) -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(f32::NEG_INFINITY),
        Just(-f32::NAN),
        Just(f32::MAX),
        Just(f32::MIN),
        (1e-3f32..1e30).prop_map(move |d| lo - d * lo.abs().max(1.0)),
        (1e-3f32..1e30).prop_map(move |d| hi + d * hi.abs().max(1.0)),
    ]
    .prop_filter("in range", move |v| !(*v >= lo && *v <= hi))
}

fn bad_u8(lo: u8, hi: u8) -> impl Strategy<Value = u8> {
    any::<u8>().prop_filter("in range", move |v| *v < lo || *v > hi)
}

fn bad_value() -> impl Strategy<Value = Bad> {
    prop_oneof![
        bad_float(0.0, 4.0).prop_map(|v| Bad::F32("w", v)),
        bad_float(1e-3, 1e9).prop_map(|v| Bad::F32("w_s", v)),
        bad_float(-10.0, 10.0).prop_map(|v| Bad::F32("alpha", v)),
        bad_float(1.0, 16.0).prop_map(|v| Bad::F32("c_d", v)),
        bad_u8(1, MAX_N).prop_map(|v| Bad::U8("n", v)),
        bad_u8(1, 99).prop_map(|v| Bad::U8("r_af", v)),
        bad_u8(1, 99).prop_map(|v| Bad::U8("r_c", v)),
        bad_u8(0, 100).prop_map(|v| Bad::U8("c_frac", v)),
        bad_u8(0, 100).prop_map(|v| Bad::U8("q_balance", v)),
        bad_u8(1, 4).prop_map(|v| Bad::U8("q_arms", v)),
        bad_u8(1, MAX_D).prop_map(|v| Bad::U8("d", v)),
        bad_u8(1, MAX_REACH).prop_map(|v| Bad::U8("s", v)),
        bad_u8(1, 16).prop_map(|v| Bad::U8("gain", v)),
        bad_u8(0, 24).prop_map(|v| Bad::U8("lm_shift", v)),
        bad_u8(0, 100).prop_map(|v| Bad::U8("flicker_pct", v)),
        bad_u8(1, MAX_AFS as u8).prop_map(|v| Bad::U8("max_fields", v)),
        (2u8..=MAX_N)
            .prop_flat_map(|n| (Just(n), (MAX_REACH / n + 1)..=MAX_REACH))
            .prop_map(|(n, s)| Bad::Reach(n, s)),
    ]
}

impl Bad {
    fn apply(&self, p: &mut Params) -> &'static str {
        match *self {
            Bad::F32(name, v) => {
                match name {
                    "w" => p.table1.w = v,
                    "w_s" => p.table1.w_s = v,
                    "alpha" => p.table1.alpha = v,
                    _ => p.choices.c_d = v,
                }
                name
            }
            Bad::U8(name, v) => {
                match name {
                    "n" => p.table1.n = v,
                    "r_af" => p.table1.r_af = v,
                    "r_c" => p.choices.r_c = v,
                    "c_frac" => p.choices.c_frac = v,
                    "q_balance" => p.choices.q_balance = v,
                    "q_arms" => p.choices.q_arms = v,
                    "d" => p.table1.d = v,
                    "s" => p.choices.s = v,
                    "gain" => p.choices.gain = v,
                    "flicker_pct" => p.mechanisms.flicker_pct = NonZeroU8::new(v),
                    "max_fields" => p.firmware.max_fields = v,
                    _ => p.choices.lm_shift = v,
                }
                name
            }
            Bad::Reach(n, s) => {
                p.table1.n = n;
                p.choices.s = s;
                "s"
            }
        }
    }

    /// The value as text, for `Params::set`.
    fn text(&self) -> String {
        match *self {
            Bad::F32(_, v) => format!("{v}"),
            Bad::U8(_, v) => v.to_string(),
            Bad::Reach(_, s) => s.to_string(),
        }
    }
}

/// An invalid value in an otherwise valid parameter set is refused by `validate`,
/// `Network::new`, `Network::set_params` and `Params::set`, naming the field, without a panic;
/// a refused `set_params` or `set` leaves everything as it was.
#[test]
fn invalid_parameters_are_refused() {
    let mut runner = TestRunner::new(config(256));
    let result = runner.run(&(valid_params(), bad_value()), |(good, bad)| {
        let mut p = good;
        let name = bad.apply(&mut p);
        let refused = |r: Result<(), ParamError>| match r {
            Err(ParamError::OutOfRange { name: n, .. })
            | Err(ParamError::OutOfRangeReal { name: n, .. }) => {
                Params::position(n) == Params::position(name)
            }
            _ => false,
        };
        prop_assert!(refused(p.validate()), "{:?}: {:?}", p, p.validate());
        prop_assert!(refused(Network::new(p).map(|_| ())), "{:?}", p);
        let mut net = Network::new(good).unwrap();
        prop_assert!(refused(net.set_params(p)), "{:?}", p);
        prop_assert_eq!(net.params(), &good);
        // the network still works with its old parameters
        let frames = [[0u8; PIXELS], [255u8; PIXELS]];
        for (i, f) in frames.iter().enumerate() {
            check(&good, i, &net.step(f), false)?;
        }
        // through the text interface (n·s > reach is refused on `s` when `n` is set first)
        let mut q = good;
        if let Bad::Reach(n, _) = bad {
            q.table1.n = n;
            q.choices.s = 1;
        }
        let before = q;
        let r = q.set(name, &bad.text());
        prop_assert!(
            matches!(
                r,
                Err(ParamError::OutOfRange { .. })
                    | Err(ParamError::OutOfRangeReal { .. })
                    | Err(ParamError::NotANumber { .. })
            ),
            "set({}, {}) = {:?}",
            name,
            bad.text(),
            r
        );
        prop_assert_eq!(q, before);
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// Text that looks like a number, or like the edge of one.
fn numberish() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<i64>().prop_map(|v| v.to_string()),
        any::<f64>().prop_map(|v| v.to_string()),
        any::<f32>().prop_map(|v| format!("{v:e}")),
        (0u32..300).prop_map(|v| v.to_string()),
        prop::sample::select(vec![
            "",
            " ",
            "NaN",
            "nan",
            "inf",
            "-inf",
            "+inf",
            "infinity",
            "1e40",
            "-0",
            "+3",
            "3.",
            ".5",
            "0x10",
            "1_000",
            " 7 ",
            "\t4\n",
            "٣",
            "4294967296",
            "-1",
            "256",
            "1e-45",
        ])
        .prop_map(String::from),
    ]
}

/// `Params::set` never panics on any name and text; when it accepts, the result validates and
/// the name was known (`group.field` or the field alone, [`Params::position`]); when it
/// refuses, nothing changed; in-range integers are accepted exactly.
#[test]
fn params_set_accepts_only_valid_text() {
    let name = prop_oneof![
        3 => prop::sample::select(Params::NAMES.to_vec()).prop_map(String::from),
        1 => "\\PC{0,12}",
        1 => prop::sample::select(Params::NAMES.to_vec()).prop_map(|n| format!(" {}", n.to_uppercase())),
    ];
    let value = prop_oneof![3 => numberish(), 1 => "\\PC{0,24}", 1 => ".*"];
    let mut runner = TestRunner::new(config(512));
    let result = runner.run(&(valid_params(), name, value), |(start, name, value)| {
        let mut p = start;
        match p.set(&name, &value) {
            Ok(()) => {
                prop_assert!(Params::position(&name).is_some(), "{}", name);
                prop_assert_eq!(p.validate(), Ok(()));
            }
            Err(ParamError::Unknown) => {
                prop_assert!(Params::position(&name).is_none(), "{}", name);
                prop_assert_eq!(p, start);
            }
            Err(_) => prop_assert_eq!(p, start),
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    // every in-range value of the integer fields goes through the text interface exactly
    let mut p = Params::default();
    for v in 0..=255u8 {
        for (name, lo, hi) in [
            ("r_af", 1, 99),
            ("c_frac", 0, 100),
            ("d", 1, MAX_D),
            ("lm_shift", 0, 24),
            ("q_balance", 0, 100),
            ("q_arms", 1, 4),
            ("warmup", 0, 255),
            ("flicker_pct", 0, 100),
            ("blocked_change", 0, 255),
        ] {
            let r = p.set(name, &format!(" {v} "));
            assert_eq!(r.is_ok(), (lo..=hi).contains(&v), "{name} = {v}: {r:?}");
        }
    }
    assert_eq!(
        (
            p.table1.r_af,
            p.choices.c_frac,
            p.table1.d,
            p.choices.lm_shift,
            p.choices.q_balance,
            p.choices.q_arms
        ),
        (99, 100, MAX_D, 24, 100, 4)
    );
    assert_eq!(
        (
            off0(p.mechanisms.warmup),
            off0(p.mechanisms.flicker_pct),
            off0(p.efference.blocked_change)
        ),
        (255, 100, 255)
    );
    // each name sets its own field
    let mut q = Params::default();
    q.set("q_arms", "3").unwrap();
    q.set("q_balance", "40").unwrap();
    q.set("warmup", "7").unwrap();
    q.set("flicker_pct", "60").unwrap();
    q.set("blocked_change", "6").unwrap();
    assert_eq!(
        (
            q.choices.q_arms,
            q.choices.q_balance,
            off0(q.mechanisms.warmup),
            off0(q.mechanisms.flicker_pct),
            off0(q.efference.blocked_change)
        ),
        (3, 40, 7, 60, 6)
    );
    for t in [0u32, 1, 7000, u32::MAX] {
        assert_eq!(p.set("t_s", &t.to_string()), Ok(()));
        assert_eq!(p.table1.t_s, t);
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

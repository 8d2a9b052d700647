//! Invalid parameters refused (`validate`, `Network::new`, `Network::set_params`,
//! `Params::set`), and `Params::set` on arbitrary names and text.

use super::*;
use alvs_tasks::model::params::{MAX_D, MAX_N, MAX_REACH};
use alvs_tasks::ParamError;
use core::num::NonZeroU8;

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
            ("noise_pct", 0, 100),
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

//! The whole network: the parameter sets, priming and rest, determinism, reset, extreme input.

use super::*;

fn both() -> [(&'static str, Lgmd2Params); 2] {
    [
        ("colias", Lgmd2Params::colias()),
        ("reference", Lgmd2Params::reference()),
    ]
}

#[test]
fn parameter_sets_are_as_lgmd2_md_says() {
    assert_eq!(Lgmd2Params::default(), Lgmd2Params::colias());
    let r = Lgmd2Params::reference();
    let c = Lgmd2Params::colias();
    assert!(r.validate().is_ok() && c.validate().is_ok());
    assert_eq!(
        (r.t_pm, r.dc, r.t_sp, r.c_spi, r.n_sp, r.tau_sfa_ms),
        (8.0, 0.1, 0.78, 4.0, 8, 800.0)
    );
    assert_eq!(
        (r.c_w, r.delta_c, r.c_de, r.t_de, r.c_sig),
        (4.0, 0.01, 0.5, 15.0, 1.0)
    );
    assert_eq!(
        (c.t_pm, c.dc, c.t_sp, c.c_spi, c.n_sp, c.tau_sfa_ms),
        (10.0, 0.0, 0.63, 4.0, 4, 500.0)
    );
    assert_eq!(
        (
            c.w_on,
            c.w_off,
            c.w_onoff,
            c.c_de * 0.0 + c.t_de / c.c_de,
            c.c_sig
        ),
        (0.5, 1.0, 0.0, 35.0, 0.5)
    );
    assert_eq!((c.arithmetic, c.p_shift), (Arithmetic::Uint8, 1));
    let mut bad = Lgmd2Params::colias();
    bad.fps = 0;
    bad.t_pm = 0.0;
    let e = bad.validate().unwrap_err();
    assert!(e.contains("fps") && e.contains("t_pm"), "{e}");
}

#[test]
fn first_frame_primes_and_a_still_scene_rests() {
    for (name, prm) in both() {
        let mut m = Lgmd2::new(prm);
        let f: Frame = std::array::from_fn(|i| (i * 7 % 251) as u8);
        for t in 0..40 {
            let o = m.step(&f);
            assert_eq!(
                (o.mp, o.smp, o.spikes, o.collision),
                (0.0, 0.5, 0, false),
                "{name} frame {t}"
            );
            assert_eq!(o.sfa, 0.5, "{name} frame {t}");
        }
    }
}

#[test]
fn first_frame_primes_even_after_a_change() {
    // a black frame then a white one: only the second is a change
    let mut m = Lgmd2::new(Lgmd2Params::reference());
    let o = m.step(&[255; PIXELS]);
    assert_eq!((o.mp, o.smp), (0.0, 0.5));
    let o = m.step(&[0; PIXELS]);
    assert!(o.pm > 0.0);
}

#[test]
fn a_synthetic_looming_square_alerts() {
    for (name, prm) in both() {
        let mut m = Lgmd2::new(prm);
        let outs: Vec<Lgmd2Output> = (0..30).map(|t| m.step(&looming(t))).collect();
        let first = outs.iter().position(|o| o.collision);
        assert!(first.is_some(), "{name}: no collision: {outs:?}");
    }
}

#[test]
fn deterministic_and_reset_replays_the_same() {
    for (name, prm) in both() {
        let frames: Vec<Frame> = (0..25).map(looming).collect();
        let mut a = Lgmd2::new(prm.clone());
        let mut b = Lgmd2::new(prm);
        let ra: Vec<Lgmd2Output> = frames.iter().map(|f| a.step(f)).collect();
        let rb: Vec<Lgmd2Output> = frames.iter().map(|f| b.step(f)).collect();
        assert_eq!(ra, rb, "{name}");
        a.reset();
        let rc: Vec<Lgmd2Output> = frames.iter().map(|f| a.step(f)).collect();
        assert_eq!(ra, rc, "{name}: reset");
    }
}

#[test]
fn extreme_input_and_degenerate_parameters_never_panic() {
    let black = [0u8; PIXELS];
    let white = [255u8; PIXELS];
    let noise: Frame = std::array::from_fn(|i| ((i as u64 * 2_654_435_761) >> 13) as u8);
    let mut degenerate = Lgmd2Params::reference();
    degenerate.fps = 0;
    degenerate.t_pm = 0.0;
    degenerate.c_w = 0.0;
    degenerate.c_sig = 0.0;
    degenerate.tau_pm_ms = 0.0;
    degenerate.delta_c = 0.0;
    degenerate.p_shift = 99;
    degenerate.n_sp = 0;
    let mut huge = Lgmd2Params::colias();
    huge.fps = u32::MAX;
    huge.c_spi = f32::MAX;
    for prm in [
        Lgmd2Params::colias(),
        Lgmd2Params::reference(),
        degenerate,
        huge,
    ] {
        let mut m = Lgmd2::new(prm);
        for t in 0..30 {
            let f = match t % 3 {
                0 => &black,
                1 => &white,
                _ => &noise,
            };
            let o = m.step(f);
            assert!(!o.sfa.is_nan() && !o.pm.is_nan(), "{o:?}");
        }
    }
    // flicker is a full-field change: it must not leave NaN in a sane model either
    let mut m = Lgmd2::default();
    for t in 0..60 {
        let o = m.step(if t % 2 == 0 { &black } else { &white });
        assert!(o.smp.is_finite() && (0.5..=1.0).contains(&o.smp), "{o:?}");
    }
}

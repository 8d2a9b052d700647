//! Each layer on tiny inputs, checked by hand.

use super::*;

#[test]
fn p_layer_is_the_frame_difference_and_colias_keeps_7_bits() {
    let cur = [10u8, 200, 0, 255, 7];
    let prev = [20u8, 100, 255, 0, 7];
    let mut p = [0.0; 5];
    p_layer(&cur, &prev, 0, &mut p);
    assert_eq!(p, [-10.0, 100.0, -255.0, 255.0, 0.0]);
    // Colias: (ΔY) >> 1, rounding toward −∞, clamped to the int8 range ±127
    p_layer(&cur, &prev, 1, &mut p);
    assert_eq!(p, [-5.0, 50.0, -127.0, 127.0, 0.0]);
    let mut odd = [0.0];
    p_layer(&[0], &[3], 1, &mut odd);
    assert_eq!(odd, [-2.0], "-3 >> 1 = -2 (arithmetic shift)");
}

#[test]
fn on_off_split_with_and_without_carry_over() {
    let p = [-5.0, 0.0, 3.0];
    let prev_on = [10.0; 3];
    let prev_off = [20.0; 3];
    let (mut on, mut off) = ([0.0; 3], [0.0; 3]);
    // reference: ON = P + 0.1·ON(t−1) if P ≥ 0.1 else 0.1·ON(t−1); OFF = |P| + 0.1·OFF(t−1)
    // if P < 0.1 else 0.1·OFF(t−1)
    on_off_layer(
        &p,
        &prev_on,
        &prev_off,
        0.1,
        0.1,
        Arithmetic::Float,
        &mut on,
        &mut off,
    );
    for (got, want) in on.iter().zip([1.0, 1.0, 4.0]) {
        assert_close!(*got, want);
    }
    for (got, want) in off.iter().zip([7.0, 2.0, 2.0]) {
        assert_close!(*got, want);
    }
    // Colias: no carry-over, integers
    on_off_layer(
        &p,
        &prev_on,
        &prev_off,
        0.1,
        0.0,
        Arithmetic::Uint8,
        &mut on,
        &mut off,
    );
    assert_eq!(on, [0.0, 0.0, 3.0]);
    assert_eq!(off, [5.0, 0.0, 0.0]);
    // uint8 with carry-over truncates: 3 + 0.1·25 = 5.5 → 5
    on_off_layer(
        &[3.0],
        &[25.0],
        &[0.0],
        0.1,
        0.1,
        Arithmetic::Uint8,
        &mut on[..1],
        &mut off[..1],
    );
    assert_eq!(on[0], 5.0);
}

#[test]
fn pm_update_and_inhibition_biases() {
    // mean |P| of [-10, 30, 0, 20] = 15
    assert_close!(mean_abs(&[-10.0, 30.0, 0.0, 20.0]), 15.0);
    assert_eq!(mean_abs(&[]), 0.0);
    // α = Δt / (Δt + τ) with Δt = 33 ms (1000 / 30, integer) and τ_PM = 90 ms
    let prm = Lgmd2Params::reference();
    assert_eq!(prm.dt_ms(), 33.0);
    let a = lowpass_coefficient(prm.dt_ms(), prm.tau_pm_ms);
    assert_close!(a, 33.0 / 123.0);
    // from rest, one frame of mean |P| = 20: pm = 20·33/123
    let pm = pm_update(0.0, 20.0, a);
    assert_close!(pm, 20.0 * 33.0 / 123.0);
    // and the next frame of 20 again: α·20 + (1 − α)·pm
    assert_close!(pm_update(pm, 20.0, a), a * 20.0 + (1.0 - a) * pm);
    // W_i = max(pm / T_pm, base): small pm → the bases 1 and 0.5
    assert_eq!(inhibition_biases(4.0, 8.0, 1.0, 0.5), (1.0, 0.5));
    assert_eq!(inhibition_biases(6.0, 8.0, 1.0, 0.5), (1.0, 0.75));
    assert_eq!(inhibition_biases(16.0, 8.0, 1.0, 0.5), (2.0, 2.0));
    // Colias T_pm = 10
    assert_eq!(inhibition_biases(16.0, 10.0, 1.0, 0.5), (1.6, 1.6));
}

#[test]
fn lateral_inhibition_of_one_lit_cell() {
    // 5x5, one ON cell of value 4 at the centre now, nothing before
    let (w, h) = (5, 5);
    let mut cur = vec![0.0; 25];
    cur[12] = 4.0;
    let prev = vec![0.0; 25];
    let k = Kernel3::ON;
    let alpha = k.tau_ms.map(|t| lowpass_coefficient(33.0, t));
    let mut out = vec![0.0; 25];
    lateral_inhibition(w, h, &cur, &prev, &k, alpha, Arithmetic::Float, &mut out);
    // centre: 2·α_c·4; nearest: 0.5·α_n·4; diagonal: 0.25·α_d·4; farther: 0
    assert_close!(out[12], 2.0 * 4.0 * 33.0 / 48.0);
    assert_close!(out[7], 0.5 * 4.0 * 33.0 / 63.0);
    assert_close!(out[13], 0.5 * 4.0 * 33.0 / 63.0);
    assert_close!(out[6], 0.25 * 4.0 * 33.0 / 78.0);
    assert_eq!(out[0], 0.0);
    assert_eq!(out[10], 0.0);
    // the same value before and not now: the delayed part (1 − α)
    lateral_inhibition(w, h, &prev, &cur, &k, alpha, Arithmetic::Float, &mut out);
    assert_close!(out[12], 2.0 * 4.0 * (1.0 - 33.0 / 48.0));
    assert_close!(out[18], 0.25 * 4.0 * (1.0 - 33.0 / 78.0));
    // uint8: shifts round each neighbour down: 3 → ×2 = 6, >>1 = 1, >>2 = 0; I truncated
    cur[12] = 3.0;
    lateral_inhibition(w, h, &cur, &prev, &k, alpha, Arithmetic::Uint8, &mut out);
    assert_eq!(out[12], (6.0 * 33.0f32 / 48.0).floor()); // 4.125 → 4
    assert_eq!(out[7], (1.0 * 33.0f32 / 63.0).floor()); // 0.52 → 0
    assert_eq!(out[6], 0.0);
    // OFF kernel (W_on / 2) with value 8: centre 8, nearest 8>>2 = 2, diagonal 8>>3 = 1
    let ko = Kernel3::OFF;
    let ao = ko.tau_ms.map(|t| lowpass_coefficient(33.0, t));
    cur[12] = 8.0;
    lateral_inhibition(w, h, &cur, &cur, &ko, ao, Arithmetic::Uint8, &mut out);
    assert_eq!((out[12], out[7], out[6]), (8.0, 2.0, 1.0));
}

#[test]
fn lateral_inhibition_replicates_the_border() {
    // 3x3, all weights 1, no delay, one lit corner (0, 0). With replicated borders the
    // neighbours of (0, 0) are ul (0,0), u (0,0), ur (1,0), l (0,0), r (1,0), dl (0,1),
    // d (0,1), dr (1,1): the lit cell counts as centre, u, l and ul
    let mut cur = vec![0.0; 9];
    cur[0] = 1.0;
    let k = Kernel3 {
        centre: 1.0,
        near: 1.0,
        diag: 1.0,
        tau_ms: [0.0; 3],
    };
    let mut out = vec![0.0; 9];
    lateral_inhibition(
        3,
        3,
        &cur,
        &[0.0; 9],
        &k,
        [1.0; 3],
        Arithmetic::Float,
        &mut out,
    );
    assert_eq!(out[0], 4.0);
    // at (1,0): l = (0,0) once, ul = (0,0) once → 2
    assert_eq!(out[1], 2.0);
    // at (1,1): ul = (0,0) → 1
    assert_eq!(out[4], 1.0);
    assert_eq!(out[8], 0.0);
}

#[test]
fn s_layer_combines_on_and_off() {
    let k = SWeights {
        w_i_on: 1.0,
        w_i_off: 0.5,
        w_on: 1.0,
        w_off: 1.0,
        w_onoff: 1.0,
    };
    let mut s = [0.0; 3];
    // S_on = max(0, 10 − 4) = 6, S_off = max(0, 6 − 0.5·4) = 4 → 6 + 4 + 24 = 34
    // S_on = max(0, 2 − 5) = 0, S_off = 3 → 3 ; both inhibited away → 0
    s_layer(
        &[10.0, 2.0, 1.0],
        &[6.0, 3.0, 1.0],
        &[4.0, 5.0, 9.0],
        &[4.0, 0.0, 9.0],
        &k,
        Arithmetic::Float,
        &mut s,
    );
    assert_eq!(s, [34.0, 3.0, 0.0]);
    // Colias: 0.5·S_on + S_off, truncated to uint8
    let kc = SWeights {
        w_on: 0.5,
        w_onoff: 0.0,
        ..k
    };
    s_layer(
        &[7.0, 200.0, 0.0],
        &[2.0, 200.0, 0.0],
        &[0.0; 3],
        &[0.0; 3],
        &kc,
        Arithmetic::Uint8,
        &mut s,
    );
    assert_eq!(s, [5.0, 255.0, 0.0]); // 3.5 + 2 = 5.5 → 5; 100 + 200 → 255
}

#[test]
fn g_layer_scale_threshold_and_mp() {
    let gp = GParams {
        delta_c: 0.01,
        c_w: 4.0,
        c_de: 0.5,
        t_de: 15.0,
    };
    // uniform S = 10 on 3x3: Ce = 10, ω = 0.01 + 10/4 = 2.51, G = 100 / 2.51 = 39.84,
    // G·0.5 = 19.9 ≥ 15: kept everywhere
    let s = [10.0; 9];
    let (mut ce, mut g) = ([0.0; 9], [0.0; 9]);
    let mp = g_layer(3, 3, &s, &gp, Arithmetic::Float, &mut ce, &mut g);
    assert_close!(ce[4], 10.0);
    assert_close!(g[0], 100.0 / 2.51);
    assert_close!(mp, 9.0 * 100.0 / 2.51);
    // uniform S = 5: G = 25 / 1.26 = 19.8, ·0.5 = 9.9 < 15: all dropped
    let mp = g_layer(3, 3, &[5.0; 9], &gp, Arithmetic::Float, &mut ce, &mut g);
    assert_eq!(mp, 0.0);
    // one cell of S = 90 in the middle of a 3x3 of zeros: every Ce = 10 (replicated border
    // counts it once for each cell), G only where S > 0: 90·10 / 2.51 = 358.6
    let mut s = [0.0; 9];
    s[4] = 90.0;
    let mp = g_layer(3, 3, &s, &gp, Arithmetic::Float, &mut ce, &mut g);
    assert!(ce.iter().all(|&c| close(c, 10.0)), "{ce:?}");
    assert_close!(mp, 900.0 / 2.51);
    // Colias: Ce = ⌊Σ/9⌋, G truncated and saturated at 255, kept where G ≥ 35
    let gc = GParams {
        c_de: 1.0,
        t_de: 35.0,
        ..gp
    };
    let mp = g_layer(3, 3, &s, &gc, Arithmetic::Uint8, &mut ce, &mut g);
    assert_eq!(g[4], 255.0);
    assert_eq!(mp, 255.0);
    let mut s = [0.0; 9];
    s[4] = 20.0; // Ce = ⌊20/9⌋ = 2, ω = 0.51, G = 40 / 0.51 = 78.4 → 78
    let mp = g_layer(3, 3, &s, &gc, Arithmetic::Uint8, &mut ce, &mut g);
    assert_eq!((ce[0], g[4], mp), (2.0, 78.0, 78.0));
    s[4] = 8.0; // Ce = 0: G = 0
    assert_eq!(
        g_layer(3, 3, &s, &gc, Arithmetic::Uint8, &mut ce, &mut g),
        0.0
    );
}

#[test]
fn sigmoid_of_the_membrane_potential() {
    assert_eq!(sigmoid(0.0, PIXELS, 1.0), 0.5);
    // exp(−MP / N) = 1/3 ⇒ SMP = 0.75
    let n = PIXELS as f32;
    assert_close!(sigmoid(n * 3f32.ln(), PIXELS, 1.0), 0.75);
    // Colias K_spi = 0.5 halves the MP needed
    assert_close!(sigmoid(0.5 * n * 3f32.ln(), PIXELS, 0.5), 0.75);
    assert_close!(sigmoid(1e9, PIXELS, 1.0), 1.0);
}

#[test]
fn spike_frequency_adaptation() {
    let hp = sfa_coefficient(33.0, 800.0);
    assert_close!(hp, 800.0 / 833.0);
    // ΔSMP = 0.001 ≤ T_sfa: hp·(SFA(t−1) + ΔSMP)
    assert_close!(sfa_update(0.7, 0.7, 0.701, hp, 0.003, 0.5), hp * 0.701);
    // ΔSMP = 0.1 > T_sfa: hp·SMP
    assert_close!(sfa_update(0.6, 0.7, 0.8, hp, 0.003, 0.5), hp * 0.8);
    // falling SMP decays SFA, never below 0.5
    assert_close!(sfa_update(0.9, 0.9, 0.8, hp, 0.003, 0.5), hp * 0.8);
    assert_eq!(sfa_update(0.52, 0.9, 0.5, hp, 0.003, 0.5), 0.5);
}

#[test]
fn spike_count_formula() {
    // n = ⌊exp(C_spi·(SFA − T_sp))⌋
    assert_eq!(spike_count(0.5, 4.0, 0.78), 0); // exp(−1.12) = 0.33
    assert_eq!(spike_count(0.78, 4.0, 0.78), 1);
    assert_eq!(spike_count(0.78 + 2f32.ln() / 4.0 + 1e-4, 4.0, 0.78), 2);
    assert_eq!(spike_count(0.96, 4.0, 0.78), 2); // exp(0.72) = 2.05
    assert_eq!(spike_count(0.6299, 4.0, 0.63), 0);
    assert_eq!(spike_count(0.938, 4.0, 0.63), 3); // exp(1.232) = 3.43: Colias' top rate
    assert_eq!(spike_count(1e9, 4.0, 0.0), 255);
    assert_eq!(spike_count(f32::NAN, 4.0, 0.0), 0);
}

#[test]
fn spikes_accumulate_over_the_current_burst() {
    // reference: 8 spikes, no reset after the alert
    let mut c = SpikeCounter::default();
    let got: Vec<(u32, bool)> = [2, 2, 2, 2, 2, 0, 2]
        .iter()
        .map(|&n| c.push(n, 8, false))
        .collect();
    assert_eq!(
        got,
        [
            (2, false),
            (4, false),
            (6, false),
            (8, true),
            (10, true),
            (0, false),
            (2, false)
        ]
    );
    // a silent frame breaks the burst
    let mut c = SpikeCounter::default();
    let got: Vec<bool> = [2, 2, 2, 0, 2, 2, 2]
        .iter()
        .map(|&n| c.push(n, 8, false).1)
        .collect();
    assert!(got.iter().all(|&b| !b));
    // Colias: 4 spikes, the count empties after each alert
    let mut c = SpikeCounter::default();
    let got: Vec<(u32, bool)> = [1, 1, 1, 1, 1, 3, 1, 0]
        .iter()
        .map(|&n| c.push(n, 4, true))
        .collect();
    assert_eq!(
        got,
        [
            (1, false),
            (2, false),
            (3, false),
            (4, true),
            (1, false),
            (4, true),
            (1, false),
            (0, false)
        ]
    );
}

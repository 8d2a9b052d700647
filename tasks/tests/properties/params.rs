//! Parameters: strategies generating every parameter set `Params::validate` accepts.

use super::*;
use alvs_tasks::model::params::{
    Choices, Efference, FirmwareVariant, Mechanisms, ShortGates, SwarmLook, TableOne,
};
use alvs_tasks::model::params::{MAX_D, MAX_N, MAX_REACH};
use core::num::{NonZeroU16, NonZeroU32, NonZeroU8};

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
pub(crate) fn valid_params() -> impl Strategy<Value = Params> {
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
        prop_oneof![1 => Just(0u16), 1 => threshold16()],
    );
    // the efference copy of forward motion's band, the floor line, the path's columns, the
    // foot's row of an imminent threat, the swarm's look, noise frames
    let fifth = (
        prop_oneof![1 => Just(0u8), 1 => 0u8..=71],
        prop_oneof![1 => Just(0u8), 1 => 0u8..=71],
        prop_oneof![1 => Just(0u8), 1 => 0u8..=49],
        prop_oneof![1 => Just(0u8), 1 => 0u8..=71],
        prop_oneof![1 => Just(0u8), 1 => any::<u8>()],
        0u8..=100,
    );
    // the authors' firmware's switches: fields alive at once, its output threshold, its
    // retirement, its correlator; the blind arms at the side borders; the exclusion zone; the
    // run of growth a partial opening may stand on; the short mode's whole cut fields; a side
    // cut once the square crosses it
    let sixth = (
        prop_oneof![1 => Just(MAX_AFS as u8), 1 => 1u8..=MAX_AFS as u8],
        prop_oneof![1 => Just(0u32), 1 => threshold()],
        any::<bool>(),
        prop_oneof![3 => Just(true), 1 => Just(false)],
        any::<bool>(),
        prop_oneof![1 => Just(0u8), 1 => 1u8..=99],
        prop_oneof![1 => Just(0u8), 1 => any::<u8>()],
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
    );
    let random = (first, second, third, fourth, fifth, sixth).prop_map(
        |(
            (w, n, r_af, t_a, t_d, d),
            (w_s, alpha, t_s, c_d, s, gain),
            (lm_shift, r_c, c_frac, q_floor, q_balance, q_arms),
            (warmup, flicker_pct, blocked_change, derotate, adapt_frames, q_grow_pct, t_a_quiet),
            (band_row, floor_row, short_cols, short_row, look_change, noise_pct),
            (
                max_fields,
                t_lplc2,
                strict_retire,
                opponent,
                border_arms,
                r_x,
                q_grow_run,
                short_uncut,
                border_crossing,
                short_young,
            ),
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
                r_x: NonZeroU8::new(r_x),
                c_frac,
                q_floor,
                q_balance,
                q_arms,
            },
            mechanisms: Mechanisms {
                warmup: NonZeroU8::new(warmup),
                flicker_pct: NonZeroU8::new(flicker_pct),
                noise_pct: NonZeroU8::new(noise_pct),
                q_grow_pct: NonZeroU8::new(q_grow_pct),
                q_grow_run: NonZeroU8::new(q_grow_run),
                t_a_quiet: NonZeroU16::new(t_a_quiet),
                border_arms,
                border_crossing,
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
                short_uncut,
                short_young,
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

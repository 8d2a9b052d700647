//! docs/lgmd2.md step 5: the S layer, excitation minus delayed inhibition.

use super::params::Arithmetic;

/// The S layer's weights and the inhibition biases of one frame (docs/lgmd2.md 5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SWeights {
    /// W_i_on from [`inhibition_biases`](super::inhibition_biases).
    pub w_i_on: f32,
    /// W_i_off from [`inhibition_biases`](super::inhibition_biases).
    pub w_i_off: f32,
    /// Weight of S_on.
    pub w_on: f32,
    /// Weight of S_off.
    pub w_off: f32,
    /// Weight of S_on·S_off.
    pub w_onoff: f32,
}

/// docs/lgmd2.md 5, S layer: `S_x = max(0, X − W_i_x·I_x)` for ON and OFF, then
/// `S = w_on·S_on + w_off·S_off + w_onoff·S_on·S_off` (truncated to uint8 in
/// [`Arithmetic::Uint8`]).
pub fn s_layer(
    on: &[f32],
    off: &[f32],
    i_on: &[f32],
    i_off: &[f32],
    k: &SWeights,
    arithmetic: Arithmetic,
    s: &mut [f32],
) {
    let cells = s.iter_mut().zip(on).zip(off).zip(i_on).zip(i_off);
    for ((((s, &on), &off), &ion), &ioff) in cells {
        // f32::max(NaN, 0) is 0: a degenerate bias cannot poison the layer
        let s_on = (on - k.w_i_on * ion).max(0.0);
        let s_off = (off - k.w_i_off * ioff).max(0.0);
        *s = arithmetic.store(
            k.w_on * s_on + k.w_off * s_off + k.w_onoff * s_on * s_off,
            255.0,
        );
    }
}

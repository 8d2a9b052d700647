//! docs/lgmd2.md steps 1–2: the P layer (the change of luminance) and the adaptive inhibition of
//! the PM pathway.

use super::grid::lanes_sum;

/// docs/lgmd2.md 1, P layer: `P = (L(t) − L(t−1)) >> shift`, clamped to `±(255 >> shift)`
/// (the firmware's int8 range for shift 1). Only the common length of the slices is written.
pub fn p_layer(cur: &[u8], prev: &[u8], shift: u32, p: &mut [f32]) {
    let shift = shift.min(7);
    let lim = 255i16 >> shift;
    for ((o, &c), &q) in p.iter_mut().zip(cur).zip(prev) {
        // arithmetic shift: rounds toward −∞, like the firmware's `>> 9` on a signed int
        *o = ((c as i16 - q as i16) >> shift).clamp(-lim, lim) as f32;
    }
}

/// docs/lgmd2.md 2: the mean of |P| over the layer (0 for an empty layer).
pub fn mean_abs(p: &[f32]) -> f32 {
    if p.is_empty() {
        return 0.0;
    }
    lanes_sum(p, f32::abs) / p.len() as f32
}

/// docs/lgmd2.md 2: `pm(t) = α·mean|P| + (1 − α)·pm(t−1)` with `α = Δt / (Δt + τ_PM)`.
pub fn pm_update(pm_prev: f32, mean_abs_p: f32, alpha: f32) -> f32 {
    alpha * mean_abs_p + (1.0 - alpha) * pm_prev
}

/// docs/lgmd2.md 2: `(W_i_on, W_i_off) = (max(pm / T_pm, on_base), max(pm / T_pm, off_base))`.
pub fn inhibition_biases(pm: f32, t_pm: f32, on_base: f32, off_base: f32) -> (f32, f32) {
    let r = pm / t_pm;
    // f32::max ignores a NaN (T_pm = 0 with pm = 0): the bases hold
    (r.max(on_base), r.max(off_base))
}

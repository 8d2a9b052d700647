//! docs/lgmd2.md step 6: the G (grouping) layer and the membrane potential MP.

use super::grid::{lanes_max_abs, lanes_sum, pad_grid, padded_len, shifted_row};
use super::params::{truncate, Arithmetic};

/// G-layer constants (docs/lgmd2.md 6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GParams {
    /// Δ_C.
    pub delta_c: f32,
    /// C_w.
    pub c_w: f32,
    /// C_de.
    pub c_de: f32,
    /// T_de.
    pub t_de: f32,
}

/// docs/lgmd2.md 6, G layer: `Ce` = 3x3 mean of S (replicated border; `⌊Σ/9⌋` in
/// [`Arithmetic::Uint8`]), `ω = Δ_C + max|Ce| / C_w`, `G = S·Ce·(1/ω)` (truncated to uint8
/// in [`Arithmetic::Uint8`]), `G = 0` where `G·C_de < T_de`. Writes `ce` and `g`, returns
/// `MP = ΣG`. If a slice is shorter than `width·height`, nothing is written and MP is 0.
pub fn g_layer(
    width: usize,
    height: usize,
    s: &[f32],
    k: &GParams,
    arithmetic: Arithmetic,
    ce: &mut [f32],
    g: &mut [f32],
) -> f32 {
    let mut pad = vec![0.0; padded_len(width, height)];
    g_layer_with(width, height, s, k, arithmetic, &mut pad, ce, g)
}

/// [`g_layer`] with caller-provided scratch of `padded_len(width, height)` cells.
#[allow(clippy::too_many_arguments)]
pub(super) fn g_layer_with(
    width: usize,
    height: usize,
    s: &[f32],
    k: &GParams,
    arithmetic: Arithmetic,
    pad: &mut [f32],
    ce: &mut [f32],
    g: &mut [f32],
) -> f32 {
    let n = width * height;
    if n == 0 || s.len() < n || ce.len() < n || g.len() < n || pad.len() < padded_len(width, height)
    {
        return 0.0;
    }
    pad_grid(s, width, height, pad);
    for (y, ce) in ce.chunks_exact_mut(width).take(height).enumerate() {
        // the 3x3 box sum from the padded rows y − 1, y, y + 1 shifted by −1, 0, +1 columns
        let rows = [0, 1, 2].map(|r| [0, 1, 2].map(|dx| shifted_row(pad, width, y + r, dx)));
        for (x, ce) in ce.iter_mut().enumerate() {
            let sum: f32 = rows.iter().flatten().map(|r| r[x]).sum();
            *ce = match arithmetic {
                Arithmetic::Float => sum / 9.0,
                // the integer division of an integer sum (≤ 9·255: exact in f32)
                Arithmetic::Uint8 => truncate(sum / 9.0, 255.0),
            };
        }
    }
    // both sources multiply by the reciprocal of the scale
    let inv_omega = 1.0 / (k.delta_c + lanes_max_abs(&ce[..n]) / k.c_w);
    for ((g, &s), &ce) in g.iter_mut().zip(s).zip(ce.iter()).take(n) {
        let v = arithmetic.store(s * ce * inv_omega, 255.0);
        // a NaN (a degenerate scale) fails the comparison and is dropped
        *g = if v * k.c_de >= k.t_de { v } else { 0.0 };
    }
    lanes_sum(&g[..n], |v| v)
}

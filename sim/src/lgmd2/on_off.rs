//! docs/lgmd2.md step 3: the ON/OFF split with carry-over.

use super::params::Arithmetic;

/// docs/lgmd2.md 3, ON/OFF split with carry-over:
/// `ON = P + dc·ON(t−1)` if `P ≥ clip` else `dc·ON(t−1)`;
/// `OFF = |P| + dc·OFF(t−1)` if `P < clip` else `dc·OFF(t−1)`.
/// In [`Arithmetic::Uint8`] the results are truncated to uint8.
#[allow(clippy::too_many_arguments)]
pub fn on_off_layer(
    p: &[f32],
    prev_on: &[f32],
    prev_off: &[f32],
    clip: f32,
    dc: f32,
    arithmetic: Arithmetic,
    on: &mut [f32],
    off: &mut [f32],
) {
    let cells = on
        .iter_mut()
        .zip(off.iter_mut())
        .zip(p)
        .zip(prev_on)
        .zip(prev_off);
    for ((((on, off), &p), &pon), &poff) in cells {
        let (exc_on, exc_off) = if p >= clip { (p, 0.0) } else { (0.0, p.abs()) };
        *on = arithmetic.store(exc_on + dc * pon, 255.0);
        *off = arithmetic.store(exc_off + dc * poff, 255.0);
    }
}

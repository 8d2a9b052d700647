//! docs/lgmd2.md step 4: delayed lateral inhibition by the 3x3 kernels.

use super::grid::{padded_len, replicate_ring, shifted_row};
use super::params::{truncate, Arithmetic, Kernel3};

/// docs/lgmd2.md 4, delayed lateral inhibition of one pathway:
/// `I = Σ_3x3 W · [α·X(t) + (1 − α)·X(t−1)]`, α = `alpha[0|1|2]` for the centre, the 4
/// nearest and the 4 diagonal cells; borders replicate the edge cell.
///
/// In [`Arithmetic::Uint8`] each product `W·X` is rounded down per cell (the firmware's
/// shifts) and the sum is truncated to an integer. Grids are `width` x `height`, row-major;
/// if a slice is shorter than that, nothing is written.
#[allow(clippy::too_many_arguments)]
pub fn lateral_inhibition(
    width: usize,
    height: usize,
    cur: &[f32],
    prev: &[f32],
    kernel: &Kernel3,
    alpha: [f32; 3],
    arithmetic: Arithmetic,
    out: &mut [f32],
) {
    let mut scratch = vec![0.0; 2 * padded_len(width, height)];
    lateral_inhibition_with(
        width,
        height,
        cur,
        prev,
        kernel,
        alpha,
        arithmetic,
        &mut scratch,
        out,
    );
}

/// [`lateral_inhibition`] with caller-provided scratch of `2·padded_len(width, height)`
/// cells (nothing is written if it is shorter).
#[allow(clippy::too_many_arguments)]
pub(super) fn lateral_inhibition_with(
    width: usize,
    height: usize,
    cur: &[f32],
    prev: &[f32],
    kernel: &Kernel3,
    alpha: [f32; 3],
    arithmetic: Arithmetic,
    scratch: &mut [f32],
    out: &mut [f32],
) {
    let (n, np) = (width * height, padded_len(width, height));
    if n == 0 || cur.len() < n || prev.len() < n || out.len() < n || scratch.len() < 2 * np {
        return;
    }
    // one branch-free loop per arithmetic
    match arithmetic {
        Arithmetic::Float => {
            lateral::<false>(width, height, cur, prev, kernel, alpha, scratch, out)
        }
        Arithmetic::Uint8 => lateral::<true>(width, height, cur, prev, kernel, alpha, scratch, out),
    }
}

/// Truncation of a non-negative value when `Q` (the firmware's float-to-integer conversion,
/// saturating at `max`, NaN to 0), identity otherwise.
#[inline(always)]
fn store<const Q: bool>(v: f32, max: f32) -> f32 {
    if Q {
        truncate(v, max)
    } else {
        v
    }
}

/// The body of [`lateral_inhibition`]; `Q` = uint8 arithmetic. Checked sizes.
#[allow(clippy::too_many_arguments)]
fn lateral<const Q: bool>(
    width: usize,
    height: usize,
    cur: &[f32],
    prev: &[f32],
    kernel: &Kernel3,
    alpha: [f32; 3],
    scratch: &mut [f32],
    out: &mut [f32],
) {
    // the delayed, weighted contribution `α·W·X(t) + (1 − α)·W·X(t−1)` of a cell, each
    // product rounded down in uint8 arithmetic (the firmware's shifts); products stay far
    // below 65,535 (at most 2 · 255)
    let delayed = |weight: f32, a: f32, x: f32, xp: f32| {
        a * store::<Q>(weight * x, 65_535.0) + (1.0 - a) * store::<Q>(weight * xp, 65_535.0)
    };
    let (wp, np) = (width + 2, padded_len(width, height));
    // every cell's contribution as a nearest and as a diagonal cell, padded
    let (near, diag) = scratch.split_at_mut(np);
    for y in 0..height {
        let row = y * width..(y + 1) * width;
        let prow = (y + 1) * wp + 1..(y + 1) * wp + 1 + width;
        let cells = near[prow.clone()]
            .iter_mut()
            .zip(&mut diag[prow])
            .zip(&cur[row.clone()])
            .zip(&prev[row]);
        for (((n, d), &x), &xp) in cells {
            *n = delayed(kernel.near, alpha[1], x, xp);
            *d = delayed(kernel.diag, alpha[2], x, xp);
        }
    }
    replicate_ring(near, width, height);
    replicate_ring(diag, width, height);
    for y in 0..height {
        let row = y * width..(y + 1) * width;
        let shifted = |pad, r, dx| shifted_row(pad, width, y + r, dx);
        let (n_u, n_l, n_r, n_d) = (
            shifted(near, 0, 1),
            shifted(near, 1, 0),
            shifted(near, 1, 2),
            shifted(near, 2, 1),
        );
        let (d_ul, d_ur, d_dl, d_dr) = (
            shifted(diag, 0, 0),
            shifted(diag, 0, 2),
            shifted(diag, 2, 0),
            shifted(diag, 2, 2),
        );
        let (cur, prev, out) = (&cur[row.clone()], &prev[row.clone()], &mut out[row]);
        for x in 0..width {
            let centre = delayed(kernel.centre, alpha[0], cur[x], prev[x]);
            let nearest = n_u[x] + n_d[x] + n_l[x] + n_r[x];
            let diagonal = d_ul[x] + d_ur[x] + d_dl[x] + d_dr[x];
            out[x] = store::<Q>(centre + nearest + diagonal, 65_535.0);
        }
    }
}

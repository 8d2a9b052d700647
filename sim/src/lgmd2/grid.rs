//! What several layers share: padded 3x3 neighbourhoods with a replicated border, and sums and
//! maxima over fixed lanes (deterministic, and they vectorise).

/// `Σ f(v)` over 8 interleaved partial sums, which vectorise (a fixed order: deterministic;
/// exact for integer-valued layers, whose sums stay far below 2^24).
pub(super) fn lanes_sum(v: &[f32], f: impl Fn(f32) -> f32) -> f32 {
    let mut acc = [0.0f32; 8];
    let chunks = v.chunks_exact(8);
    let tail: f32 = chunks.remainder().iter().map(|&x| f(x)).sum();
    for c in chunks {
        for (a, &x) in acc.iter_mut().zip(c) {
            *a += f(x);
        }
    }
    acc.iter().sum::<f32>() + tail
}

/// `max(0, max |v|)` over 8 interleaved partial maxima (NaN ignored).
pub(super) fn lanes_max_abs(v: &[f32]) -> f32 {
    let mut acc = [0.0f32; 8];
    let chunks = v.chunks_exact(8);
    let tail = chunks
        .remainder()
        .iter()
        .fold(0.0f32, |m, x| m.max(x.abs()));
    for c in chunks {
        for (a, &x) in acc.iter_mut().zip(c) {
            *a = a.max(x.abs());
        }
    }
    acc.iter().fold(tail, |m, &a| m.max(a))
}

/// Cells of the `(width + 2) x (height + 2)` padded copy of a `width` x `height` grid.
pub(super) fn padded_len(width: usize, height: usize) -> usize {
    (width + 2) * (height + 2)
}

/// Fills the 1-cell ring of a padded grid (row stride `width + 2`) from its interior: borders
/// replicate the edge cell (docs/lgmd2.md), so every 3x3 neighbourhood is a plain offset.
pub(super) fn replicate_ring(pad: &mut [f32], width: usize, height: usize) {
    let wp = width + 2;
    for y in 1..=height {
        let row = &mut pad[y * wp..(y + 1) * wp];
        row[0] = row[1];
        row[width + 1] = row[width];
    }
    pad.copy_within(wp..2 * wp, 0);
    pad.copy_within(height * wp..(height + 1) * wp, (height + 1) * wp);
}

/// Row `r` of a padded grid from column `dx` on, `width` cells: element `x` is the cell at
/// column `x − 1 + dx` of row `r − 1` of the grid, so `(r, dx)` in `{y, y+1, y+2} x {0, 1, 2}`
/// are the 3x3 neighbourhood of row `y`, as slices of equal length (which vectorise).
pub(super) fn shifted_row(pad: &[f32], width: usize, r: usize, dx: usize) -> &[f32] {
    let start = r * (width + 2) + dx;
    &pad[start..start + width]
}

/// Copies a grid into the interior of a padded grid and fills its ring.
pub(super) fn pad_grid(src: &[f32], width: usize, height: usize, pad: &mut [f32]) {
    let wp = width + 2;
    for (y, row) in src.chunks_exact(width).take(height).enumerate() {
        pad[(y + 1) * wp + 1..(y + 1) * wp + 1 + width].copy_from_slice(row);
    }
    replicate_ring(pad, width, height);
}

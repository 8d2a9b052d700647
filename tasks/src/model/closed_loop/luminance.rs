//! Whole-field luminance events, a closed-loop mechanism the paper leaves out
//! (`docs/model.md`, "Closed-loop mechanisms"; its effect in `docs/experiments.md`).
//!
//! A looming object, a moving edge or the robot's own motion changes part of the image, and in
//! both directions: where something dark arrives the image darkens, where it leaves it
//! brightens. A change of the light (a flickering lamp, sunlight through leaves) or of the
//! sensor's automatic exposure and gain (the OV7670 adjusts them between frames, `COM8`) moves
//! every pixel the same way at once. The correlators of Eq. (6) cannot tell the two apart: on a
//! strobing scene the rounding of the 3x3 means and of the delay line leaves a residue in every
//! direction, and every quadrant of Eq. (8) sees "outward motion". Photoreceptors adapt to such
//! steps within tens of milliseconds; this detector stands in for that adaptation at the level
//! the model works on, one frame: a frame in which most of the retina brightens (or darkens)
//! and next to nothing changes the other way reports no stimulated field.

use crate::model::hrc::Cells;

/// A pixel whose 3x3 mean change (the stored ON or OFF byte, in grey levels) reaches this many
/// levels counts as changing: above the sensor noise (about ±2 levels on the OV7670 in indoor
/// light, which the 3x3 mean brings under 1).
pub const CHANGE_LEVEL: u32 = 4;

/// The other direction must change on fewer than `1 / OPPOSITE_DIVISOR` as many pixels as the
/// dominant one for the frame to count as a luminance event. Motion of a textured scene
/// brightens and darkens about equally many pixels; a change of the light or of the exposure
/// moves next to none the other way. An object that fills the view as it arrives does darken
/// most of the image, but its edges brighten what it uncovers: on the clips, a bird filling
/// the camera's view darkens 6,423 pixels and brightens 816 (1/8), which 16 keeps a threat.
pub const OPPOSITE_DIVISOR: u32 = 16;

/// Every how many pixels one is sampled: a quarter of the retina (1,782 pixels; 99 mod 4 = 3,
/// so the samples shift from row to row) measures a share of the whole to better than 2 %, at a
/// quarter of the cost (≈ 15 k cycles a frame on the Cortex-M4, docs/budget.md).
pub const SAMPLE_STEP: usize = 4;

/// Of the sampled pixels (every [`SAMPLE_STEP`]-th), those whose ON and whose OFF mean reach
/// [`CHANGE_LEVEL`] (bytes 0 and 1 of each cell), and how many were sampled.
pub fn changing(cells: &Cells) -> (u32, u32, u32) {
    let sampled = cells.len().div_ceil(SAMPLE_STEP) as u32;
    // the first cell of each chunk (`step_by` compiled to a slower loop)
    let (chunks, rest) = cells.as_chunks::<SAMPLE_STEP>();
    let (on, off) = chunks
        .iter()
        .map(|c| c[0])
        .chain(rest.first().copied())
        .fold((0u32, 0u32), |(on, off), c| {
            (
                on + u32::from(c & 0xFF >= CHANGE_LEVEL),
                off + u32::from((c >> 8) & 0xFF >= CHANGE_LEVEL),
            )
        });
    (on, off, sampled)
}

/// Whether this frame is a whole-field luminance event: one direction of change covers at least
/// `pct` percent of the retina and the other less than 1/[`OPPOSITE_DIVISOR`] as much. `pct = 0` is off.
pub fn is_event(cells: &Cells, pct: u8) -> bool {
    pct != 0 && is_event_of(changing(cells), pct)
}

/// [`is_event`] on the counts [`changing`] returned (computed once per frame for both uses).
pub fn is_event_of((on, off, sampled): (u32, u32, u32), pct: u8) -> bool {
    if pct == 0 {
        return false;
    }
    let (most, least) = (on.max(off), on.min(off));
    // `sampled · pct` ≤ 1,782 · 100: no overflow
    let need = (sampled * u32::from(pct)).div_ceil(100);
    most >= need && least * OPPOSITE_DIVISOR < most
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::PIXELS;

    fn cells(on: u8, off: u8, n_on: usize, n_off: usize) -> Cells {
        let mut c = [0u32; PIXELS];
        for (i, w) in c.iter_mut().enumerate() {
            let a = if i < n_on { u32::from(on) } else { 0 };
            let b = if i >= PIXELS - n_off {
                u32::from(off)
            } else {
                0
            };
            *w = a | b << 8 | 0xAB << 16 | 0xCD << 24;
        }
        c
    }

    #[test]
    fn a_whole_field_step_is_an_event_and_local_change_is_not() {
        // the whole retina brightens by 20 levels
        assert!(is_event(&cells(20, 0, PIXELS, 0), 50));
        assert!(is_event(&cells(0, 20, 0, PIXELS), 50));
        // a dark object covering a tenth of the view
        assert!(!is_event(&cells(0, 60, 0, PIXELS / 10), 50));
        // a moving texture: brightening and darkening about equally
        assert!(!is_event(
            &cells(30, 30, PIXELS * 6 / 10, PIXELS * 6 / 10),
            50
        ));
        // changes under the level do not count (sensor noise)
        assert!(!is_event(&cells(3, 0, PIXELS, 0), 50));
        // off
        assert!(!is_event(&cells(20, 0, PIXELS, 0), 0));
    }

    #[test]
    fn the_threshold_is_a_share_of_the_sampled_retina_and_the_delayed_bytes_do_not_count() {
        let sampled = PIXELS.div_ceil(SAMPLE_STEP);
        assert_eq!(sampled, 1782);
        // the first n pixels hold ⌈n / 4⌉ samples
        let pixels = |samples: usize| (samples - 1) * SAMPLE_STEP + 1;
        let half = sampled.div_ceil(2);
        assert!(is_event(&cells(10, 0, pixels(half), 0), 50));
        assert!(!is_event(&cells(10, 0, pixels(half - 1), 0), 50));
        assert_eq!(changing(&cells(4, 4, 40, 0)), (10, 0, 1782));
        // 0xAB, 0xCD in the delayed bytes never count
        assert_eq!(changing(&cells(3, 3, PIXELS, PIXELS)), (0, 0, 1782));
        // the other direction on 1/16 of the dominant one's samples is too much
        let (on, off, _) = changing(&cells(10, 10, pixels(half), 700));
        assert!(off * OPPOSITE_DIVISOR >= on, "{on} {off}");
        assert!(!is_event(&cells(10, 10, pixels(half), 700), 50));
        let (on, off, _) = changing(&cells(10, 10, pixels(half), 50));
        assert!(off * OPPOSITE_DIVISOR < on, "{on} {off}");
        assert!(is_event(&cells(10, 10, pixels(half), 50), 50));
    }
}

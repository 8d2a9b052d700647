//! Moving objects seen while standing still: the swarm's cue for where the others are
//! (`Params::look_change`, a closed-loop mechanism; not in the paper).
//!
//! The paper's swarm robots spin on an approaching object and "moved toward a swarm leader";
//! it does not say how they found it. Walking flies stop to look, and orient to small moving
//! objects (object-detecting lobula columnar neurons, LC10/LC11, drive pursuit and
//! fixation); a robot standing still has no flow of its own, so anything that changes in its
//! view moves. A spinning or driving robot is such an object; a wall is not.
//!
//! The stage runs beside the network, on the same frames, in whatever runs the swarm (the
//! simulator's swarm robots, the replay's swarm mode; the firmware escapes and has none: it
//! would cost 2.6 KB of RAM, 2,674 B).
//! While the robot's wheels are commanded to stand (an efference copy, [`Movers::step`]), the
//! stage waits [`SETTLE_FRAMES`] for the wheels to stop (their lag is 50 ms: the residual
//! turn of a robot that has just stopped changes every textured edge), takes the band of rows
//! where other robots appear ([`BAND_TOP`].., [`BAND_ROWS`] rows around the horizon) as its
//! reference, and on each of the next [`SPAN_FRAMES`] frames counts per column the pixels that
//! changed by more than the threshold, keeping each column's most. The [`WINDOW`] neighbouring
//! columns with the most changed pixels hold the mover, if they have at least [`MIN_PIXELS`].
//! Integer arithmetic, one pass over the band per standing frame (2,574 pixels).

use crate::frame::{Frame, CENTRE_X, WIDTH};
use crate::model::closed_loop::derotate::FOCAL_PX;

/// First row of the band compared: 28 mm tall robots 100–800 mm away, seen from 20 mm above
/// the floor, span rows 30–49 (the horizon is row 35.5); rows above show only walls.
pub const BAND_TOP: usize = 24;
/// Rows of the band compared.
pub const BAND_ROWS: usize = 26;
/// Standing frames before the reference is taken.
pub const SETTLE_FRAMES: u8 = 10;
/// Frames between the reference and the comparison (0.4 s: a robot driving 100 mm/s 500 mm
/// away moves 40 mm, its own width; one spinning at 180°/s turns 72°, more than a stripe).
pub const SPAN_FRAMES: u8 = 12;
/// Neighbouring columns summed: a robot 500 mm away is 6 columns wide.
pub const WINDOW: usize = 5;
/// Changed pixels the window needs: a robot 800 mm away covers about 4 × 3 pixels.
pub const MIN_PIXELS: u16 = 6;

/// Pixels of the band.
pub const BAND: usize = BAND_ROWS * WIDTH;

/// What a look found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sighting {
    /// Something moved; the centre column of the window with the most change.
    Mover {
        /// Column, 0..[`WIDTH`].
        x: u8,
    },
    /// Nothing changed (at most [`MIN_PIXELS`] − 1 pixels in any window).
    Nothing,
}

impl Sighting {
    /// Bearing of a mover, degrees (positive = right of the heading); `None` for nothing.
    pub fn bearing_deg(self) -> Option<f32> {
        match self {
            Sighting::Mover { x } => {
                Some(libm::atanf((f32::from(x) - CENTRE_X) / FOCAL_PX).to_degrees())
            }
            Sighting::Nothing => None,
        }
    }
}

/// The reference band, how long the robot has stood, and the change seen so far.
#[derive(Debug, Clone)]
pub struct Movers {
    reference: [u8; BAND],
    standing: u8,
    /// Per column, the most pixels changed on any frame of the span so far.
    most: [u8; WIDTH],
}

impl Default for Movers {
    fn default() -> Self {
        Self::new()
    }
}

impl Movers {
    /// Nothing seen yet.
    pub const fn new() -> Self {
        Movers {
            reference: [0; BAND],
            standing: 0,
            most: [0; WIDTH],
        }
    }

    /// One frame. `standing`: the wheels were commanded to stand still for this frame.
    /// `threshold`: grey levels a pixel must change by (0 turns the stage off). A look
    /// reports once, [`SETTLE_FRAMES`] + [`SPAN_FRAMES`] standing frames after the robot
    /// stopped, and the next look of a robot that keeps standing follows [`SPAN_FRAMES`]
    /// later; every other frame gives `None`. A frame on which more than half the band
    /// changed is a change of the light or of the exposure, not a mover: the look starts over
    /// from it.
    pub fn step(&mut self, frame: &Frame, standing: bool, threshold: u8) -> Option<Sighting> {
        if !standing || threshold == 0 {
            self.standing = 0;
            return None;
        }
        self.standing = self.standing.saturating_add(1);
        let band: &[u8; BAND] = frame
            .get(BAND_TOP * WIDTH..BAND_TOP * WIDTH + BAND)?
            .try_into()
            .ok()?;
        if self.standing <= SETTLE_FRAMES {
            if self.standing == SETTLE_FRAMES {
                self.new_reference(band);
            }
            return None;
        }
        // each frame of the span against the reference: a spinning robot's stripes may line
        // up again at the span's end, a driving one may have left the view
        let cols = changed(&self.reference, band, threshold);
        if 2 * cols.iter().map(|&c| usize::from(c)).sum::<usize>() > BAND {
            self.new_reference(band);
            return None;
        }
        for (m, c) in self.most.iter_mut().zip(cols) {
            *m = (*m).max(c);
        }
        if self.standing < SETTLE_FRAMES + SPAN_FRAMES {
            return None;
        }
        let seen = strongest(&self.most);
        self.new_reference(band);
        Some(seen)
    }

    fn new_reference(&mut self, band: &[u8; BAND]) {
        self.reference = *band;
        self.most = [0; WIDTH];
        self.standing = SETTLE_FRAMES;
    }
}

/// Per column, the pixels of two bands of [`BAND_ROWS`] rows that differ by more than
/// `threshold` grey levels.
pub fn changed(reference: &[u8; BAND], band: &[u8; BAND], threshold: u8) -> [u8; WIDTH] {
    let mut cols = [0u8; WIDTH];
    for (row_ref, row) in reference.chunks_exact(WIDTH).zip(band.chunks_exact(WIDTH)) {
        for ((c, &a), &b) in cols.iter_mut().zip(row_ref).zip(row) {
            // at most BAND_ROWS (26) per column
            *c = c.saturating_add(u8::from(a.abs_diff(b) > threshold));
        }
    }
    cols
}

/// The window of [`WINDOW`] columns with the most changed pixels `cols`, if it holds at
/// least [`MIN_PIXELS`] and twice its share of all the change (the first such window on a
/// tie): a change spread over the view (an exposure step that moved only the bright pixels)
/// has no place and is no mover.
pub fn strongest(cols: &[u8; WIDTH]) -> Sighting {
    let mut best = (0u16, 0usize);
    for (start, w) in cols.windows(WINDOW).enumerate() {
        let sum = w.iter().map(|&c| u16::from(c)).sum::<u16>();
        if sum > best.0 {
            best = (sum, start);
        }
    }
    let total: u32 = cols.iter().map(|&c| u32::from(c)).sum();
    // ≤ 130 · 99 and 2 · 5 · 2,574: no overflow
    let stands_out = u32::from(best.0) * WIDTH as u32 >= 2 * WINDOW as u32 * total;
    match u8::try_from(best.1 + WINDOW / 2) {
        Ok(x) if best.0 >= MIN_PIXELS && stands_out => Sighting::Mover { x },
        _ => Sighting::Nothing,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::PIXELS;

    fn look(before: &Frame, after: &Frame) -> Option<Sighting> {
        let mut m = Movers::new();
        let mut out = None;
        for i in 0..SETTLE_FRAMES + SPAN_FRAMES {
            let f = if i < SETTLE_FRAMES { before } else { after };
            out = m.step(f, true, 25);
            if i + 1 < SETTLE_FRAMES + SPAN_FRAMES {
                assert_eq!(out, None, "frame {i}");
            }
        }
        out
    }

    #[test]
    fn a_blob_that_appears_is_a_mover_at_its_column() {
        let before = [120u8; PIXELS];
        let mut after = before;
        for y in 33..38 {
            for x in 70..74 {
                after[y * WIDTH + x] = 30;
            }
        }
        // 20 changed pixels in columns 70–73: the first window holding all of them
        assert_eq!(look(&before, &after), Some(Sighting::Mover { x: 71 }));
        let b = Sighting::Mover { x: 71 }.bearing_deg().unwrap();
        assert!((b - 17.45).abs() < 0.1, "{b}");
    }

    #[test]
    fn a_still_scene_or_a_change_outside_the_band_is_nothing() {
        let before = [120u8; PIXELS];
        assert_eq!(look(&before, &before), Some(Sighting::Nothing));
        let mut after = before;
        for x in 0..WIDTH {
            after[60 * WIDTH + x] = 0; // below the band
            after[10 * WIDTH + x] = 0; // above it
        }
        assert_eq!(look(&before, &after), Some(Sighting::Nothing));
        // too few pixels, or too small a change
        let mut small = before;
        small[35 * WIDTH + 40] = 0;
        small[36 * WIDTH + 40] = 0;
        for x in 0..WIDTH {
            small[30 * WIDTH + x] = 140;
        }
        assert_eq!(look(&before, &small), Some(Sighting::Nothing));
    }

    #[test]
    fn a_change_of_the_whole_band_is_the_light_and_the_look_starts_over() {
        let before = [120u8; PIXELS];
        let after = [160u8; PIXELS];
        let mut m = Movers::new();
        for _ in 0..SETTLE_FRAMES {
            assert_eq!(m.step(&before, true, 25), None);
        }
        // the light changes: the look starts over from that frame, and a span later it
        // reports a still scene
        let reports: heapless::Vec<u8, 4> = (0..=2 * SPAN_FRAMES)
            .filter(|_| m.step(&after, true, 25).is_some())
            .collect();
        assert_eq!(&reports[..], &[SPAN_FRAMES, 2 * SPAN_FRAMES][..]);
    }

    #[test]
    fn the_boundaries_hold() {
        let before = [120u8; PIXELS];
        let with = |pixels: &[(usize, usize)], grey: u8| {
            let mut f = before;
            for &(x, y) in pixels {
                f[y * WIDTH + x] = grey;
            }
            f
        };
        // 6 changed pixels are a mover, 5 are not
        let six: [(usize, usize); 6] = [(50, 30), (50, 31), (50, 32), (51, 30), (51, 31), (51, 32)];
        assert_eq!(
            look(&before, &with(&six, 0)),
            Some(Sighting::Mover { x: 49 })
        );
        assert_eq!(look(&before, &with(&six[..5], 0)), Some(Sighting::Nothing));
        // a change of exactly the threshold does not count, one more does
        assert_eq!(look(&before, &with(&six, 145)), Some(Sighting::Nothing));
        assert_eq!(
            look(&before, &with(&six, 146)),
            Some(Sighting::Mover { x: 49 })
        );
        // rows 24 and 49 are the band's first and last, 23 and 50 are outside it
        let rows = |a: usize, b: usize| [(20, a), (21, a), (22, a), (20, b), (21, b), (22, b)];
        assert_eq!(
            look(&before, &with(&rows(24, 49), 0)),
            Some(Sighting::Mover { x: 20 })
        );
        assert_eq!(
            look(&before, &with(&rows(23, 50), 0)),
            Some(Sighting::Nothing)
        );
    }

    #[test]
    fn a_change_spread_over_the_view_or_over_half_the_band_is_no_mover() {
        let before = [120u8; PIXELS];
        // three pixels in every column: a change without a place
        let mut spread = before;
        for x in 0..WIDTH {
            for y in [30, 35, 40] {
                spread[y * WIDTH + x] = 0;
            }
        }
        assert_eq!(look(&before, &spread), Some(Sighting::Nothing));
        // exactly half the band still looks; one pixel more is the light
        let mut half = before;
        for p in half[BAND_TOP * WIDTH..].iter_mut().take(BAND / 2) {
            *p = 0;
        }
        assert!(look(&before, &half).is_some());
        half[BAND_TOP * WIDTH + BAND / 2] = 0;
        assert_eq!(look(&before, &half), None);
    }

    #[test]
    fn moving_or_switched_off_never_looks() {
        let f = [0u8; PIXELS];
        let mut m = Movers::new();
        for i in 0..100 {
            assert_eq!(m.step(&f, i % 20 != 19, 25), None);
        }
        for _ in 0..100 {
            assert_eq!(m.step(&f, true, 0), None);
        }
    }

    #[test]
    fn standing_on_looks_again_every_span() {
        let f = [50u8; PIXELS];
        let mut m = Movers::new();
        let looks: heapless::Vec<u32, 8> = (0..60u32)
            .filter(|_| m.step(&f, true, 25).is_some())
            .collect();
        let first = u32::from(SETTLE_FRAMES + SPAN_FRAMES) - 1;
        let span = u32::from(SPAN_FRAMES);
        assert_eq!(
            &looks[..],
            &[first, first + span, first + 2 * span, first + 3 * span][..]
        );
    }
}

//! Camera side of perception: luminance out of the OV7670's YUV422 stream, and the policy that
//! hands completed frames to the perception task.
//!
//! # Luminance
//!
//! The sensor sends 2 bytes a pixel in `Y U Y V` order (`COM7 = 0x08`), so pixel `x` of a line
//! has its luminance at byte `2x + Y_OFFSET`. The public firmware reads pixel `x` from byte
//! `2x + 2` (one pixel late, 7 bits); here the offset is the single constant [`Y_OFFSET`], and
//! the model gets all 8 bits. A 99-pixel line is [`LINE_BYTES`] = 198 bytes.
//!
//! # Frame capture
//!
//! The firmware keeps no frame buffer: DMA fills a small ring of YUV lines, and the DMA
//! interrupt pushes each line's luminance straight into the network's retina
//! ([`crate::Network::push_row`]), which keeps the only copy of a frame (as `P(t−1)`). At
//! frame complete the perception task takes the network and runs the rest of the step. The
//! network has one owner at a time:
//!
//! ```text
//!   VSYNC, network parked ──▶ accepted: rows stream into the retina ──▶ frame complete:
//!        ▲                                                              72 clean rows?
//!        │                                                 yes ─▶ Deliver: perception owns
//!        │                                                        the network, runs, parks it
//!        └──────── parked again ◀──────────────────────────────────────┘
//!   VSYNC while perception still owns it ──▶ waiting: rows into the backlog ─┬─▶ parked before
//!        the backlog is full: adopted, backlog rows first, then stream ◀───┘   (late hand-off)
//!        otherwise ──▶ no row goes anywhere ──▶ Dropped
//! ```
//!
//! The late hand-off: the sensor's VSYNC (start of blanking) may come right after frame complete
//! when the crop window ends near the bottom of what it sends; a frame that begins while
//! perception runs keeps its first [`BACKLOG_ROWS`] rows in a [`Backlog`] and is adopted when
//! perception parks the network in time (docs/firmware.md, "Frame hand-off").
//!
//! [`Capture`] is that policy as a pure state machine (no pixels): it says which row each line
//! is, whether a frame is delivered, dropped (perception was still busy when it began) or
//! invalid (overrun, sync error, wrong line count, cut short). **Invariant**: a delivered frame
//! is exactly [`HEIGHT`] rows streamed in order since one VSYNC with no error — never a frame
//! made of two halves; every frame that ends is counted once:
//! `completed = delivered + dropped + invalidated`. After an invalid frame whose rows were
//! streamed, the firmware calls [`crate::Network::abort_frame`] (the network starts over).
//!
//! Where the paper's firmware drops the *older* of two complete frames, here the frame that
//! begins while perception is busy is the one dropped: it is the only one that can be, since
//! the older frame is already inside the network. Perception takes a few ms and the sensor
//! leaves ≈ 10 ms between frames, so a drop means perception overran (docs/firmware.md).

use crate::frame::{Frame, HEIGHT, PIXELS, WIDTH};

/// Byte offset of the luminance inside each 2-byte pixel: 0 for `Y U Y V` (`Y V Y U`), 1 for
/// `U Y V Y`. From public firmware (which reads Y at even offsets, one pixel late); verify on
/// the first real frame at bring-up.
pub const Y_OFFSET: usize = 0;

/// Bytes per pixel in YUV422.
pub const BYTES_PER_PIXEL: usize = 2;

/// Bytes of one 99-pixel YUV422 line.
pub const LINE_BYTES: usize = WIDTH * BYTES_PER_PIXEL;

/// Bytes of one 99x72 YUV422 frame.
pub const FRAME_BYTES: usize = PIXELS * BYTES_PER_PIXEL;

const _: () = assert!(Y_OFFSET < BYTES_PER_PIXEL);

/// Why a buffer cannot be converted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum YuvError {
    /// The YUV422 input holds `got` bytes instead of `expected`.
    InputLength {
        /// Bytes needed.
        expected: usize,
        /// Bytes given.
        got: usize,
    },
    /// The luminance output holds `got` bytes instead of `expected`.
    OutputLength {
        /// Bytes needed.
        expected: usize,
        /// Bytes given.
        got: usize,
    },
    /// The luminance offset is not 0 or 1.
    BadOffset(usize),
}

impl core::fmt::Display for YuvError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            YuvError::InputLength { expected, got } => {
                write!(f, "YUV422 input of {got} bytes, expected {expected}")
            }
            YuvError::OutputLength { expected, got } => {
                write!(f, "luminance output of {got} bytes, expected {expected}")
            }
            YuvError::BadOffset(o) => write!(f, "luminance offset {o}, must be 0 or 1"),
        }
    }
}

impl core::error::Error for YuvError {}

/// The luminance of one YUV422 line (`2 · WIDTH` bytes) into `y` (`WIDTH` bytes), at
/// [`Y_OFFSET`].
pub fn luma_line(yuv: &[u8], y: &mut [u8]) -> Result<(), YuvError> {
    luma_line_at(Y_OFFSET, yuv, y)
}

/// [`luma_line`] with the luminance at byte `y_offset` of each pixel (bring-up experiments).
pub fn luma_line_at(y_offset: usize, yuv: &[u8], y: &mut [u8]) -> Result<(), YuvError> {
    check(y_offset, yuv.len(), LINE_BYTES, y.len(), WIDTH)?;
    extract(y_offset, yuv, y);
    Ok(())
}

/// The luminance of a whole YUV422 frame ([`FRAME_BYTES`]) into a model frame, at
/// [`Y_OFFSET`] (for whole-frame capture and the host; the firmware converts line by line).
pub fn luma_frame(yuv: &[u8], y: &mut Frame) -> Result<(), YuvError> {
    check(Y_OFFSET, yuv.len(), FRAME_BYTES, y.len(), PIXELS)?;
    extract(Y_OFFSET, yuv, y);
    Ok(())
}

fn check(
    off: usize,
    got_in: usize,
    want_in: usize,
    got_out: usize,
    want_out: usize,
) -> Result<(), YuvError> {
    if off >= BYTES_PER_PIXEL {
        Err(YuvError::BadOffset(off))
    } else if got_in != want_in {
        Err(YuvError::InputLength {
            expected: want_in,
            got: got_in,
        })
    } else if got_out != want_out {
        Err(YuvError::OutputLength {
            expected: want_out,
            got: got_out,
        })
    } else {
        Ok(())
    }
}

fn extract(off: usize, yuv: &[u8], y: &mut [u8]) {
    for (out, px) in y.iter_mut().zip(yuv.chunks_exact(BYTES_PER_PIXEL)) {
        if let Some(&v) = px.get(off) {
            *out = v;
        }
    }
}

/// Rows a frame may send before perception gives the network back (late hand-off): 16 rows of
/// 99 bytes, 1.6 KB. With a sensor that sends only the 72 window lines at 5 % blanking that
/// is 8.7 ms after VSYNC, against ≤ 5.2 ms of perception after frame complete
/// (docs/firmware.md, "Frame hand-off").
pub const BACKLOG_ROWS: usize = 16;

/// The rows of a waiting frame (see [`Capture::waiting`]), in order, until the network is back.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Backlog {
    rows: [[u8; WIDTH]; BACKLOG_ROWS],
    len: usize,
    overflow: bool,
}

impl Default for Backlog {
    fn default() -> Self {
        Self::new()
    }
}

impl Backlog {
    /// Empty.
    pub const fn new() -> Self {
        Backlog {
            rows: [[0; WIDTH]; BACKLOG_ROWS],
            len: 0,
            overflow: false,
        }
    }

    /// Empty again (a new frame).
    pub fn clear(&mut self) {
        self.len = 0;
        self.overflow = false;
    }

    /// Keeps a row; a row that does not fit marks the backlog overflowed (its frame can no
    /// longer be adopted).
    pub fn push(&mut self, row: &[u8; WIDTH]) {
        match self.rows.get_mut(self.len) {
            Some(slot) => {
                *slot = *row;
                self.len += 1;
            }
            None => self.overflow = true,
        }
    }

    /// Every row of the frame so far is here.
    pub fn complete(&self) -> bool {
        !self.overflow
    }

    /// The rows kept, oldest first.
    pub fn rows(&self) -> &[[u8; WIDTH]] {
        &self.rows[..self.len.min(BACKLOG_ROWS)]
    }
}

/// How a frame that begins is taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Start {
    /// Its rows go into the network (false: perception is busy, the frame will be dropped).
    pub accepted: bool,
    /// A frame still in progress was cut short by this VSYNC: it ended invalid
    /// ([`Invalid::Restarted`]), and its rows must be dropped from the network.
    pub cut_short: bool,
}

/// Why a frame that ended is not delivered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Invalid {
    /// A DCMI overrun hit the frame.
    Overrun,
    /// A DCMI embedded-sync error hit the frame.
    SyncError,
    /// The frame ended with `rows` lines instead of [`HEIGHT`] (too few, or more: then the
    /// capture window is wrong).
    WrongLines {
        /// Lines received.
        rows: u16,
    },
    /// A frame end without a frame start (capture started mid-frame).
    NotStarted,
    /// A new VSYNC arrived before the frame-complete event.
    Restarted,
}

/// What [`Capture::frame_complete`] decided.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameEnd {
    /// Whole and clean: perception takes the network and finishes the step.
    Deliver {
        /// Frame number (0-based count of every frame that ended).
        seq: u32,
    },
    /// Whole, but it began while perception was busy: nothing of it entered the network.
    Dropped {
        /// Frame number.
        seq: u32,
    },
    /// Not usable; rows it streamed must be dropped ([`crate::Network::abort_frame`]).
    Invalid(Invalid),
}

/// Running totals since boot (wrapping).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Counters {
    /// Frames that ended (frame-complete, or cut short by the next VSYNC), valid or not.
    pub completed: u32,
    /// Frames handed to perception.
    pub delivered: u32,
    /// Whole frames skipped because perception was still busy when they began.
    pub dropped: u32,
    /// Frames that ended invalid (overrun, sync error, wrong line count, cut short).
    pub invalidated: u32,
    /// DCMI overrun events.
    pub overruns: u32,
    /// DCMI sync error events.
    pub sync_errors: u32,
}

impl Counters {
    /// All totals 0 (usable in `const fn`, unlike `Default`).
    pub const ZERO: Counters = Counters {
        completed: 0,
        delivered: 0,
        dropped: 0,
        invalidated: 0,
        overruns: 0,
        sync_errors: 0,
    };
}

/// The capture policy between the DCMI/DMA interrupts and the perception task (see the
/// module docs for the invariant).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Capture {
    in_frame: bool,
    accepted: bool,
    rows: u16,
    taint: Option<Invalid>,
    counters: Counters,
}

impl Default for Capture {
    fn default() -> Self {
        Self::new()
    }
}

impl Capture {
    /// No frame started.
    pub const fn new() -> Self {
        Capture {
            in_frame: false,
            accepted: false,
            rows: 0,
            taint: None,
            counters: Counters::ZERO,
        }
    }

    /// The totals.
    pub fn counters(&self) -> Counters {
        self.counters
    }

    /// Lines received in the frame in progress.
    pub fn rows(&self) -> u16 {
        self.rows
    }

    /// Whether the frame in progress streams into the network.
    pub fn accepted(&self) -> bool {
        self.in_frame && self.accepted
    }

    /// VSYNC: a new frame begins; it is accepted if the network is free (parked, not owned by
    /// perception).
    pub fn frame_start(&mut self, network_free: bool) -> Start {
        let cut_short = self.in_frame;
        if cut_short {
            self.end_invalid();
        }
        self.in_frame = true;
        self.accepted = network_free;
        self.rows = 0;
        self.taint = None;
        Start {
            accepted: network_free,
            cut_short,
        }
    }

    /// A line arrived: the row it is, if it goes into the network. `None` outside a frame, in
    /// a skipped frame, or past the last row (the frame then ends invalid).
    pub fn line(&mut self) -> Option<u16> {
        if !self.in_frame {
            return None;
        }
        let row = self.rows;
        self.rows = self.rows.saturating_add(1);
        (self.accepted && usize::from(row) < HEIGHT).then_some(row)
    }

    /// The frame in progress began while perception owned the network: its rows wait in the
    /// [`Backlog`] for [`Capture::adopt`].
    pub fn waiting(&self) -> bool {
        self.in_frame && !self.accepted
    }

    /// Perception parked the network while a frame is waiting: the frame is taken if the backlog
    /// holds every row so far (`backlog_complete`); the caller then pushes the backlog's rows
    /// into the network, oldest first, before any new one. Returns whether it was taken.
    pub fn adopt(&mut self, backlog_complete: bool) -> bool {
        let taken = self.waiting()
            && backlog_complete
            && usize::from(self.rows) <= BACKLOG_ROWS.min(HEIGHT);
        if taken {
            self.accepted = true;
        }
        taken
    }

    /// DCMI overrun: counted; the frame in progress is invalid.
    pub fn overrun(&mut self) {
        self.counters.overruns = self.counters.overruns.wrapping_add(1);
        self.taint(Invalid::Overrun);
    }

    /// DCMI sync error: counted; the frame in progress is invalid.
    pub fn sync_error(&mut self) {
        self.counters.sync_errors = self.counters.sync_errors.wrapping_add(1);
        self.taint(Invalid::SyncError);
    }

    fn taint(&mut self, why: Invalid) {
        if self.in_frame && self.taint.is_none() {
            self.taint = Some(why);
        }
    }

    /// Frame complete: delivered if whole, clean and accepted.
    pub fn frame_complete(&mut self) -> FrameEnd {
        let why = if !self.in_frame {
            Some(Invalid::NotStarted)
        } else if let Some(t) = self.taint {
            Some(t)
        } else if usize::from(self.rows) != HEIGHT {
            Some(Invalid::WrongLines { rows: self.rows })
        } else {
            None
        };
        if let Some(why) = why {
            self.end_invalid();
            return FrameEnd::Invalid(why);
        }
        self.in_frame = false;
        let seq = self.counters.completed;
        self.counters.completed = seq.wrapping_add(1);
        if self.accepted {
            self.counters.delivered = self.counters.delivered.wrapping_add(1);
            FrameEnd::Deliver { seq }
        } else {
            self.counters.dropped = self.counters.dropped.wrapping_add(1);
            FrameEnd::Dropped { seq }
        }
    }

    fn end_invalid(&mut self) {
        self.in_frame = false;
        self.taint = None;
        self.counters.completed = self.counters.completed.wrapping_add(1);
        self.counters.invalidated = self.counters.invalidated.wrapping_add(1);
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use proptest::prelude::*;
    use std::vec::Vec;

    #[test]
    fn luma_comes_from_even_bytes() {
        let mut yuv = [0u8; LINE_BYTES];
        for (i, b) in yuv.iter_mut().enumerate() {
            // Y = pixel index, chroma = 200 + parity
            *b = if i % 2 == 0 {
                (i / 2) as u8
            } else {
                200 + (i % 4) as u8
            };
        }
        let mut y = [0u8; WIDTH];
        luma_line(&yuv, &mut y).unwrap();
        assert_eq!((y[0], y[1], y[50], y[98]), (0, 1, 50, 98));
        // U Y V Y reads the chroma instead: 201, 203, …
        luma_line_at(1, &yuv, &mut y).unwrap();
        assert_eq!((y[0], y[1], y[2]), (201, 203, 201));
    }

    #[test]
    fn wrong_lengths_are_errors_not_panics() {
        let yuv = [0u8; LINE_BYTES + 1];
        let mut y = [0u8; WIDTH + 1];
        assert_eq!(
            luma_line(&yuv, &mut y[..WIDTH]),
            Err(YuvError::InputLength {
                expected: 198,
                got: 199
            })
        );
        assert_eq!(
            luma_line(&yuv[..LINE_BYTES], &mut y),
            Err(YuvError::OutputLength {
                expected: 99,
                got: 100
            })
        );
        assert_eq!(
            luma_line_at(2, &yuv[..LINE_BYTES], &mut y[..WIDTH]),
            Err(YuvError::BadOffset(2))
        );
        let mut frame = [0u8; PIXELS];
        assert_eq!(
            luma_frame(&yuv, &mut frame),
            Err(YuvError::InputLength {
                expected: FRAME_BYTES,
                got: 199
            })
        );
    }

    #[test]
    fn a_frame_is_its_lines() {
        let yuv: Vec<u8> = (0..FRAME_BYTES).map(|i| (i * 7 % 251) as u8).collect();
        let mut frame = [0u8; PIXELS];
        luma_frame(&yuv, &mut frame).unwrap();
        // pixel (x, y) is byte 2·(y·99 + x)
        assert_eq!(frame[0], 0);
        assert_eq!(frame[1], 14);
        assert_eq!(frame[99 * 3 + 5], ((2 * (99 * 3 + 5)) * 7 % 251) as u8);
        for row in 0..HEIGHT {
            let mut line = [0u8; WIDTH];
            luma_line(&yuv[row * LINE_BYTES..][..LINE_BYTES], &mut line).unwrap();
            assert_eq!(&frame[row * WIDTH..][..WIDTH], &line[..]);
        }
    }

    /// A whole clean frame: every line is the next row when accepted, none otherwise.
    fn capture(c: &mut Capture, free: bool) -> FrameEnd {
        assert!(!c.frame_start(free).cut_short);
        for r in 0..HEIGHT {
            assert_eq!(c.line(), free.then_some(r as u16));
        }
        c.frame_complete()
    }

    fn counters(c: u32, d: u32, dr: u32, i: u32, o: u32, s: u32) -> Counters {
        Counters {
            completed: c,
            delivered: d,
            dropped: dr,
            invalidated: i,
            overruns: o,
            sync_errors: s,
        }
    }

    #[test]
    fn frames_are_delivered_when_the_network_is_free_and_dropped_whole_when_not() {
        let mut c = Capture::new();
        assert_eq!(capture(&mut c, true), FrameEnd::Deliver { seq: 0 });
        assert_eq!(capture(&mut c, false), FrameEnd::Dropped { seq: 1 });
        assert_eq!(capture(&mut c, true), FrameEnd::Deliver { seq: 2 });
        assert_eq!(c.counters(), counters(3, 2, 1, 0, 0, 0));
    }

    #[test]
    fn overrun_and_sync_error_invalidate_the_frame_in_progress() {
        let mut c = Capture::new();
        c.frame_start(true);
        c.line();
        c.overrun();
        for _ in 1..HEIGHT {
            c.line();
        }
        c.sync_error();
        assert_eq!(c.frame_complete(), FrameEnd::Invalid(Invalid::Overrun));
        assert_eq!(c.counters(), counters(1, 0, 0, 1, 1, 1));
        assert_eq!(capture(&mut c, true), FrameEnd::Deliver { seq: 1 });
        c.frame_start(true);
        c.sync_error();
        assert_eq!(c.frame_complete(), FrameEnd::Invalid(Invalid::SyncError));
        // errors between frames are counted but taint nothing
        c.overrun();
        assert_eq!(capture(&mut c, true), FrameEnd::Deliver { seq: 3 });
        assert_eq!(c.counters(), counters(4, 2, 0, 2, 2, 2));
        // an error in a skipped frame: invalid rather than dropped
        c.frame_start(false);
        c.overrun();
        assert_eq!(c.frame_complete(), FrameEnd::Invalid(Invalid::Overrun));
    }

    #[test]
    fn frames_with_wrong_line_counts_or_no_start_are_invalid() {
        let mut c = Capture::new();
        // capture began mid-frame
        assert_eq!(c.line(), None);
        assert_eq!(c.frame_complete(), FrameEnd::Invalid(Invalid::NotStarted));
        // short frame
        c.frame_start(true);
        c.line();
        assert_eq!(
            c.frame_complete(),
            FrameEnd::Invalid(Invalid::WrongLines { rows: 1 })
        );
        // long frame: the 73rd line is no row
        c.frame_start(true);
        for _ in 0..HEIGHT {
            assert!(c.line().is_some());
        }
        assert_eq!(c.line(), None);
        assert_eq!(
            c.frame_complete(),
            FrameEnd::Invalid(Invalid::WrongLines { rows: 73 })
        );
        // a VSYNC in the middle of a frame: the first half is cut short, never delivered
        c.frame_start(true);
        for _ in 0..HEIGHT / 2 {
            c.line();
        }
        assert_eq!(
            c.frame_start(true),
            Start {
                accepted: true,
                cut_short: true
            }
        );
        for _ in 0..HEIGHT / 2 {
            c.line();
        }
        assert_eq!(
            c.frame_complete(),
            FrameEnd::Invalid(Invalid::WrongLines { rows: 36 })
        );
        assert_eq!(c.counters(), counters(5, 0, 0, 5, 0, 0));
    }

    #[test]
    fn a_waiting_frame_is_adopted_while_its_backlog_holds_every_row() {
        let mut c = Capture::new();
        let mut b = Backlog::new();
        assert!(!c.frame_start(false).accepted);
        for r in 0..10u8 {
            assert_eq!(c.line(), None);
            assert!(c.waiting());
            b.push(&[r; WIDTH]);
        }
        assert!(c.adopt(b.complete()));
        assert!(!c.waiting());
        assert_eq!(b.rows().len(), 10);
        assert_eq!(b.rows()[9], [9; WIDTH]);
        for r in 10..HEIGHT as u16 {
            assert_eq!(
                c.line(),
                Some(r),
                "the stream goes on after the backlog's rows"
            );
        }
        assert_eq!(c.frame_complete(), FrameEnd::Deliver { seq: 0 });

        // one row too many: the frame can only be dropped
        c.frame_start(false);
        b.clear();
        for _ in 0..=BACKLOG_ROWS {
            c.line();
            b.push(&[0; WIDTH]);
        }
        assert!(!b.complete());
        assert!(!c.adopt(b.complete()));
        assert!(!c.adopt(true), "more rows than a backlog holds");
        for _ in BACKLOG_ROWS + 1..HEIGHT {
            assert_eq!(c.line(), None);
        }
        assert_eq!(c.frame_complete(), FrameEnd::Dropped { seq: 1 });
    }

    #[derive(Debug, Clone, Copy)]
    enum Ev {
        Start,
        Line,
        Lines,
        Complete,
        Overrun,
        SyncError,
        Park,
        Adopt,
    }

    fn ev() -> impl Strategy<Value = Ev> {
        prop_oneof![
            2 => Just(Ev::Start),
            2 => Just(Ev::Line),
            6 => Just(Ev::Lines),
            3 => Just(Ev::Complete),
            1 => Just(Ev::Overrun),
            1 => Just(Ev::SyncError),
            3 => Just(Ev::Park),
            2 => Just(Ev::Adopt),
        ]
    }

    proptest! {
        #[test]
        fn the_invariant_holds_for_any_event_sequence(evs in prop::collection::vec(ev(), 0..300)) {
            let mut c = Capture::new();
            // the network as the firmware drives it: rows streamed since the last start,
            // and who owns it
            let mut streamed: Option<u16> = None;
            let mut parked = true;
            let mut last_seq: Option<u32> = None;
            // rows of a waiting frame, as the backlog holds them (None: overflowed)
            let mut held: Option<u16> = None;
            for e in evs {
                match e {
                    Ev::Start => {
                        let s = c.frame_start(parked);
                        prop_assert_eq!(s.accepted, parked);
                        streamed = s.accepted.then_some(0);
                        held = Some(0);
                    }
                    Ev::Line | Ev::Lines => {
                        let n = if matches!(e, Ev::Line) { 1 } else { HEIGHT };
                        for _ in 0..n {
                            if let Some(row) = c.line() {
                                // rows reach the network only while it is not perception's,
                                // in order from one VSYNC
                                prop_assert!(parked);
                                prop_assert_eq!(Some(row), streamed);
                                streamed = Some(row + 1);
                            } else if c.waiting() {
                                held = held
                                    .map(|h| h + 1)
                                    .filter(|&h| usize::from(h) <= BACKLOG_ROWS);
                            }
                        }
                    }
                    Ev::Complete => match c.frame_complete() {
                        FrameEnd::Deliver { seq } => {
                            prop_assert_eq!(streamed, Some(HEIGHT as u16));
                            prop_assert!(last_seq.is_none_or(|s| seq > s));
                            last_seq = Some(seq);
                            parked = false;
                            streamed = None;
                        }
                        FrameEnd::Dropped { .. } | FrameEnd::Invalid(_) => {
                            streamed = None;
                            held = None;
                        }
                    },
                    Ev::Overrun => c.overrun(),
                    Ev::SyncError => c.sync_error(),
                    Ev::Park => parked = true,
                    Ev::Adopt => {
                        if parked && c.adopt(held.is_some()) {
                            // the backlog's rows go in first: the stream continues after them
                            prop_assert_eq!(Some(c.rows()), held);
                            streamed = held;
                        }
                    }
                }
                let k = c.counters();
                prop_assert_eq!(k.delivered + k.dropped + k.invalidated, k.completed);
            }
        }
    }
}

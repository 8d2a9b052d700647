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
//! # Frame hand-off
//!
//! The firmware keeps [`BUFFERS`] = 3 Y-only frames (3 × 7128 B; DMA fills a small YUV line
//! buffer and the DCMI/DMA interrupt copies each line's Y into the frame being written). Each
//! buffer has one role at a time:
//!
//! ```text
//!        frame complete             take()
//! writing ───────────────▶ ready ───────────▶ reading ──▶ (released by take/release)
//!    ▲                       │ frame complete while still ready:
//!    └───────────────────────┘ the older ready frame is dropped, its buffer written next
//! ```
//!
//! **Invariant**: the writing, ready and reading buffers are pairwise distinct. So perception
//! never reads a buffer the camera writes, a frame is only published after exactly
//! [`HEIGHT`] lines arrived since its VSYNC with no overrun or sync error (never a frame made
//! of two halves), and the newest complete frame is the one delivered. Every frame that ends
//! is counted exactly once: `completed = delivered + dropped + invalidated + (1 if a frame
//! is waiting in ready)`.
//!
//! [`Handoff`] holds only buffer indices and counters, no pixels: the firmware owns the memory
//! and calls these methods from the DCMI interrupt and the perception task (under a lock).

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

/// Frame buffers the hand-off rotates.
pub const BUFFERS: usize = 3;

/// Index of a frame buffer, `0..BUFFERS`.
pub type BufferId = u8;

/// Where the interrupt copies the luminance of the line just received.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineSlot {
    /// The buffer being written.
    pub buffer: BufferId,
    /// Row of the frame, `0..HEIGHT`.
    pub row: u16,
}

/// A frame handed to perception.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Delivery {
    /// Buffer to read; no one writes it until the next [`Handoff::take`] or
    /// [`Handoff::release`].
    pub buffer: BufferId,
    /// Camera frame number (0-based count of every frame that ended, valid or not); gaps mean
    /// dropped or invalid frames.
    pub seq: u32,
}

/// Why a frame that ended is not published.
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

/// What [`Handoff::frame_complete`] did with the frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameEnd {
    /// Published in `buffer` for perception.
    Ready {
        /// Buffer now ready.
        buffer: BufferId,
        /// Its frame number.
        seq: u32,
    },
    /// Published, and the older frame perception had not taken yet was dropped.
    ReadyDroppedOlder {
        /// Buffer now ready.
        buffer: BufferId,
        /// Its frame number.
        seq: u32,
    },
    /// Not published; the buffer is written again.
    Invalid(Invalid),
}

/// Running totals since boot (wrapping).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Counters {
    /// Frames that ended (frame-complete, or cut short by the next VSYNC), valid or not.
    pub completed: u32,
    /// Frames handed to perception.
    pub delivered: u32,
    /// Complete frames replaced by a newer one before perception took them.
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

/// The frame hand-off between the DCMI interrupt and the perception task (see the module
/// docs for the invariant).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Handoff {
    writing: BufferId,
    ready: Option<(BufferId, u32)>,
    reading: Option<BufferId>,
    in_frame: bool,
    rows: u16,
    taint: Option<Invalid>,
    counters: Counters,
}

impl Default for Handoff {
    fn default() -> Self {
        Self::new()
    }
}

impl Handoff {
    /// Camera writing buffer 0, nothing ready, nothing read, no frame started.
    pub const fn new() -> Self {
        Handoff {
            writing: 0,
            ready: None,
            reading: None,
            in_frame: false,
            rows: 0,
            taint: None,
            counters: Counters::ZERO,
        }
    }

    /// The buffer the camera writes.
    pub fn writing(&self) -> BufferId {
        self.writing
    }

    /// The buffer waiting for perception, if any.
    pub fn ready(&self) -> Option<BufferId> {
        self.ready.map(|(b, _)| b)
    }

    /// The buffer perception reads, if any.
    pub fn reading(&self) -> Option<BufferId> {
        self.reading
    }

    /// The totals.
    pub fn counters(&self) -> Counters {
        self.counters
    }

    /// VSYNC: a new frame starts in the writing buffer. A frame still in progress ends
    /// invalid ([`Invalid::Restarted`]).
    pub fn frame_start(&mut self) {
        if self.in_frame {
            self.end_invalid(Invalid::Restarted);
        }
        self.in_frame = true;
        self.rows = 0;
        self.taint = None;
    }

    /// A line arrived: where to put its luminance. `None` outside a frame, or past the last
    /// row (the frame then ends invalid).
    pub fn line(&mut self) -> Option<LineSlot> {
        if !self.in_frame {
            return None;
        }
        let row = self.rows;
        self.rows = self.rows.saturating_add(1);
        (usize::from(row) < HEIGHT).then_some(LineSlot {
            buffer: self.writing,
            row,
        })
    }

    /// DCMI overrun: counted; the frame being written is invalid.
    pub fn overrun(&mut self) {
        self.counters.overruns = self.counters.overruns.wrapping_add(1);
        self.taint(Invalid::Overrun);
    }

    /// DCMI sync error: counted; the frame being written is invalid.
    pub fn sync_error(&mut self) {
        self.counters.sync_errors = self.counters.sync_errors.wrapping_add(1);
        self.taint(Invalid::SyncError);
    }

    fn taint(&mut self, why: Invalid) {
        if self.in_frame && self.taint.is_none() {
            self.taint = Some(why);
        }
    }

    /// Frame complete: publishes the frame if it is whole and clean, else writes the same
    /// buffer again.
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
            self.end_invalid(why);
            return FrameEnd::Invalid(why);
        }
        self.in_frame = false;
        let seq = self.counters.completed;
        self.counters.completed = seq.wrapping_add(1);
        let done = self.writing;
        match self.ready.replace((done, seq)) {
            Some((older, _)) => {
                self.counters.dropped = self.counters.dropped.wrapping_add(1);
                self.writing = older;
                FrameEnd::ReadyDroppedOlder { buffer: done, seq }
            }
            None => {
                let reading = self.reading;
                // With 3 buffers exactly one is neither `done` nor `reading`.
                self.writing = (0..BUFFERS as BufferId)
                    .find(|&b| b != done && Some(b) != reading)
                    .unwrap_or(done);
                FrameEnd::Ready { buffer: done, seq }
            }
        }
    }

    fn end_invalid(&mut self, _why: Invalid) {
        self.in_frame = false;
        self.taint = None;
        self.counters.completed = self.counters.completed.wrapping_add(1);
        self.counters.invalidated = self.counters.invalidated.wrapping_add(1);
    }

    /// Perception asks for the newest frame: the buffer it was reading (if any) is released,
    /// and the ready frame (if any) becomes the one it reads.
    pub fn take(&mut self) -> Option<Delivery> {
        self.reading = None;
        let (buffer, seq) = self.ready.take()?;
        self.reading = Some(buffer);
        self.counters.delivered = self.counters.delivered.wrapping_add(1);
        Some(Delivery { buffer, seq })
    }

    /// Perception is done with its buffer.
    pub fn release(&mut self) {
        self.reading = None;
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

    /// A whole clean frame into the writing buffer.
    fn capture(h: &mut Handoff) -> FrameEnd {
        h.frame_start();
        for r in 0..HEIGHT {
            assert_eq!(
                h.line(),
                Some(LineSlot {
                    buffer: h.writing(),
                    row: r as u16
                })
            );
        }
        h.frame_complete()
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
    fn frames_rotate_through_the_three_buffers() {
        let mut h = Handoff::new();
        assert_eq!((h.writing(), h.ready(), h.reading()), (0, None, None));
        assert_eq!(h.take(), None);
        assert_eq!(capture(&mut h), FrameEnd::Ready { buffer: 0, seq: 0 });
        assert_eq!((h.writing(), h.ready(), h.reading()), (1, Some(0), None));
        assert_eq!(h.take(), Some(Delivery { buffer: 0, seq: 0 }));
        assert_eq!((h.writing(), h.ready(), h.reading()), (1, None, Some(0)));
        // perception busy on 0: frame 1 goes to ready, the camera moves to 2
        assert_eq!(capture(&mut h), FrameEnd::Ready { buffer: 1, seq: 1 });
        assert_eq!((h.writing(), h.ready(), h.reading()), (2, Some(1), Some(0)));
        // still busy: frame 2 replaces frame 1, whose buffer is written next
        assert_eq!(
            capture(&mut h),
            FrameEnd::ReadyDroppedOlder { buffer: 2, seq: 2 }
        );
        assert_eq!((h.writing(), h.ready(), h.reading()), (1, Some(2), Some(0)));
        // perception finishes 0 and takes the newest
        assert_eq!(h.take(), Some(Delivery { buffer: 2, seq: 2 }));
        assert_eq!((h.writing(), h.ready(), h.reading()), (1, None, Some(2)));
        h.release();
        assert_eq!((h.writing(), h.ready(), h.reading()), (1, None, None));
        assert_eq!(capture(&mut h), FrameEnd::Ready { buffer: 1, seq: 3 });
        assert_eq!((h.writing(), h.ready(), h.reading()), (0, Some(1), None));
        assert_eq!(h.counters(), counters(4, 2, 1, 0, 0, 0));
    }

    #[test]
    fn take_without_a_new_frame_releases_and_returns_nothing() {
        let mut h = Handoff::new();
        capture(&mut h);
        h.take();
        assert_eq!(h.take(), None);
        assert_eq!(h.reading(), None);
    }

    #[test]
    fn overrun_and_sync_error_invalidate_the_frame_being_written() {
        let mut h = Handoff::new();
        h.frame_start();
        h.line();
        h.overrun();
        for _ in 1..HEIGHT {
            h.line();
        }
        h.sync_error();
        assert_eq!(h.frame_complete(), FrameEnd::Invalid(Invalid::Overrun));
        assert_eq!((h.writing(), h.ready()), (0, None));
        assert_eq!(h.counters(), counters(1, 0, 0, 1, 1, 1));
        // the next frame is clean again
        assert_eq!(capture(&mut h), FrameEnd::Ready { buffer: 0, seq: 1 });
        h.frame_start();
        h.sync_error();
        assert_eq!(h.frame_complete(), FrameEnd::Invalid(Invalid::SyncError));
        // errors between frames are counted but taint nothing
        h.overrun();
        assert_eq!(
            capture(&mut h),
            FrameEnd::ReadyDroppedOlder { buffer: 1, seq: 3 }
        );
        assert_eq!(h.counters(), counters(4, 0, 1, 2, 2, 2));
    }

    #[test]
    fn frames_with_wrong_line_counts_or_no_start_are_invalid() {
        let mut h = Handoff::new();
        // capture began mid-frame
        assert_eq!(h.line(), None);
        assert_eq!(h.frame_complete(), FrameEnd::Invalid(Invalid::NotStarted));
        // short frame
        h.frame_start();
        h.line();
        assert_eq!(
            h.frame_complete(),
            FrameEnd::Invalid(Invalid::WrongLines { rows: 1 })
        );
        // long frame: the 73rd line has no slot
        h.frame_start();
        for _ in 0..HEIGHT {
            assert!(h.line().is_some());
        }
        assert_eq!(h.line(), None);
        assert_eq!(
            h.frame_complete(),
            FrameEnd::Invalid(Invalid::WrongLines { rows: 73 })
        );
        // a VSYNC in the middle of a frame: the first half is never published
        h.frame_start();
        for _ in 0..HEIGHT / 2 {
            h.line();
        }
        h.frame_start();
        for _ in 0..HEIGHT / 2 {
            h.line();
        }
        assert_eq!(
            h.frame_complete(),
            FrameEnd::Invalid(Invalid::WrongLines { rows: 36 })
        );
        assert_eq!(h.counters(), counters(5, 0, 0, 5, 0, 0));
        assert_eq!((h.writing(), h.ready()), (0, None));
    }

    #[derive(Debug, Clone, Copy)]
    enum Ev {
        Start,
        Line,
        Lines,
        Complete,
        Overrun,
        SyncError,
        Take,
        Release,
    }

    fn ev() -> impl Strategy<Value = Ev> {
        prop_oneof![
            2 => Just(Ev::Start),
            2 => Just(Ev::Line),
            6 => Just(Ev::Lines),
            3 => Just(Ev::Complete),
            1 => Just(Ev::Overrun),
            1 => Just(Ev::SyncError),
            3 => Just(Ev::Take),
            1 => Just(Ev::Release),
        ]
    }

    proptest! {
        #[test]
        fn the_invariant_holds_for_any_event_sequence(evs in prop::collection::vec(ev(), 0..300)) {
            let mut h = Handoff::new();
            let mut last_seq: Option<u32> = None;
            // frame each buffer holds, written line by line: (seq of its VSYNC, rows)
            let mut starts = 0u32;
            let mut content: [Option<(u32, u16)>; BUFFERS] = [None; BUFFERS];
            for e in evs {
                match e {
                    Ev::Start => {
                        h.frame_start();
                        starts += 1;
                    }
                    Ev::Line | Ev::Lines => {
                        let n = if matches!(e, Ev::Line) { 1 } else { HEIGHT };
                        for _ in 0..n {
                            if let Some(s) = h.line() {
                                prop_assert_ne!(Some(s.buffer), h.reading());
                                prop_assert_ne!(Some(s.buffer), h.ready());
                                let c = &mut content[usize::from(s.buffer)];
                                // a buffer's rows come from one VSYNC, in order
                                *c = match *c {
                                    Some((v, r)) if v == starts && r == s.row => Some((v, r + 1)),
                                    _ if s.row == 0 => Some((starts, 1)),
                                    _ => None,
                                };
                            }
                        }
                    }
                    Ev::Complete => {
                        if let FrameEnd::Ready { buffer, .. }
                        | FrameEnd::ReadyDroppedOlder { buffer, .. } = h.frame_complete()
                        {
                            // published frames are whole and from a single VSYNC
                            prop_assert_eq!(
                                content[usize::from(buffer)],
                                Some((starts, HEIGHT as u16))
                            );
                        }
                    }
                    Ev::Overrun => h.overrun(),
                    Ev::SyncError => h.sync_error(),
                    Ev::Take => {
                        if let Some(d) = h.take() {
                            prop_assert_ne!(d.buffer, h.writing());
                            // never the same frame twice, newest first
                            prop_assert!(last_seq.is_none_or(|s| d.seq > s));
                            last_seq = Some(d.seq);
                        }
                    }
                    Ev::Release => h.release(),
                }
                let (w, rd, rr) = (h.writing(), h.ready(), h.reading());
                prop_assert!(usize::from(w) < BUFFERS);
                prop_assert_ne!(Some(w), rd);
                prop_assert_ne!(Some(w), rr);
                prop_assert!(rd.is_none() || rd != rr);
                let c = h.counters();
                prop_assert_eq!(
                    c.delivered + c.dropped + c.invalidated + u32::from(rd.is_some()),
                    c.completed
                );
            }
        }
    }
}

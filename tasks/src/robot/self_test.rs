//! The boot self-test: the firmware's `init` runs the bench step ([`super::bench::step`]) on
//! built-in frames before the camera starts and prints each frame's stage cycles on RTT
//! channel 0, so a user can hold the board's counts against the cycle model's for the same
//! build (`cargo alvs log`). Its frames, its line, and the line's parser live here, shared by
//! the firmware, the cycle model and the host.
//!
//! ```text
//! bench: frame 1 cycles retina 236196 attention 192789 motion 224319 visuomotor 24600 control 4936 total 682840 (3793 us at 180 MHz), 1 AFs
//! ```
//!
//! Grammar (single spaces): `"bench: frame " u32 " cycles" 5 × (" " stage " " u32) " total "
//! u32 " (" u32 " us at 180 MHz), " u32 " AFs"`, the stages in [`STAGE_NAMES`] order, the total
//! their sum (wrapping, as the counter does) and the microseconds the total at
//! [`CPU_HZ`](super::health::CPU_HZ), rounded down.

use core::fmt::{self, Write};

use super::bench::{Report, STAMPS};
use super::health::CPU_HZ;
use super::line::{self, LineError};
use crate::frame::{Frame, HEIGHT, PIXELS, WIDTH};

/// The stages of a step, in the order of [`Report::stage_cycles`].
pub const STAGE_NAMES: [&str; STAMPS - 1] =
    ["retina", "attention", "motion", "visuomotor", "control"];

/// Seeds of the two built-in frames.
pub const SEEDS: [u32; 2] = [0x1234_5678, 0x9abc_def0];

/// Frames the self-test steps through: the two built-in ones, twice (the first primes).
pub const FRAMES: usize = 4;

/// Random black and white blocks of [`BLOCK`] x [`BLOCK`] pixels, a compile-time constant
/// (xorshift32 of `seed`, one draw per block): two such frames differ on half of the retina,
/// so nearly every part of it changes and is salient. Neighbouring pixels are mostly alike,
/// as in a picture: frames of independent pixels are noise, which the default model
/// recognises and skips (`Params::noise_pct`), and would time that shortcut instead of the
/// network.
pub const fn blocks(seed: u32) -> Frame {
    let mut f = [0u8; PIXELS];
    let mut s = seed;
    let mut by = 0;
    while by < HEIGHT.div_ceil(BLOCK) {
        let mut bx = 0;
        while bx < WIDTH.div_ceil(BLOCK) {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            let v = if s & 0x100 != 0 { 255 } else { 0 };
            let mut y = by * BLOCK;
            while y < (by + 1) * BLOCK && y < HEIGHT {
                let mut x = bx * BLOCK;
                while x < (bx + 1) * BLOCK && x < WIDTH {
                    f[y * WIDTH + x] = v;
                    x += 1;
                }
                y += 1;
            }
            bx += 1;
        }
        by += 1;
    }
    f
}

/// Side of the blocks of [`blocks`], pixels: the 3x3 mean of Eq. (2) sees a block's full
/// contrast at its centre.
pub const BLOCK: usize = 3;

/// One `bench:` line: a self-test frame's stage cycles and the attention fields it left.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BenchLine {
    /// Self-test frame, 0 first.
    pub frame: u32,
    /// Cycles per stage, in [`STAGE_NAMES`] order.
    pub stages: [u32; STAMPS - 1],
    /// Attention fields standing after the frame.
    pub afs: u32,
}

impl BenchLine {
    /// The line of self-test frame `frame` from its step's report.
    pub fn from_report(frame: u32, r: &Report) -> BenchLine {
        BenchLine {
            frame,
            stages: r.stage_cycles(),
            afs: r.afs,
        }
    }

    /// The stages' sum, wrapping as the 32-bit cycle counter does.
    pub fn total(&self) -> u32 {
        self.stages.iter().fold(0u32, |a, &c| a.wrapping_add(c))
    }

    /// Writes the line with its trailing `'\n'`, integers only.
    pub fn write_line<W: Write>(&self, w: &mut W) -> fmt::Result {
        write!(w, "bench: frame {} cycles", self.frame)?;
        for (name, c) in STAGE_NAMES.iter().zip(self.stages) {
            write!(w, " {name} {c}")?;
        }
        let total = self.total();
        writeln!(
            w,
            " total {total} ({} us at {} MHz), {} AFs",
            total / (CPU_HZ / 1_000_000),
            CPU_HZ / 1_000_000,
            self.afs
        )
    }

    /// Parses a line [`BenchLine::write_line`] wrote (the terminator is optional); the total
    /// and the microseconds must agree with the stages. Never panics.
    pub fn parse_line(s: &str) -> Result<BenchLine, LineError> {
        let mut t = line::bare(s).split(' ');
        if t.next() != Some("bench:") {
            return Err(LineError::OtherLine);
        }
        line::word(&mut t, "frame", "frame")?;
        let frame = line::number(&mut t, "frame")?;
        line::word(&mut t, "cycles", "cycles")?;
        let mut stages = [0u32; STAMPS - 1];
        for (name, c) in STAGE_NAMES.iter().zip(&mut stages) {
            line::word(&mut t, name, name)?;
            *c = line::number(&mut t, name)?;
        }
        line::word(&mut t, "total", "total")?;
        let total = line::number(&mut t, "total")?;
        let us = t
            .next()
            .and_then(|v| v.strip_prefix('('))
            .ok_or(LineError::Missing("us"))?;
        let us = line::canonical_u32(us).ok_or(LineError::BadNumber("us"))?;
        for w in ["us", "at", "180"] {
            line::word(&mut t, w, "us")?;
        }
        // the comma before the field count
        line::word(&mut t, "MHz),", "AFs")?;
        let afs = line::number(&mut t, "AFs")?;
        line::word(&mut t, "AFs", "AFs")?;
        line::end(&mut t)?;
        let b = BenchLine { frame, stages, afs };
        if b.total() != total {
            return Err(LineError::Inconsistent("total"));
        }
        if total / (CPU_HZ / 1_000_000) != us {
            return Err(LineError::Inconsistent("us"));
        }
        Ok(b)
    }
}

impl fmt::Display for BenchLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write_line(f)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use proptest::prelude::*;
    use std::string::{String, ToString};

    const LINE: &str = "bench: frame 1 cycles retina 236196 attention 192789 motion 224319 visuomotor 24600 control 4936 total 682840 (3793 us at 180 MHz), 1 AFs\n";

    #[test]
    fn the_board_line_parses_and_renders_back() {
        let b = BenchLine::parse_line(LINE).expect("parses");
        assert_eq!(b.frame, 1);
        assert_eq!(b.stages, [236196, 192789, 224319, 24600, 4936]);
        assert_eq!((b.total(), b.afs), (682_840, 1));
        assert_eq!(b.to_string(), LINE);
        assert_eq!(BenchLine::parse_line(LINE.trim_end()), Ok(b));
    }

    #[test]
    fn from_a_report() {
        let r = Report {
            stamps: [10, 20, 20, 20, 20, 35],
            afs: 0,
            ..Report::default()
        };
        let b = BenchLine::from_report(0, &r);
        assert_eq!(b.stages, [10, 0, 0, 0, 15]);
        assert_eq!(
            b.to_string(),
            "bench: frame 0 cycles retina 10 attention 0 motion 0 visuomotor 0 control 15 total 25 (0 us at 180 MHz), 0 AFs\n"
        );
    }

    #[test]
    fn broken_lines_are_refused() {
        use LineError::*;
        let cases: [(String, LineError); 8] = [
            ("camera: OV7670".into(), OtherLine),
            (LINE.replace("frame 1", "frame x"), BadNumber("frame")),
            (LINE.replace(" motion", " motor"), Missing("motion")),
            (
                LINE.replace("total 682840", "total 682841"),
                Inconsistent("total"),
            ),
            (LINE.replace("(3793", "(3794"), Inconsistent("us")),
            (LINE.replace(", 1 AFs", ""), Missing("AFs")),
            (LINE[..60].to_string(), BadNumber("motion")),
            (LINE.trim_end().to_string() + " x", TrailingData),
        ];
        for (line, err) in cases {
            assert_eq!(BenchLine::parse_line(&line), Err(err), "{line}");
        }
    }

    #[test]
    fn the_built_in_frames_change_half_the_retina_and_are_no_noise() {
        use crate::model::closed_loop::noise_frames::{grain, is_noise};
        let (a, b) = (blocks(SEEDS[0]), blocks(SEEDS[1]));
        assert!(a.iter().chain(&b).all(|&p| p == 0 || p == 255));
        let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        assert!(differ > PIXELS * 2 / 5, "{differ}");
        let pct = crate::model::param_table::off0(crate::Params::ALVS.mechanisms.noise_pct);
        assert!(pct > 0 && !is_noise(&grain(&a), pct) && !is_noise(&grain(&b), pct));
    }

    proptest! {
        #[test]
        fn round_trip(frame in any::<u32>(), stages in any::<[u32; 5]>(), afs in any::<u32>()) {
            let b = BenchLine { frame, stages, afs };
            prop_assert_eq!(BenchLine::parse_line(&b.to_string()), Ok(b));
        }

        #[test]
        fn never_panics(s in "bench: [a-z0-9 (),.]{0,150}") {
            let _ = BenchLine::parse_line(&s);
        }
    }
}

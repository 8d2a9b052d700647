//! The camera side: the OV7670's frame timing and the DCMI that samples it (RM0090 15.5–15.8).
//!
//! Timing: a frame every `frame_cycles`; VSYNC leaves its blanking level at the frame's start,
//! `lines` HREF lines follow evenly over the active part, then VSYNC blanks for
//! `blank_fraction` of the frame. The DCMI (hardware sync, 8-bit data) starts a capture at the
//! first VSYNC deactivation after CAPTURE is set, packs bytes into words (first byte in the
//! low byte) and asks its DMA stream for each word. In crop mode it takes CAPCNT + 1 pixel
//! clocks from HOFFCNT of lines VST..=VST + VLINE and raises FRAME after the window's last
//! line; VSYNC_RIS rises when VSYNC enters blanking ("inactive to active", 15.8.3). A word the
//! DMA does not take waits in the 8-word FIFO; a ninth is an overrun: OVR_RIS, and the DCMI
//! waits for the next frame.

pub const DCMI_BASE: u32 = 0x5005_0000;

const CAPTURE: u32 = 1;
const SNAPSHOT: u32 = 1 << 1;
const CROP: u32 = 1 << 2;
const ENABLE: u32 = 1 << 14;

pub const FRAME_RIS: u32 = 1;
pub const OVR_RIS: u32 = 1 << 1;
pub const VSYNC_RIS: u32 = 1 << 3;
pub const LINE_RIS: u32 = 1 << 4;

/// Words the DCMI FIFO holds (RM0090 15.5.2: "8-word FIFO").
pub const FIFO_WORDS: u32 = 8;

/// The sensor's output timing (unknown until bring-up: every field is a parameter).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraTiming {
    /// Core cycles per frame: 6,000,000 = 30 fps at 180 MHz.
    pub frame_cycles: u64,
    /// HREF lines per frame (QCIF: 144).
    pub lines: u16,
    /// Pixel clocks per HREF line (QCIF YUV422: 2 × 176).
    pub line_clocks: u16,
    /// Fraction of the frame period VSYNC blanks. VGA timing: 30 of 510 line periods, 0.06.
    pub blank_fraction: f64,
    /// Cycle of the first frame's start.
    pub first_frame_at: u64,
}

impl Default for CameraTiming {
    fn default() -> Self {
        CameraTiming {
            frame_cycles: 6_000_000,
            lines: 144,
            line_clocks: 352,
            blank_fraction: 0.06,
            first_frame_at: 1_000_000,
        }
    }
}

impl CameraTiming {
    /// Cycles from a frame's start to the end of its HREF line `line` (0-based).
    pub fn line_end(&self, line: u16) -> u64 {
        let active = self.frame_cycles as f64 * (1.0 - self.blank_fraction);
        (active * f64::from(line + 1) / f64::from(self.lines)) as u64
    }

    /// Cycles from a frame's start to VSYNC blanking.
    pub fn blank_start(&self) -> u64 {
        self.line_end(self.lines - 1)
    }
}

/// The DCMI's registers and capture state.
#[derive(Clone, Debug, Default)]
pub struct Dcmi {
    cr: u32,
    ris: u32,
    ier: u32,
    escr: u32,
    esur: u32,
    cwstrt: u32,
    cwsize: u32,
    /// Capturing the current frame.
    capturing: bool,
    /// Bytes of a word not yet complete.
    partial: Vec<u8>,
    /// Words refused by the DMA, waiting in the FIFO.
    fifo: u32,
    vsync_blank: bool,
    /// Frames whose capture began / overruns, for reports.
    pub frames_captured: u64,
    pub overruns: u64,
}

impl Dcmi {
    pub fn read(&self, offset: u32) -> u32 {
        match offset {
            0x00 => self.cr,
            0x04 => u32::from(self.vsync_blank) << 1 | u32::from(self.fifo > 0) << 2,
            0x08 => self.ris,
            0x0C => self.ier,
            0x10 => self.ris & self.ier,
            0x18 => self.escr,
            0x1C => self.esur,
            0x20 => self.cwstrt,
            0x24 => self.cwsize,
            _ => 0,
        }
    }

    pub fn write(&mut self, offset: u32, value: u32) {
        match offset {
            0x00 => self.cr = value & 0x7FFF,
            0x0C => self.ier = value & 0x1F,
            0x14 => self.ris &= !value,
            0x18 => self.escr = value,
            0x1C => self.esur = value,
            0x20 => self.cwstrt = value & 0x1FFF_3FFF,
            0x24 => self.cwsize = value & 0x3FFF_3FFF,
            _ => {}
        }
    }

    /// The DCMI interrupt line.
    pub fn line_high(&self) -> bool {
        self.ris & self.ier != 0
    }

    fn window(&self) -> Option<(u32, u32, u32, u32)> {
        (self.cr & CROP != 0).then(|| {
            (
                self.cwstrt & 0x3FFF,
                (self.cwsize & 0x3FFF) + 1,
                (self.cwstrt >> 16) & 0x1FFF,
                ((self.cwsize >> 16) & 0x3FFF) + 1,
            )
        })
    }

    /// VSYNC leaves blanking: a capture starts if the interface is enabled and capturing.
    pub fn frame_start(&mut self) {
        self.vsync_blank = false;
        self.capturing = self.cr & ENABLE != 0 && self.cr & CAPTURE != 0;
        self.partial.clear();
        self.fifo = 0;
        if self.capturing {
            self.frames_captured += 1;
        }
    }

    /// Where the crop window starts, in pixels (2 clocks each) and lines: (0, 0) uncropped.
    pub fn window_origin(&self) -> (usize, usize) {
        self.window()
            .map_or((0, 0), |(x, _, y, _)| ((x / 2) as usize, y as usize))
    }

    /// HREF line `line` ended with these pixel-clock bytes: returns the words completed, to be
    /// offered to the DMA (see [`Dcmi::refused`]), and whether the window is now complete
    /// (FRAME).
    pub fn line_end(&mut self, line: u16, bytes: &[u8]) -> (Vec<u32>, bool) {
        self.ris |= LINE_RIS;
        if !self.capturing {
            return (Vec::new(), false);
        }
        let line = u32::from(line);
        let (taken, last): (&[u8], bool) = match self.window() {
            Some((x, w, y, h)) => {
                if line < y || line >= y + h {
                    return (Vec::new(), false);
                }
                let from = (x as usize).min(bytes.len());
                let to = (x + w).min(bytes.len() as u32) as usize;
                (&bytes[from..to], line + 1 == y + h)
            }
            None => (bytes, false),
        };
        self.partial.extend_from_slice(taken);
        let words: Vec<u32> = self
            .partial
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        let rest = self.partial.len() % 4;
        self.partial.drain(..self.partial.len() - rest);
        if last {
            self.frame_captured();
        }
        (words, last)
    }

    fn frame_captured(&mut self) {
        self.ris |= FRAME_RIS;
        self.capturing = false;
        if self.cr & SNAPSHOT != 0 {
            self.cr &= !CAPTURE;
        }
    }

    /// The DMA did not take a word: into the FIFO, or an overrun when it is full.
    pub fn refused(&mut self) {
        if !self.capturing {
            return;
        }
        self.fifo += 1;
        if self.fifo > FIFO_WORDS {
            self.ris |= OVR_RIS;
            self.overruns += 1;
            self.capturing = false;
            self.fifo = 0;
        }
    }

    /// VSYNC enters blanking.
    pub fn frame_end(&mut self) {
        self.vsync_blank = true;
        self.ris |= VSYNC_RIS;
        if self.capturing && self.window().is_none() {
            self.frame_captured();
        }
        self.capturing = false;
    }
}

/// The bytes of one sensor line in YUV422 (Y at even pixel clocks, U and V 128) with the 99x72
/// luma image placed at (`x0`, `y0`) pixels; grey elsewhere.
pub fn sensor_line(
    image: &[u8],
    width: usize,
    height: usize,
    line: usize,
    clocks: usize,
    x0: usize,
    y0: usize,
) -> Vec<u8> {
    (0..clocks)
        .map(|c| {
            if c % 2 == 1 {
                return 128;
            }
            let x = (c / 2).wrapping_sub(x0);
            let y = line.wrapping_sub(y0);
            if x < width && y < height {
                image.get(y * width + x).copied().unwrap_or(128)
            } else {
                128
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cropped(x: u32, w: u32, y: u32, h: u32) -> Dcmi {
        let mut d = Dcmi::default();
        d.write(0x20, x | y << 16);
        d.write(0x24, (w - 1) | (h - 1) << 16);
        d.write(0x0C, FRAME_RIS | OVR_RIS | VSYNC_RIS);
        d.write(0x00, ENABLE | CROP | CAPTURE);
        d
    }

    #[test]
    fn crop_window_words_and_frame_after_its_last_line() {
        let mut d = cropped(2, 6, 1, 2);
        d.frame_start();
        let line: Vec<u8> = (0..10).collect();
        assert!(d.line_end(0, &line).0.is_empty(), "above the window");
        assert_eq!(d.line_end(1, &line), (vec![0x0504_0302], false));
        assert_eq!(d.read(0x10) & FRAME_RIS, 0);
        // 2 bytes left over + 6 = 8: two words
        assert_eq!(d.line_end(2, &line), (vec![0x0302_0706, 0x0706_0504], true));
        assert_eq!(d.read(0x10) & FRAME_RIS, FRAME_RIS);
        assert!(d.line_end(3, &line).0.is_empty(), "after the window");
        assert_eq!(d.window_origin(), (1, 1));
        assert!(d.line_high());
        d.write(0x14, FRAME_RIS);
        assert!(!d.line_high());
        d.frame_end();
        assert_eq!(d.read(0x10), VSYNC_RIS);
    }

    #[test]
    fn nine_refused_words_overrun_and_wait_for_the_next_frame() {
        let mut d = cropped(0, 8, 0, 4);
        d.frame_start();
        for _ in 0..FIFO_WORDS {
            d.refused();
        }
        assert_eq!(d.read(0x08) & OVR_RIS, 0);
        d.refused();
        assert_eq!(d.read(0x08) & OVR_RIS, OVR_RIS);
        assert!(
            d.line_end(0, &[1; 8]).0.is_empty(),
            "no capture until the next frame"
        );
        d.frame_start();
        assert_eq!(d.line_end(0, &[1; 8]).0.len(), 2);
    }

    #[test]
    fn no_capture_without_enable_and_capture() {
        let mut d = cropped(0, 8, 0, 1);
        d.write(0x00, CROP | ENABLE);
        d.frame_start();
        assert!(d.line_end(0, &[1; 8]).0.is_empty());
        assert_eq!(d.frames_captured, 0);
    }

    #[test]
    fn timing_spreads_lines_over_the_active_part() {
        let t = CameraTiming::default();
        assert_eq!(t.blank_start(), 5_640_000);
        assert!(t.line_end(0) > 0 && t.line_end(71) < t.blank_start() / 2 + 40_000);
        let l = sensor_line(&[10, 20, 30, 40], 2, 2, 1, 8, 1, 0);
        assert_eq!(l, vec![128, 128, 30, 128, 40, 128, 128, 128]);
    }
}

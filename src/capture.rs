//! The camera side of the frame path, owned by the DCMI and DMA interrupts (same priority):
//! lines from the DMA ring stream into the network's retina under the [`Capture`] policy of
//! `tasks::robot::camera`; at frame complete the network goes to the perception task.

use alvs_tasks::robot::camera::{self, Backlog, Capture, FrameEnd, Start};
use alvs_tasks::{Network, HEIGHT, WIDTH};
use cortex_m::peripheral::DWT;

use crate::camera::dcmi::{Dcmi, HALF_LINES};

/// DMA interrupt latency tolerated at frame complete, in polls of the DMA flags: the DCMI
/// raises FRAME when the last pixel enters its FIFO; the DMA moves the last words a few bus
/// cycles later.
const LAST_HALF_POLLS: u32 = 2_000;

/// Camera-side state.
pub struct FrameIn {
    /// The DCMI and its DMA stream.
    pub dcmi: Dcmi,
    /// The capture policy.
    pub capture: Capture,
    /// The network while the camera holds it (between VSYNC and frame complete, or parked
    /// here across invalid frames).
    pub network: Option<&'static mut Network>,
    /// Cycles spent streaming this frame's rows (the retina stage runs here).
    pub retina_cycles: u32,
    /// The ring half the DMA fills next (false = first).
    next_second: bool,
    /// Rows of a frame that began while perception owned the network (late hand-off).
    backlog: Backlog,
}

impl FrameIn {
    /// Nothing captured yet.
    pub fn new(dcmi: Dcmi) -> Self {
        FrameIn {
            dcmi,
            capture: Capture::new(),
            network: None,
            retina_cycles: 0,
            next_second: false,
            backlog: Backlog::new(),
        }
    }

    /// Starts continuous capture (DCMI and DMA interrupts follow).
    pub fn capture_start(&mut self) {
        self.dcmi.start();
    }

    /// VSYNC: re-arms the DMA at the ring's start and begins a frame, accepted if `network`
    /// (the network, if perception parked it) is available.
    pub fn frame_start(&mut self, parked: Option<&'static mut Network>) -> Start {
        self.dcmi.arm_dma();
        self.next_second = false;
        self.retina_cycles = 0;
        self.backlog.clear();
        if self.network.is_none() {
            self.network = parked;
        }
        let start = self.capture.frame_start(self.network.is_some());
        if start.cut_short {
            if let Some(n) = self.network.as_deref_mut() {
                n.abort_frame();
            }
        }
        start
    }

    /// DMA interrupt: streams every complete half of the ring into the network.
    pub fn drain(&mut self) {
        let h = self.dcmi.take_halves();
        if h.error || (h.first && h.second) {
            // a transfer error, or both halves at once: the interrupt came so late that
            // the older half may be overwritten; the frame cannot be trusted
            self.capture.overrun();
            return;
        }
        if h.first || h.second {
            if h.second != self.next_second {
                self.capture.overrun();
                return;
            }
            self.next_second = !self.next_second;
            self.stream(h.second);
        }
    }

    /// Late hand-off: perception parked the network while a frame waits; the frame is adopted
    /// if the backlog holds all its rows so far, which then go into the retina first.
    /// `parked` keeps the network otherwise.
    pub fn offer(&mut self, parked: &mut Option<&'static mut Network>) {
        if self.network.is_some() || parked.is_none() || !self.capture.waiting() {
            return;
        }
        if !self.capture.adopt(self.backlog.complete()) {
            return;
        }
        let t0 = DWT::cycle_count();
        let mut network = parked.take();
        if let Some(n) = network.as_deref_mut() {
            for row in self.backlog.rows() {
                // at most BACKLOG_ROWS < HEIGHT rows: cannot fail
                let _ = n.push_row(row);
            }
        }
        self.network = network;
        self.backlog.clear();
        self.retina_cycles = self
            .retina_cycles
            .wrapping_add(DWT::cycle_count().wrapping_sub(t0));
    }

    fn stream(&mut self, second: bool) {
        let t0 = DWT::cycle_count();
        for i in 0..HALF_LINES {
            let row = self.capture.line();
            if row.is_none() && !self.capture.waiting() {
                continue;
            }
            let mut y = [0u8; WIDTH];
            // a ring line is exactly LINE_BYTES and `y` WIDTH: cannot fail
            let _ = camera::luma_line(self.dcmi.line(second, i), &mut y);
            match self.network.as_deref_mut() {
                // the policy hands out at most HEIGHT rows a frame: cannot fail
                Some(n) if row.is_some() => {
                    let _ = n.push_row(&y);
                }
                _ => self.backlog.push(&y),
            }
        }
        self.retina_cycles = self
            .retina_cycles
            .wrapping_add(DWT::cycle_count().wrapping_sub(t0));
    }

    /// FRAME: takes the last lines (waiting briefly for the DMA's final half), then decides.
    /// On delivery the network leaves with the result.
    pub fn frame_complete(&mut self) -> (FrameEnd, Option<&'static mut Network>) {
        self.drain();
        let mut polls = 0;
        while self.capture.accepted()
            && usize::from(self.capture.rows()) + HALF_LINES == HEIGHT
            && polls < LAST_HALF_POLLS
        {
            self.drain();
            polls += 1;
        }
        let end = self.capture.frame_complete();
        match end {
            FrameEnd::Deliver { .. } => (end, self.network.take()),
            FrameEnd::Invalid(_) => {
                if let Some(n) = self.network.as_deref_mut() {
                    n.abort_frame();
                }
                (end, None)
            }
            FrameEnd::Dropped { .. } => (end, None),
        }
    }
}

//! DCMI capture into a DMA ring of YUV422 lines, through the PAC (the HAL has no DCMI driver).
//!
//! DCMI: 8-bit data, hardware sync (polarities in [`crate::board`]), continuous capture, crop
//! window 99x72 (198 pixel clocks x 72 lines). DMA2 stream 1 channel 1 moves the 32-bit DCMI
//! data register into [`RING_LINES`] = 4 lines (792 bytes = 198 words: a line of 198 bytes is
//! not a whole number of words, two are) in circular mode; the half-transfer and
//! transfer-complete interrupts each mean "two more lines are in" (the older half is read
//! while DMA fills the other). At every VSYNC the stream is re-armed so each frame starts at
//! the ring's beginning whatever happened to the last one. The ring is in SRAM: DMA cannot
//! reach CCM (see memory.x).

use alvs_tasks::robot::camera::LINE_BYTES;
use stm32f4xx_hal::pac;

use crate::board;

/// Lines in the DMA ring.
pub const RING_LINES: usize = 4;
/// Lines per half of the ring (per DMA interrupt).
pub const HALF_LINES: usize = RING_LINES / 2;
/// Size of the ring in 32-bit words.
pub const RING_WORDS: usize = RING_LINES * LINE_BYTES / 4;
const _: () = assert!(
    (HALF_LINES * LINE_BYTES).is_multiple_of(4),
    "a half must be whole words"
);

/// The DMA target. Written only by the DMA, read only through [`Dcmi::half`] while the DMA
/// fills the other half.
static mut RING: [u32; RING_WORDS] = [0; RING_WORDS];

/// DCMI events of one interrupt, in the order they must be handled.
#[derive(Debug, Clone, Copy, Default)]
pub struct Events {
    /// The last line of a frame was captured (FRAME).
    pub frame: bool,
    /// Data was lost: the DMA did not empty the DCMI FIFO in time (OVR).
    pub overrun: bool,
    /// Embedded-sync error (ERR; only in embedded sync mode, kept for completeness).
    pub sync_error: bool,
    /// VSYNC went to its blanking level: the next lines are a new frame.
    pub vsync: bool,
}

/// Which halves of the ring the DMA finished since the last look.
#[derive(Debug, Clone, Copy, Default)]
pub struct Halves {
    /// First half (lines 0, 1 of the ring) complete.
    pub first: bool,
    /// Second half (lines 2, 3) complete.
    pub second: bool,
    /// DMA transfer error (bad address: a bug, never expected).
    pub error: bool,
}

/// The DCMI and its DMA stream.
pub struct Dcmi {
    dcmi: pac::DCMI,
    dma: pac::DMA2,
}

impl Dcmi {
    /// Takes the peripherals; clocks must be enabled and the pins set to AF13 by the caller.
    pub fn new(dcmi: pac::DCMI, dma: pac::DMA2) -> Self {
        Dcmi { dcmi, dma }
    }

    /// Configures DCMI and DMA and starts continuous capture with its interrupts.
    pub fn start(&mut self) {
        self.dcmi.cr().write(|w| {
            w.cm().continuous();
            w.ess().hardware();
            if board::DCMI_PIXCLK_RISING {
                w.pckpol().rising_edge();
            } else {
                w.pckpol().falling_edge();
            }
            if board::DCMI_VSYNC_BLANK_HIGH {
                w.vspol().active_high();
            } else {
                w.vspol().active_low();
            }
            if board::DCMI_HREF_BLANK_HIGH {
                w.hspol().active_high();
            } else {
                w.hspol().active_low();
            }
            w.fcrc().all();
            w.edm().bit_width8();
            w.crop().cropped()
        });
        // CAPCNT counts pixel clocks minus one; VLINE lines minus one.
        let clocks = (LINE_BYTES - 1) as u16;
        let lines = (alvs_tasks::HEIGHT - 1) as u16;
        self.dcmi.cwstrt().write(|w| {
            w.hoffcnt().set(board::DCMI_CROP_X_CLOCKS);
            w.vst().set(board::DCMI_CROP_Y_LINES)
        });
        self.dcmi.cwsize().write(|w| {
            w.capcnt().set(clocks);
            w.vline().set(lines)
        });
        self.arm_dma();
        self.dcmi.icr().write(|w| {
            w.frame_isc().set_bit();
            w.ovr_isc().set_bit();
            w.err_isc().set_bit();
            w.vsync_isc().set_bit();
            w.line_isc().set_bit()
        });
        self.dcmi.ier().write(|w| {
            w.frame_ie().enabled();
            w.ovr_ie().enabled();
            w.err_ie().enabled();
            w.vsync_ie().enabled()
        });
        self.dcmi.cr().modify(|_, w| w.enable().enabled());
        self.dcmi.cr().modify(|_, w| w.capture().set_bit());
    }

    /// (Re)starts the DMA stream at the beginning of the ring.
    pub fn arm_dma(&mut self) {
        self.dma
            .st(board::DCMI_DMA_STREAM)
            .cr()
            .modify(|_, w| w.en().disabled());
        // The stream finishes its current beat before EN reads 0 (a few bus cycles).
        let mut spins = 0u32;
        while self
            .dma
            .st(board::DCMI_DMA_STREAM)
            .cr()
            .read()
            .en()
            .is_enabled()
            && spins < 10_000
        {
            spins += 1;
        }
        self.clear_dma_flags();
        let st = self.dma.st(board::DCMI_DMA_STREAM);
        let ring = core::ptr::addr_of_mut!(RING) as u32;
        st.par()
            .write(|w| unsafe { w.pa().bits(self.dcmi.dr().as_ptr() as u32) });
        st.m0ar().write(|w| unsafe { w.m0a().bits(ring) });
        st.ndtr().write(|w| w.ndt().set(RING_WORDS as u16));
        st.fcr().write(|w| {
            // FIFO on (DCMI needs 32-bit peripheral reads), threshold half: the DCMI
            // reference design
            w.dmdis().enabled();
            w.fth().half()
        });
        st.cr().write(|w| {
            w.chsel().set(board::DCMI_DMA_CHANNEL);
            w.dir().peripheral_to_memory();
            w.psize().bits32();
            w.msize().bits32();
            w.minc().incremented();
            w.pinc().fixed();
            w.circ().enabled();
            w.pl().very_high();
            w.htie().enabled();
            w.tcie().enabled();
            w.teie().enabled();
            w.en().enabled()
        });
    }

    fn clear_dma_flags(&mut self) {
        self.dma.lifcr().write(|w| {
            w.ctcif1().set_bit();
            w.chtif1().set_bit();
            w.cteif1().set_bit();
            w.cdmeif1().set_bit();
            w.cfeif1().set_bit()
        });
    }

    /// Reads and clears the DCMI interrupt flags.
    pub fn take_events(&mut self) -> Events {
        let m = self.dcmi.mis().read();
        let e = Events {
            frame: m.frame_mis().bit_is_set(),
            overrun: m.ovr_mis().bit_is_set(),
            sync_error: m.err_mis().bit_is_set(),
            vsync: m.vsync_mis().bit_is_set(),
        };
        self.dcmi.icr().write(|w| {
            w.frame_isc().bit(e.frame);
            w.ovr_isc().bit(e.overrun);
            w.err_isc().bit(e.sync_error);
            w.vsync_isc().bit(e.vsync)
        });
        e
    }

    /// Reads and clears the DMA half/complete flags.
    pub fn take_halves(&mut self) -> Halves {
        let s = self.dma.lisr().read();
        let h = Halves {
            first: s.htif1().is_half(),
            second: s.tcif1().is_complete(),
            error: s.teif1().is_error(),
        };
        self.dma.lifcr().write(|w| {
            w.chtif1().bit(h.first);
            w.ctcif1().bit(h.second);
            w.cteif1().bit(h.error)
        });
        h
    }

    /// Line `i` (`0..HALF_LINES`) of half `second`, as YUV422 bytes.
    pub fn line(&self, second: bool, i: usize) -> &[u8; LINE_BYTES] {
        let line = usize::from(second) * HALF_LINES + i.min(HALF_LINES - 1);
        // SAFETY: the ring is only written by the DMA, and only in the other half while this
        // half is read (its interrupt came; the next one for this half is two lines away);
        // `line < RING_LINES`, so the 198 bytes lie inside the 792-byte ring; u8 has no
        // alignment. A late reader sees newer pixels, never an invalid value.
        unsafe {
            let base = core::ptr::addr_of!(RING) as *const u8;
            &*(base.add(line * LINE_BYTES) as *const [u8; LINE_BYTES])
        }
    }
}

//! DMA2 (RM0090 10.5): eight streams with their registers; peripheral-to-memory transfers with
//! circular mode and the half/complete/error flags, which is what the DCMI uses (stream 1,
//! channel 1). Memory-to-memory and double-buffer modes are not modelled (the firmware uses
//! neither): their registers only hold what was written.

pub const DMA2_BASE: u32 = 0x4002_6400;

/// Flag bits of one stream within its 6-bit field of LISR/HISR.
pub const FEIF: u32 = 1;
pub const DMEIF: u32 = 1 << 2;
pub const TEIF: u32 = 1 << 3;
pub const HTIF: u32 = 1 << 4;
pub const TCIF: u32 = 1 << 5;

const EN: u32 = 1;
const DMEIE: u32 = 1 << 1;
const TEIE: u32 = 1 << 2;
const HTIE: u32 = 1 << 3;
const TCIE: u32 = 1 << 4;
const CIRC: u32 = 1 << 8;
const MINC: u32 = 1 << 10;
const FEIE: u32 = 1 << 7;

#[derive(Clone, Copy, Debug, Default)]
pub struct Stream {
    pub cr: u32,
    ndtr: u32,
    pub par: u32,
    pub m0ar: u32,
    pub m1ar: u32,
    pub fcr: u32,
    flags: u32,
    /// NDTR latched at enable (the circular reload value).
    initial: u32,
}

impl Stream {
    pub fn enabled(&self) -> bool {
        self.cr & EN != 0
    }

    pub fn channel(&self) -> u32 {
        (self.cr >> 25) & 7
    }

    /// Direction bits: 0 peripheral-to-memory.
    fn direction(&self) -> u32 {
        (self.cr >> 6) & 3
    }

    fn memory_bytes(&self) -> u32 {
        1 << ((self.cr >> 13) & 3)
    }

    /// Whether the stream's interrupt line is high.
    fn line(&self) -> bool {
        let f = self.flags;
        (f & TCIF != 0 && self.cr & TCIE != 0)
            || (f & HTIF != 0 && self.cr & HTIE != 0)
            || (f & TEIF != 0 && self.cr & TEIE != 0)
            || (f & DMEIF != 0 && self.cr & DMEIE != 0)
            || (f & FEIF != 0 && self.fcr & FEIE != 0)
    }
}

/// What a peripheral request became.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Transfer {
    /// Write the word at this memory address.
    Write(u32),
    /// The stream does not serve the request (disabled, other channel or direction).
    Refused,
}

#[derive(Clone, Debug, Default)]
pub struct Dma {
    pub streams: [Stream; 8],
}

/// Bit offset of stream `s`'s flags in LISR (s < 4) or HISR.
fn shift(s: usize) -> u32 {
    [0, 6, 16, 22][s % 4]
}

impl Dma {
    pub fn read(&self, offset: u32) -> u32 {
        match offset {
            0x00 | 0x04 => {
                let base = if offset == 0 { 0 } else { 4 };
                (0..4).fold(0, |v, i| v | self.streams[base + i].flags << shift(i))
            }
            0x08 | 0x0C => 0,
            o if (0x10..0xD0).contains(&o) => {
                let s = &self.streams[((o - 0x10) / 0x18) as usize];
                match (o - 0x10) % 0x18 {
                    0x00 => s.cr,
                    0x04 => s.ndtr,
                    0x08 => s.par,
                    0x0C => s.m0ar,
                    0x10 => s.m1ar,
                    // FS (FIFO status 5:3) = 100: empty
                    _ => (s.fcr & !0x38) | 0x20,
                }
            }
            _ => 0,
        }
    }

    pub fn write(&mut self, offset: u32, value: u32) {
        match offset {
            0x08 | 0x0C => {
                let base = if offset == 8 { 0 } else { 4 };
                for i in 0..4 {
                    self.streams[base + i].flags &= !((value >> shift(i)) & 0x3D);
                }
            }
            o if (0x10..0xD0).contains(&o) => {
                let s = &mut self.streams[((o - 0x10) / 0x18) as usize];
                let configurable = !s.enabled();
                match (o - 0x10) % 0x18 {
                    0x00 => {
                        if s.enabled() {
                            // only EN can change while enabled (RM0090 10.5.5)
                            s.cr = (s.cr & !EN) | (value & EN);
                        } else {
                            s.cr = value;
                            if value & EN != 0 {
                                s.initial = s.ndtr;
                            }
                        }
                    }
                    0x04 if configurable => s.ndtr = value & 0xFFFF,
                    0x08 if configurable => s.par = value,
                    0x0C => s.m0ar = value,
                    0x10 => s.m1ar = value,
                    0x14 => s.fcr = value,
                    _ => {}
                }
            }
            _ => {}
        }
    }

    /// Stream `s`'s interrupt line.
    pub fn line(&self, s: usize) -> bool {
        self.streams[s].line()
    }

    /// A peripheral asks stream `s` on `channel` to move one data item from the peripheral.
    /// `reachable`: whether the DMA can write the memory address (not CCM).
    pub fn request(&mut self, s: usize, channel: u32, reachable: impl Fn(u32) -> bool) -> Transfer {
        let st = &mut self.streams[s];
        if !st.enabled() || st.channel() != channel || st.direction() != 0 || st.ndtr == 0 {
            return Transfer::Refused;
        }
        let index = st.initial - st.ndtr;
        let addr = if st.cr & MINC != 0 {
            st.m0ar.wrapping_add(index * st.memory_bytes())
        } else {
            st.m0ar
        };
        if !reachable(addr) {
            // a bus error: TEIF, and the stream disables itself (RM0090 10.3.16)
            st.flags |= TEIF;
            st.cr &= !EN;
            return Transfer::Refused;
        }
        st.ndtr -= 1;
        if st.ndtr == st.initial / 2 {
            st.flags |= HTIF;
        }
        if st.ndtr == 0 {
            st.flags |= TCIF;
            if st.cr & CIRC != 0 {
                st.ndtr = st.initial;
            } else {
                st.cr &= !EN;
            }
        }
        Transfer::Write(addr)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn armed(words: u32) -> Dma {
        let mut d = Dma::default();
        let s1 = 0x10 + 0x18;
        d.write(s1 + 4, words);
        d.write(s1 + 0xC, 0x2000_0100);
        d.write(
            s1,
            1 << 25 | 2 << 13 | 2 << 11 | MINC | CIRC | HTIE | TCIE | EN,
        );
        d
    }

    #[test]
    fn circular_ring_with_half_and_complete_flags() {
        let mut d = armed(4);
        let sram = |a: u32| (0x2000_0000..0x2003_0000).contains(&a);
        assert_eq!(d.request(1, 1, sram), Transfer::Write(0x2000_0100));
        assert_eq!(d.request(1, 1, sram), Transfer::Write(0x2000_0104));
        assert_eq!(d.read(0) >> 6 & 0x3F, HTIF);
        assert!(d.line(1));
        d.write(0x08, HTIF << 6);
        assert!(!d.line(1));
        d.request(1, 1, sram);
        assert_eq!(d.request(1, 1, sram), Transfer::Write(0x2000_010C));
        assert_eq!(d.read(0) >> 6 & 0x3F, TCIF);
        assert_eq!(d.request(1, 1, sram), Transfer::Write(0x2000_0100), "wraps");
        assert_eq!(d.read(0x10 + 0x18 + 4), 3);
    }

    #[test]
    fn refuses_when_disabled_or_other_channel_and_errors_on_ccm() {
        let mut d = armed(4);
        assert_eq!(d.request(1, 2, |_| true), Transfer::Refused);
        let cr = d.read(0x28);
        d.write(0x28, cr & !EN);
        assert_eq!(d.read(0x28) & EN, 0, "EN reads 0 at once");
        assert_eq!(d.request(1, 1, |_| true), Transfer::Refused);
        let mut d = armed(4);
        assert_eq!(d.request(1, 1, |_| false), Transfer::Refused);
        assert_eq!(d.read(0) >> 6 & TEIF, TEIF);
        assert_eq!(d.read(0x28) & EN, 0);
    }
}

//! UART4's transmitter (RM0090 30.6): a data register in front of a shift register. A byte
//! written to DR moves to the shift register when it is free (TXE set again), leaves the
//! pin 10 bit times later (8N1), then TC is set if nothing follows. Only transmit is modelled:
//! the firmware sends motor frames with the no-ack head and never reads.

use super::events::{Event, Queue};

pub const UART4_BASE: u32 = 0x4000_4C00;

const TC: u32 = 1 << 6;
const TXE: u32 = 1 << 7;
const TE: u32 = 1 << 3;
const TCIE: u32 = 1 << 6;
const TXEIE: u32 = 1 << 7;
const UE: u32 = 1 << 13;

#[derive(Clone, Debug, Default)]
pub struct Uart {
    brr: u32,
    cr1: u32,
    cr2: u32,
    cr3: u32,
    gtpr: u32,
    holding: Option<u8>,
    shifting: Option<u8>,
    tc: bool,
    generation: u32,
    /// Bytes that left the pin, with the cycle their stop bit ended.
    pub sent: Vec<(u64, u8)>,
}

impl Uart {
    pub fn read(&self, offset: u32) -> u32 {
        match offset {
            0x00 => {
                let mut sr = 0;
                if self.holding.is_none() {
                    sr |= TXE;
                }
                if self.tc {
                    sr |= TC;
                }
                sr
            }
            0x08 => self.brr,
            0x0C => self.cr1,
            0x10 => self.cr2,
            0x14 => self.cr3,
            0x18 => self.gtpr,
            _ => 0,
        }
    }

    /// `byte_cycles`: core cycles per frame of 10 bits at the configured baud rate.
    pub fn write(&mut self, offset: u32, value: u32, now: u64, byte_cycles: u64, q: &mut Queue) {
        match offset {
            // TC is cleared by writing 0
            0x00 if value & TC == 0 => self.tc = false,
            0x04 => {
                if self.cr1 & (UE | TE) != UE | TE {
                    return; // transmitter off: the byte is lost
                }
                self.tc = false;
                let b = value as u8;
                if self.shifting.is_none() {
                    self.start(b, now, byte_cycles, q);
                } else {
                    self.holding = Some(b);
                }
            }
            0x08 => self.brr = value & 0xFFFF,
            0x0C => {
                self.cr1 = value;
                if value & TE != 0 && self.shifting.is_none() && self.holding.is_none() {
                    // enabling the transmitter sends an idle frame; TC ends up set
                    self.tc = true;
                }
            }
            0x10 => self.cr2 = value,
            0x14 => self.cr3 = value,
            0x18 => self.gtpr = value,
            _ => {}
        }
    }

    fn start(&mut self, b: u8, now: u64, byte_cycles: u64, q: &mut Queue) {
        self.shifting = Some(b);
        self.generation = self.generation.wrapping_add(1);
        q.schedule(
            now + byte_cycles,
            Event::UartShifted {
                generation: self.generation,
            },
        );
    }

    /// The shift register emptied.
    pub fn shifted(&mut self, generation: u32, now: u64, byte_cycles: u64, q: &mut Queue) {
        if generation != self.generation {
            return;
        }
        if let Some(b) = self.shifting.take() {
            self.sent.push((now, b));
        }
        match self.holding.take() {
            Some(b) => self.start(b, now, byte_cycles, q),
            None => self.tc = true,
        }
    }

    pub fn line_high(&self) -> bool {
        (self.holding.is_none() && self.cr1 & TXEIE != 0) || (self.tc && self.cr1 & TCIE != 0)
    }

    /// Core cycles per byte (start, 8 data, stop) at `sysclk` with the UART clocked by `pclk`:
    /// baud = pclk / BRR (16x oversampling, RM0090 30.6.3).
    pub fn byte_cycles(&self, sysclk: u64, pclk: u64) -> u64 {
        let brr = u64::from(self.brr.max(16));
        10 * brr * sysclk / pclk.max(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_bytes_back_to_back_at_38400_baud() {
        let mut u = Uart::default();
        let mut q = Queue::default();
        // 45 MHz / 38400 = 1171.875 → BRR 0x493 (mantissa 73, fraction 3)
        u.write(0x08, 0x493, 0, 0, &mut q);
        u.write(0x0C, UE | TE | TXEIE, 0, 0, &mut q);
        let cycles = u.byte_cycles(180_000_000, 45_000_000);
        assert_eq!(cycles, 46_840, "260.2 µs a byte: 38,430 baud");
        u.write(0x04, 0x78, 100, cycles, &mut q);
        assert_ne!(u.read(0) & TXE, 0, "moved straight to the shift register");
        u.write(0x04, 0x9A, 200, cycles, &mut q);
        assert_eq!(u.read(0) & TXE, 0, "held");
        assert!(!u.line_high());
        let (t, Event::UartShifted { generation }) = q.pop_due(u64::MAX).unwrap() else {
            panic!()
        };
        assert_eq!(t, 100 + cycles);
        u.shifted(generation, t, cycles, &mut q);
        assert!(u.line_high());
        let (t2, Event::UartShifted { generation }) = q.pop_due(u64::MAX).unwrap() else {
            panic!()
        };
        u.shifted(generation, t2, cycles, &mut q);
        assert_eq!(u.sent, vec![(t, 0x78), (t + cycles, 0x9A)]);
        assert_ne!(u.read(0) & TC, 0);
    }

    #[test]
    fn a_disabled_transmitter_loses_bytes() {
        let mut u = Uart::default();
        let mut q = Queue::default();
        u.write(0x04, 0x55, 0, 10, &mut q);
        assert_eq!(q.next_at(), u64::MAX);
        assert!(u.sent.is_empty());
    }
}

//! SysTick, the core's 24-bit down-counter (ARMv7-M ARM B3.3; PM0214 4.5). rtic-monotonics
//! counts its ticks through COUNTFLAG (set when the counter reaches 0, cleared by reading
//! CSR) and its interrupt.

use super::events::{Event, Queue};

const ENABLE: u32 = 1;
const TICKINT: u32 = 1 << 1;
const CLKSOURCE: u32 = 1 << 2;
const COUNTFLAG: u32 = 1 << 16;

#[derive(Clone, Debug, Default)]
pub struct SysTick {
    csr: u32,
    rvr: u32,
    /// Counter value while stopped.
    cvr: u32,
    /// Cycle at which a running counter next reaches 0.
    zero_at: u64,
    generation: u32,
}

impl SysTick {
    /// Core cycles per counter clock: the core clock, or the STM32's HCLK/8 reference.
    fn scale(&self) -> u64 {
        if self.csr & CLKSOURCE != 0 {
            1
        } else {
            8
        }
    }

    fn running(&self) -> bool {
        self.csr & ENABLE != 0
    }

    fn value(&self, now: u64) -> u32 {
        if self.running() {
            (self.zero_at.saturating_sub(now) / self.scale()) as u32 & 0xFF_FFFF
        } else {
            self.cvr
        }
    }

    fn reschedule(&mut self, now: u64, events: &mut Queue) {
        self.generation = self.generation.wrapping_add(1);
        if self.running() {
            // A counter at 0 reloads on the next clock, then counts RVR clocks down to 0.
            let clocks = if self.cvr == 0 {
                u64::from(self.rvr) + 1
            } else {
                u64::from(self.cvr)
            };
            self.zero_at = now + clocks * self.scale();
            events.schedule(
                self.zero_at,
                Event::SysTickWrap {
                    generation: self.generation,
                },
            );
        }
    }

    /// Reads CSR (clears COUNTFLAG), RVR, CVR or CALIB at `offset` from 0xE000_E010.
    pub fn read(&mut self, offset: u32, now: u64) -> u32 {
        match offset {
            0x0 => {
                let v = self.csr;
                self.csr &= !COUNTFLAG;
                v
            }
            0x4 => self.rvr,
            0x8 => self.value(now),
            // CALIB: no reference clock skew info; TENMS for HCLK/8 at 180 MHz (PM0214 4.5.4)
            0xC => 0x4000_0000 | 224_999,
            _ => 0,
        }
    }

    pub fn write(&mut self, offset: u32, value: u32, now: u64, events: &mut Queue) {
        match offset {
            0x0 => {
                let was = self.running();
                if was {
                    self.cvr = self.value(now);
                }
                self.csr = (self.csr & COUNTFLAG) | (value & (ENABLE | TICKINT | CLKSOURCE));
                if self.running() != was || self.running() {
                    self.reschedule(now, events);
                }
            }
            0x4 => self.rvr = value & 0xFF_FFFF,
            0x8 => {
                self.cvr = 0;
                self.csr &= !COUNTFLAG;
                self.reschedule(now, events);
            }
            _ => {}
        }
    }

    /// A scheduled wrap: returns whether the SysTick exception is to be pended.
    pub fn wrap(&mut self, generation: u32, events: &mut Queue) -> bool {
        if generation != self.generation || !self.running() {
            return false;
        }
        self.csr |= COUNTFLAG;
        self.zero_at += (u64::from(self.rvr) + 1) * self.scale();
        events.schedule(self.zero_at, Event::SysTickWrap { generation });
        self.csr & TICKINT != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_every_reload_plus_one_cycles_with_countflag() {
        let mut st = SysTick::default();
        let mut q = Queue::default();
        st.write(0x4, 179_999, 0, &mut q);
        st.write(0x8, 0, 0, &mut q);
        st.write(0x0, ENABLE | TICKINT | CLKSOURCE, 100, &mut q);
        assert_eq!(q.next_at(), 100 + 180_000);
        assert_eq!(st.read(0x8, 100 + 80_000), 100_000);
        assert_eq!(st.read(0x0, 1000) & COUNTFLAG, 0);
        let Some((t, Event::SysTickWrap { generation })) = q.pop_due(u64::MAX) else {
            panic!("a wrap");
        };
        assert!(st.wrap(generation, &mut q));
        assert_eq!(q.next_at(), t + 180_000);
        assert_ne!(st.read(0x0, t) & COUNTFLAG, 0);
        assert_eq!(st.read(0x0, t) & COUNTFLAG, 0, "cleared by the read");
    }

    #[test]
    fn disabling_cancels_the_scheduled_wrap() {
        let mut st = SysTick::default();
        let mut q = Queue::default();
        st.write(0x4, 999, 0, &mut q);
        st.write(0x0, ENABLE | TICKINT | CLKSOURCE, 0, &mut q);
        st.write(0x0, 0, 10, &mut q);
        let Some((_, Event::SysTickWrap { generation })) = q.pop_due(u64::MAX) else {
            panic!("the old event is still queued");
        };
        assert!(!st.wrap(generation, &mut q));
        assert_eq!(q.next_at(), u64::MAX);
    }
}

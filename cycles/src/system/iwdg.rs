//! The independent watchdog (RM0090 21): started by key 0xCCCC, reloaded by 0xAAAA, PR and RLR
//! writable after 0x5555; counts the ~32 kHz LSI down from RLR and resets the MCU at 0. The
//! LSI's real frequency is 17–47 kHz (datasheet); 32 kHz is used, a parameter.

use super::events::{Event, Queue};

pub const IWDG_BASE: u32 = 0x4000_3000;

#[derive(Clone, Debug)]
pub struct Iwdg {
    pr: u32,
    rlr: u32,
    unlocked: bool,
    running: bool,
    generation: u32,
    /// LSI frequency, Hz.
    pub lsi_hz: u64,
    /// Reloads since start, for reports.
    pub reloads: u64,
}

impl Default for Iwdg {
    fn default() -> Self {
        Iwdg {
            pr: 0,
            rlr: 0xFFF,
            unlocked: false,
            running: false,
            generation: 0,
            lsi_hz: 32_000,
            reloads: 0,
        }
    }
}

impl Iwdg {
    pub fn read(&self, offset: u32) -> u32 {
        match offset {
            0x04 => self.pr,
            0x08 => self.rlr,
            _ => 0, // SR: PVU, RVU clear (updates are immediate here)
        }
    }

    /// Core cycles from a reload to the reset at `sysclk`.
    pub fn timeout_cycles(&self, sysclk: u64) -> u64 {
        let ticks = u64::from(self.rlr + 1) * (4 << self.pr.min(6));
        ticks * sysclk / self.lsi_hz
    }

    fn reload(&mut self, now: u64, sysclk: u64, q: &mut Queue) {
        self.generation = self.generation.wrapping_add(1);
        q.schedule(
            now + self.timeout_cycles(sysclk),
            Event::WatchdogExpired {
                generation: self.generation,
            },
        );
    }

    pub fn write(&mut self, offset: u32, value: u32, now: u64, sysclk: u64, q: &mut Queue) {
        match offset {
            0x00 => match value & 0xFFFF {
                0xCCCC => {
                    self.running = true;
                    self.unlocked = false;
                    self.reload(now, sysclk, q);
                }
                0xAAAA => {
                    self.unlocked = false;
                    if self.running {
                        self.reloads += 1;
                        self.reload(now, sysclk, q);
                    }
                }
                0x5555 => self.unlocked = true,
                _ => self.unlocked = false,
            },
            0x04 if self.unlocked => self.pr = value & 7,
            0x08 if self.unlocked => self.rlr = value & 0xFFF,
            _ => {}
        }
    }

    /// Whether a scheduled expiry resets the MCU.
    pub fn expired(&self, generation: u32) -> bool {
        self.running && generation == self.generation
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resets_unless_reloaded_in_time() {
        let mut w = Iwdg::default();
        let mut q = Queue::default();
        w.write(0, 0x5555, 0, 180_000_000, &mut q);
        w.write(4, 2, 0, 180_000_000, &mut q); // /16
        w.write(8, 999, 0, 180_000_000, &mut q); // 1000 × 16 / 32 kHz = 0.5 s
        w.write(4, 6, 0, 180_000_000, &mut q);
        assert_eq!(w.read(4), 6, "still unlocked until the next key");
        w.write(0, 0xCCCC, 0, 180_000_000, &mut q);
        w.write(4, 2, 0, 180_000_000, &mut q);
        assert_eq!(w.read(4), 6, "locked by the start key");
        let t = w.timeout_cycles(180_000_000);
        assert_eq!(t, 1000 * 256 * 180_000_000 / 32_000);
        w.write(0, 0xAAAA, 1000, 180_000_000, &mut q);
        let (_, Event::WatchdogExpired { generation }) = q.pop_due(u64::MAX).unwrap() else {
            panic!()
        };
        assert!(!w.expired(generation), "reloaded since");
        let (at, Event::WatchdogExpired { generation }) = q.pop_due(u64::MAX).unwrap() else {
            panic!()
        };
        assert_eq!(at, 1000 + t);
        assert!(w.expired(generation));
    }
}

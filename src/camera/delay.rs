//! Busy-wait delays for the camera bring-up, counted in core clock cycles.
//!
//! Only for `init`-time waits (SCCB bit timing, sensor settle times), where no timer is running
//! yet and precision does not matter: `cortex_m::asm::delay(n)` waits **at least** `n` cycles. On
//! the Cortex-M4 its loop takes about 3 cycles per count, so the real waits are about 3x the
//! nominal ones (still well inside every limit: the waits here are minimums, and SCCB has no
//! minimum clock rate). Interrupts lengthen them further; `init` runs with interrupts masked.

/// Blocks for at least a given time, from the core clock frequency.
#[derive(Clone, Copy)]
pub struct CycleDelay {
    /// Core clock cycles per microsecond, rounded up (180 at 180 MHz).
    cycles_per_us: u32,
}

impl CycleDelay {
    /// A delay source for a core running at `sysclk_hz` (pass the frequency the clock
    /// configuration actually achieved, `clocks.sysclk()`, not the requested one).
    pub fn new(sysclk_hz: u32) -> Self {
        Self {
            cycles_per_us: sysclk_hz.div_ceil(1_000_000),
        }
    }

    /// Waits at least `us` microseconds.
    pub fn us(&self, us: u32) {
        cortex_m::asm::delay(us.saturating_mul(self.cycles_per_us));
    }

    /// Waits at least `ms` milliseconds.
    pub fn ms(&self, ms: u32) {
        for _ in 0..ms {
            self.us(1_000);
        }
    }
}

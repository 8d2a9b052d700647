//! The virtual board's clock: an event queue in CPU cycles.
//!
//! Peripherals schedule what happens next (a camera line, a UART byte leaving the shift
//! register, a SysTick wrap, the watchdog running out); the CPU runs until the earliest event,
//! which is then applied. Events at the same cycle are applied in the order they were scheduled.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Something that happens at a cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Event {
    /// SysTick reached zero (reloads, sets COUNTFLAG, pends its exception if enabled).
    SysTickWrap { generation: u32 },
    /// The IWDG counter reached zero: reset (unless reloaded since: `generation`).
    WatchdogExpired { generation: u32 },
    /// UART4 finished shifting out a byte.
    UartShifted { generation: u32 },
    /// The camera's VSYNC leaves its blanking level: frame `frame`'s lines follow.
    FrameStart { frame: u64 },
    /// The camera finished line `line` of the current frame (HREF falls).
    LineEnd { frame: u64, line: u16 },
    /// VSYNC enters its blanking level: the end of frame `frame`.
    FrameEnd { frame: u64 },
    /// The host reads the RTT buffers, as a probe polls them.
    RttPoll,
}

/// Events ordered by cycle, then by scheduling order.
#[derive(Default)]
pub struct Queue {
    heap: BinaryHeap<Reverse<(u64, u64, Event)>>,
    seq: u64,
}

impl Queue {
    pub fn schedule(&mut self, at: u64, event: Event) {
        self.seq += 1;
        self.heap.push(Reverse((at, self.seq, event)));
    }

    /// Cycle of the earliest event (`u64::MAX` when none).
    pub fn next_at(&self) -> u64 {
        self.heap.peek().map_or(u64::MAX, |Reverse((t, _, _))| *t)
    }

    /// The earliest event if it is due at `now`.
    pub fn pop_due(&mut self, now: u64) -> Option<(u64, Event)> {
        if self.next_at() <= now {
            self.heap.pop().map(|Reverse((t, _, e))| (t, e))
        } else {
            None
        }
    }

    pub fn clear(&mut self) {
        self.heap.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn earliest_first_then_scheduling_order() {
        let mut q = Queue::default();
        q.schedule(30, Event::RttPoll);
        q.schedule(10, Event::FrameEnd { frame: 1 });
        q.schedule(10, Event::FrameStart { frame: 2 });
        assert_eq!(q.next_at(), 10);
        assert_eq!(q.pop_due(9), None);
        assert_eq!(q.pop_due(10), Some((10, Event::FrameEnd { frame: 1 })));
        assert_eq!(q.pop_due(10), Some((10, Event::FrameStart { frame: 2 })));
        assert_eq!(q.pop_due(29), None);
        assert_eq!(q.pop_due(100), Some((30, Event::RttPoll)));
        assert_eq!(q.next_at(), u64::MAX);
    }
}

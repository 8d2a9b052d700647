//! What a run of the virtual board measured: the latency from a frame's completion to the first
//! motor byte, the CPU time per exception, frames and faults, as a plain-text table.

use std::fmt;

use super::board::{Board, ResetCause};
use crate::CLOCK_HZ;

/// One exception's share of the CPU.
#[derive(Clone, Debug, PartialEq)]
pub struct Load {
    /// Exception number (0: Thread mode, i.e. `init` and `idle` awake).
    pub exception: u16,
    /// The handler's symbol in the vector table (RTIC names bound tasks by their interrupt).
    pub name: String,
    pub cycles: u64,
}

/// The timing report of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    pub cycles: u64,
    /// Frames the sensor sent and the DCMI completed (FRAME).
    pub frames_sent: u64,
    pub frames_captured: u64,
    /// Telemetry records (one per frame perception finished).
    pub frames_processed: u64,
    /// Frame complete → first byte written to UART4's DR after it, ms, for the frames after the
    /// priming ones (after boot and after a stall) that found the link idle (every earlier byte out on the wire) and whose motor control sent
    /// something before the next frame completed.
    pub latency_ms: Vec<f64>,
    pub load: Vec<Load>,
    pub asleep: u64,
    /// Deepest stack since power-on, or since [`Board::repaint_stack`] (then `boot_stack_bytes`
    /// holds the boot's), bytes, interrupts nesting on tasks included.
    pub stack_bytes: u32,
    pub boot_stack_bytes: Option<u32>,
    pub overruns: u64,
    pub resets: Vec<(u64, ResetCause)>,
    /// Totals of the firmware's own once-a-second summary lines.
    pub dropped: u64,
    pub invalid: u64,
    pub misses: u64,
}

/// Sums a `key=` field over the firmware's `S …` summary lines.
pub fn summary_total(log: &str, key: &str) -> u64 {
    log.lines()
        .filter(|l| l.starts_with("S "))
        .filter_map(|l| {
            l.split(' ')
                .find_map(|f| f.strip_prefix(key)?.strip_prefix('='))
                .and_then(|v| v.parse::<u64>().ok())
        })
        .sum()
}

impl Report {
    pub fn of(board: &Board) -> Report {
        let log = board.log();
        let writes = &log.uart_writes;
        let sent = board.uart_sent();
        let frames = &log.frames_captured;
        let mut latency_ms = Vec::new();
        // the first frames after boot or after a stall only prime the model (their step is a
        // fraction of a frame's): not the escape path's latency
        let primed = alvs_tasks::robot::health::PRIME_FRAMES as usize;
        let stall = u64::from(alvs_tasks::robot::health::STALL_MS) * CLOCK_HZ / 1000;
        let mut since_gap = 0;
        for (i, &(t, _)) in frames.iter().enumerate() {
            let gap = i == 0 || t - frames[i - 1].0 >= stall;
            since_gap = if gap { 1 } else { since_gap + 1 };
            if since_gap <= primed {
                continue;
            }
            let next = frames.get(i + 1).map_or(u64::MAX, |f| f.0);
            let first = writes.partition_point(|&(w, _)| w < t);
            let out = sent.partition_point(|&(s, _)| s <= t);
            if out < first {
                continue; // bytes of an earlier frame still queued or on the wire
            }
            if let Some(&(w, _)) = writes.get(first) {
                if w < next {
                    latency_ms.push((w - t) as f64 * 1e3 / CLOCK_HZ as f64);
                }
            }
        }
        let load = log
            .load
            .iter()
            .enumerate()
            .filter(|(_, &c)| c > 0)
            .map(|(e, &c)| {
                let exception = e as u16;
                let cycles = if e == 0 {
                    c.saturating_sub(log.asleep)
                } else {
                    c
                };
                Load {
                    exception,
                    name: board.exception_name(exception),
                    cycles,
                }
            })
            .collect();
        let text = board.rtt(0);
        Report {
            cycles: board.now(),
            frames_sent: log.frames_sent,
            frames_captured: frames.len() as u64,
            frames_processed: board.rtt(1).lines().filter(|l| l.starts_with("F ")).count() as u64,
            latency_ms,
            load,
            asleep: log.asleep,
            stack_bytes: board.stack_high_water().unwrap_or(0),
            boot_stack_bytes: None,
            overruns: board.dcmi_overruns(),
            resets: log.resets.clone(),
            dropped: summary_total(text, "dropped"),
            invalid: summary_total(text, "invalid"),
            misses: summary_total(text, "misses"),
        }
    }

    /// (min, mean, max) of the latency, ms.
    pub fn latency(&self) -> Option<(f64, f64, f64)> {
        let l = &self.latency_ms;
        if l.is_empty() {
            return None;
        }
        let min = l.iter().copied().fold(f64::MAX, f64::min);
        let max = l.iter().copied().fold(0.0, f64::max);
        Some((min, l.iter().sum::<f64>() / l.len() as f64, max))
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let secs = self.cycles as f64 / CLOCK_HZ as f64;
        writeln!(
            f,
            "virtual board: {secs:.2} s simulated ({} cycles at 180 MHz)",
            self.cycles
        )?;
        writeln!(
            f,
            "frames: sent {}, captured {}, processed {}; firmware counted dropped {}, invalid {}, over budget {}; DCMI overruns {}",
            self.frames_sent,
            self.frames_captured,
            self.frames_processed,
            self.dropped,
            self.invalid,
            self.misses,
            self.overruns
        )?;
        match self.boot_stack_bytes {
            Some(boot) => writeln!(
                f,
                "stack: {} B at its deepest while running (tasks and nested interrupts), {boot} B at boot (init and its self-benchmark)",
                self.stack_bytes
            )?,
            None => writeln!(
                f,
                "stack: {} B at its deepest (every task and nested interrupt since power-on)",
                self.stack_bytes
            )?,
        }
        match self.latency() {
            Some((min, mean, max)) => writeln!(
                f,
                "frame complete -> first motor byte: min {min:.2} ms, mean {mean:.2} ms, max {max:.2} ms over {} frames",
                self.latency_ms.len()
            )?,
            None => writeln!(f, "frame complete -> first motor byte: no motor byte followed a frame")?,
        }
        for (t, cause) in &self.resets {
            writeln!(
                f,
                "reset ({cause:?}) at {:.3} s",
                *t as f64 / CLOCK_HZ as f64
            )?;
        }
        writeln!(f, "CPU load:")?;
        let pct = |c: u64| 100.0 * c as f64 / self.cycles.max(1) as f64;
        for l in &self.load {
            writeln!(
                f,
                "  {:>3} {:<48} {:>12} cycles {:>6.2} %",
                l.exception,
                l.name,
                l.cycles,
                pct(l.cycles)
            )?;
        }
        writeln!(
            f,
            "      {:<48} {:>12} cycles {:>6.2} %",
            "asleep (WFI)",
            self.asleep,
            pct(self.asleep)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_totals_add_the_seconds() {
        let log = "S 1 frames=30 dropped=2 misses=0\nF 3 x\nS 2 frames=30 dropped=1 misses=1\n";
        assert_eq!(summary_total(log, "dropped"), 3);
        assert_eq!(summary_total(log, "frames"), 60);
        assert_eq!(summary_total(log, "misses"), 1);
        assert_eq!(summary_total(log, "nothing"), 0);
    }
}

//! Health of the running firmware: the 1 Hz summary on RTT channel 0, and the safety policy
//! that decides whether the motors may run and whether the independent watchdog is fed.
//!
//! Both are plain state machines over counters and timestamps: the firmware feeds them events
//! and the time (`u32` milliseconds since boot from the monotonic timer, compared with
//! wrapping arithmetic so the 49.7-day roll-over is harmless) and acts on what they return.
//!
//! # Summary line
//!
//! ```text
//! S 12 frames=30 processed=29 dropped=1 invalid=0 overruns=0 sync=0 cycles=1401234/1650000/1900321 misses=0 rtt_dropped=0
//! ```
//!
//! second 12 since boot; in that second the camera ended 30 frames, perception processed 29,
//! one was dropped because perception was busy, none invalid, no DCMI overrun or sync error;
//! per-frame CPU cycles min/mean/max (`cycles=-` without frames); frames over the
//! [`FRAME_BUDGET_CYCLES`] budget; telemetry records lost because the host was not reading.
//! Integers only: the firmware formats no float.
//!
//! # Safety policy ([`Safety`])
//!
//! - Motors stay disabled until [`PRIME_FRAMES`] frames went through perception (the first
//!   frame only primes the retina, the next ones fill the ON/OFF maps and their delayed
//!   copies), and again after any fault clears.
//! - The watchdog is fed only when perception finished a frame since the last feed.
//! - No frame for [`STALL_MS`] → [`Fault::CameraStall`], motors stopped, until frames return.
//! - [`OVERRUN_BURST`] overruns within [`OVERRUN_WINDOW_MS`] → [`Fault::OverrunBurst`], motors
//!   stopped, until a whole window passes without overrun.
//! - The panic flag → [`Fault::Panic`], motors stopped and the watchdog starved, for good.
//! - A hold ([`Safety::hold`]: `h`, or anything but `g`, typed on RTT down channel 0,
//!   "control"; `g` alone releases it, [`console_command`]) stops the motors without a fault:
//!   perception and the FSM run on, and the FSM is told its commands are not carried out. The
//!   evasion protocol's "stand until the first alert", and a stop switch for whoever holds the
//!   robot while a probe is attached. A reset (watchdog, panic) forgets it: the robot drives
//!   again once primed.

use crate::model::fsm::Behaviour;
use crate::robot::camera::Counters;
use crate::robot::line::{self, LineError};
use core::fmt::{self, Write};

/// CPU clock, Hz: HSE 25 MHz through the PLL (M 25, N 360, P 2). From public firmware;
/// verify at bring-up.
pub const CPU_HZ: u32 = 180_000_000;

/// Per-frame cycle budget: one camera frame period (≈ 33.3 ms at 30 fps) at [`CPU_HZ`]. A
/// frame that takes more is a deadline miss: the next frame is already waiting.
pub const FRAME_BUDGET_CYCLES: u32 = 6_000_000;

// The budget is at most one frame period at 30 fps.
const _: () = assert!(FRAME_BUDGET_CYCLES <= CPU_HZ / 30);

/// Period of the summary line, ms.
pub const SUMMARY_PERIOD_MS: u32 = 1000;

/// Frames perception must process before the motors may run. Frame 0 only primes the retina
/// (no motion signal), frame 1 has ON/OFF maps but zero delayed maps, frame 2 is the first
/// with a real delayed copy: 3 frames (100 ms) is the least that gives the FSM a meaningful
/// input.
pub const PRIME_FRAMES: u32 = 3;

const _: () = assert!(PRIME_FRAMES >= 2);

/// No processed frame for this long (3 frame periods) is a camera stall, ms.
pub const STALL_MS: u32 = 100;

/// Overruns within [`OVERRUN_WINDOW_MS`] that stop the motors: one is a glitch (the frame is
/// discarded), several in a second mean the capture path is overloaded and perception sees
/// frames with gaps.
pub const OVERRUN_BURST: usize = 3;

const _: () = assert!(OVERRUN_BURST >= 1);

/// Window of [`OVERRUN_BURST`], and the quiet time that clears the fault, ms.
pub const OVERRUN_WINDOW_MS: u32 = 1000;

/// Suggested independent-watchdog timeout, ms: longer than [`STALL_MS`] plus a worst frame,
/// so a stall stops the motors and reaches the RTT log before the watchdog resets the MCU.
pub const WATCHDOG_TIMEOUT_MS: u32 = 500;

const _: () = assert!(WATCHDOG_TIMEOUT_MS > STALL_MS + 2 * 34);

/// Cycle statistics of the frames in one summary period.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CycleStats {
    frames: u32,
    min: u32,
    max: u32,
    sum: u64,
    misses: u32,
}

impl CycleStats {
    /// No frames yet.
    pub const fn new() -> Self {
        CycleStats {
            frames: 0,
            min: 0,
            max: 0,
            sum: 0,
            misses: 0,
        }
    }

    /// One processed frame that took `cycles` CPU cycles.
    pub fn record(&mut self, cycles: u32) {
        if self.frames == 0 {
            self.min = cycles;
            self.max = cycles;
        } else {
            self.min = self.min.min(cycles);
            self.max = self.max.max(cycles);
        }
        self.frames = self.frames.saturating_add(1);
        self.sum = self.sum.saturating_add(u64::from(cycles));
        if cycles > FRAME_BUDGET_CYCLES {
            self.misses = self.misses.saturating_add(1);
        }
    }

    /// Frames recorded.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Frames over [`FRAME_BUDGET_CYCLES`].
    pub fn misses(&self) -> u32 {
        self.misses
    }

    /// `(min, mean, max)` cycles, the mean rounded down; `None` without frames.
    pub fn min_mean_max(&self) -> Option<(u32, u32, u32)> {
        let n = u64::from(self.frames);
        // mean ≤ max ≤ u32::MAX, so the conversion cannot fail
        let mean = u32::try_from(self.sum.checked_div(n)?).unwrap_or(u32::MAX);
        Some((self.min, mean, self.max))
    }
}

/// One period's numbers, as printed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Summary {
    /// Summary number = seconds since boot (1 for the first).
    pub second: u32,
    /// Camera frames that ended (valid or not).
    pub frames: u32,
    /// Frames perception processed.
    pub processed: u32,
    /// Frames dropped because perception was busy.
    pub dropped: u32,
    /// Frames discarded as invalid (overrun, sync error, wrong line count).
    pub invalid: u32,
    /// DCMI overruns.
    pub overruns: u32,
    /// DCMI sync errors.
    pub sync_errors: u32,
    /// `(min, mean, max)` cycles per processed frame.
    pub cycles: Option<(u32, u32, u32)>,
    /// Processed frames over [`FRAME_BUDGET_CYCLES`].
    pub misses: u32,
    /// Telemetry records lost on RTT.
    pub rtt_dropped: u32,
}

/// Longest summary line, `'\n'` included: `"S "` and 9 `" key="` prefixes with u32 values
/// (10 digits each), `cycles` with three of them.
pub const SUMMARY_LINE_CAP: usize = 2
    + 10
    + " frames=".len()
    + " processed=".len()
    + " dropped=".len()
    + " invalid=".len()
    + " overruns=".len()
    + " sync=".len()
    + " cycles=".len()
    + " misses=".len()
    + " rtt_dropped=".len()
    + 8 * 10
    + 3 * 10
    + 2
    + 1;

impl Summary {
    /// Writes the line with its trailing `'\n'`, integers only.
    pub fn write_line<W: Write>(&self, w: &mut W) -> fmt::Result {
        write!(
            w,
            "S {} frames={} processed={} dropped={} invalid={} overruns={} sync={} cycles=",
            self.second,
            self.frames,
            self.processed,
            self.dropped,
            self.invalid,
            self.overruns,
            self.sync_errors
        )?;
        match self.cycles {
            Some((lo, mean, hi)) => write!(w, "{lo}/{mean}/{hi}")?,
            None => w.write_char('-')?,
        }
        writeln!(
            w,
            " misses={} rtt_dropped={}",
            self.misses, self.rtt_dropped
        )
    }

    /// The line in a fixed buffer; never truncated (see [`SUMMARY_LINE_CAP`]).
    pub fn to_line(&self) -> heapless::String<SUMMARY_LINE_CAP> {
        let mut s = heapless::String::new();
        // Cannot fail: SUMMARY_LINE_CAP bounds every line (tested).
        let _ = self.write_line(&mut s);
        s
    }

    /// Parses a line [`Summary::write_line`] wrote (the terminator is optional): every field
    /// in order, canonical decimals, `cycles` as `-` or `min/mean/max` in that order. Anything
    /// else is an error, so a host never counts a corrupted line. Never panics.
    pub fn parse_line(s: &str) -> Result<Summary, LineError> {
        let mut t = line::bare(s).split(' ');
        if t.next() != Some("S") {
            return Err(LineError::OtherLine);
        }
        let second = line::number(&mut t, "S")?;
        let mut field = |key: &'static str| {
            let v = line::tagged(&mut t, key).ok_or(LineError::Missing(key))?;
            Ok::<&str, LineError>(v)
        };
        let num =
            |v: &str, key: &'static str| line::canonical_u32(v).ok_or(LineError::BadNumber(key));
        let frames = num(field("frames=")?, "frames=")?;
        let processed = num(field("processed=")?, "processed=")?;
        let dropped = num(field("dropped=")?, "dropped=")?;
        let invalid = num(field("invalid=")?, "invalid=")?;
        let overruns = num(field("overruns=")?, "overruns=")?;
        let sync_errors = num(field("sync=")?, "sync=")?;
        let cycles = match field("cycles=")? {
            "-" => None,
            v => {
                let mut parts = v.split('/');
                let mut next = || num(parts.next().unwrap_or(""), "cycles=");
                let c = (next()?, next()?, next()?);
                if parts.next().is_some() {
                    return Err(LineError::BadNumber("cycles="));
                }
                if !(c.0 <= c.1 && c.1 <= c.2) {
                    return Err(LineError::Inconsistent("cycles="));
                }
                Some(c)
            }
        };
        let misses = num(field("misses=")?, "misses=")?;
        let rtt_dropped = num(field("rtt_dropped=")?, "rtt_dropped=")?;
        line::end(&mut t)?;
        if (cycles.is_none() && processed > 0) || (cycles.is_some() && processed == 0) {
            return Err(LineError::Inconsistent("cycles="));
        }
        if misses > processed {
            return Err(LineError::Inconsistent("misses="));
        }
        Ok(Summary {
            second,
            frames,
            processed,
            dropped,
            invalid,
            overruns,
            sync_errors,
            cycles,
            misses,
            rtt_dropped,
        })
    }
}

/// Accumulates one summary period: cycle statistics from the perception task, differences of
/// the hand-off's running [`Counters`] and of the RTT loss count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SummaryWindow {
    second: u32,
    last: Counters,
    last_rtt_dropped: u32,
    cycles: CycleStats,
}

impl SummaryWindow {
    /// Starts at boot (all totals 0).
    pub const fn new() -> Self {
        SummaryWindow {
            second: 0,
            last: Counters::ZERO,
            last_rtt_dropped: 0,
            cycles: CycleStats::new(),
        }
    }

    /// Perception processed a frame in `cycles` CPU cycles.
    pub fn record_frame(&mut self, cycles: u32) {
        self.cycles.record(cycles);
    }

    /// Ends the period: the numbers since the previous call, given the running totals now.
    pub fn close(&mut self, totals: Counters, rtt_dropped_total: u32) -> Summary {
        let d = |now: u32, before: u32| now.wrapping_sub(before);
        let l = self.last;
        self.second = self.second.wrapping_add(1);
        let s = Summary {
            second: self.second,
            frames: d(totals.completed, l.completed),
            processed: self.cycles.frames(),
            dropped: d(totals.dropped, l.dropped),
            invalid: d(totals.invalidated, l.invalidated),
            overruns: d(totals.overruns, l.overruns),
            sync_errors: d(totals.sync_errors, l.sync_errors),
            cycles: self.cycles.min_mean_max(),
            misses: self.cycles.misses(),
            rtt_dropped: d(rtt_dropped_total, self.last_rtt_dropped),
        };
        self.last = totals;
        self.last_rtt_dropped = rtt_dropped_total;
        self.cycles = CycleStats::new();
        s
    }
}

/// Why the motors are stopped although the model is primed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// No processed frame for [`STALL_MS`]: the camera stopped, or perception hangs.
    CameraStall,
    /// [`OVERRUN_BURST`] DCMI overruns within [`OVERRUN_WINDOW_MS`].
    OverrunBurst,
    /// The panic flag is set.
    Panic,
}

impl Fault {
    /// Short name for the RTT log.
    pub const fn name(self) -> &'static str {
        match self {
            Fault::CameraStall => "camera stall",
            Fault::OverrunBurst => "overrun burst",
            Fault::Panic => "panic",
        }
    }
}

/// What the firmware does now.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Decision {
    /// Reload the independent watchdog.
    pub feed_watchdog: bool,
    /// The motors may follow the FSM; otherwise send stop frames.
    pub motors_enabled: bool,
    /// The active fault, if any (highest priority: panic, overrun burst, stall).
    pub fault: Option<Fault>,
}

/// The safety policy (see the module docs).
///
/// Call [`Safety::frame`] when perception finished a frame, [`Safety::overrun`] on each DCMI
/// overrun, and [`Safety::tick`] periodically *independently of frames* (e.g. the motor task
/// waiting for a frame with a 10–20 ms timeout), else a stall is never noticed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Safety {
    primed: u32,
    last_frame: Option<u32>,
    progress: bool,
    stalled: bool,
    overrun_at: [u32; OVERRUN_BURST],
    overruns: usize,
    burst: bool,
    panicked: bool,
    held: bool,
}

/// What a line typed on the RTT control channel asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConsoleCommand {
    /// Stop the motors ([`Safety::hold`]).
    Hold,
    /// Let them go again.
    Go,
    /// Switch the motor-control task's behaviour (escape or the swarm's spin), keeping the
    /// hold as it is.
    Mode(Behaviour),
}

/// The command the bytes typed on the RTT control channel ask for, failing safe: `g` alone
/// (either case, around whitespace) lets go, `s` alone switches to the swarm's behaviour, `e`
/// alone back to escape; anything else typed holds, so a mistyped or longer word ("stop",
/// "going") stops the motors rather than starting them; nothing typed (or only whitespace)
/// changes nothing.
pub fn console_command(bytes: &[u8]) -> Option<ConsoleCommand> {
    match bytes.trim_ascii() {
        [] => None,
        [b'g' | b'G'] => Some(ConsoleCommand::Go),
        [b's' | b'S'] => Some(ConsoleCommand::Mode(Behaviour::Swarm)),
        [b'e' | b'E'] => Some(ConsoleCommand::Mode(Behaviour::Escape)),
        _ => Some(ConsoleCommand::Hold),
    }
}

impl Safety {
    /// At boot: not primed, no fault, nothing to feed. The stall rule is armed by the first
    /// frame (a camera that never starts is reported by its ID check, not as a stall).
    pub const fn new() -> Self {
        Safety {
            primed: 0,
            last_frame: None,
            progress: false,
            stalled: false,
            overrun_at: [0; OVERRUN_BURST],
            overruns: 0,
            burst: false,
            panicked: false,
            held: false,
        }
    }

    /// Holds the motors stopped (`true`) or lets them follow the FSM again; whether that
    /// changed anything.
    pub fn hold(&mut self, on: bool) -> bool {
        let changed = self.held != on;
        self.held = on;
        changed
    }

    /// Whether the motors may follow the FSM: primed, no fault, not held.
    pub fn motors_allowed(&self) -> bool {
        self.fault().is_none() && self.primed() && !self.held
    }

    /// Perception finished a frame at `now_ms`.
    ///
    /// A frame after a gap of [`STALL_MS`] or more (noticed by [`Safety::tick`] or not)
    /// restarts priming; frames during an overrun burst or after a panic do not count toward
    /// it. The perception task should `Network::reset()` when a fault appears, so that the
    /// model primes again together with this count.
    pub fn frame(&mut self, now_ms: u32) {
        let gap = self
            .last_frame
            .is_some_and(|t| now_ms.wrapping_sub(t) >= STALL_MS);
        if gap || self.stalled {
            self.primed = 0;
        }
        self.stalled = false;
        self.last_frame = Some(now_ms);
        self.progress = true;
        if !self.burst && !self.panicked {
            self.primed = self.primed.saturating_add(1);
        }
    }

    /// A DCMI overrun at `now_ms`.
    pub fn overrun(&mut self, now_ms: u32) {
        self.overrun_at.rotate_left(1);
        if let Some(last) = self.overrun_at.last_mut() {
            *last = now_ms;
        }
        self.overruns = self.overruns.saturating_add(1).min(OVERRUN_BURST);
        let oldest = self.overrun_at[0];
        if self.overruns == OVERRUN_BURST && now_ms.wrapping_sub(oldest) < OVERRUN_WINDOW_MS {
            self.burst = true;
            self.primed = 0;
        }
    }

    /// The panic flag: motors off and watchdog starved from now on.
    pub fn panic(&mut self) {
        self.panicked = true;
        self.primed = 0;
    }

    /// Applies the time rules at `now_ms` and says what to do; feeding clears the progress.
    pub fn tick(&mut self, now_ms: u32) -> Decision {
        if let Some(t) = self.last_frame {
            if !self.stalled && now_ms.wrapping_sub(t) >= STALL_MS {
                self.stalled = true;
                self.primed = 0;
            }
        }
        if self.burst {
            let last = self.overrun_at[OVERRUN_BURST - 1];
            if now_ms.wrapping_sub(last) >= OVERRUN_WINDOW_MS {
                self.burst = false;
                self.overruns = 0;
            }
        }
        let feed = self.progress && !self.panicked;
        if feed {
            self.progress = false;
        }
        Decision {
            feed_watchdog: feed,
            motors_enabled: self.motors_allowed(),
            fault: self.fault(),
        }
    }

    /// The active fault, as of the last event or tick.
    pub fn fault(&self) -> Option<Fault> {
        if self.panicked {
            Some(Fault::Panic)
        } else if self.burst {
            Some(Fault::OverrunBurst)
        } else if self.stalled {
            Some(Fault::CameraStall)
        } else {
            None
        }
    }

    /// [`PRIME_FRAMES`] frames processed since boot or the last fault.
    pub fn primed(&self) -> bool {
        self.primed >= PRIME_FRAMES
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use std::string::{String, ToString};

    #[test]
    fn budget_is_one_frame_at_180_mhz() {
        // 6.0 M cycles / 180 MHz = 33.3 ms = one frame at 30 fps
        assert_eq!(FRAME_BUDGET_CYCLES / (CPU_HZ / 1000), 33);
    }

    #[test]
    fn cycle_stats_min_mean_max_and_misses() {
        let mut c = CycleStats::new();
        assert_eq!(c.min_mean_max(), None);
        for x in [1_500_000, 1_000_000, 6_000_000, 6_000_001] {
            c.record(x);
        }
        // mean = 14_500_001 / 4 = 3_625_000 (rounded down); only > budget is a miss
        assert_eq!(c.min_mean_max(), Some((1_000_000, 3_625_000, 6_000_001)));
        assert_eq!((c.frames(), c.misses()), (4, 1));
        let mut c = CycleStats::new();
        c.record(u32::MAX);
        c.record(u32::MAX);
        assert_eq!(c.min_mean_max(), Some((u32::MAX, u32::MAX, u32::MAX)));
    }

    fn totals(c: u32, dr: u32, i: u32, o: u32, s: u32) -> Counters {
        Counters {
            completed: c,
            delivered: c - dr - i,
            dropped: dr,
            invalidated: i,
            overruns: o,
            sync_errors: s,
        }
    }

    #[test]
    fn summary_reports_the_last_second_only() {
        let mut w = SummaryWindow::new();
        for x in [1_401_234, 1_900_321, 1_650_000] {
            w.record_frame(x);
        }
        let s = w.close(totals(30, 1, 0, 0, 0), 0);
        assert_eq!(
            s.to_line().as_str(),
            "S 1 frames=30 processed=3 dropped=1 invalid=0 overruns=0 sync=0 \
             cycles=1401234/1650518/1900321 misses=0 rtt_dropped=0\n"
        );
        // second 2: differences of the totals, and a deadline miss
        w.record_frame(7_000_000);
        let s = w.close(totals(61, 2, 3, 4, 1), 17);
        assert_eq!(
            s.to_line().as_str(),
            "S 2 frames=31 processed=1 dropped=1 invalid=3 overruns=4 sync=1 \
             cycles=7000000/7000000/7000000 misses=1 rtt_dropped=17\n"
        );
        let s = w.close(totals(61, 2, 3, 4, 1), 17);
        assert_eq!(
            s.to_line().as_str(),
            "S 3 frames=0 processed=0 dropped=0 invalid=0 overruns=0 sync=0 cycles=- \
             misses=0 rtt_dropped=0\n"
        );
    }

    #[test]
    fn summary_differences_survive_counter_wrap() {
        let mut w = SummaryWindow::new();
        let mut t = Counters {
            completed: u32::MAX - 4,
            ..Counters::default()
        };
        w.close(t, u32::MAX);
        t.completed = 25;
        let s = w.close(t, 2);
        assert_eq!((s.frames, s.rtt_dropped), (30, 3));
    }

    #[test]
    fn the_longest_line_fits() {
        let s = Summary {
            second: u32::MAX,
            frames: u32::MAX,
            processed: u32::MAX,
            dropped: u32::MAX,
            invalid: u32::MAX,
            overruns: u32::MAX,
            sync_errors: u32::MAX,
            cycles: Some((u32::MAX, u32::MAX, u32::MAX)),
            misses: u32::MAX,
            rtt_dropped: u32::MAX,
        };
        let line = s.to_line();
        assert_eq!(line.len(), SUMMARY_LINE_CAP);
        assert!(line.ends_with(" rtt_dropped=4294967295\n"));
    }

    #[test]
    fn summary_lines_parse_back() {
        let mut w = SummaryWindow::new();
        w.record_frame(1_401_234);
        w.record_frame(7_000_000);
        let busy = w.close(totals(30, 1, 2, 3, 4), 5);
        let idle = w.close(totals(30, 1, 2, 3, 4), 5);
        for s in [busy, idle] {
            let line = s.to_line();
            assert_eq!(Summary::parse_line(&line), Ok(s));
            assert_eq!(Summary::parse_line(line.trim_end()), Ok(s));
        }
        let ok = "S 1 frames=30 processed=3 dropped=1 invalid=0 overruns=0 sync=0 cycles=1/2/3 misses=0 rtt_dropped=0";
        assert!(Summary::parse_line(ok).is_ok());
        use LineError::*;
        let cases: [(String, LineError); 12] = [
            ("F 1 st=wander".into(), OtherLine),
            ("S".into(), Missing("S")),
            ("S 01 frames=30".into(), BadNumber("S")),
            ("S 1 frames=30 processed=3".into(), Missing("dropped=")),
            (ok.replace("sync=0", "sync=x"), BadNumber("sync=")),
            (ok.replace("1/2/3", "1/2"), BadNumber("cycles=")),
            (ok.replace("1/2/3", "1/2/3/4"), BadNumber("cycles=")),
            (ok.replace("1/2/3", "3/2/1"), Inconsistent("cycles=")),
            (ok.replace("1/2/3", "-"), Inconsistent("cycles=")),
            (ok.replace("misses=0", "misses=4"), Inconsistent("misses=")),
            (ok.replace(" rtt_dropped=0", ""), Missing("rtt_dropped=")),
            (ok.to_string() + " x", TrailingData),
        ];
        for (line, err) in cases {
            assert_eq!(Summary::parse_line(&line), Err(err), "{line}");
        }
    }

    const T0: u32 = 1_000;

    /// Safety primed with frames every 33 ms from `t0`; returns the time of the last frame.
    fn primed(t0: u32) -> (Safety, u32) {
        let mut s = Safety::new();
        let mut t = t0;
        for i in 0..PRIME_FRAMES {
            t = t0.wrapping_add(33 * i);
            s.frame(t);
        }
        (s, t)
    }

    #[test]
    fn motors_wait_for_the_priming_frames() {
        let mut s = Safety::new();
        let d = s.tick(0);
        assert_eq!(
            d,
            Decision {
                feed_watchdog: false,
                motors_enabled: false,
                fault: None
            }
        );
        // no stall before the first frame, however long the camera takes
        assert_eq!(s.tick(5_000).fault, None);
        s.frame(T0);
        assert!(!s.tick(T0).motors_enabled);
        s.frame(T0 + 33);
        assert!(!s.tick(T0 + 33).motors_enabled);
        s.frame(T0 + 66);
        assert!(s.tick(T0 + 66).motors_enabled);
    }

    #[test]
    fn watchdog_is_fed_only_after_progress() {
        let (mut s, t) = primed(T0);
        assert!(s.tick(t).feed_watchdog);
        // no frame since the last feed: no feed, even well before a stall
        assert!(!s.tick(t + 10).feed_watchdog);
        assert!(!s.tick(t + 20).feed_watchdog);
        s.frame(t + 33);
        assert!(s.tick(t + 33).feed_watchdog);
        assert!(!s.tick(t + 34).feed_watchdog);
        // two frames between ticks: one feed
        s.frame(t + 66);
        s.frame(t + 99);
        assert!(s.tick(t + 100).feed_watchdog);
        assert!(!s.tick(t + 101).feed_watchdog);
    }

    #[test]
    fn no_frame_for_100_ms_stalls_and_stops() {
        let (mut s, t) = primed(T0);
        assert!(s.tick(t + 99).motors_enabled);
        let d = s.tick(t + 100);
        assert_eq!(
            d,
            Decision {
                feed_watchdog: false,
                motors_enabled: false,
                fault: Some(Fault::CameraStall)
            }
        );
        assert_eq!(s.tick(t + 150).fault, Some(Fault::CameraStall));
        // frames return: the fault clears, priming starts over
        s.frame(t + 200);
        let d = s.tick(t + 200);
        assert_eq!(
            d,
            Decision {
                feed_watchdog: true,
                motors_enabled: false,
                fault: None
            }
        );
        s.frame(t + 233);
        s.frame(t + 266);
        assert!(s.tick(t + 266).motors_enabled);
    }

    #[test]
    fn a_gap_not_seen_by_tick_still_restarts_priming() {
        let (mut s, t) = primed(T0);
        s.frame(t + 150);
        assert!(!s.tick(t + 150).motors_enabled);
    }

    #[test]
    fn time_wraps_without_false_stalls() {
        let (mut s, t) = primed(u32::MAX - 40);
        // the last frame was at u32::MAX - 40 + 66 = 25 after the wrap
        assert_eq!(t, 25);
        assert!(s.tick(29).motors_enabled);
        s.frame(58);
        assert!(s.tick(157).motors_enabled);
        assert_eq!(s.tick(158).fault, Some(Fault::CameraStall));
    }

    /// Frames (each followed by a tick) every 33 ms from `from` while `<= to`; the last
    /// decision.
    fn run(s: &mut Safety, from: u32, to: u32) -> Decision {
        let mut now = from;
        let mut d = s.tick(from);
        while now <= to {
            s.frame(now);
            d = s.tick(now);
            now += 33;
        }
        d
    }

    #[test]
    fn an_overrun_burst_stops_until_a_quiet_window() {
        let (mut s, t) = primed(T0);
        // two overruns within a second are glitches
        s.overrun(t);
        s.overrun(t + 500);
        let d = run(&mut s, t + 33, t + 990);
        assert!(d.motors_enabled && d.fault.is_none());
        // a third within 1000 ms of the first: stop
        s.overrun(t + 999);
        let d = s.tick(t + 999);
        assert_eq!(
            (d.motors_enabled, d.fault),
            (false, Some(Fault::OverrunBurst))
        );
        // frames keep coming (and feed the watchdog) but do not prime during the burst
        let mut now = t + 1023;
        while now < t + 1999 {
            s.frame(now);
            let d = s.tick(now);
            assert!(d.feed_watchdog && !d.motors_enabled, "{now}");
            assert_eq!(d.fault, Some(Fault::OverrunBurst));
            now += 33;
        }
        // the burst clears one window after the last overrun; then priming again
        let d = s.tick(t + 1999);
        assert_eq!((d.motors_enabled, d.fault), (false, None));
        let d = run(&mut s, t + 2013, t + 2046);
        assert!(!d.motors_enabled);
        let d = run(&mut s, t + 2079, t + 2079);
        assert!(d.motors_enabled);
        // one overrun every 600 ms never makes a burst
        for k in 0..10 {
            let start = t + 2112 + 600 * k;
            s.overrun(start);
            let d = run(&mut s, start, start + 599);
            assert!(d.motors_enabled && d.fault.is_none(), "{k}");
        }
    }

    #[test]
    fn panic_latches() {
        let (mut s, t) = primed(T0);
        s.panic();
        s.frame(t + 33);
        let d = s.tick(t + 33);
        assert_eq!(
            d,
            Decision {
                feed_watchdog: false,
                motors_enabled: false,
                fault: Some(Fault::Panic)
            }
        );
        for k in 2..10 {
            s.frame(t + 33 * k);
            assert_eq!(s.tick(t + 33 * k).fault, Some(Fault::Panic));
        }
        // panic outranks the other faults
        s.overrun(t + 400);
        s.overrun(t + 401);
        s.overrun(t + 402);
        assert_eq!(s.tick(t + 1000).fault, Some(Fault::Panic));
        assert_eq!(Fault::Panic.name(), "panic");
    }

    #[test]
    fn a_hold_stops_the_motors_without_a_fault_until_released() {
        let (mut s, t) = primed(T0);
        assert!(s.motors_allowed());
        assert!(s.hold(true), "a change");
        assert!(!s.hold(true), "no change");
        let d = run(&mut s, t + 33, t + 500);
        assert_eq!(
            d,
            Decision {
                feed_watchdog: true,
                motors_enabled: false,
                fault: None
            },
            "frames go on, the watchdog is fed, no fault"
        );
        assert!(!s.motors_allowed());
        assert!(s.hold(false));
        assert!(s.tick(t + 500).motors_enabled, "primed all along");
        // a hold outlives a camera stall and the priming after it ...
        s.hold(true);
        assert_eq!(s.tick(t + 600).fault, Some(Fault::CameraStall));
        let d = run(&mut s, t + 650, t + 800);
        assert_eq!(
            (d.motors_enabled, d.fault),
            (false, None),
            "re-primed, still held"
        );
        s.hold(false);
        assert!(s.tick(t + 800).motors_enabled);
        // ... and letting go does not lift a fault
        s.hold(true);
        s.panic();
        s.hold(false);
        assert!(!s.motors_allowed());
    }

    #[test]
    fn the_control_channel_lets_go_only_on_g_alone_and_switches_mode_on_s_or_e() {
        use ConsoleCommand::{Go, Hold, Mode};
        assert_eq!(console_command(b"h"), Some(Hold));
        assert_eq!(console_command(b"H\r\n"), Some(Hold));
        assert_eq!(console_command(b"G\n"), Some(Go));
        assert_eq!(console_command(b" g "), Some(Go));
        assert_eq!(console_command(b"s\n"), Some(Mode(Behaviour::Swarm)));
        assert_eq!(console_command(b"E"), Some(Mode(Behaviour::Escape)));
        // anything else holds: fail safe
        for typed in [
            &b"stop\n"[..],
            b"go",
            b"gg",
            b"hxg",
            b"\x00",
            b"swarm",
            b"se",
        ] {
            assert_eq!(console_command(typed), Some(Hold), "{typed:?}");
        }
        assert_eq!(console_command(b""), None);
        assert_eq!(console_command(b" \r\n"), None);
    }
}

//! What one line of the firmware's RTT output is: the parsed telemetry record, summary or
//! `bench:` line (the grammars of `alvs_tasks::robot`), the boot banner, a boot or event
//! message of `src/`, or a line that is none of them and why.

use alvs_tasks::robot::health::Summary;
use alvs_tasks::robot::self_test::BenchLine;
use alvs_tasks::robot::telemetry::Record;
use serde::Serialize;

/// The banner's first word (src/main.rs: `alvs-firmware <version> on the Colias sense board`).
pub const BANNER: &str = "alvs-firmware ";

/// A message of the firmware that is not a measurement.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Event {
    /// `ERROR …`: the camera not found, a camera stall or overrun burst, perception errors.
    Error,
    /// `FAULT: …`: a hard fault stopped the motors; the watchdog resets.
    Fault,
    /// `WARNING: …`: clocks other than asked for.
    Warning,
    /// panic-probe's `panicked at …` and its message.
    Panic,
    /// `held: …` (`h` typed) and `let go` (`g`).
    Hold,
    /// `recovered: …`: frames flow again after a fault.
    Recovered,
    /// `behaviour: …`: motor control's behaviour (escape or the swarm's spin), at boot and when
    /// `s` or `e` is typed.
    Behaviour,
}

/// One logical line.
#[derive(Clone, Debug, PartialEq)]
pub enum Entry {
    /// Channel 1: a frame's telemetry record.
    Record(Record),
    /// Channel 0: the 1 Hz summary.
    Summary(Summary),
    /// Channel 0: a frame of the boot self-test.
    Bench(BenchLine),
    /// Channel 0: the boot banner, with the firmware's version.
    Banner(String),
    /// Channel 0: a boot step's report (`clocks:`, `camera:`, `running:`).
    Boot,
    /// Channel 0: a message.
    Event(Event),
    /// None of the above: which kind it started as (`None`: no kind at all) and why it is not
    /// one.
    Bad(Option<&'static str>, String),
}

impl Entry {
    /// Reads one line (without its terminator and time stamp).
    pub fn of(text: &str) -> Entry {
        let bad = |kind, e: &dyn std::fmt::Display| Entry::Bad(Some(kind), e.to_string());
        if text.starts_with("F ") {
            return Record::parse_line(text).map_or_else(|e| bad(KINDS[0], &e), Entry::Record);
        }
        if text.starts_with("S ") {
            return Summary::parse_line(text).map_or_else(|e| bad(KINDS[1], &e), Entry::Summary);
        }
        if text.starts_with("bench:") {
            return BenchLine::parse_line(text).map_or_else(|e| bad(KINDS[2], &e), Entry::Bench);
        }
        if let Some(rest) = text.strip_prefix(BANNER) {
            let version = rest.split(' ').next().unwrap_or("");
            return Entry::Banner(version.to_owned());
        }
        const BOOT: [&str; 3] = ["clocks: ", "camera: ", "running: "];
        if BOOT.iter().any(|p| text.starts_with(p)) {
            return Entry::Boot;
        }
        const EVENTS: [(&str, Event); 8] = [
            ("ERROR ", Event::Error),
            ("FAULT: ", Event::Fault),
            ("WARNING: ", Event::Warning),
            ("panicked at ", Event::Panic),
            ("held: ", Event::Hold),
            ("let go", Event::Hold),
            ("recovered: ", Event::Recovered),
            ("behaviour: ", Event::Behaviour),
        ];
        match EVENTS.iter().find(|(p, _)| text.starts_with(p)) {
            Some(&(_, e)) => Entry::Event(e),
            None => Entry::Bad(None, "not a line this firmware prints".into()),
        }
    }

    /// A line of a known kind, read whole.
    pub fn is_known(&self) -> bool {
        !matches!(self, Entry::Bad(..))
    }
}

/// The kinds of line a [`Entry::Bad`] may have started as.
pub const KINDS: [&str; 3] = ["telemetry record", "summary", "bench line"];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_kind() {
        let rec = "F 3 st=wander S=0.500 X=- sum=0 cyc=7 af=-";
        assert!(matches!(Entry::of(rec), Entry::Record(r) if r.frame == 3));
        assert!(matches!(
            Entry::of("S 1 frames=30 processed=30 dropped=0 invalid=0 overruns=0 sync=0 cycles=1/2/3 misses=0 rtt_dropped=0"),
            Entry::Summary(s) if s.frames == 30
        ));
        assert_eq!(
            Entry::of("alvs-firmware 0.1.0 on the Colias sense board (STM32F427VI)"),
            Entry::Banner("0.1.0".into())
        );
        assert_eq!(Entry::of("camera: OV7670 PID 0x76"), Entry::Boot);
        assert_eq!(
            Entry::of("ERROR camera stall: motors stopped"),
            Entry::Event(Event::Error)
        );
        assert_eq!(Entry::of("let go"), Entry::Event(Event::Hold));
        assert_eq!(
            Entry::of("behaviour: swarm, spin on an approaching robot (type e to escape)"),
            Entry::Event(Event::Behaviour)
        );
        assert_eq!(
            Entry::of("F 3 st=wander S=0.500"),
            Entry::Bad(Some("telemetry record"), "missing field `X`".into())
        );
        assert!(matches!(
            Entry::of("bench: frame x"),
            Entry::Bad(Some("bench line"), _)
        ));
        assert!(matches!(Entry::of("~~~"), Entry::Bad(None, _)));
        assert!(!Entry::of("").is_known());
    }
}

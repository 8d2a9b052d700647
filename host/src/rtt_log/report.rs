//! The summary of a log: the firmware's own counters (its 1 Hz summaries), the telemetry
//! records' cycles, states, alerts and attention fields, the boots and what ended each, the
//! boot self-test against the cycle model, the events, and every line that was skipped.

use alvs_tasks::model::fsm::State;
use alvs_tasks::robot::health::{CPU_HZ, FRAME_BUDGET_CYCLES};
use alvs_tasks::robot::self_test::{BenchLine, STAGE_NAMES};
use alvs_tasks::MAX_AFS;
use anyhow::{bail, Result};
use serde::Serialize;

use super::entry::{Entry, Event, KINDS};
use super::model::{Prediction, WorstCase};
use super::{Line, Log};

/// Camera frames per second: a processed frame stands for one period.
pub const FPS: f64 = 30.0;

/// Skipped lines quoted in the summary.
pub const QUOTED: usize = 5;

/// A line's place and text (and, for a skipped line, why).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Quote {
    pub source: String,
    pub line: usize,
    pub text: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

/// One boot of the firmware (a banner), or the part of a log before its first banner.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Boot {
    /// The banner's version; `None`: the log starts after the boot.
    pub version: Option<String>,
    /// Where the boot's first line is.
    pub source: String,
    pub line: usize,
    /// The camera's report, `camera: …` or `ERROR camera: …`.
    pub camera: Option<String>,
    /// Its self-test lines (in the JSON through [`LogReport::bench`]).
    #[serde(skip)]
    pub bench: Vec<BenchLine>,
    /// The last error, fault or panic before the next boot (what reset it); `None` for the last
    /// boot, or when nothing was said.
    pub ended_after: Option<Quote>,
}

/// Sums of the firmware's 1 Hz summary lines.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Counters {
    /// Summary lines (seconds covered).
    pub seconds: u64,
    pub frames: u64,
    pub processed: u64,
    pub dropped: u64,
    pub invalid: u64,
    pub overruns: u64,
    pub sync_errors: u64,
    pub over_budget: u64,
    pub rtt_dropped: u64,
    /// The largest per-second maximum of cycles per frame.
    pub cycles_max: Option<u32>,
}

/// Cycles per processed frame over the telemetry records.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Cycles {
    pub min: u32,
    pub mean: f64,
    /// Nearest-rank 99th percentile.
    pub p99: u32,
    pub max: u32,
    /// The frame period in cycles (33.3 ms at 180 MHz).
    pub period: u32,
}

/// Processed frames in one FSM state.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StateTime {
    pub state: &'static str,
    pub frames: usize,
    /// Frames × the frame period.
    pub seconds: f64,
    pub share: f64,
}

/// Frames that alerted (a threat centroid X̄ in the record).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Alerts {
    pub frames: usize,
    /// Runs of consecutive alerting records.
    pub episodes: usize,
    /// The frame number of the first.
    pub first_frame: Option<u32>,
    pub max_lplc2_sum: u32,
}

/// Attention fields per record.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Fields {
    /// Records with 0, 1, … `MAX_AFS` fields.
    pub per_frame: Vec<usize>,
    pub mean: f64,
    pub max: usize,
}

/// What the telemetry records say.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Telemetry {
    pub records: usize,
    /// Runs of frame numbers: a run restarts at 0 after a reset, or when the model primes
    /// again after a fault.
    pub runs: usize,
    /// Frame numbers absent inside the runs (records the firmware could not send, or lines
    /// skipped here).
    pub missing: u64,
    pub over_budget: usize,
    pub cycles: Option<Cycles>,
    pub states: Vec<StateTime>,
    pub alerts: Alerts,
    pub fields: Fields,
}

/// One stage of one self-test frame: the board's cycles and the model's.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BenchRow {
    pub frame: u32,
    pub stage: &'static str,
    pub board: u32,
    pub nominal: Option<u64>,
    pub pessimistic: Option<u64>,
}

impl BenchRow {
    /// board ÷ model, when the model counted anything.
    pub fn ratio(&self, model: Option<u64>) -> Option<f64> {
        model
            .filter(|&m| m > 0)
            .map(|m| f64::from(self.board) / m as f64)
    }
}

/// The boot self-test against the cycle model.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Bench {
    /// The boot (from 1) whose lines are compared.
    pub boot: usize,
    pub rows: Vec<BenchRow>,
    /// Self-test frames whose attention fields differ from the model's (another build ran).
    pub afs_differ: Vec<u32>,
    /// Other boots whose self-test differs from the compared one's: (boot, largest relative
    /// difference of a stage).
    pub other_boots: Vec<(usize, f64)>,
}

/// Lines skipped: not a line of this firmware's, or not whole.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Skipped {
    pub lines: usize,
    /// Per kind the line started as ("unknown": none).
    pub by_kind: Vec<(String, usize)>,
    /// The first [`QUOTED`].
    pub first: Vec<Quote>,
}

/// The whole summary.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LogReport {
    pub sources: Vec<String>,
    /// The version of these tools (the workspace's, the firmware's they were built with).
    pub tools_version: String,
    pub boots: Vec<Boot>,
    /// Banner versions other than the tools'.
    pub other_versions: Vec<String>,
    pub counters: Counters,
    pub telemetry: Telemetry,
    pub bench: Option<Bench>,
    /// What the cycle model is, or why it is missing.
    pub model: String,
    pub worst_case: Option<WorstCase>,
    pub events: Vec<Quote>,
    pub skipped: Skipped,
    /// Lines put back together from pieces.
    pub rejoined: usize,
}

/// A log with neither a telemetry record nor a 1 Hz summary line is an error, in one line: what
/// it holds instead (its last error message, if any).
pub fn check(log: &Log) -> Result<()> {
    let telemetry = log
        .lines
        .iter()
        .any(|(_, e)| matches!(e, Entry::Record(_) | Entry::Summary(_)));
    if telemetry {
        return Ok(());
    }
    let what = if log.lines.is_empty() {
        "it is empty".to_owned()
    } else {
        let known = log.lines.iter().filter(|(_, e)| e.is_known()).count();
        let last_error =
            log.lines.iter().rev().find(|(_, e)| {
                matches!(e, Entry::Event(Event::Error | Event::Fault | Event::Panic))
            });
        match last_error {
            Some((l, _)) => format!("its last error: {:?}", l.text),
            None => format!("{} lines, {known} of them the firmware's", log.lines.len()),
        }
    };
    bail!(
        "{}: no telemetry (no frame record, no 1 Hz summary): {what}",
        log.sources.join(", ")
    )
}

/// The place and text of `line`.
fn quote(log: &Log, line: &Line, reason: Option<String>) -> Quote {
    Quote {
        source: log.sources.get(line.source).cloned().unwrap_or_default(),
        line: line.number,
        text: line.text.clone(),
        reason,
    }
}

impl LogReport {
    /// The summary of `log`; `model` is the cycle model's prediction, or why there is none.
    /// A log without telemetry is an error ([`check`]).
    pub fn of(log: &Log, model: Result<Prediction, String>) -> Result<LogReport> {
        check(log)?;
        let counters = counters(log);
        let records: Vec<_> = log.records().collect();
        let (events, skipped) = events_and_skipped(log);
        let boots = boots(log);
        let tools_version = env!("CARGO_PKG_VERSION").to_owned();
        let mut other_versions: Vec<String> = boots
            .iter()
            .filter_map(|b| b.version.clone())
            .filter(|v| *v != tools_version)
            .collect();
        other_versions.dedup();
        let (prediction, model) = match model {
            Ok(p) => (
                Some(p),
                "the cycle model of this working tree's release build".into(),
            ),
            Err(why) => (None, why),
        };
        Ok(LogReport {
            sources: log.sources.clone(),
            tools_version,
            bench: bench(&boots, prediction.as_ref()),
            worst_case: prediction.and_then(|p| p.worst_case),
            model,
            boots,
            other_versions,
            counters,
            telemetry: telemetry(&records),
            events,
            skipped,
            rejoined: log.lines.iter().filter(|(l, _)| l.pieces > 1).count(),
        })
    }
}

fn counters(log: &Log) -> Counters {
    let mut c = Counters::default();
    for (_, e) in &log.lines {
        if let Entry::Summary(s) = e {
            c.seconds += 1;
            c.frames += u64::from(s.frames);
            c.processed += u64::from(s.processed);
            c.dropped += u64::from(s.dropped);
            c.invalid += u64::from(s.invalid);
            c.overruns += u64::from(s.overruns);
            c.sync_errors += u64::from(s.sync_errors);
            c.over_budget += u64::from(s.misses);
            c.rtt_dropped += u64::from(s.rtt_dropped);
            if let Some((_, _, max)) = s.cycles {
                c.cycles_max = c.cycles_max.max(Some(max));
            }
        }
    }
    c
}

fn telemetry(records: &[&alvs_tasks::robot::telemetry::Record]) -> Telemetry {
    let n = records.len();
    let mut t = Telemetry {
        records: n,
        ..Telemetry::default()
    };
    let mut prev: Option<u32> = None;
    for r in records {
        match prev {
            Some(p) if r.frame > p => t.missing += u64::from(r.frame - p - 1),
            _ => t.runs += 1,
        }
        prev = Some(r.frame);
    }
    let mut cycles: Vec<u32> = records.iter().map(|r| r.cycles).collect();
    cycles.sort_unstable();
    t.over_budget = cycles.iter().filter(|&&c| c > FRAME_BUDGET_CYCLES).count();
    if let (Some(&min), Some(&max)) = (cycles.first(), cycles.last()) {
        let p99 = cycles[(n * 99).div_ceil(100).max(1) - 1];
        let mean = cycles.iter().map(|&c| f64::from(c)).sum::<f64>() / n as f64;
        t.cycles = Some(Cycles {
            min,
            mean,
            p99,
            max,
            period: FRAME_BUDGET_CYCLES,
        });
    }
    t.states = State::ALL
        .iter()
        .map(|&s| {
            let frames = records.iter().filter(|r| r.state == s).count();
            StateTime {
                state: s.name(),
                frames,
                seconds: frames as f64 / FPS,
                share: frames as f64 / n.max(1) as f64,
            }
        })
        .filter(|s| s.frames > 0)
        .collect();
    let mut was = false;
    for r in records {
        let alert = r.alert();
        if alert {
            t.alerts.frames += 1;
            t.alerts.first_frame = t.alerts.first_frame.or(Some(r.frame));
            t.alerts.episodes += usize::from(!was);
        }
        was = alert;
        t.alerts.max_lplc2_sum = t.alerts.max_lplc2_sum.max(r.lplc2_sum);
    }
    let mut per_frame = vec![0usize; MAX_AFS + 1];
    for r in records {
        per_frame[r.afs.len()] += 1;
    }
    let total: usize = records.iter().map(|r| r.afs.len()).sum();
    t.fields = Fields {
        max: per_frame.iter().rposition(|&k| k > 0).unwrap_or(0),
        per_frame,
        mean: total as f64 / n.max(1) as f64,
    };
    t
}

/// The boots: a banner starts one; a log's lines before its first banner are a boot of
/// unknown version when they hold anything of the firmware's.
fn boots(log: &Log) -> Vec<Boot> {
    let mut boots: Vec<Boot> = Vec::new();
    let mut last_error: Option<Quote> = None;
    for (line, entry) in &log.lines {
        let start = |version| Boot {
            version,
            source: log.sources.get(line.source).cloned().unwrap_or_default(),
            line: line.number,
            camera: None,
            bench: Vec::new(),
            ended_after: None,
        };
        match entry {
            Entry::Banner(v) => {
                if let Some(b) = boots.last_mut() {
                    b.ended_after = last_error.take();
                }
                last_error = None;
                boots.push(start(Some(v.clone())));
                continue;
            }
            Entry::Bad(..) => continue,
            _ if boots.is_empty() => boots.push(start(None)),
            _ => {}
        }
        let Some(boot) = boots.last_mut() else {
            continue;
        };
        match entry {
            Entry::Bench(b) => boot.bench.push(*b),
            Entry::Boot if line.text.starts_with("camera: ") => {
                boot.camera = Some(line.text.clone())
            }
            Entry::Event(Event::Error) if line.text.starts_with("ERROR camera: ") => {
                boot.camera = Some(line.text.clone());
                last_error = Some(quote(log, line, None));
            }
            Entry::Event(Event::Error | Event::Fault | Event::Panic) => {
                last_error = Some(quote(log, line, None))
            }
            Entry::Event(Event::Recovered) => last_error = None,
            _ => {}
        }
    }
    boots
}

/// The events, and the skipped lines; the message line after a panic belongs to the panic.
fn events_and_skipped(log: &Log) -> (Vec<Quote>, Skipped) {
    let mut events: Vec<Quote> = Vec::new();
    let mut skipped = Skipped::default();
    let mut kinds: Vec<(String, usize)> = KINDS
        .iter()
        .chain(&["unknown"])
        .map(|k| (k.to_string(), 0))
        .collect();
    let mut after_panic = false;
    for (line, entry) in &log.lines {
        match entry {
            Entry::Event(e) => {
                events.push(quote(log, line, None));
                after_panic = *e == Event::Panic;
                continue;
            }
            Entry::Bad(None, _) if after_panic => {
                if let Some(p) = events.last_mut() {
                    p.text = format!("{} {}", p.text, line.text);
                }
            }
            Entry::Bad(kind, why) => {
                skipped.lines += 1;
                let k = kind.unwrap_or("unknown");
                if let Some(c) = kinds.iter_mut().find(|(name, _)| name == k) {
                    c.1 += 1;
                }
                if skipped.first.len() < QUOTED {
                    skipped.first.push(quote(log, line, Some(why.clone())));
                }
            }
            _ => {}
        }
        after_panic = false;
    }
    skipped.by_kind = kinds.into_iter().filter(|(_, n)| *n > 0).collect();
    (events, skipped)
}

/// The first boot's self-test next to the model's; other boots' self-tests checked against it.
fn bench(boots: &[Boot], model: Option<&Prediction>) -> Option<Bench> {
    let (i, first) = boots
        .iter()
        .enumerate()
        .find(|(_, b)| !b.bench.is_empty())?;
    let mut rows = Vec::new();
    let mut afs_differ = Vec::new();
    for b in &first.bench {
        let p = model.and_then(|m| m.frame(b.frame));
        if p.is_some_and(|p| p.afs != b.afs) {
            afs_differ.push(b.frame);
        }
        let stages = STAGE_NAMES.iter().zip(b.stages).enumerate();
        for (k, (&stage, board)) in stages {
            rows.push(BenchRow {
                frame: b.frame,
                stage,
                board,
                nominal: p.map(|p| p.nominal[k]),
                pessimistic: p.map(|p| p.pessimistic[k]),
            });
        }
        rows.push(BenchRow {
            frame: b.frame,
            stage: "total",
            board: b.total(),
            nominal: p.map(|p| p.nominal.iter().sum()),
            pessimistic: p.map(|p| p.pessimistic.iter().sum()),
        });
    }
    let other_boots = boots
        .iter()
        .enumerate()
        .skip(i + 1)
        .filter(|(_, b)| !b.bench.is_empty() && b.bench != first.bench)
        .map(|(j, b)| {
            let pairs = b.bench.iter().zip(&first.bench);
            let stages = pairs.flat_map(|(x, y)| x.stages.into_iter().zip(y.stages));
            let worst = stages
                .map(|(x, y)| (f64::from(x) - f64::from(y)).abs() / f64::from(y.max(1)))
                .fold(0.0, f64::max);
            (j + 1, worst)
        })
        .collect();
    Some(Bench {
        boot: i + 1,
        rows,
        afs_differ,
        other_boots,
    })
}

/// Cycles as milliseconds at the robot's clock.
pub fn ms(cycles: f64) -> f64 {
    cycles * 1e3 / f64::from(CPU_HZ)
}

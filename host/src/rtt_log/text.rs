//! The summary as text (what `cargo alvs log` prints).

use std::fmt::{self, Display, Formatter, Write};

use super::report::{ms, Bench, LogReport, Quote};

/// A quoted line, shortened to `max` characters.
fn short(text: &str, max: usize) -> String {
    if text.chars().count() <= max {
        format!("{text:?}")
    } else {
        let cut: String = text.chars().take(max).collect();
        format!("{cut:?}…")
    }
}

/// A source's short name: `channel<N>` for a cargo-embed file, else the file's name.
fn short_source(source: &str) -> &str {
    let name = source.rsplit('/').next().unwrap_or(source);
    name.rsplit_once('_')
        .and_then(|(_, tab)| tab.strip_suffix(".txt"))
        .filter(|tab| tab.starts_with("channel"))
        .unwrap_or(name)
}

/// `source:line`, the source by its short name.
fn place(q: &Quote) -> String {
    format!("{}:{}", short_source(&q.source), q.line)
}

/// "s" after a count other than one.
fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

fn pct(x: f64) -> String {
    format!("{:.1} %", 100.0 * x)
}

fn ratio(r: Option<f64>) -> String {
    r.map_or_else(|| "-".into(), |r| format!("{r:.3}"))
}

fn bench_table(f: &mut Formatter<'_>, b: &Bench, model: &str) -> fmt::Result {
    if b.rows.iter().any(|r| r.pessimistic.is_some()) {
        writeln!(
            f,
            "boot self-test (bench: lines of boot {}) against {model}:",
            b.boot
        )?;
    } else {
        writeln!(
            f,
            "boot self-test (bench: lines of boot {}); the cycle model: {model}",
            b.boot
        )?;
    }
    writeln!(
        f,
        "  frame  stage          board    nominal  pessimistic  board/nominal  board/pessimistic"
    )?;
    let opt = |v: Option<u64>| v.map_or_else(|| "-".into(), |v| v.to_string());
    for r in &b.rows {
        writeln!(
            f,
            "  {:>5}  {:<10} {:>9} {:>10} {:>12} {:>14} {:>18}",
            r.frame,
            r.stage,
            r.board,
            opt(r.nominal),
            opt(r.pessimistic),
            ratio(r.ratio(r.nominal)),
            ratio(r.ratio(r.pessimistic))
        )?;
    }
    if !b.afs_differ.is_empty() {
        writeln!(
            f,
            "  attention fields differ from the model's in frames {:?}: the board ran another build",
            b.afs_differ
        )?;
    }
    for (boot, d) in &b.other_boots {
        writeln!(
            f,
            "  boot {boot}'s self-test differs from boot {}'s by up to {}",
            b.boot,
            pct(*d)
        )?;
    }
    Ok(())
}

impl Display for LogReport {
    fn fmt(&self, f: &mut Formatter<'_>) -> fmt::Result {
        writeln!(f, "read: {}", self.sources.join(", "))?;
        let versions: Vec<String> = self
            .boots
            .iter()
            .map(|b| b.version.clone().unwrap_or_else(|| "unknown".into()))
            .collect();
        let mut firmware = format!(
            "firmware: {} boot{} ({}), these tools {}",
            self.boots.len(),
            plural(self.boots.len()),
            versions.join(", "),
            self.tools_version
        );
        if !self.other_versions.is_empty() {
            let _ = write!(
                firmware,
                " — a log of alvs-firmware {}: read with {}'s grammar, its bench against {}'s build",
                self.other_versions.join(", "),
                self.tools_version,
                self.tools_version
            );
        }
        writeln!(f, "{firmware}")?;
        for (i, b) in self.boots.iter().enumerate() {
            let start = match &b.version {
                Some(_) => format!("banner at {}:{}", short_source(&b.source), b.line),
                None => "no banner: the log starts after the boot".into(),
            };
            let camera = b
                .camera
                .as_deref()
                .map_or_else(|| "no camera line".into(), |c| short(c, 70));
            write!(f, "  boot {}: {start}; {camera}", i + 1)?;
            match (&b.ended_after, i + 1 < self.boots.len()) {
                (Some(q), true) => {
                    writeln!(f, "; reset after {} ({})", short(&q.text, 70), place(q))?
                }
                (None, true) => writeln!(f, "; reset with no message before it")?,
                _ => writeln!(f)?,
            }
        }
        let c = &self.counters;
        if c.seconds == 0 {
            writeln!(
                f,
                "frames: no 1 Hz summary line in the log (the first comes a second after boot)"
            )?;
        } else {
            writeln!(
                f,
                "frames (the firmware's 1 Hz summaries, {} s): {} ended, {} processed, {} dropped, {} invalid ({} DCMI overruns, {} sync errors), {} over budget, {} telemetry records lost on RTT",
                c.seconds, c.frames, c.processed, c.dropped, c.invalid, c.overruns, c.sync_errors, c.over_budget, c.rtt_dropped
            )?;
        }
        let t = &self.telemetry;
        writeln!(
            f,
            "telemetry: {} records in {} run{} of frame numbers (a run restarts at a reset and after a fault), {} frame numbers missing",
            t.records,
            t.runs,
            plural(t.runs),
            t.missing
        )?;
        match &t.cycles {
            Some(cy) => writeln!(
                f,
                "cycles per frame: min {}, mean {:.0}, p99 {}, max {} = {:.2} ms, {} of the {:.1} ms period; {} over budget",
                cy.min,
                cy.mean,
                cy.p99,
                cy.max,
                ms(f64::from(cy.max)),
                pct(f64::from(cy.max) / f64::from(cy.period)),
                ms(f64::from(cy.period)),
                t.over_budget
            )?,
            None => writeln!(f, "cycles per frame: no records")?,
        }
        let states: Vec<String> = t
            .states
            .iter()
            .map(|s| format!("{} {:.1} s ({})", s.state, s.seconds, pct(s.share)))
            .collect();
        writeln!(
            f,
            "time per state (processed frames x 33.3 ms): {}",
            if states.is_empty() {
                "-".into()
            } else {
                states.join(", ")
            }
        )?;
        let a = &t.alerts;
        writeln!(
            f,
            "alerts: {} frames in {} episode{}{}; the largest ΣLPLC2 {}",
            a.frames,
            a.episodes,
            plural(a.episodes),
            a.first_frame
                .map_or_else(String::new, |fr| format!(", the first at frame {fr}")),
            a.max_lplc2_sum
        )?;
        let per: Vec<String> = t
            .fields
            .per_frame
            .iter()
            .enumerate()
            .filter(|(_, &n)| n > 0)
            .map(|(k, &n)| format!("{k}: {n}"))
            .collect();
        writeln!(
            f,
            "attention fields per frame: mean {:.2}, max {} (frames with 0..6 fields: {})",
            t.fields.mean,
            t.fields.max,
            per.join(", ")
        )?;
        match &self.bench {
            Some(b) => bench_table(f, b, &self.model)?,
            None => writeln!(f, "boot self-test: no bench: lines in the log")?,
        }
        if let Some(w) = &self.worst_case {
            writeln!(
                f,
                "the model's worst frame ({}): {} frame {}, {} pessimistic cycles = {:.2} ms",
                w.source,
                w.scene,
                w.frame,
                w.pessimistic,
                ms(w.pessimistic as f64)
            )?;
        }
        writeln!(f, "events: {}", self.events.len())?;
        for q in &self.events {
            writeln!(f, "  {}: {}", place(q), short(&q.text, 100))?;
        }
        let s = &self.skipped;
        let kinds: Vec<String> = s.by_kind.iter().map(|(k, n)| format!("{n} {k}")).collect();
        write!(f, "skipped: {} line{}", s.lines, plural(s.lines))?;
        if kinds.is_empty() {
            writeln!(f)?;
        } else {
            writeln!(f, " ({})", kinds.join(", "))?;
        }
        for q in &s.first {
            writeln!(
                f,
                "  {}: {} ({})",
                place(q),
                short(&q.text, 80),
                q.reason.as_deref().unwrap_or("")
            )?;
        }
        if s.lines > s.first.len() {
            writeln!(f, "  … and {} more", s.lines - s.first.len())?;
        }
        if self.rejoined > 0 {
            writeln!(
                f,
                "rejoined: {} lines the RTT reads (or a terminal) had cut in pieces",
                self.rejoined
            )?;
        }
        Ok(())
    }
}

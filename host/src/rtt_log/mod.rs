//! Reading back a saved RTT session of the firmware (`cargo alvs log`, docs/log.md): the files
//! `cargo embed` writes with `log_enabled` (one per tab: "log" = RTT up channel 0, "telemetry"
//! = up channel 1), or either tab's text piped in, both channels in one stream if need be.
//!
//! | step | module |
//! |---|---|
//! | which files, or standard input | [`source`] |
//! | time stamps off, lines a poll cut joined | [`lines`] |
//! | what each line is (the grammars of `alvs_tasks::robot`) | [`entry`] |
//! | the summary: counters, cycles, states, alerts, fields, boots, bench vs model, skipped lines | [`report`] |
//! | the cycle model's prediction of the boot self-test | [`model`] |
//! | the summary as text | [`text`] |
//! | pictures | [`pictures`] |
//!
//! Nothing is dropped silently: a line that is not one the firmware prints, or does not parse
//! whole, is counted and the first few are quoted with their place; a second banner is a
//! reset; a banner of another version is said.

pub mod entry;
pub mod lines;
pub mod model;
pub mod pictures;
pub mod report;
pub mod source;
pub mod text;

use std::path::Path;

use alvs_tasks::robot::telemetry::Record;
use anyhow::Result;

pub use entry::{Entry, Event};
pub use lines::Line;
pub use model::Prediction;
pub use report::LogReport;
pub use source::Source;

/// A read log: every logical line with what it is, in each source's order.
#[derive(Clone, Debug)]
pub struct Log {
    /// The sources' names (files, or standard input), in the order read.
    pub sources: Vec<String>,
    pub lines: Vec<(Line, Entry)>,
}

impl Log {
    /// Reads the sources' lines; `progress` gets the bytes of each line read.
    pub fn parse(sources: &[Source], progress: &mut dyn FnMut(u64)) -> Log {
        let mut lines = Vec::new();
        for (i, s) in sources.iter().enumerate() {
            for line in lines::logical(i, &s.text) {
                progress(line.text.len() as u64 + line.pieces as u64);
                let entry = Entry::of(&line.text);
                lines.push((line, entry));
            }
        }
        Log {
            sources: sources.iter().map(|s| s.name.clone()).collect(),
            lines,
        }
    }

    /// The session at `path` (a cargo-embed log file with its sibling tabs, their folder's
    /// newest session, or another text file).
    pub fn read(path: &Path) -> Result<Log> {
        let files = source::locate(path)?;
        Ok(Log::parse(&source::read_files(&files)?, &mut |_| {}))
    }

    /// The telemetry records, in order.
    pub fn records(&self) -> impl Iterator<Item = &Record> {
        self.lines.iter().filter_map(|(_, e)| match e {
            Entry::Record(r) => Some(r),
            _ => None,
        })
    }
}

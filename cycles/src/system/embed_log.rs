//! The files `cargo embed` saves of a session when Embed.toml sets `log_enabled`, written from
//! the virtual board's RTT reads, so the host's log reader (`cargo alvs log`) is tested on the
//! format it meets on a real board.
//!
//! What probe-rs' cargo-embed does (probe-rs-tools `cmd/cargo_embed/rttui/app.rs`,
//! `save_tab_logs`, and `util/rtt/processing.rs`, read at commit 67993c4b): when the session
//! ends it writes one file per tab into `log_path`, named
//! `<ELF file stem>_<chip>_<unix time in ms at the start>_channel<tab index>.txt`. A text
//! channel's file holds every piece of text one poll of that channel read, in order, each
//! followed by a newline (`writeln!(file, "{piece}")`). With `show_timestamps` (its default)
//! each line that starts in a piece gets the host's wall-clock time, `HH:MM:SS.mmm: `, in
//! front; the session's very first line, and the rest of a line a poll cut in two, get none.
//! So a piece that ends a line leaves an empty line after it, and a line a poll cut in two
//! continues on the next line of the file.

use std::io;
use std::path::{Path, PathBuf};

use super::rtt::Channel;
use super::Board;
use crate::CLOCK_HZ;

/// The file stem of the firmware's ELF, the first part of the files' names.
pub const ELF_NAME: &str = "alvs-firmware";

/// Embed.toml's `chip`.
pub const CHIP: &str = "STM32F427VITx";

/// One cargo-embed tab: the up channel it shows and whether its lines get time stamps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tab {
    pub up_channel: usize,
    pub show_timestamps: bool,
}

/// Embed.toml's tabs, in order: "log" (up channel 0, `show_timestamps = true`) and
/// "telemetry" (up channel 1; cargo-embed's default `show_timestamps` is true).
pub const TABS: [Tab; 2] = [
    Tab {
        up_channel: 0,
        show_timestamps: true,
    },
    Tab {
        up_channel: 1,
        show_timestamps: true,
    },
];

/// The name cargo-embed gives tab `tab`'s file of a session that started at `start_ms`.
pub fn file_name(start_ms: u64, tab: usize) -> String {
    format!("{ELF_NAME}_{CHIP}_{start_ms}_channel{tab}.txt")
}

/// `HH:MM:SS.mmm` of a wall-clock time in unix milliseconds (UTC).
fn time_of_day(ms: u64) -> String {
    let day = ms % 86_400_000;
    format!(
        "{:02}:{:02}:{:02}.{:03}",
        day / 3_600_000,
        day / 60_000 % 60,
        day / 1000 % 60,
        day % 1000
    )
}

/// A channel's file as cargo-embed writes it: the session started at wall-clock `start_ms`
/// (unix ms) when the board's clock read 0.
pub fn render(channel: &Channel, show_timestamps: bool, start_ms: u64) -> String {
    let mut out = String::with_capacity(channel.text.len() * 5 / 4);
    let mut at = 0;
    // cargo-embed's decoder starts as if in the middle of a line
    let mut line_done = false;
    for &(time, len) in &channel.reads {
        let Some(piece) = channel.text.get(at..at + len) else {
            break;
        };
        at += len;
        let stamp = time_of_day(start_ms + time * 1000 / CLOCK_HZ);
        for line in piece.split_inclusive('\n') {
            if show_timestamps && line_done {
                out.push_str(&stamp);
                out.push_str(": ");
            }
            out.push_str(line);
            line_done = line.ends_with('\n');
        }
        out.push('\n');
    }
    out
}

/// Writes the board's session so far into `dir` as cargo-embed would (created if missing),
/// for a session that started at wall-clock `start_ms`; returns the files' paths.
pub fn write(board: &Board, dir: &Path, start_ms: u64) -> io::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let empty = Channel::default();
    TABS.iter()
        .enumerate()
        .map(|(i, tab)| {
            let channel = board.rtt_channel(tab.up_channel).unwrap_or(&empty);
            let path = dir.join(file_name(start_ms, i));
            std::fs::write(&path, render(channel, tab.show_timestamps, start_ms))?;
            Ok(path)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(pieces: &[(u64, &str)]) -> Channel {
        Channel {
            name: "log".into(),
            text: pieces.iter().map(|p| p.1).collect(),
            reads: pieces.iter().map(|&(t, s)| (t, s.len())).collect(),
        }
    }

    #[test]
    fn pieces_end_with_a_newline_and_lines_start_with_the_time() {
        // 13:00:00.000 UTC, reads at 0 ms, 1 ms and 1.5 s
        let start = 1_700_000_000_000 - 1_700_000_000_000 % 86_400_000 + 13 * 3_600_000;
        let ms = CLOCK_HZ / 1000;
        let c = channel(&[
            (0, "banner\nclocks: a\n"),
            (ms, "bench: fr"),
            (1500 * ms, "ame 0\nS 1\n"),
        ]);
        assert_eq!(
            render(&c, true, start),
            "banner\n13:00:00.000: clocks: a\n\n13:00:00.001: bench: fr\name 0\n13:00:01.500: S 1\n\n"
        );
        assert_eq!(
            render(&c, false, start),
            "banner\nclocks: a\n\nbench: fr\name 0\nS 1\n\n"
        );
        assert_eq!(render(&Channel::default(), true, start), "");
    }

    #[test]
    fn names_as_cargo_embed() {
        assert_eq!(
            file_name(1_723_456_789_012, 1),
            "alvs-firmware_STM32F427VITx_1723456789012_channel1.txt"
        );
    }

    /// The tabs and chip above are Embed.toml's.
    #[test]
    fn embed_toml_has_these_tabs() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
        let toml = std::fs::read_to_string(root.join("Embed.toml")).unwrap();
        assert!(toml.contains(&format!("chip = \"{CHIP}\"")));
        assert!(toml.contains("{ channel = 0, format = \"String\", show_timestamps = true }"));
        assert!(toml.contains("{ channel = 1, format = \"String\" }"));
        let log = toml.find("{ up_channel = 0, down_channel = 0, name = \"log\" }");
        let telemetry = toml.find("{ up_channel = 1, name = \"telemetry\" }");
        assert!(
            log.is_some() && log < telemetry,
            "tab 0 log, tab 1 telemetry"
        );
    }
}

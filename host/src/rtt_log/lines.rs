//! The logical lines of a saved RTT channel: cargo-embed's time stamps removed, the empty line
//! it writes after each piece a poll read dropped, and a line that a poll (or a terminal's
//! wrapping, when a tab's text is pasted) cut in two joined again
//! (`alvs_cycles::system::embed_log` describes the file format). The output of `probe-rs run`
//! (`cargo run --release`) reads too: it puts the channel's name, `[log      ] ` or
//! `[telemetry] `, before each piece it prints, and the same time stamps.

use super::entry::Entry;

/// One logical line and where it starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Line {
    /// Index of the source (file or standard input) it came from.
    pub source: usize,
    /// Its first physical line's number in that source, from 1.
    pub number: usize,
    /// The text without time stamp and terminator.
    pub text: String,
    /// The physical lines it was joined from (1: not split).
    pub pieces: usize,
}

/// The text after cargo-embed's `HH:MM:SS.mmm: ` time stamp, if the line has one.
pub fn unstamped(line: &str) -> Option<&str> {
    let b = line.as_bytes();
    let digits = |r: std::ops::Range<usize>| r.into_iter().all(|i| b[i].is_ascii_digit());
    let stamped = b.len() >= 14
        && digits(0..2)
        && b[2] == b':'
        && digits(3..5)
        && b[5] == b':'
        && digits(6..8)
        && b[8] == b'.'
        && digits(9..12)
        && &b[12..14] == b": ";
    stamped.then(|| &line[14..])
}

/// The text after `probe-rs run`'s channel name (`[log      ] `, `[telemetry] `: the firmware's
/// up channels, padded to the longer name), if the line has one.
pub fn unprefixed(line: &str) -> Option<&str> {
    let (name, rest) = line.strip_prefix('[')?.split_once("] ")?;
    ["log", "telemetry"]
        .contains(&name.trim_end())
        .then_some(rest)
}

/// The logical lines of source `source`'s text.
///
/// A physical line continues the one before it (nothing but a line break between them) when
/// that one is not a whole line of the firmware's and, in time-stamped text, it has no stamp
/// (cargo-embed's mark of a line a poll cut). The join that reads as a known line wins:
/// directly (a poll's cut) or with a space (a terminal's wrap); in stamped text the pieces are
/// joined in any case (and then counted as one line that does not read).
pub fn logical(source: usize, text: &str) -> Vec<Line> {
    let physical: Vec<(&str, Option<&str>)> = text
        .split('\n')
        .map(|l| l.strip_suffix('\r').unwrap_or(l))
        .map(|l| unprefixed(l).unwrap_or(l))
        .map(|l| (l, unstamped(l)))
        .collect();
    let stamped = physical.iter().any(|(_, s)| s.is_some());
    let mut out: Vec<Line> = Vec::new();
    let mut after_break = true;
    for (i, (raw, stripped)) in physical.into_iter().enumerate() {
        if raw.is_empty() {
            after_break = true;
            continue;
        }
        let body = stripped.unwrap_or(raw);
        if let Some(prev) = out.last_mut().filter(|_| !after_break) {
            let cut = (!stamped || stripped.is_none()) && !Entry::of(&prev.text).is_known();
            if cut {
                let direct = format!("{}{body}", prev.text);
                let spaced = format!("{} {body}", prev.text);
                let joined = if Entry::of(&direct).is_known() {
                    Some(direct)
                } else if Entry::of(&spaced).is_known() {
                    Some(spaced)
                } else {
                    stamped.then_some(direct)
                };
                if let Some(text) = joined {
                    prev.text = text;
                    prev.pieces += 1;
                    continue;
                }
            }
        }
        after_break = false;
        out.push(Line {
            source,
            number: i + 1,
            text: body.to_owned(),
            pieces: 1,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(lines: &[Line]) -> Vec<&str> {
        lines.iter().map(|l| l.text.as_str()).collect()
    }

    const REC: &str = "F 12 st=wander S=0.500 X=- sum=0 cyc=496643 af=-";

    #[test]
    fn stamps() {
        assert_eq!(unstamped("06:26:57.965: F 1"), Some("F 1"));
        assert_eq!(unstamped("06:26:57.965 F 1"), None);
        assert_eq!(unstamped("6:26:57.965: F 1"), None);
        assert_eq!(unstamped("ab"), None);
    }

    #[test]
    fn cargo_embed_pieces_and_a_poll_cut() {
        let text = format!(
            "alvs-firmware 0.1.0 on the Colias\n10:00:00.001: clocks: a\n\n10:00:00.050: {}\n{}\n\n",
            &REC[..20],
            &REC[20..]
        );
        let lines = logical(0, &text);
        assert_eq!(
            texts(&lines),
            ["alvs-firmware 0.1.0 on the Colias", "clocks: a", REC]
        );
        assert_eq!((lines[2].number, lines[2].pieces), (4, 2));
    }

    #[test]
    fn a_stamped_cut_that_makes_no_line_stays_one_bad_line() {
        let lines = logical(
            0,
            "10:00:00.001: F 1 st=wan\nGARBAGE\n\n10:00:00.002: let go\n",
        );
        assert_eq!(texts(&lines), ["F 1 st=wanGARBAGE", "let go"]);
    }

    #[test]
    fn probe_rs_run_output_of_both_channels() {
        // each piece after the channel's name; a channel's first line has no stamp
        let text = format!(
            "[log      ] alvs-firmware 0.1.0 on the Colias\n[telemetry] {REC}\n\
             [log      ] 10:00:00.001: clocks: a\n10:00:00.001: let go\n[telemetry] 10:00:00.033: {REC}\n"
        );
        assert_eq!(
            texts(&logical(0, &text)),
            [
                "alvs-firmware 0.1.0 on the Colias",
                REC,
                "clocks: a",
                "let go",
                REC
            ]
        );
        assert_eq!(unprefixed("[other] x"), None);
        assert_eq!(unprefixed("[telemetry] x"), Some("x"));
    }

    #[test]
    fn unstamped_text_joins_only_what_makes_a_line() {
        // a poll's cut, a terminal's wrap at a space, garbage, a whole record
        let text = format!(
            "{}\n{}\n{}\n{}\ngarbage\n{REC}\n",
            &REC[..20],
            &REC[20..],
            &REC[..22],
            &REC[23..]
        );
        assert_eq!(texts(&logical(3, &text)), [REC, REC, "garbage", REC]);
        // a truncated last line stays as it is
        assert_eq!(texts(&logical(0, &REC[..30])), [&REC[..30]]);
    }
}

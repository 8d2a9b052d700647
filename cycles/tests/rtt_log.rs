//! `cargo alvs log` on sessions of the virtual board saved as `cargo embed` saves them
//! (`alvs-virtual --embed-log`): a clean run of a looming clip, a camera stall, a fault and
//! its watchdog reset. The summary's numbers must be the board's own (its timing report, printed
//! by the same run), and its boot self-test the cycle model's (the virtual board counts cycles
//! with the pessimistic model).

use std::path::PathBuf;
use std::process::Command;

use alvs_cycles::budget::{self_test, STAGE_NAMES};
use alvs_host::rtt_log::model::{PredictedFrame, Prediction};
use alvs_host::rtt_log::{Log, LogReport};

mod common;
use common::{firmware, root};

/// The board's counters of one run, from its timing report.
#[derive(Debug)]
struct Board {
    captured: u64,
    processed: u64,
    dropped: u64,
    invalid: u64,
    over_budget: u64,
    resets: usize,
}

/// The number after `key` in `text`.
fn after(text: &str, key: &str) -> u64 {
    let rest = &text[text
        .find(key)
        .unwrap_or_else(|| panic!("{key:?} in {text}"))
        + key.len()..];
    let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
    digits
        .parse()
        .unwrap_or_else(|_| panic!("a number after {key:?}"))
}

/// Runs `alvs-virtual` with `args` and `--embed-log` into a fresh folder; the board's counters
/// and the files.
fn session(name: &str, args: &[&str]) -> (Board, Vec<PathBuf>) {
    let dir = std::env::temp_dir().join(format!("alvs-rtt-log-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = Command::new(env!("CARGO_BIN_EXE_alvs-virtual"))
        .args(args)
        .args(["--telemetry", "0", "--embed-log"])
        .arg(&dir)
        .current_dir(root())
        .output()
        .expect("alvs-virtual runs");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let board = Board {
        captured: after(&stdout, "captured "),
        processed: after(&stdout, "processed "),
        dropped: after(&stdout, "counted dropped "),
        invalid: after(&stdout, "invalid "),
        over_budget: after(&stdout, "over budget "),
        resets: stdout.matches("reset (Watchdog)").count(),
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("the log folder")
        .map(|e| e.expect("entry").path())
        .collect();
    files.sort();
    (board, files)
}

/// The model's self-test as `cargo alvs budget --boot --json` reports it.
fn prediction(elf: &[u8]) -> Prediction {
    let frames = self_test(elf).expect("the self-test runs on the model");
    Prediction {
        stages: STAGE_NAMES.iter().map(|s| s.to_string()).collect(),
        frames: frames
            .iter()
            .map(|f| PredictedFrame {
                frame: f.line.frame,
                afs: f.line.afs,
                nominal: f.cycles.nominal.to_vec(),
                pessimistic: f.cycles.pessimistic.to_vec(),
            })
            .collect(),
        worst_case: None,
    }
}

/// Reads the session as `cargo alvs log` does; checks what every session shares.
fn summary(board: &Board, files: &[PathBuf], elf: &[u8]) -> (Log, LogReport) {
    assert_eq!(files.len(), 2, "one file per tab: {files:?}");
    let name = files[0].file_name().unwrap().to_string_lossy().into_owned();
    assert!(
        name.starts_with("alvs-firmware_STM32F427VITx_") && name.ends_with("_channel0.txt"),
        "{name}"
    );
    // from one of the files, as a user would point at it
    let log = Log::read(&files[1]).expect("the log reads");
    let r = LogReport::of(&log, Ok(prediction(elf))).expect("a summary");
    assert_eq!(r.sources.len(), 2, "both tabs read");
    assert_eq!(r.skipped.lines, 0, "{:?}", r.skipped);
    assert!(r.other_versions.is_empty());
    assert_eq!(r.boots.len(), board.resets + 1, "{:?}", r.boots);
    let t = &r.telemetry;
    assert_eq!(
        t.records as u64, board.processed,
        "records = frames processed"
    );
    assert_eq!(t.missing, 0);
    assert_eq!(r.counters.dropped, board.dropped);
    assert_eq!(r.counters.invalid, board.invalid);
    assert_eq!(r.counters.over_budget, board.over_budget);
    let c = t.cycles.as_ref().expect("cycles");
    assert!(c.min as f64 <= c.mean && c.mean <= c.p99 as f64 && c.p99 <= c.max);
    assert!(r.counters.cycles_max <= Some(c.max));
    let frames_in_states: usize = t.states.iter().map(|s| s.frames).sum();
    assert_eq!(frames_in_states, t.records);
    // the boot self-test: the virtual board counts with the pessimistic model
    let bench = r.bench.as_ref().expect("bench lines");
    assert_eq!(bench.rows.len(), 4 * 6, "4 frames, 5 stages and the total");
    assert!(bench.afs_differ.is_empty());
    for row in &bench.rows {
        if let Some(ratio) = row.ratio(row.pessimistic) {
            assert!((ratio - 1.0).abs() < 1e-3, "{row:?}");
            assert!(row.ratio(row.nominal).unwrap() > 1.0, "{row:?}");
        }
    }
    (log, r)
}

#[test]
fn a_clean_session_sums_to_the_boards_counters() {
    let Some(elf) = firmware() else { return };
    let (board, files) = session(
        "clean",
        &[
            "--clip",
            "data/clips/real_bird_attack.y8",
            "--seconds",
            "1.5",
        ],
    );
    let (log, r) = summary(&board, &files, &elf);
    assert_eq!(
        r.telemetry.records as u64, board.captured,
        "nothing dropped"
    );
    assert_eq!((r.counters.seconds, r.telemetry.runs), (1, 1));
    assert!(r.events.is_empty(), "{:?}", r.events);
    assert!(r.rejoined == 0);
    // the looming clip alerts; the records say so through X̄
    let alerts = log.records().filter(|rec| rec.alert()).count();
    assert!(alerts > 0);
    assert_eq!(r.telemetry.alerts.frames, alerts);
    assert!(r.telemetry.fields.max >= 1);
    assert!(r.boots[0]
        .camera
        .as_deref()
        .is_some_and(|c| c.starts_with("camera: OV7670")));
}

#[test]
fn a_camera_stall_is_an_error_then_a_new_run_of_frames() {
    let Some(elf) = firmware() else { return };
    let (board, files) = session(
        "stall",
        &[
            "--seconds",
            "1.6",
            "--stall-at",
            "0.7",
            "--stall-for",
            "0.4",
        ],
    );
    let (_, r) = summary(&board, &files, &elf);
    assert_eq!(r.boots.len(), 1);
    assert_eq!(
        r.telemetry.runs, 2,
        "the model primes again after the stall"
    );
    let texts: Vec<&str> = r.events.iter().map(|q| q.text.as_str()).collect();
    assert_eq!(
        texts,
        [
            "ERROR camera stall: motors stopped; the model primes again",
            "recovered: frames flow again"
        ]
    );
}

#[test]
fn a_fault_and_its_watchdog_reset_are_a_second_boot() {
    let Some(elf) = firmware() else { return };
    let (board, files) = session("fault", &["--seconds", "2.2", "--fault-at", "1.3"]);
    assert_eq!(board.resets, 1);
    let (_, r) = summary(&board, &files, &elf);
    assert_eq!(r.boots.len(), 2);
    let ended = r.boots[0].ended_after.as_ref().expect("what reset it");
    assert_eq!(
        ended.text,
        "FAULT: motors stopped; waiting for the watchdog reset"
    );
    assert!(r.boots[1].ended_after.is_none());
    assert_eq!(r.telemetry.runs, 2);
    assert_eq!(r.counters.seconds, 1, "the first boot's summary");
    // the second boot's self-test is the first's
    assert!(r.bench.as_ref().unwrap().other_boots.is_empty());
}

#[test]
fn the_budget_tools_boot_json_is_what_the_log_reader_reads() {
    let Some(elf) = firmware() else { return };
    let out = Command::new(env!("CARGO_BIN_EXE_alvs-budget"))
        .args(["--boot", "--json"])
        .output()
        .expect("alvs-budget runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let p = Prediction::from_json(&String::from_utf8_lossy(&out.stdout)).expect("it reads");
    let expected = prediction(&elf);
    assert_eq!((&p.stages, &p.frames), (&expected.stages, &expected.frames));
    let worst = p.worst_case.expect("docs/budget.md documents a worst case");
    assert_eq!(worst.source, "docs/budget.md");
    assert!(worst.nominal < worst.pessimistic);
}

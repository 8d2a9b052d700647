//! `alvs log` on hand-made logs in cargo-embed's format (the virtual board's real sessions are
//! read in cycles/tests/rtt_log.rs): the numbers of a healthy session, and bad logs that lose
//! nothing silently — a truncated line, garbage between and inside lines, a reset in the
//! middle, another firmware version, a panic, no telemetry at all — each skipped line counted
//! and quoted, every error one line. Without the cycle model (`--no-model`): that half is the
//! cycles crate's test.

use std::path::{Path, PathBuf};
use std::process::{Output, Stdio};

use alvs_tasks::model::fsm::State;
use alvs_tasks::robot::health::Summary;
use alvs_tasks::robot::self_test::BenchLine;
use alvs_tasks::robot::telemetry::{AfTelemetry, Record};
use serde_json::Value;

mod common;
use common::{alvs, succeed, tmp};

const VERSION: &str = env!("CARGO_PKG_VERSION");

fn banner(version: &str) -> String {
    format!("alvs-firmware {version} on the Colias sense board (STM32F427VI)")
}

/// The boot's lines up to the camera: banner, clocks, the four self-test frames.
fn boot(version: &str) -> Vec<String> {
    let mut v = vec![
        banner(version),
        "clocks: starting HSE 25000000 Hz -> SYSCLK 180000000 Hz".into(),
    ];
    for (frame, stages, afs) in [
        (0, [22926, 0, 0, 0, 3988], 0),
        (1, [236196, 192789, 224319, 24600, 4936], 1),
        (2, [236196, 197488, 555036, 25431, 4681], 2),
        (3, [236196, 218844, 354743, 24609, 4681], 1),
    ] {
        let line = BenchLine { frame, stages, afs }.to_string();
        v.push(line.trim_end().to_owned());
    }
    v.push("camera: OV7670 PID 0x76 VER 0x73, 12 registers written (6 read back OK)".into());
    v.push("running: model alvs = Table I ...; type h to hold them, g to let go".into());
    v
}

/// Second `second`'s summary: 30 frames, all processed.
fn summary(second: u32, dropped: u32, misses: u32) -> String {
    let s = Summary {
        second,
        frames: 30 + dropped,
        processed: 30,
        dropped,
        invalid: 0,
        overruns: 0,
        sync_errors: 0,
        cycles: Some((400_000, 500_000, 6_500_000)),
        misses,
        rtt_dropped: 0,
    };
    s.to_line().trim_end().to_owned()
}

/// Record `frame`: alerting on frames 20-24 (one field at column 70), escaping after.
fn record(frame: u32) -> String {
    let alert = (20..25).contains(&frame);
    let field = AfTelemetry {
        x: 70,
        y: 30,
        lplc2: 5000,
    };
    let r = Record {
        frame,
        afs: alert.then_some(field).into_iter().collect(),
        lplc2_sum: if alert { 5000 } else { 0 },
        strength_milli: if alert { 800 } else { 500 },
        threat_x_tenths: alert.then_some(700),
        state: if frame < 20 {
            State::Wander
        } else {
            State::Escape
        },
        cycles: 500_000 + frame,
    };
    r.to_line().trim_end().to_owned()
}

/// `lines` as cargo-embed saves a stamped channel: one poll's piece per line here, so each is
/// followed by the empty line cargo-embed writes after a piece; the session's first line has
/// no stamp.
fn embed(lines: &[String]) -> String {
    let mut s = String::new();
    for (i, l) in lines.iter().enumerate() {
        if i > 0 {
            s += &format!("10:00:{:02}.{:03}: ", i / 30 % 60, i * 33 % 1000);
        }
        s += l;
        s += "\n\n";
    }
    s
}

/// A session's two files in `dir`, as cargo-embed names them; returns the channel 0 file.
fn save(dir: &Path, ms: u64, log: &[String], telemetry: &[String]) -> PathBuf {
    let name = |tab| dir.join(format!("alvs-firmware_STM32F427VITx_{ms}_channel{tab}.txt"));
    std::fs::write(name(0), embed(log)).unwrap();
    std::fs::write(name(1), embed(telemetry)).unwrap();
    name(0)
}

/// A healthy 2-second session.
fn healthy() -> (Vec<String>, Vec<String>) {
    let mut log = boot(VERSION);
    log.push(summary(1, 0, 0));
    log.push(summary(2, 0, 0));
    (log, (0..60).map(record).collect())
}

/// `alvs log ARGS --no-model --json`'s summary.
fn json(args: &[&std::ffi::OsStr]) -> Value {
    let out = succeed(alvs().arg("log").args(args).args(["--no-model", "--json"]));
    serde_json::from_slice(&out.stdout).unwrap()
}

fn text(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// `alvs log ARGS` fails with one line containing `expect`.
fn fails(args: &[&std::ffi::OsStr], expect: &str) {
    let out = alvs()
        .arg("log")
        .args(args)
        .arg("--no-model")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} read");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains(expect), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn a_healthy_session_is_summed_and_drawn() {
    let d = tmp("log-healthy");
    let (log, tel) = healthy();
    // an older session in the same folder: the newest is read
    save(&d, 1_700_000_000_000, &boot(VERSION), &[record(0)]);
    save(&d, 1_800_000_000_000, &log, &tel);
    let v = json(&[d.as_os_str()]);
    assert_eq!(v["sources"].as_array().unwrap().len(), 2);
    assert!(v["sources"][1]
        .as_str()
        .unwrap()
        .ends_with("1800000000000_channel1.txt"));
    assert_eq!(v["counters"]["seconds"], 2);
    assert_eq!(v["counters"]["frames"], 60);
    assert_eq!(v["counters"]["over_budget"], 0);
    let t = &v["telemetry"];
    assert_eq!(
        (
            t["records"].as_u64(),
            t["runs"].as_u64(),
            t["missing"].as_u64()
        ),
        (Some(60), Some(1), Some(0))
    );
    assert_eq!(t["cycles"]["min"], 500_000);
    assert_eq!(t["cycles"]["max"], 500_059);
    assert_eq!(t["cycles"]["p99"], 500_059, "nearest rank of 60: the 60th");
    assert_eq!(t["states"][0]["state"], "wander");
    assert_eq!(t["states"][0]["frames"], 20);
    assert_eq!(t["states"][1]["state"], "escape");
    assert!((t["states"][1]["seconds"].as_f64().unwrap() - 40.0 / 30.0).abs() < 1e-9);
    assert_eq!(t["alerts"]["frames"], 5);
    assert_eq!(t["alerts"]["episodes"], 1);
    assert_eq!(t["alerts"]["first_frame"], 20);
    assert_eq!(t["fields"]["per_frame"][0], 55);
    assert_eq!(t["fields"]["per_frame"][1], 5);
    assert_eq!(v["boots"].as_array().unwrap().len(), 1);
    assert_eq!(v["bench"]["rows"].as_array().unwrap().len(), 24);
    assert_eq!(v["bench"]["rows"][11]["stage"], "total");
    assert_eq!(v["bench"]["rows"][11]["board"], 682_840);
    assert_eq!(v["skipped"]["lines"], 0);

    let png = d.join("png");
    let out = succeed(
        alvs()
            .arg("log")
            .arg(&d)
            .arg("--no-model")
            .arg("--png")
            .arg(&png),
    );
    let summary = text(&out);
    for part in [
        "firmware: 1 boot (",
        "frames (the firmware's 1 Hz summaries, 2 s): 60 ended, 60 processed, 0 dropped",
        "telemetry: 60 records in 1 run of frame numbers",
        "cycles per frame: min 500000, mean 500030, p99 500059, max 500059",
        "time per state (processed frames x 33.3 ms): wander 0.7 s (33.3 %), escape 1.3 s (66.7 %)",
        "alerts: 5 frames in 1 episode, the first at frame 20",
        "boot self-test (bench: lines of boot 1); the cycle model: left out (--no-model)",
        "skipped: 0 lines",
    ] {
        assert!(summary.contains(part), "{part:?} missing:\n{summary}");
    }
    for name in ["timeline.png", "fields.png", "cycles.png"] {
        let bytes = std::fs::read(png.join(name)).unwrap();
        assert!(bytes.starts_with(b"\x89PNG"), "{name}");
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn truncated_and_garbled_lines_are_counted_and_quoted() {
    let d = tmp("log-garbled");
    let (mut log, mut tel) = healthy();
    tel[30] = tel[30].replace("cyc=", "cyc=4#!&"); // garbage inside a record
    tel.insert(10, "\u{1b}[2J\u{1b}[H noise".into()); // garbage between records
    tel.push(record(60)[..18].to_owned()); // the session ended mid-line
    log.insert(3, "bench: frame 1 cycles retina 236196 attention".into());
    log.push("S 3 frames=30 processed=".into());
    let first = save(&d, 1_800_000_000_000, &log, &tel);
    let v = json(&[first.as_os_str()]);
    let s = &v["skipped"];
    assert_eq!(s["lines"], 5);
    let by_kind: Vec<(String, u64)> = s["by_kind"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p[0].as_str().unwrap().to_owned(), p[1].as_u64().unwrap()))
        .collect();
    assert_eq!(
        by_kind,
        [
            ("telemetry record".into(), 2),
            ("summary".into(), 1),
            ("bench line".into(), 1),
            ("unknown".into(), 1)
        ]
    );
    let quoted = s["first"].as_array().unwrap();
    assert_eq!(quoted.len(), 5);
    assert_eq!(quoted[0]["reason"], "missing field `attention`");
    assert!(quoted[0]["source"]
        .as_str()
        .unwrap()
        .ends_with("_channel0.txt"));
    assert_eq!(quoted[2]["text"], "\u{1b}[2J\u{1b}[H noise");
    assert_eq!(quoted[3]["reason"], "malformed number in `cyc`");
    assert_eq!(quoted[4]["text"], &record(60)[..18]);
    // 59 records read; frame 30's is the one missing from its run
    assert_eq!(v["telemetry"]["records"], 59);
    assert_eq!(v["telemetry"]["missing"], 1);
    assert_eq!(v["counters"]["seconds"], 2);

    let out = succeed(alvs().arg("log").arg(&first).arg("--no-model"));
    let summary = text(&out);
    assert!(
        summary
            .contains("skipped: 5 lines (2 telemetry record, 1 summary, 1 bench line, 1 unknown)"),
        "{summary}"
    );
    assert!(
        summary.contains("channel1:123: \"F 60 st=escape S=0\" (malformed number in `S`)"),
        "{summary}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_reset_in_the_middle_is_a_second_boot_and_its_cause_is_quoted() {
    let d = tmp("log-reset");
    let mut log = boot(VERSION);
    log.push(summary(1, 1, 1));
    log.push("FAULT: motors stopped; waiting for the watchdog reset".into());
    log.extend(boot(VERSION));
    log.push(summary(1, 0, 0));
    let mut tel: Vec<String> = (0..35).map(record).collect();
    tel.extend((0..30).map(record));
    let first = save(&d, 1_800_000_000_000, &log, &tel);
    let v = json(&[first.as_os_str()]);
    let boots = v["boots"].as_array().unwrap();
    assert_eq!(boots.len(), 2);
    assert_eq!(
        boots[0]["ended_after"]["text"],
        "FAULT: motors stopped; waiting for the watchdog reset"
    );
    // 10 lines before it, each followed by cargo-embed's empty line
    assert_eq!(boots[1]["line"], 2 * 10 + 1, "the second banner's line");
    assert_eq!(v["telemetry"]["runs"], 2);
    assert_eq!(v["telemetry"]["records"], 65);
    assert_eq!(v["counters"]["dropped"], 1);
    assert_eq!(v["counters"]["over_budget"], 1);
    assert_eq!(v["telemetry"]["over_budget"], 0, "the records say none");
    assert_eq!(v["bench"]["other_boots"].as_array().unwrap().len(), 0);
    let out = succeed(alvs().arg("log").arg(&first).arg("--no-model"));
    assert!(
        text(&out)
            .contains("; reset after \"FAULT: motors stopped; waiting for the watchdog reset\""),
        "{}",
        text(&out)
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_log_of_another_version_says_so() {
    let d = tmp("log-version");
    let (mut log, tel) = healthy();
    log[0] = banner("0.0.9");
    let first = save(&d, 1_800_000_000_000, &log, &tel);
    let v = json(&[first.as_os_str()]);
    assert_eq!(v["other_versions"], serde_json::json!(["0.0.9"]));
    assert_eq!(v["tools_version"], VERSION);
    let out = succeed(alvs().arg("log").arg(&first).arg("--no-model"));
    let expect = format!("a log of alvs-firmware 0.0.9: read with {VERSION}'s grammar");
    assert!(text(&out).contains(&expect), "{}", text(&out));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn piped_text_of_both_tabs_with_cut_and_wrapped_lines_reads_whole() {
    // copied from a terminal: no stamps, both tabs, a record cut by a poll, one wrapped at a
    // space, and a panic with its message
    let (log, tel) = healthy();
    let mut lines: Vec<String> = log;
    let cut = tel[5].clone();
    let wrapped = tel[6].clone();
    let at = wrapped.find(" X=").unwrap();
    lines.extend(tel[..5].iter().cloned());
    lines.push(cut[..15].to_owned());
    lines.push(cut[15..].to_owned());
    lines.push(wrapped[..at].to_owned());
    lines.push(wrapped[at + 1..].to_owned());
    lines.extend(tel[7..].iter().cloned());
    lines.push("panicked at src/main.rs:10:5:".into());
    lines.push("index out of bounds".into());
    let mut child = alvs()
        .args(["log", "-", "--no-model", "--json"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let input = lines.join("\n") + "\n";
    let mut stdin = child.stdin.take().unwrap();
    std::thread::spawn(move || {
        use std::io::Write;
        stdin.write_all(input.as_bytes()).unwrap();
    });
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["sources"], serde_json::json!(["standard input"]));
    assert_eq!(v["telemetry"]["records"], 60);
    assert_eq!(v["telemetry"]["missing"], 0);
    assert_eq!(v["rejoined"], 2);
    assert_eq!(v["skipped"]["lines"], 0, "{}", v["skipped"]);
    let events = v["events"].as_array().unwrap();
    assert_eq!(
        events.last().unwrap()["text"],
        "panicked at src/main.rs:10:5: index out of bounds"
    );
}

#[test]
fn no_telemetry_or_no_log_is_one_line() {
    let d = tmp("log-none");
    let camera = vec![
        banner(VERSION),
        "ERROR camera: no answer on SCCB (no capture; the watchdog retries by a reset)".into(),
    ];
    let first = save(&d, 1_800_000_000_000, &camera, &[]);
    fails(
        &[first.as_os_str()],
        "no telemetry (no frame record, no 1 Hz summary): its last error: \"ERROR camera: no answer on SCCB",
    );
    let empty = d.join("empty.txt");
    std::fs::write(&empty, "").unwrap();
    fails(
        &[empty.as_os_str()],
        "empty.txt: no telemetry (no frame record, no 1 Hz summary): it is empty",
    );
    let other = d.join("other.txt");
    std::fs::write(&other, "Hello from another program\nvalue = 3\n").unwrap();
    fails(&[other.as_os_str()], "2 lines, 0 of them the firmware's");
    let binary = d.join("binary.txt");
    std::fs::write(&binary, [0u8, 159, 146, 150, 255, 10, 70, 32]).unwrap();
    fails(&[binary.as_os_str()], "no telemetry");
    fails(
        &[d.join("missing").as_os_str()],
        "missing: No such file or directory",
    );
    let folder = d.join("no-logs");
    std::fs::create_dir_all(&folder).unwrap();
    fails(&[folder.as_os_str()], "no cargo-embed log in this folder");
    // no path: ./logs, which is not there
    let out = alvs().arg("log").current_dir(&folder).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("no logs/ folder here: cargo embed saves its sessions there"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

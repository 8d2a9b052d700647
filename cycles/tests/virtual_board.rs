//! The unmodified release firmware on the virtual Colias board (`alvs_cycles::system`): boot,
//! frames through DCMI and DMA into perception, motor frames on UART4, and the fault paths.
//! Each scenario is a second or two of simulated time.

use std::path::Path;

use alvs_cycles::budget::{read_clip, CLIPS_DIR};
use alvs_cycles::system::closed_loop::BottomBoard;
use alvs_cycles::system::{Board, Config, ResetCause};
use alvs_cycles::CLOCK_HZ;
use alvs_tasks::model::fsm::{Behaviour, FsmParams};
use alvs_tasks::robot::control::Control;
use alvs_tasks::robot::health::{Safety, PRIME_FRAMES};
use alvs_tasks::robot::motor::{self, BoardModel};
use alvs_tasks::robot::telemetry::Record;
use alvs_tasks::{Frame, Network, PIXELS};

mod common;
use common::{firmware, root};

const MS: u64 = CLOCK_HZ / 1000;

fn clip(name: &str) -> Vec<Vec<u8>> {
    let frames = read_clip(&root().join(CLIPS_DIR).join(name)).expect("clip");
    frames.iter().map(|f| f.to_vec()).collect()
}

/// A board whose camera loops over `frames`.
fn board(elf: &[u8], frames: Vec<Vec<u8>>, config: Config) -> Board {
    let source = Box::new(move |n: u64| frames[n as usize % frames.len()].clone());
    Board::new(elf, config, source).expect("board")
}

/// Grey frames with a little noise, so that nothing alerts and the robot wanders.
fn quiet_frames() -> Vec<Vec<u8>> {
    (0..8u32)
        .map(|k| {
            (0..PIXELS as u32)
                .map(|i| (120 + (i.wrapping_mul(2_654_435_761) >> (28 - k % 3)) % 8) as u8)
                .collect()
        })
        .collect()
}

/// Telemetry lines without their cycle field (the host build has no cycle counter).
fn without_cycles(line: &str) -> String {
    line.split(' ')
        .filter(|f| !f.starts_with("cyc="))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The motor frames in a byte stream (each ends with the protocol's END byte).
fn frames_of(bytes: &[u8]) -> Vec<Vec<u8>> {
    bytes
        .split_inclusive(|&b| b == motor::END)
        .filter(|f| f.last() == Some(&motor::END))
        .map(<[u8]>::to_vec)
        .collect()
}

fn stop_bytes() -> Vec<u8> {
    motor::stop_frames().iter().flatten().copied().collect()
}

#[test]
fn boots_to_the_banner_brings_the_camera_up_and_streams_frames() {
    let Some(elf) = firmware() else { return };
    let mut b = board(&elf, quiet_frames(), Config::default());
    b.run_for(600 * MS).expect("runs");
    let log = b.rtt(0);
    assert_eq!(b.rtt_names(), ["log", "telemetry"]);
    assert!(log.starts_with("alvs-firmware "), "{log}");
    assert!(log.contains("clocks: SYSCLK 180000000 Hz"), "{log}");
    assert!(log.contains("camera: OV7670 PID 0x76 VER 0x73"), "{log}");
    assert!(log.contains("running: model alvs"), "{log}");
    // the closed-loop mechanisms the firmware runs, named in its banner
    assert!(
        log.contains(
            "derotate 1, gate 3 of 4 arms (growing 50 %, or on 3 frames in a row), T_a 30 in a \
             quiet scene, blind border arms 1 (a side cut once the field crosses it 1) and cut \
             fields whole for T_s 1 and the short mode on an alert in a field's first d frames 1 \
             while standing"
        ),
        "{log}"
    );
    assert!(!log.contains("ERROR"), "{log}");
    assert!(b.log().resets.is_empty());
    let lines = b.rtt(1).lines().filter(|l| l.starts_with("F ")).count();
    assert!(lines >= 8, "{lines} telemetry lines:\n{}", b.rtt(1));
    // motors: the stop frames first, then (once primed) the enable sequence and wheel powers
    let sent: Vec<u8> = b.uart_sent().iter().map(|&(_, v)| v).collect();
    assert!(sent.starts_with(&stop_bytes()), "{sent:02X?}");
    let mut robot = BoardModel::default();
    for f in frames_of(&sent) {
        robot.apply(&f).expect("well-formed motor frame");
    }
    assert!(robot.enabled(), "wandering after priming");
}

#[test]
fn without_a_camera_it_reports_and_the_watchdog_retries() {
    let Some(elf) = firmware() else { return };
    let config = Config {
        camera_present: false,
        ..Config::default()
    };
    let mut b = board(&elf, quiet_frames(), config);
    b.run_for(700 * MS).expect("runs");
    let log = b.rtt(0);
    assert!(log.contains("ERROR camera: no sensor"), "{log}");
    let resets = &b.log().resets;
    assert_eq!(resets.len(), 1, "{resets:?}");
    assert_eq!(resets[0].1, ResetCause::Watchdog);
    assert_eq!(log.matches("alvs-firmware ").count(), 2, "{log}");
}

#[test]
fn a_clip_runs_bit_identical_to_the_host_build() {
    let Some(elf) = firmware() else { return };
    let frames = clip("test_black_approach.y8");
    let mut b = board(&elf, frames.clone(), Config::default());
    b.run_for(2_500 * MS).expect("runs");
    let captured: Vec<u64> = b.log().frames_captured.iter().map(|&(_, f)| f).collect();
    let telemetry: Vec<&str> = b.rtt(1).lines().collect();
    assert!(telemetry.len() >= 60, "{} lines", telemetry.len());
    assert!(
        b.rtt(0).contains("dropped=0 invalid=0 overruns=0"),
        "{}",
        b.rtt(0)
    );

    // the same frames through the host build of the same task code
    let mut network = Network::alvs();
    let mut control = Control::new(FsmParams::default(), Behaviour::Escape);
    let mut safety = Safety::new();
    let mut expected_bytes: Vec<u8> = control.stop().iter().flatten().copied().collect();
    let mut alerts = 0;
    for (k, line) in telemetry.iter().enumerate() {
        let mut frame: Frame = [0; PIXELS];
        frame.copy_from_slice(&frames[captured[k] as usize % frames.len()]);
        let p = network.step(&frame);
        safety.frame(33 * k as u32);
        let enable = safety.fault().is_none() && safety.primed();
        let (command, out) = control.step(&p.vm, enable);
        // motor control reports the turn and the forward speed before it parks the network
        network.turned(control.last_turn_deg());
        network.driving(control.last_forward_mm_s());
        expected_bytes.extend(out.iter().flatten());
        let host = Record::from_perception(&p, command.state, 0).to_line();
        assert_eq!(
            without_cycles(line),
            without_cycles(host.trim_end()),
            "frame {k}"
        );
        alerts += usize::from(p.alert());
    }
    assert!(alerts > 0, "the clip looms: some frames alert");
    assert!(PRIME_FRAMES as usize <= telemetry.len());
    // every byte the firmware wrote to UART4 is the host's, in order
    let written: Vec<u8> = b.log().uart_writes.iter().map(|&(_, v)| v).collect();
    assert!(written.len() > 100);
    assert_eq!(written[..], expected_bytes[..written.len()]);
}

#[test]
fn a_camera_stall_stops_the_motors_and_frames_bring_them_back() {
    let Some(elf) = firmware() else { return };
    let mut b = board(&elf, quiet_frames(), Config::default());
    b.run_for(700 * MS).expect("runs");
    let stall = b.now();
    b.stall_camera(stall..stall + 400 * MS);
    b.run_for(700 * MS).expect("runs");
    let last_frame = b
        .log()
        .frames_captured
        .iter()
        .map(|&(t, _)| t)
        .filter(|&t| t < stall)
        .max()
        .expect("frames before the stall");
    let log = b.rtt(0);
    assert!(log.contains("ERROR camera stall: motors stopped"), "{log}");
    assert!(log.contains("recovered: frames flow again"), "{log}");
    // the disable frame is written within STALL_MS (100 ms) plus one supervisor period
    // (10 ms) of the last frame
    let disable = &motor::stop_frames()[0];
    let writes = &b.log().uart_writes;
    let at = writes
        .windows(disable.len())
        .position(|w| w.iter().map(|&(_, v)| v).eq(disable.iter().copied()) && w[0].0 > stall)
        .map(|i| writes[i].0)
        .expect("stop frames after the stall");
    let after = (at - last_frame) / MS;
    assert!(
        (100..=115).contains(&after),
        "stop frames {after} ms after the last frame"
    );
    assert!(
        b.log().resets.is_empty(),
        "perception resumed before the watchdog ran out"
    );
}

/// The bottom board's state after every byte UART4 sent so far.
fn wheels_after(b: &Board) -> BoardModel {
    let mut wheels = BottomBoard::default();
    wheels.hear(b.uart_sent().iter().map(|&(_, v)| v));
    *wheels.registers()
}

#[test]
fn a_hold_typed_on_rtt_stops_the_motors_and_g_lets_them_go() {
    let Some(elf) = firmware() else { return };
    let mut b = board(&elf, quiet_frames(), Config::default());
    b.run_for(700 * MS).expect("runs");
    assert!(wheels_after(&b).enabled(), "primed and wandering");
    b.rtt_type(b"h\n");
    b.run_for(100 * MS).expect("runs");
    assert!(
        b.rtt(0).contains("held: motors off ('g' lets go)"),
        "{}",
        b.rtt(0)
    );
    assert!(!wheels_after(&b).enabled(), "the stop frames went out");
    assert!(b.rtt(1).lines().last().is_some_and(|l| l.contains("st=")));
    b.run_for(300 * MS).expect("runs");
    assert!(!wheels_after(&b).enabled(), "still held");
    b.rtt_type(b"g\n");
    b.run_for(100 * MS).expect("runs");
    assert!(b.rtt(0).contains("let go"), "{}", b.rtt(0));
    assert!(wheels_after(&b).enabled(), "driving again, no re-priming");
    assert!(b.log().resets.is_empty());
}

#[test]
fn a_fault_stops_the_motors_then_the_watchdog_resets() {
    let Some(elf) = firmware() else { return };
    let mut b = board(&elf, quiet_frames(), Config::default());
    b.run_for(700 * MS).expect("runs");
    let fault = b.now();
    b.inject_undefined_instruction().expect("fault taken");
    b.run_for(800 * MS).expect("runs");
    let log = b.rtt(0);
    assert!(log.contains("FAULT: motors stopped"), "{log}");
    let sent: Vec<u8> = b
        .uart_sent()
        .iter()
        .filter(|&&(t, _)| t > fault)
        .map(|&(_, v)| v)
        .collect();
    let stop = stop_bytes();
    let found = sent.windows(stop.len()).position(|w| w == stop);
    assert!(found.is_some(), "stop frames after the fault: {sent:02X?}");
    let resets = &b.log().resets;
    assert_eq!(resets.len(), 1, "{resets:?}");
    assert_eq!(resets[0].1, ResetCause::Watchdog);
    let after = (resets[0].0 - fault) / MS;
    assert!(
        (400..=600).contains(&after),
        "reset {after} ms after the fault"
    );
    assert_eq!(
        log.matches("alvs-firmware ").count(),
        2,
        "booted again: {log}"
    );
}

#[test]
fn overruns_and_torn_frames_are_counted_and_never_delivered() {
    let Some(elf) = firmware() else { return };
    let mut b = board(&elf, quiet_frames(), Config::default());
    b.run_for(600 * MS).expect("runs");
    let t = b.now();
    // the DMA held off the bus for one line period inside the next frame's window
    let frame = 6_000_000;
    let next = (t / frame + 1) * frame + 1_000_000;
    b.hold_dma(next + 300_000..next + 340_000);
    // and the frame after it torn after 40 of its 144 lines
    let torn = (next + frame - 1_000_000) / frame;
    b.tear_frame(torn, 40);
    b.run_for(1_600 * MS).expect("runs");
    assert_eq!(b.dcmi_overruns(), 1);
    let summaries: Vec<&str> = b.rtt(0).lines().filter(|l| l.starts_with("S ")).collect();
    let total = |key: &str| -> u32 {
        summaries
            .iter()
            .filter_map(|l| {
                l.split(' ')
                    .find_map(|f| f.strip_prefix(key))
                    .and_then(|v| v.parse::<u32>().ok())
            })
            .sum()
    };
    assert_eq!(total("overruns="), 1, "{summaries:?}");
    assert_eq!(total("invalid="), 2, "{summaries:?}");
    assert_eq!(total("processed="), total("frames=") - 2, "{summaries:?}");
    assert!(b.log().resets.is_empty());
}

#[test]
fn the_cli_prints_the_rtt_tabs_and_the_timing_report_and_rejects_bad_clips() {
    if firmware().is_none() {
        return;
    }
    let exe = env!("CARGO_BIN_EXE_alvs-virtual");
    let out = std::process::Command::new(exe)
        .args(["--seconds", "0.8", "--telemetry", "3"])
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for part in [
        "── RTT up channel 0: log ──\nalvs-firmware ",
        "── RTT up channel 1: telemetry (last 3 of ",
        "── timing ──",
        "frame complete -> first motor byte: min ",
        "DMA2_STREAM1",
        "asleep (WFI)",
    ] {
        assert!(stdout.contains(part), "{part:?} missing:\n{stdout}");
    }

    let bad = std::env::temp_dir().join(format!("alvs-virtual-bad-{}.y8", std::process::id()));
    std::fs::write(&bad, vec![0u8; PIXELS + 5]).unwrap();
    let out = std::process::Command::new(exe)
        .arg("--clip")
        .arg(&bad)
        .output()
        .expect("runs");
    let _ = std::fs::remove_file(&bad);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("7133 bytes is not a whole number of 99x72 Y8 frames (7128 bytes each)"),
        "{stderr}"
    );

    // relative paths are the caller's, and a missing clip is one line
    let clips = root().join(CLIPS_DIR);
    let run_in = |dir: &Path, clip: &str| {
        std::process::Command::new(exe)
            .args(["--clip", clip, "--seconds", "0.3", "--telemetry", "0"])
            .current_dir(dir)
            .output()
            .expect("runs")
    };
    let out = run_in(&clips, "test_grating.y8");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = run_in(&clips, "data/clips/test_grating.y8");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "not the workspace's path");
    assert_eq!(
        stderr.trim_end(),
        "alvs-virtual: --clip data/clips/test_grating.y8: No such file or directory (os error 2)"
    );
}

#[test]
fn closed_loop_the_firmware_turns_away_from_an_obstacle_on_its_right() {
    use alvs_cycles::system::closed_loop::evasion_trial;
    let Some(elf) = firmware() else { return };
    let texture = alvs_sim::texture::parse("clutter:1").expect("texture");
    let e = evasion_trial(elf, Config::default(), 20.0, texture, 1);
    assert_eq!(e.error, None);
    let r = &e.result;
    let alert = r.first_alert_s.expect("the firmware saw it coming");
    assert!(
        alert < 5.0,
        "alert {alert} s, before the obstacle arrives (5 s)"
    );
    assert!(e.correct_side, "turned {} °", r.escape_turn_deg);
    assert!(
        r.escape_turn_deg < -60.0,
        "a left turn: {} °",
        r.escape_turn_deg
    );
}

/// The stack at boot (init and its self-benchmark) and while running, every task and interrupt
/// nesting, keeps the RAM budget's headroom: in its own CCM region and with the network's state
/// in the whole CCM (docs/budget.md, "RAM").
#[test]
fn the_stack_keeps_its_headroom_at_boot_and_running() {
    use alvs_cycles::budget::{CCM_BUDGET, RAM_HEADROOM};
    let Some(elf) = firmware() else { return };
    let mut b = board(&elf, clip("test_grating.y8"), Config::default());
    b.run_for(500 * MS).expect("boots");
    let boot = b.stack_high_water().unwrap();
    while !b.repaint_stack().unwrap() {
        b.run_for(1_000).unwrap();
    }
    b.run_for(1_500 * MS).expect("runs");
    let running = b.stack_high_water().unwrap();
    let machine = alvs_cycles::Machine::from_elf(&elf).unwrap();
    let ccm = machine.ram_report().used("CCM");
    let region = machine.stack().end - machine.stack().start;
    println!("CCM data {ccm} B; stack running {running} B, at boot {boot} B, of {region} B");
    // the frame step alone takes ≈ 4.6 KB (docs/budget.md); interrupts nest on top of it
    assert!((4_600..=6_144).contains(&running), "{running} B");
    assert!(boot >= running, "init's self-benchmark is the deepest");
    assert!(
        boot + RAM_HEADROOM <= region,
        "boot stack {boot} B: less than {RAM_HEADROOM} B under its {region} B region"
    );
    assert!(
        ccm + boot + RAM_HEADROOM <= CCM_BUDGET,
        "CCM {ccm} B + boot stack {boot} B: less than {RAM_HEADROOM} B under {CCM_BUDGET} B"
    );
}

#[test]
fn no_frame_is_dropped_when_vsync_follows_frame_complete_at_once() {
    // a sensor that sends only the window's 72 lines: VSYNC (start of blanking) comes right
    // after FRAME, long before perception is done; the late hand-off keeps every frame (with
    // the hand-off at VSYNC alone, every other frame was dropped: 14.5 a second)
    let Some(elf) = firmware() else { return };
    let config = Config {
        camera: alvs_cycles::system::CameraTiming {
            lines: 72,
            blank_fraction: 0.05,
            ..Default::default()
        },
        ..Config::default()
    };
    let mut b = board(&elf, clip("test_grating.y8"), config);
    b.run_for(2_200 * MS).expect("runs");
    let log = b.rtt(0);
    let summaries: Vec<&str> = log.lines().filter(|l| l.starts_with("S ")).collect();
    assert_eq!(summaries.len(), 2, "{log}");
    assert!(
        summaries[1].contains("frames=30 processed=30 dropped=0 invalid=0"),
        "{log}"
    );
    let frames = alvs_cycles::system::report::summary_total(log, "frames");
    assert_eq!(
        alvs_cycles::system::report::summary_total(log, "processed"),
        frames
    );
}

/// `line` with every run of digits as `#`: the shape of a line, whatever the cycle counts.
fn masked(line: &str) -> String {
    let mut out = String::new();
    for c in line.chars() {
        if !c.is_ascii_digit() {
            out.push(c);
        } else if !out.ends_with('#') {
            out.push('#');
        }
    }
    out
}

#[test]
fn the_bring_up_guide_shows_what_a_healthy_boot_prints() {
    if firmware().is_none() {
        return;
    }
    let doc = std::fs::read_to_string(root().join("docs/bringup.md")).expect("docs/bringup.md");
    let start = doc
        .find("<!-- boot-log:start -->\n```text\n")
        .expect("start marker");
    let end = doc.find("```\n<!-- boot-log:end -->").expect("end marker");
    let shown = &doc[start + "<!-- boot-log:start -->\n```text\n".len()..end];
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_alvs-virtual"))
        .args(["--seconds", "1.3", "--telemetry", "3"])
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let printed = &stdout[..stdout.find("── timing ──").expect("the timing report")];
    let (shown, printed): (Vec<String>, Vec<String>) = (
        shown.lines().map(masked).collect(),
        printed.lines().map(masked).collect(),
    );
    assert_eq!(
        shown, printed,
        "docs/bringup.md's boot differs from `cargo alvs virtual --seconds 1.3 --telemetry 3`:\n{stdout}"
    );
}

/// Swarm mode without reflashing (issue 31): `s` typed on RTT down channel 0 switches motor
/// control to the swarm's behaviour, which spins on the looming clip where the boot's escape
/// takes off; `e` switches back.
#[test]
fn swarm_mode_typed_on_rtt_spins_on_a_looming_clip_instead_of_escaping() {
    let Some(elf) = firmware() else { return };
    let states = |typed: &[u8]| {
        let mut b = board(&elf, clip("test_black_approach.y8"), Config::default());
        b.run_for(100 * MS).expect("boots");
        b.rtt_type(typed);
        b.run_for(4_000 * MS).expect("runs");
        let log = b.rtt(0).to_owned();
        let states: std::collections::BTreeSet<String> = b
            .rtt(1)
            .lines()
            .filter_map(|l| l.split_whitespace().find_map(|w| w.strip_prefix("st=")))
            .map(str::to_owned)
            .collect();
        (log, states)
    };
    let (log, escape) = states(b"");
    assert!(log.contains("behaviour escape (type s"), "{log}");
    assert!(
        escape.contains("long_takeoff") || escape.contains("short_takeoff"),
        "{escape:?}"
    );
    assert!(!escape.contains("spin"), "{escape:?}");
    let (log, swarm) = states(b"s\n");
    assert!(log.contains("behaviour: swarm"), "{log}");
    assert!(swarm.contains("spin"), "{swarm:?}");
    for s in ["long_takeoff", "short_takeoff", "escape"] {
        assert!(!swarm.contains(s), "{s} in swarm mode: {swarm:?}");
    }
    let (log, back) = states(b"e\n");
    assert!(log.contains("behaviour: escape (s for"), "{log}");
    assert!(!back.contains("spin"), "{back:?}");
}

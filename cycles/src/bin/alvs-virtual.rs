//! `alvs-virtual`: the release firmware on the virtual Colias board (what `cargo alvs virtual`
//! runs). Builds the firmware, boots it from its reset vector, feeds its camera a clip or a
//! grey scene, prints the RTT tabs as `cargo embed` shows them and a timing report.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use alvs_cycles::budget::{build_firmware, read_clip};
use alvs_cycles::system::{Board, CameraTiming, Config, Report, HEIGHT, WIDTH};
use alvs_cycles::CLOCK_HZ;
use clap::Parser;

/// Runs the unmodified firmware ELF on a virtual Colias sense board and reports its timing.
#[derive(Parser)]
#[command(
    version,
    about = "Runs the unmodified firmware ELF on a virtual Colias sense board: RTT tabs and a timing report"
)]
struct Args {
    /// Camera input: a raw 99x72 Y8 clip (looped); without it a still grey scene with sensor
    /// noise.
    #[arg(long, value_name = "FILE")]
    clip: Option<PathBuf>,
    /// Simulated time, seconds.
    #[arg(long, default_value_t = 3.0)]
    seconds: f64,
    /// Fraction of the frame period the camera's VSYNC blanks (OV7670 VGA timing: 0.06).
    #[arg(long, default_value_t = 0.06)]
    blanking: f64,
    /// HREF lines the camera sends per frame (QCIF: 144; the DCMI crops 72).
    #[arg(long, default_value_t = 144)]
    lines: u16,
    /// Camera frame rate, frames per second.
    #[arg(long, default_value_t = 30.0)]
    fps: f64,
    /// The board without its camera (SCCB unanswered).
    #[arg(long)]
    no_camera: bool,
    /// Stop the camera at this time, seconds (for --stall-for seconds).
    #[arg(long, value_name = "S")]
    stall_at: Option<f64>,
    /// Length of the camera stall, seconds.
    #[arg(long, value_name = "S", default_value_t = 0.5)]
    stall_for: f64,
    /// Raise the fault a panic ends with (an undefined instruction) at this time, seconds.
    #[arg(long, value_name = "S")]
    fault_at: Option<f64>,
    /// Telemetry lines to print (the last N).
    #[arg(long, default_value_t = 10)]
    telemetry: usize,
    /// Closed loop instead of a clip: the evasion trial of `cargo alvs evasion` with the
    /// firmware as the tested robot's brain; an obstacle approaches from this bearing, degrees
    /// (positive = right).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    evasion: Option<f64>,
    /// Wall texture of the evasion arena (as `cargo alvs evasion --background`).
    #[arg(long, default_value = "clutter:1")]
    background: String,
    /// Folder for the evasion picture.
    #[arg(long, value_name = "DIR", default_value = "out/virtual")]
    out: PathBuf,
    /// Also save the session's RTT channels into this folder exactly as `cargo embed` does with
    /// `log_enabled` (one file per tab, `alvs-firmware_STM32F427VITx_<unix ms>_channel<tab>.txt`),
    /// for `cargo alvs log`; the probe then reads RTT as often as cargo-embed does (50 ms).
    #[arg(long, value_name = "DIR")]
    embed_log: Option<PathBuf>,
    /// How often the virtual probe reads RTT, ms (default 1; 50, cargo-embed's, with
    /// --embed-log). The firmware drops a line that does not fit its channel's buffer.
    #[arg(long, value_name = "MS")]
    rtt_poll_ms: Option<f64>,
    /// Instead of one run: dropped frames per second for each of these blanking fractions
    /// (comma-separated), at the given --lines.
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    sweep_blanking: Vec<f64>,
}

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("alvs-virtual: {e}");
            ExitCode::FAILURE
        }
    }
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the crate sits in the workspace")
}

/// The camera's frames: the clip's, or grey with ±4 levels of noise.
fn frames(args: &Args) -> Result<Vec<Vec<u8>>, String> {
    let size = WIDTH * HEIGHT;
    match &args.clip {
        Some(path) => Ok(read_clip(path)
            .map_err(|e| format!("--clip {e}"))?
            .iter()
            .map(|f| f.to_vec())
            .collect()),
        None => Ok((0..8u32)
            .map(|k| {
                (0..size as u32)
                    .map(|i| (124 + (i.wrapping_mul(2_654_435_761).rotate_left(k) >> 29)) as u8)
                    .collect()
            })
            .collect()),
    }
}

fn config(args: &Args, blanking: f64) -> Result<Config, String> {
    if !(0.01..0.9).contains(&blanking) {
        return Err(format!(
            "--blanking {blanking}: must be in 0.01..0.9 (VSYNC needs a pulse)"
        ));
    }
    if args.lines < 72 {
        return Err(format!(
            "--lines {}: the DCMI window takes 72 lines",
            args.lines
        ));
    }
    if !(1.0..=120.0).contains(&args.fps) {
        return Err(format!("--fps {}: must be in 1..=120", args.fps));
    }
    Ok(Config {
        camera: CameraTiming {
            frame_cycles: (CLOCK_HZ as f64 / args.fps) as u64,
            lines: args.lines,
            blank_fraction: blanking,
            ..CameraTiming::default()
        },
        camera_present: !args.no_camera,
        rtt_poll_cycles: cycles(rtt_poll_ms(args)? / 1e3).max(1),
    })
}

/// cargo-embed reads RTT every 50 ms (`RTT_POLL_INTERVAL` in its `rttui/app.rs`).
const EMBED_POLL_MS: f64 = 50.0;

/// The virtual probe's RTT poll interval, ms.
fn rtt_poll_ms(args: &Args) -> Result<f64, String> {
    let default = if args.embed_log.is_some() {
        EMBED_POLL_MS
    } else {
        1.0
    };
    match args.rtt_poll_ms.unwrap_or(default) {
        ms if (0.01..=1000.0).contains(&ms) => Ok(ms),
        ms => Err(format!("--rtt-poll-ms {ms}: must be in 0.01..=1000")),
    }
}

fn board(elf: &[u8], frames: &[Vec<u8>], config: Config) -> Result<Board, String> {
    let frames = frames.to_vec();
    let source = Box::new(move |n: u64| frames[n as usize % frames.len()].clone());
    Board::new(elf, config, source).map_err(|e| e.to_string())
}

/// The firmware's RTIC tasks behind each handler (src/main.rs: the bound tasks, and the
/// dispatchers of the software tasks by priority).
fn tasks_of(handler: &str) -> Option<&'static str> {
    Some(match handler {
        "Thread" => "init, idle",
        "UART4" => "uart4",
        "DMA2_STREAM1" => "dma_lines",
        "DCMI" => "dcmi",
        "SPI4" => "priority 1: telemetry, summary",
        "SPI5" => "priority 2: perception",
        "SPI6" => "priority 3: motor_control, supervisor",
        "SysTick" => "monotonic timer",
        "HardFault" => "fault: stop motors",
        _ => return None,
    })
}

/// Time by which `init` has finished (boot, self-benchmark, camera set-up: ≈ 0.2 s).
const BOOTED_S: f64 = 0.5;

fn cycles(seconds: f64) -> u64 {
    (seconds.max(0.0) * CLOCK_HZ as f64) as u64
}

fn run(args: &Args) -> Result<(), String> {
    if !(0.0..=600.0).contains(&args.seconds) {
        return Err(format!("--seconds {}: must be in 0..=600", args.seconds));
    }
    if args.embed_log.is_some() && (args.evasion.is_some() || !args.sweep_blanking.is_empty()) {
        return Err(
            "--embed-log saves one plain run: not with --evasion or --sweep-blanking".into(),
        );
    }
    let frames = frames(args)?;
    let elf_path = build_firmware(root()).map_err(|e| e.to_string())?;
    let elf =
        std::fs::read(&elf_path).map_err(|e| format!("cannot read {}: {e}", elf_path.display()))?;
    if !args.sweep_blanking.is_empty() {
        return sweep(args, &elf, &frames);
    }
    if let Some(bearing) = args.evasion {
        return evasion(args, elf, bearing);
    }
    let mut b = board(&elf, &frames, config(args, args.blanking)?)?;
    if let Some(at) = args.stall_at {
        b.stall_camera(cycles(at)..cycles(at + args.stall_for));
    }
    let end = cycles(args.seconds);
    // the boot's stack apart from the running tasks': repaint once init is long done
    let mut boot_stack = None;
    let booted = cycles(BOOTED_S);
    if end > booted && args.fault_at.is_none_or(|t| cycles(t) > booted) {
        b.run_until(booted).map_err(|e| e.to_string())?;
        boot_stack = Some(b.stack_high_water().map_err(|e| e.to_string())?);
        while !b.repaint_stack().map_err(|e| e.to_string())? {
            b.run_for(1_000).map_err(|e| e.to_string())?;
        }
    }
    // the wall clock when the virtual probe attached, as cargo-embed notes it
    let start_ms = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_millis() as u64);
    if let Some(at) = args.fault_at.filter(|&t| cycles(t) < end) {
        b.run_until(cycles(at)).map_err(|e| e.to_string())?;
        b.inject_undefined_instruction()
            .map_err(|e| e.to_string())?;
    }
    b.run_until(end).map_err(|e| e.to_string())?;

    println!("── RTT up channel 0: log ──");
    print!("{}", b.rtt(0));
    let telemetry: Vec<&str> = b.rtt(1).lines().collect();
    let shown = args.telemetry.min(telemetry.len());
    println!(
        "── RTT up channel 1: telemetry (last {shown} of {} lines) ──",
        telemetry.len()
    );
    for l in &telemetry[telemetry.len() - shown..] {
        println!("{l}");
    }
    println!("── timing ──");
    let mut report = Report::of(&b);
    report.boot_stack_bytes = boot_stack.filter(|_| b.log().resets.is_empty());
    for l in &mut report.load {
        if let Some(tasks) = tasks_of(&l.name) {
            l.name = format!("{} ({tasks})", l.name);
        }
    }
    print!("{report}");
    if let Some(dir) = &args.embed_log {
        let files = alvs_cycles::system::embed_log::write(&b, dir, start_ms)
            .map_err(|e| format!("--embed-log {}: {e}", dir.display()))?;
        println!("── cargo-embed log ──");
        for f in files {
            println!("{}", f.display());
        }
    }
    Ok(())
}

/// One evasion trial with the firmware in the loop; prints the outcome.
fn evasion(args: &Args, elf: Vec<u8>, bearing: f64) -> Result<(), String> {
    use alvs_cycles::system::closed_loop::{evasion_trial, Evasion};
    if !(-35.0..=35.0).contains(&bearing) {
        return Err(format!(
            "--evasion {bearing}: the bearing must be in -35..=35 degrees"
        ));
    }
    let texture = alvs_sim::texture::parse(&args.background).map_err(|e| e.to_string())?;
    let Evasion {
        result,
        correct_side,
        error,
    } = evasion_trial(elf, config(args, args.blanking)?, bearing, texture, 1);
    if let Some(e) = error {
        return Err(format!("the virtual board stopped: {e}"));
    }
    println!(
        "evasion with the firmware in the loop: obstacle at {bearing:+.1}°, first alert {}, turned {:+.0}° ({:?}), {}, {}, closest {:.0} mm",
        result
            .first_alert_s
            .map_or_else(|| "never".to_owned(), |s| format!("after {s:.2} s")),
        result.escape_turn_deg,
        result.side(),
        if correct_side { "correct side" } else { "WRONG side" },
        if result.collided() { "COLLIDED" } else { "no collision" },
        result.min_distance_mm[0]
    );
    let path = args.out.join(format!("evasion_{bearing:+.0}.png"));
    picture(&result, bearing, correct_side, &path)?;
    println!("picture: {}", path.display());
    Ok(())
}

/// Top-down view of the trial: the obstacle's path in grey, the firmware robot's in colour.
fn picture(
    r: &alvs_sim::encounter::EncounterResult,
    bearing: f64,
    correct_side: bool,
    path: &Path,
) -> Result<(), String> {
    use alvs_sim::encounter::tested_start;
    use alvs_sim::{TopDown, World};
    let mut td = TopDown::new(&World::default().arena, 0.6);
    td.title(&format!(
        "firmware on the virtual board: obstacle at {bearing:+.0} deg, {}, {}",
        if correct_side {
            "correct side"
        } else {
            "wrong side"
        },
        if r.collided() {
            "collided"
        } else {
            "no collision"
        }
    ));
    let grey = [150, 150, 150];
    if let Some(o) = r.trails.get(1) {
        td.trail(o, grey);
        if let Some(s) = o.first() {
            td.mark(s.0, s.1, grey);
        }
    }
    let colour = [200, 40, 40];
    td.trail(&r.trails[0], colour);
    if let Some(e) = r.trails[0].last() {
        td.mark(e.0, e.1, colour);
    }
    td.robot(&tested_start(), [255, 255, 255]);
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    }
    td.into_canvas()
        .save_png(path)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn sweep(args: &Args, elf: &[u8], frames: &[Vec<u8>]) -> Result<(), String> {
    println!(
        "{} HREF lines a frame, window of 72 from line 0, {:.0} fps, {} s each",
        args.lines, args.fps, args.seconds
    );
    println!("blanking  dropped/s  processed/s  latency mean ms");
    for &blanking in &args.sweep_blanking {
        let mut b = board(elf, frames, config(args, blanking)?)?;
        b.run_for(cycles(args.seconds)).map_err(|e| e.to_string())?;
        let r = Report::of(&b);
        // the firmware's summary lines cover whole seconds after boot
        let seconds = b
            .rtt(0)
            .lines()
            .filter(|l| l.starts_with("S "))
            .count()
            .max(1) as f64;
        let processed = alvs_cycles::system::report::summary_total(b.rtt(0), "processed");
        println!(
            "{blanking:>8.2}  {:>9.1}  {:>11.1}  {:>15}",
            r.dropped as f64 / seconds,
            processed as f64 / seconds,
            r.latency()
                .map_or_else(|| "-".to_owned(), |(_, mean, _)| format!("{mean:.2}"))
        );
    }
    Ok(())
}

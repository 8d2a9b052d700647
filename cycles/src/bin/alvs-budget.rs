//! `alvs-budget`: the firmware's frame budget on the Cortex-M4 cycle model (what
//! `cargo alvs budget` runs). Builds the firmware, runs its exported bench entry on the
//! constructed worst cases and the shared clips, checks every output against the host build,
//! and prints the table (or `--json` for tooling).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use alvs_cycles::budget::{
    build_firmware, clips, ms, run_scene, table, worst_cases, Bench, SceneResult, GATE_CLIPS,
    GATE_CYCLES, GOAL_CYCLES, PERIOD_CYCLES,
};
use clap::Parser;

/// Times one frame of the firmware's perception and control on a Cortex-M4 cycle model.
#[derive(Parser)]
#[command(
    version,
    about = "Times one frame of the firmware's perception and control on a Cortex-M4 cycle model"
)]
struct Args {
    /// Print only the summary as JSON: worst-case cycles (pessimistic, nominal), static RAM,
    /// stack peak.
    #[arg(long)]
    json: bool,
    /// Folder of the shared `.y8` clips.
    #[arg(long, value_name = "DIR", default_value = "../shared/stimuli")]
    clips: PathBuf,
    /// Run every clip of the folder (minutes), not only the CI gate's busiest four.
    #[arg(long)]
    all_clips: bool,
    /// Replace the table between the `budget-table` markers of this Markdown file.
    #[arg(long, value_name = "FILE")]
    write_doc: Option<PathBuf>,
}

const START: &str = "<!-- budget-table:start -->";
const END: &str = "<!-- budget-table:end -->";

fn main() -> ExitCode {
    match run(Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(a: Args) -> Result<(), String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .ok_or("no workspace root")?;
    let path = build_firmware(root)?;
    let elf = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut bench = Bench::new(&elf).map_err(|e| e.to_string())?;
    let ram = bench.machine().ram_report().clone();
    let mut scenes = worst_cases();
    let dir = if a.clips.is_relative() {
        root.join(&a.clips)
    } else {
        a.clips.clone()
    };
    if dir.is_dir() {
        let only: Option<&[&str]> = if a.all_clips { None } else { Some(&GATE_CLIPS) };
        scenes.extend(clips(&dir, only)?);
    } else if !a.json {
        eprintln!("note: {} is absent: constructed cases only", dir.display());
    }
    let mut results: Vec<SceneResult> = Vec::new();
    for s in &scenes {
        if !a.json {
            eprintln!("running {} ({} frames)", s.name, s.frames.len());
        }
        results.push(run_scene(&mut bench, s).map_err(|e| e.to_string())?);
    }
    let worst = results
        .iter()
        .max_by_key(|r| r.worst.pessimistic_total())
        .ok_or("no scene")?;
    let nominal = results
        .iter()
        .map(|r| r.worst.nominal_total())
        .max()
        .unwrap_or(0);
    let stack = results.iter().map(|r| r.stack).max().unwrap_or(0);
    let p = worst.worst.pessimistic_total();
    if a.json {
        println!(
            "{{\"worst_case_cycles_pessimistic\":{p},\"worst_case_cycles_nominal\":{nominal},\"ram_static_bytes\":{},\"stack_peak_bytes\":{stack}}}",
            ram.static_ram()
        );
        return Ok(());
    }
    let mut text = table(&results);
    text += &format!(
        "\nWorst case: **{}** frame {}: {p} pessimistic cycles = {:.2} ms at 180 MHz = {:.1} % of the \
         6.0 M-cycle period (gate: {GATE_CYCLES}); worst nominal {nominal}. Goal {GOAL_CYCLES} (2.0 ms).\n\
         Static RAM {} B (.data + .bss + .uninit), frame stack peak {stack} B.\n",
        worst.name,
        worst.worst_frame,
        ms(p),
        100.0 * p as f64 / PERIOD_CYCLES as f64,
        ram.static_ram()
    );
    text += &format!("\n{ram}");
    println!("{text}");
    if let Some(doc) = a.write_doc {
        let old = std::fs::read_to_string(&doc).map_err(|e| format!("{}: {e}", doc.display()))?;
        let (Some(i), Some(j)) = (old.find(START), old.find(END)) else {
            return Err(format!("{}: no {START} … {END} markers", doc.display()));
        };
        let new = format!("{}{START}\n{text}{}", &old[..i], &old[j..]);
        std::fs::write(&doc, new).map_err(|e| format!("{}: {e}", doc.display()))?;
        eprintln!("wrote {}", doc.display());
    }
    Ok(())
}

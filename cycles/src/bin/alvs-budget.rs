//! `alvs-budget`: the firmware's frame budget on the Cortex-M4 cycle model (what
//! `cargo alvs budget` runs). Builds the firmware, runs its exported bench entry on the
//! constructed worst cases and the looming clips of data/clips, checks every output against
//! the host build, and prints the table (or `--json` for tooling).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use alvs_cycles::budget::{
    build_firmware, clips, ms, profile_scene, run_scene, table, worst_cases, Bench, Profile,
    SceneResult, CLIPS_DIR, GATE_CLIPS, GATE_CYCLES, GOAL_CYCLES, PERIOD_CYCLES, STAGE_NAMES,
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
    /// Folder of `.y8` clips (default: the workspace's data/clips).
    #[arg(long, value_name = "DIR")]
    clips: Option<PathBuf>,
    /// Run every clip of the folder (minutes), not only the CI gate's busiest four.
    #[arg(long)]
    all_clips: bool,
    /// Replace the table between the `budget-table` markers of this Markdown file.
    #[arg(long, value_name = "FILE")]
    write_doc: Option<PathBuf>,
    /// Profile one scene instead (a constructed case or a clip, by name): the cycles of its
    /// worst frame per function symbol, per source line (innermost inlined frame, through
    /// `llvm-addr2line` when it is on the PATH) and per instruction.
    #[arg(long, value_name = "SCENE")]
    profile: Option<String>,
    /// Rows of each profile listing.
    #[arg(long, value_name = "N", default_value_t = 40)]
    top: usize,
    /// Only the boot self-test (the `bench:` lines the firmware prints at boot) on the model,
    /// per frame and stage, nominal and pessimistic, with the worst case documented in
    /// docs/budget.md (what `cargo alvs log` compares a board's log with); seconds, not
    /// minutes. With --json, as JSON.
    #[arg(long)]
    boot: bool,
}

/// The budget's document, where `--write-doc` puts the table and its worst case.
const DOC: &str = "docs/budget.md";
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
    if a.boot {
        let doc = std::fs::read_to_string(root.join(DOC)).unwrap_or_default();
        print!("{}", boot_text(&elf, documented_worst(&doc), a.json)?);
        return Ok(());
    }
    let mut bench = Bench::new(&elf).map_err(|e| e.to_string())?;
    let ram = bench.machine().ram_report().clone();
    let mut scenes = worst_cases();
    let dir = a.clips.clone().unwrap_or_else(|| root.join(CLIPS_DIR));
    let only: Option<&[&str]> = if a.all_clips { None } else { Some(&GATE_CLIPS) };
    scenes.extend(clips(&dir, only)?);
    if let Some(name) = &a.profile {
        if !a.all_clips {
            scenes.extend(clips(&dir, None)?.into_iter().filter(|s| &s.name == name));
        }
        let scene = scenes
            .iter()
            .find(|s| &s.name == name)
            .ok_or_else(|| format!("no scene {name}"))?;
        let p = profile_scene(&mut bench, scene).map_err(|e| e.to_string())?;
        print!("{}", profile_text(&p, &bench, &path, a.top));
        return Ok(());
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
        "\n{WORST} **{}** frame {}: {p} pessimistic cycles = {:.2} ms at 180 MHz = {:.1} % of the \
         6.0 M-cycle period (gate: {GATE_CYCLES}); worst nominal {nominal}. Goal {GOAL_CYCLES} ({:.1} ms).\n\
         Static RAM {} B (.data + .bss + .uninit): CCM {} B (the network), SRAM {} B; frame stack \
         peak {stack} B.\n",
        worst.name,
        worst.worst_frame,
        ms(p),
        100.0 * p as f64 / PERIOD_CYCLES as f64,
        ms(GOAL_CYCLES),
        ram.static_ram(),
        ram.used("CCM"),
        ram.used("SRAM"),
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

/// Source location of each address, from `llvm-addr2line` (`None` when it is not on the PATH):
/// the innermost inlined frame in the project's own code (frames in the Rust library are
/// skipped), as `module::function (file:line)`.
fn source_lines(elf: &Path, pcs: &[u32]) -> Option<Vec<String>> {
    use std::io::Write;
    use std::process::{Command, Stdio};
    let mut child = Command::new("llvm-addr2line")
        .args(["--output-style=LLVM", "-f", "-i", "-C", "-e"])
        .arg(elf)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .ok()?;
    let input: String = pcs.iter().map(|pc| format!("{pc:#x}\n")).collect();
    let mut stdin = child.stdin.take()?;
    let writer = std::thread::spawn(move || stdin.write_all(input.as_bytes()));
    let out = child.wait_with_output().ok()?;
    writer.join().ok()?.ok()?;
    // LLVM style: "function\nfile:line:column\n" per inlined frame (innermost first), a
    // blank line after each address
    let text = String::from_utf8_lossy(&out.stdout);
    let v: Vec<String> = text
        .split("\n\n")
        .filter(|b| !b.trim().is_empty())
        .map(|b| {
            let lines: Vec<&str> = b.lines().collect();
            let frames: Vec<(&str, &str)> = lines
                .chunks(2)
                .map(|c| (c[0], *c.get(1).unwrap_or(&"?")))
                .collect();
            let (f, at) = frames
                .iter()
                .find(|(_, at)| !at.starts_with("/rustc/") && !at.contains("/.cargo/"))
                .or(frames.first())
                .copied()
                .unwrap_or(("?", "?"));
            let at = at.rsplit_once(':').map_or(at, |(a, _col)| a);
            let file = at.rsplit('/').next().unwrap_or(at);
            // the last two path segments: `module::function`
            let segs: Vec<&str> = f.split("::").collect();
            let short = segs[segs.len().saturating_sub(2)..].join("::");
            format!("{short} ({file})")
        })
        .collect();
    (v.len() == pcs.len()).then_some(v)
}

/// The profile as text: per stage, per function symbol, per source line and per instruction.
fn profile_text(p: &Profile, bench: &Bench, elf: &Path, top: usize) -> String {
    use std::collections::HashMap;
    use std::fmt::Write;
    let total: u64 = p.pcs.iter().map(|c| c.pessimistic).sum();
    let share = |c: u64| 100.0 * c as f64 / total.max(1) as f64;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{} frame {}: {} pessimistic cycles ({} profiled), {} nominal",
        p.name,
        p.frame,
        p.cycles.pessimistic_total(),
        total,
        p.cycles.nominal_total()
    );
    for (name, c) in STAGE_NAMES.iter().zip(p.cycles.pessimistic) {
        let _ = writeln!(s, "  {name:<10} {c:>9}");
    }
    let list = |s: &mut String, title: &str, mut rows: Vec<(String, u64, u64)>| {
        rows.sort_by_key(|r| std::cmp::Reverse(r.1));
        let _ = writeln!(
            s,
            "\n{title}\n  {:>9} {:>6} {:>9}  what",
            "cycles", "%", "executed"
        );
        for (what, c, n) in rows.into_iter().take(top) {
            let _ = writeln!(s, "  {c:>9} {:>5.1}% {n:>9}  {what}", share(c));
        }
    };
    let funcs = bench.machine().functions();
    let mut per_fn: HashMap<String, (u64, u64)> = HashMap::new();
    for c in &p.pcs {
        let i = funcs.partition_point(|f| f.0 <= c.pc);
        let name = i
            .checked_sub(1)
            .map(|i| &funcs[i])
            .filter(|f| c.pc < f.0 + f.1)
            .map_or("?", |f| f.2.as_str());
        let e = per_fn.entry(name.to_owned()).or_default();
        e.0 += c.pessimistic;
        e.1 += c.count;
    }
    list(
        &mut s,
        "per function symbol (after inlining)",
        per_fn.into_iter().map(|(k, v)| (k, v.0, v.1)).collect(),
    );
    let pcs: Vec<u32> = p.pcs.iter().map(|c| c.pc).collect();
    if let Some(lines) = source_lines(elf, &pcs) {
        let mut per_line: HashMap<String, (u64, u64)> = HashMap::new();
        let mut per_src_fn: HashMap<String, (u64, u64)> = HashMap::new();
        for (c, l) in p.pcs.iter().zip(&lines) {
            let e = per_line.entry(l.clone()).or_default();
            e.0 += c.pessimistic;
            e.1 += c.count;
            let f = l.split(" (").next().unwrap_or(l);
            let e = per_src_fn.entry(f.to_owned()).or_default();
            e.0 += c.pessimistic;
            e.1 += c.count;
        }
        list(
            &mut s,
            "per source function (innermost inlined frame)",
            per_src_fn.into_iter().map(|(k, v)| (k, v.0, v.1)).collect(),
        );
        list(
            &mut s,
            "per source line",
            per_line.into_iter().map(|(k, v)| (k, v.0, v.1)).collect(),
        );
        let rows: Vec<(String, u64, u64)> = p
            .pcs
            .iter()
            .zip(&lines)
            .map(|(c, l)| {
                (
                    format!("{:#010x}  {:<32} {l}", c.pc, c.text),
                    c.pessimistic,
                    c.count,
                )
            })
            .collect();
        list(&mut s, "per instruction", rows);
    } else {
        let rows: Vec<(String, u64, u64)> = p
            .pcs
            .iter()
            .map(|c| {
                (
                    format!("{:#010x}  {}", c.pc, c.text),
                    c.pessimistic,
                    c.count,
                )
            })
            .collect();
        list(
            &mut s,
            "per instruction (llvm-addr2line not found: no source lines)",
            rows,
        );
    }
    s
}

/// How the worst-case sentence after the table begins.
const WORST: &str = "Worst case:";

/// The worst case a `--write-doc` run put in the document: scene, frame, pessimistic and
/// nominal cycles (`None` when the document has no such sentence).
fn documented_worst(doc: &str) -> Option<(String, u32, u64, u64)> {
    let line = doc.lines().find_map(|l| l.strip_prefix(WORST))?;
    let (scene, rest) = line.trim().strip_prefix("**")?.split_once("** frame ")?;
    let (frame, rest) = rest.split_once(": ")?;
    let (p, rest) = rest.split_once(" pessimistic cycles")?;
    let n = rest.split_once("worst nominal ")?.1.split('.').next()?;
    Some((
        scene.to_owned(),
        frame.parse().ok()?,
        p.parse().ok()?,
        n.parse().ok()?,
    ))
}

/// The boot self-test under the model, as a table or JSON, with the documented worst case.
fn boot_text(
    elf: &[u8],
    worst: Option<(String, u32, u64, u64)>,
    json: bool,
) -> Result<String, String> {
    use std::fmt::Write;
    let frames = alvs_cycles::budget::self_test(elf).map_err(|e| e.to_string())?;
    let mut s = String::new();
    if json {
        let list = |v: &[u64]| v.iter().map(u64::to_string).collect::<Vec<_>>().join(",");
        let frames: Vec<String> = frames
            .iter()
            .map(|f| {
                format!(
                    "{{\"frame\":{},\"afs\":{},\"nominal\":[{}],\"pessimistic\":[{}]}}",
                    f.line.frame,
                    f.line.afs,
                    list(&f.cycles.nominal),
                    list(&f.cycles.pessimistic)
                )
            })
            .collect();
        let worst = worst.map_or("null".to_owned(), |(scene, frame, p, n)| {
            format!(
                "{{\"scene\":\"{scene}\",\"frame\":{frame},\"pessimistic\":{p},\"nominal\":{n},\"source\":\"{DOC}\"}}"
            )
        });
        let _ = writeln!(
            s,
            "{{\"stages\":[{}],\"frames\":[{}],\"worst_case\":{worst}}}",
            STAGE_NAMES.map(|n| format!("\"{n}\"")).join(","),
            frames.join(",")
        );
        return Ok(s);
    }
    let _ = writeln!(
        s,
        "boot self-test on the cycle model (the ELF's built-in frames, in flash, as init runs them)"
    );
    let _ = writeln!(s, "frame  stage        nominal  pessimistic");
    for f in &frames {
        let rows = STAGE_NAMES
            .iter()
            .zip(f.cycles.nominal.iter().zip(&f.cycles.pessimistic));
        for (name, (n, p)) in rows {
            let _ = writeln!(s, "{:>5}  {name:<10} {n:>9} {p:>12}", f.line.frame);
        }
        let _ = writeln!(
            s,
            "{:>5}  {:<10} {:>9} {:>12}   {} AFs",
            f.line.frame,
            "total",
            f.cycles.nominal_total(),
            f.cycles.pessimistic_total(),
            f.line.afs
        );
    }
    match worst {
        Some((scene, frame, p, n)) => {
            let _ = writeln!(
                s,
                "worst case in {DOC}: {scene} frame {frame}, {p} pessimistic, {n} nominal cycles"
            );
        }
        None => {
            let _ = writeln!(
                s,
                "no worst case in {DOC} (cargo alvs budget --write-doc {DOC})"
            );
        }
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_documented_worst_case_reads_back() {
        let doc = "| a | b |\n\nWorst case: **test_black_approach** frame 49: 1784382 pessimistic cycles = 9.91 ms at 180 MHz = 29.7 % of the 6.0 M-cycle period (gate: 4800000); worst nominal 1681455. Goal 360000 (2.0 ms).\n";
        assert_eq!(
            documented_worst(doc),
            Some(("test_black_approach".into(), 49, 1_784_382, 1_681_455))
        );
        assert_eq!(documented_worst("no table"), None);
    }
}

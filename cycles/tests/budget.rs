//! The deadline and RAM budget of the firmware, proven on the Cortex-M4 cycle model: the
//! firmware's own release build, its exported `alvs_bench_step`, on constructed worst cases and
//! the busiest looming clips of `data/clips`. Gates CI:
//! - outputs bit-identical to the host build of the same code on every frame;
//! - counts identical run to run;
//! - pessimistic worst case ≤ 80 % of the 6.0 M-cycle frame period;
//! - static RAM and measured stack under their ceilings.

use std::path::Path;

use alvs_cycles::budget::{
    build_firmware, clips, ms, run_scene, table, worst_cases, Bench, SceneResult, CCM_BUDGET,
    CLIPS_DIR, GATE_CLIPS, GATE_CYCLES, GOAL_CYCLES, PERIOD_CYCLES, RAM_HEADROOM, SRAM_BUDGET,
};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace root")
}

fn elf() -> Vec<u8> {
    let path = build_firmware(root()).unwrap_or_else(|e| panic!("{e}"));
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn the_frame_fits_the_deadline_with_bit_identical_outputs() {
    let elf = elf();
    let mut bench = Bench::new(&elf).expect("the firmware exports the bench entry");
    let mut scenes = worst_cases();
    let dir = root().join(CLIPS_DIR);
    let found = clips(&dir, Some(&GATE_CLIPS)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        found.len(),
        GATE_CLIPS.len(),
        "gate clips missing in {}",
        dir.display()
    );
    scenes.extend(found);
    let results: Vec<SceneResult> = scenes
        .iter()
        .map(|s| run_scene(&mut bench, s).unwrap_or_else(|e| panic!("{e}")))
        .collect();
    println!("{}", table(&results));
    let worst = results
        .iter()
        .max_by_key(|r| r.worst.pessimistic_total())
        .expect("scenes ran");
    let (p, n) = (worst.worst.pessimistic_total(), worst.worst.nominal_total());
    println!(
        "worst case: {} frame {}: {p} pessimistic ({:.2} ms, {:.1} % of the period), {n} nominal; goal {GOAL_CYCLES}",
        worst.name,
        worst.worst_frame,
        ms(p),
        100.0 * p as f64 / PERIOD_CYCLES as f64
    );
    assert!(
        p <= GATE_CYCLES,
        "{}: {p} pessimistic cycles exceed 80 % of the period ({GATE_CYCLES})",
        worst.name
    );
    // the constructed cases hold every field the geometry keeps alive at once
    let looms = results.iter().find(|r| r.name == "four-looms").unwrap();
    assert_eq!(looms.max_afs, 4, "four-looms held {} fields", looms.max_afs);
}

#[test]
fn counts_are_identical_run_to_run() {
    let elf = elf();
    let scene = &worst_cases()[0];
    let a = run_scene(&mut Bench::new(&elf).unwrap(), scene).unwrap();
    let b = run_scene(&mut Bench::new(&elf).unwrap(), scene).unwrap();
    assert_eq!(
        (a.worst, a.worst_frame, a.mean_pessimistic),
        (b.worst, b.worst_frame, b.mean_pessimistic)
    );
}

/// The placement of memory.x and its budget (docs/budget.md, "RAM"): the network in CCM with
/// the stack, every DMA target and the RTT buffers in SRAM; each region keeps
/// [`RAM_HEADROOM`] under its budget with the stack of the deepest frame step (the virtual
/// board adds the interrupts and the boot, `the_stack_keeps_its_headroom_at_boot_and_running`).
#[test]
fn ram_keeps_its_headroom_in_each_region() {
    let elf = elf();
    let mut bench = Bench::new(&elf).unwrap();
    let report = bench.machine().ram_report().clone();
    println!("{report}");
    let stack = worst_cases()
        .iter()
        .take(2)
        .map(|s| run_scene(&mut bench, s).unwrap().stack)
        .max()
        .unwrap();
    let (ccm, sram) = (report.used("CCM"), report.used("SRAM"));
    let stack_region = bench.machine().stack();
    let stack_size = stack_region.end - stack_region.start;
    println!(
        "CCM data {ccm} B + frame stack {stack} B (stack region {stack_size} B); SRAM {sram} B"
    );
    assert!(
        report.region("CCM").is_some_and(|r| r.data >= 30_000),
        "the network's state is in CCM"
    );
    assert!(
        sram + RAM_HEADROOM <= SRAM_BUDGET,
        "SRAM statics {sram} B: less than {RAM_HEADROOM} B under {SRAM_BUDGET} B"
    );
    assert!(
        ccm + stack + RAM_HEADROOM <= CCM_BUDGET,
        "CCM {ccm} B + stack {stack} B: less than {RAM_HEADROOM} B under {CCM_BUDGET} B"
    );
    assert!(
        stack + RAM_HEADROOM <= stack_size,
        "frame stack {stack} B: less than {RAM_HEADROOM} B under its {stack_size} B region"
    );
}

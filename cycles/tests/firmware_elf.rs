//! Loads the real firmware ELF (built for thumbv7em-none-eabihf with the release profile, as the
//! robot gets it): symbols, the loaded image and the static RAM report. Reset is not run.

use std::path::{Path, PathBuf};

use alvs_cycles::budget::{build_firmware, BuildError};
use alvs_cycles::{memory, Machine, RamReport};

/// Builds the firmware (a no-op when it is up to date) and returns its ELF, or `None` when the
/// thumbv7em target is not installed.
fn firmware_elf() -> Option<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace root");
    match build_firmware(root) {
        Ok(path) => Some(path),
        Err(BuildError::TargetMissing) => {
            println!(
                "SKIPPED: {}; the firmware ELF cannot be built",
                BuildError::TargetMissing
            );
            None
        }
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn firmware_elf_loads_with_symbols_and_ram_report() {
    let Some(path) = firmware_elf() else { return };
    let elf = std::fs::read(&path).expect("firmware ELF");
    let m = Machine::from_elf(&elf).expect("loads");

    // Reset is a Thumb function: bit 0 set in the symbol, cleared in the address.
    let reset = m.symbol("Reset").expect("Reset");
    assert_eq!(m.symbol_raw("Reset"), Some(reset | 1));
    assert!(memory::FLASH.contains(&reset));
    assert!(m.symbol_size("Reset").unwrap() > 0);
    // The vector table as loaded in flash: its reset entry is Reset's Thumb address.
    let vector = m.symbol("__RESET_VECTOR").expect("__RESET_VECTOR");
    assert_eq!(m.read_u32(vector).unwrap(), reset | 1);
    assert_eq!(m.read_u32(memory::FLASH.start + 4).unwrap(), reset | 1);
    // The stack from memory.x: the bottom of CCM, growing down, so that an overflow runs
    // into the unmapped space below CCM and faults; the network's state lies above it.
    let stack = m.stack();
    assert_eq!(stack.start, memory::CCM.start, "an overflow leaves CCM");
    assert!(stack.end > stack.start && stack.end < memory::CCM.end);
    assert_eq!(
        m.read_u32(memory::FLASH.start).unwrap(),
        stack.end,
        "initial SP"
    );
    let (data, end) = (
        m.symbol("__sccmdata").unwrap(),
        m.symbol("__eccmdata").unwrap(),
    );
    assert!(
        stack.end <= data && data < end && end <= memory::CCM.end,
        "the network's state above the stack"
    );
    let network_size = m
        .read_u32(m.symbol("ALVS_BENCH_SIZES").expect("ALVS_BENCH_SIZES"))
        .unwrap();
    assert_eq!(
        m.ram_report().region("CCM").map_or(0, |r| r.data),
        network_size,
        "the network, and only it, in CCM"
    );
    assert_eq!(end - data, network_size);
    assert!(m.symbol("no such symbol").is_none());

    let report: &RamReport = m.ram_report();
    println!("{report}");
    let sram = report.region("SRAM").unwrap();
    assert!(sram.bss > 0, "the firmware has .bss in SRAM");
    assert!(report.flash.text > 1000 && report.flash.rodata > 0);
    assert_eq!(
        report.flash.data_load,
        sram.data + sram.code + report.region("CCM").unwrap().data
    );
    assert!(report.elsewhere.is_empty(), "{:?}", report.elsewhere);
    assert_eq!(
        report.static_ram(),
        report.regions.iter().map(|r| r.total()).sum::<u32>()
    );
    assert_eq!(RamReport::from_elf(&elf).unwrap(), *report);
}

#[test]
fn a_non_arm_or_broken_elf_is_an_error() {
    assert!(matches!(
        Machine::from_elf(b"not an elf"),
        Err(alvs_cycles::Error::Elf(_))
    ));
    // This test binary itself: an ELF, but not ARM.
    let me = std::fs::read(std::env::current_exe().unwrap()).unwrap();
    assert!(matches!(
        Machine::from_elf(&me),
        Err(alvs_cycles::Error::Elf(_))
    ));
}

#[test]
fn compiled_code_from_the_firmware_runs_deterministically() {
    let Some(path) = firmware_elf() else { return };
    let elf = std::fs::read(&path).expect("firmware ELF");
    let mut m = Machine::from_elf(&elf).expect("loads");
    // compiler_builtins' memcpy as LTO linked it: IT blocks, LDM/STM, unaligned tails.
    let memcpy = m.symbol("__aeabi_memcpy").expect("__aeabi_memcpy");
    let src: Vec<u8> = (0..1000u32).map(|i| (i * 7) as u8).collect();
    m.write(0x2001_0000, &src).unwrap();
    let mut runs = Vec::new();
    for _ in 0..2 {
        m.write(0x2002_0000, &[0; 1000]).unwrap();
        m.paint_stack(0xAAAA_5555).unwrap();
        let run = m
            .call(memcpy, &[0x2002_0001, 0x2001_0003, 997])
            .expect("runs");
        assert_eq!(m.read(0x2002_0001, 997).unwrap(), src[3..]);
        let stack = m.stack_high_water(0xAAAA_5555).unwrap();
        assert!(stack > 0 && stack < 256, "{stack}");
        assert!(run.nominal > run.instructions && run.pessimistic > run.nominal);
        runs.push((run, stack));
    }
    assert_eq!(runs[0], runs[1]);
}

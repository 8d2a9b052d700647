//! The STM32F427 memory map as modelled here (RM0090 section 2.3, "Memory map").

use std::ops::Range;

/// Main flash, 2 MiB; read-only and executable (writes are reported as errors).
pub const FLASH: Range<u32> = 0x0800_0000..0x0820_0000;
/// Core-coupled memory, 64 KiB; data only (the CCM is on the D-bus: no instruction fetch).
pub const CCM: Range<u32> = 0x1000_0000..0x1001_0000;
/// SRAM1+2+3, 192 KiB, contiguous.
pub const SRAM: Range<u32> = 0x2000_0000..0x2003_0000;
/// Private peripheral bus (ITM, DWT, FPB, SCS with SysTick/NVIC/SCB): plain RAM, except the DWT
/// page, whose CYCCNT returns the modelled cycle count.
pub const PPB: Range<u32> = 0xE000_0000..0xE010_0000;
/// The 4 KiB page holding the DWT registers.
pub const DWT_PAGE: u32 = 0xE000_1000;
/// DWT_CYCCNT.
pub const DWT_CYCCNT: u32 = 0xE000_1004;
/// SCB CPUID, preset to a Cortex-M4 r0p1 so code that checks it is satisfied.
pub const SCB_CPUID: u32 = 0xE000_ED00;
/// SCB CPACR, preset to full access for CP10/CP11 (the FPU enabled).
pub const SCB_CPACR: u32 = 0xE000_ED88;
/// The return address given to called code: a page of ST's system memory (boot ROM), which
/// firmware never calls. The run stops when the PC reaches it.
pub const EXIT: u32 = 0x1FFF_0000;

/// Whether `addr` is in the flash, where the ART accelerator and the wait states matter.
pub fn in_flash(addr: u32) -> bool {
    FLASH.contains(&addr)
}

/// Whether `addr..addr+len` lies inside one of the RAM or flash regions loadable from an ELF.
pub fn loadable(addr: u32, len: u32) -> bool {
    let end = u64::from(addr) + u64::from(len);
    [FLASH, CCM, SRAM]
        .iter()
        .any(|r| r.start <= addr && end <= u64::from(r.end))
}

//! The board's memory map beyond flash, CCM and SRAM (which `emu::cortex_m4` maps): ST's
//! system memory, the page of EXC_RETURN values, the PPB as RAM around the DWT and SCS models,
//! and the peripherals (with their bit-band alias) behind the bus models, which are read and
//! written a word at a time.

use unicorn_engine::{Prot, Unicorn};

use super::exceptions::EXC_RETURN_PAGE;
use super::Sys;
use crate::emu::emu;
use crate::error::Error;
use crate::memory::{DWT_CYCCNT, DWT_PAGE};
use crate::system::bus::{Peripherals, PERIPH, PERIPH_BB, SCS_PAGE};
use crate::system::dcmi::DCMI_BASE;
use crate::system::uart::UART4_BASE;

/// The board's memory map beyond flash, CCM and SRAM.
pub(super) fn map_memory(uc: &mut Unicorn<'static, Sys>) -> Result<(), Error> {
    // ST's system memory and OTP/UID area: read-only zeros
    uc.mem_map(0x1FFF_0000, 0x1_0000, Prot::READ).map_err(emu)?;
    uc.mem_map(EXC_RETURN_PAGE.into(), 0x1000, Prot::READ | Prot::EXEC)
        .map_err(emu)?;
    let rw = Prot::READ | Prot::WRITE;
    // PPB as RAM except the DWT page and the SCS page, which are models
    uc.mem_map(0xE000_0000, u64::from(DWT_PAGE - 0xE000_0000), rw)
        .map_err(emu)?;
    uc.mem_map(
        u64::from(DWT_PAGE + 0x1000),
        u64::from(SCS_PAGE - DWT_PAGE - 0x1000),
        rw,
    )
    .map_err(emu)?;
    uc.mem_map(
        u64::from(SCS_PAGE + 0x1000),
        0xE010_0000 - u64::from(SCS_PAGE + 0x1000),
        rw,
    )
    .map_err(emu)?;
    uc.mmio_map(
        DWT_PAGE.into(),
        0x1000,
        Some(|uc: &mut Unicorn<'_, Sys>, offset: u64, size: usize| {
            let st = uc.get_data_mut();
            if offset == u64::from(DWT_CYCCNT - DWT_PAGE) {
                return st.now() & 0xFFFF_FFFF;
            }
            st.dwt.read(offset, size)
        }),
        Some(
            |uc: &mut Unicorn<'_, Sys>, offset: u64, size: usize, value: u64| {
                uc.get_data_mut().dwt.write(offset, size, value);
            },
        ),
    )
    .map_err(emu)?;
    for (base, size) in [
        (SCS_PAGE, 0x1000u64),
        (PERIPH.start, u64::from(PERIPH.end - PERIPH.start)),
        (DCMI_BASE, 0x1000),
    ] {
        uc.mmio_map(
            base.into(),
            size,
            Some(move |uc: &mut Unicorn<'_, Sys>, offset: u64, size: usize| {
                u64::from(bus_read(uc.get_data_mut(), base + offset as u32, size))
            }),
            Some(
                move |uc: &mut Unicorn<'_, Sys>, offset: u64, size: usize, value: u64| {
                    bus_write(uc.get_data_mut(), base + offset as u32, size, value as u32);
                },
            ),
        )
        .map_err(emu)?;
    }
    // the peripheral bit-band alias
    uc.mmio_map(
        PERIPH_BB.into(),
        u64::from(PERIPH.end - PERIPH.start) * 32,
        Some(|uc: &mut Unicorn<'_, Sys>, offset: u64, _size: usize| {
            let (word, bit) = Peripherals::bit_band(PERIPH_BB + offset as u32);
            let st = uc.get_data_mut();
            let now = st.now();
            u64::from((st.p.read(word, now) >> bit) & 1)
        }),
        Some(
            |uc: &mut Unicorn<'_, Sys>, offset: u64, _size: usize, value: u64| {
                let (word, bit) = Peripherals::bit_band(PERIPH_BB + offset as u32);
                let st = uc.get_data_mut();
                let now = st.now();
                let old = st.p.read(word, now);
                let new = if value & 1 != 0 {
                    old | 1 << bit
                } else {
                    old & !(1 << bit)
                };
                bus_write(st, word, 4, new);
            },
        ),
    )
    .map_err(emu)?;
    Ok(())
}

fn bus_read(st: &mut Sys, addr: u32, size: usize) -> u32 {
    let now = st.now();
    let word = st.p.read(addr & !3, now);
    let shift = 8 * (addr & 3);
    let mask = if size >= 4 {
        u32::MAX
    } else {
        (1u32 << (8 * size)) - 1
    };
    (word >> shift) & mask
}

fn bus_write(st: &mut Sys, addr: u32, size: usize, value: u32) {
    let now = st.now();
    let aligned = addr & !3;
    let word = if size >= 4 {
        value
    } else {
        // a narrow write: the other bytes keep what a read returns (0 for the write-only
        // and write-1-to-clear registers)
        let shift = 8 * (addr & 3);
        let mask = ((1u32 << (8 * size)) - 1) << shift;
        (st.p.read(aligned, now) & !mask) | ((value << shift) & mask)
    };
    if aligned == UART4_BASE + 4 {
        st.log.uart_writes.push((now, value as u8));
    }
    if st.p.write(aligned, word, now, &mut st.events) {
        st.p.update_lines();
    }
    // the queue may hold an earlier event now, and an interrupt may be pending
    st.stop_at = st.stop_at.min(st.events.next_at());
    if st.p.nvic.any_pending() {
        st.force_stop = true;
    }
}

//! Unicorn's callbacks into the board. Before each instruction the code hook decodes it (once
//! per address), stops the CPU where the run loop must act (an event due, an interrupt that
//! may preempt, WFI, a branch into the EXC_RETURN page) and counts its cycles; the memory,
//! interrupt and invalid-instruction hooks record a fault or an exception return, which the
//! run loop hands to `exceptions.rs` once the CPU has stopped.

use unicorn_engine::{HookType, MemType, RegisterARM, Unicorn};

use super::exceptions::{Fault, EXC_RETURN_PAGE};
use super::{Kind, Sys};
use crate::emu::{decode_at, emu};
use crate::error::{Access, Error};

/// Installs the hooks on the board's unicorn.
pub(super) fn add_hooks(uc: &mut Unicorn<'static, Sys>) -> Result<(), Error> {
    uc.add_code_hook(1, 0, |uc: &mut Unicorn<'_, Sys>, addr: u64, size: u32| {
        let pc = addr as u32;
        if !uc.get_data().decoded.contains_key(&pc) {
            let d = decode_at(uc, &uc.get_data().decoder, addr, size);
            let text = d.text();
            let kind = if text.starts_with("wfi") || text.starts_with("wfe") {
                Kind::Sleep
            } else if text.starts_with("msr") || text.starts_with("cps") {
                Kind::Mask
            } else {
                Kind::Plain
            };
            uc.get_data_mut().decoded.insert(pc, (d, kind));
        }
        let st = uc.get_data_mut();
        let Some(&(d, kind)) = st.decoded.get(&pc) else {
            return;
        };
        if !st.timing.in_it_block()
            && (st.force_stop
                || st.now() >= st.stop_at
                || kind == Kind::Sleep
                || pc >= EXC_RETURN_PAGE)
        {
            let _ = uc.emu_stop();
            return;
        }
        st.timing.step(pc, &d);
        if kind == Kind::Mask && st.p.nvic.any_pending() {
            st.force_stop = true;
        }
    })
    .map_err(emu)?;

    uc.add_mem_hook(
        HookType::MEM_INVALID,
        1,
        0,
        |uc: &mut Unicorn<'_, Sys>, kind: MemType, addr: u64, _size: usize, _v: i64| {
            let access = match kind {
                MemType::READ_UNMAPPED | MemType::READ_PROT => Access::Read,
                MemType::WRITE_UNMAPPED | MemType::WRITE_PROT => Access::Write,
                _ => Access::Fetch,
            };
            let st = uc.get_data_mut();
            let pc = st.timing.pc();
            st.fault.get_or_insert(Fault::Memory {
                access,
                addr: addr as u32,
                pc,
            });
            false
        },
    )
    .map_err(emu)?;
    uc.add_intr_hook(|uc: &mut Unicorn<'_, Sys>, number: u32| {
        let pc = uc.reg_read(RegisterARM::PC).unwrap_or(0) as u32;
        let st = uc.get_data_mut();
        if number == 8 {
            // EXCP_EXCEPTION_EXIT: a branch to an EXC_RETURN value in Handler mode
            st.exc_return = true;
        } else {
            st.fault.get_or_insert(Fault::Other { number, pc });
        }
        let _ = uc.emu_stop();
    })
    .map_err(emu)?;
    uc.add_insn_invalid_hook(|uc: &mut Unicorn<'_, Sys>| {
        let pc = uc.reg_read(RegisterARM::PC).unwrap_or(0) as u32;
        let st = uc.get_data_mut();
        st.fault.get_or_insert(Fault::Undefined { pc });
        false
    })
    .map_err(emu)?;
    Ok(())
}

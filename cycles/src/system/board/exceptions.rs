//! Exception entry and return, tail-chaining and faults: the part of the Cortex-M4's
//! exception model (ARMv7-M ARM B1.5) that unicorn leaves out, done by the host between two
//! runs of the CPU. The NVIC model (`system::nvic`) says which exception is pending and may
//! preempt; this file stacks and unstacks the context, charges the entry, return and
//! tail-chain latencies, and turns a fault a hook saw into a HardFault, or a lockup.

use unicorn_engine::RegisterARM;

use super::Board;
use crate::error::{Access, Error};
use crate::memory::{CCM, SRAM};
use crate::system::nvic::HARD_FAULT;

/// Cortex-M4 exception entry and return latency, and a tail-chain (ARM DDI 0439B 3.3.1).
const ENTRY_CYCLES: u64 = 12;
const RETURN_CYCLES: u64 = 12;
const TAIL_CHAIN_CYCLES: u64 = 6;
/// Exception return values live at the top of the address space (ARMv7-M ARM B1.5.8).
pub(super) const EXC_RETURN_PAGE: u32 = 0xFFFF_F000;

/// A fault seen by a hook.
#[derive(Clone, Copy, Debug)]
pub(super) enum Fault {
    Memory { access: Access, addr: u32, pc: u32 },
    Undefined { pc: u32 },
    Other { number: u32, pc: u32 },
}

impl Board {
    /// The pending exception that preempts now (BASEPRI, PRIMASK and FAULTMASK applied), if any.
    pub(super) fn preempting(&self) -> Result<Option<u16>, Error> {
        let basepri = self.reg(RegisterARM::BASEPRI)? as u8;
        let primask = self.reg(RegisterARM::PRIMASK)? & 1 != 0;
        let faultmask = self.reg(RegisterARM::FAULTMASK)? & 1 != 0;
        Ok(self
            .uc
            .get_data()
            .p
            .nvic
            .preempting(basepri, primask, faultmask))
    }

    /// Exception entry (B1.5.6): stacks the context (with the FP registers when CONTROL.FPCA
    /// says the context uses them), then runs the handler. `return_to`: the address to resume
    /// (the faulting instruction for a fault; else the current PC).
    pub(super) fn enter(&mut self, exc: u16, return_to: Option<u32>) -> Result<(), Error> {
        self.account();
        let pc = match return_to {
            Some(pc) => pc,
            None => self.pc()?,
        };
        let control = self.reg(RegisterARM::CONTROL)?;
        if control & 2 != 0 {
            return Err(Error::Lockup {
                pc,
                reason: "Thread mode on the process stack is not modelled".into(),
            });
        }
        let fp = control & 4 != 0;
        let sp = self.reg(RegisterARM::SP)?;
        let size = if fp { 0x68 } else { 0x20 };
        let align = (sp >> 2) & 1;
        let frame = sp.wrapping_sub(size) & !(align << 2);
        let xpsr = (self.reg(RegisterARM::XPSR)? & !0x200) | align << 9 | 1 << 24;
        let mut words = vec![
            self.reg(RegisterARM::R0)?,
            self.reg(RegisterARM::R1)?,
            self.reg(RegisterARM::R2)?,
            self.reg(RegisterARM::R3)?,
            self.reg(RegisterARM::R12)?,
            self.reg(RegisterARM::LR)?,
            pc,
            xpsr,
        ];
        if fp {
            for i in 0..16 {
                words.push(self.reg(s_reg(i))?);
            }
            words.push(self.reg(RegisterARM::FPSCR)?);
            words.push(0);
        }
        let ccm_or_sram = |a: u32| CCM.contains(&a) || SRAM.contains(&a);
        if !ccm_or_sram(frame) || !ccm_or_sram(sp.wrapping_sub(1)) {
            return Err(Error::Lockup {
                pc,
                reason: format!(
                    "exception {exc} cannot stack its frame: SP {sp:#010x} (stack overflow)"
                ),
            });
        }
        self.write_words(frame, &words)?;
        let thread = self.uc.get_data().p.nvic.current() == 0;
        let exc_return = match (fp, thread) {
            (false, false) => 0xFFFF_FFF1,
            (false, true) => 0xFFFF_FFF9,
            (true, false) => 0xFFFF_FFE1,
            (true, true) => 0xFFFF_FFE9,
        };
        self.set(RegisterARM::SP, frame)?;
        self.set(RegisterARM::LR, exc_return)?;
        self.set(RegisterARM::CONTROL, control & !4)?;
        self.handler(exc)?;
        self.uc.get_data_mut().extra += ENTRY_CYCLES;
        Ok(())
    }

    /// Makes `exc` active and jumps to its handler.
    fn handler(&mut self, exc: u16) -> Result<(), Error> {
        let vector = self.read_u32(self.vector_table() + 4 * u32::from(exc))?;
        self.set(RegisterARM::IPSR, u32::from(exc))?;
        self.set(RegisterARM::PC, vector | 1)?;
        let st = self.uc.get_data_mut();
        st.p.nvic.activate(exc);
        st.timing.redirect();
        Ok(())
    }

    /// Exception return (B1.5.8), or a tail-chain into the next pending exception.
    pub(super) fn exception_return(&mut self) -> Result<(), Error> {
        self.account();
        let exc_return = self.pc()? | 1;
        let st = self.uc.get_data_mut();
        if st.p.nvic.deactivate().is_none() {
            return Err(Error::Lockup {
                pc: exc_return,
                reason: "exception return with no active exception".into(),
            });
        }
        st.p.update_lines();
        if let Some(next) = self.preempting()? {
            self.set(RegisterARM::LR, exc_return)?;
            self.handler(next)?;
            self.uc.get_data_mut().extra += TAIL_CHAIN_CYCLES;
            return Ok(());
        }
        let sp = self.reg(RegisterARM::SP)?;
        let fp = exc_return & 0x10 == 0;
        let n = if fp { 26 } else { 8 };
        let bytes = self.read(sp, 4 * n)?;
        let w: Vec<u32> = bytes
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        for (r, v) in [
            RegisterARM::R0,
            RegisterARM::R1,
            RegisterARM::R2,
            RegisterARM::R3,
            RegisterARM::R12,
            RegisterARM::LR,
        ]
        .into_iter()
        .zip(&w)
        {
            self.set(r, *v)?;
        }
        if fp {
            for i in 0..16 {
                self.set(s_reg(i), w[8 + i])?;
            }
            self.set(RegisterARM::FPSCR, w[24])?;
        }
        let xpsr = w[7];
        let size = 4 * n as u32 + ((xpsr >> 9) & 1) * 4;
        self.set(RegisterARM::SP, sp + size)?;
        let control = self.reg(RegisterARM::CONTROL)?;
        self.set(
            RegisterARM::CONTROL,
            if fp { control | 4 } else { control & !4 },
        )?;
        self.set(RegisterARM::XPSR_NZCVQG, xpsr)?;
        self.set(RegisterARM::IPSR, xpsr & 0x1FF)?;
        self.set(RegisterARM::PC, w[6] | 1)?;
        let st = self.uc.get_data_mut();
        st.extra += RETURN_CYCLES;
        st.timing.redirect();
        Ok(())
    }

    /// A synchronous fault: HardFault (the configurable faults are not enabled by the firmware,
    /// so they escalate, B1.5.8), or a lockup when HardFault itself faults.
    pub(super) fn fault(&mut self, fault: Fault) -> Result<(), Error> {
        let (pc, cfsr, what) = match fault {
            Fault::Memory { access, addr, pc } => (
                pc,
                1 << 9, // PRECISERR
                format!("{access} of unmapped address {addr:#010x}"),
            ),
            Fault::Undefined { pc } => (pc, 1 << 16, "undefined instruction".to_owned()), // UNDEFINSTR
            Fault::Other { number, pc } => (pc, 1 << 16, format!("CPU exception {number}")),
        };
        let st = self.uc.get_data_mut();
        if st.p.nvic.current() == HARD_FAULT || st.p.nvic.active().contains(&HARD_FAULT) {
            return Err(Error::Lockup {
                pc,
                reason: format!("{what} in the HardFault handler"),
            });
        }
        st.p.nvic.cfsr |= cfsr;
        st.p.nvic.hfsr |= 1 << 30; // FORCED
        self.sleeping = false;
        self.enter(HARD_FAULT, Some(pc))
    }

    /// Writes an exception stack frame; a frame that cannot be written is a lockup.
    fn write_words(&mut self, addr: u32, words: &[u32]) -> Result<(), Error> {
        let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        self.uc
            .mem_write(addr.into(), &bytes)
            .map_err(|_| Error::Lockup {
                pc: 0,
                reason: format!("exception stack frame cannot be written at {addr:#010x}"),
            })
    }
}

fn s_reg(i: usize) -> RegisterARM {
    const S: [RegisterARM; 16] = [
        RegisterARM::S0,
        RegisterARM::S1,
        RegisterARM::S2,
        RegisterARM::S3,
        RegisterARM::S4,
        RegisterARM::S5,
        RegisterARM::S6,
        RegisterARM::S7,
        RegisterARM::S8,
        RegisterARM::S9,
        RegisterARM::S10,
        RegisterARM::S11,
        RegisterARM::S12,
        RegisterARM::S13,
        RegisterARM::S14,
        RegisterARM::S15,
    ];
    S[i]
}

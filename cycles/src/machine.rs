//! The emulated STM32F427: unicorn's Cortex-M4 with the chip's memory map, the timing model
//! hooked on every instruction, and a DWT cycle counter that returns the modelled count.

use std::collections::HashMap;
use std::ops::Range;

use unicorn_engine::{HookType, MemType, Prot, RegisterARM, Unicorn};

use crate::decode::{Decoded, Decoder};
use crate::elf::{self, Symbol};
use crate::emu::{self, cortex_m4, decode_at, emu, load, RegisterPage};
use crate::error::{Access, Error};
use crate::memory::{self, CCM, DWT_CYCCNT, DWT_PAGE, EXIT, PPB, SCB_CPACR, SCB_CPUID};
use crate::ram::RamReport;
use crate::timing::{Class, ClassStat, FlashModel, Timing};

/// The counts at one read of DWT_CYCCNT, since the start of the call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stamp {
    /// The reading instruction.
    pub pc: u32,
    pub nominal: u64,
    pub pessimistic: u64,
}

/// What one instruction address cost over the calls profiled ([`Machine::set_profiling`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PcCycles {
    pub pc: u32,
    /// Times executed (IT-skipped executions not included).
    pub count: u64,
    /// Pessimistic cycles charged while this instruction was the one reported: its own cost,
    /// the IT-skipped instructions before it, and the penalty (P, flash miss) of the taken
    /// branch that arrived at it.
    pub pessimistic: u64,
    /// Nominal cycles, likewise.
    pub nominal: u64,
    /// The instruction (capstone's text).
    pub text: String,
}

/// The result of one call.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Run {
    /// Cycles of the nominal model (P = 1, flash wait states hidden by the ART).
    pub nominal: u64,
    /// Cycles of the pessimistic model (P = 3, +5 per ART miss at a branch target in flash).
    pub pessimistic: u64,
    /// Instructions, including those skipped in IT blocks.
    pub instructions: u64,
    pub taken_branches: u64,
    /// Taken-branch targets in flash that missed the ART (pessimistic model only).
    pub flash_misses: u64,
    /// r0 on return.
    pub ret: u32,
    /// r1 on return (the high word of a 64-bit result).
    pub ret_hi: u32,
    /// Every read of DWT_CYCCNT, in order.
    pub dwt_reads: Vec<Stamp>,
    /// Instructions and base cycles (without branch and flash penalties) per class, for the
    /// classes that occurred.
    pub classes: Vec<(Class, ClassStat)>,
}

/// What a hook saw go wrong; turned into an [`Error`] once the emulator has stopped.
#[derive(Clone, Copy, Debug)]
enum Fault {
    Memory {
        access: Access,
        addr: u32,
        pc: u32,
        unmapped: bool,
    },
    Exception {
        number: u32,
        pc: u32,
    },
    Invalid {
        pc: u32,
    },
}

/// Everything the hooks need; lives inside the unicorn instance.
struct State {
    decoder: Decoder,
    decoded: HashMap<u32, Decoded>,
    timing: Timing,
    stamps: Vec<Stamp>,
    fault: Option<Fault>,
    /// The DWT page's registers (other than CYCCNT) as plain memory.
    dwt: RegisterPage,
    /// Pessimistic cycles of earlier calls: CYCCNT free-runs across calls, like the hardware.
    cycles_before: u64,
    /// Value written to CYCCNT minus the modelled count at the write.
    cyccnt_offset: u32,
    /// Per-PC `(count, pessimistic, nominal)` when profiling.
    profile: Option<HashMap<u32, (u64, u64, u64)>>,
}

impl State {
    fn cyccnt(&self) -> u32 {
        let now = self.cycles_before + self.timing.counters.pessimistic();
        (now as u32).wrapping_add(self.cyccnt_offset)
    }
}

/// An STM32F427 (Cortex-M4F) running code under the cycle model.
pub struct Machine {
    uc: Unicorn<'static, State>,
    symbols: HashMap<String, Symbol>,
    ram: RamReport,
    stack: Range<u32>,
    sp: u32,
    limit: Option<u64>,
}

/// The default instruction limit of a call: far above a frame (~10^6), low enough that a
/// runaway loop fails a test in about a second instead of hanging it.
pub const DEFAULT_LIMIT: u64 = 50_000_000;

const CORE_REGS: [RegisterARM; 13] = [
    RegisterARM::R0,
    RegisterARM::R1,
    RegisterARM::R2,
    RegisterARM::R3,
    RegisterARM::R4,
    RegisterARM::R5,
    RegisterARM::R6,
    RegisterARM::R7,
    RegisterARM::R8,
    RegisterARM::R9,
    RegisterARM::R10,
    RegisterARM::R11,
    RegisterARM::R12,
];

impl Machine {
    /// An empty machine: the memory map, nothing loaded; the stack is all of CCM.
    pub fn new() -> Result<Machine, Error> {
        let state = State {
            decoder: Decoder::new().map_err(Error::Emulator)?,
            decoded: HashMap::new(),
            timing: Timing::new(FlashModel::default()),
            stamps: Vec::new(),
            fault: None,
            dwt: RegisterPage::new(0x1000),
            cycles_before: 0,
            cyccnt_offset: 0,
            profile: None,
        };
        let mut uc = cortex_m4(state)?;
        uc.mem_map(EXIT.into(), 0x1000, Prot::READ | Prot::EXEC)
            .map_err(emu)?;
        // The PPB as RAM around the DWT page, which is served by callbacks.
        let rw = Prot::READ | Prot::WRITE;
        uc.mem_map(PPB.start.into(), u64::from(DWT_PAGE - PPB.start), rw)
            .map_err(emu)?;
        uc.mem_map(
            u64::from(DWT_PAGE) + 0x1000,
            u64::from(PPB.end - DWT_PAGE - 0x1000),
            rw,
        )
        .map_err(emu)?;
        uc.mmio_map(
            DWT_PAGE.into(),
            0x1000,
            Some(|uc: &mut Unicorn<'_, State>, offset: u64, size: usize| {
                let st = uc.get_data_mut();
                if u64::from(DWT_CYCCNT - DWT_PAGE) == offset {
                    let c = st.timing.counters;
                    st.stamps.push(Stamp {
                        pc: st.timing.pc(),
                        nominal: c.nominal(),
                        pessimistic: c.pessimistic(),
                    });
                    return u64::from(st.cyccnt());
                }
                st.dwt.read(offset, size)
            }),
            Some(
                |uc: &mut Unicorn<'_, State>, offset: u64, size: usize, value: u64| {
                    let st = uc.get_data_mut();
                    if u64::from(DWT_CYCCNT - DWT_PAGE) == offset {
                        st.cyccnt_offset = 0;
                        st.cyccnt_offset = (value as u32).wrapping_sub(st.cyccnt());
                        return;
                    }
                    st.dwt.write(offset, size, value);
                },
            ),
        )
        .map_err(emu)?;
        uc.mem_write(SCB_CPUID.into(), &0x410F_C241u32.to_le_bytes())
            .map_err(emu)?;
        uc.mem_write(SCB_CPACR.into(), &(0xFu32 << 20).to_le_bytes())
            .map_err(emu)?;

        uc.add_code_hook(1, 0, |uc: &mut Unicorn<'_, State>, addr: u64, size: u32| {
            let pc = addr as u32;
            if !uc.get_data().decoded.contains_key(&pc) {
                let d = decode_at(uc, &uc.get_data().decoder, addr, size);
                uc.get_data_mut().decoded.insert(pc, d);
            }
            let st = uc.get_data_mut();
            if let Some(d) = st.decoded.get(&pc).copied() {
                let before = st.timing.counters;
                st.timing.step(pc, &d);
                if let Some(p) = st.profile.as_mut() {
                    let after = st.timing.counters;
                    let e = p.entry(pc).or_insert((0, 0, 0));
                    e.0 += 1;
                    e.1 += after.pessimistic() - before.pessimistic();
                    e.2 += after.nominal() - before.nominal();
                }
            }
        })
        .map_err(emu)?;

        let bad_memory =
            |uc: &mut Unicorn<'_, State>, kind: MemType, addr: u64, _size: usize, _v: i64| {
                let (access, unmapped) = match kind {
                    MemType::READ_UNMAPPED => (Access::Read, true),
                    MemType::WRITE_UNMAPPED => (Access::Write, true),
                    MemType::FETCH_UNMAPPED => (Access::Fetch, true),
                    MemType::READ_PROT => (Access::Read, false),
                    MemType::WRITE_PROT => (Access::Write, false),
                    _ => (Access::Fetch, false),
                };
                let st = uc.get_data_mut();
                let pc = st.timing.pc();
                st.fault.get_or_insert(Fault::Memory {
                    access,
                    addr: addr as u32,
                    pc,
                    unmapped,
                });
                false
            };
        uc.add_mem_hook(HookType::MEM_INVALID, 1, 0, bad_memory)
            .map_err(emu)?;
        uc.add_intr_hook(|uc: &mut Unicorn<'_, State>, number: u32| {
            let st = uc.get_data_mut();
            let pc = st.timing.pc();
            st.fault.get_or_insert(Fault::Exception { number, pc });
            let _ = uc.emu_stop();
        })
        .map_err(emu)?;
        uc.add_insn_invalid_hook(|uc: &mut Unicorn<'_, State>| {
            let st = uc.get_data_mut();
            let pc = st.timing.pc();
            st.fault.get_or_insert(Fault::Invalid { pc });
            false
        })
        .map_err(emu)?;

        Ok(Machine {
            uc,
            symbols: HashMap::new(),
            ram: RamReport::default(),
            stack: CCM,
            sp: CCM.end,
            limit: Some(DEFAULT_LIMIT),
        })
    }

    /// Loads an ELF at its run addresses (.data initialised at its VMA and its image at its LMA,
    /// .bss zeroed). The stack is `_stack_end.._stack_start` when the ELF defines those
    /// (cortex-m-rt and this project's memory.x do), else all of CCM.
    pub fn from_elf(bytes: &[u8]) -> Result<Machine, Error> {
        let image = elf::parse(bytes)?;
        let mut m = Machine::new()?;
        load(&mut m.uc, &image.chunks)?;
        if let Some(stack) = image.stack() {
            m.set_stack(stack);
        }
        m.symbols = image.symbols;
        m.ram = RamReport::from_sections(image.sections);
        Ok(m)
    }

    /// A machine with `code` at `at` (in flash or SRAM; CCM cannot execute), for tests.
    pub fn from_raw(code: &[u8], at: u32) -> Result<Machine, Error> {
        let len = code.len() as u32;
        if !memory::loadable(at, len) || CCM.contains(&at) {
            return Err(Error::Load {
                what: "code".into(),
                addr: at,
                len,
            });
        }
        let mut m = Machine::new()?;
        m.write(at, code)?;
        Ok(m)
    }

    /// A symbol's address (Thumb bit cleared for functions).
    pub fn symbol(&self, name: &str) -> Option<u32> {
        self.symbols.get(name).map(Symbol::address)
    }

    /// A symbol's raw st_value (bit 0 set for Thumb functions).
    pub fn symbol_raw(&self, name: &str) -> Option<u32> {
        self.symbols.get(name).map(|s| s.value)
    }

    pub fn symbol_size(&self, name: &str) -> Option<u32> {
        self.symbols.get(name).map(|s| s.size)
    }

    /// The static RAM/flash report of the loaded ELF (empty for `from_raw`).
    pub fn ram_report(&self) -> &RamReport {
        &self.ram
    }

    pub fn read(&self, addr: u32, len: usize) -> Result<Vec<u8>, Error> {
        emu::read(&self.uc, addr, len)
    }

    pub fn read_u32(&self, addr: u32) -> Result<u32, Error> {
        emu::read_u32(&self.uc, addr)
    }

    /// Writes memory (flash too: this is the loader's view). Clears the decode cache, so code
    /// written here is re-decoded; code that rewrites itself while running is not supported.
    pub fn write(&mut self, addr: u32, bytes: &[u8]) -> Result<(), Error> {
        self.uc
            .mem_write(addr.into(), bytes)
            .map_err(|_| Error::Unmapped {
                access: Access::Write,
                addr,
                pc: 0,
            })?;
        self.uc.get_data_mut().decoded.clear();
        Ok(())
    }

    /// The initial SP of calls (the stack's top by default).
    pub fn set_sp(&mut self, sp: u32) {
        self.sp = sp;
    }

    /// The stack region (for overflow reports and [`Machine::paint_stack`]); sets SP to its top.
    pub fn set_stack(&mut self, stack: Range<u32>) {
        self.sp = stack.end;
        self.stack = stack;
    }

    pub fn stack(&self) -> Range<u32> {
        self.stack.clone()
    }

    /// Instruction limit of a call (`None`: unlimited). Default [`DEFAULT_LIMIT`].
    pub fn set_limit(&mut self, limit: Option<u64>) {
        self.limit = limit;
    }

    /// How the pessimistic model treats flash fetches; default the 64-line ART.
    pub fn set_flash_model(&mut self, model: FlashModel) {
        self.uc.get_data_mut().timing = Timing::new(model);
    }

    /// Turns the per-instruction profile on (cleared) or off. While on, every executed
    /// instruction's cycles are added to its address (slower: a hash map update per
    /// instruction); [`Machine::take_profile`] returns and clears it.
    pub fn set_profiling(&mut self, on: bool) {
        self.uc.get_data_mut().profile = on.then(HashMap::new);
    }

    /// The profile since [`Machine::set_profiling`] or the last take, sorted by address; empty
    /// when profiling is off. Profiling stays on.
    pub fn take_profile(&mut self) -> Vec<PcCycles> {
        let st = self.uc.get_data_mut();
        let Some(p) = st.profile.as_mut() else {
            return Vec::new();
        };
        let taken = std::mem::take(p);
        let mut v: Vec<PcCycles> = taken
            .into_iter()
            .map(|(pc, (count, pessimistic, nominal))| PcCycles {
                pc,
                count,
                pessimistic,
                nominal,
                text: st
                    .decoded
                    .get(&pc)
                    .map_or_else(String::new, |d| d.text().to_owned()),
            })
            .collect();
        v.sort_by_key(|c| c.pc);
        v
    }

    /// The function symbols of the ELF, as `(address, size, name)` sorted by address (Thumb
    /// bit cleared), for attributing profiled addresses.
    pub fn functions(&self) -> Vec<(u32, u32, String)> {
        let mut v: Vec<(u32, u32, String)> = self
            .symbols
            .iter()
            .filter(|(_, s)| s.function && s.size > 0)
            .map(|(n, s)| (s.address(), s.size, n.clone()))
            .collect();
        v.sort();
        v
    }

    /// Fills `range` (word aligned) with `pattern`.
    pub fn paint(&mut self, range: Range<u32>, pattern: u32) -> Result<(), Error> {
        emu::paint(&mut self.uc, range, pattern)?;
        self.uc.get_data_mut().decoded.clear();
        Ok(())
    }

    /// Bytes of `range` (a downward-growing stack painted with `pattern`) that were written:
    /// from the lowest changed word to the end of the range.
    pub fn high_water(&self, range: Range<u32>, pattern: u32) -> Result<u32, Error> {
        emu::high_water(&self.uc, range, pattern)
    }

    /// Paints the stack below the initial SP (see [`Machine::stack`]).
    pub fn paint_stack(&mut self, pattern: u32) -> Result<(), Error> {
        self.paint(self.stack.start..self.sp & !3, pattern)
    }

    /// Stack bytes used since [`Machine::paint_stack`], measured from the initial SP.
    pub fn stack_high_water(&self, pattern: u32) -> Result<u32, Error> {
        self.high_water(self.stack.start..self.sp & !3, pattern)
    }

    /// Calls the Thumb function at `entry` (bit 0 ignored) with AAPCS integer arguments: the
    /// first four in r0-r3, the rest on the stack. r4-r12 start at 0, SP at the initial SP, LR
    /// at [`memory::EXIT`]; the run ends when the function returns there.
    pub fn call(&mut self, entry: u32, args: &[u32]) -> Result<Run, Error> {
        {
            let st = self.uc.get_data_mut();
            st.timing.start();
            st.stamps.clear();
            st.fault = None;
        }
        let mut sp = self.sp & !7;
        if let Some(stacked) = args.get(4..) {
            sp = sp.wrapping_sub(4 * stacked.len() as u32) & !7;
            let bytes: Vec<u8> = stacked.iter().flat_map(|a| a.to_le_bytes()).collect();
            self.write(sp, &bytes)?;
        }
        for (i, reg) in CORE_REGS.iter().enumerate() {
            let v = args.get(i).filter(|_| i < 4).copied().unwrap_or(0);
            self.uc.reg_write(*reg, v.into()).map_err(emu)?;
        }
        self.uc.reg_write(RegisterARM::SP, sp.into()).map_err(emu)?;
        self.uc
            .reg_write(RegisterARM::LR, u64::from(EXIT | 1))
            .map_err(emu)?;

        let count = self
            .limit
            .map_or(0, |l| usize::try_from(l).unwrap_or(usize::MAX));
        let result = self
            .uc
            .emu_start(u64::from(entry | 1), EXIT.into(), 0, count);
        if let Some(fault) = self.uc.get_data_mut().fault.take() {
            return Err(self.fault_error(fault));
        }
        result.map_err(emu)?;
        // (pc_read() fails with MODE for Thumb|MClass: it asks for the mode first.)
        let pc = self.uc.reg_read(RegisterARM::PC).map_err(emu)? as u32;
        if pc != EXIT {
            return Err(Error::InstructionLimit {
                limit: self.limit.unwrap_or(0),
                pc,
            });
        }

        let ret = self.uc.reg_read(RegisterARM::R0).map_err(emu)? as u32;
        let ret_hi = self.uc.reg_read(RegisterARM::R1).map_err(emu)? as u32;
        let st = self.uc.get_data_mut();
        st.timing.finish(EXIT);
        let c = st.timing.counters;
        // Bank this call's cycles so CYCCNT keeps counting from them, and start from zero.
        st.cycles_before += c.pessimistic();
        st.timing.start();
        let classes = Class::ALL
            .iter()
            .zip(c.classes.iter())
            .filter(|(_, s)| s.instructions > 0)
            .map(|(k, s)| (*k, *s))
            .collect();
        Ok(Run {
            nominal: c.nominal(),
            pessimistic: c.pessimistic(),
            instructions: c.instructions,
            taken_branches: c.taken_branches,
            flash_misses: c.flash_misses,
            ret,
            ret_hi,
            dwt_reads: std::mem::take(&mut st.stamps),
            classes,
        })
    }

    fn fault_error(&self, fault: Fault) -> Error {
        match fault {
            Fault::Memory {
                access,
                addr,
                pc,
                unmapped,
            } => {
                let sp = self.uc.reg_read(RegisterARM::SP).map_or(0, |v| v as u32);
                let below = self.stack.start.wrapping_sub(addr);
                if unmapped && (sp < self.stack.start || (1..=0x1000).contains(&below)) {
                    Error::StackOverflow {
                        addr,
                        sp,
                        pc,
                        stack: self.stack.clone(),
                    }
                } else if unmapped {
                    Error::Unmapped { access, addr, pc }
                } else {
                    Error::Protected { access, addr, pc }
                }
            }
            Fault::Exception { number, pc } => {
                let insn = self
                    .uc
                    .get_data()
                    .decoded
                    .get(&pc)
                    .map_or_else(|| "?".to_owned(), |d| d.text().to_owned());
                Error::Exception { number, pc, insn }
            }
            Fault::Invalid { pc } => Error::InvalidInstruction { pc },
        }
    }
}

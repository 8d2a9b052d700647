//! The one error type of the crate: every failure of loading or running code is a value, never a
//! panic, and names the address (and the PC of the instruction) involved.

use std::fmt;

/// What kind of memory access failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    Read,
    Write,
    Fetch,
}

impl fmt::Display for Access {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Access::Read => "read",
            Access::Write => "write",
            Access::Fetch => "instruction fetch",
        })
    }
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Error {
    /// The ELF could not be parsed (or is not a 32-bit little-endian ARM ELF).
    Elf(String),
    /// A loadable part of the image (or a raw blob) lies outside the modelled memory map.
    Load { what: String, addr: u32, len: u32 },
    /// An access to an address the STM32F427 map of this model does not back (reserved space,
    /// or the peripheral buses 0x4000_0000.., which are deliberately left unmapped so that stray
    /// peripheral accesses in code under test are reported instead of silently absorbed).
    Unmapped { access: Access, addr: u32, pc: u32 },
    /// A write to flash or an instruction fetch from a non-executable region (CCM is data-bus
    /// only on the STM32F4).
    Protected { access: Access, addr: u32, pc: u32 },
    /// The stack ran off the bottom of its region (`stack` is the region).
    StackOverflow {
        addr: u32,
        sp: u32,
        pc: u32,
        stack: std::ops::Range<u32>,
    },
    /// The call executed more instructions than the limit without returning.
    InstructionLimit { limit: u64, pc: u32 },
    /// The CPU raised an exception (UDF, SVC, BKPT, a usage fault, ...); `number` is unicorn's
    /// (QEMU's) exception index, `insn` the disassembly at `pc` when it could be decoded.
    Exception { number: u32, pc: u32, insn: String },
    /// An undecodable instruction.
    InvalidInstruction { pc: u32 },
    /// The virtual board cannot go on: a fault while HardFault runs (the core locks up), an
    /// exception stack frame that cannot be written, an exception return with nothing active.
    Lockup { pc: u32, reason: String },
    /// Anything else unicorn reported.
    Emulator(String),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Elf(m) => write!(f, "ELF: {m}"),
            Error::Load { what, addr, len } => write!(
                f,
                "cannot load {what} ({len} bytes at {addr:#010x}): outside the modelled memory map"
            ),
            Error::Unmapped { access, addr, pc } => {
                let hint = if (0x4000_0000..0x6000_0000).contains(addr) {
                    " (peripheral register: not modelled)"
                } else {
                    ""
                };
                write!(
                    f,
                    "{access} of unmapped address {addr:#010x}{hint} at pc {pc:#010x}"
                )
            }
            Error::Protected { access, addr, pc } => {
                write!(f, "{access} not allowed at {addr:#010x} (pc {pc:#010x})")
            }
            Error::StackOverflow {
                addr,
                sp,
                pc,
                stack,
            } => write!(
                f,
                "stack overflow: access at {addr:#010x} below the stack {:#010x}..{:#010x} \
                 (sp {sp:#010x}, pc {pc:#010x})",
                stack.start, stack.end
            ),
            Error::InstructionLimit { limit, pc } => {
                write!(f, "no return after {limit} instructions (pc {pc:#010x})")
            }
            Error::Exception { number, pc, insn } => {
                write!(f, "CPU exception {number} at pc {pc:#010x} ({insn})")
            }
            Error::InvalidInstruction { pc } => write!(f, "invalid instruction at pc {pc:#010x}"),
            Error::Lockup { pc, reason } => write!(f, "core lockup at pc {pc:#010x}: {reason}"),
            Error::Emulator(m) => write!(f, "emulator: {m}"),
        }
    }
}

impl std::error::Error for Error {}

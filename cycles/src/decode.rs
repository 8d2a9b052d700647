//! Static decoding of one Thumb-2 instruction into what the timing rules need: its class and base
//! cost, the core registers that form its data address, and the core registers it writes.
//! Done once per address with capstone and cached, so the per-instruction hook stays cheap.

use capstone::arch::arm::{ArchExtraMode, ArchMode, ArmOperandType};
use capstone::arch::{BuildsCapstone, BuildsCapstoneExtraMode, DetailsArchInsn};
use capstone::{Capstone, RegId};

use crate::timing::Class;

/// The timing-relevant facts about one instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Decoded {
    /// Length in bytes (2 or 4).
    pub size: u8,
    pub class: Class,
    /// Cycles before the dynamic rules (pipelining, address dependency, taken branch).
    pub base: u8,
    /// A single LDR/LDRB/LDRH/LDRSB/LDRSH (these pipeline behind a preceding load).
    pub load_single: bool,
    /// A single STR/STRB/STRH with an immediate offset (1 cycle, 2 after another store).
    pub store_single: bool,
    /// Core registers (bit n = Rn) used to compute the data address.
    pub addr_regs: u16,
    /// Core registers written; for memory instructions without the base write-back, which the
    /// address generation unit forwards (so `ldr r1, [r0], #4` loops do not stall on r0).
    pub writes: u16,
    /// For an IT instruction: how many instructions it covers and their sizes.
    pub it: Option<ItBlock>,
    /// Capstone's text, for error messages.
    pub text: [u8; 32],
}

/// The instructions covered by an IT instruction (sizes known statically from the code bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ItBlock {
    pub count: u8,
    pub sizes: [u8; 4],
}

impl Decoded {
    /// Capstone's disassembly, e.g. `udiv r0, r1, r2`.
    pub fn text(&self) -> &str {
        let end = self
            .text
            .iter()
            .position(|&b| b == 0)
            .unwrap_or(self.text.len());
        std::str::from_utf8(&self.text[..end]).unwrap_or("?")
    }
}

/// Length of the Thumb instruction starting with halfword `hw`.
pub fn thumb_size(hw: u16) -> u8 {
    match hw >> 11 {
        0b11101..=0b11111 => 4,
        _ => 2,
    }
}

pub struct Decoder {
    cs: Capstone,
}

impl Decoder {
    pub fn new() -> Result<Decoder, String> {
        let cs = Capstone::new()
            .arm()
            .mode(ArchMode::Thumb)
            .extra_mode([ArchExtraMode::MClass].iter().copied())
            .detail(true)
            .build()
            .map_err(|e| e.to_string())?;
        Ok(Decoder { cs })
    }

    /// Decodes the instruction at `addr` whose bytes start `bytes` (which may extend past it; for
    /// an IT instruction they should cover the block, up to 18 bytes). `size` is the length
    /// unicorn executed, used when capstone cannot decode the instruction (then it counts as a
    /// 1-cycle ALU instruction).
    pub fn decode(&self, addr: u32, bytes: &[u8], size: u8) -> Decoded {
        let mut d = Decoded {
            size,
            class: Class::Alu,
            base: 1,
            load_single: false,
            store_single: false,
            addr_regs: 0,
            writes: 0,
            it: None,
            text: [0; 32],
        };
        let Some(code) = bytes.get(..usize::from(size)) else {
            return d;
        };
        let Ok(insns) = self.cs.disasm_count(code, u64::from(addr), 1) else {
            return d;
        };
        let Some(insn) = insns.iter().next() else {
            return d;
        };
        let text = format!(
            "{} {}",
            insn.mnemonic().unwrap_or("?"),
            insn.op_str().unwrap_or("")
        );
        let n = text.len().min(d.text.len());
        d.text[..n].copy_from_slice(&text.as_bytes()[..n]);
        let Some(name) = self.cs.insn_name(insn.id()) else {
            return d;
        };
        let Ok(detail) = self.cs.insn_detail(insn) else {
            return d;
        };

        // Operands: registers (with access), the memory operand's base and index.
        let mut regs: Vec<(u16, bool, bool)> = Vec::new(); // (mask, is core, written)
        let mut fp_words = 0u8; // number of 32-bit FP registers among the operands
        let mut has_core = false;
        let mut mem_base = 0u16;
        let mut mem_index = 0u16;
        let mut explicit_written = 0u16;
        if let Some(arm) = detail.arch_detail().arm() {
            for op in arm.operands() {
                let written = op.access.is_some_and(|a| a.is_writable());
                match op.op_type {
                    ArmOperandType::Reg(r) => {
                        let name = self.cs.reg_name(r).unwrap_or_default();
                        let core = core_mask(&name);
                        if core != 0 {
                            has_core = true;
                            if written {
                                explicit_written |= core;
                            }
                        } else if name.starts_with('d') {
                            fp_words += 2;
                        } else if name.starts_with('s') {
                            fp_words += 1;
                        }
                        regs.push((core, core != 0, written));
                    }
                    ArmOperandType::Mem(m) => {
                        mem_base = self.core_of(m.base());
                        mem_index = self.core_of(m.index());
                    }
                    _ => {}
                }
            }
        }
        let all_written = detail
            .regs_write()
            .iter()
            .fold(0u16, |acc, &r| acc | self.core_of(r));
        let core_list = || regs.iter().filter(|r| r.1).count() as u8;

        let mut memory = mem_base != 0;
        match name.as_str() {
            "sdiv" | "udiv" => set(&mut d, Class::Divide, 12),
            "ldr" | "ldrb" | "ldrh" | "ldrsb" | "ldrsh" | "ldrt" | "ldrbt" | "ldrht" | "ldrsbt"
            | "ldrsht" | "ldrex" | "ldrexb" | "ldrexh" => {
                set(&mut d, Class::Load, 2);
                d.load_single = true;
            }
            "str" | "strb" | "strh" | "strt" | "strbt" | "strht" | "strex" | "strexb"
            | "strexh" => {
                // Register offset: 2, and nothing pipelines with it.
                if mem_index != 0 {
                    set(&mut d, Class::Store, 2);
                } else {
                    set(&mut d, Class::Store, 1);
                    d.store_single = true;
                }
            }
            "ldrd" | "strd" => set(&mut d, Class::LoadStoreDouble, 3),
            "push" | "pop" => {
                set(&mut d, Class::LoadStoreMultiple, 1 + core_list());
                mem_base = 1 << 13;
                memory = true;
            }
            "ldm" | "ldmia" | "ldmdb" | "ldmda" | "ldmib" | "stm" | "stmia" | "stmdb" | "stmda"
            | "stmib" => {
                // The first register operand is the base, the rest the list.
                set(
                    &mut d,
                    Class::LoadStoreMultiple,
                    core_list().saturating_sub(1) + 1,
                );
                mem_base = regs.first().map_or(0, |r| r.0);
                memory = true;
            }
            "b" | "bl" | "bx" | "blx" | "cbz" | "cbnz" => set(&mut d, Class::Branch, 1),
            // A table branch is a load plus a branch: 2 + P.
            "tbb" | "tbh" => set(&mut d, Class::Branch, 2),
            "vmla" | "vmls" | "vnmla" | "vnmls" | "vfma" | "vfms" | "vfnma" | "vfnms" => {
                set(&mut d, Class::FpMac, 3)
            }
            "vdiv" | "vsqrt" => set(&mut d, Class::FpDivSqrt, 14),
            "vldr" | "vstr" => {
                let cost = if fp_words >= 2 { 3 } else { 2 };
                set(&mut d, Class::FpLoadStore, cost)
            }
            "vmov" if has_core => set(&mut d, Class::FpTransfer, 2),
            "vpush" | "vpop" => {
                set(&mut d, Class::FpLoadStoreMultiple, 1 + fp_words);
                mem_base = 1 << 13;
                memory = true;
            }
            n if n.starts_with("vldm") || n.starts_with("vstm") => {
                set(&mut d, Class::FpLoadStoreMultiple, 1 + fp_words);
                mem_base = regs.first().map_or(0, |r| r.0);
                memory = true;
            }
            n if n.starts_with('v') => set(&mut d, Class::FpAlu, 1),
            "it" => {
                d.it = it_block(bytes);
            }
            _ => {}
        }
        // PC-relative addresses (literal pools) never wait for a register.
        d.addr_regs = (mem_base | mem_index) & !(1 << 15);
        d.writes = if memory {
            // Drop the base write-back (forwarded by the AGU), keep loaded registers.
            (all_written & !mem_base) | explicit_written
        } else {
            all_written | explicit_written
        };
        d
    }

    fn core_of(&self, r: RegId) -> u16 {
        if r.0 == 0 {
            return 0;
        }
        self.cs.reg_name(r).map_or(0, |n| core_mask(&n))
    }
}

fn set(d: &mut Decoded, class: Class, base: u8) {
    d.class = class;
    d.base = base;
}

/// Bit mask of a core register by capstone's name (r9..r12 may be named sb, sl, fp, ip).
fn core_mask(name: &str) -> u16 {
    let n = match name {
        "sb" => 9,
        "sl" => 10,
        "fp" => 11,
        "ip" => 12,
        "sp" => 13,
        "lr" => 14,
        "pc" => 15,
        _ => match name.strip_prefix('r').and_then(|n| n.parse::<u16>().ok()) {
            Some(n) if n < 16 => n,
            _ => return 0,
        },
    };
    1 << n
}

/// The block of an IT instruction: `bytes` starts at the IT (0xBFxy: firstcond x, mask y) and
/// goes on over the following instructions.
fn it_block(bytes: &[u8]) -> Option<ItBlock> {
    let mask = bytes.first()? & 0xF;
    if mask == 0 {
        return None; // a hint (NOP, YIELD, ...), not an IT
    }
    let count = 4 - mask.trailing_zeros() as u8;
    let mut sizes = [0u8; 4];
    let mut at = 2usize;
    for size in sizes.iter_mut().take(usize::from(count)) {
        let hw = u16::from_le_bytes([*bytes.get(at)?, *bytes.get(at + 1)?]);
        *size = thumb_size(hw);
        at += usize::from(*size);
    }
    Some(ItBlock { count, sizes })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dec(halfwords: &[u16]) -> Decoded {
        let bytes: Vec<u8> = halfwords.iter().flat_map(|h| h.to_le_bytes()).collect();
        let size = thumb_size(halfwords[0]);
        Decoder::new().unwrap().decode(0x0800_0000, &bytes, size)
    }

    #[test]
    fn classes_and_register_masks() {
        // ldr r1, [r0], #4: a load, address r0, writes r1 only (write-back forwarded).
        let d = dec(&[0xF850, 0x1B04]);
        assert_eq!(
            (d.class, d.base, d.load_single),
            (Class::Load, 2, true),
            "{}",
            d.text()
        );
        assert_eq!((d.addr_regs, d.writes), (1 << 0, 1 << 1), "{}", d.text());
        // ldr r0, [r0]: the loaded register is the base and stays written.
        let d = dec(&[0x6800]);
        assert_eq!((d.addr_regs, d.writes), (1, 1), "{}", d.text());
        // str r1, [r0, r2]: register offset costs 2 and does not pipeline.
        let d = dec(&[0x5081]);
        assert_eq!((d.class, d.base, d.store_single), (Class::Store, 2, false));
        assert_eq!(d.addr_regs, 0b101);
        // push {r4, r5, r6, lr}: 1 + 4.
        let d = dec(&[0xB570]);
        assert_eq!(
            (d.class, d.base),
            (Class::LoadStoreMultiple, 5),
            "{}",
            d.text()
        );
        // udiv r0, r1, r2
        let d = dec(&[0xFBB1, 0xF0F2]);
        assert_eq!((d.class, d.base), (Class::Divide, 12), "{}", d.text());
        // ldr r0, [pc, #8]: a literal load has no address register to wait for.
        let d = dec(&[0x4802]);
        assert_eq!(
            (d.class, d.addr_regs, d.writes),
            (Class::Load, 0, 1),
            "{}",
            d.text()
        );
        // adds r0, r1, r2 writes r0
        let d = dec(&[0x1888]);
        assert_eq!(
            (d.class, d.base, d.writes),
            (Class::Alu, 1, 1),
            "{}",
            d.text()
        );
        // vmov s0, r0: core to FP transfer, 2.
        let d = dec(&[0xEE00, 0x0A10]);
        assert_eq!((d.class, d.base), (Class::FpTransfer, 2), "{}", d.text());
        // vadd.f32 s0, s0, s1
        let d = dec(&[0xEE30, 0x0A20]);
        assert_eq!((d.class, d.base), (Class::FpAlu, 1), "{}", d.text());
        // vldr d0, [r0]: a double, 3.
        let d = dec(&[0xED90, 0x0B00]);
        assert_eq!(
            (d.class, d.base, d.addr_regs),
            (Class::FpLoadStore, 3, 1),
            "{}",
            d.text()
        );
        // vpush {s16-s19}: 1 + 4.
        let d = dec(&[0xED2D, 0x8A04]);
        assert_eq!(
            (d.class, d.base),
            (Class::FpLoadStoreMultiple, 5),
            "{}",
            d.text()
        );
        // itte eq, then two 16-bit and one 32-bit instruction.
        let d = dec(&[0xBF06, 0x2001, 0x2102, 0xF04F, 0x0203]);
        assert_eq!(
            d.it,
            Some(ItBlock {
                count: 3,
                sizes: [2, 2, 4, 0]
            }),
            "{}",
            d.text()
        );
    }
}

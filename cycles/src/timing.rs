//! The two Cortex-M4 timing models, evaluated together on one instruction stream.
//!
//! Every rule except two is shared by both models, so the stream is reduced to four numbers:
//! base cycles (per-class costs after the pipelining / dependency rules, plus 1 per IT-skipped
//! instruction), taken branches, and flash misses. Then
//!
//! - nominal     = base + 1 × taken branches (P = 1; the ART hides the flash wait states);
//! - pessimistic = base + 3 × taken branches (P = 3) + 5 × flash misses (5 wait states at
//!   180 MHz for a taken-branch target in flash that the ART instruction cache does not hold).

use crate::decode::Decoded;
use crate::memory::in_flash;

/// Branch penalty P of the nominal model.
pub const P_NOMINAL: u64 = 1;
/// Branch penalty P of the pessimistic model.
pub const P_PESSIMISTIC: u64 = 3;
/// Flash wait states paid on an instruction-fetch miss (RM0090: 5 WS at 180 MHz, 2.7-3.6 V).
pub const FLASH_MISS: u64 = 5;

/// Instruction classes of the timing table (ARM DDI 0439 Table 3-1, FPU Table 7-1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Class {
    /// ALU, shifts, extends, saturation, DSP/SIMD, multiplies and MACs, IT, hints: 1.
    Alu,
    /// SDIV/UDIV: 12 (the worst case of 2-12).
    Divide,
    /// LDR{B,H,SB,SH}: 2, 1 when it directly follows a load it does not depend on.
    Load,
    /// STR{B,H} immediate offset 1 (2 after another store), register offset 2.
    Store,
    /// LDRD/STRD: 3.
    LoadStoreDouble,
    /// LDM/STM/PUSH/POP: 1 + N.
    LoadStoreMultiple,
    /// B/BL/BX/BLX/CBZ/CBNZ 1, TBB/TBH 2; + P when taken.
    Branch,
    /// VADD/VSUB/VMUL/VNMUL/VABS/VNEG/VCMP/VCVT/VMOV(FP)/VMRS/VMSR: 1.
    FpAlu,
    /// VMLA/VMLS/VNMLA/VNMLS/VFMA/VFMS/VFNMA/VFNMS: 3.
    FpMac,
    /// VDIV/VSQRT: 14.
    FpDivSqrt,
    /// VLDR/VSTR: 2, 3 for a double.
    FpLoadStore,
    /// VMOV between core and FP registers: 2.
    FpTransfer,
    /// VPUSH/VPOP/VLDM/VSTM: 1 + N (N in 32-bit words).
    FpLoadStoreMultiple,
    /// An instruction in an IT block whose condition failed: 1 (unicorn does not report these).
    ItSkipped,
}

impl Class {
    pub const ALL: [Class; 14] = [
        Class::Alu,
        Class::Divide,
        Class::Load,
        Class::Store,
        Class::LoadStoreDouble,
        Class::LoadStoreMultiple,
        Class::Branch,
        Class::FpAlu,
        Class::FpMac,
        Class::FpDivSqrt,
        Class::FpLoadStore,
        Class::FpTransfer,
        Class::FpLoadStoreMultiple,
        Class::ItSkipped,
    ];

    fn index(self) -> usize {
        self as usize
    }
}

/// Instructions and base cycles (without branch and flash penalties) of one class.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClassStat {
    pub instructions: u64,
    pub cycles: u64,
}

/// Running totals of one call.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    pub instructions: u64,
    pub base: u64,
    pub taken_branches: u64,
    pub flash_misses: u64,
    pub classes: [ClassStat; 14],
}

impl Counters {
    pub fn nominal(&self) -> u64 {
        self.base + P_NOMINAL * self.taken_branches
    }

    pub fn pessimistic(&self) -> u64 {
        self.base + P_PESSIMISTIC * self.taken_branches + FLASH_MISS * self.flash_misses
    }

    fn charge(&mut self, class: Class, instructions: u64, cycles: u64) {
        self.instructions += instructions;
        self.base += cycles;
        let c = &mut self.classes[class.index()];
        c.instructions += instructions;
        c.cycles += cycles;
    }
}

/// How the pessimistic model decides that a taken branch into flash misses the ART.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlashModel {
    /// The STM32F42x ART instruction cache: `lines` lines of 16 bytes (RM0090: 64 lines of
    /// 128 bits), modelled fully associative with LRU replacement, cold at the start of each
    /// call. Every flash line the code executes from is filled into it (the prefetch buffer is
    /// assumed to hide sequential fetches); a taken branch to a line it does not hold pays the
    /// wait states. The default.
    Art { lines: usize },
    /// Every taken branch into flash pays the wait states (an upper bound: no cache at all).
    EveryBranchTarget,
}

impl Default for FlashModel {
    fn default() -> Self {
        FlashModel::Art { lines: 64 }
    }
}

/// A fully associative LRU cache of 16-byte flash lines.
struct Art {
    lines: Vec<(u32, u64)>, // (line address >> 4, last use)
    capacity: usize,
    clock: u64,
}

impl Art {
    fn new(capacity: usize) -> Art {
        Art {
            lines: Vec::with_capacity(capacity),
            capacity,
            clock: 0,
        }
    }

    /// Uses `line`; returns whether it was already cached.
    fn touch(&mut self, line: u32) -> bool {
        self.clock += 1;
        if let Some(l) = self.lines.iter_mut().find(|l| l.0 == line) {
            l.1 = self.clock;
            return true;
        }
        if self.lines.len() < self.capacity {
            self.lines.push((line, self.clock));
        } else if let Some(lru) = self.lines.iter_mut().min_by_key(|l| l.1) {
            *lru = (line, self.clock);
        }
        false
    }
}

/// What the rules need to know about the previous executed instruction.
#[derive(Clone, Copy)]
struct Prev {
    pc: u32,
    size: u32,
    load_single: bool,
    store: bool,
    writes: u16,
}

/// The open IT block: `slots[..count]` are the addresses of the covered instructions,
/// `slots[count]` the address after the block; `next` the first slot not yet reached.
#[derive(Clone, Copy, Default)]
struct It {
    slots: [u32; 5],
    count: usize,
    next: usize,
}

/// The timing model's state over a stream of executed instructions.
pub struct Timing {
    pub counters: Counters,
    flash: FlashModel,
    art: Art,
    prev: Option<Prev>,
    it: Option<It>,
    last_line: Option<u32>,
}

impl Timing {
    pub fn new(flash: FlashModel) -> Timing {
        let lines = match flash {
            FlashModel::Art { lines } => lines.max(1),
            FlashModel::EveryBranchTarget => 1,
        };
        Timing {
            counters: Counters::default(),
            flash,
            art: Art::new(lines),
            prev: None,
            it: None,
            last_line: None,
        }
    }

    /// Starts a new call: counters to zero, cold ART, no previous instruction.
    pub fn start(&mut self) {
        let flash = self.flash;
        *self = Timing::new(flash);
    }

    /// Accounts the instruction at `pc`, about to execute, given the one executed before it.
    pub fn step(&mut self, pc: u32, d: &Decoded) {
        // 1. How did we get here from the previous instruction?
        let mut neighbour = self.prev; // the instruction the pipelining rules look at
        let mut taken = false;
        match self.prev {
            None => taken = true, // entered by the caller's BL: a fetch at a branch target
            Some(p) => {
                let expected = p.pc.wrapping_add(p.size);
                match self.it.as_mut() {
                    Some(it) if it.next <= it.count && it.slots[it.next] == expected => {
                        // Inside an IT block: instructions between `expected` and `pc` had
                        // their condition fail; unicorn did not report them.
                        match (it.next..=it.count).find(|&j| it.slots[j] == pc) {
                            Some(j) => {
                                let skipped = (j - it.next) as u64;
                                if skipped > 0 {
                                    self.counters.charge(Class::ItSkipped, skipped, skipped);
                                    neighbour = None;
                                }
                                it.next = j + 1;
                                if j >= it.count {
                                    self.it = None;
                                }
                            }
                            None => {
                                taken = true;
                                self.it = None;
                            }
                        }
                    }
                    _ => {
                        self.it = None;
                        taken = pc != expected;
                    }
                }
                if taken {
                    self.counters.taken_branches += 1;
                }
            }
        }

        // 2. Instruction fetch from flash: the ART model.
        if in_flash(pc) {
            let line = pc >> 4;
            if taken {
                let hit = self.art.touch(line);
                let miss = match self.flash {
                    FlashModel::Art { .. } => !hit,
                    FlashModel::EveryBranchTarget => true,
                };
                if miss {
                    self.counters.flash_misses += 1;
                }
            } else if self.last_line != Some(line) {
                self.art.touch(line);
            }
            let last = pc.wrapping_add(u32::from(d.size) - 1) >> 4;
            if last != line {
                self.art.touch(last);
            }
            self.last_line = Some(last);
        } else {
            self.last_line = None;
        }

        // 3. The instruction's own cost.
        let mut cost = u64::from(d.base);
        if let Some(n) = neighbour {
            let depends = d.addr_regs & n.writes != 0;
            if d.load_single && n.load_single && !depends {
                cost = 1;
            }
            if d.store_single && n.store {
                cost = 2;
            }
            if depends {
                cost += 1;
            }
        }
        self.counters.charge(d.class, 1, cost);

        if let Some(block) = d.it {
            let mut slots = [0u32; 5];
            let mut at = pc.wrapping_add(u32::from(d.size));
            let count = usize::from(block.count);
            for (slot, size) in slots.iter_mut().zip(block.sizes.iter()).take(count) {
                *slot = at;
                at = at.wrapping_add(u32::from(*size));
            }
            slots[count] = at;
            self.it = Some(It {
                slots,
                count,
                next: 0,
            });
        }

        self.prev = Some(Prev {
            pc,
            size: u32::from(d.size),
            load_single: d.load_single,
            store: d.class == Class::Store,
            writes: d.writes,
        });
    }

    /// Ends a call that returned to `exit`: the return is a taken branch (its target, the
    /// caller, is outside the model, so no flash miss is charged for it).
    pub fn finish(&mut self, exit: u32) {
        if let Some(p) = self.prev {
            if p.pc.wrapping_add(p.size) != exit {
                self.counters.taken_branches += 1;
            }
        }
        self.prev = None;
        self.it = None;
    }

    /// The next instruction is reached by a jump the code did not make (exception entry or
    /// return, reset): counted as a taken branch to its address, outside any IT block.
    pub fn redirect(&mut self) {
        self.prev = None;
        self.it = None;
    }

    /// Whether the next instruction may be inside an IT block (an interrupt must not be taken
    /// there: the virtual board's exception entry does not stack the IT state).
    pub fn in_it_block(&self) -> bool {
        self.it.is_some()
    }

    /// The PC of the instruction being executed (the last one reported).
    pub fn pc(&self) -> u32 {
        self.prev.map_or(0, |p| p.pc)
    }
}

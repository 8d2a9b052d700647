//! The NVIC and the System Control Block: which exception runs next.
//!
//! ARMv7-M Architecture Reference Manual (DDI 0403E), B1.5 "ARMv7-M exception model" (priorities,
//! preemption, pending, active) and B3.2/B3.4 (SCB and NVIC registers). The STM32F427 implements
//! 4 priority bits (PM0214 4.3.7), 91 external interrupts (RM0090 table 62) and a VTOR.
//!
//! Exceptions here are numbers: 1 Reset … 15 SysTick, 16 + n the external interrupt n.
//! Peripheral interrupt lines are level-sensitive: while a line is high its interrupt is
//! pending again as soon as it is not active (B1.5.3, "a pending exception … is cleared when
//! it becomes active"; the peripheral keeps requesting).

/// Exception numbers of the Cortex-M4.
pub const HARD_FAULT: u16 = 3;
pub const MEM_MANAGE: u16 = 4;
pub const BUS_FAULT: u16 = 5;
pub const USAGE_FAULT: u16 = 6;
pub const SVCALL: u16 = 11;
pub const PENDSV: u16 = 14;
pub const SYSTICK: u16 = 15;
/// First external interrupt.
pub const IRQ0: u16 = 16;
/// External interrupts of the STM32F427 (RM0090 table 62, positions 0–90).
pub const IRQS: u16 = 91;

/// Implemented priority bits (PM0214: "4 bits of interrupt priority").
const PRIO_MASK: u8 = 0xF0;
/// The "no active exception, no mask" priority of Thread mode.
pub const THREAD: i16 = 256;

/// NVIC and SCB state.
#[derive(Clone, Debug)]
pub struct Nvic {
    enabled: [u32; 4],
    pending: [u32; 4],
    lines: [u32; 4],
    ipr: [u8; IRQS as usize],
    /// SHPR1–3: priorities of exceptions 4–15.
    shpr: [u8; 12],
    /// Pending system exceptions, bit = exception number (2–15).
    sys_pending: u16,
    /// Active exceptions, innermost last.
    active: Vec<u16>,
    pub vtor: u32,
    prigroup: u8,
    pub scr: u32,
    pub ccr: u32,
    pub shcsr: u32,
    pub cfsr: u32,
    pub hfsr: u32,
    pub cpacr: u32,
    pub fpccr: u32,
    pub fpcar: u32,
    /// AIRCR.SYSRESETREQ was written with the key.
    pub reset_requested: bool,
}

impl Default for Nvic {
    fn default() -> Self {
        Nvic {
            enabled: [0; 4],
            pending: [0; 4],
            lines: [0; 4],
            ipr: [0; IRQS as usize],
            shpr: [0; 12],
            sys_pending: 0,
            active: Vec::new(),
            vtor: 0,
            prigroup: 0,
            scr: 0,
            ccr: 0x200, // STKALIGN (B3.2.8: resets to 1 on the M4)
            shcsr: 0,
            cfsr: 0,
            hfsr: 0,
            cpacr: 0,
            // ASPEN | LSPEN (B3.2.22 reset value): lazy FP state preservation on.
            fpccr: 0xC000_0000,
            fpcar: 0,
            reset_requested: false,
        }
    }
}

fn bit(exc: u16) -> (usize, u32) {
    let n = usize::from(exc - IRQ0);
    (n / 32, 1 << (n % 32))
}

fn is_irq(exc: u16) -> bool {
    (IRQ0..IRQ0 + IRQS).contains(&exc)
}

impl Nvic {
    /// Raw priority of an exception (fixed negative ones for Reset, NMI, HardFault).
    pub fn priority(&self, exc: u16) -> i16 {
        match exc {
            1 => -3,
            2 => -2,
            HARD_FAULT => -1,
            4..=15 => i16::from(self.shpr[usize::from(exc - 4)]),
            e if is_irq(e) => i16::from(self.ipr[usize::from(e - IRQ0)]),
            _ => THREAD,
        }
    }

    /// The group priority (B1.5.4: the sub-priority bits below PRIGROUP do not preempt).
    fn group(&self, prio: i16) -> i16 {
        if prio < 0 {
            return prio;
        }
        let mask = (0xFFu16 << (self.prigroup + 1)) as u8;
        i16::from(prio as u8 & mask)
    }

    /// Execution priority (B1.5.4): the highest of the active exceptions, BASEPRI, PRIMASK,
    /// FAULTMASK.
    pub fn execution_priority(&self, basepri: u8, primask: bool, faultmask: bool) -> i16 {
        let mut p = THREAD;
        for &e in &self.active {
            p = p.min(self.group(self.priority(e)));
        }
        if basepri & PRIO_MASK != 0 {
            p = p.min(self.group(i16::from(basepri & PRIO_MASK)));
        }
        if primask {
            p = p.min(0);
        }
        if faultmask {
            p = p.min(-1);
        }
        p
    }

    /// The pending exception that would be taken next, whatever the masks: highest priority,
    /// then lowest number.
    pub fn highest_pending(&self) -> Option<u16> {
        let mut best: Option<(i16, u16)> = None;
        let mut consider = |exc: u16, prio: i16| {
            if best.is_none_or(|(p, _)| prio < p) {
                best = Some((prio, exc));
            }
        };
        for exc in 2..16u16 {
            if self.sys_pending & (1 << exc) != 0 {
                consider(exc, self.priority(exc));
            }
        }
        for w in 0..4 {
            let mut bits = self.pending[w] & self.enabled[w];
            while bits != 0 {
                let b = bits.trailing_zeros();
                bits &= bits - 1;
                let exc = IRQ0 + (w as u16) * 32 + b as u16;
                if is_irq(exc) {
                    consider(exc, self.priority(exc));
                }
            }
        }
        best.map(|(_, e)| e)
    }

    /// The exception that preempts now, if any.
    pub fn preempting(&self, basepri: u8, primask: bool, faultmask: bool) -> Option<u16> {
        let exc = self.highest_pending()?;
        let level = self.execution_priority(basepri, primask, faultmask);
        (self.group(self.priority(exc)) < level).then_some(exc)
    }

    /// Whether anything is pending and enabled (a WFI wakes on it, masked or not: B1.5.19).
    pub fn any_pending(&self) -> bool {
        self.highest_pending().is_some()
    }

    pub fn set_pending(&mut self, exc: u16) {
        if is_irq(exc) {
            let (w, m) = bit(exc);
            self.pending[w] |= m;
        } else if (2..16).contains(&exc) {
            self.sys_pending |= 1 << exc;
        }
    }

    fn clear_pending(&mut self, exc: u16) {
        if is_irq(exc) {
            let (w, m) = bit(exc);
            self.pending[w] &= !m;
        } else if (2..16).contains(&exc) {
            self.sys_pending &= !(1 << exc);
        }
    }

    pub fn is_pending(&self, exc: u16) -> bool {
        if is_irq(exc) {
            let (w, m) = bit(exc);
            self.pending[w] & m != 0
        } else {
            (2..16).contains(&exc) && self.sys_pending & (1 << exc) != 0
        }
    }

    pub fn is_active(&self, exc: u16) -> bool {
        self.active.contains(&exc)
    }

    /// Sets a peripheral's interrupt line (external interrupt `irq`, 0-based) high or low.
    pub fn set_line(&mut self, irq: u16, high: bool) {
        let exc = IRQ0 + irq;
        if !is_irq(exc) {
            return;
        }
        let (w, m) = bit(exc);
        if high {
            self.lines[w] |= m;
            if !self.is_active(exc) {
                self.pending[w] |= m;
            }
        } else {
            self.lines[w] &= !m;
        }
    }

    /// Exception entry: `exc` becomes active and stops pending.
    pub fn activate(&mut self, exc: u16) {
        self.clear_pending(exc);
        self.active.push(exc);
    }

    /// Exception return from the innermost active exception; a peripheral line still high
    /// pends its interrupt again. Returns the exception, or `None` when nothing was active.
    pub fn deactivate(&mut self) -> Option<u16> {
        let exc = self.active.pop()?;
        if is_irq(exc) {
            let (w, m) = bit(exc);
            if self.lines[w] & m != 0 {
                self.pending[w] |= m;
            }
        }
        Some(exc)
    }

    /// Innermost active exception (0 in Thread mode).
    pub fn current(&self) -> u16 {
        self.active.last().copied().unwrap_or(0)
    }

    /// Active exceptions, outermost first.
    pub fn active(&self) -> &[u16] {
        &self.active
    }

    /// Whether a fault of the given configurable kind is enabled in SHCSR (else it escalates to
    /// HardFault, B1.5.8).
    pub fn fault_enabled(&self, exc: u16) -> bool {
        let bit = match exc {
            MEM_MANAGE => 16,
            BUS_FAULT => 17,
            USAGE_FAULT => 18,
            _ => return false,
        };
        self.shcsr & (1 << bit) != 0
    }

    /// Reads a register of the System Control Space page 0xE000_E000 (offset into the page),
    /// except SysTick's. `None`: not an NVIC/SCB register (plain memory).
    pub fn read(&self, offset: u32) -> Option<u32> {
        let word = |a: &[u32; 4], o: u32| a.get(((o & 0x7F) / 4) as usize).copied().unwrap_or(0);
        Some(match offset {
            0x100..=0x17F => word(&self.enabled, offset - 0x100),
            0x180..=0x1FF => word(&self.enabled, offset - 0x180),
            0x200..=0x27F => word(&self.pending, offset - 0x200),
            0x280..=0x2FF => word(&self.pending, offset - 0x280),
            0x300..=0x37F => {
                let mut v = 0;
                for b in 0..32u16 {
                    let exc = IRQ0 + ((offset - 0x300) / 4 * 32) as u16 + b;
                    if self.is_active(exc) {
                        v |= 1 << b;
                    }
                }
                v
            }
            0x400..=0x4FF => {
                let at = (offset & !3) - 0x400;
                let mut v = 0u32;
                for i in 0..4 {
                    let p = self.ipr.get((at + i) as usize).copied().unwrap_or(0);
                    v |= u32::from(p) << (8 * i);
                }
                v
            }
            0xD00 => 0x410F_C241, // CPUID: Cortex-M4 r0p1
            0xD04 => self.icsr(),
            0xD08 => self.vtor,
            0xD0C => 0xFA05_0000 | u32::from(self.prigroup) << 8,
            0xD10 => self.scr,
            0xD14 => self.ccr,
            0xD18..=0xD23 => {
                let at = ((offset & !3) - 0xD18) as usize;
                u32::from_le_bytes([
                    self.shpr[at],
                    self.shpr[at + 1],
                    self.shpr[at + 2],
                    self.shpr[at + 3],
                ])
            }
            0xD24 => self.shcsr,
            0xD28 => self.cfsr,
            0xD2C => self.hfsr,
            0xD88 => self.cpacr,
            0xF34 => self.fpccr,
            0xF38 => self.fpcar,
            _ => return None,
        })
    }

    fn icsr(&self) -> u32 {
        let active = u32::from(self.current());
        let pending = u32::from(self.highest_pending().unwrap_or(0));
        let isr_pending = (self.pending.iter().zip(self.enabled.iter())).any(|(p, _)| *p != 0);
        let mut v = active | pending << 12;
        if self.active.len() <= 1 {
            v |= 1 << 11; // RETTOBASE
        }
        if isr_pending {
            v |= 1 << 22;
        }
        if self.sys_pending & (1 << SYSTICK) != 0 {
            v |= 1 << 26;
        }
        if self.sys_pending & (1 << PENDSV) != 0 {
            v |= 1 << 28;
        }
        v
    }

    /// Writes a register (see [`Nvic::read`]); returns false for plain memory.
    pub fn write(&mut self, offset: u32, value: u32) -> bool {
        let idx = |o: u32| ((o & 0x7F) / 4) as usize;
        match offset {
            0x100..=0x10F => self.enabled[idx(offset - 0x100)] |= value,
            0x180..=0x18F => self.enabled[idx(offset - 0x180)] &= !value,
            0x200..=0x20F => self.pending[idx(offset - 0x200)] |= value,
            0x280..=0x28F => {
                let i = idx(offset - 0x280);
                // a line still high keeps its interrupt pending
                self.pending[i] &= !value | self.lines[i];
            }
            0x110..=0x17F | 0x190..=0x1FF | 0x210..=0x27F | 0x290..=0x37F => {}
            0x400..=0x4FF => {
                let at = (offset & !3) - 0x400;
                for i in 0..4 {
                    if let Some(p) = self.ipr.get_mut((at + i) as usize) {
                        *p = (value >> (8 * i)) as u8 & PRIO_MASK;
                    }
                }
            }
            0xF00 => self.set_pending(IRQ0 + (value & 0x1FF) as u16), // STIR
            0xD04 => {
                if value & (1 << 28) != 0 {
                    self.sys_pending |= 1 << PENDSV;
                }
                if value & (1 << 27) != 0 {
                    self.sys_pending &= !(1 << PENDSV);
                }
                if value & (1 << 26) != 0 {
                    self.sys_pending |= 1 << SYSTICK;
                }
                if value & (1 << 25) != 0 {
                    self.sys_pending &= !(1 << SYSTICK);
                }
                if value & (1 << 31) != 0 {
                    self.sys_pending |= 1 << 2;
                }
            }
            0xD08 => self.vtor = value & 0xFFFF_FF80,
            0xD0C => {
                if value >> 16 == 0x05FA {
                    self.prigroup = ((value >> 8) & 7) as u8;
                    if value & 4 != 0 {
                        self.reset_requested = true;
                    }
                }
            }
            0xD10 => self.scr = value,
            0xD14 => self.ccr = value,
            0xD18..=0xD23 => {
                let at = ((offset & !3) - 0xD18) as usize;
                for (i, b) in value.to_le_bytes().iter().enumerate() {
                    self.shpr[at + i] = b & PRIO_MASK;
                }
            }
            0xD24 => self.shcsr = value,
            0xD28 => self.cfsr &= !value, // write 1 to clear
            0xD2C => self.hfsr &= !value,
            0xD88 => self.cpacr = value,
            0xF34 => self.fpccr = value,
            0xF38 => self.fpcar = value,
            _ => return false,
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RTIC's encoding of logical priority `p` with 4 bits: (16 − p) << 4.
    fn rtic(p: u8) -> u8 {
        (16 - p) << 4
    }

    fn with_irqs(prios: &[(u16, u8)]) -> Nvic {
        let mut n = Nvic::default();
        for &(irq, p) in prios {
            n.write(
                0x400 + u32::from(irq & !3),
                u32::from(rtic(p)) << (8 * (irq % 4)),
            );
            n.write(0x100 + u32::from(irq / 32) * 4, 1 << (irq % 32));
        }
        n
    }

    #[test]
    fn higher_priority_preempts_lower_waits() {
        let mut n = with_irqs(&[(57, 4), (84, 1), (52, 5)]);
        n.set_pending(IRQ0 + 84);
        assert_eq!(n.preempting(0, false, false), Some(IRQ0 + 84));
        n.activate(IRQ0 + 84);
        assert_eq!(n.preempting(0, false, false), None);
        n.set_pending(IRQ0 + 57);
        assert_eq!(n.preempting(0, false, false), Some(IRQ0 + 57));
        n.activate(IRQ0 + 57);
        // BASEPRI at logical 5 (a lock on a resource shared with the UART task) masks UART4
        n.set_pending(IRQ0 + 52);
        assert_eq!(n.preempting(rtic(5), false, false), None);
        assert_eq!(n.preempting(0, false, false), Some(IRQ0 + 52));
        // PRIMASK masks everything but the faults
        assert_eq!(n.preempting(0, true, false), None);
        assert_eq!(n.deactivate(), Some(IRQ0 + 57));
        assert_eq!(n.current(), IRQ0 + 84);
    }

    #[test]
    fn same_priority_does_not_preempt_and_lowest_number_goes_first() {
        let mut n = with_irqs(&[(57, 4), (78, 4)]);
        n.set_pending(IRQ0 + 78);
        n.set_pending(IRQ0 + 57);
        assert_eq!(n.highest_pending(), Some(IRQ0 + 57));
        n.activate(IRQ0 + 57);
        assert_eq!(n.preempting(0, false, false), None, "equal priority waits");
        n.deactivate();
        assert_eq!(
            n.preempting(0, false, false),
            Some(IRQ0 + 78),
            "then tail-chains"
        );
    }

    #[test]
    fn disabled_interrupts_stay_pending_but_are_not_taken() {
        let mut n = with_irqs(&[(57, 4)]);
        n.write(0x180 + 4, 1 << (57 - 32));
        n.set_pending(IRQ0 + 57);
        assert!(n.is_pending(IRQ0 + 57));
        assert_eq!(n.preempting(0, false, false), None);
        assert!(!n.any_pending());
    }

    #[test]
    fn a_high_line_pends_again_after_return_and_after_clear() {
        let mut n = with_irqs(&[(52, 5)]);
        n.set_line(52, true);
        assert!(n.is_pending(IRQ0 + 52));
        n.activate(IRQ0 + 52);
        assert!(!n.is_pending(IRQ0 + 52));
        assert_eq!(n.deactivate(), Some(IRQ0 + 52));
        assert!(n.is_pending(IRQ0 + 52), "still requesting");
        n.write(0x280 + 4, 1 << (52 - 32));
        assert!(n.is_pending(IRQ0 + 52), "ICPR cannot clear a high line");
        n.set_line(52, false);
        n.write(0x280 + 4, 1 << (52 - 32));
        assert!(!n.is_pending(IRQ0 + 52));
    }

    #[test]
    fn prigroup_splits_group_and_subpriority() {
        let mut n = with_irqs(&[(10, 4), (11, 3)]);
        // PRIGROUP 5: group = bits 7:6 → (16-4)<<4 = 0xC0 and (16-3)<<4 = 0xD0 share group 0xC0
        n.write(0xD0C, 0x05FA_0000 | 5 << 8);
        n.set_pending(IRQ0 + 11);
        n.activate(IRQ0 + 10);
        assert_eq!(n.preempting(0, false, false), None);
        assert_eq!(n.read(0xD0C), Some(0xFA05_0500));
        n.write(0xD0C, 4); // no key: ignored
        assert!(!n.reset_requested);
        n.write(0xD0C, 0x05FA_0004);
        assert!(n.reset_requested);
    }

    #[test]
    fn icsr_shows_active_and_pending_and_sets_pendsv() {
        let mut n = with_irqs(&[(57, 4)]);
        n.write(0xD20, 0xF0F0_0000); // PendSV and SysTick lowest
        n.write(0xD04, 1 << 28);
        assert_eq!(n.highest_pending(), Some(PENDSV));
        n.set_pending(IRQ0 + 57);
        n.activate(IRQ0 + 57);
        let icsr = n.read(0xD04).unwrap();
        assert_eq!(icsr & 0x1FF, u32::from(IRQ0 + 57));
        assert_eq!((icsr >> 12) & 0x1FF, u32::from(PENDSV));
        assert_ne!(icsr & (1 << 28), 0);
    }
}

//! The peripherals behind the memory map, and what their registers do when the CPU touches
//! them. Registers without a model (FLASH interface, SYSCFG, DBGMCU, timers the firmware does
//! not use…) hold what was written. Bit-band aliases (ARMv7-M ARM B3.1.3; the HAL sets RCC
//! enable bits through them) are read-modify-writes of the word they alias.

use std::collections::HashMap;

use super::dcmi::{Dcmi, DCMI_BASE};
use super::dma::{Dma, DMA2_BASE};
use super::events::Queue;
use super::gpio::{Gpio, GPIO_BASE, PORTS, PORT_A, PORT_E};
use super::iwdg::{Iwdg, IWDG_BASE};
use super::nvic::Nvic;
use super::ov7670::Ov7670;
use super::rcc::{self, Clocks, PWR_BASE, RCC_BASE};
use super::systick::SysTick;
use super::uart::{Uart, UART4_BASE};

/// Peripheral region mapped as MMIO: APB1, APB2, AHB1 (RM0090 table 1).
pub const PERIPH: std::ops::Range<u32> = 0x4000_0000..0x4008_0000;
/// Its bit-band alias.
pub const PERIPH_BB: u32 = 0x4200_0000;
/// System Control Space page: SysTick, NVIC, SCB.
pub const SCS_PAGE: u32 = 0xE000_E000;

/// External interrupt numbers (RM0090 table 62) of the modelled peripherals.
pub const IRQ_UART4: u16 = 52;
pub const IRQ_DMA2_STREAM0: u16 = 56;
pub const IRQ_DCMI: u16 = 78;
/// DMA2 streams 5–7 sit after the Ethernet and OTG interrupts.
const IRQ_DMA2_STREAM5: u16 = 68;

/// The DCMI's DMA stream and channel (RM0090 table 43).
pub const DCMI_STREAM: usize = 1;
pub const DCMI_CHANNEL: u32 = 1;

/// SCCB pins: SDA PE2, SCL PE3 (docs/hardware.md); XCLK on PA8 (MCO1, AF0).
const SDA: u32 = 2;
const SCL: u32 = 3;
const XCLK: u32 = 8;

/// Every peripheral model.
#[derive(Clone, Debug, Default)]
pub struct Peripherals {
    pub nvic: Nvic,
    pub systick: SysTick,
    pub gpio: Gpio,
    pub camera: Ov7670,
    pub dma: Dma,
    pub dcmi: Dcmi,
    pub uart: Uart,
    pub iwdg: Iwdg,
    /// Unmodelled registers (and the RCC/PWR ones), by word address.
    regs: HashMap<u32, u32>,
    /// Whether an OV7670 is on the board.
    pub camera_present: bool,
    /// RCC_CSR reset flags to show after the next reset.
    pub reset_flags: u32,
}

impl Peripherals {
    /// Power-on (or reset) state with the sensor present or not.
    pub fn new(camera_present: bool, reset_flags: u32) -> Peripherals {
        let mut p = Peripherals {
            camera_present,
            reset_flags,
            ..Peripherals::default()
        };
        p.gpio.board_pull_up[PORT_E] = 1 << SDA | 1 << SCL;
        p.regs.insert(RCC_BASE + 0x74, reset_flags);
        p
    }

    fn stored(&self, addr: u32) -> u32 {
        self.regs
            .get(&addr)
            .copied()
            .unwrap_or_else(|| rcc::reset_value(addr))
    }

    pub fn clocks(&self) -> Clocks {
        rcc::clocks(self.stored(RCC_BASE + 4), self.stored(RCC_BASE + 8))
    }

    /// Whether the sensor gets its clock: MCO1 = HSE with HSE on, and PA8 on AF0.
    pub fn xclk_running(&self) -> bool {
        let cfgr = self.stored(RCC_BASE + 8);
        let cr = self.stored(RCC_BASE);
        (cfgr >> 21) & 3 == 2
            && cr & (1 << 16) != 0
            && self.gpio.mode(PORT_A, XCLK) == 2
            && self.gpio.alternate(PORT_A, XCLK) == 0
    }

    /// The sensor answers on SCCB.
    pub fn camera_alive(&self) -> bool {
        self.camera_present && self.xclk_running()
    }

    /// Word read of a peripheral register (word-aligned `addr`).
    pub fn read(&mut self, addr: u32, now: u64) -> u32 {
        match addr {
            a if (GPIO_BASE..GPIO_BASE + 0x400 * PORTS as u32).contains(&a) => self
                .gpio
                .read(((a - GPIO_BASE) / 0x400) as usize, (a - GPIO_BASE) % 0x400),
            a if (DMA2_BASE..DMA2_BASE + 0x400).contains(&a) => self.dma.read(a - DMA2_BASE),
            a if (DCMI_BASE..DCMI_BASE + 0x400).contains(&a) => self.dcmi.read(a - DCMI_BASE),
            a if (UART4_BASE..UART4_BASE + 0x400).contains(&a) => self.uart.read(a - UART4_BASE),
            a if (IWDG_BASE..IWDG_BASE + 0x400).contains(&a) => self.iwdg.read(a - IWDG_BASE),
            a if a == PWR_BASE + 4 => {
                let cr = self.stored(PWR_BASE);
                let mut csr = rcc::read_fixup(a, self.stored(a));
                csr = (csr & !(3 << 16)) | (cr & (3 << 16));
                csr
            }
            a if (SCS_PAGE + 0x10..SCS_PAGE + 0x20).contains(&a) => {
                self.systick.read(a - SCS_PAGE - 0x10, now)
            }
            a if (SCS_PAGE..SCS_PAGE + 0x1000).contains(&a) => self
                .nvic
                .read(a - SCS_PAGE)
                .unwrap_or_else(|| self.stored(a)),
            a => rcc::read_fixup(a, self.stored(a)),
        }
    }

    /// Word write; returns whether interrupt state may have changed.
    pub fn write(&mut self, addr: u32, value: u32, now: u64, q: &mut Queue) -> bool {
        match addr {
            a if (GPIO_BASE..GPIO_BASE + 0x400 * PORTS as u32).contains(&a) => {
                let port = ((a - GPIO_BASE) / 0x400) as usize;
                self.gpio.write(port, (a - GPIO_BASE) % 0x400, value);
                if port == PORT_E {
                    self.sccb_changed();
                }
                false
            }
            a if (DMA2_BASE..DMA2_BASE + 0x400).contains(&a) => {
                self.dma.write(a - DMA2_BASE, value);
                true
            }
            a if (DCMI_BASE..DCMI_BASE + 0x400).contains(&a) => {
                self.dcmi.write(a - DCMI_BASE, value);
                true
            }
            a if (UART4_BASE..UART4_BASE + 0x400).contains(&a) => {
                let cycles = self.uart_byte_cycles();
                self.uart.write(a - UART4_BASE, value, now, cycles, q);
                true
            }
            a if (IWDG_BASE..IWDG_BASE + 0x400).contains(&a) => {
                self.iwdg
                    .write(a - IWDG_BASE, value, now, crate::CLOCK_HZ, q);
                false
            }
            a if (SCS_PAGE + 0x10..SCS_PAGE + 0x20).contains(&a) => {
                self.systick.write(a - SCS_PAGE - 0x10, value, now, q);
                false
            }
            a if (SCS_PAGE..SCS_PAGE + 0x1000).contains(&a) => {
                if !self.nvic.write(a - SCS_PAGE, value) {
                    self.regs.insert(a, value);
                }
                true
            }
            a => {
                let old = self.stored(a);
                self.regs.insert(a, rcc::write_fixup(a, old, value));
                if a == RCC_BASE + 8 || a == RCC_BASE {
                    self.sccb_changed();
                }
                false
            }
        }
    }

    /// Core cycles (at [`crate::CLOCK_HZ`]) per UART4 byte at its current baud rate.
    pub fn uart_byte_cycles(&self) -> u64 {
        self.uart.byte_cycles(crate::CLOCK_HZ, self.clocks().pclk1)
    }

    /// SCCB lines may have moved: let the sensor see them, and show its pull on SDA.
    fn sccb_changed(&mut self) {
        let scl = self.gpio.released_or_high(PORT_E, SCL);
        let sda = self.gpio.released_or_high(PORT_E, SDA);
        let alive = self.camera_alive();
        self.camera.bus(scl, sda, alive);
        if self.camera.pulls_sda_low() {
            self.gpio.external_low[PORT_E] |= 1 << SDA;
        } else {
            self.gpio.external_low[PORT_E] &= !(1 << SDA);
        }
    }

    /// Sets the NVIC lines of the modelled peripherals from their state.
    pub fn update_lines(&mut self) {
        self.nvic.set_line(IRQ_UART4, self.uart.line_high());
        self.nvic.set_line(IRQ_DCMI, self.dcmi.line_high());
        for s in 0..8 {
            let irq = if s < 5 {
                IRQ_DMA2_STREAM0 + s as u16
            } else {
                IRQ_DMA2_STREAM5 + (s as u16 - 5)
            };
            self.nvic.set_line(irq, self.dma.line(s));
        }
    }

    /// The bit-band alias `addr` → (word address, bit).
    pub fn bit_band(addr: u32) -> (u32, u32) {
        let off = addr - PERIPH_BB;
        (
            (PERIPH.start + off / 32) & !3,
            (off % 32) / 4 + 8 * ((off / 32) % 4),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bit_band_alias_addresses_rcc_enable_bits() {
        // RCC_AHB1ENR (0x4002_3830) bit 22 (DMA2EN): alias 0x4200_0000 + 0x23830 × 32 + 22 × 4
        let alias = PERIPH_BB + 0x23830 * 32 + 22 * 4;
        assert_eq!(Peripherals::bit_band(alias), (0x4002_3830, 22));
        // a byte offset inside the word: 0x4002_3831 bit 1 is bit 9 of the word
        let alias = PERIPH_BB + 0x23831 * 32 + 4;
        assert_eq!(Peripherals::bit_band(alias), (0x4002_3830, 9));
    }

    #[test]
    fn sccb_answers_only_with_xclk() {
        let mut p = Peripherals::new(true, 0);
        let mut q = Queue::default();
        assert!(!p.camera_alive());
        p.write(RCC_BASE, 1 << 16, 0, &mut q); // HSEON
        p.write(RCC_BASE + 8, 2 << 21, 0, &mut q); // MCO1 = HSE
        p.write(GPIO_BASE, 2 << 16, 0, &mut q); // PA8 alternate, AF0
        assert!(p.camera_alive());
        assert!(!Peripherals::new(false, 0).camera_alive());
    }
}

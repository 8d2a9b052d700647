//! Board bring-up steps of `init`, each returning a ready driver (so `init` reads as a list).

use rtt_target::rprintln;
use stm32f4xx_hal::gpio::{gpioa, gpiob, gpioc, gpioe};
use stm32f4xx_hal::pac;
use stm32f4xx_hal::prelude::*;
use stm32f4xx_hal::rcc::{Config, Rcc};
use stm32f4xx_hal::serial::SerialExt;
use stm32f4xx_hal::time::Bps;

use crate::board;
use crate::camera;
use crate::motor_link::MotorLink;

/// HSE 25 MHz → 180 MHz, the debug bits RTT needs in Sleep, and the clocks of DMA2 and DCMI.
/// Prints what the HAL actually configured.
pub fn clocks(rcc: pac::RCC, dbgmcu: &pac::DBGMCU) -> Rcc {
    // Printed before `freeze`: if this is the last line, HSE did not start (`freeze` waits
    // for HSERDY forever) or a clock request was rejected (the panic message follows).
    rprintln!(
        "clocks: starting HSE {} Hz -> SYSCLK {} Hz",
        board::HSE_HZ,
        board::SYSCLK_HZ
    );
    // `freeze` sets the PLL, the flash wait states and the regulator over-drive, and panics
    // if the request is out of range.
    let rcc = rcc.freeze(
        Config::hse(board::HSE_HZ.Hz())
            .sysclk(board::SYSCLK_HZ.Hz())
            .pclk1(board::PCLK1_HZ.Hz())
            .pclk2(board::PCLK2_HZ.Hz()),
    );
    // `wfi` in idle: on STM32 the debugger loses memory access to a sleeping core unless
    // DBGMCU_CR.DBG_SLEEP keeps the clocks running in Sleep mode, and RTT stops with it; probe-rs
    // clears the bit when it detaches, so the firmware sets it itself. A clocked DMA controller
    // is the other half of the usual STM32 RTT-in-sleep workaround (probe-rs issue #350): DMA2
    // runs the camera anyway. DBG_IWDG_STOP freezes the watchdog while a debugger halts the core.
    dbgmcu.cr().modify(|_, w| w.dbg_sleep().set_bit());
    dbgmcu.apb1_fz().modify(|_, w| w.dbg_iwdg_stop().set_bit());
    rcc.ahb1enr().modify(|_, w| w.dma2en().set_bit());
    rcc.ahb2enr().modify(|_, w| w.dcmien().set_bit());

    let c = rcc.clocks;
    rprintln!(
        "clocks: SYSCLK {} Hz (asked {}), HCLK {} Hz, PCLK1 {} Hz (asked {}), PCLK2 {} Hz (asked {}), computed for an HSE of {} Hz",
        c.sysclk().raw(),
        board::SYSCLK_HZ,
        c.hclk().raw(),
        c.pclk1().raw(),
        board::PCLK1_HZ,
        c.pclk2().raw(),
        board::PCLK2_HZ,
        board::HSE_HZ
    );
    if c.sysclk().raw() != board::SYSCLK_HZ
        || c.pclk1().raw() != board::PCLK1_HZ
        || c.pclk2().raw() != board::PCLK2_HZ
    {
        rprintln!("WARNING: clocks differ from the requested ones (src/board.rs)");
    }
    rcc
}

/// The GPIO ports the firmware uses, split once (`split` resets its port).
pub struct Ports {
    /// Port A.
    pub a: gpioa::Parts,
    /// Port B.
    pub b: gpiob::Parts,
    /// Port C.
    pub c: gpioc::Parts,
    /// Port E.
    pub e: gpioe::Parts,
}

/// The camera: XCLK, then sensor reset, id check and register table over SCCB (reported on
/// RTT), and the DCMI with its pins (not started). Also whether the sensor answered, and the
/// motor link's pin from port C.
pub fn camera(
    ports: Ports,
    rcc: &mut Rcc,
    dcmi: pac::DCMI,
    dma2: pac::DMA2,
) -> (camera::Camera, camera::dcmi::Dcmi, bool, gpioc::PC10) {
    let Ports { a, b, c, e } = ports;
    let pins = camera::Pins {
        xclk: a.pa8,
        sda: e.pe2,
        scl: e.pe3,
    };
    let mut cam = camera::Camera::new(pins, rcc, rcc.clocks.sysclk().raw());
    let ok = match cam.init() {
        Ok(info) => {
            rprintln!("camera: {}", info);
            true
        }
        Err(error) => {
            rprintln!(
                "ERROR camera: {} (no capture; the watchdog retries by a reset)",
                error
            );
            false
        }
    };
    // DCMI pins to AF13 (board::DCMI_AF). The pin objects are dropped: the mode stays.
    let _ = (
        c.pc6.into_alternate::<{ board::DCMI_AF }>(),
        c.pc7.into_alternate::<{ board::DCMI_AF }>(),
        e.pe0.into_alternate::<{ board::DCMI_AF }>(),
        e.pe1.into_alternate::<{ board::DCMI_AF }>(),
        e.pe4.into_alternate::<{ board::DCMI_AF }>(),
        b.pb6.into_alternate::<{ board::DCMI_AF }>(),
        e.pe5.into_alternate::<{ board::DCMI_AF }>(),
        e.pe6.into_alternate::<{ board::DCMI_AF }>(),
        a.pa4.into_alternate::<{ board::DCMI_AF }>(),
        b.pb7.into_alternate::<{ board::DCMI_AF }>(),
        a.pa6.into_alternate::<{ board::DCMI_AF }>(),
    );
    (cam, camera::dcmi::Dcmi::new(dcmi, dma2), ok, c.pc10)
}

/// The motor link on UART4 TX, with the stop frames already queued.
pub fn motor_link(uart: pac::UART4, tx: board::MotorTxPin, rcc: &mut Rcc) -> MotorLink {
    let tx = match uart.tx(tx, Bps(board::MOTOR_BAUD), rcc) {
        Ok(tx) => tx,
        Err(_) => panic!(
            "UART4 cannot do {} baud at PCLK1 {} Hz",
            board::MOTOR_BAUD,
            board::PCLK1_HZ
        ),
    };
    MotorLink::new(tx)
}

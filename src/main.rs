//! # alvs-firmware: RTIC 2 firmware for the Colias sense board (STM32F427VI)
//!
//! This firmware so far only brings the board up:
//!
//! - configures the clocks (25 MHz HSE -> 180 MHz SYSCLK, see [`board`]);
//! - sets up RTT with two up channels, 0 "log" (text; also where panic messages go) and
//!   1 "telemetry" (reserved: nothing is written to it yet);
//! - prints a boot banner with the crate version and the clocks actually achieved;
//! - starts the camera's XCLK and configures the OV7670 over SCCB ([`camera`]), then reports
//!   its id or a clear `ERROR camera: ...` line; the firmware runs on without a camera;
//! - prints the Table I thresholds of `alvs_tasks::Params::default()` (which proves the model
//!   crate links);
//! - then sleeps in `idle`.
//!
//! It does **not** yet capture frames (DCMI/DMA), run the aLPLC2 network, send telemetry or
//! drive the motors: those come later.
//!
//! Flash and watch the log with `cargo embed --release` (see `Embed.toml`).
#![no_std]
#![no_main]

mod board;
mod camera;

// A panic prints its message over RTT (the print channel, up channel 0 "log"; lost if it happens
// before `rtt_init!` in `init`), then executes `udf`: the core ends in cortex-m-rt's default
// HardFault handler, a loop with interrupts disabled. Stopping the motors on panic comes with the
// motor driver (later issue): this firmware does not drive them at all.
use panic_probe as _;

// Dispatchers for the software tasks of later issues (none exists yet): the interrupts of SPI5 and
// SPI6, peripherals this firmware does not use and HARDWARE.md assigns nothing to. Re-check when
// the bottom-board link and the IMU are wired up.
#[rtic::app(device = stm32f4xx_hal::pac, peripherals = true, dispatchers = [SPI5, SPI6])]
mod app {
    use crate::{board, camera};
    use rtt_target::{rprintln, rtt_init, set_print_channel, UpChannel};
    use stm32f4xx_hal::{prelude::*, rcc::Config};

    #[shared]
    struct Shared {}

    #[local]
    struct Local {
        /// RTT up channel 1 "telemetry". Held (by `idle`) so that the channel stays usable;
        /// the telemetry task of a later issue takes it over. Nothing writes to it yet.
        telemetry: UpChannel,
        /// The camera (XCLK pin and SCCB bus), configured or not. Held (by `idle`) for the
        /// capture work to come (and a retry of `init` if the fault policy wants one).
        camera: camera::Camera,
    }

    #[init]
    fn init(cx: init::Context) -> (Shared, Local) {
        // RTT first (it needs no clock set-up), so that a panic or a hang in the clock
        // configuration below is visible on the probe. Channel 0 "log" (text, the print channel
        // of `rprintln!` and of panic-probe's `print-rtt`), channel 1 "telemetry". Both
        // NoBlockSkip: output is dropped, never blocking, when no probe reads it (the robot runs
        // untethered).
        let channels = rtt_init! {
            up: {
                0: {
                    size: 1024,
                    name: "log"
                }
                1: {
                    size: 1024,
                    name: "telemetry"
                }
            }
        };
        set_print_channel(channels.up.0);
        rprintln!(
            "alvs-firmware {} on the Colias sense board (STM32F427VI)",
            env!("CARGO_PKG_VERSION")
        );
        // Printed before `freeze`: if this is the last line, HSE did not start (`freeze` waits
        // for HSERDY forever) or a clock request was rejected (the panic message follows).
        rprintln!(
            "clocks: starting HSE {} Hz -> SYSCLK {} Hz",
            board::HSE_HZ,
            board::SYSCLK_HZ
        );

        // `freeze` sets the PLL, the flash wait states and the regulator over-drive, and panics
        // if the request is out of range.
        let mut rcc = cx.device.RCC.freeze(
            Config::hse(board::HSE_HZ.Hz())
                .sysclk(board::SYSCLK_HZ.Hz())
                .pclk1(board::PCLK1_HZ.Hz())
                .pclk2(board::PCLK2_HZ.Hz()),
        );
        let clocks = rcc.clocks;

        // `idle` sleeps with `wfi`. On STM32 the debugger loses memory access to a sleeping core
        // unless DBGMCU_CR.DBG_SLEEP keeps the clocks running in Sleep mode, and RTT (the probe
        // reading RAM) stops with it; probe-rs sets the bit when it attaches but clears it when it
        // detaches, so a later attach could fail. The firmware sets it itself. A clocked DMA
        // controller is the other half of the usual STM32 RTT-in-sleep workaround (probe-rs
        // issue #350): DMA1 is enabled here for that reason only, nothing uses it. Cost: a little
        // power in Sleep mode, negligible next to the motors. We never enter Stop/Standby, so
        // DBG_STOP/DBG_STANDBY are left alone.
        cx.device.DBGMCU.cr().modify(|_, w| w.dbg_sleep().set_bit());
        rcc.ahb1enr().modify(|_, w| w.dma1en().set_bit());

        let params = alvs_tasks::Params::default();
        rprintln!(
            "clocks: SYSCLK {} Hz (asked {}), HCLK {} Hz, PCLK1 {} Hz (asked {}), PCLK2 {} Hz (asked {}), computed for an HSE of {} Hz",
            clocks.sysclk().raw(),
            board::SYSCLK_HZ,
            clocks.hclk().raw(),
            clocks.pclk1().raw(),
            board::PCLK1_HZ,
            clocks.pclk2().raw(),
            board::PCLK2_HZ,
            board::HSE_HZ
        );
        if clocks.sysclk().raw() != board::SYSCLK_HZ
            || clocks.pclk1().raw() != board::PCLK1_HZ
            || clocks.pclk2().raw() != board::PCLK2_HZ
        {
            rprintln!("WARNING: clocks differ from the requested ones (src/board.rs)");
        }

        // Camera: XCLK, then sensor reset, id check and register table over SCCB. A failure is
        // reported and the firmware runs on (the fault policy comes with the capture work).
        // `split` resets its port, so each port is split once, here; the other pins of GPIOA and
        // GPIOE (DCMI among them) stay in `gpioa`/`gpioe` for the capture work.
        let gpioa = cx.device.GPIOA.split(&mut rcc);
        let gpioe = cx.device.GPIOE.split(&mut rcc);
        let pins = camera::Pins {
            xclk: gpioa.pa8,
            sda: gpioe.pe2,
            scl: gpioe.pe3,
        };
        let mut camera = camera::Camera::new(pins, &rcc, clocks.sysclk().raw());
        match camera.init() {
            Ok(info) => rprintln!("camera: {}", info),
            Err(error) => rprintln!("ERROR camera: {}", error),
        }
        rprintln!(
            "model: alvs-tasks Params::default() Table I: T_a = {}, T_d = {}, T_s = {}",
            params.t_a,
            params.t_d,
            params.t_s
        );
        rprintln!(
            "bring-up firmware: camera set-up only (no DCMI capture yet), no network, no telemetry, no motors yet; idling"
        );

        (
            Shared {},
            Local {
                telemetry: channels.up.1,
                camera,
            },
        )
    }

    /// Sleeps until an interrupt, forever (no interrupt is enabled yet). A user-defined `idle`
    /// replaces RTIC's default (which sets SLEEPONEXIT). `wfi` should not disturb the probe since
    /// `init` set DBG_SLEEP (see there); not yet checked on a board. Should the probe still lose
    /// the target or RTT, replace `wfi` with `cortex_m::asm::nop()` to keep the core awake (more
    /// power, same behaviour).
    #[idle(local = [telemetry, camera])]
    fn idle(_cx: idle::Context) -> ! {
        loop {
            cortex_m::asm::wfi();
        }
    }
}

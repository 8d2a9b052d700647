//! Hardware constants of the Colias sense board, in one place.
//!
//! Every value comes from `/work/shared/HARDWARE.md` ("MCU and clocks"), which gathers facts from
//! public Colias firmware that were not checked on a board: each one is to be verified at
//! bring-up. Pin maps, the camera and the bottom-board UART join this module with the issues that
//! use them.

/// Frequency of the external crystal (HSE), in Hz: 25 MHz.
///
/// Source: HARDWARE.md, "MCU and clocks" (the same clock is forwarded to the OV7670 XCLK on
/// MCO1/PA8). Verify at bring-up: if the crystal is not there or not 25 MHz, `init` hangs waiting
/// for HSERDY or every derived clock is off by the same ratio.
pub const HSE_HZ: u32 = 25_000_000;

/// Requested system (core) clock, in Hz: 180 MHz, the STM32F427 maximum.
///
/// Source: HARDWARE.md, "MCU and clocks" (PLL M=25, N=360, P=2 from the 25 MHz HSE, regulator
/// over-drive on, which stm32f4xx-hal enables by itself above 168 MHz). Verify at bring-up: the
/// boot banner prints the clock the HAL actually configured.
pub const SYSCLK_HZ: u32 = 180_000_000;

/// Requested APB1 (low-speed peripheral bus) clock, in Hz: 45 MHz (AHB / 4), the F427 maximum.
///
/// Source: HARDWARE.md, "MCU and clocks". Verify at bring-up (printed in the boot banner).
pub const PCLK1_HZ: u32 = 45_000_000;

/// Requested APB2 (high-speed peripheral bus) clock, in Hz: 90 MHz (AHB / 2), the F427 maximum.
///
/// Source: HARDWARE.md, "MCU and clocks". Verify at bring-up (printed in the boot banner).
pub const PCLK2_HZ: u32 = 90_000_000;

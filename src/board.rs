//! Hardware constants of the Colias sense board, in one place.
//!
//! Every value comes from `/work/shared/HARDWARE.md` ("MCU and clocks", "Camera: OV7670 over
//! DCMI"), which gathers facts from public Colias firmware that were not checked on a board: each
//! one is to be verified at bring-up. The camera clock and SCCB pins are here; the DCMI pins and
//! the bottom-board UART join this module with the work that uses them.

use stm32f4xx_hal::gpio;

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

// ---------------------------------------------------------------------------------------------
// Camera (OV7670): clock output and SCCB pins. HARDWARE.md, "Camera: OV7670 over DCMI".
// ---------------------------------------------------------------------------------------------

/// Pin that carries the OV7670 XCLK: PA8, driven by MCO1 (the MCU's clock output 1).
///
/// Source: HARDWARE.md, "Camera: OV7670 over DCMI" ("XCLK: MCO1 on PA8 outputs the 25 MHz HSE").
/// Verify at bring-up: a 25 MHz square wave on PA8 and on the sensor's XCLK pad (scope). The
/// generic parameter is the pin's mode (as `split` hands it over: an input).
pub type CameraXclkPin<MODE = gpio::DefaultMode> = gpio::PA8<MODE>;

/// Frequency of the OV7670 XCLK, in Hz: the HSE itself (MCO1 source = HSE, MCO1 prescaler /1).
///
/// Source: HARDWARE.md, "Camera: OV7670 over DCMI". The OV7670 accepts 10–48 MHz (24 MHz
/// nominal, 30 fps); 25 MHz presumably gives ≈ 31 fps, consistent with the ≈ 32 ms frame interval
/// of HARDWARE.md. Verify at bring-up: frequency on PA8, then the VSYNC period.
pub const CAMERA_XCLK_HZ: u32 = HSE_HZ;

/// SCCB data line to the OV7670: PE2, bit-banged as an open-drain output with the internal
/// pull-up on (an external pull-up, if fitted, just adds to it).
///
/// Source: HARDWARE.md, "Camera: OV7670 over DCMI" ("SCCB is bit-banged on PE2 (SDA) / PE3
/// (SCL) in the public firmware"). Bit-banging is required, not a choice: on the STM32F427 PE2
/// and PE3 have no I2C alternate function (AF4). Verify at bring-up: both lines idle high, and
/// the sensor acknowledges its address (the boot log prints the camera id).
pub type SccbSdaPin<MODE = gpio::DefaultMode> = gpio::PE2<MODE>;

/// SCCB clock line to the OV7670: PE3, bit-banged as a push-pull output (the OV7670 never
/// drives or stretches SCL, so no open drain is needed).
///
/// Source: HARDWARE.md, "Camera: OV7670 over DCMI". Verify at bring-up: clock bursts on PE3 at
/// boot (≤ 50 kHz, see `camera::sccb::SCCB_HALF_PERIOD_US`).
pub type SccbSclPin<MODE = gpio::DefaultMode> = gpio::PE3<MODE>;

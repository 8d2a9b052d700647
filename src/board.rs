//! Hardware constants of the Colias sense board, in one place.
//!
//! Every value comes from `docs/hardware.md` ("MCU and clocks", "Camera: OV7670 over
//! DCMI"), which gathers facts from public Colias firmware that were not checked on a board: each
//! one is to be verified at bring-up: clocks, the camera's clock and SCCB pins, the DCMI pins,
//! polarities and crop window, its DMA stream, and the bottom-board UART.

use stm32f4xx_hal::gpio;

/// Frequency of the external crystal (HSE), in Hz: 25 MHz.
///
/// Source: docs/hardware.md, "MCU and clocks" (the same clock is forwarded to the OV7670 XCLK on
/// MCO1/PA8). Verify at bring-up: if the crystal is not there or not 25 MHz, `init` hangs waiting
/// for HSERDY or every derived clock is off by the same ratio.
pub const HSE_HZ: u32 = 25_000_000;

/// Requested system (core) clock, in Hz: 180 MHz, the STM32F427 maximum.
///
/// Source: docs/hardware.md, "MCU and clocks" (PLL M=25, N=360, P=2 from the 25 MHz HSE, regulator
/// over-drive on, which stm32f4xx-hal enables by itself above 168 MHz). Verify at bring-up: the
/// boot banner prints the clock the HAL actually configured.
pub const SYSCLK_HZ: u32 = 180_000_000;

/// Requested APB1 (low-speed peripheral bus) clock, in Hz: 45 MHz (AHB / 4), the F427 maximum.
///
/// Source: docs/hardware.md, "MCU and clocks". Verify at bring-up (printed in the boot banner).
pub const PCLK1_HZ: u32 = 45_000_000;

/// Requested APB2 (high-speed peripheral bus) clock, in Hz: 90 MHz (AHB / 2), the F427 maximum.
///
/// Source: docs/hardware.md, "MCU and clocks". Verify at bring-up (printed in the boot banner).
pub const PCLK2_HZ: u32 = 90_000_000;

// ---------------------------------------------------------------------------------------------
// Camera (OV7670): clock output and SCCB pins. docs/hardware.md, "Camera: OV7670 over DCMI".
// ---------------------------------------------------------------------------------------------

/// Pin that carries the OV7670 XCLK: PA8, driven by MCO1 (the MCU's clock output 1).
///
/// Source: docs/hardware.md, "Camera: OV7670 over DCMI" (XCLK is MCO1 on PA8, forwarding the
/// 25 MHz HSE).
/// Verify at bring-up: a 25 MHz square wave on PA8 and on the sensor's XCLK pad (scope). The
/// generic parameter is the pin's mode (as `split` hands it over: an input).
pub type CameraXclkPin<MODE = gpio::DefaultMode> = gpio::PA8<MODE>;

/// Frequency of the OV7670 XCLK, in Hz: the HSE itself (MCO1 source = HSE, MCO1 prescaler /1).
///
/// Source: docs/hardware.md, "Camera: OV7670 over DCMI". The OV7670 accepts 10–48 MHz (24 MHz
/// nominal, 30 fps); 25 MHz presumably gives ≈ 31 fps, consistent with the ≈ 32 ms frame interval
/// of docs/hardware.md. Verify at bring-up: frequency on PA8, then the VSYNC period.
pub const CAMERA_XCLK_HZ: u32 = HSE_HZ;

/// SCCB data line to the OV7670: PE2, bit-banged as an open-drain output with the internal
/// pull-up on (an external pull-up, if fitted, just adds to it).
///
/// Source: docs/hardware.md, "Camera: OV7670 over DCMI" (the public firmware bit-bangs SCCB on
/// PE2 = SDA and PE3 = SCL). Bit-banging is required, not a choice: on the STM32F427 PE2
/// and PE3 have no I2C alternate function (AF4). Verify at bring-up: both lines idle high, and
/// the sensor acknowledges its address (the boot log prints the camera id).
pub type SccbSdaPin<MODE = gpio::DefaultMode> = gpio::PE2<MODE>;

/// SCCB clock line to the OV7670: PE3, bit-banged as a push-pull output (the OV7670 never
/// drives or stretches SCL, so no open drain is needed).
///
/// Source: docs/hardware.md, "Camera: OV7670 over DCMI". Verify at bring-up: clock bursts on PE3 at
/// boot (≤ 50 kHz, see `camera::sccb::SCCB_HALF_PERIOD_US`).
pub type SccbSclPin<MODE = gpio::DefaultMode> = gpio::PE3<MODE>;

// ---------------------------------------------------------------------------------------------
// Camera capture: DCMI pins, polarities, crop window, DMA. docs/hardware.md, "Camera: OV7670 over
// DCMI".
// ---------------------------------------------------------------------------------------------

/// DCMI data and sync pins, alternate function 13: D0 PC6, D1 PC7, D2 PE0, D3 PE1, D4 PE4,
/// D5 PB6, D6 PE5, D7 PE6, HSYNC (the sensor's HREF) PA4, VSYNC PB7, PIXCLK PA6.
///
/// Source: docs/hardware.md. Verify at bring-up: PIXCLK and HREF toggle on the scope once XCLK
/// runs; a wrong data pin shows as a stuck bit in the first frame (telemetry of a still scene).
pub const DCMI_AF: u8 = 13;

/// DCMI samples data on the rising PIXCLK edge (`PCKPOL = 1`). The OV7670 changes data on
/// the falling edge by default (COM10 bit 4 = 0). Verify at bring-up (a wrong edge gives noisy
/// or shifted pixels).
pub const DCMI_PIXCLK_RISING: bool = true;

/// VSYNC level during which data is *not* valid: high (`VSPOL = 1`); the OV7670 pulses VSYNC
/// high between frames by default (COM10 bit 1 = 0). Verify at bring-up.
pub const DCMI_VSYNC_BLANK_HIGH: bool = true;

/// HSYNC (HREF) level during which data is *not* valid: low (`HSPOL = 0`); the OV7670's HREF
/// is high during active pixels. Verify at bring-up.
pub const DCMI_HREF_BLANK_HIGH: bool = false;

/// Crop window: first captured pixel clock of a line (DCMI counts 2 clocks a pixel in 8-bit
/// YUV422) and first captured line. docs/hardware.md does not say how the public firmware gets
/// 99x72 out of the sensor; the scaling registers resemble QQCIF, so the window starts at the
/// top-left and takes 99x72. Verify at bring-up: scope HREF/VSYNC, count PIXCLKs per HREF and
/// HREFs per VSYNC, then centre the window in what the sensor sends.
pub const DCMI_CROP_X_CLOCKS: u16 = 0;
/// First captured line of the crop window (see [`DCMI_CROP_X_CLOCKS`]).
pub const DCMI_CROP_Y_LINES: u16 = 0;

/// DMA2 stream and channel of the DCMI (RM0090 table 43: DMA2 stream 1 channel 1).
pub const DCMI_DMA_STREAM: usize = 1;
/// See [`DCMI_DMA_STREAM`].
pub const DCMI_DMA_CHANNEL: u8 = 1;

// ---------------------------------------------------------------------------------------------
// Bottom board (motors): UART. docs/hardware.md, "Motion: the Colias basic unit".
// ---------------------------------------------------------------------------------------------

/// Transmit pin of the bottom-board link: PC10 (UART4_TX, AF8).
///
/// Source: docs/hardware.md, "Motion: the Colias basic unit" (UART4 on PC10/PC11 at 38,400 8N1 in
/// the older firmware; UART2 with an unpublished baud rate in the 2025 firmware). Only TX is used:
/// frames are sent with the no-ack head. Verify at bring-up: bytes on PC10 at the baud below when
/// the robot wanders.
pub type MotorTxPin<MODE = gpio::DefaultMode> = gpio::PC10<MODE>;

/// Baud rate of the bottom-board link, 8N1: the protocol's own constant (`tasks::robot::motor`).
/// Verify at bring-up (see [`MotorTxPin`]).
pub const MOTOR_BAUD: u32 = alvs_tasks::robot::motor::BAUD;

/// Bytes the motor link can hold queued (a frame period sends ≤ 3 frames of ≤ 12 bytes).
pub const MOTOR_QUEUE_BYTES: usize = 128;

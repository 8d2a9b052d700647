//! OV7670 camera bring-up: master clock, control bus, identification and register set-up.
//!
//! What this module does (hardware only, no policy):
//!
//! 1. XCLK: MCO1 forwards the 25 MHz HSE to PA8 ([`xclk`]);
//! 2. SCCB: a bit-banged control bus on PE2 (SDA) / PE3 (SCL) ([`sccb`]);
//! 3. [`Camera::init`]: software reset of the sensor, identification (PID/VER), the register
//!    table of [`ov7670::CONFIG`], and a read-back of a few of those registers.
//!
//! 4. [`dcmi`]: capture of the 99x72 window into a DMA ring of lines (no frame buffer: the
//!    lines stream into the network's retina, see `tasks::robot::camera`).
//!
//! Deciding what a camera error means for the robot is the caller's business: [`Camera::init`]
//! reports and can be called again.
//!
//! Every board fact used here is a named constant of [`crate::board`] or [`ov7670`], to verify
//! at bring-up.

pub mod dcmi;
mod delay;
pub mod ov7670;
pub mod sccb;
pub mod xclk;

use crate::board::{self, CameraXclkPin, SccbSclPin, SccbSdaPin};
use core::fmt;
use delay::CycleDelay;
use sccb::{Sccb, SccbError};
use stm32f4xx_hal::pac;

/// The pins the camera driver takes over, as `split` hands them out.
pub struct Pins {
    /// XCLK output (MCO1).
    pub xclk: CameraXclkPin,
    /// SCCB data.
    pub sda: SccbSdaPin,
    /// SCCB clock.
    pub scl: SccbSclPin,
}

/// What [`Camera::init`] found and did.
#[derive(Clone, Copy, Debug)]
pub struct CameraInfo {
    /// Product id read from the sensor ([`ov7670::reg::PID`]).
    pub pid: u8,
    /// Version read from the sensor ([`ov7670::reg::VER`]).
    pub ver: u8,
    /// Registers written from [`ov7670::CONFIG`] (the reset write not counted).
    pub written: usize,
    /// Registers of [`ov7670::VERIFY`] read back with the value written.
    pub verified: usize,
}

impl fmt::Display for CameraInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "OV7670 PID 0x{:02X} VER 0x{:02X}, {} registers written ({} read back OK), XCLK {} Hz on MCO1/PA8",
            self.pid,
            self.ver,
            self.written,
            self.verified,
            board::CAMERA_XCLK_HZ
        )
    }
}

/// Why [`Camera::init`] failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraError {
    /// Nothing acknowledged the OV7670's SCCB id on the first access (the reset write).
    NoSensor,
    /// The SCCB bus could not be freed before the first access.
    Bus(SccbError),
    /// A sensor answered, but its id is not the OV7670's.
    WrongId { pid: u8, ver: u8 },
    /// Reading register `reg` failed.
    ReadFailed { reg: u8, error: SccbError },
    /// Writing register `reg` failed.
    WriteFailed { reg: u8, error: SccbError },
    /// Register `reg` reads back `read` after `wrote` was written.
    ReadBack { reg: u8, wrote: u8, read: u8 },
}

impl fmt::Display for CameraError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::NoSensor => write!(
                f,
                "no sensor: SCCB id 0x{:02X} not acknowledged on PE2/PE3 (camera absent, unpowered, held in power-down or reset, or no XCLK on PA8)",
                ov7670::SCCB_ID
            ),
            Self::Bus(error) => write!(f, "SCCB bus: {error}"),
            Self::WrongId { pid, ver } => write!(
                f,
                "not an OV7670: PID 0x{pid:02X} VER 0x{ver:02X} (expected PID 0x{:02X} VER 0x{:02X})",
                ov7670::EXPECTED_PID,
                ov7670::EXPECTED_VER
            ),
            Self::ReadFailed { reg, error } => {
                write!(f, "reading register 0x{reg:02X} failed: {error}")
            }
            Self::WriteFailed { reg, error } => {
                write!(f, "writing register 0x{reg:02X} failed: {error}")
            }
            Self::ReadBack { reg, wrote, read } => write!(
                f,
                "register 0x{reg:02X} reads back 0x{read:02X} after writing 0x{wrote:02X}"
            ),
        }
    }
}

/// The OV7670 camera: owns the XCLK pin and the SCCB bus.
pub struct Camera {
    sccb: Sccb,
    delay: CycleDelay,
    /// Held so that nothing else takes PA8 while the sensor needs its clock.
    _xclk: xclk::XclkPin,
}

impl Camera {
    /// Starts XCLK and sets up the SCCB pins. No sensor access yet: call [`Camera::init`].
    ///
    /// `rcc` is the RCC block after the clocks were frozen (the HSE must be running);
    /// `sysclk_hz` the core clock actually configured, for the busy-wait delays.
    pub fn new(pins: Pins, rcc: &pac::RCC, sysclk_hz: u32) -> Self {
        let delay = CycleDelay::new(sysclk_hz);
        let xclk = xclk::start(rcc, pins.xclk);
        let sccb = Sccb::new(pins.sda, pins.scl, ov7670::SCCB_ID, delay);
        Self {
            sccb,
            delay,
            _xclk: xclk,
        }
    }

    /// Resets and configures the sensor: lets XCLK run [`ov7670::XCLK_STARTUP_MS`], frees the
    /// bus, resets the registers (COM7 bit 7) and waits [`ov7670::RESET_SETTLE_MS`], checks
    /// PID/VER, writes [`ov7670::CONFIG`] and reads back [`ov7670::VERIFY`].
    ///
    /// Blocks for some tens of ms (busy-waits; meant for `init`). Can be called again, e.g. to
    /// retry after an error: it starts over with the reset.
    pub fn init(&mut self) -> Result<CameraInfo, CameraError> {
        self.delay.ms(ov7670::XCLK_STARTUP_MS);
        self.sccb.recover().map_err(CameraError::Bus)?;

        // The reset is the first access: an unacknowledged id there means no sensor.
        self.sccb
            .write(ov7670::reg::COM7, ov7670::COM7_RESET)
            .map_err(|error| match error {
                SccbError::AddressNack => CameraError::NoSensor,
                error => CameraError::WriteFailed {
                    reg: ov7670::reg::COM7,
                    error,
                },
            })?;
        self.delay.ms(ov7670::RESET_SETTLE_MS);

        let pid = self.read(ov7670::reg::PID)?;
        let ver = self.read(ov7670::reg::VER)?;
        if (pid, ver) != (ov7670::EXPECTED_PID, ov7670::EXPECTED_VER) {
            return Err(CameraError::WrongId { pid, ver });
        }

        for &(reg, val) in ov7670::CONFIG {
            self.sccb
                .write(reg, val)
                .map_err(|error| CameraError::WriteFailed { reg, error })?;
        }

        for &reg in ov7670::VERIFY {
            // `VERIFY` only lists registers `CONFIG` writes (checked at compile time).
            let Some(wrote) = ov7670::configured(reg) else {
                continue;
            };
            let read = self.read(reg)?;
            if read != wrote {
                return Err(CameraError::ReadBack { reg, wrote, read });
            }
        }

        Ok(CameraInfo {
            pid,
            ver,
            written: ov7670::CONFIG.len(),
            verified: ov7670::VERIFY.len(),
        })
    }

    fn read(&mut self, reg: u8) -> Result<u8, CameraError> {
        self.sccb
            .read(reg)
            .map_err(|error| CameraError::ReadFailed { reg, error })
    }
}

//! SCCB, OmniVision's I2C-like camera control bus, bit-banged on two GPIOs
//! ([`board::SccbSdaPin`](crate::board::SccbSdaPin) / [`board::SccbSclPin`](crate::board::SccbSclPin)).
//!
//! Transactions (OmniVision "Serial Camera Control Bus Functional Specification"):
//!
//! - 3-phase write: START, device id + W, register address, data, STOP.
//! - read = 2-phase write then 2-phase read: START, id + W, register address, STOP; START,
//!   id + R, data (the master answers "not acknowledge"), STOP. SCCB uses a STOP and a new START
//!   between the two, not an I2C repeated start.
//!
//! Bits are MSB first; SDA changes only while SCL is low. SCCB calls the 9th bit of a byte
//! "don't care", but the OV7670 drives it low like an I2C ACK; this driver relies on that: no
//! acknowledge of the device id means nothing answered (no sensor).
//!
//! Timing: each SCL half-period is at least [`SCCB_HALF_PERIOD_US`], so the bus runs at
//! ≤ 50 kHz (SCCB allows up to 400 kHz). Slow on purpose: it leaves time for the internal
//! pull-up (≈ 40 kΩ) to raise SDA, in case the board has no external one.

use super::delay::CycleDelay;
use crate::board::{SccbSclPin, SccbSdaPin};
use core::fmt;
use stm32f4xx_hal::gpio::{OpenDrain, Output, PinState, PushPull};

/// Minimum SCL half-period, in µs (≤ 50 kHz SCCB clock). Converted to core cycles from the
/// actual SYSCLK by [`CycleDelay`]; the busy-wait makes the real half-period ≈ 3x longer on the
/// M4 (see `delay.rs`), ≈ 17 kHz, which SCCB tolerates (no minimum clock rate).
pub const SCCB_HALF_PERIOD_US: u32 = 10;

/// SCL pulses sent, at most, to free an SDA line that a slave holds low (a slave interrupted
/// mid-byte by an MCU reset releases SDA within 9 clocks: 8 data bits + acknowledge).
const RECOVERY_CLOCKS: u32 = 9;

/// A failed SCCB transaction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SccbError {
    /// The device id was not acknowledged: no device answered at that address.
    AddressNack,
    /// The device acknowledged its id but not a following byte (register address or data).
    DataNack,
    /// SDA stays low with the bus released, even after [`RECOVERY_CLOCKS`] clock pulses (line
    /// shorted to ground, or a slave stuck).
    BusStuck,
}

impl fmt::Display for SccbError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::AddressNack => f.write_str("device id not acknowledged"),
            Self::DataNack => f.write_str("register address or data byte not acknowledged"),
            Self::BusStuck => f.write_str("SDA (PE2) held low, bus cannot be freed"),
        }
    }
}

/// Bit-banged SCCB master talking to one device.
pub struct Sccb {
    /// Open drain: the pin only pulls low; "high" releases the line to the pull-up, and reading
    /// the pin gives the line level (used for acknowledges and read data).
    sda: SccbSdaPin<Output<OpenDrain>>,
    /// Push-pull: only the master drives SCL.
    scl: SccbSclPin<Output<PushPull>>,
    /// Device id for writes (8-bit form, R/W bit clear); reads use `id | 1`.
    id: u8,
    delay: CycleDelay,
}

impl Sccb {
    /// Configures the pins (both lines released high, bus idle) for the device whose 8-bit write
    /// id is `id`.
    pub fn new(sda: SccbSdaPin, scl: SccbSclPin, id: u8, delay: CycleDelay) -> Self {
        // Pull-up first, while SDA is still an input, then open drain released: the line never
        // glitches low (a changed mode keeps the pull-up setting).
        let sda = sda
            .into_pull_up_input()
            .into_open_drain_output_in_state(PinState::High);
        let scl = scl.into_push_pull_output_in_state(PinState::High);
        Self {
            sda,
            scl,
            id,
            delay,
        }
    }

    /// Frees the bus: if a slave holds SDA low (e.g. the MCU was reset in the middle of a read),
    /// clocks SCL until it lets go, then sends START + STOP to reset every slave's bus logic.
    pub fn recover(&mut self) -> Result<(), SccbError> {
        self.sda.set_high();
        self.scl.set_high();
        self.half();
        let mut pulses = 0;
        while self.sda.is_low() {
            if pulses == RECOVERY_CLOCKS {
                return Err(SccbError::BusStuck);
            }
            self.scl.set_low();
            self.half();
            self.scl.set_high();
            self.half();
            pulses += 1;
        }
        self.start();
        self.stop();
        Ok(())
    }

    /// 3-phase write of `val` to register `reg`.
    pub fn write(&mut self, reg: u8, val: u8) -> Result<(), SccbError> {
        self.start();
        let result = self.send(&[self.id, reg, val]);
        self.stop();
        result
    }

    /// Reads register `reg` (2-phase write of the address, then 2-phase read).
    pub fn read(&mut self, reg: u8) -> Result<u8, SccbError> {
        self.start();
        let result = self.send(&[self.id, reg]);
        self.stop();
        result?;

        self.start();
        let result = self.send(&[self.id | 1]).map(|()| self.read_byte());
        self.stop();
        result
    }

    /// Sends bytes; the first is the device id (its NACK is [`SccbError::AddressNack`]).
    fn send(&mut self, bytes: &[u8]) -> Result<(), SccbError> {
        for (i, &byte) in bytes.iter().enumerate() {
            if !self.write_byte(byte) {
                return Err(if i == 0 {
                    SccbError::AddressNack
                } else {
                    SccbError::DataNack
                });
            }
        }
        Ok(())
    }

    /// START: SDA falls while SCL is high. Leaves SCL low.
    fn start(&mut self) {
        self.sda.set_high();
        self.scl.set_high();
        self.half();
        self.sda.set_low();
        self.half();
        self.scl.set_low();
        self.half();
    }

    /// STOP: SDA rises while SCL is high. Expects SCL low; leaves the bus idle (both high) after
    /// a half-period of bus-free time.
    fn stop(&mut self) {
        self.sda.set_low();
        self.half();
        self.scl.set_high();
        self.half();
        self.sda.set_high();
        self.half();
    }

    /// Sends one byte MSB first and returns whether the device acknowledged it.
    fn write_byte(&mut self, byte: u8) -> bool {
        for bit in (0..8).rev() {
            self.bit_out(byte & (1 << bit) != 0);
        }
        // Acknowledge: the device pulls SDA low.
        !self.bit_in()
    }

    /// Receives one byte MSB first, then answers "not acknowledge" (SDA high), as SCCB requires
    /// after the single data byte of a read.
    fn read_byte(&mut self) -> u8 {
        let mut byte = 0;
        for _ in 0..8 {
            byte = (byte << 1) | u8::from(self.bit_in());
        }
        self.bit_out(true);
        byte
    }

    /// Clocks one bit out. SCL is low on entry and on exit.
    fn bit_out(&mut self, high: bool) {
        if high {
            self.sda.set_high();
        } else {
            self.sda.set_low();
        }
        self.half();
        self.scl.set_high();
        self.half();
        self.scl.set_low();
    }

    /// Releases SDA and clocks one bit in, sampled at the end of the SCL high phase. SCL is low
    /// on entry and on exit.
    fn bit_in(&mut self) -> bool {
        self.sda.set_high();
        self.half();
        self.scl.set_high();
        self.half();
        let bit = self.sda.is_high();
        self.scl.set_low();
        bit
    }

    fn half(&self) {
        self.delay.us(SCCB_HALF_PERIOD_US);
    }
}

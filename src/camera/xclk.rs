//! The OV7670 master clock (XCLK): the 25 MHz HSE forwarded to PA8 by MCO1.
//!
//! stm32f4xx-hal 0.23 knows that PA8 is MCO1 on alternate function 0 (`gpio::alt::rcc::Mco1`)
//! but has no API to select the MCO1 source or prescaler, so those two fields of RCC_CFGR are
//! written through the PAC. The PAC field writers used are safe (every value is valid): no
//! `unsafe` here.

use crate::board::CameraXclkPin;
use stm32f4xx_hal::gpio::{Alternate, Speed};
use stm32f4xx_hal::pac;

/// Alternate function number of MCO1 on PA8: AF0 (STM32F427 datasheet, alternate function
/// table; also the HAL's `gpio::alt::rcc::Mco1` mapping). An MCU fact, not a board one.
const MCO1_AF: u8 = 0;

/// PA8 once it outputs the clock. Held by the camera driver so that nothing else reconfigures
/// the pin while the sensor needs its clock.
pub type XclkPin = CameraXclkPin<Alternate<MCO1_AF>>;

/// Starts XCLK: MCO1 source = HSE, MCO1 prescaler /1, then PA8 to AF0 at very high speed.
///
/// The HSE must be running (`freeze` with an HSE configuration leaves it on: it feeds the PLL).
/// RM0090 (RCC_CFGR, MCO1 and MCO1PRE) warns that changing the MCO1 source or prescaler may
/// glitch the output and recommends doing it before the clocks start. Here the glitch cannot
/// reach the sensor: the fields are written while PA8 is still a GPIO input (as `split` left
/// it), and only then is the pin switched to the MCO1 function.
pub fn start(rcc: &pac::RCC, pin: CameraXclkPin) -> XclkPin {
    rcc.cfgr().modify(|_, w| w.mco1().hse().mco1pre().div1());
    // Very high speed (fastest edges) is more than 25 MHz needs; it keeps the clock square into
    // the sensor's input capacitance. Costs a little EMI and supply noise.
    pin.into_alternate::<MCO1_AF>().speed(Speed::VeryHigh)
}

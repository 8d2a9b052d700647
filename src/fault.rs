//! Faults end with the motors stopped.
//!
//! A panic prints its message over RTT (panic-probe, `print-rtt`) and then executes `udf`,
//! which lands in this HardFault handler, as does every other fault (a stack overflow runs
//! off the bottom of CCM into unmapped memory and faults too). The handler writes the motor
//! stop frames to the bottom board by polling UART4 ([`crate::motor_link::stop_now`]) and
//! then waits: the independent watchdog, no longer fed, resets the MCU within
//! `WATCHDOG_TIMEOUT_MS`, and the firmware boots with the motors disabled until the model
//! has primed again.

use cortex_m_rt::{exception, ExceptionFrame};

#[exception]
unsafe fn HardFault(_frame: &ExceptionFrame) -> ! {
    crate::motor_link::stop_now();
    rtt_target::rprintln!("FAULT: motors stopped; waiting for the watchdog reset");
    loop {
        cortex_m::asm::nop();
    }
}

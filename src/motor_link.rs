//! The bottom-board link: UART4 TX, interrupt-driven, so the motor task never waits on the
//! 38400-baud line (a frame period's ~20 bytes take 5 ms on the wire).
//!
//! The motor task queues whole frames ([`MotorLink::send`]); the UART4 interrupt feeds one
//! byte per TXE ([`MotorLink::on_interrupt`]). A full queue drops the newest frames and
//! counts them: the next period resends absolute powers anyway. On a fault,
//! [`stop_now`] writes the stop frames by polling, from any context.

use alvs_tasks::robot::motor::{self, MotorFrames};
use heapless::Deque;
use stm32f4xx_hal::hal_02::serial::Write;
use stm32f4xx_hal::pac;
use stm32f4xx_hal::prelude::*;
use stm32f4xx_hal::serial::Tx;

use crate::board;

/// The UART transmitter and its byte queue.
pub struct MotorLink {
    tx: Tx<pac::UART4>,
    queue: Deque<u8, { board::MOTOR_QUEUE_BYTES }>,
    dropped_frames: u32,
}

impl MotorLink {
    /// Takes the configured transmitter.
    pub fn new(tx: Tx<pac::UART4>) -> Self {
        MotorLink {
            tx,
            queue: Deque::new(),
            dropped_frames: 0,
        }
    }

    /// Queues whole frames (a frame that does not fit is dropped and counted, never cut).
    pub fn send(&mut self, frames: &MotorFrames) {
        for f in frames {
            if self.queue.capacity() - self.queue.len() < f.len() {
                self.dropped_frames = self.dropped_frames.wrapping_add(1);
                continue;
            }
            for &b in f {
                let _ = self.queue.push_back(b);
            }
        }
        if !self.queue.is_empty() {
            self.tx.listen();
        }
    }

    /// UART4 interrupt: the next byte, or silence when the queue is empty.
    pub fn on_interrupt(&mut self) {
        match self.queue.front() {
            Some(&b) => {
                if Write::write(&mut self.tx, b).is_ok() {
                    self.queue.pop_front();
                }
            }
            None => self.tx.unlisten(),
        }
    }

    /// Frames dropped because the queue was full.
    pub fn dropped_frames(&self) -> u32 {
        self.dropped_frames
    }
}

/// Stops the motors from any context (HardFault included): writes the stop frames to UART4 by
/// polling, without the queue. Bounded: gives up on a byte if TXE never comes (UART not yet
/// configured), so a fault before the link exists cannot hang here.
pub fn stop_now() {
    // SAFETY: only register reads/writes of UART4 that a fault handler may do while the
    // normal owner is preempted forever; the worst race is a half-sent queued frame, which
    // the stop frames (head byte first) resynchronise.
    let uart = unsafe { &*pac::UART4::ptr() };
    uart.cr1().modify(|_, w| w.txeie().clear_bit());
    for frame in &motor::stop_frames() {
        for &b in frame {
            let mut spins = 0u32;
            while uart.sr().read().txe().bit_is_clear() && spins < 1_000_000 {
                spins += 1;
            }
            uart.dr().write(|w| unsafe { w.dr().bits(u16::from(b)) });
        }
    }
}

//! A Cortex-M4 cycle model for thumbv7em machine code, run on the host.
//!
//! Loads a firmware ELF (or raw bytes) into an STM32F427 memory map, executes functions with
//! unicorn-engine's Cortex-M4, and counts cycles with two timing models at once (see
//! [`timing`] and the crate's README.md): a nominal one and a pessimistic one that bracket a real
//! STM32F427 at 180 MHz.
//!
//! ```no_run
//! # fn main() -> Result<(), alvs_cycles::Error> {
//! let elf = std::fs::read("target/thumbv7em-none-eabihf/release/alvs-firmware").unwrap();
//! let mut m = alvs_cycles::Machine::from_elf(&elf)?;
//! let entry = m.symbol("bench_frame").expect("entry linked");
//! m.paint_stack(0xDEAD_BEEF)?;
//! let run = m.call(entry, &[0])?;
//! println!("{} nominal / {} pessimistic cycles, stack {} B", run.nominal, run.pessimistic,
//!          m.stack_high_water(0xDEAD_BEEF)?);
//! # Ok(()) }
//! ```

pub mod budget;
mod decode;
pub mod elf;
mod emu;
mod error;
mod machine;
pub mod memory;
pub mod ram;
pub mod system;
pub mod timing;

pub use error::{Access, Error};
pub use machine::{Machine, PcCycles, Run, Stamp, DEFAULT_LIMIT};
pub use ram::{FlashUse, RamReport, RegionUse};
pub use timing::{Class, ClassStat, FlashModel};

/// The STM32F427's core clock in the robot's configuration.
pub const CLOCK_HZ: u64 = 180_000_000;

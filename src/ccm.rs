//! The network's state in core-coupled memory (memory.x, docs/budget.md "RAM").
//!
//! The 64 KB CCM is reachable only by the CPU, at zero wait states, so it suits the network:
//! 37 KB that no DMA touches. cortex-m-rt initialises only `.data` and `.bss` in SRAM, so
//! [`take_network`] copies `.ccmdata`'s image from flash before handing out the one reference.

use core::ptr::{addr_of, addr_of_mut};

use alvs_tasks::Network;

/// The model's state, initialised from its image in flash by [`take_network`].
#[link_section = ".ccmdata.network"]
static mut NETWORK: Network = Network::alvs();

extern "C" {
    static mut __sccmdata: u32;
    static mut __eccmdata: u32;
    static __siccmdata: u32;
}

/// Copies `.ccmdata` from flash to CCM and returns the network.
///
/// # Safety
///
/// Call once, before anything else reads CCM's data (`init` does, first thing after RTT): a
/// second call would alias the `&'static mut` and overwrite the running network.
pub unsafe fn take_network() -> &'static mut Network {
    // SAFETY: the symbols bound `.ccmdata` (memory.x), word aligned, and its image in flash is
    // as long; by the caller's contract nothing has read or referenced it yet.
    unsafe {
        let start = addr_of_mut!(__sccmdata);
        let words = addr_of_mut!(__eccmdata).offset_from(start) as usize;
        core::ptr::copy_nonoverlapping(addr_of!(__siccmdata), start, words);
        &mut *addr_of_mut!(NETWORK)
    }
}

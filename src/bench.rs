//! The exported benchmark entry: one frame of perception and control, its stages timed with
//! the DWT cycle counter. The same machine code runs on the host's Cortex-M4 cycle model
//! (`tests/budget.rs` loads this ELF, calls these symbols and reads the DWT stamps it models)
//! and on the board, where `init` runs it on built-in frames and prints the cycles over RTT
//! ([`self_test`]), so the model can be calibrated against the real chip.

use alvs_tasks::model::closed_loop::movers::Movers;
use alvs_tasks::model::fsm::{Behaviour, FsmParams};
use alvs_tasks::robot::bench::{self, Report};
use alvs_tasks::robot::control::Control;
use alvs_tasks::robot::self_test::{self, BenchLine};
use alvs_tasks::{Frame, Network, PIXELS};
use cortex_m::peripheral::DWT;

/// Sizes the caller must reserve: `Network`, `Control`, `Report`, a frame (bytes).
#[no_mangle]
#[used]
pub static ALVS_BENCH_SIZES: [u32; 5] = [
    core::mem::size_of::<Network>() as u32,
    core::mem::size_of::<Control>() as u32,
    core::mem::size_of::<Report>() as u32,
    PIXELS as u32,
    core::mem::size_of::<Movers>() as u32,
];

/// The entry points by address: keeps both linked (and exported) even where the firmware
/// itself does not call them, so the cycle model always finds them.
#[used]
static ENTRIES: (
    unsafe extern "C" fn(*mut Network, *mut Control, *mut Movers),
    unsafe extern "C" fn(*mut Network, *mut Control, *mut Movers, *const Frame, *mut Report),
) = (alvs_bench_init, alvs_bench_step);

/// Writes a fresh default network and a controller into the given memory: an escape one if
/// `movers` is null, else the swarm's, with a fresh look in `movers`.
///
/// # Safety
/// `network`, `control` and `movers` (unless null) must be valid for writes of
/// `ALVS_BENCH_SIZES[0]`, `[1]` and `[4]` bytes, aligned for their types (8 bytes suffices).
#[no_mangle]
pub unsafe extern "C" fn alvs_bench_init(
    network: *mut Network,
    control: *mut Control,
    movers: *mut Movers,
) {
    if network.is_null() || control.is_null() {
        return;
    }
    network.write(Network::alvs());
    let behaviour = if movers.is_null() {
        Behaviour::Escape
    } else {
        movers.write(Movers::new());
        Behaviour::Swarm
    };
    control.write(Control::new(FsmParams::default(), behaviour));
}

/// One frame: `bench::step` with the DWT cycle counter as its clock; the report (stamps
/// and outputs) goes to `out`.
///
/// # Safety
/// `network`, `control` and `movers` (null in escape) must point to values set up by
/// [`alvs_bench_init`], `frame` to `PIXELS` readable bytes and `out` to a writable `Report`,
/// none overlapping.
#[no_mangle]
pub unsafe extern "C" fn alvs_bench_step(
    network: *mut Network,
    control: *mut Control,
    movers: *mut Movers,
    frame: *const Frame,
    out: *mut Report,
) {
    let (Some(network), Some(control), Some(frame), Some(out)) = (
        network.as_mut(),
        control.as_mut(),
        frame.as_ref(),
        out.as_mut(),
    ) else {
        return;
    };
    *out = bench::step(
        network,
        control,
        movers.as_mut(),
        frame,
        &mut DWT::cycle_count,
    );
}

/// Built-in frames of the self-test (`alvs_tasks::robot::self_test`): two unrelated
/// frames of random black and white 3x3 blocks (half the retina changes, every part of it
/// salient). In flash,
/// so reading them costs wait states a camera row in SRAM does not: the board's figure is an
/// upper bound. Exported by name so that the cycle model runs the self-test on these very bytes
/// (`cargo alvs budget --boot`).
#[no_mangle]
pub static ALVS_BENCH_FRAMES: [Frame; 2] = [
    self_test::blocks(self_test::SEEDS[0]),
    self_test::blocks(self_test::SEEDS[1]),
];

/// Runs the bench entry on the built-in frames with `network` (then reset: the real run
/// starts from a clean model) and prints the stage cycles of each frame on the log channel
/// (`bench:` lines, `alvs_tasks::robot::self_test::BenchLine`).
pub fn self_test(network: &mut Network) {
    let mut control = Control::new(FsmParams::default(), Behaviour::Escape);
    let frames = ALVS_BENCH_FRAMES.iter().cycle().take(self_test::FRAMES);
    for (i, frame) in (0u32..).zip(frames) {
        let mut report = Report::default();
        // SAFETY: distinct live references of the right types; no look (escape).
        unsafe {
            alvs_bench_step(
                network,
                &mut control,
                core::ptr::null_mut(),
                frame,
                &mut report,
            )
        };
        rtt_target::rprint!("{}", BenchLine::from_report(i, &report));
    }
    network.reset();
}

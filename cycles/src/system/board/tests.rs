//! The board's own unit tests on hand-written Thumb code: the reset path (the vector table
//! read again, RAM kept, the cause logged), the stack's high-water mark and its repainting,
//! and the exception names without symbols. Exception entry, preemption and the fault path
//! are tested from outside in `cycles/tests/virtual_core.rs`.

use super::*;

#[path = "../../../tests/thumb/mod.rs"]
mod thumb;
use thumb::{mov32, place, put_word, B_SELF};

const RESET: u32 = 0x0800_0100;
/// A word of SRAM the programs below keep a count in.
const COUNTER: u32 = 0x2000_0100;
/// The top of CCM, the initial SP of every image here.
const TOP: u32 = 0x1001_0000;

/// A flash image: SP = top of CCM, the reset vector, and `code` at [`RESET`].
fn image(code: &[u16]) -> Vec<u8> {
    let mut flash = vec![0u8; 0x200];
    put_word(&mut flash, 0, TOP);
    put_word(&mut flash, 4, RESET | 1);
    place(&mut flash, RESET, code);
    flash
}

fn board(code: &[u16]) -> Board {
    let config = Config {
        camera_present: false,
        ..Config::default()
    };
    Board::from_flash(&image(code), config, Box::new(|_| Vec::new())).expect("board")
}

fn word(b: &Board, addr: u32) -> u32 {
    let v = b.read(addr, 4).unwrap();
    u32::from_le_bytes([v[0], v[1], v[2], v[3]])
}

#[test]
fn a_software_reset_boots_again_from_the_vector_table_and_keeps_ram() {
    // each boot: counter += 1; the first two request a system reset (AIRCR.SYSRESETREQ with
    // its key), the third halts
    let code = [
        mov32(0, COUNTER),
        vec![
            0x6801, // ldr r1, [r0]
            0x3101, // adds r1, #1
            0x6001, // str r1, [r0]
            0x2903, // cmp r1, #3
            0xDAFE, // bge .
        ],
        mov32(2, 0xE000_ED0C),
        mov32(3, 0x05FA_0004),
        vec![0x6013, B_SELF], // str r3, [r2]; b .
    ]
    .concat();
    let mut b = board(&code);
    // the request takes effect when the run loop next stops (an event: the probe polls RTT
    // every 1 ms)
    b.run_for(1_000_000).expect("runs");
    assert_eq!(
        word(&b, COUNTER),
        3,
        "three boots, RAM kept across the resets"
    );
    let causes: Vec<ResetCause> = b.log().resets.iter().map(|&(_, c)| c).collect();
    assert_eq!(causes, [ResetCause::Software, ResetCause::Software]);
    let at: Vec<u64> = b.log().resets.iter().map(|&(t, _)| t).collect();
    assert!(at[0] < at[1] && at[1] < b.now(), "{at:?}");
}

#[test]
fn the_stack_high_water_mark_is_the_deepest_word_written_and_repaints_from_sp() {
    // push 8 registers (32 B), then 64 B more, and write one word at the new SP: 96 B deep
    let code = [
        mov32(0, 0x1234_5678),
        vec![
            0xB4FF, // push {r0-r7}
            0xB090, // sub sp, #64
            0x9000, // str r0, [sp]
            0xB010, // add sp, #64
            B_SELF,
        ],
    ]
    .concat();
    let mut b = board(&code);
    assert_eq!(b.stack_high_water().unwrap(), 0, "painted at power-on");
    b.run_for(10_000).expect("runs");
    assert_eq!(b.stack_high_water().unwrap(), 96);
    // SP is back 32 B below the top: repainting below it leaves the pushed words
    assert!(b.repaint_stack().unwrap(), "Thread mode repaints");
    assert_eq!(b.stack_high_water().unwrap(), 32);
}

#[test]
fn exceptions_without_symbols_are_named_by_number() {
    let b = board(&[B_SELF]);
    assert_eq!(b.exception_name(0), "Thread");
    assert_eq!(b.exception_name(15), "exception 15");
    assert_eq!(b.exception_name(16 + 78), "exception 94");
}

//! The virtual board's core on hand-written Thumb code: exception entry and return with the FP
//! context, preemption by priority, BASEPRI masking, tail-chaining, WFI and the fault path.

use alvs_cycles::system::{Board, Config};

mod thumb;
use thumb::{mov32, place, put_word, str, B_SELF};

const RESET: u32 = 0x0800_0100;
const HANDLER_A: u32 = 0x0800_0200;
const HANDLER_B: u32 = 0x0800_0300;
const HARD_FAULT: u32 = 0x0800_0400;
const RAM: u32 = 0x2000_0000;

/// Thumb-2 encodings used below (beside those of `thumb`).
const VMOV_S0_R0: [u16; 2] = [0xEE00, 0x0A10];
const VMOV_R3_S0: [u16; 2] = [0xEE10, 0x3A10];
const BX_LR: u16 = 0x4770;
const WFI: u16 = 0xBF30;
const UDF: u16 = 0xDE00;
/// msr basepri, r2
const MSR_BASEPRI_R2: [u16; 2] = [0xF382, 0x8811];

/// A flash image: the vector table (SP = top of CCM; Reset; HardFault; IRQ0 → A; IRQ1 → B) and
/// the code at their addresses.
fn image(reset: &[u16], a: &[u16], b: &[u16], hard_fault: &[u16]) -> Vec<u8> {
    let mut flash = vec![0u8; 0x500];
    for (offset, v) in [
        (0, 0x1001_0000),
        (4, RESET | 1),
        (12, HARD_FAULT | 1),
        (64, HANDLER_A | 1),
        (68, HANDLER_B | 1),
    ] {
        put_word(&mut flash, offset, v);
    }
    for (at, code) in [
        (RESET, reset),
        (HANDLER_A, a),
        (HANDLER_B, b),
        (HARD_FAULT, hard_fault),
    ] {
        place(&mut flash, at, code);
    }
    flash
}

fn run(flash: &[u8]) -> Board {
    let config = Config {
        camera_present: false,
        ..Config::default()
    };
    let mut b = Board::from_flash(flash, config, Box::new(|_| Vec::new())).expect("board");
    b.run_for(100_000).expect("runs");
    b
}

fn word(b: &Board, addr: u32) -> u32 {
    let v = b.read(addr, 4).unwrap();
    u32::from_le_bytes([v[0], v[1], v[2], v[3]])
}

/// Enable IRQ `n` (ISER0) at priority `prio`; r1, r2 scratch.
fn enable(n: u16, prio: u8) -> Vec<u16> {
    [
        mov32(1, 0xE000_E400 + u32::from(n)),
        vec![0x2200 | u16::from(prio), 0x700A], // movs r2, #prio; strb r2, [r1]
        mov32(1, 0xE000_E100),
        vec![0x2200 | (1 << n), str(2, 1, 0)], // movs r2, #(1 << n); str r2, [r1]
    ]
    .concat()
}

/// Pend IRQ `n` through STIR; r1, r2 scratch.
fn pend(n: u16) -> Vec<u16> {
    [mov32(1, 0xE000_EF00), vec![0x2200 | n, str(2, 1, 0)]].concat()
}

#[test]
fn an_interrupt_preserves_the_fp_context_and_returns_with_exc_return_e9() {
    // main: s0 = 1.5; enable and pend IRQ0; then store s0 and halt
    let reset = [
        mov32(0, 0x3FC0_0000),
        VMOV_S0_R0.to_vec(),
        enable(0, 0x80),
        pend(0),
        VMOV_R3_S0.to_vec(),
        mov32(4, RAM),
        vec![str(3, 4, 0), B_SELF],
    ]
    .concat();
    // handler: s0 = 2.5, records its LR, returns
    let a = [
        mov32(0, 0x4020_0000),
        VMOV_S0_R0.to_vec(),
        mov32(5, RAM),
        vec![0xF8C5, 0xE004], // str.w lr, [r5, #4]
        vec![BX_LR],
    ]
    .concat();
    let b = run(&image(&reset, &a, &[BX_LR], &[B_SELF]));
    assert_eq!(word(&b, RAM + 4), 0xFFFF_FFE9, "Thread, MSP, FP frame");
    assert_eq!(
        word(&b, RAM),
        0x3FC0_0000,
        "s0 restored after the handler changed it"
    );
    assert!(b.log().load[16] > 0, "the handler ran");
}

#[test]
fn a_higher_priority_interrupt_preempts_and_basepri_masks_it() {
    // main: IRQ0 at priority 0x80, IRQ1 at 0x40; pend IRQ0; halt
    // A: counts into RAM+0, pends IRQ1 (it preempts A: RAM+8 records A's count at that time),
    //    then sets BASEPRI 0x40 and pends IRQ1 again (masked), counts, clears BASEPRI (IRQ1 runs)
    let reset = [enable(0, 0x80), enable(1, 0x40), pend(0), vec![B_SELF]].concat();
    // r4 = RAM; r6 = step counter
    let a = [
        mov32(4, RAM),
        vec![0x2601, str(6, 4, 0)], // movs r6, #1; str r6, [r4]   (A started)
        pend(1),                    // B preempts here: B stores RAM+0 into RAM+8
        vec![0x2602, str(6, 4, 0)], // movs r6, #2; str r6, [r4]
        vec![0x2240],               // movs r2, #0x40
        MSR_BASEPRI_R2.to_vec(),
        pend(1),                    // masked: B must not run yet
        vec![0x2603, str(6, 4, 0)], // movs r6, #3
        vec![0x2200],               // movs r2, #0
        MSR_BASEPRI_R2.to_vec(),    // B runs now: RAM+8 ← 3
        vec![0x2604, str(6, 4, 0)], // movs r6, #4
        vec![BX_LR],
    ]
    .concat();
    // B: RAM+8 ← RAM+0; RAM+12 += 1
    let bh = [
        mov32(5, RAM),
        vec![
            0x682B,       // ldr r3, [r5]
            str(3, 5, 8), // str r3, [r5, #8]
            0x68EB,       // ldr r3, [r5, #12]
            0x3301,       // adds r3, #1
            str(3, 5, 12),
            BX_LR,
        ],
    ]
    .concat();
    let b = run(&image(&reset, &a, &bh, &[B_SELF]));
    assert_eq!(word(&b, RAM + 12), 2, "B ran twice");
    assert_eq!(
        word(&b, RAM + 8),
        3,
        "the second time only when BASEPRI was cleared"
    );
    assert_eq!(word(&b, RAM), 4, "A finished");
}

#[test]
fn wfi_sleeps_until_an_interrupt_and_udf_lands_in_hard_fault() {
    // main: WFI with nothing enabled sleeps to the end of the run
    let sleeper = run(&image(&[WFI, B_SELF], &[BX_LR], &[BX_LR], &[B_SELF]));
    assert!(sleeper.log().asleep > 90_000, "{}", sleeper.log().asleep);
    // a UDF: the HardFault handler records its stacked PC
    let fault = [
        mov32(4, RAM),
        vec![0x9806, str(0, 4, 0), B_SELF], // ldr r0, [sp, #24]; str r0, [r4]
    ]
    .concat();
    let b = run(&image(&[0xBF00, UDF, B_SELF], &[BX_LR], &[BX_LR], &fault));
    assert_eq!(
        word(&b, RAM),
        RESET + 2,
        "the return address is the UDF itself"
    );
}

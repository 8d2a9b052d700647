//! The timing rules on hand-encoded Thumb-2 snippets (encodings checked with llvm-mc; each
//! halfword is commented with its instruction). Code runs from SRAM unless the test is about
//! flash, so that only the rule under test moves the counts.

use alvs_cycles::{memory, Access, Class, Error, FlashModel, Machine, Run};

const SRAM_CODE: u32 = 0x2000_0000;
const FLASH_CODE: u32 = 0x0800_0000;
/// Where tests put data: the middle of SRAM, clear of the code.
const DATA: u32 = 0x2001_0000;

fn bytes(halfwords: &[u16]) -> Vec<u8> {
    halfwords.iter().flat_map(|h| h.to_le_bytes()).collect()
}

fn run_at(at: u32, halfwords: &[u16], args: &[u32]) -> Run {
    let mut m = Machine::from_raw(&bytes(halfwords), at).unwrap();
    m.call(at, args).unwrap()
}

fn class(run: &Run, class: Class) -> (u64, u64) {
    run.classes
        .iter()
        .find(|(c, _)| *c == class)
        .map_or((0, 0), |(_, s)| (s.instructions, s.cycles))
}

const ALU: [u16; 7] = [
    0x2001, // movs r0, #1
    0x3002, // adds r0, #2
    0x1800, // adds r0, r0, r0
    0x0080, // lsls r0, r0, #2
    0x4049, // eors r1, r1
    0x4308, // orrs r0, r1
    0x4770, // bx lr
];

#[test]
fn straight_line_alu_is_one_cycle_each_plus_the_return() {
    let run = run_at(SRAM_CODE, &ALU, &[]);
    assert_eq!(run.ret, 24);
    assert_eq!(run.instructions, 7);
    // 6 ALU + bx lr (1 + P): the return is the only taken branch.
    assert_eq!(run.taken_branches, 1);
    assert_eq!(run.nominal, 6 + 2);
    assert_eq!(run.pessimistic, 6 + 4);
    assert_eq!(class(&run, Class::Alu), (6, 6));
    assert_eq!(run.flash_misses, 0);
}

const LOOP: [u16; 6] = [
    0x2000, // movs r0, #0
    0x210A, // movs r1, #10
    0x3001, // loop: adds r0, #1
    0x3901, // subs r1, #1
    0xD1FC, // bne loop
    0x4770, // bx lr
];

#[test]
fn loop_pays_the_taken_branch_penalty_per_model() {
    // From SRAM: no flash effects. base = 2 + 10 * 3 + 1 = 33; taken = 9 bne + bx lr.
    let run = run_at(SRAM_CODE, &LOOP, &[]);
    assert_eq!(run.ret, 10);
    assert_eq!(run.taken_branches, 10);
    assert_eq!(run.nominal, 33 + 10);
    assert_eq!(run.pessimistic, 33 + 30);

    // From flash with the ART: the entry misses (cold cache), the loop's target line then hits.
    let run = run_at(FLASH_CODE, &LOOP, &[]);
    assert_eq!(run.flash_misses, 1);
    assert_eq!(run.nominal, 43);
    assert_eq!(run.pessimistic, 33 + 30 + 5);

    // Without a cache every taken branch into flash pays the 5 wait states.
    let mut m = Machine::from_raw(&bytes(&LOOP), FLASH_CODE).unwrap();
    m.set_flash_model(FlashModel::EveryBranchTarget);
    let run = m.call(FLASH_CODE, &[]).unwrap();
    assert_eq!(run.flash_misses, 1 + 9);
    assert_eq!(run.nominal, 43);
    assert_eq!(run.pessimistic, 33 + 30 + 50);
}

/// Bcc.W (encoding T3) at `from` to `to`.
fn bcc_w(cond: u16, from: u32, to: u32) -> [u16; 2] {
    let v = (to.wrapping_sub(from + 4) as i32 >> 1) as u32;
    let (imm11, imm6) = ((v & 0x7FF) as u16, ((v >> 11) & 0x3F) as u16);
    let (j1, j2, s) = (
        ((v >> 17) & 1) as u16,
        ((v >> 18) & 1) as u16,
        ((v >> 19) & 1) as u16,
    );
    [
        0xF000 | s << 10 | cond << 6 | imm6,
        0x8000 | j1 << 13 | j2 << 11 | imm11,
    ]
}

#[test]
fn art_misses_when_the_code_outgrows_the_cache() {
    // llvm-mc/llvm-objdump: `bne.w` at 0x412 back to 0x0 is f47f adf5.
    assert_eq!(bcc_w(1, 0x412, 0x0), [0xF47F, 0xADF5]);
    // A loop over 520 nops (65 lines of 16 bytes, more than the ART's 64):
    // movs r1, #3; top: 520 x nop; subs r1, #1; bne.w top; bx lr.
    let nops = 520;
    let mut code = vec![0x2103]; // movs r1, #3
    code.extend(std::iter::repeat_n(0xBF00u16, nops)); // nop
    code.push(0x3901); // subs r1, #1
    let at = 2 + 2 * nops as u32 + 2;
    code.extend(bcc_w(1, at, 2)); // bne.w top
    code.push(0x4770); // bx lr
    let mut m = Machine::from_raw(&bytes(&code), FLASH_CODE).unwrap();
    let run = m.call(FLASH_CODE, &[]).unwrap();
    assert_eq!(run.taken_branches, 2 + 1);
    // LRU over 66 lines with 64 entries: the loop's first line was evicted every time.
    assert_eq!(run.flash_misses, 1 + 2);
    m.set_flash_model(FlashModel::Art { lines: 128 });
    let run = m.call(FLASH_CODE, &[]).unwrap();
    assert_eq!(run.flash_misses, 1);
}

#[test]
fn loads_pipeline_unless_dependent_and_stores_pay_after_stores() {
    let code = [
        0x6801, // ldr r1, [r0]       2
        0x6842, // ldr r2, [r0, #4]   1: follows an independent load
        0x6813, // ldr r3, [r2]       3: r2 from the preceding load: no pipelining, +1 address
        0x3008, // adds r0, #8        1
        0x6801, // ldr r1, [r0]       3: r0 written by the preceding instruction
        0x6001, // str r1, [r0]       1
        0x6041, // str r1, [r0, #4]   2: after another store
        0x4770, // bx lr              1 + P
    ];
    let mut m = Machine::from_raw(&bytes(&code), SRAM_CODE).unwrap();
    // [DATA + 4] points back at DATA, so `ldr r3, [r2]` reads mapped memory.
    m.write(DATA + 4, &DATA.to_le_bytes()).unwrap();
    m.write(DATA + 8, &0x1234u32.to_le_bytes()).unwrap();
    let run = m.call(SRAM_CODE, &[DATA]).unwrap();
    assert_eq!(class(&run, Class::Load), (4, 2 + 1 + 3 + 3));
    assert_eq!(class(&run, Class::Store), (2, 1 + 2));
    assert_eq!(run.nominal, 14 + 1);
    assert_eq!(run.pessimistic, 14 + 3);
    assert_eq!(m.read_u32(DATA + 12).unwrap(), 0x1234, "the stores ran");
}

#[test]
fn udiv_costs_twelve() {
    let code = [
        0xFBB0, 0xF0F1, // udiv r0, r0, r1
        0x4770, // bx lr
    ];
    let run = run_at(SRAM_CODE, &code, &[100, 7]);
    assert_eq!(run.ret, 14);
    assert_eq!(class(&run, Class::Divide), (1, 12));
    assert_eq!(run.nominal, 12 + 2);
}

#[test]
fn failed_it_conditions_cost_one_each_and_are_no_branch() {
    let ite = [
        0x2800, // cmp r0, #0
        0xBF0C, // ite eq
        0x2101, // moveq r1, #1
        0x2102, // movne r1, #2
        0x4608, // mov r0, r1
        0x4770, // bx lr
    ];
    for (arg, ret) in [(0, 1), (5, 2)] {
        let run = run_at(FLASH_CODE, &ite, &[arg]);
        assert_eq!(run.ret, ret);
        assert_eq!(run.instructions, 6);
        assert_eq!(class(&run, Class::ItSkipped), (1, 1));
        assert_eq!(run.taken_branches, 1, "only the return");
        assert_eq!(run.flash_misses, 1, "only the entry");
        assert_eq!(run.nominal, 6 + 1);
    }
    // Both instructions at the end of the block skipped: the next executed follows the block.
    let itt = [
        0x2800, // cmp r0, #0
        0xBF04, // itt eq
        0x3001, // addeq r0, #1
        0x3001, // addeq r0, #1
        0x3005, // adds r0, #5
        0x4770, // bx lr
    ];
    let run = run_at(SRAM_CODE, &itt, &[3]);
    assert_eq!(run.ret, 8);
    assert_eq!(class(&run, Class::ItSkipped), (2, 2));
    assert_eq!((run.taken_branches, run.nominal), (1, 6 + 1));
    let run = run_at(SRAM_CODE, &itt, &[0]);
    assert_eq!(run.ret, 7);
    assert_eq!(class(&run, Class::ItSkipped), (0, 0));
    assert_eq!((run.taken_branches, run.nominal), (1, 6 + 1));
}

#[test]
fn dwt_cyccnt_returns_the_modelled_count_and_is_logged() {
    let code = [
        0xF241, 0x0104, // movw r1, #0x1004
        0xF2CE, 0x0100, // movt r1, #0xe000
        0x6808, // ldr r0, [r1]   (3: r1 written just before)
        0xBF00, // nop
        0xBF00, // nop
        0xBF00, // nop
        0x680A, // ldr r2, [r1]
        0x1A10, // subs r0, r2, r0
        0x4770, // bx lr
    ];
    let mut m = Machine::from_raw(&bytes(&code), FLASH_CODE).unwrap();
    let run = m.call(FLASH_CODE, &[]).unwrap();
    assert_eq!(run.dwt_reads.len(), 2);
    let (a, b) = (run.dwt_reads[0], run.dwt_reads[1]);
    // Counts at each read include the reading instruction; the entry's flash miss is in the
    // pessimistic count only.
    assert_eq!((a.pc, a.nominal, a.pessimistic), (FLASH_CODE + 8, 5, 10));
    assert_eq!((b.pc, b.nominal, b.pessimistic), (FLASH_CODE + 16, 10, 15));
    assert_eq!(u64::from(run.ret), b.pessimistic - a.pessimistic);

    // CYCCNT free-runs across calls: a second call reads on from the first's total.
    let first = run.pessimistic;
    let run = m.call(FLASH_CODE, &[]).unwrap();
    assert_eq!(run.dwt_reads[0].pessimistic, 10, "stamps are per call");
    let cyccnt = m.read_u32(memory::DWT_CYCCNT).unwrap();
    assert_eq!(u64::from(cyccnt), 2 * first);
    // Writing CYCCNT (as `DWT::set_cycle_count` does) restarts it from the value written.
    m.write(memory::DWT_CYCCNT, &1000u32.to_le_bytes()).unwrap();
    let run = m.call(FLASH_CODE, &[]).unwrap();
    assert_eq!(
        u64::from(m.read_u32(memory::DWT_CYCCNT).unwrap()),
        1000 + run.pessimistic
    );
}

#[test]
fn bad_accesses_are_errors_naming_the_address() {
    let load = [
        0x6808, // ldr r0, [r1]
        0x4770, // bx lr
    ];
    let mut m = Machine::from_raw(&bytes(&load), SRAM_CODE).unwrap();
    let err = m.call(SRAM_CODE, &[0, 0x4002_0010]).unwrap_err();
    assert_eq!(
        err,
        Error::Unmapped {
            access: Access::Read,
            addr: 0x4002_0010,
            pc: SRAM_CODE
        }
    );
    assert!(err.to_string().contains("0x40020010"), "{err}");
    // The machine is usable after an error.
    m.write(DATA, &7u32.to_le_bytes()).unwrap();
    assert_eq!(m.call(SRAM_CODE, &[0, DATA]).unwrap().ret, 7);

    let store = [
        0x6001, // str r1, [r0]
        0x4770, // bx lr
    ];
    let mut m = Machine::from_raw(&bytes(&store), SRAM_CODE).unwrap();
    let err = m.call(SRAM_CODE, &[FLASH_CODE + 0x100, 1]).unwrap_err();
    assert_eq!(
        err,
        Error::Protected {
            access: Access::Write,
            addr: FLASH_CODE + 0x100,
            pc: SRAM_CODE
        }
    );
    // Raw code may not be placed outside the map nor in CCM (no instruction fetch there).
    assert!(matches!(
        Machine::from_raw(&[0; 4], 0x3000_0000),
        Err(Error::Load { .. })
    ));
    assert!(matches!(
        Machine::from_raw(&[0; 4], memory::CCM.start),
        Err(Error::Load { .. })
    ));
}

#[test]
fn runaway_code_overflows_and_faults_are_errors() {
    let forever = [0xE7FE]; // b .
    let mut m = Machine::from_raw(&bytes(&forever), SRAM_CODE).unwrap();
    m.set_limit(Some(1000));
    let err = m.call(SRAM_CODE, &[]).unwrap_err();
    assert!(
        matches!(
            err,
            Error::InstructionLimit {
                limit: 1000,
                pc: SRAM_CODE
            }
        ),
        "{err}"
    );

    let recurse = [
        0xB5F0, // f: push {r4, r5, r6, r7, lr}
        0xF7FF, 0xFFFD, // bl f
    ];
    let mut m = Machine::from_raw(&bytes(&recurse), SRAM_CODE).unwrap();
    let err = m.call(SRAM_CODE, &[]).unwrap_err();
    match err {
        Error::StackOverflow {
            addr, stack, pc, ..
        } => {
            assert_eq!(stack, memory::CCM);
            assert!(
                (memory::CCM.start - 20..memory::CCM.start).contains(&addr),
                "{addr:#x}"
            );
            assert_eq!(pc, SRAM_CODE);
        }
        e => panic!("expected a stack overflow, got {e}"),
    }

    let udf = [0xDE00]; // udf #0
    let mut m = Machine::from_raw(&bytes(&udf), SRAM_CODE).unwrap();
    let err = m.call(SRAM_CODE, &[]).unwrap_err();
    assert!(
        matches!(
            err,
            Error::Exception { pc: SRAM_CODE, .. } | Error::InvalidInstruction { pc: SRAM_CODE }
        ),
        "{err}"
    );
}

#[test]
fn vfp_runs_with_the_fpu_enabled_and_costs_per_table() {
    let code = [
        0xEE00, 0x0A10, // vmov s0, r0            2
        0xEE00, 0x1A90, // vmov s1, r1            2
        0xEE30, 0x1A20, // vadd.f32 s2, s0, s1    1
        0xEE21, 0x1A20, // vmul.f32 s2, s2, s1    1
        0xEEC1, 0x1A20, // vdiv.f32 s3, s2, s1   14
        0xEE11, 0x0A90, // vmov r0, s3            2
        0x4770, // bx lr
    ];
    let mut m = Machine::from_raw(&bytes(&code), SRAM_CODE).unwrap();
    assert_eq!(
        m.read_u32(memory::SCB_CPACR).unwrap() >> 20 & 0xF,
        0xF,
        "CP10/CP11 full access"
    );
    let run = m
        .call(SRAM_CODE, &[1.5f32.to_bits(), 2.0f32.to_bits()])
        .unwrap();
    assert_eq!(f32::from_bits(run.ret), 3.5);
    assert_eq!(class(&run, Class::FpTransfer), (3, 6));
    assert_eq!(class(&run, Class::FpAlu), (2, 2));
    assert_eq!(class(&run, Class::FpDivSqrt), (1, 14));
    assert_eq!(run.nominal, 22 + 2);
}

#[test]
fn stack_painting_measures_the_push_depth() {
    let code = [
        0xB5F0, // push {r4, r5, r6, r7, lr}   20 bytes, 1 + 5
        0xB090, // sub sp, #64                 84 bytes
        0xB010, // add sp, #64
        0xBDF0, // pop {r4, r5, r6, r7, pc}    1 + 5 + P
    ];
    let mut m = Machine::from_raw(&bytes(&code), SRAM_CODE).unwrap();
    m.paint_stack(0xDEAD_BEEF).unwrap();
    assert_eq!(m.stack_high_water(0xDEAD_BEEF).unwrap(), 0);
    let run = m.call(SRAM_CODE, &[1, 2, 3, 4]).unwrap();
    // sub sp only moves SP: the measured depth is what was written, the 20 pushed bytes.
    assert_eq!(m.stack_high_water(0xDEAD_BEEF).unwrap(), 20);
    // The pop pays +1: its address register SP was written by the `add sp` before it.
    assert_eq!(class(&run, Class::LoadStoreMultiple), (2, 6 + 7));
    assert_eq!(run.nominal, 13 + 2 + 1);
    assert_eq!(run.pessimistic, 13 + 2 + 3);

    // Explicit ranges work the same way.
    let top = m.stack().end;
    m.paint(top - 256..top, 0).unwrap();
    m.write(top - 100, &[1]).unwrap();
    assert_eq!(m.high_water(top - 256..top, 0).unwrap(), 100);
}

#[test]
fn arguments_beyond_four_go_on_the_stack() {
    let code = [
        0xE9DD, 0x2300, // ldrd r2, r3, [sp]
        0x4410, // add r0, r2
        0x4418, // add r0, r3
        0x4770, // bx lr
    ];
    let run = run_at(SRAM_CODE, &code, &[10, 0, 0, 0, 5, 6]);
    assert_eq!(run.ret, 21);
    assert_eq!(class(&run, Class::LoadStoreDouble), (1, 3));
}

#[test]
fn counts_are_identical_run_to_run() {
    let runs: Vec<Run> = (0..3)
        .map(|_| {
            let mut m = Machine::from_raw(&bytes(&LOOP), FLASH_CODE).unwrap();
            let a = m.call(FLASH_CODE, &[]).unwrap();
            let b = m.call(FLASH_CODE, &[]).unwrap();
            assert_eq!(a, b, "same machine, second call");
            a
        })
        .collect();
    assert!(runs.windows(2).all(|w| w[0] == w[1]));
}

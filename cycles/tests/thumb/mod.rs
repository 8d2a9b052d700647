//! Thumb-2 encodings for tests that run hand-written code on the virtual board: the
//! integration tests of its core (`virtual_core.rs`) and the board's own unit tests
//! (`src/system/board/tests.rs`, which include this file by path).

// each user takes part of this module
#![allow(dead_code)]

/// Flash starts here in the memory map.
pub const FLASH_BASE: u32 = 0x0800_0000;

/// Writes the little-endian word `v` at byte `offset` of a flash image (a vector table entry).
pub fn put_word(flash: &mut [u8], offset: usize, v: u32) {
    flash[offset..offset + 4].copy_from_slice(&v.to_le_bytes());
}

/// Writes the halfwords of `code` into a flash image at flash address `at`.
pub fn place(flash: &mut [u8], at: u32, code: &[u16]) {
    let start = (at - FLASH_BASE) as usize;
    for (k, h) in code.iter().enumerate() {
        flash[start + 2 * k..start + 2 * k + 2].copy_from_slice(&h.to_le_bytes());
    }
}

/// movw rd, #imm16
pub fn movw(rd: u16, imm: u16) -> [u16; 2] {
    let (i, imm4, imm3, imm8) = ((imm >> 11) & 1, imm >> 12, (imm >> 8) & 7, imm & 0xFF);
    [0xF240 | i << 10 | imm4, imm3 << 12 | rd << 8 | imm8]
}

/// movt rd, #imm16
pub fn movt(rd: u16, imm: u16) -> [u16; 2] {
    let [a, b] = movw(rd, imm);
    [a | 0x0080, b]
}

/// rd = v (movw, movt)
pub fn mov32(rd: u16, v: u32) -> Vec<u16> {
    [movw(rd, v as u16), movt(rd, (v >> 16) as u16)].concat()
}

/// str rt, [rn, #4 imm5]
pub fn str(rt: u16, rn: u16, offset: u16) -> u16 {
    0x6000 | (offset / 4) << 6 | rn << 3 | rt
}

/// b . (halt)
pub const B_SELF: u16 = 0xE7FE;

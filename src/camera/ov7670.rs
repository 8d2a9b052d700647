//! OV7670 facts: SCCB id, register addresses, identification values and the configuration
//! table, as data.
//!
//! The values of [`CONFIG`] are those of the public Colias firmware listed in docs/hardware.md
//! ("Camera: OV7670 over DCMI"); they were never checked on a board. The per-register notes come
//! from the OV7670 datasheet (rev. 1.4) and OmniVision's OV7670 implementation guide as recalled
//! here, not re-read: where a note says "unsure", the bring-up checklist has to confirm it.
//! Together, COM3/COM14/0x72/0x73/0xA2 are, as far as we recall, the implementation guide's
//! down-scaled ("QQCIF", 88x72) setting; docs/hardware.md says the frames the firmware processes
//! are 99x72, so the real output size has to be measured on the first frames (and the DCMI crop
//! window set from it).

/// SCCB id of the OV7670 for writes, 8-bit form (0x43 for reads; 7-bit address 0x21).
/// OV7670 datasheet; fixed in the sensor.
pub const SCCB_ID: u8 = 0x42;

/// Register addresses (OV7670 datasheet names).
pub mod reg {
    /// Product ID number MSB (read-only).
    pub const PID: u8 = 0x0A;
    /// Product ID number LSB, the version (read-only).
    pub const VER: u8 = 0x0B;
    /// Common control 3: scaling / DCW enables.
    pub const COM3: u8 = 0x0C;
    /// Internal clock: prescaler from XCLK.
    pub const CLKRC: u8 = 0x11;
    /// Common control 7: reset, output size and format.
    pub const COM7: u8 = 0x12;
    /// Common control 8: AGC / AWB / AEC enables.
    pub const COM8: u8 = 0x13;
    /// Common control 9: automatic gain ceiling.
    pub const COM9: u8 = 0x14;
    /// Mirror / vertical flip.
    pub const MVFP: u8 = 0x1E;
    /// Common control 14: DCW / scaling pixel clock.
    pub const COM14: u8 = 0x3E;
    /// Horizontal scale factor.
    pub const SCALING_XSC: u8 = 0x70;
    /// Vertical scale factor.
    pub const SCALING_YSC: u8 = 0x71;
    /// Down-sampling (DCW) control.
    pub const SCALING_DCWCTR: u8 = 0x72;
    /// DSP scaling clock divider.
    pub const SCALING_PCLK_DIV: u8 = 0x73;
    /// Scaling output delay.
    pub const SCALING_PCLK_DELAY: u8 = 0xA2;
}

/// Expected [`reg::PID`] of an OV7670 (datasheet default, read-only).
pub const EXPECTED_PID: u8 = 0x76;
/// Expected [`reg::VER`] of an OV7670 (datasheet default, read-only; docs/hardware.md: VER =
/// 0x73).
pub const EXPECTED_VER: u8 = 0x73;

/// [`reg::COM7`] value that resets every register to its default (bit 7, self-clearing).
pub const COM7_RESET: u8 = 0x80;

/// Wait after the register reset before the next SCCB access, in ms. The datasheet gives 1 ms
/// for the reset to settle; 10 ms is a margin (bring-up cost only).
pub const RESET_SETTLE_MS: u32 = 10;

/// Wait between starting XCLK and the first SCCB access, in ms: the sensor's SCCB logic runs on
/// XCLK. Not from a datasheet figure, a margin (bring-up cost only).
pub const XCLK_STARTUP_MS: u32 = 10;

/// Configuration written after the reset, in this order: (register, value).
pub const CONFIG: &[(u8, u8)] = &[
    // CLKRC 0x80. Bits 5:0 = 0: internal clock = XCLK / (0 + 1), so 25 MHz (the PLL in DBLV
    // stays at its bypass default); bit 6 = 0: go through that prescaler rather than use XCLK
    // directly (same result at /1). Bit 7 is "reserved" in the datasheet, yet set here; some
    // public drivers name 0x80 an automatic frame-rate adjust (night mode): unsure what it does.
    (reg::CLKRC, 0x80),
    // COM7 0x08. Bit 3: QCIF output size (176x144) selected; bits 2 and 0 = 0: YUV output;
    // bit 1 = 0: no colour bar; bit 7 = 0: no reset. Unsure how the QCIF bit combines with the
    // down-scaling below (some drivers get QCIF from VGA + scaling instead): measure the output.
    (reg::COM7, 0x08),
    // COM3 0x0C. Bit 3: scaling enable; bit 2: DCW (down-sample/crop/window) enable; bit 6 =
    // 0: no output MSB/LSB swap. The YUV byte order (TSLB 0x3A, COM13 0x3D) stays at its
    // default, believed Y U Y V (docs/hardware.md's public code finds luminance on even bytes):
    // check on the first frame.
    (reg::COM3, 0x0C),
    // COM14 0x12. Bit 4: PCLK comes from the DCW/scaling divider instead of the normal pixel
    // clock; bits 2:0 = 010: that divider is /4, matching SCALING_PCLK_DIV (so PCLK presumably
    // ≈ 6.25 MHz from the 25 MHz internal clock: measure); bit 3 = 0: no manual scaling (the predefined scaling of
    // the size COM7 selects). Unsure whether SCALING_XSC/YSC apply with bit 3 clear.
    (reg::COM14, 0x12),
    // SCALING_XSC 0x3A. Bits 6:0: horizontal scale factor 0x3A (the implementation guide's
    // value for all its sizes; datasheet default 0x4A); bit 7 = 0: test pattern bit 0 off.
    (reg::SCALING_XSC, 0x3A),
    // SCALING_YSC 0x35. Bits 6:0: vertical scale factor 0x35 (datasheet default); bit 7 = 0:
    // test pattern bit 1 off.
    (reg::SCALING_YSC, 0x35),
    // SCALING_DCWCTR 0x22. Bits 5:4 = 10: vertical down-sampling by 4; bits 1:0 = 10:
    // horizontal down-sampling by 4; averaging/rounding options (bits 7, 6, 3, 2) off.
    (reg::SCALING_DCWCTR, 0x22),
    // SCALING_PCLK_DIV 0xF2. Bits 2:0 = 010: DSP scaling clock divided by 4 (same as COM14);
    // bit 3 = 0: divider not bypassed; bits 7:4 reserved, written 0xF as public drivers do
    // (unsure of their meaning).
    (reg::SCALING_PCLK_DIV, 0xF2),
    // SCALING_PCLK_DELAY 0x2A. Bits 6:0: scaling output delay 42 (datasheet default 0x02); shifts
    // the scaled pixels within the line. Unsure of the unit (pixel clocks, presumably).
    (reg::SCALING_PCLK_DELAY, 0x2A),
    // MVFP 0x11. Bit 4: vertical flip on (docs/hardware.md: image flipped vertically, the sensor
    // sits upside down presumably); bit 5 = 0: no mirror; bit 0 reserved (written 1, unsure why;
    // probably the reserved default kept).
    (reg::MVFP, 0x11),
    // COM8 0x8F, automatic gain on in docs/hardware.md. Bit 2: AGC on. The other bits are the
    // datasheet reset value, kept because the public firmware's exact COM8 is not documented: bit 7
    // fast AGC/AEC algorithm, bit 6 = 0 AEC step limited to the vertical blank, bit 5 = 0 banding
    // filter off, bit 1 AWB on, bit 0 AEC (auto exposure) on. Unsure whether the public firmware
    // keeps AEC on; an exposure that tracks the scene changes global luminance, which the model
    // sees.
    (reg::COM8, 0x8F),
    // COM9 0x6A, "gain ceiling 0x6A" in docs/hardware.md. Bits 6:4 = 110: automatic gain ceiling
    // 128x (datasheet default 0x4A = 32x); bits 3:1 = 101 reserved (as in the default); bit 0 =
    // 0: AGC/AEC not frozen.
    (reg::COM9, 0x6A),
];

/// Registers of [`CONFIG`] read back after writing it, to check that the writes took: the size,
/// format and scaling ones, whose bits are all documented. Not CLKRC (its bit 7 is reserved and
/// may read back differently), MVFP (reserved bit 0), COM8 (the sensor may update it).
pub const VERIFY: &[u8] = &[
    reg::COM7,
    reg::COM3,
    reg::COM14,
    reg::SCALING_DCWCTR,
    reg::SCALING_PCLK_DIV,
    reg::COM9,
];

/// The value [`CONFIG`] writes to `reg`, if it writes one (the last one, if several).
pub const fn configured(reg: u8) -> Option<u8> {
    let mut value = None;
    let mut i = 0;
    while i < CONFIG.len() {
        if CONFIG[i].0 == reg {
            value = Some(CONFIG[i].1);
        }
        i += 1;
    }
    value
}

// Every verified register is one the table writes (checked at compile time).
const _: () = {
    let mut i = 0;
    while i < VERIFY.len() {
        assert!(
            configured(VERIFY[i]).is_some(),
            "VERIFY lists a register CONFIG does not write"
        );
        i += 1;
    }
};

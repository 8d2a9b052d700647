//! The Cortex-M4 DSP instructions the pixel loops are built on, each with its exact meaning in
//! plain Rust.
//!
//! LLVM does not select these from ordinary arithmetic (a dual 16x16 multiply-subtract comes
//! out as `SMULBT` + `SXTH` + `ASR` + `MLS`), and their intrinsics in `core::arch::arm` are not
//! stable. So on `target_arch = "arm"` (the firmware, `thumbv7em`: ARMv7E-M has the DSP
//! extension) each function is the one instruction, written with `asm!`; everywhere else
//! (the host: replay, simulator, tests) it is the plain Rust below. The two are held equal bit
//! for bit by the cycle model's budget test, which runs the firmware build on every frame and
//! compares its outputs with the host build's (`cycles/tests/budget.rs`), and the plain forms
//! are checked here against their definitions. The FPU's square root (`VSQRT.F32`) is here too:
//! on the firmware `libm::sqrtf` is a software routine.
//!
//! This is the only `unsafe` in the model: single register-to-register instructions, no memory,
//! no stack (`asm!` options `pure, nomem, nostack`). Those that may set the APSR's Q or GE flags
//! (which no code reads) do not claim `preserves_flags`.
#![allow(unsafe_code)]

/// Signed low half of a word (an `i16` lane).
#[inline(always)]
pub fn lo(v: u32) -> i32 {
    i32::from(v as u16 as i16)
}

/// Signed high half of a word (an `i16` lane).
#[inline(always)]
pub fn hi(v: u32) -> i32 {
    (v as i32) >> 16
}

/// `SMUSDX`: `lo(a)·hi(b) − hi(a)·lo(b)`, the dual 16x16 multiply-subtract with the second
/// operand's halves exchanged. Cannot overflow: `|result| ≤ 2^31 − 2^15`.
#[inline(always)]
pub fn smusdx(a: u32, b: u32) -> i32 {
    #[cfg(target_arch = "arm")]
    {
        let r: i32;
        // SAFETY: one register-only instruction of ARMv7E-M.
        unsafe {
            core::arch::asm!("smusdx {r}, {a}, {b}", r = lateout(reg) r, a = in(reg) a,
                b = in(reg) b, options(pure, nomem, nostack));
        }
        r
    }
    #[cfg(not(target_arch = "arm"))]
    {
        (lo(a) * hi(b)).wrapping_sub(hi(a) * lo(b))
    }
}

/// `SMLSDX`: `acc + lo(a)·hi(b) − hi(a)·lo(b)`, wrapping like the instruction.
#[inline(always)]
pub fn smlsdx(a: u32, b: u32, acc: i32) -> i32 {
    #[cfg(target_arch = "arm")]
    {
        let r: i32;
        // SAFETY: one register-only instruction of ARMv7E-M.
        unsafe {
            core::arch::asm!("smlsdx {r}, {a}, {b}, {c}", r = lateout(reg) r, a = in(reg) a,
                b = in(reg) b, c = in(reg) acc, options(pure, nomem, nostack));
        }
        r
    }
    #[cfg(not(target_arch = "arm"))]
    {
        acc.wrapping_add((lo(a) * hi(b)).wrapping_sub(hi(a) * lo(b)))
    }
}

/// `USAT rd, #31, x, ASR #SH`: `max(0, x >> SH)` (arithmetic shift; the upper clamp at
/// `2^31 − 1` never bites after a shift of a 32-bit value). Half-wave rectification and
/// scaling in one instruction. `SH` is 1–31.
#[inline(always)]
pub fn rectify_asr<const SH: u32>(x: i32) -> u32 {
    #[cfg(target_arch = "arm")]
    {
        let r: u32;
        // SAFETY: one register-only instruction of ARMv7-M.
        unsafe {
            core::arch::asm!("usat {r}, #31, {x}, asr #{sh}", r = lateout(reg) r, x = in(reg) x,
                sh = const SH, options(pure, nomem, nostack));
        }
        r
    }
    #[cfg(not(target_arch = "arm"))]
    {
        (x >> SH).max(0) as u32
    }
}

/// `UQSUB8`: `a − b` in each of the four bytes, saturated at 0.
#[inline(always)]
pub fn uqsub8(a: u32, b: u32) -> u32 {
    #[cfg(target_arch = "arm")]
    {
        let r: u32;
        // SAFETY: one register-only instruction of ARMv7E-M.
        unsafe {
            core::arch::asm!("uqsub8 {r}, {a}, {b}", r = lateout(reg) r, a = in(reg) a,
                b = in(reg) b, options(pure, nomem, nostack));
        }
        r
    }
    #[cfg(not(target_arch = "arm"))]
    {
        let (a, b) = (a.to_le_bytes(), b.to_le_bytes());
        u32::from_le_bytes(core::array::from_fn(|i| a[i].saturating_sub(b[i])))
    }
}

/// `SMULWB`: `(a · lo(b)) >> 16`, a 32x16 multiply keeping the top 32 bits of the 48-bit
/// product (arithmetic shift).
#[inline(always)]
pub fn smulwb(a: i32, b: u32) -> i32 {
    #[cfg(target_arch = "arm")]
    {
        let r: i32;
        // SAFETY: one register-only instruction of ARMv7E-M.
        unsafe {
            core::arch::asm!("smulwb {r}, {a}, {b}", r = lateout(reg) r, a = in(reg) a,
                b = in(reg) b, options(pure, nomem, nostack, preserves_flags));
        }
        r
    }
    #[cfg(not(target_arch = "arm"))]
    {
        ((i64::from(a) * i64::from(lo(b))) >> 16) as i32
    }
}

/// `SMULWT`: `(a · hi(b)) >> 16`.
#[inline(always)]
pub fn smulwt(a: i32, b: u32) -> i32 {
    #[cfg(target_arch = "arm")]
    {
        let r: i32;
        // SAFETY: one register-only instruction of ARMv7E-M.
        unsafe {
            core::arch::asm!("smulwt {r}, {a}, {b}", r = lateout(reg) r, a = in(reg) a,
                b = in(reg) b, options(pure, nomem, nostack, preserves_flags));
        }
        r
    }
    #[cfg(not(target_arch = "arm"))]
    {
        ((i64::from(a) * i64::from(hi(b))) >> 16) as i32
    }
}

/// `USUB8` then `SEL`: per byte, `x` where `a ≥ b` (unsigned) and `y` elsewhere. One `asm!`
/// block, since the GE flags `USUB8` sets must reach `SEL` untouched.
#[inline(always)]
pub fn sel_ge(a: u32, b: u32, x: u32, y: u32) -> u32 {
    #[cfg(target_arch = "arm")]
    {
        let r: u32;
        // SAFETY: two register-only instructions of ARMv7E-M (the GE flags are clobbered).
        unsafe {
            core::arch::asm!("usub8 {r}, {a}, {b}", "sel {r}, {x}, {y}", r = out(reg) r,
                a = in(reg) a, b = in(reg) b, x = in(reg) x, y = in(reg) y,
                options(pure, nomem, nostack));
        }
        r
    }
    #[cfg(not(target_arch = "arm"))]
    {
        let (a, b, x, y) = (
            a.to_le_bytes(),
            b.to_le_bytes(),
            x.to_le_bytes(),
            y.to_le_bytes(),
        );
        u32::from_le_bytes(core::array::from_fn(
            |i| if a[i] >= b[i] { x[i] } else { y[i] },
        ))
    }
}

/// `USUB16` then `SEL`: per 16-bit lane, `x` where `a ≥ b` (unsigned) and `y` elsewhere. One
/// `asm!` block, as [`sel_ge`].
#[inline(always)]
pub fn sel_ge16(a: u32, b: u32, x: u32, y: u32) -> u32 {
    #[cfg(target_arch = "arm")]
    {
        let r: u32;
        // SAFETY: two register-only instructions of ARMv7E-M (the GE flags are clobbered).
        unsafe {
            core::arch::asm!("usub16 {r}, {a}, {b}", "sel {r}, {x}, {y}", r = out(reg) r,
                a = in(reg) a, b = in(reg) b, x = in(reg) x, y = in(reg) y,
                options(pure, nomem, nostack));
        }
        r
    }
    #[cfg(not(target_arch = "arm"))]
    {
        let lane = |v: u32, i: u32| (v >> (16 * i)) & 0xFFFF;
        (0..2).fold(0, |r, i| {
            let v = if lane(a, i) >= lane(b, i) { x } else { y };
            r | lane(v, i) << (16 * i)
        })
    }
}

/// `SMLAD`: `acc + lo(a)·lo(b) + hi(a)·hi(b)`, the dual 16x16 multiply-accumulate, wrapping
/// like the instruction.
#[inline(always)]
pub fn smlad(a: u32, b: u32, acc: i32) -> i32 {
    #[cfg(target_arch = "arm")]
    {
        let r: i32;
        // SAFETY: one register-only instruction of ARMv7E-M.
        unsafe {
            core::arch::asm!("smlad {r}, {a}, {b}, {c}", r = lateout(reg) r, a = in(reg) a,
                b = in(reg) b, c = in(reg) acc, options(pure, nomem, nostack));
        }
        r
    }
    #[cfg(not(target_arch = "arm"))]
    {
        acc.wrapping_add(lo(a) * lo(b)).wrapping_add(hi(a) * hi(b))
    }
}

/// `UXTAB16`: `acc + (x & 0x00FF00FF)` lane by lane, each 16-bit lane of `acc` adding its
/// byte of `x` (bytes 0 and 2) modulo 2^16, no carry between the lanes.
#[inline(always)]
pub fn uxtab16(acc: u32, x: u32) -> u32 {
    #[cfg(target_arch = "arm")]
    {
        let r: u32;
        // SAFETY: one register-only instruction of ARMv7E-M.
        unsafe {
            core::arch::asm!("uxtab16 {r}, {a}, {x}", r = lateout(reg) r, a = in(reg) acc,
                x = in(reg) x, options(pure, nomem, nostack, preserves_flags));
        }
        r
    }
    #[cfg(not(target_arch = "arm"))]
    {
        lanes_add(acc, x & 0x00FF_00FF)
    }
}

/// `UXTAB16 …, ROR #8`: [`uxtab16`] of bytes 1 and 3 of `x`.
#[inline(always)]
pub fn uxtab16_ror8(acc: u32, x: u32) -> u32 {
    #[cfg(target_arch = "arm")]
    {
        let r: u32;
        // SAFETY: one register-only instruction of ARMv7E-M.
        unsafe {
            core::arch::asm!("uxtab16 {r}, {a}, {x}, ror #8", r = lateout(reg) r, a = in(reg) acc,
                x = in(reg) x, options(pure, nomem, nostack, preserves_flags));
        }
        r
    }
    #[cfg(not(target_arch = "arm"))]
    {
        lanes_add(acc, (x >> 8) & 0x00FF_00FF)
    }
}

/// `VSQRT.F32`: the square root, one FPU instruction (14 cycles) where `libm::sqrtf` is a
/// software routine of ≈ 50 instructions on the firmware. Both round correctly (IEEE 754 asks
/// it of a square root), so the results are the same bit for bit.
#[inline(always)]
pub fn sqrtf(x: f32) -> f32 {
    #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
    {
        // The FPU's register classes in `asm!` need the unstable `vfp2` target feature, so
        // the value passes through a core register and S15 is saved and restored around it.
        let r: u32;
        // SAFETY: register-only instructions of the Cortex-M4F's FPU (the hard-float targets
        // have it); S15 leaves as it came.
        unsafe {
            core::arch::asm!(
                "vmov {t}, s15",
                "vmov s15, {x}",
                "vsqrt.f32 s15, s15",
                "vmov {r}, s15",
                "vmov s15, {t}",
                t = out(reg) _, x = in(reg) x.to_bits(), r = lateout(reg) r,
                options(pure, nomem, nostack));
        }
        f32::from_bits(r)
    }
    #[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
    {
        libm::sqrtf(x)
    }
}

/// Two independent 16-bit additions modulo 2^16 (the plain form of the `UXTAB16` family).
#[cfg(not(target_arch = "arm"))]
fn lanes_add(a: u32, b: u32) -> u32 {
    let lo = (a as u16).wrapping_add(b as u16);
    let hi = ((a >> 16) as u16).wrapping_add((b >> 16) as u16);
    u32::from(lo) | u32::from(hi) << 16
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn lanes(v: u32) -> (i64, i64) {
        (
            i64::from(v as u16 as i16),
            i64::from((v >> 16) as u16 as i16),
        )
    }

    proptest! {
        #[test]
        fn dual_multiply_subtract_is_its_definition(a: u32, b: u32, acc: i32) {
            let ((al, ah), (bl, bh)) = (lanes(a), lanes(b));
            let want = al * bh - ah * bl;
            prop_assert_eq!(i64::from(smusdx(a, b)), want);
            prop_assert_eq!(smlsdx(a, b, acc), (i64::from(acc) + want) as i32);
        }

        #[test]
        fn rectify_is_max_zero_of_the_shift(x: i32) {
            prop_assert_eq!(i64::from(rectify_asr::<8>(x)), (i64::from(x) >> 8).max(0));
            prop_assert_eq!(i64::from(rectify_asr::<1>(x)), (i64::from(x) >> 1).max(0));
        }

        #[test]
        fn byte_lanes_accumulate_without_carry(acc: u32, x: u32) {
            let lane = |v: u32, i: u32| (v >> (16 * i)) & 0xFFFF;
            let (r, q) = (uxtab16(acc, x), uxtab16_ror8(acc, x));
            for i in 0..2 {
                let (b, b8) = ((x >> (16 * i)) & 0xFF, (x >> (16 * i + 8)) & 0xFF);
                prop_assert_eq!(lane(r, i), (lane(acc, i) + b) & 0xFFFF);
                prop_assert_eq!(lane(q, i), (lane(acc, i) + b8) & 0xFFFF);
            }
        }

        #[test]
        fn wide_multiply_keeps_the_top_bits(a: i32, b: u32) {
            let ((bl, bh), a) = (lanes(b), i64::from(a));
            prop_assert_eq!(i64::from(smulwb(a as i32, b)), (a * bl) >> 16);
            prop_assert_eq!(i64::from(smulwt(a as i32, b)), (a * bh) >> 16);
        }

        #[test]
        fn byte_select_by_compare(a: u32, b: u32, x: u32, y: u32) {
            let r = sel_ge(a, b, x, y);
            for i in 0..4 {
                let byte = |v: u32| (v >> (8 * i)) & 255;
                let want = if byte(a) >= byte(b) { byte(x) } else { byte(y) };
                prop_assert_eq!(byte(r), want);
            }
        }

        #[test]
        fn halfword_select_by_compare(a: u32, b: u32, x: u32, y: u32) {
            let r = sel_ge16(a, b, x, y);
            for i in 0..2 {
                let lane = |v: u32| (v >> (16 * i)) & 0xFFFF;
                let want = if lane(a) >= lane(b) { lane(x) } else { lane(y) };
                prop_assert_eq!(lane(r), want);
            }
        }

        #[test]
        fn dual_multiply_accumulate_is_its_definition(a: u32, b: u32, acc: i32) {
            let ((al, ah), (bl, bh)) = (lanes(a), lanes(b));
            prop_assert_eq!(smlad(a, b, acc), (i64::from(acc) + al * bl + ah * bh) as i32);
        }

        #[test]
        fn byte_saturating_subtract(a: u32, b: u32) {
            let r = uqsub8(a, b);
            for i in 0..4 {
                let (x, y) = ((a >> (8 * i)) & 255, (b >> (8 * i)) & 255);
                prop_assert_eq!((r >> (8 * i)) & 255, x.saturating_sub(y));
            }
        }
    }

    #[test]
    fn extreme_lanes() {
        // −32768·−32768 − (−32768)·32767: the largest magnitude, still an i32
        assert_eq!(smusdx(0x8000_8000, 0x8000_7FFF), 2_147_450_880);
        assert_eq!(rectify_asr::<8>(i32::MIN), 0);
        assert_eq!(rectify_asr::<8>(i32::MAX), (i32::MAX >> 8) as u32);
        assert_eq!(uqsub8(0x00FF_10FF, 0xFF01_2000), 0x00FE_00FF);
    }
}

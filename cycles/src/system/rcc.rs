//! Reset and clock control, power control and the flash interface: registers that hold what
//! was written, with their ready bits following their enables at once (RM0090 6.3 RCC, 5.4
//! PWR, 3.9 FLASH). The oscillators and PLLs lock instantly here; on the board HSE takes
//! ~2 ms and the PLL ~0.1 ms, which only lengthen the boot.

/// RCC, PWR and FLASH interface base addresses (RM0090 table 1).
pub const RCC_BASE: u32 = 0x4002_3800;
pub const PWR_BASE: u32 = 0x4000_7000;
pub const FLASH_IF_BASE: u32 = 0x4002_3C00;

/// HSE crystal (docs/hardware.md) and HSI frequencies, Hz.
pub const HSE_HZ: u64 = 25_000_000;
pub const HSI_HZ: u64 = 16_000_000;

/// RCC_CSR reset flags (RM0090 6.3.21).
pub const CSR_IWDGRSTF: u32 = 1 << 29;
pub const CSR_SFTRSTF: u32 = 1 << 28;
pub const CSR_PORRSTF: u32 = 1 << 27;
pub const CSR_PINRSTF: u32 = 1 << 26;

/// Register reset values that are not 0 (RM0090 6.3.1–6.3.2, 5.4.1).
pub fn reset_value(addr: u32) -> u32 {
    match addr {
        a if a == RCC_BASE => 0x0000_0083,        // CR: HSION, HSIRDY
        a if a == RCC_BASE + 0x04 => 0x2400_3010, // PLLCFGR
        a if a == RCC_BASE + 0x84 => 0x2000_3000, // PLLI2SCFGR
        a if a == RCC_BASE + 0x88 => 0x2400_3000, // PLLSAICFGR
        a if a == PWR_BASE => 0x0000_C000,        // CR: VOS scale 1
        _ => 0,
    }
}

/// The value a read returns, given the stored one: ready bits follow their enables.
pub fn read_fixup(addr: u32, stored: u32) -> u32 {
    let follow = |v: u32, pairs: &[(u32, u32)]| {
        pairs.iter().fold(v, |acc, &(on, rdy)| {
            if v & (1 << on) != 0 {
                acc | (1 << rdy)
            } else {
                acc & !(1 << rdy)
            }
        })
    };
    match addr.wrapping_sub(RCC_BASE) {
        // CR: HSI, HSE, PLL, PLLI2S, PLLSAI ready
        0x00 => follow(stored, &[(0, 1), (16, 17), (24, 25), (26, 27), (28, 29)]),
        // CFGR: SWS mirrors SW
        0x08 => (stored & !0xC) | ((stored & 3) << 2),
        // BDCR: LSERDY; CSR: LSIRDY
        0x70 => follow(stored, &[(0, 1)]),
        0x74 => follow(stored, &[(0, 1)]),
        _ => match addr.wrapping_sub(PWR_BASE) {
            // CSR: VOSRDY always, ODRDY, ODSWRDY follow CR's ODEN, ODSWEN (handled by caller)
            0x04 => stored | (1 << 14),
            _ => stored,
        },
    }
}

/// What a write stores, given the old value (RCC_CSR.RMVF clears the reset flags).
pub fn write_fixup(addr: u32, old: u32, value: u32) -> u32 {
    if addr == RCC_BASE + 0x74 && value & (1 << 24) != 0 {
        return value & 0x00FF_FFFF & !(1 << 24);
    }
    if addr == RCC_BASE + 0x74 {
        // reset flags are read-only
        return (value & 0x00FF_FFFF) | (old & 0xFF00_0000);
    }
    value
}

/// The clock tree as the RCC registers configure it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Clocks {
    pub sysclk: u64,
    pub hclk: u64,
    pub pclk1: u64,
    pub pclk2: u64,
}

/// Clocks from RCC_PLLCFGR and RCC_CFGR (RM0090 6.3.2, 6.3.3).
pub fn clocks(pllcfgr: u32, cfgr: u32) -> Clocks {
    let pll_in = if pllcfgr & (1 << 22) != 0 {
        HSE_HZ
    } else {
        HSI_HZ
    };
    let m = u64::from(pllcfgr & 0x3F).max(2);
    let n = u64::from((pllcfgr >> 6) & 0x1FF).max(2);
    let p = 2 * (u64::from((pllcfgr >> 16) & 3) + 1);
    let sysclk = match (cfgr >> 2) & 3 {
        1 => HSE_HZ,
        2 => pll_in / m * n / p,
        _ => HSI_HZ,
    };
    let hpre = (cfgr >> 4) & 0xF;
    let hdiv = if hpre < 8 {
        1
    } else {
        [2, 4, 8, 16, 64, 128, 256, 512][(hpre - 8) as usize]
    };
    let apb = |bits: u32| if bits < 4 { 1 } else { 1 << (bits - 3) };
    let hclk = sysclk / hdiv;
    Clocks {
        sysclk,
        hclk,
        pclk1: hclk / apb((cfgr >> 10) & 7),
        pclk2: hclk / apb((cfgr >> 13) & 7),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_robots_pll_gives_180_45_90_mhz() {
        // M=25, N=360, P=2, source HSE; SW=PLL, AHB/1, APB1/4, APB2/2
        let pllcfgr = 25 | 360 << 6 | 1 << 22;
        let cfgr = 2 | (2 << 2) | 0b101 << 10 | 0b100 << 13;
        let c = clocks(pllcfgr, cfgr);
        assert_eq!(c.sysclk, 180_000_000);
        assert_eq!(c.pclk1, 45_000_000);
        assert_eq!(c.pclk2, 90_000_000);
        assert_eq!(clocks(reset_value(RCC_BASE + 4), 0).sysclk, HSI_HZ);
    }

    #[test]
    fn ready_bits_follow_enables() {
        let cr = read_fixup(RCC_BASE, 1 << 16 | 1 << 24);
        assert_eq!(cr & (1 << 17 | 1 << 25), 1 << 17 | 1 << 25);
        assert_eq!(read_fixup(RCC_BASE, 0) & (1 << 17), 0);
        assert_eq!(read_fixup(RCC_BASE + 8, 2) & 0xC, 0x8, "SWS = PLL");
        let csr = write_fixup(RCC_BASE + 0x74, CSR_IWDGRSTF, 1);
        assert_eq!(
            csr & CSR_IWDGRSTF,
            CSR_IWDGRSTF,
            "flags survive a plain write"
        );
        assert_eq!(write_fixup(RCC_BASE + 0x74, CSR_IWDGRSTF, 1 << 24), 0);
    }
}

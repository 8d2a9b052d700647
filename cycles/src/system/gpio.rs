//! GPIO ports A–K (RM0090 8.4): mode, output type, pull, output data and BSRR as registers; IDR
//! is computed from them and from what the outside pulls low (the OV7670 on SCCB's SDA).

/// Base of port A; port n is at `GPIO_BASE + 0x400 n` (RM0090 table 1).
pub const GPIO_BASE: u32 = 0x4002_0000;
pub const PORTS: usize = 11;

/// Port indices used by the board model.
pub const PORT_A: usize = 0;
pub const PORT_E: usize = 4;

#[derive(Clone, Copy, Debug, Default)]
struct Port {
    moder: u32,
    otyper: u32,
    ospeedr: u32,
    pupdr: u32,
    odr: u32,
    lckr: u32,
    afr: [u32; 2],
}

#[derive(Clone, Debug)]
pub struct Gpio {
    ports: [Port; PORTS],
    /// Pins the outside world pulls low, per port.
    pub external_low: [u32; PORTS],
    /// Pins with an external pull-up on the board, per port (SCCB's lines).
    pub board_pull_up: [u32; PORTS],
}

impl Default for Gpio {
    fn default() -> Self {
        let mut ports = [Port::default(); PORTS];
        // reset values (RM0090 8.4.1, 8.4.4): the debug pins of ports A and B
        ports[0].moder = 0xA800_0000;
        ports[0].pupdr = 0x6400_0000;
        ports[0].ospeedr = 0x0C00_0000;
        ports[1].moder = 0x0000_0280;
        ports[1].pupdr = 0x0000_0100;
        ports[1].ospeedr = 0x0000_00C0;
        Gpio {
            ports,
            external_low: [0; PORTS],
            board_pull_up: [0; PORTS],
        }
    }
}

impl Gpio {
    /// The 2-bit mode of a pin: 0 input, 1 output, 2 alternate, 3 analog.
    pub fn mode(&self, port: usize, pin: u32) -> u32 {
        (self.ports[port].moder >> (2 * pin)) & 3
    }

    /// The alternate function number of a pin.
    pub fn alternate(&self, port: usize, pin: u32) -> u32 {
        (self.ports[port].afr[(pin / 8) as usize] >> (4 * (pin % 8))) & 0xF
    }

    /// Whether the MCU releases the pin (input, or open drain at 1) or drives it high: the
    /// level it leaves on an open-drain bus.
    pub fn released_or_high(&self, port: usize, pin: u32) -> bool {
        let p = &self.ports[port];
        self.mode(port, pin) != 1 || p.odr & (1 << pin) != 0
    }

    fn idr(&self, port: usize) -> u32 {
        let p = &self.ports[port];
        let mut v = 0;
        for pin in 0..16 {
            let m = 1u32 << pin;
            let pull = (p.pupdr >> (2 * pin)) & 3;
            let floating_high = pull == 1 || self.board_pull_up[port] & m != 0;
            let level = match self.mode(port, pin) {
                1 if p.otyper & m == 0 => p.odr & m != 0,
                1 => p.odr & m != 0 && self.external_low[port] & m == 0,
                0 => floating_high && self.external_low[port] & m == 0,
                _ => false,
            };
            if level {
                v |= m;
            }
        }
        v
    }

    /// Reads register `offset` of `port`.
    pub fn read(&self, port: usize, offset: u32) -> u32 {
        let p = &self.ports[port];
        match offset {
            0x00 => p.moder,
            0x04 => p.otyper,
            0x08 => p.ospeedr,
            0x0C => p.pupdr,
            0x10 => self.idr(port),
            0x14 => p.odr,
            0x1C => p.lckr,
            0x20 => p.afr[0],
            0x24 => p.afr[1],
            _ => 0, // BSRR reads 0
        }
    }

    /// Writes register `offset` of `port`.
    pub fn write(&mut self, port: usize, offset: u32, value: u32) {
        let p = &mut self.ports[port];
        match offset {
            0x00 => p.moder = value,
            0x04 => p.otyper = value & 0xFFFF,
            0x08 => p.ospeedr = value,
            0x0C => p.pupdr = value,
            0x14 => p.odr = value & 0xFFFF,
            0x18 => p.odr = (p.odr | (value & 0xFFFF)) & !(value >> 16) | (value & 0xFFFF),
            0x1C => p.lckr = value,
            0x20 => p.afr[0] = value,
            0x24 => p.afr[1] = value,
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_drain_pin_reads_the_wired_and() {
        let mut g = Gpio::default();
        g.board_pull_up[PORT_E] = 1 << 2;
        // PE2 open-drain output released (ODR 1)
        g.write(PORT_E, 0x00, 1 << 4);
        g.write(PORT_E, 0x04, 1 << 2);
        g.write(PORT_E, 0x18, 1 << 2);
        assert_ne!(g.read(PORT_E, 0x10) & (1 << 2), 0);
        g.external_low[PORT_E] = 1 << 2;
        assert_eq!(g.read(PORT_E, 0x10) & (1 << 2), 0, "the slave pulls it low");
        g.external_low[PORT_E] = 0;
        g.write(PORT_E, 0x18, 1 << 18); // BSRR reset bit 2
        assert_eq!(g.read(PORT_E, 0x10) & (1 << 2), 0);
        assert!(!g.released_or_high(PORT_E, 2));
    }

    #[test]
    fn bsrr_set_wins_over_reset_and_afr_reads_back() {
        let mut g = Gpio::default();
        g.write(PORT_A, 0x18, 1 << 3 | 1 << 19);
        assert_eq!(g.read(PORT_A, 0x14) & (1 << 3), 1 << 3);
        g.write(PORT_A, 0x24, 0);
        assert_eq!(g.alternate(PORT_A, 8), 0);
        g.write(PORT_A, 0x24, 5);
        assert_eq!(g.alternate(PORT_A, 8), 5);
    }
}

//! The OV7670 as its SCCB control bus sees it: a slave at write id 0x42 / read id 0x43 that
//! acknowledges its id, register address and data, stores what is written and answers reads
//! (OmniVision "SCCB Functional Specification" 3.x; OV7670 datasheet, register table). COM7
//! bit 7 resets the registers to their defaults. The sensor answers only while it has a
//! clock (XCLK) and is present.
//!
//! The bus is two open-drain lines: the responder watches the levels the GPIO model computes
//! and says whether it pulls SDA low.

/// 8-bit write id of the OV7670.
pub const WRITE_ID: u8 = 0x42;
/// Product id (PID, register 0x0A) and version (VER, 0x0B) of the OV7670.
pub const PID: u8 = 0x76;
pub const VER: u8 = 0x73;
const COM7: u8 = 0x12;

/// Register defaults that are not 0 (OV7670 datasheet, "Device control register list").
const DEFAULTS: &[(u8, u8)] = &[
    (0x00, 0x00),
    (0x01, 0x80), // BLUE
    (0x02, 0x80), // RED
    (0x0A, PID),
    (0x0B, VER),
    (0x11, 0x80), // CLKRC
    (0x1C, 0x7F), // MIDH
    (0x1D, 0xA2), // MIDL
    (0x3A, 0x0D), // TSLB
    (0x3D, 0x88), // COM13
];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    Idle,
    /// Receiving byte `index` of the transaction; `bits` sampled so far.
    Receive {
        index: u8,
        bits: u8,
        byte: u8,
    },
    /// Pulling SDA low for the acknowledge clock after byte `index`.
    Ack {
        index: u8,
    },
    /// Sending a register's bits; `sent` are on the bus.
    Send {
        sent: u8,
        byte: u8,
    },
    /// The master's acknowledge clock after a sent byte.
    MasterAck,
    /// Not addressed: wait for the next START.
    Ignore,
}

/// The sensor's control side.
#[derive(Clone, Debug)]
pub struct Ov7670 {
    regs: [u8; 256],
    pointer: u8,
    read: bool,
    phase: Phase,
    scl: bool,
    sda: bool,
    pull_low: bool,
    /// Register writes received (the reset write included), for tests and reports.
    pub writes: u32,
}

impl Default for Ov7670 {
    fn default() -> Self {
        let mut s = Ov7670 {
            regs: [0; 256],
            pointer: 0,
            read: false,
            phase: Phase::Idle,
            scl: true,
            sda: true,
            pull_low: false,
            writes: 0,
        };
        s.reset_registers();
        s
    }
}

impl Ov7670 {
    fn reset_registers(&mut self) {
        self.regs = [0; 256];
        for &(r, v) in DEFAULTS {
            self.regs[usize::from(r)] = v;
        }
    }

    pub fn register(&self, reg: u8) -> u8 {
        self.regs[usize::from(reg)]
    }

    /// Whether the sensor pulls SDA low now.
    pub fn pulls_sda_low(&self) -> bool {
        self.pull_low
    }

    /// The bus lines changed (or may have): SCL as driven by the master, and SDA as the master
    /// leaves it (true = released). `alive`: the sensor is present and clocked.
    pub fn bus(&mut self, scl: bool, master_sda: bool, alive: bool) {
        if !alive {
            self.phase = Phase::Idle;
            self.pull_low = false;
            self.scl = scl;
            self.sda = master_sda;
            return;
        }
        let sda = master_sda && !self.pull_low;
        if scl && self.scl && sda != self.sda {
            // SDA moved while SCL is high: START (falling) or STOP (rising)
            self.pull_low = false;
            self.phase = if sda {
                Phase::Idle
            } else {
                Phase::Receive {
                    index: 0,
                    bits: 0,
                    byte: 0,
                }
            };
        } else if scl && !self.scl {
            self.rising(sda);
        } else if !scl && self.scl {
            self.falling();
        }
        self.scl = scl;
        self.sda = master_sda && !self.pull_low;
    }

    /// SCL rises: the receiver samples SDA.
    fn rising(&mut self, sda: bool) {
        match self.phase {
            Phase::Receive { index, bits, byte } if bits < 8 => {
                self.phase = Phase::Receive {
                    index,
                    bits: bits + 1,
                    byte: (byte << 1) | u8::from(sda),
                };
            }
            // the master answers "not acknowledge" (SCCB reads are one byte); an
            // acknowledge would ask for the next register
            Phase::MasterAck if !sda => {
                self.pointer = self.pointer.wrapping_add(1);
                self.phase = Phase::Send {
                    sent: 0,
                    byte: self.regs[usize::from(self.pointer)],
                };
            }
            Phase::MasterAck => self.phase = Phase::Ignore,
            _ => {}
        }
    }

    /// SCL falls: the slave may change SDA.
    fn falling(&mut self) {
        match self.phase {
            Phase::Receive {
                index,
                bits: 8,
                byte,
            } => {
                let ack = if index == 0 {
                    self.read = byte & 1 != 0;
                    byte & 0xFE == WRITE_ID
                } else {
                    self.byte(index, byte);
                    true
                };
                self.pull_low = ack;
                self.phase = if ack {
                    Phase::Ack { index }
                } else {
                    Phase::Ignore
                };
            }
            Phase::Ack { index } => {
                self.pull_low = false;
                self.phase = if index == 0 && self.read {
                    let byte = self.regs[usize::from(self.pointer)];
                    self.pull_low = byte & 0x80 == 0;
                    Phase::Send { sent: 1, byte }
                } else {
                    Phase::Receive {
                        index: index.saturating_add(1),
                        bits: 0,
                        byte: 0,
                    }
                };
            }
            Phase::Send { sent, byte } if sent < 8 => {
                self.pull_low = byte & (0x80 >> sent) == 0;
                self.phase = Phase::Send {
                    sent: sent + 1,
                    byte,
                };
            }
            Phase::Send { .. } => {
                self.pull_low = false;
                self.phase = Phase::MasterAck;
            }
            _ => {}
        }
    }

    /// Byte `index` ≥ 1 of a write transaction: the register address, then data.
    fn byte(&mut self, index: u8, byte: u8) {
        if index == 1 {
            self.pointer = byte;
            return;
        }
        self.writes += 1;
        if self.pointer == COM7 && byte & 0x80 != 0 {
            self.reset_registers();
        } else {
            self.regs[usize::from(self.pointer)] = byte;
        }
        self.pointer = self.pointer.wrapping_add(1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bit-banging master over the responder, as `src/camera/sccb.rs` drives the pins.
    struct Master<'a> {
        dev: &'a mut Ov7670,
        scl: bool,
        sda: bool,
    }

    impl Master<'_> {
        fn set(&mut self, scl: bool, sda: bool) {
            self.scl = scl;
            self.sda = sda;
            self.dev.bus(scl, sda, true);
        }
        fn line(&self) -> bool {
            self.sda && !self.dev.pulls_sda_low()
        }
        fn start(&mut self) {
            self.set(true, true);
            self.set(true, false);
            self.set(false, false);
        }
        fn stop(&mut self) {
            self.set(false, false);
            self.set(true, false);
            self.set(true, true);
        }
        fn bit_out(&mut self, b: bool) {
            self.set(false, b);
            self.set(true, b);
            self.set(false, b);
        }
        fn bit_in(&mut self) -> bool {
            self.set(false, true);
            self.set(true, true);
            let b = self.line();
            self.set(false, true);
            b
        }
        fn write_byte(&mut self, byte: u8) -> bool {
            for i in (0..8).rev() {
                self.bit_out(byte & (1 << i) != 0);
            }
            !self.bit_in()
        }
        fn read_byte(&mut self) -> u8 {
            let mut v = 0;
            for _ in 0..8 {
                v = (v << 1) | u8::from(self.bit_in());
            }
            self.bit_out(true);
            v
        }
        fn write(&mut self, reg: u8, val: u8) -> bool {
            self.start();
            let ok = self.write_byte(WRITE_ID) && self.write_byte(reg) && self.write_byte(val);
            self.stop();
            ok
        }
        fn read(&mut self, reg: u8) -> Option<u8> {
            self.start();
            let ok = self.write_byte(WRITE_ID) && self.write_byte(reg);
            self.stop();
            if !ok {
                return None;
            }
            self.start();
            let v = self.write_byte(WRITE_ID | 1).then(|| self.read_byte());
            self.stop();
            v
        }
    }

    #[test]
    fn id_reads_and_writes_round_trip() {
        let mut dev = Ov7670::default();
        let mut m = Master {
            dev: &mut dev,
            scl: true,
            sda: true,
        };
        assert_eq!(m.read(0x0A), Some(PID));
        assert_eq!(m.read(0x0B), Some(VER));
        assert!(m.write(0x40, 0xD0));
        assert_eq!(m.read(0x40), Some(0xD0));
        assert!(m.write(COM7, 0x80), "reset");
        assert_eq!(m.read(0x40), Some(0x00));
        assert_eq!(m.read(0x1D), Some(0xA2));
        assert_eq!(m.dev.writes, 2);
    }

    #[test]
    fn another_id_is_not_acknowledged_and_a_dead_sensor_never_answers() {
        let mut dev = Ov7670::default();
        let mut m = Master {
            dev: &mut dev,
            scl: true,
            sda: true,
        };
        m.start();
        assert!(!m.write_byte(0x60));
        m.stop();
        assert_eq!(
            m.read(0x0A),
            Some(PID),
            "the bus recovers at the next START"
        );
        let mut dev = Ov7670::default();
        dev.bus(true, false, false);
        dev.bus(false, false, false);
        assert!(!dev.pulls_sda_low());
    }
}

//! Static memory use of a firmware ELF, per region of the STM32F427 map.

use std::fmt;

use crate::elf::{self, Section, SectionKind};
use crate::error::Error;
use crate::memory::{CCM, FLASH, SRAM};

/// Static use of one RAM region (CCM or SRAM), in bytes.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RegionUse {
    pub name: &'static str,
    pub base: u32,
    pub capacity: u32,
    /// Initialised data (PROGBITS run in RAM: .data and the like).
    pub data: u32,
    /// Zero-initialised (NOBITS: .bss and the like).
    pub bss: u32,
    /// Not initialised (NOBITS named `.uninit*`).
    pub uninit: u32,
    /// Code placed in RAM (executable PROGBITS run from RAM, e.g. a `.ramfunc`).
    pub code: u32,
}

impl RegionUse {
    pub fn total(&self) -> u32 {
        self.data + self.bss + self.uninit + self.code
    }
}

/// Flash use, in bytes.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FlashUse {
    /// Executable sections (.vector_table counts as read-only data).
    pub text: u32,
    /// Read-only data: .rodata, .vector_table, ...
    pub rodata: u32,
    /// Initial images of sections that run from RAM (.data's load image).
    pub data_load: u32,
}

impl FlashUse {
    pub fn total(&self) -> u32 {
        self.text + self.rodata + self.data_load
    }
}

/// The static RAM and flash report of an ELF. Does not include the stack, which is not a section
/// (measure it with [`crate::Machine::high_water`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RamReport {
    /// CCM, then SRAM.
    pub regions: Vec<RegionUse>,
    pub flash: FlashUse,
    /// Every allocated section, for detail.
    pub sections: Vec<Section>,
    /// Allocated sections outside flash, CCM and SRAM (names), should there be any.
    pub elsewhere: Vec<String>,
}

impl RamReport {
    pub fn from_elf(data: &[u8]) -> Result<RamReport, Error> {
        Ok(RamReport::from_sections(elf::parse(data)?.sections))
    }

    pub(crate) fn from_sections(sections: Vec<Section>) -> RamReport {
        let mut regions = vec![
            RegionUse {
                name: "CCM",
                base: CCM.start,
                capacity: CCM.end - CCM.start,
                ..Default::default()
            },
            RegionUse {
                name: "SRAM",
                base: SRAM.start,
                capacity: SRAM.end - SRAM.start,
                ..Default::default()
            },
        ];
        let mut flash = FlashUse::default();
        let mut elsewhere = Vec::new();
        for s in &sections {
            if FLASH.contains(&s.addr) {
                match s.kind {
                    SectionKind::Text => flash.text += s.size,
                    _ => flash.rodata += s.size,
                }
                continue;
            }
            let region = if CCM.contains(&s.addr) {
                &mut regions[0]
            } else if SRAM.contains(&s.addr) {
                &mut regions[1]
            } else {
                elsewhere.push(s.name.clone());
                continue;
            };
            match s.kind {
                SectionKind::Text => region.code += s.size,
                SectionKind::Data => region.data += s.size,
                SectionKind::Bss => region.bss += s.size,
                SectionKind::Uninit => region.uninit += s.size,
            }
            if matches!(s.kind, SectionKind::Text | SectionKind::Data) && FLASH.contains(&s.lma) {
                flash.data_load += s.size;
            }
        }
        RamReport {
            regions,
            flash,
            sections,
            elsewhere,
        }
    }

    /// All static RAM (every region's data + bss + uninit + code).
    pub fn static_ram(&self) -> u32 {
        self.regions.iter().map(RegionUse::total).sum()
    }

    pub fn region(&self, name: &str) -> Option<&RegionUse> {
        self.regions.iter().find(|r| r.name == name)
    }

    /// Static use of the region `name` ("CCM", "SRAM"), bytes; 0 for a region with nothing.
    pub fn used(&self, name: &str) -> u32 {
        self.region(name).map_or(0, RegionUse::total)
    }
}

impl fmt::Display for RamReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "| region | data | bss | uninit | code | total | capacity |"
        )?;
        writeln!(f, "|---|---:|---:|---:|---:|---:|---:|")?;
        for r in &self.regions {
            writeln!(
                f,
                "| {} | {} | {} | {} | {} | {} | {} |",
                r.name,
                r.data,
                r.bss,
                r.uninit,
                r.code,
                r.total(),
                r.capacity
            )?;
        }
        writeln!(
            f,
            "| flash | text {} | rodata {} | .data image {} | | {} | {} |",
            self.flash.text,
            self.flash.rodata,
            self.flash.data_load,
            self.flash.total(),
            FLASH.end - FLASH.start
        )
    }
}

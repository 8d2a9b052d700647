//! Reading a thumbv7em ELF: what to load where, the symbol table and the allocated sections.

use std::collections::HashMap;
use std::ops::Range;

use object::elf;
use object::read::elf::{ElfFile32, FileHeader, ProgramHeader, SectionHeader};
use object::{Endianness, Object, ObjectSymbol, SymbolKind};

use crate::error::Error;
use crate::memory::{CCM, SRAM};

/// Bytes to place at `addr`, followed by `zeros` zero bytes (the NOBITS tail of a segment).
pub struct Chunk {
    pub what: String,
    pub addr: u32,
    pub bytes: Vec<u8>,
    pub zeros: u32,
}

/// One symbol. `value` is the raw st_value (bit 0 set for Thumb functions).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Symbol {
    pub value: u32,
    pub size: u32,
    pub function: bool,
}

impl Symbol {
    /// The address: for a function, the Thumb bit cleared; data symbols are left as they are
    /// (a byte-sized static may sit at an odd address).
    pub fn address(&self) -> u32 {
        if self.function {
            self.value & !1
        } else {
            self.value
        }
    }
}

/// What an allocated section holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SectionKind {
    /// Executable code.
    Text,
    /// Read-only or initialised data (PROGBITS, not executable).
    Data,
    /// Zero-initialised (NOBITS), except `.uninit*`.
    Bss,
    /// NOBITS named `.uninit*` (cortex-m-rt's `#[link_section = ".uninit"]`): not initialised.
    Uninit,
}

/// An SHF_ALLOC section.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Section {
    pub name: String,
    /// Run address (VMA).
    pub addr: u32,
    /// Load address (LMA): where the initial image sits (flash for .data); = `addr` otherwise.
    pub lma: u32,
    pub size: u32,
    pub kind: SectionKind,
}

pub struct Image {
    pub chunks: Vec<Chunk>,
    pub symbols: HashMap<String, Symbol>,
    pub sections: Vec<Section>,
}

impl Image {
    /// The call stack's region, `_stack_end.._stack_start` (cortex-m-rt and this project's
    /// memory.x define both; without `_stack_end`, from the start of the CCM or SRAM holding
    /// `_stack_start`); `None` without `_stack_start`.
    pub fn stack(&self) -> Option<Range<u32>> {
        let top = self.symbols.get("_stack_start")?.value;
        let bottom = self.symbols.get("_stack_end").map(|s| s.value).or_else(|| {
            [CCM, SRAM]
                .into_iter()
                .find(|r| r.start < top && top <= r.end)
                .map(|r| r.start)
        });
        Some(bottom.unwrap_or(top)..top)
    }
}

fn bad(e: impl std::fmt::Display) -> Error {
    Error::Elf(e.to_string())
}

fn u32_of(v: u64, what: &str) -> Result<u32, Error> {
    u32::try_from(v).map_err(|_| Error::Elf(format!("{what} {v:#x} does not fit 32 bits")))
}

/// Parses a 32-bit little-endian ARM ELF.
pub fn parse(data: &[u8]) -> Result<Image, Error> {
    let file = ElfFile32::<Endianness>::parse(data).map_err(bad)?;
    let endian = file.endian();
    if file.elf_header().e_machine(endian) != elf::EM_ARM || !file.is_little_endian() {
        return Err(Error::Elf("not a little-endian ARM ELF".into()));
    }

    // Segments: the run image at p_vaddr (.data initialised, .bss zero), and for .data also its
    // initial image at p_paddr in flash, as the flashed chip holds it.
    let mut chunks = Vec::new();
    let phdrs = file.elf_program_headers();
    for (i, ph) in phdrs.iter().enumerate() {
        if ph.p_type(endian) != elf::PT_LOAD || ph.p_memsz(endian) == 0 {
            continue;
        }
        let bytes = ph
            .data(endian, data)
            .map_err(|()| bad("segment out of file"))?;
        let vaddr = ph.p_vaddr(endian);
        let paddr = ph.p_paddr(endian);
        let memsz = ph.p_memsz(endian);
        let zeros = memsz.saturating_sub(bytes.len() as u32);
        chunks.push(Chunk {
            what: format!("segment {i}"),
            addr: vaddr,
            bytes: bytes.to_vec(),
            zeros,
        });
        if paddr != vaddr && !bytes.is_empty() {
            chunks.push(Chunk {
                what: format!("segment {i} load image"),
                addr: paddr,
                bytes: bytes.to_vec(),
                zeros: 0,
            });
        }
    }

    let lma_of = |addr: u32| {
        phdrs
            .iter()
            .filter(|ph| ph.p_type(endian) == elf::PT_LOAD && ph.p_filesz(endian) > 0)
            .find(|ph| {
                let v = ph.p_vaddr(endian);
                addr >= v && addr - v < ph.p_filesz(endian)
            })
            .map_or(addr, |ph| ph.p_paddr(endian) + (addr - ph.p_vaddr(endian)))
    };

    let table = file.elf_section_table();
    let mut sections = Vec::new();
    for sh in table.iter() {
        let flags = sh.sh_flags(endian);
        if flags & elf::SHF_ALLOC == 0 || sh.sh_size(endian) == 0 {
            continue;
        }
        let name = table.section_name(endian, sh).map_err(bad)?;
        let name = String::from_utf8_lossy(name).into_owned();
        let addr = sh.sh_addr(endian);
        let nobits = sh.sh_type(endian) == elf::SHT_NOBITS;
        let kind = if nobits && name.starts_with(".uninit") {
            SectionKind::Uninit
        } else if nobits {
            SectionKind::Bss
        } else if flags & elf::SHF_EXECINSTR != 0 {
            SectionKind::Text
        } else {
            SectionKind::Data
        };
        let lma = if nobits { addr } else { lma_of(addr) };
        sections.push(Section {
            name,
            addr,
            lma,
            size: sh.sh_size(endian),
            kind,
        });
    }

    let mut symbols: HashMap<String, Symbol> = HashMap::new();
    for sym in file.symbols() {
        let Ok(name) = sym.name() else { continue };
        if name.is_empty() || sym.is_undefined() {
            continue;
        }
        let s = Symbol {
            value: u32_of(sym.address(), "symbol value")?,
            size: u32_of(sym.size(), "symbol size")?,
            function: sym.kind() == SymbolKind::Text,
        };
        // Prefer a global definition over a local one of the same name.
        match symbols.get(name) {
            Some(_) if !sym.is_global() => {}
            _ => {
                symbols.insert(name.to_owned(), s);
            }
        }
    }

    Ok(Image {
        chunks,
        symbols,
        sections,
    })
}

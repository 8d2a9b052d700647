//! Plumbing both emulated chips share (the call-level [`crate::Machine`] and the virtual board
//! [`crate::system::Board`]): unicorn's Cortex-M4 with the STM32F427's memories, the bytes of an
//! instruction for the decoder, and plain register pages.

use std::ops::Range;

use unicorn_engine::{Arch, ArmCpuModel, Mode, Prot, Unicorn};

use crate::decode::{Decoded, Decoder};
use crate::error::Error;
use crate::memory::{CCM, FLASH, SRAM};

pub fn emu(e: unicorn_engine::uc_error) -> Error {
    Error::Emulator(format!("{e:?}"))
}

/// A Cortex-M4 with flash (read/execute), CCM (data only) and SRAM mapped.
pub fn cortex_m4<D>(data: D) -> Result<Unicorn<'static, D>, Error> {
    let mut uc =
        Unicorn::new_with_data(Arch::ARM, Mode::THUMB | Mode::MCLASS, data).map_err(emu)?;
    uc.ctl_set_cpu_model(ArmCpuModel::CORTEX_M4 as i32)
        .map_err(emu)?;
    let len = |r: &Range<u32>| u64::from(r.end - r.start);
    uc.mem_map(FLASH.start.into(), len(&FLASH), Prot::READ | Prot::EXEC)
        .map_err(emu)?;
    uc.mem_map(CCM.start.into(), len(&CCM), Prot::READ | Prot::WRITE)
        .map_err(emu)?;
    uc.mem_map(SRAM.start.into(), len(&SRAM), Prot::ALL)
        .map_err(emu)?;
    Ok(uc)
}

/// Loads an ELF image's chunks at their addresses (zero-filled parts included); a chunk outside
/// flash, CCM and SRAM is an error.
pub fn load<D>(uc: &mut Unicorn<'_, D>, chunks: &[crate::elf::Chunk]) -> Result<(), Error> {
    for c in chunks {
        let len = c.bytes.len() as u32 + c.zeros;
        if !crate::memory::loadable(c.addr, len) {
            return Err(Error::Load {
                what: c.what.clone(),
                addr: c.addr,
                len,
            });
        }
        uc.mem_write(c.addr.into(), &c.bytes).map_err(emu)?;
        if c.zeros > 0 {
            let end = c.addr + c.bytes.len() as u32;
            uc.mem_write(end.into(), &vec![0; c.zeros as usize])
                .map_err(emu)?;
        }
    }
    Ok(())
}

/// Reads memory; an unmapped address is [`Error::Unmapped`].
pub fn read<D>(uc: &Unicorn<'_, D>, addr: u32, len: usize) -> Result<Vec<u8>, Error> {
    uc.mem_read_as_vec(addr.into(), len)
        .map_err(|_| Error::Unmapped {
            access: crate::error::Access::Read,
            addr,
            pc: 0,
        })
}

/// Reads a little-endian word.
pub fn read_u32<D>(uc: &Unicorn<'_, D>, addr: u32) -> Result<u32, Error> {
    let b = read(uc, addr, 4)?;
    Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Fills `range` (word aligned) with `pattern`, for a stack's high-water mark.
pub fn paint<D>(uc: &mut Unicorn<'_, D>, range: Range<u32>, pattern: u32) -> Result<(), Error> {
    let words = (range.end.saturating_sub(range.start) / 4) as usize;
    let bytes: Vec<u8> = std::iter::repeat_n(pattern.to_le_bytes(), words)
        .flatten()
        .collect();
    uc.mem_write(range.start.into(), &bytes).map_err(emu)
}

/// Bytes of `range` (a downward-growing stack painted with `pattern`) that were written: from
/// the lowest changed word to the end of the range.
pub fn high_water<D>(uc: &Unicorn<'_, D>, range: Range<u32>, pattern: u32) -> Result<u32, Error> {
    let len = range.end.saturating_sub(range.start) as usize & !3;
    let bytes = read(uc, range.start, len)?;
    let first = bytes
        .chunks_exact(4)
        .position(|w| w != pattern.to_le_bytes())
        .map_or(len as u32, |i| 4 * i as u32);
    Ok(len as u32 - first)
}

/// Decodes the instruction at `addr` (`size` bytes as unicorn reports it), reading up to 18
/// bytes: an IT instruction and the four it covers.
pub fn decode_at<D>(uc: &Unicorn<'_, D>, decoder: &Decoder, addr: u64, size: u32) -> Decoded {
    let mut buf = [0u8; 18];
    let bytes = match uc.mem_read(addr, &mut buf) {
        Ok(()) => &buf[..],
        Err(_) => match uc.mem_read(addr, &mut buf[..size as usize]) {
            Ok(()) => &buf[..size as usize],
            Err(_) => &[][..],
        },
    };
    decoder.decode(addr as u32, bytes, size as u8)
}

/// A page of registers that hold what is written (little-endian, any access size).
#[derive(Clone, Debug)]
pub struct RegisterPage(Vec<u8>);

impl RegisterPage {
    pub fn new(len: usize) -> RegisterPage {
        RegisterPage(vec![0; len])
    }

    pub fn read(&self, offset: u64, size: usize) -> u64 {
        let at = offset as usize;
        let mut v = [0u8; 8];
        let n = size.min(8).min(self.0.len().saturating_sub(at));
        if let Some(bytes) = self.0.get(at..at + n) {
            v[..n].copy_from_slice(bytes);
        }
        u64::from_le_bytes(v)
    }

    pub fn write(&mut self, offset: u64, size: usize, value: u64) {
        let at = offset as usize;
        let n = size.min(8).min(self.0.len().saturating_sub(at));
        if let Some(bytes) = self.0.get_mut(at..at + n) {
            bytes.copy_from_slice(&value.to_le_bytes()[..n]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn register_page_holds_what_is_written_at_any_size_and_clips_at_its_end() {
        let mut p = RegisterPage::new(8);
        p.write(0, 4, 0x1122_3344);
        p.write(5, 1, 0xAB);
        assert_eq!(p.read(0, 4), 0x1122_3344);
        assert_eq!(p.read(1, 2), 0x2233);
        assert_eq!(p.read(4, 4), 0x0000_AB00);
        p.write(6, 4, 0xFFFF_FFFF);
        assert_eq!(p.read(6, 4), 0xFFFF, "two bytes left in the page");
        assert_eq!(p.read(100, 4), 0);
        p.write(100, 4, 1); // ignored
    }
}

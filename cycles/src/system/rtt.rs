//! The host side of RTT, as a debug probe does it: find the SEGGER control block
//! (`_SEGGER_RTT`: the id "SEGGER RTT", the channel counts, then 24-byte channel descriptors
//! name, buffer, size, write, read, flags) and move each up channel's new bytes out by
//! advancing its read offset; bytes typed for down channel 0 go in by advancing its write
//! offset, as far as the target has read.

/// Memory access the reader needs.
pub trait Memory {
    fn read(&self, addr: u32, len: usize) -> Option<Vec<u8>>;
    fn write_u32(&mut self, addr: u32, value: u32) -> bool;
    fn write(&mut self, addr: u32, bytes: &[u8]) -> bool;

    fn read_u32(&self, addr: u32) -> Option<u32> {
        let b = self.read(addr, 4)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
}

const ID: &[u8] = b"SEGGER RTT";
const HEADER: u32 = 24;
const CHANNEL: u32 = 24;
/// Offsets in a channel descriptor of the write and read offsets.
const WRITE_OFFSET: u32 = 12;
const READ_OFFSET: u32 = 16;

/// A channel descriptor's words (the flags are not needed).
struct Descriptor {
    name: u32,
    buffer: u32,
    size: u32,
    write: u32,
    read: u32,
}

impl Descriptor {
    fn read(mem: &impl Memory, at: u32) -> Option<Descriptor> {
        let d = mem.read(at, CHANNEL as usize)?;
        let w = |k: usize| u32::from_le_bytes([d[4 * k], d[4 * k + 1], d[4 * k + 2], d[4 * k + 3]]);
        Some(Descriptor {
            name: w(0),
            buffer: w(1),
            size: w(2),
            write: w(3),
            read: w(4),
        })
    }
}

/// One up channel's text so far.
#[derive(Clone, Debug, Default)]
pub struct Channel {
    pub name: String,
    pub text: String,
    /// What each poll that found new bytes read: its time (the caller's clock) and the length
    /// of the text it appended, in order (the pieces a probe's host tool receives).
    pub reads: Vec<(u64, usize)>,
}

/// The reader's state: the block address and the channels seen.
#[derive(Clone, Debug, Default)]
pub struct Rtt {
    pub block: u32,
    pub channels: Vec<Channel>,
    /// Bytes typed for down channel 0, not yet in the target's buffer.
    pub typed: std::collections::VecDeque<u8>,
}

impl Rtt {
    pub fn new(block: u32) -> Rtt {
        Rtt {
            block,
            channels: Vec::new(),
            typed: std::collections::VecDeque::new(),
        }
    }

    /// Types `bytes` into down channel 0 (they reach the target on the next polls, as its
    /// buffer frees up).
    pub fn type_in(&mut self, bytes: &[u8]) {
        self.typed.extend(bytes);
    }

    /// Moves typed bytes into down channel 0's ring, as much as it has room for (a ring of
    /// `size` holds `size − 1`).
    fn deliver(&mut self, mem: &mut impl Memory) {
        if self.typed.is_empty() {
            return;
        }
        let downs = mem
            .read_u32(self.block.wrapping_add(20))
            .unwrap_or(0)
            .min(16);
        if downs == 0 {
            return;
        }
        // down descriptors follow all `MaxNumUpBuffers` up descriptors
        let at = self.block.wrapping_add(HEADER + self.max_up(mem) * CHANNEL);
        let Some(d) = Descriptor::read(mem, at) else {
            return;
        };
        let (buffer, size, mut write, read) = (d.buffer, d.size, d.write, d.read);
        if buffer == 0 || size < 2 || write >= size || read >= size {
            return;
        }
        while (write + 1) % size != read {
            let Some(b) = self.typed.pop_front() else {
                break;
            };
            if !mem.write(buffer.wrapping_add(write), &[b]) {
                return;
            }
            write = (write + 1) % size;
        }
        mem.write_u32(at.wrapping_add(WRITE_OFFSET), write);
    }

    /// `MaxNumUpBuffers` of the control block (at most 16).
    fn max_up(&self, mem: &impl Memory) -> u32 {
        mem.read_u32(self.block.wrapping_add(16))
            .unwrap_or(0)
            .min(16)
    }

    /// Moves every up channel's new bytes into its text, noting the read at time `now`;
    /// nothing while the block is not initialised (before `rtt_init!` ran).
    pub fn poll(&mut self, mem: &mut impl Memory, now: u64) {
        let Some(id) = mem.read(self.block, ID.len()) else {
            return;
        };
        if id != ID {
            return;
        }
        self.deliver(mem);
        for i in 0..self.max_up(mem) {
            let at = self.block + HEADER + i * CHANNEL;
            let Some(d) = Descriptor::read(mem, at) else {
                return;
            };
            let (name, buffer, size, write, read) = (d.name, d.buffer, d.size, d.write, d.read);
            if self.channels.len() <= i as usize {
                self.channels.push(Channel {
                    name: c_string(mem, name),
                    text: String::new(),
                    reads: Vec::new(),
                });
            }
            if buffer == 0 || size == 0 || write >= size || read >= size || write == read {
                continue;
            }
            let bytes = if write > read {
                mem.read(buffer + read, (write - read) as usize)
            } else {
                let mut a = mem
                    .read(buffer + read, (size - read) as usize)
                    .unwrap_or_default();
                a.extend(mem.read(buffer, write as usize).unwrap_or_default());
                Some(a)
            };
            if let Some(b) = bytes {
                let channel = &mut self.channels[i as usize];
                let piece = String::from_utf8_lossy(&b);
                channel.text.push_str(&piece);
                channel.reads.push((now, piece.len()));
                mem.write_u32(at + READ_OFFSET, write);
            }
        }
    }

    /// Text of up channel `i` so far.
    pub fn text(&self, i: usize) -> &str {
        self.channels.get(i).map_or("", |c| c.text.as_str())
    }
}

fn c_string(mem: &impl Memory, addr: u32) -> String {
    let bytes = mem.read(addr, 32).unwrap_or_default();
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    String::from_utf8_lossy(&bytes[..end]).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Ram(Vec<u8>);
    impl Memory for Ram {
        fn read(&self, addr: u32, len: usize) -> Option<Vec<u8>> {
            self.0
                .get(addr as usize..addr as usize + len)
                .map(<[u8]>::to_vec)
        }
        fn write_u32(&mut self, addr: u32, value: u32) -> bool {
            self.write(addr, &value.to_le_bytes())
        }
        fn write(&mut self, addr: u32, bytes: &[u8]) -> bool {
            self.0[addr as usize..addr as usize + bytes.len()].copy_from_slice(bytes);
            true
        }
    }

    #[test]
    fn typed_bytes_fill_the_down_ring_as_the_target_reads() {
        let mut ram = Ram(vec![0; 512]);
        ram.0[..10].copy_from_slice(ID);
        ram.write_u32(16, 1); // one up channel, then one down channel
        ram.write_u32(20, 1);
        let down = 24 + 24;
        for (k, v) in [0u32, 400, 4, 0, 0].iter().enumerate() {
            ram.write_u32(down + 4 * k as u32, *v);
        }
        let mut rtt = Rtt::new(0);
        rtt.type_in(b"hgxy");
        rtt.poll(&mut ram, 0);
        assert_eq!(&ram.0[400..403], b"hgx", "a ring of 4 holds 3");
        assert_eq!(ram.read_u32(down + 12), Some(3));
        rtt.poll(&mut ram, 0);
        assert_eq!(
            ram.read_u32(down + 12),
            Some(3),
            "full until the target reads"
        );
        ram.write_u32(down + 16, 2); // the target read "hg"
        rtt.poll(&mut ram, 0);
        assert_eq!(ram.0[403], b'y');
        assert_eq!(ram.read_u32(down + 12), Some(0), "wrapped");
        assert!(rtt.typed.is_empty());
    }

    #[test]
    fn reads_new_bytes_once_and_wraps() {
        let mut ram = Ram(vec![0; 512]);
        ram.0[..10].copy_from_slice(ID);
        ram.write_u32(16, 1);
        ram.0[200..204].copy_from_slice(b"log\0");
        for (k, v) in [200u32, 300, 8, 5, 0].iter().enumerate() {
            ram.write_u32(24 + 4 * k as u32, *v);
        }
        ram.0[300..308].copy_from_slice(b"hello!ab");
        let mut rtt = Rtt::new(0);
        rtt.poll(&mut ram, 0);
        assert_eq!(rtt.channels[0].name, "log");
        assert_eq!(rtt.text(0), "hello");
        rtt.poll(&mut ram, 0);
        assert_eq!(rtt.text(0), "hello", "read offset advanced");
        ram.write_u32(24 + 12, 2); // wrote "!ab" and wrapped to 2
        ram.0[300..302].copy_from_slice(b"cd");
        rtt.poll(&mut ram, 7);
        assert_eq!(rtt.text(0), "hello!abcd");
        assert_eq!(
            rtt.channels[0].reads,
            [(0, 5), (7, 5)],
            "one read per poll with news"
        );
    }
}

//! Fieldbus memory management units (ETG.1000.4 6.6, table 57): each maps a bit range of
//! the master's logical address space onto the ESC's physical memory, for reading,
//! writing or both, so that one LRW carries every slave's process data.

/// FMMUs this ESC has.
pub const FMMU_COUNT: usize = 8;
/// Register bytes per FMMU.
pub const FMMU_REGISTER_LEN: usize = 16;

/// One FMMU, as its 16 registers hold it (table 57).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Fmmu {
    /// First logical byte.
    pub logical_start: u32,
    /// Logical bytes, first and last partly.
    pub length: u16,
    /// First bit in the first logical byte.
    pub logical_start_bit: u8,
    /// Last bit in the last logical byte.
    pub logical_end_bit: u8,
    /// First physical byte.
    pub physical_start: u16,
    /// First bit in the first physical byte.
    pub physical_start_bit: u8,
    /// Bit 0: read (memory to datagram), bit 1: write.
    pub kind: u8,
    /// Bit 0: active.
    pub activate: u8,
}

/// Consecutive bits one FMMU maps between a datagram and one physical byte.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BitRun {
    /// The physical byte (past 0xFFFF when the FMMU maps beyond the address space: no
    /// memory is there).
    pub physical: u32,
    /// Its first bit.
    pub physical_bit: u8,
    /// The first bit in the datagram's data, counted from its first byte's bit 0.
    pub datagram_bit: usize,
    /// Bits in the run, 1 to 8, within the physical byte.
    pub count: u8,
}

impl Fmmu {
    /// Reads the 16 register bytes.
    pub fn from_registers(bytes: [u8; FMMU_REGISTER_LEN]) -> Self {
        Fmmu {
            logical_start: u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]),
            length: u16::from_le_bytes([bytes[4], bytes[5]]),
            logical_start_bit: bytes[6] & 7,
            logical_end_bit: bytes[7] & 7,
            physical_start: u16::from_le_bytes([bytes[8], bytes[9]]),
            physical_start_bit: bytes[10] & 7,
            kind: bytes[11],
            activate: bytes[12],
        }
    }

    /// Active with a length.
    pub fn active(&self) -> bool {
        self.activate & 1 != 0 && self.length > 0
    }

    /// Maps memory into the datagram.
    pub fn reads(&self) -> bool {
        self.kind & 1 != 0
    }

    /// Maps the datagram into memory.
    pub fn writes(&self) -> bool {
        self.kind & 2 != 0
    }

    /// The bits a logical datagram at `address` with `len` bytes shares with this FMMU, in
    /// runs within one physical byte each, in order. Nothing when inactive.
    pub fn runs(&self, address: u32, len: usize) -> impl Iterator<Item = BitRun> + use<> {
        let first = u64::from(self.logical_start) * 8 + u64::from(self.logical_start_bit);
        let last = (u64::from(self.logical_start) + u64::from(self.length)).saturating_sub(1) * 8
            + u64::from(self.logical_end_bit);
        let datagram = u64::from(address) * 8..(u64::from(address) + len as u64) * 8;
        let from = first.max(datagram.start);
        let to = (last + 1).min(datagram.end);
        let (from, to) = if self.active() && from < to { (from, to) } else { (0, 0) };
        let physical_first = u64::from(self.physical_start) * 8 + u64::from(self.physical_start_bit);
        let mut bit = from;
        std::iter::from_fn(move || {
            if bit >= to {
                return None;
            }
            let physical = physical_first + (bit - first);
            let physical_bit = (physical % 8) as u8;
            let count = (to - bit).min(u64::from(8 - physical_bit)) as u8;
            let run = BitRun {
                physical: (physical / 8) as u32,
                physical_bit,
                datagram_bit: (bit - datagram.start) as usize,
                count,
            };
            bit += u64::from(count);
            Some(run)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SOEM's output FMMU of a drive: 6 bytes from logical 0 to SM2 at 0x1000, write.
    fn outputs() -> Fmmu {
        Fmmu::from_registers([0, 0, 0, 0, 6, 0, 0, 7, 0x00, 0x10, 0, 2, 1, 0, 0, 0])
    }

    #[test]
    fn the_registers_give_the_mapping() {
        let fmmu = outputs();
        assert_eq!((fmmu.logical_start, fmmu.length, fmmu.physical_start), (0, 6, 0x1000));
        assert!(fmmu.active() && fmmu.writes() && !fmmu.reads());
    }

    /// Byte-aligned: one run per byte, the datagram's part only.
    #[test]
    fn byte_aligned_runs() {
        let runs: Vec<_> = outputs().runs(4, 4).collect();
        assert_eq!(
            runs,
            [
                BitRun { physical: 0x1004, physical_bit: 0, datagram_bit: 0, count: 8 },
                BitRun { physical: 0x1005, physical_bit: 0, datagram_bit: 8, count: 8 },
            ],
            "logical 0..6 against a datagram at 4..8: the FMMU's last two bytes"
        );
        assert_eq!(outputs().runs(6, 4).count(), 0);
    }

    /// Bit-wise: logical bits 3..=5 of byte 0x10 to physical bits 6..=7 of 0x0F00 and bit 0
    /// of 0x0F01.
    #[test]
    fn bit_runs_split_at_physical_bytes() {
        let fmmu = Fmmu {
            logical_start: 0x10,
            length: 1,
            logical_start_bit: 3,
            logical_end_bit: 5,
            physical_start: 0x0F00,
            physical_start_bit: 6,
            kind: 1,
            activate: 1,
        };
        let runs: Vec<_> = fmmu.runs(0x0F, 2).collect();
        assert_eq!(
            runs,
            [
                BitRun { physical: 0x0F00, physical_bit: 6, datagram_bit: 11, count: 2 },
                BitRun { physical: 0x0F01, physical_bit: 0, datagram_bit: 13, count: 1 },
            ]
        );
        assert_eq!(Fmmu { activate: 0, ..fmmu }.runs(0x0F, 2).count(), 0);
    }
}

//! PDO mapping (CoE manual 2.4, table 4-3): which objects a PDO carries, in order,
//! and where each sits in the slave's process data.

use crate::coe::{Access, DataType, ObjId, ObjectStore};

/// At most 7 entries per PDO (CoE manual 2.4).
pub const MAX_ENTRIES: usize = 7;
/// At most 20 bytes of process data per PDO (CoE manual 2.4).
pub const MAX_BYTES: usize = 20;

/// One mapping entry, `0xIIII SS LL` on the wire: index, sub-index, bit length.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PdoEntry {
    /// The mapped object's index (`0xIIII`).
    pub index: u16,
    /// Its sub-index (`SS`).
    pub sub: u8,
    /// Its length in bits (`LL`), which must be the object's type's.
    pub bits: u8,
}

impl PdoEntry {
    /// The entry a mapping object's sub-index holds (`0xIIIISSLL`).
    pub const fn from_u32(v: u32) -> Self {
        PdoEntry { index: (v >> 16) as u16, sub: (v >> 8) as u8, bits: v as u8 }
    }
}

/// A mapped object and its byte offset in the slave's process data.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mapped {
    /// The object in the device's dictionary.
    pub obj: ObjId,
    /// Its data type, which sets its width in the process data.
    pub ty: DataType,
    /// Its first byte in the slave's process data of this direction.
    pub offset: usize,
}

/// Why a PDO's mapping is refused (CoE manual 2.4; the master sees an SDO abort or the
/// SafeOp refusal).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MappingError {
    /// More than `MAX_ENTRIES` entries.
    TooManyEntries,
    /// More than `MAX_BYTES` bytes of process data.
    TooLong,
    /// The entry names an object the device does not have.
    UnknownObject(PdoEntry),
    /// The object exists but may not be mapped into a PDO.
    NotMappable(PdoEntry),
    /// A read-only object in the RxPDO: the master could not write it.
    NotWritable(PdoEntry),
    /// The entry's bit length is not the object's type's.
    LengthMismatch(PdoEntry),
    /// An assignment names no mapping object of its direction, or one twice.
    NotAPdo(u16),
}

/// Which way a PDO carries its objects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// RxPDOs 0x1600.., assigned in 0x1C12: master to slave.
    Outputs,
    /// TxPDOs 0x1A00.., assigned in 0x1C13: slave to master.
    Inputs,
}

impl Direction {
    /// The SyncManager's PDO assignment object (CoE manual table 4-4).
    pub const fn assignment(self) -> u16 {
        match self {
            Direction::Outputs => 0x1C12,
            Direction::Inputs => 0x1C13,
        }
    }

    /// The direction of a PDO mapping object (CiA 301: RxPDO mappings 0x1600-0x17FF,
    /// TxPDO mappings 0x1A00-0x1BFF).
    pub const fn of_mapping(index: u16) -> Option<Direction> {
        match index {
            0x1600..=0x17FF => Some(Direction::Outputs),
            0x1A00..=0x1BFF => Some(Direction::Inputs),
            _ => None,
        }
    }
}

/// Resolves the entries of one PDO against a device's dictionary and lays them out.
pub fn layout(
    store: &ObjectStore,
    direction: Direction,
    entries: &[PdoEntry],
) -> Result<(Vec<Mapped>, usize), MappingError> {
    if entries.len() > MAX_ENTRIES {
        return Err(MappingError::TooManyEntries);
    }
    let mut mapped = Vec::with_capacity(entries.len());
    let mut offset = 0;
    for &entry in entries {
        let obj = store.find(entry.index, entry.sub).ok_or(MappingError::UnknownObject(entry))?;
        let def = store.def(obj);
        if !def.pdo_mappable {
            return Err(MappingError::NotMappable(entry));
        }
        if direction == Direction::Outputs && def.access == Access::ReadOnly {
            return Err(MappingError::NotWritable(entry));
        }
        if def.ty.bits() != entry.bits {
            return Err(MappingError::LengthMismatch(entry));
        }
        mapped.push(Mapped { obj, ty: def.ty, offset });
        offset += entry.bits as usize / 8;
    }
    if offset > MAX_BYTES {
        return Err(MappingError::TooLong);
    }
    Ok((mapped, offset))
}

/// The entries a mapping object (0x1600, 0x1A00, ...) holds: sub 0 is the count.
pub fn entries(store: &ObjectStore, mapping_index: u16) -> ([PdoEntry; MAX_ENTRIES], usize) {
    let count = store.find(mapping_index, 0).map_or(0, |id| store.get(id) as usize).min(MAX_ENTRIES);
    let mut entries = [PdoEntry::from_u32(0); MAX_ENTRIES];
    for (i, entry) in entries.iter_mut().enumerate().take(count) {
        if let Some(id) = store.find(mapping_index, i as u8 + 1) {
            *entry = PdoEntry::from_u32(store.get(id) as u32);
        }
    }
    (entries, count)
}

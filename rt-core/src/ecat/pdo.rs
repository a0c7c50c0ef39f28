//! PDO mapping (CoE manual 2.4, tables 2-4 and 4-3): the objects a PDO carries, in order,
//! and where each sits in the slave's process data.

use crate::drive::od::{DataType, ObjId, ObjectStore};

/// At most 7 entries and 20 bytes per PDO (CoE manual 2.4).
pub const MAX_ENTRIES: usize = 7;
pub const MAX_BYTES: usize = 20;

/// One mapping entry, `0xIIII SS LL` on the wire: index, sub-index, bit length.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PdoEntry {
    pub index: u16,
    pub sub: u8,
    pub bits: u8,
}

impl PdoEntry {
    pub const fn from_u32(v: u32) -> Self {
        PdoEntry { index: (v >> 16) as u16, sub: (v >> 8) as u8, bits: v as u8 }
    }

    pub const fn to_u32(self) -> u32 {
        (self.index as u32) << 16 | (self.sub as u32) << 8 | self.bits as u32
    }
}

/// A mapped object and its byte offset in the slave's PDO.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mapped {
    pub obj: ObjId,
    pub ty: DataType,
    pub offset: usize,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MappingError {
    TooManyEntries,
    TooLong,
    UnknownObject(PdoEntry),
    NotMappable(PdoEntry),
    /// A read-only object in the RxPDO: the master could not write it.
    NotWritable(PdoEntry),
    LengthMismatch(PdoEntry),
}

/// Which way a PDO carries its objects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// RxPDO 0x1600: master to slave.
    Outputs,
    /// TxPDO 0x1A00: slave to master.
    Inputs,
}

/// Resolves mapping entries against a drive's dictionary and lays them out.
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
        let obj = crate::drive::od::find(entry.index, entry.sub)
            .filter(|&id| store.has(id))
            .ok_or(MappingError::UnknownObject(entry))?;
        let def = obj.def();
        if !def.pdo_mappable {
            return Err(MappingError::NotMappable(entry));
        }
        if direction == Direction::Outputs && def.access == crate::drive::od::Access::ReadOnly {
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

/// The entries a mapping object (0x1600 or 0x1A00) holds: sub 0 is the count.
pub fn entries(store: &ObjectStore, mapping_index: u16) -> ([PdoEntry; MAX_ENTRIES], usize) {
    let count = crate::drive::od::find(mapping_index, 0).map_or(0, |id| store.get(id) as usize).min(MAX_ENTRIES);
    let mut entries = [PdoEntry::from_u32(0); MAX_ENTRIES];
    for (i, entry) in entries.iter_mut().enumerate().take(count) {
        if let Some(id) = crate::drive::od::find(mapping_index, i as u8 + 1) {
            *entry = PdoEntry::from_u32(store.get(id) as u32);
        }
    }
    (entries, count)
}

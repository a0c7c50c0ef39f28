//! PDO mapping (CoE manual 2.4, tables 2-4 and 4-3): the objects a PDO carries, in order,
//! and where each sits in the slave's process data.

use crate::drive::od::{self, DataType, ObjId};

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
    LengthMismatch(PdoEntry),
}

/// Resolves mapping entries against the dictionary and lays them out.
pub fn layout(entries: &[PdoEntry]) -> Result<(Vec<Mapped>, usize), MappingError> {
    if entries.len() > MAX_ENTRIES {
        return Err(MappingError::TooManyEntries);
    }
    let mut mapped = Vec::with_capacity(entries.len());
    let mut offset = 0;
    for &entry in entries {
        let obj = od::find(entry.index, entry.sub).ok_or(MappingError::UnknownObject(entry))?;
        let def = od::ObjectStore::def(obj);
        if !def.pdo_mappable {
            return Err(MappingError::NotMappable(entry));
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

/// Default RxPDO 0x1600: controlword, target position (6 bytes).
pub const DEFAULT_RX: [PdoEntry; 2] = [PdoEntry::from_u32(0x6040_0010), PdoEntry::from_u32(0x607A_0020)];
/// Default TxPDO 0x1A00: statusword, position actual, following error (10 bytes).
pub const DEFAULT_TX: [PdoEntry; 3] =
    [PdoEntry::from_u32(0x6041_0010), PdoEntry::from_u32(0x6064_0020), PdoEntry::from_u32(0x60F4_0020)];

#[cfg(test)]
mod tests {
    use super::*;

    /// CoE manual table 4-3: the default mappings and their sizes.
    #[test]
    fn default_mappings_are_6_and_10_bytes() {
        assert_eq!(layout(&DEFAULT_RX).unwrap().1, 6);
        assert_eq!(layout(&DEFAULT_TX).unwrap().1, 10);
        assert_eq!(DEFAULT_TX[1].to_u32(), 0x6064_0020);
    }

    #[test]
    fn non_mappable_objects_are_refused() {
        let entry = PdoEntry::from_u32(0x6063_0020);
        assert_eq!(layout(&[entry]), Err(MappingError::NotMappable(entry)));
    }
}

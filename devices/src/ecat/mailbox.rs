//! CoE mailbox: SDO upload and download against a slave's object dictionary (CoE manual
//! 2.2, "SDO request"), the SDO information service's entry description (ETG.1000.6), with
//! the standard abort codes (`api::SdoAbort`).

use crate::coe::{Access, DataType, ObjId, ObjectDef, ObjectStore};

pub use api::SdoAbort;

/// Why an SDO did not happen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SdoError {
    /// The slave answered with an abort code.
    #[error("{0}")]
    Abort(#[from] SdoAbort),
    /// No mailbox in Init (CoE manual 2.3, table 2-3).
    #[error("the slave has no mailbox in Init")]
    NoMailbox,
    /// No slave at this position in the ring.
    #[error("no slave {0}")]
    NoSlave(usize),
    /// On a wire: the slave's mailbox has a transfer under way, or the queue to the wire
    /// is full; asked again in a later cycle, it is taken.
    #[error("the mailbox is busy")]
    MailboxBusy,
    /// On a wire: the transfer is queued, its answer comes in a later cycle.
    #[error("the transfer is under way")]
    Pending,
}

/// What the SDO information service tells of one object: how a master reads and maps it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EntryDescription {
    /// The object's data type.
    pub ty: DataType,
    /// Whether a master may write it.
    pub access: Access,
    /// Whether a PDO may carry it.
    pub pdo_mappable: bool,
}

/// Finds an object the device has; the abort a missing one gets.
pub fn resolve(store: &ObjectStore, index: u16, sub: u8) -> Result<ObjId, SdoAbort> {
    match store.find(index, sub) {
        Some(id) => Ok(id),
        None if store.find(index, 0).is_some() => Err(SdoAbort::NoSubIndex),
        None => Err(SdoAbort::NoObject),
    }
}

/// An upload: the stored value and its length in bytes.
pub fn upload(store: &ObjectStore, index: u16, sub: u8) -> Result<(i64, usize), SdoAbort> {
    let id = resolve(store, index, sub)?;
    check_readable(store.def(id))?;
    Ok((store.get(id), store.def(id).ty.bytes()))
}

/// An entry description (SDO information service).
pub fn describe(store: &ObjectStore, index: u16, sub: u8) -> Result<EntryDescription, SdoAbort> {
    let def = store.def(resolve(store, index, sub)?);
    Ok(EntryDescription { ty: def.ty, access: def.access, pdo_mappable: def.pdo_mappable })
}

fn check_readable(def: &ObjectDef) -> Result<(), SdoAbort> {
    if def.access == Access::WriteOnly { Err(SdoAbort::WriteOnly) } else { Ok(()) }
}

/// Checks a download against the object's access, length and range; returns the object
/// and the value in stored form. Writing it is the caller's (state rules come first).
pub fn check_download(store: &ObjectStore, index: u16, sub: u8, data: &[u8]) -> Result<(ObjId, i64), SdoAbort> {
    let id = resolve(store, index, sub)?;
    let def = store.def(id);
    if def.access == Access::ReadOnly {
        return Err(SdoAbort::ReadOnly);
    }
    let n = def.ty.bytes();
    match data.len().cmp(&n) {
        std::cmp::Ordering::Greater => return Err(SdoAbort::LengthTooHigh),
        std::cmp::Ordering::Less => return Err(SdoAbort::LengthTooLow),
        std::cmp::Ordering::Equal => {}
    }
    let value = def.ty.decode(data);
    let number = def.ty.to_f64(value);
    if def.ty == DataType::Real32 && !number.is_finite() {
        return Err(SdoAbort::ValueRange);
    }
    if number > def.max {
        return Err(SdoAbort::ValueTooHigh);
    }
    if number < def.min {
        return Err(SdoAbort::ValueTooLow);
    }
    Ok((id, value))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coe::test_object;

    const fn row(index: u16, sub: u8, ty: DataType, access: Access) -> ObjectDef {
        ObjectDef { access, min: -1000.0, max: 1000.0, ..test_object(index, sub, ty) }
    }

    static TABLE: &[ObjectDef] = &[
        row(0x2000, 0, DataType::UInt8, Access::ReadOnly),
        row(0x2000, 1, DataType::Int16, Access::ReadWrite),
        row(0x2001, 0, DataType::Real32, Access::ReadWrite),
        row(0x2002, 0, DataType::Int32, Access::WriteOnly),
    ];

    fn store() -> ObjectStore {
        ObjectStore::new(TABLE, 1)
    }

    /// CiA 301 abort codes over any device's table, one row per case.
    #[test]
    fn abort_codes_on_a_table_of_any_device() {
        let rows: [(u16, u8, &[u8], SdoAbort, &str); 6] = [
            (0x2003, 0, &[0], SdoAbort::NoObject, "unknown object"),
            (0x2000, 2, &[0, 0], SdoAbort::NoSubIndex, "unknown sub-index"),
            (0x2000, 0, &[0], SdoAbort::ReadOnly, "read-only"),
            (0x2000, 1, &[0, 0, 0], SdoAbort::LengthTooHigh, "3 bytes to an INT16"),
            (0x2000, 1, &1001i16.to_le_bytes(), SdoAbort::ValueTooHigh, "1001 > 1000"),
            (0x2001, 0, &f32::NAN.to_bits().to_le_bytes(), SdoAbort::ValueRange, "REAL32 NaN"),
        ];
        for (index, sub, data, abort, what) in rows {
            assert_eq!(check_download(&store(), index, sub, data).map(|_| ()), Err(abort), "{what}");
        }
        assert_eq!(check_download(&store(), 0x2000, 1, &(-7i16).to_le_bytes()).map(|(_, v)| v), Ok(-7));
    }

    /// The access rule is checked on a write-only object.
    #[test]
    fn a_write_only_object_cannot_be_read() {
        assert_eq!(upload(&store(), 0x2002, 0), Err(SdoAbort::WriteOnly));
        assert_eq!(upload(&store(), 0x2000, 1), Ok((0, 2)));
    }

    /// The entry description a master lays its process image out with.
    #[test]
    fn an_entry_description_gives_type_and_access() {
        let description = describe(&store(), 0x2000, 1).unwrap();
        assert_eq!(
            description,
            EntryDescription { ty: DataType::Int16, access: Access::ReadWrite, pdo_mappable: false }
        );
        assert_eq!(describe(&store(), 0x2000, 5), Err(SdoAbort::NoSubIndex));
    }
}

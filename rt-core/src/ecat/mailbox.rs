//! CoE mailbox: SDO upload and download against a slave's object dictionary (CoE manual
//! 2.2, "SDO request" only), with the standard abort codes (`api::SdoAbort`).

use crate::drive::od::{Access, DataType, ObjId, ObjectDef, ObjectStore, find, index_exists};

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
    #[error("no slave {0}")]
    NoSlave(usize),
}

/// Finds an object the drive has; the abort a missing one gets.
pub fn resolve(store: &ObjectStore, index: u16, sub: u8) -> Result<ObjId, SdoAbort> {
    match find(index, sub).filter(|&id| store.has(id)) {
        Some(id) => Ok(id),
        None if index_exists(index) && find(index, 0).is_some_and(|id| store.has(id)) => Err(SdoAbort::NoSubIndex),
        None => Err(SdoAbort::NoObject),
    }
}

/// An upload: the stored value and its length in bytes.
pub fn upload(store: &ObjectStore, index: u16, sub: u8) -> Result<(i64, usize), SdoAbort> {
    let id = resolve(store, index, sub)?;
    check_readable(id.def())?;
    Ok((store.get(id), id.def().ty.bytes()))
}

fn check_readable(def: &ObjectDef) -> Result<(), SdoAbort> {
    if def.access == Access::WriteOnly { Err(SdoAbort::WriteOnly) } else { Ok(()) }
}

/// Checks a download against the object's access, length and range; returns the object
/// and the value in stored form. Writing it is the caller's (state rules come first).
pub fn check_download(store: &ObjectStore, index: u16, sub: u8, data: &[u8]) -> Result<(ObjId, i64), SdoAbort> {
    let id = resolve(store, index, sub)?;
    let def = id.def();
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
    use crate::drive::DriveModel;
    use crate::drive::od::OBJECTS;

    fn d1() -> ObjectStore {
        ObjectStore::new(DriveModel::D1)
    }

    /// CiA 301 abort codes, one row per case (CoE manual ch. 4 objects).
    #[test]
    fn abort_codes() {
        let rows: [(u16, u8, &[u8], SdoAbort, &str); 9] = [
            (0x6011, 0, &[0, 0], SdoAbort::NoObject, "unknown object"),
            (0x60BC, 0, &[0, 0, 0, 0], SdoAbort::NoObject, "0x60BC is not in the dictionary (no TP2)"),
            (0x6099, 3, &[0, 0, 0, 0], SdoAbort::NoSubIndex, "unknown sub-index"),
            (0x6041, 0, &[0, 0], SdoAbort::ReadOnly, "statusword is read-only"),
            (0x6040, 0, &[0, 0, 0, 0], SdoAbort::LengthTooHigh, "4 bytes to a UINT16"),
            (0x607A, 0, &[0, 0], SdoAbort::LengthTooLow, "2 bytes to an INT32"),
            (0x6071, 0, &1001i16.to_le_bytes(), SdoAbort::ValueTooHigh, "target torque 1001 (max 1000)"),
            (0x6071, 0, &(-1001i16).to_le_bytes(), SdoAbort::ValueTooLow, "target torque -1001"),
            (0x2004, 1, &0i32.to_le_bytes(), SdoAbort::ValueTooLow, "gear numerator 0 (min 1)"),
        ];
        for (index, sub, data, abort, what) in rows {
            assert_eq!(check_download(&d1(), index, sub, data).map(|_| ()), Err(abort), "{what}");
        }
        assert_eq!(upload(&d1(), 0x1234, 0), Err(SdoAbort::NoObject));
    }

    /// CoE manual table 4-22: objects of other models do not exist.
    #[test]
    fn model_support() {
        let d1n = ObjectStore::new(DriveModel::D1N);
        assert_eq!(upload(&d1n, 0x6075, 0), Err(SdoAbort::NoObject));
        assert_eq!(upload(&d1n, 0x2060, 0), Err(SdoAbort::NoObject));
        assert_eq!(upload(&ObjectStore::new(DriveModel::Abily), 0x2110, 0), Err(SdoAbort::NoObject));
        assert!(upload(&ObjectStore::new(DriveModel::D2), 0x2110, 0).is_ok());
    }

    #[test]
    fn real32_range_is_checked_on_the_number() {
        let gain = |v: f32| check_download(&d1(), 0x2050, 0, &v.to_bits().to_le_bytes()).map(|_| ());
        assert_eq!(gain(20.0), Err(SdoAbort::ValueTooHigh), "common gain max 10");
        assert_eq!(gain(0.001), Err(SdoAbort::ValueTooLow), "common gain min 0.01");
        assert_eq!(gain(1.5), Ok(()));
    }

    /// No HIWIN object is write-only; the access rule is checked on a made-up one.
    #[test]
    fn a_write_only_object_cannot_be_read() {
        let write_only = ObjectDef { access: Access::WriteOnly, ..OBJECTS[0] };
        assert_eq!(check_readable(&write_only), Err(SdoAbort::WriteOnly));
        assert_eq!(check_readable(&OBJECTS[0]), Ok(()));
    }
}

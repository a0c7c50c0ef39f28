//! DXMC A.1: the Modbus user areas, DV (volatile) at 0x0000..0x2FFF and DH (kept across
//! restarts) at 0x8000..0xAFFF. Their words live in the namespace's shared memory
//! (`schema::shared::SharedData`); this is what a Modbus address means.

use schema::shared::{SharedData, USER_AREA_WORDS};

/// Where DV starts in the Modbus address space.
pub const DV_BASE: u16 = 0x0000;
/// Where DH starts in the Modbus address space.
pub const DH_BASE: u16 = 0x8000;

/// A Modbus user area (DXMC A.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UserArea {
    /// Volatile.
    Dv,
    /// Retentive: kept across restarts.
    Dh,
}

impl UserArea {
    /// The area and word index of a Modbus address, if it is in DV or DH.
    pub fn of(address: i64) -> Option<(UserArea, usize)> {
        let words = USER_AREA_WORDS as i64;
        match address {
            a if (DV_BASE as i64..DV_BASE as i64 + words).contains(&a) => {
                Some((UserArea::Dv, (a - DV_BASE as i64) as usize))
            }
            a if (DH_BASE as i64..DH_BASE as i64 + words).contains(&a) => {
                Some((UserArea::Dh, (a - DH_BASE as i64) as usize))
            }
            _ => None,
        }
    }
}

/// A word of DV or DH by Modbus address; `None` outside them.
pub fn read(shared: &SharedData, address: i64) -> Option<u16> {
    match UserArea::of(address)? {
        (UserArea::Dv, i) => shared.dv_word(i),
        (UserArea::Dh, i) => shared.dh_word(i),
    }
}

/// Writes a word of DV or DH by Modbus address; false outside them.
pub fn write(shared: &SharedData, address: i64, value: u16) -> bool {
    match UserArea::of(address) {
        Some((UserArea::Dv, i)) => shared.set_dv_word(i, value),
        Some((UserArea::Dh, i)) => shared.set_dh_word(i, value),
        None => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// DXMC A.1: the first and last word of each area, and the addresses just outside.
    #[test]
    fn addresses_of_the_user_areas() {
        assert_eq!(UserArea::of(0x0000), Some((UserArea::Dv, 0)));
        assert_eq!(UserArea::of(0x2FFF), Some((UserArea::Dv, 0x2FFF)));
        assert_eq!(UserArea::of(0x3000), None);
        assert_eq!(UserArea::of(0x7FFF), None);
        assert_eq!(UserArea::of(0x8000), Some((UserArea::Dh, 0)));
        assert_eq!(UserArea::of(0xAFFF), Some((UserArea::Dh, 0x2FFF)));
        assert_eq!(UserArea::of(0xB000), None);
        assert_eq!(UserArea::of(-1), None);
    }

    /// A write by address lands in the area's word, and only a DH write counts as one to save.
    #[test]
    fn words_by_address() {
        let shared: Box<SharedData> = schema::layout::zeroed();
        assert!(write(&shared, 0x0010, 7));
        assert_eq!(shared.dh_writes(), 0);
        assert!(write(&shared, 0x8010, 9));
        assert_eq!(shared.dh_writes(), 1);
        assert_eq!((read(&shared, 0x0010), read(&shared, 0x8010)), (Some(7), Some(9)));
        assert_eq!((shared.dv_word(0x10), shared.dh_word(0x10)), (Some(7), Some(9)));
        assert!(!write(&shared, 0x3000, 1));
        assert_eq!(read(&shared, 0xB000), None);
    }
}

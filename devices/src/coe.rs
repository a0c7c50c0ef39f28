//! The CoE object dictionary machinery every simulated device shares: data types, access,
//! PDO-mappable flags, ranges and defaults of an object (CiA 301 as the CoE manual's
//! ch. 4 tables describe its objects), and the store of one device's values over the
//! table the device supplies. What the objects mean is the device's (`drive::od` for the
//! HIWIN drive); the SDO rules over them are the mailbox's (`ecat::mailbox`).
//!
//! Objects are looked up by `(index, sub)` only when an SDO arrives or a PDO is mapped;
//! a device itself uses `ObjId` constants resolved at compile time with `id`.

/// CoE data types.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DataType {
    /// INTEGER8 (the manual's INT8).
    Int8,
    /// INTEGER16 (INT16).
    Int16,
    /// INTEGER32 (INT32).
    Int32,
    /// UNSIGNED8 (UINT8).
    UInt8,
    /// UNSIGNED16 (UINT16).
    UInt16,
    /// UNSIGNED32 (UINT32).
    UInt32,
    /// REAL32, an IEEE 754 single, stored as its bits.
    Real32,
}

impl DataType {
    /// The width in bits, as a PDO mapping entry's length byte gives it.
    pub const fn bits(self) -> u8 {
        match self {
            DataType::Int8 | DataType::UInt8 => 8,
            DataType::Int16 | DataType::UInt16 => 16,
            DataType::Int32 | DataType::UInt32 | DataType::Real32 => 32,
        }
    }

    /// The width in bytes on the bus and in an SDO.
    pub const fn bytes(self) -> usize {
        self.bits() as usize / 8
    }

    /// Whether it is one of the INTEGER types (sign-extended when read).
    pub const fn is_signed(self) -> bool {
        matches!(self, DataType::Int8 | DataType::Int16 | DataType::Int32)
    }

    /// Reads a little-endian value of this type into its stored form (REAL32 as its bits).
    pub fn decode(self, bytes: &[u8]) -> i64 {
        match self {
            DataType::Int8 => bytes[0] as i8 as i64,
            DataType::UInt8 => bytes[0] as i64,
            DataType::Int16 => i16::from_le_bytes([bytes[0], bytes[1]]) as i64,
            DataType::UInt16 => u16::from_le_bytes([bytes[0], bytes[1]]) as i64,
            DataType::Int32 => i32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as i64,
            DataType::UInt32 | DataType::Real32 => u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as i64,
        }
    }

    /// Writes a stored value little-endian, truncated to the type's width.
    pub fn encode(self, value: i64, bytes: &mut [u8]) {
        let n = self.bytes();
        bytes[..n].copy_from_slice(&value.to_le_bytes()[..n]);
    }

    /// The stored form of a raw bit pattern of this type's width (sign-extends signed types).
    pub fn from_raw(self, raw: u64) -> i64 {
        self.decode(&raw.to_le_bytes())
    }

    /// A stored value as a number, for range checks and for users.
    pub fn to_f64(self, stored: i64) -> f64 {
        match self {
            DataType::Real32 => f32::from_bits(stored as u32) as f64,
            _ => stored as f64,
        }
    }
}

/// Whether `value` fits `bytes` bytes as a signed or an unsigned integer: what a master
/// may write to an object that wide without cutting it (its range is the device's to check).
pub fn fits_width(value: i64, bytes: usize) -> bool {
    if bytes >= 8 {
        return true;
    }
    let bits = 8 * bytes as u32;
    (-(1i64 << (bits - 1))..=(1i64 << bits) - 1).contains(&value)
}

/// Who may write an object over SDO (the device itself always may).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// RO: uploads only; a download is aborted.
    ReadOnly,
    /// RW: upload and download.
    ReadWrite,
    /// The SDO layer refuses to read one.
    WriteOnly,
}

/// Every variant of a device family has the object.
pub const ALL_VARIANTS: u32 = u32::MAX;

/// One row of a device's object table. Ranges and defaults are numbers (REAL32 ones
/// included); integers up to 2^32 are exact in an f64.
#[derive(Clone, Copy, Debug)]
pub struct ObjectDef {
    /// The object's index (`0x6040`).
    pub index: u16,
    /// The sub-index, 0 for a simple object.
    pub sub: u8,
    /// The name the manual's table gives it.
    pub name: &'static str,
    /// Its data type.
    pub ty: DataType,
    /// RO, RW or WO over SDO.
    pub access: Access,
    /// Whether a PDO may carry it (the tables' PDO column, O).
    pub pdo_mappable: bool,
    /// The lowest value a download may write.
    pub min: f64,
    /// The highest value a download may write.
    pub max: f64,
    /// The value at power-up.
    pub default: f64,
    /// The unit as the table prints it (`count/s`), empty for none.
    pub unit: &'static str,
    /// The variants of the device family that have the object, one bit each
    /// (`ALL_VARIANTS` for most); a store is made for one variant.
    pub variants: u32,
}

impl ObjectDef {
    /// The stored form of the default.
    pub fn default_value(&self) -> i64 {
        match self.ty {
            DataType::Real32 => (self.default as f32).to_bits() as i64,
            _ => self.default as i64,
        }
    }
}

/// Read-only, read-write; `_PDO`: mappable too (a terminal object's `(access, pdo)`).
pub(crate) const RO: (Access, bool) = (Access::ReadOnly, false);
pub(crate) const RW: (Access, bool) = (Access::ReadWrite, false);
pub(crate) const RO_PDO: (Access, bool) = (Access::ReadOnly, true);
pub(crate) const RW_PDO: (Access, bool) = (Access::ReadWrite, true);

/// An object of a simple device (an I/O terminal): no unit, on every variant, `(access,
/// pdo)` one of `RO`.. `RW_PDO`, its range and default as integers.
pub(crate) const fn terminal_object(
    index: u16,
    sub: u8,
    name: &'static str,
    ty: DataType,
    (access, pdo_mappable): (Access, bool),
    (min, max): (i64, i64),
    default: i64,
) -> ObjectDef {
    ObjectDef {
        index,
        sub,
        name,
        ty,
        access,
        pdo_mappable,
        min: min as f64,
        max: max as f64,
        default: default as f64,
        unit: "",
        variants: ALL_VARIANTS,
    }
}

/// A nameless object for tests' own tables: read-write, not mappable, any value, default
/// 0, on every variant.
#[cfg(test)]
pub(crate) const fn test_object(index: u16, sub: u8, ty: DataType) -> ObjectDef {
    ObjectDef {
        index,
        sub,
        name: "",
        ty,
        access: Access::ReadWrite,
        pdo_mappable: false,
        min: f64::MIN,
        max: f64::MAX,
        default: 0.0,
        unit: "",
        variants: ALL_VARIANTS,
    }
}

/// The position of an object in its device's table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ObjId(pub usize);

/// Resolves an object of `table` at compile time; a missing object fails the build.
pub const fn id(table: &[ObjectDef], index: u16, sub: u8) -> ObjId {
    let mut i = 0;
    while i < table.len() {
        if table[i].index == index && table[i].sub == sub {
            return ObjId(i);
        }
        i += 1;
    }
    panic!("object not in the dictionary");
}

/// The values of one device's objects. Objects of other variants read as absent.
#[derive(Clone, Debug)]
pub struct ObjectStore {
    table: &'static [ObjectDef],
    variant: u32,
    values: Vec<i64>,
}

impl ObjectStore {
    /// Power-up values: the table's defaults, for the variant whose bit is `variant`.
    pub fn new(table: &'static [ObjectDef], variant: u32) -> Self {
        ObjectStore { table, variant, values: table.iter().map(ObjectDef::default_value).collect() }
    }

    /// Whether this device has the object.
    pub fn has(&self, id: ObjId) -> bool {
        self.def(id).variants & self.variant != 0
    }

    /// The definition of object `id`: its name, type, access and PDO flags.
    pub fn def(&self, id: ObjId) -> &'static ObjectDef {
        &self.table[id.0]
    }

    /// Looks an object of this device up; `None` for objects it does not have.
    pub fn find(&self, index: u16, sub: u8) -> Option<ObjId> {
        self.table.iter().position(|o| o.index == index && o.sub == sub).map(ObjId).filter(|&id| self.has(id))
    }

    /// The stored value of object `id`, as the device last set it or a master wrote it.
    pub fn get(&self, id: ObjId) -> i64 {
        self.values[id.0]
    }

    /// A REAL32 object's value.
    pub fn get_f32(&self, id: ObjId) -> f32 {
        f32::from_bits(self.values[id.0] as u32)
    }

    /// Sets a value from the device's own logic (no access or range check).
    pub fn set(&mut self, id: ObjId, value: i64) {
        self.values[id.0] = value;
    }

    pub(crate) fn set_f32(&mut self, id: ObjId, value: f32) {
        self.values[id.0] = value.to_bits() as i64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const fn row(index: u16, sub: u8, ty: DataType, variants: u32) -> ObjectDef {
        ObjectDef { default: -2.0, variants, ..test_object(index, sub, ty) }
    }

    static TABLE: &[ObjectDef] =
        &[row(0x1000, 0, DataType::UInt32, ALL_VARIANTS), row(0x2000, 0, DataType::Int16, 0b10)];

    /// A store serves any table: the variant decides which objects exist, defaults are stored.
    #[test]
    fn a_store_over_a_table_of_its_own() {
        let first = ObjectStore::new(TABLE, 0b01);
        let second = ObjectStore::new(TABLE, 0b10);
        assert_eq!(first.find(0x2000, 0), None, "not on the first variant");
        assert_eq!(second.find(0x2000, 0), Some(ObjId(1)));
        assert_eq!(first.find(0x1000, 0), Some(id(TABLE, 0x1000, 0)));
        assert_eq!(second.get(ObjId(1)), -2);
        assert_eq!(second.def(ObjId(1)).ty, DataType::Int16);
    }

    #[test]
    fn values_travel_little_endian_and_sign_extended() {
        let mut bytes = [0u8; 4];
        DataType::Int16.encode(-2, &mut bytes);
        assert_eq!(bytes, [0xFE, 0xFF, 0, 0]);
        assert_eq!(DataType::Int16.decode(&bytes), -2);
        assert_eq!(DataType::UInt16.decode(&bytes), 0xFFFE);
        assert!(DataType::Int8.is_signed() && !DataType::UInt32.is_signed());
    }
}

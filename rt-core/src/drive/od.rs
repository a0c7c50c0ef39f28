//! The drive's object dictionary: which objects exist, their type, access, PDO
//! mappability, range and default (CoE manual ch. 4, tables 4-1 to 4-15), and the store
//! that holds their values.
//!
//! Objects are looked up by `(index, sub)` only when a PDO is mapped or an SDO arrives;
//! the drive itself reads and writes them through `ObjId` constants resolved at compile
//! time.

/// CoE data types (CoE manual ch. 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DataType {
    Int8,
    Int16,
    Int32,
    UInt8,
    UInt16,
    UInt32,
}

impl DataType {
    pub const fn bits(self) -> u8 {
        match self {
            DataType::Int8 | DataType::UInt8 => 8,
            DataType::Int16 | DataType::UInt16 => 16,
            DataType::Int32 | DataType::UInt32 => 32,
        }
    }

    /// Reads a little-endian value of this type.
    pub fn decode(self, bytes: &[u8]) -> i64 {
        match self {
            DataType::Int8 => bytes[0] as i8 as i64,
            DataType::UInt8 => bytes[0] as i64,
            DataType::Int16 => i16::from_le_bytes([bytes[0], bytes[1]]) as i64,
            DataType::UInt16 => u16::from_le_bytes([bytes[0], bytes[1]]) as i64,
            DataType::Int32 => i32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as i64,
            DataType::UInt32 => u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as i64,
        }
    }

    /// Writes a value of this type little-endian (truncating, as a cast in C would).
    pub fn encode(self, value: i64, bytes: &mut [u8]) {
        let le = value.to_le_bytes();
        let n = self.bits() as usize / 8;
        bytes[..n].copy_from_slice(&le[..n]);
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    ReadOnly,
    ReadWrite,
}

/// One row of the manual's object tables.
#[derive(Clone, Copy, Debug)]
pub struct ObjectDef {
    pub index: u16,
    pub sub: u8,
    pub name: &'static str,
    pub ty: DataType,
    pub access: Access,
    pub pdo_mappable: bool,
    pub min: i64,
    pub max: i64,
    pub default: i64,
}

/// One row, in the column order of the manual's tables.
#[allow(clippy::too_many_arguments)]
const fn obj(
    index: u16,
    sub: u8,
    name: &'static str,
    ty: DataType,
    access: Access,
    pdo_mappable: bool,
    min: i64,
    max: i64,
    default: i64,
) -> ObjectDef {
    ObjectDef { index, sub, name, ty, access, pdo_mappable, min, max, default }
}

use Access::*;
use DataType::*;

const I32_MIN: i64 = i32::MIN as i64;
const I32_MAX: i64 = i32::MAX as i64;

/// The objects of the CoE manual, tables 4-1 (common) and 4-15 (device profile).
pub static OBJECTS: &[ObjectDef] = &[
    obj(0x1000, 0, "Device type", UInt32, ReadOnly, false, 0, u32::MAX as i64, 0x0002_0192),
    obj(0x603F, 0, "Error code", UInt16, ReadOnly, true, 0, 0xFFFF, 0),
    obj(0x6040, 0, "Controlword", UInt16, ReadWrite, true, 0, 0xFFFF, 0),
    obj(0x6041, 0, "Statusword", UInt16, ReadOnly, true, 0, 0xFFFF, 0),
    obj(0x6060, 0, "Modes of operation", Int8, ReadWrite, true, 0, 10, 8),
    obj(0x6061, 0, "Modes of operation display", Int8, ReadOnly, true, 0, 10, 8),
    obj(0x6063, 0, "Position actual internal value", Int32, ReadOnly, false, I32_MIN, I32_MAX, 0),
    obj(0x6064, 0, "Position actual value", Int32, ReadOnly, true, I32_MIN, I32_MAX, 0),
    obj(0x606C, 0, "Velocity actual value", Int32, ReadOnly, true, I32_MIN, I32_MAX, 0),
    obj(0x6077, 0, "Torque actual value", Int16, ReadOnly, true, -32768, 32767, 0),
    obj(0x607A, 0, "Target position", Int32, ReadWrite, true, I32_MIN, I32_MAX, 0),
    obj(0x6085, 0, "Quick stop deceleration", UInt32, ReadWrite, false, 0, u32::MAX as i64, 100_000_000),
    obj(0x60F4, 0, "Following error actual value", Int32, ReadOnly, true, I32_MIN, I32_MAX, 0),
    obj(0x60FC, 0, "Position demand internal value", Int32, ReadOnly, false, I32_MIN, I32_MAX, 0),
];

/// The position of an object in `OBJECTS`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ObjId(pub usize);

/// Resolves an object at compile time; a missing object fails the build.
pub const fn id(index: u16, sub: u8) -> ObjId {
    let mut i = 0;
    while i < OBJECTS.len() {
        if OBJECTS[i].index == index && OBJECTS[i].sub == sub {
            return ObjId(i);
        }
        i += 1;
    }
    panic!("object not in the dictionary");
}

pub fn find(index: u16, sub: u8) -> Option<ObjId> {
    OBJECTS.iter().position(|o| o.index == index && o.sub == sub).map(ObjId)
}

pub const CONTROLWORD: ObjId = id(0x6040, 0);
pub const STATUSWORD: ObjId = id(0x6041, 0);
pub const ERROR_CODE: ObjId = id(0x603F, 0);
pub const MODES_OF_OPERATION: ObjId = id(0x6060, 0);
pub const MODES_OF_OPERATION_DISPLAY: ObjId = id(0x6061, 0);
pub const POSITION_ACTUAL_INTERNAL: ObjId = id(0x6063, 0);
pub const POSITION_ACTUAL: ObjId = id(0x6064, 0);
pub const VELOCITY_ACTUAL: ObjId = id(0x606C, 0);
pub const TORQUE_ACTUAL: ObjId = id(0x6077, 0);
pub const TARGET_POSITION: ObjId = id(0x607A, 0);
pub const QUICK_STOP_DECELERATION: ObjId = id(0x6085, 0);
pub const FOLLOWING_ERROR_ACTUAL: ObjId = id(0x60F4, 0);
pub const POSITION_DEMAND_INTERNAL: ObjId = id(0x60FC, 0);

/// The values of one drive's objects, with the manual's defaults at power-up.
#[derive(Clone, Debug)]
pub struct ObjectStore {
    values: Vec<i64>,
}

impl Default for ObjectStore {
    fn default() -> Self {
        ObjectStore { values: OBJECTS.iter().map(|o| o.default).collect() }
    }
}

impl ObjectStore {
    pub fn get(&self, id: ObjId) -> i64 {
        self.values[id.0]
    }

    /// Sets a value from the drive's own logic (no access or range check).
    pub fn set(&mut self, id: ObjId, value: i64) {
        self.values[id.0] = value;
    }

    pub fn def(id: ObjId) -> &'static ObjectDef {
        &OBJECTS[id.0]
    }
}

//! The drive's object dictionary (CoE manual ch. 4): every object of tables 4-1 (common),
//! 4-3 (PDO mapping), 4-4 (SyncManager), 4-6 (manufacturer) and 4-15 (device profile),
//! with its type, access, PDO mappability, range, default and the models that have it
//! (table 4-22). Choices where the tables contradict themselves are in docs/drive.md.
//!
//! Objects are looked up by `(index, sub)` only when an SDO arrives or a PDO is mapped;
//! the drive itself uses `ObjId` constants resolved at compile time.

use crate::drive::DriveModel;

/// CoE data types.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DataType {
    Int8,
    Int16,
    Int32,
    UInt8,
    UInt16,
    UInt32,
    Real32,
}

impl DataType {
    pub const fn bits(self) -> u8 {
        match self {
            DataType::Int8 | DataType::UInt8 => 8,
            DataType::Int16 | DataType::UInt16 => 16,
            DataType::Int32 | DataType::UInt32 | DataType::Real32 => 32,
        }
    }

    pub const fn bytes(self) -> usize {
        self.bits() as usize / 8
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
/// may write to an object that wide without cutting it (its range is the drive's to check).
pub fn fits_width(value: i64, bytes: usize) -> bool {
    if bytes >= 8 {
        return true;
    }
    let bits = 8 * bytes as u32;
    (-(1i64 << (bits - 1))..=(1i64 << bits) - 1).contains(&value)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    ReadOnly,
    ReadWrite,
    /// No HIWIN object is write-only; the SDO layer still refuses to read one.
    WriteOnly,
}

/// The drive models an object exists on (CoE manual table 4-22).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Models {
    All,
    NotD1N,
    NotD1NNorAbily,
}

impl Models {
    pub fn includes(self, model: DriveModel) -> bool {
        match self {
            Models::All => true,
            Models::NotD1N => model != DriveModel::D1N,
            Models::NotD1NNorAbily => !matches!(model, DriveModel::D1N | DriveModel::Abily),
        }
    }
}

/// One row of the manual's object tables. Ranges and defaults are numbers (REAL32 ones
/// included); integers up to 2^32 are exact in an f64.
#[derive(Clone, Copy, Debug)]
pub struct ObjectDef {
    pub index: u16,
    pub sub: u8,
    pub name: &'static str,
    pub ty: DataType,
    pub access: Access,
    pub pdo_mappable: bool,
    pub min: f64,
    pub max: f64,
    pub default: f64,
    pub unit: &'static str,
    pub models: Models,
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

use Access::{ReadOnly as RO, ReadWrite as RW};
use DataType::*;

const U8: f64 = u8::MAX as f64;
const U16: f64 = u16::MAX as f64;
const U32: f64 = u32::MAX as f64;
const I32_MIN: f64 = i32::MIN as f64;
const I32_MAX: f64 = i32::MAX as f64;
const FLT: f64 = f32::MAX as f64;

/// A row in the manual's column order: index, sub, name, type, access, PDO, max, min,
/// default, unit.
macro_rules! rows {
    ($( ($index:literal, $sub:literal, $name:literal, $ty:ident, $acc:ident, $pdo:literal, $max:expr, $min:expr, $default:expr, $unit:literal $(, $models:ident)?) ),* $(,)?) => {
        &[ $( ObjectDef {
            index: $index, sub: $sub, name: $name, ty: $ty, access: $acc, pdo_mappable: $pdo,
            max: $max as f64, min: $min as f64, default: $default as f64, unit: $unit,
            models: rows!(@models $($models)?),
        }, )* ]
    };
    (@models) => { Models::All };
    (@models $m:ident) => { Models::$m };
}

/// Every object, sorted by index and sub-index.
pub static OBJECTS: &[ObjectDef] = rows![
    // Table 4-1: common objects.
    (0x1000, 0, "Device type", UInt32, RO, false, U32, 0, 0x0002_0192, ""),
    (0x1001, 0, "Error register", UInt8, RO, false, 255, 0, 0, ""),
    (0x1010, 0, "Store parameters: number of entries", UInt8, RO, false, U8, 0, 1, ""),
    (0x1010, 1, "Save all parameters", UInt32, RW, false, U32, 0, 0, ""),
    (0x1018, 0, "Identity: number of entries", UInt8, RO, false, U8, 0, 4, ""),
    (0x1018, 1, "Vendor ID", UInt32, RO, false, U32, 0, 0xAAAA, ""),
    (0x1018, 2, "Product code", UInt32, RO, false, U32, 1, 2, ""),
    (0x1018, 3, "Revision number", UInt32, RO, false, U32, 0, 1, ""),
    (0x1018, 4, "Serial number", UInt32, RO, false, U32, 0, 0, ""),
    // Table 4-3: PDO mapping.
    (0x1600, 0, "1st receive PDO mapping: number of objects", UInt8, RW, false, 7, 0, 2, ""),
    (0x1600, 1, "RxPDO mapping entry 1", UInt32, RW, false, U32, 0, 0x6040_0010u32, ""),
    (0x1600, 2, "RxPDO mapping entry 2", UInt32, RW, false, U32, 0, 0x607A_0020u32, ""),
    (0x1600, 3, "RxPDO mapping entry 3", UInt32, RW, false, U32, 0, 0, ""),
    (0x1600, 4, "RxPDO mapping entry 4", UInt32, RW, false, U32, 0, 0, ""),
    (0x1600, 5, "RxPDO mapping entry 5", UInt32, RW, false, U32, 0, 0, ""),
    (0x1600, 6, "RxPDO mapping entry 6", UInt32, RW, false, U32, 0, 0, ""),
    (0x1600, 7, "RxPDO mapping entry 7", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A00, 0, "1st transmit PDO mapping: number of objects", UInt8, RW, false, 7, 0, 3, ""),
    (0x1A00, 1, "TxPDO mapping entry 1", UInt32, RW, false, U32, 0, 0x6041_0010u32, ""),
    (0x1A00, 2, "TxPDO mapping entry 2", UInt32, RW, false, U32, 0, 0x6064_0020u32, ""),
    (0x1A00, 3, "TxPDO mapping entry 3", UInt32, RW, false, U32, 0, 0x60F4_0020u32, ""),
    (0x1A00, 4, "TxPDO mapping entry 4", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A00, 5, "TxPDO mapping entry 5", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A00, 6, "TxPDO mapping entry 6", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A00, 7, "TxPDO mapping entry 7", UInt32, RW, false, U32, 0, 0, ""),
    // Table 4-4: SyncManager communication objects.
    (0x1C00, 0, "SM comm type: number of used SMs", UInt8, RO, false, U8, 0, 4, ""),
    (0x1C00, 1, "Comm type SM0", UInt8, RO, false, U8, 0, 1, ""),
    (0x1C00, 2, "Comm type SM1", UInt8, RO, false, U8, 0, 2, ""),
    (0x1C00, 3, "Comm type SM2", UInt8, RO, false, U8, 0, 3, ""),
    (0x1C00, 4, "Comm type SM3", UInt8, RO, false, U8, 0, 4, ""),
    (0x1C10, 0, "SM0 PDO assignment", UInt8, RO, false, U8, 0, 0, ""),
    (0x1C11, 0, "SM1 PDO assignment", UInt8, RO, false, U8, 0, 0, ""),
    (0x1C12, 0, "SM2 PDO assignment: number of assigned RxPDOs", UInt8, RW, false, 1, 0, 1, ""),
    (0x1C12, 1, "PDO mapping index of assigned RxPDO", UInt16, RW, false, 0x1600, 0x1600, 0x1600, ""),
    (0x1C13, 0, "SM3 PDO assignment: number of assigned TxPDOs", UInt8, RW, false, 1, 0, 1, ""),
    (0x1C13, 1, "PDO mapping index of assigned TxPDO", UInt16, RW, false, 0x1A00, 0x1A00, 0x1A00, ""),
    (0x1C32, 0, "SM2 sync: number of sync parameters", UInt8, RO, false, U8, 0, 8, ""),
    (0x1C32, 1, "Synchronization type", UInt16, RW, false, 2, 0, 2, ""),
    (0x1C32, 2, "Cycle time", UInt32, RW, false, U32, 0, 125_000, "ns"),
    (0x1C32, 3, "Reserved 1", UInt32, RW, false, U32, 0, 0, ""),
    (0x1C32, 4, "Synchronization types supported", UInt16, RO, false, U16, 0, 0x0005, ""),
    (0x1C32, 5, "Minimum cycle time", UInt32, RO, false, U32, 0, 125_000, "ns"),
    (0x1C32, 6, "Calc and copy time", UInt32, RO, false, U32, 0, 62_500, "ns"),
    (0x1C32, 7, "Reserved 2", UInt32, RO, false, U32, 0, 0, ""),
    (0x1C32, 8, "Reserved 3", UInt16, RW, false, U16, 0, 0, ""),
    (0x1C33, 0, "SM3 sync: number of sync parameters", UInt8, RO, false, U8, 0, 9, ""),
    (0x1C33, 1, "Synchronization type", UInt16, RO, false, 2, 0, 2, ""),
    (0x1C33, 2, "Cycle time", UInt32, RO, false, U32, 0, 125_000, "ns"),
    (0x1C33, 3, "Reserved 1", UInt32, RW, false, U32, 0, 0, ""),
    (0x1C33, 4, "Synchronization types supported", UInt16, RO, false, U16, 0, 0x0005, ""),
    (0x1C33, 5, "Minimum cycle time", UInt32, RO, false, U32, 0, 125_000, "ns"),
    (0x1C33, 6, "Calc and copy time", UInt32, RO, false, U32, 0, 62_500, "ns"),
    (0x1C33, 7, "Reserved 2", UInt32, RW, false, U32, 0, 0, ""),
    (0x1C33, 8, "Reserved 3", UInt16, RW, false, U16, 0, 0, ""),
    (0x1C33, 9, "Delay time", UInt32, RO, false, U32, 0, 0, "ns"),
    // Table 4-6: manufacturer-specific objects.
    (0x2000, 0, "Motor type", UInt16, RO, false, 2, 0, 2, ""),
    (0x2001, 0, "Inner encoder resolution", Int32, RO, false, I32_MAX, 0, 0, "count"),
    (0x2002, 0, "Outer encoder resolution", Int32, RO, false, I32_MAX, 0, 0, "count"),
    (0x2003, 0, "Screw pitch", Int32, RO, false, I32_MAX, 1, 1, "mm"),
    (0x2004, 0, "Electronic gear: number of entries", UInt8, RO, false, U8, 0, 2, ""),
    (0x2004, 1, "Numerator of gear ratio", Int32, RW, false, I32_MAX, 1, 1, ""),
    (0x2004, 2, "Denominator of gear ratio", Int32, RW, false, I32_MAX, 1, 1, ""),
    (0x2010, 0, "Input function", UInt16, RW, true, 3, 0, 0, ""),
    (0x2020, 0, "Index signal", Int8, RO, true, 1, 0, 0, ""),
    (0x2021, 0, "Latched index position", Int32, RO, true, I32_MAX, I32_MIN, 0, "count"),
    (0x2022, 0, "Motor actual current", Real32, RO, true, FLT, -FLT, 0, "A_rms"),
    (0x2040, 0, "2nd encoder option", UInt16, RO, false, 1, 0, 0, ""),
    (0x2041, 0, "Enable software position limit", UInt16, RW, false, 1, 0, 0, ""),
    (0x2042, 0, "Enable hardware limit protection", UInt16, RW, false, 1, 0, 1, ""),
    (0x2043, 0, "Input logic inversion", Int16, RW, false, 0x7FFF, -0x8000, 0x07EF, ""),
    (0x2050, 0, "Common gain", Real32, RW, false, 10, 0.01, 0.3, ""),
    (0x2051, 0, "Velocity proportional gain", Real32, RW, false, 1, 0.000001, 0.001, ""),
    (0x2052, 0, "Proportional gain of the current loop", Real32, RW, false, FLT, -FLT, 500, ""),
    (0x2053, 0, "Integral gain of the current loop", Real32, RW, false, FLT, -FLT, 100, ""),
    (0x2054, 0, "Integral gain of the velocity loop", Real32, RW, false, FLT, -FLT, 314, ""),
    (0x2055, 0, "Proportional gain of the position loop", Real32, RW, false, FLT, -FLT, 314, ""),
    (0x2060, 0, "Multi turn encoder reset flag", UInt8, RW, false, 1, 0, 0, "", NotD1N),
    (0x2100, 0, "Drive error events 1", UInt32, RO, false, U32, 0, 0, ""),
    (0x2101, 0, "Drive error events 2", UInt32, RO, false, U32, 0, 0, ""),
    (0x2110, 0, "Drive warning events 1", UInt16, RO, false, U16, 0, 0, "", NotD1NNorAbily),
    (0x2111, 0, "Drive warning events 2", UInt16, RO, false, U16, 0, 0, "", NotD1NNorAbily),
    (0x2112, 0, "Drive warning events 3", UInt16, RO, false, U16, 0, 0, "", NotD1NNorAbily),
    (0x2113, 0, "Drive warning events 4", UInt16, RO, false, U16, 0, 0, "", NotD1NNorAbily),
    // Table 4-15: device profile objects.
    (0x603F, 0, "Error code", UInt16, RO, true, U16, 0, 0, ""),
    (0x6040, 0, "Controlword", UInt16, RW, true, U16, 0, 0, ""),
    (0x6041, 0, "Statusword", UInt16, RO, true, U16, 0, 0, ""),
    (0x6060, 0, "Modes of operation", Int8, RW, true, 10, 0, 8, ""),
    (0x6061, 0, "Modes of operation display", Int8, RO, true, 10, 0, 8, ""),
    (0x6063, 0, "Position actual internal value", Int32, RO, false, I32_MAX, I32_MIN, 0, "count"),
    (0x6064, 0, "Position actual value", Int32, RO, true, I32_MAX, I32_MIN, 0, "count"),
    (0x6065, 0, "Following error window", UInt32, RW, false, U32, 0, 0, "count"),
    (0x6066, 0, "Following error time out", UInt16, RW, false, U16, 0, 0, "ms"),
    (0x606C, 0, "Velocity actual value", Int32, RO, true, I32_MAX, I32_MIN, 0, "count/s"),
    (0x6071, 0, "Target torque", Int16, RW, true, 1000, -1000, 0, "0.1 %"),
    (0x6075, 0, "Motor rated current", UInt32, RO, false, U32, 0, 0, "mA", NotD1N),
    (0x6077, 0, "Torque actual value", Int16, RO, true, 1000, -1000, 0, "0.1 %"),
    (0x607A, 0, "Target position", Int32, RW, true, I32_MAX, I32_MIN, 0, "count"),
    (0x607C, 0, "Home offset", Int32, RW, false, I32_MAX, I32_MIN, 0, "count"),
    (0x607D, 0, "Software position limit: highest sub-index", UInt8, RO, false, U8, 0, 2, ""),
    (0x607D, 1, "Min software position limit", Int32, RW, false, I32_MAX, I32_MIN, I32_MIN, "count"),
    (0x607D, 2, "Max software position limit", Int32, RW, false, I32_MAX, I32_MIN, I32_MAX, "count"),
    (0x607F, 0, "Maximum profile velocity", UInt32, RW, false, U32, 0, 0, "count/s"),
    (0x6081, 0, "Profile velocity", UInt32, RW, false, U32, 0, 0, "count/s"),
    (0x6083, 0, "Profile acceleration", UInt32, RW, false, U32, 0, 0, "count/s²"),
    (0x6084, 0, "Profile deceleration", UInt32, RW, false, U32, 0, 0, "count/s²"),
    (0x6085, 0, "Quick stop deceleration", UInt32, RW, false, U32, 0, 0, "count/s²"),
    (0x6087, 0, "Torque slope", UInt32, RW, false, U32, 0, 0, "0.1 %/s"),
    (0x6098, 0, "Homing method", Int8, RW, false, 37, -5, 0, ""),
    (0x6099, 0, "Homing speeds: highest sub-index", UInt8, RO, false, U8, 0, 2, ""),
    (0x6099, 1, "Speed during search for switch", UInt32, RW, false, I32_MAX, 0, 0, "count/s"),
    (0x6099, 2, "Speed during search for zero", UInt32, RW, false, I32_MAX, 0, 0, "count/s"),
    (0x609A, 0, "Homing acceleration", UInt32, RW, false, U32, 0, 0, "count/s²"),
    (0x60B1, 0, "Velocity offset", Int32, RW, false, I32_MAX, I32_MIN, 0, "count/s"),
    (0x60B2, 0, "Torque offset", Int16, RW, false, 1000, -1000, 0, "0.1 %"),
    (0x60B8, 0, "Touch probe function", UInt16, RW, true, U16, 0, 0, ""),
    (0x60B9, 0, "Touch probe status", UInt16, RO, true, U16, 0, 0, ""),
    (0x60BA, 0, "Touch probe 1 positive edge", Int32, RO, true, I32_MAX, I32_MIN, 0, "count"),
    (0x60BB, 0, "Touch probe 1 negative edge", Int32, RO, true, I32_MAX, I32_MIN, 0, "count"),
    (0x60C2, 0, "Interpolation time period: highest sub-index", UInt8, RO, false, U8, 0, 2, ""),
    (0x60C2, 1, "Interpolation time period", UInt8, RW, false, 255, 0, 0, ""),
    (0x60C2, 2, "Interpolation time index", Int8, RW, false, 63, -128, 0, ""),
    (0x60C5, 0, "Max acceleration", UInt32, RW, false, I32_MAX, 0, 10_000, "count/s²"),
    (0x60C6, 0, "Max deceleration", UInt32, RW, false, I32_MAX, 0, 10_000, "count/s²"),
    (0x60F4, 0, "Following error actual value", Int32, RO, true, I32_MAX, I32_MIN, 0, "count"),
    (0x60FC, 0, "Position demand internal value", Int32, RO, false, I32_MAX, I32_MIN, 0, "count"),
    (0x60FD, 0, "Digital inputs", UInt32, RO, true, U32, 0, 0, ""),
    (0x60FE, 0, "Digital outputs: highest sub-index", UInt8, RO, true, U8, 0, 2, ""),
    (0x60FE, 1, "Physical outputs", UInt32, RW, true, U32, 0, 0, ""),
    (0x60FE, 2, "Bit mask", UInt32, RW, true, U32, 0, 0, ""),
    (0x60FF, 0, "Target velocity", Int32, RW, true, I32_MAX, I32_MIN, 0, "count/s"),
    (0x6502, 0, "Supported drive modes", UInt32, RO, false, U32, 0, 0x03AD, ""),
];

/// The position of an object in `OBJECTS`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ObjId(pub usize);

impl ObjId {
    pub fn def(self) -> &'static ObjectDef {
        &OBJECTS[self.0]
    }
}

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

/// Looks an object up. `None` for objects the table does not list.
pub fn find(index: u16, sub: u8) -> Option<ObjId> {
    OBJECTS.iter().position(|o| o.index == index && o.sub == sub).map(ObjId)
}

/// True when the index exists at all (some sub-index of it is listed).
pub fn index_exists(index: u16) -> bool {
    OBJECTS.iter().any(|o| o.index == index)
}

pub const DEVICE_TYPE: ObjId = id(0x1000, 0);
pub const ERROR_REGISTER: ObjId = id(0x1001, 0);
pub const SAVE_ALL_PARAMETERS: ObjId = id(0x1010, 1);
pub const PRODUCT_CODE: ObjId = id(0x1018, 2);
pub const RX_MAPPING_COUNT: ObjId = id(0x1600, 0);
pub const TX_MAPPING_COUNT: ObjId = id(0x1A00, 0);
pub const RX_ASSIGNMENT_COUNT: ObjId = id(0x1C12, 0);
pub const TX_ASSIGNMENT_COUNT: ObjId = id(0x1C13, 0);
pub const SYNC_TYPE: ObjId = id(0x1C32, 1);
pub const CYCLE_TIME: ObjId = id(0x1C32, 2);
pub const SYNC_TYPE_INPUTS: ObjId = id(0x1C33, 1);
pub const CYCLE_TIME_INPUTS: ObjId = id(0x1C33, 2);
pub const INDEX_SIGNAL: ObjId = id(0x2020, 0);
pub const LATCHED_INDEX_POSITION: ObjId = id(0x2021, 0);
pub const MOTOR_ACTUAL_CURRENT: ObjId = id(0x2022, 0);
pub const SOFTWARE_LIMIT_ENABLE: ObjId = id(0x2041, 0);
pub const HARDWARE_LIMIT_ENABLE: ObjId = id(0x2042, 0);
pub const ERROR_EVENTS_1: ObjId = id(0x2100, 0);
pub const ERROR_EVENTS_2: ObjId = id(0x2101, 0);
pub const ERROR_CODE: ObjId = id(0x603F, 0);
pub const CONTROLWORD: ObjId = id(0x6040, 0);
pub const STATUSWORD: ObjId = id(0x6041, 0);
pub const MODES_OF_OPERATION: ObjId = id(0x6060, 0);
pub const MODES_OF_OPERATION_DISPLAY: ObjId = id(0x6061, 0);
pub const POSITION_ACTUAL_INTERNAL: ObjId = id(0x6063, 0);
pub const POSITION_ACTUAL: ObjId = id(0x6064, 0);
pub const FOLLOWING_ERROR_WINDOW: ObjId = id(0x6065, 0);
pub const FOLLOWING_ERROR_TIMEOUT: ObjId = id(0x6066, 0);
pub const VELOCITY_ACTUAL: ObjId = id(0x606C, 0);
pub const TARGET_TORQUE: ObjId = id(0x6071, 0);
pub const MOTOR_RATED_CURRENT: ObjId = id(0x6075, 0);
pub const TORQUE_ACTUAL: ObjId = id(0x6077, 0);
pub const TARGET_POSITION: ObjId = id(0x607A, 0);
pub const HOME_OFFSET: ObjId = id(0x607C, 0);
pub const MIN_SOFTWARE_LIMIT: ObjId = id(0x607D, 1);
pub const MAX_SOFTWARE_LIMIT: ObjId = id(0x607D, 2);
pub const MAX_PROFILE_VELOCITY: ObjId = id(0x607F, 0);
pub const PROFILE_VELOCITY: ObjId = id(0x6081, 0);
pub const PROFILE_ACCELERATION: ObjId = id(0x6083, 0);
pub const PROFILE_DECELERATION: ObjId = id(0x6084, 0);
pub const QUICK_STOP_DECELERATION: ObjId = id(0x6085, 0);
pub const TORQUE_SLOPE: ObjId = id(0x6087, 0);
pub const HOMING_METHOD: ObjId = id(0x6098, 0);
pub const HOMING_SPEED_SWITCH: ObjId = id(0x6099, 1);
pub const HOMING_SPEED_ZERO: ObjId = id(0x6099, 2);
pub const HOMING_ACCELERATION: ObjId = id(0x609A, 0);
pub const TOUCH_PROBE_FUNCTION: ObjId = id(0x60B8, 0);
pub const TOUCH_PROBE_STATUS: ObjId = id(0x60B9, 0);
pub const TOUCH_PROBE_1_POSITIVE: ObjId = id(0x60BA, 0);
pub const TOUCH_PROBE_1_NEGATIVE: ObjId = id(0x60BB, 0);
pub const MAX_ACCELERATION: ObjId = id(0x60C5, 0);
pub const MAX_DECELERATION: ObjId = id(0x60C6, 0);
pub const FOLLOWING_ERROR_ACTUAL: ObjId = id(0x60F4, 0);
pub const POSITION_DEMAND_INTERNAL: ObjId = id(0x60FC, 0);
pub const DIGITAL_INPUTS: ObjId = id(0x60FD, 0);
pub const PHYSICAL_OUTPUTS: ObjId = id(0x60FE, 1);
pub const OUTPUT_MASK: ObjId = id(0x60FE, 2);
pub const TARGET_VELOCITY: ObjId = id(0x60FF, 0);

/// The values of one drive's objects. Objects of other models read as absent.
#[derive(Clone, Debug)]
pub struct ObjectStore {
    model: DriveModel,
    values: Vec<i64>,
}

impl ObjectStore {
    /// Power-up values: the manual's defaults, with the model's product code.
    pub fn new(model: DriveModel) -> Self {
        let mut values: Vec<i64> = OBJECTS.iter().map(ObjectDef::default_value).collect();
        values[PRODUCT_CODE.0] = model.product_code() as i64;
        ObjectStore { model, values }
    }

    pub fn model(&self) -> DriveModel {
        self.model
    }

    /// Whether this drive has the object (table 4-22).
    pub fn has(&self, id: ObjId) -> bool {
        id.def().models.includes(self.model)
    }

    pub fn get(&self, id: ObjId) -> i64 {
        self.values[id.0]
    }

    /// A REAL32 object's value.
    pub fn get_f32(&self, id: ObjId) -> f32 {
        f32::from_bits(self.values[id.0] as u32)
    }

    /// Sets a value from the drive's own logic (no access or range check).
    pub fn set(&mut self, id: ObjId, value: i64) {
        self.values[id.0] = value;
    }

    pub fn set_f32(&mut self, id: ObjId, value: f32) {
        self.values[id.0] = value.to_bits() as i64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_is_sorted_unique_and_its_defaults_in_range() {
        for pair in OBJECTS.windows(2) {
            assert!(
                (pair[0].index, pair[0].sub) < (pair[1].index, pair[1].sub),
                "{:#06x}:{}",
                pair[1].index,
                pair[1].sub
            );
        }
        for o in OBJECTS {
            let value = o.ty.to_f64(o.default_value());
            let (lo, hi) = (o.min.min(o.max), o.min.max(o.max));
            assert!((lo..=hi).contains(&value) || o.access == Access::ReadOnly, "{:#06x}:{} default", o.index, o.sub);
        }
    }

    /// REAL32 values travel as their IEEE bits.
    #[test]
    fn real32_defaults_are_stored_as_bits() {
        let store = ObjectStore::new(DriveModel::D1);
        assert_eq!(store.get_f32(id(0x2050, 0)), 0.3);
        assert_eq!(store.get_f32(id(0x2051, 0)), 0.001);
    }
}

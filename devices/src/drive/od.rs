//! The drive's object dictionary (CoE manual ch. 4): every object of tables 4-1 (common),
//! 4-3 (PDO mapping), 4-4 (SyncManager), 4-6 (manufacturer) and 4-15 (device profile),
//! with its type, access, PDO mappability, range, default and the models that have it
//! (table 4-22). Choices where the tables contradict themselves are in docs/drive.md.
//! This is the drive's data; the machinery (types, access, the store) is `crate::coe`.
//!
//! The drive uses `ObjId` constants resolved at compile time.

use crate::coe::{ALL_VARIANTS, Access, ObjectDef};
use crate::coe::{ObjId, ObjectStore};
use crate::drive::DriveModel;
use config::TouchProbeKind;

/// The drive models an object exists on (CoE manual table 4-22).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Models {
    All,
    NotD1N,
    NotD1NNorAbily,
    /// A drive with the CiA 402 touch probe (docs/decisions.md, "Touch probe").
    TouchProbe2,
}

impl Models {
    /// The models as the store's variant bits.
    const fn variants(self) -> u32 {
        match self {
            Models::All => ALL_VARIANTS,
            Models::NotD1N => MODELS & !variant(DriveModel::D1N),
            Models::NotD1NNorAbily => MODELS & !(variant(DriveModel::D1N) | variant(DriveModel::Abily)),
            Models::TouchProbe2 => TOUCH_PROBE_2,
        }
    }
}

/// A model's bit in `ObjectDef::variants`.
const fn variant(model: DriveModel) -> u32 {
    1 << model as u32
}

/// The models' bits; a store's variant is its model's bit, plus `TOUCH_PROBE_2` for a
/// drive with the CiA 402 touch probe, so a row of some models must not match that bit.
const MODELS: u32 = 0xFF;
const TOUCH_PROBE_2: u32 = 1 << 8;

use crate::coe::DataType::*;
use Access::{ReadOnly as RO, ReadWrite as RW};

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
            variants: rows!(@models $($models)?).variants(),
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
    // The second PDO per direction (docs/decisions.md, "Second PDO").
    (0x1601, 0, "2nd receive PDO mapping: number of objects", UInt8, RW, false, 7, 0, 0, ""),
    (0x1601, 1, "2nd RxPDO mapping entry 1", UInt32, RW, false, U32, 0, 0, ""),
    (0x1601, 2, "2nd RxPDO mapping entry 2", UInt32, RW, false, U32, 0, 0, ""),
    (0x1601, 3, "2nd RxPDO mapping entry 3", UInt32, RW, false, U32, 0, 0, ""),
    (0x1601, 4, "2nd RxPDO mapping entry 4", UInt32, RW, false, U32, 0, 0, ""),
    (0x1601, 5, "2nd RxPDO mapping entry 5", UInt32, RW, false, U32, 0, 0, ""),
    (0x1601, 6, "2nd RxPDO mapping entry 6", UInt32, RW, false, U32, 0, 0, ""),
    (0x1601, 7, "2nd RxPDO mapping entry 7", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A00, 0, "1st transmit PDO mapping: number of objects", UInt8, RW, false, 7, 0, 3, ""),
    (0x1A00, 1, "TxPDO mapping entry 1", UInt32, RW, false, U32, 0, 0x6041_0010u32, ""),
    (0x1A00, 2, "TxPDO mapping entry 2", UInt32, RW, false, U32, 0, 0x6064_0020u32, ""),
    (0x1A00, 3, "TxPDO mapping entry 3", UInt32, RW, false, U32, 0, 0x60F4_0020u32, ""),
    (0x1A00, 4, "TxPDO mapping entry 4", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A00, 5, "TxPDO mapping entry 5", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A00, 6, "TxPDO mapping entry 6", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A00, 7, "TxPDO mapping entry 7", UInt32, RW, false, U32, 0, 0, ""),
    // The second PDO per direction (docs/decisions.md, "Second PDO").
    (0x1A01, 0, "2nd transmit PDO mapping: number of objects", UInt8, RW, false, 7, 0, 0, ""),
    (0x1A01, 1, "2nd TxPDO mapping entry 1", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A01, 2, "2nd TxPDO mapping entry 2", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A01, 3, "2nd TxPDO mapping entry 3", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A01, 4, "2nd TxPDO mapping entry 4", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A01, 5, "2nd TxPDO mapping entry 5", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A01, 6, "2nd TxPDO mapping entry 6", UInt32, RW, false, U32, 0, 0, ""),
    (0x1A01, 7, "2nd TxPDO mapping entry 7", UInt32, RW, false, U32, 0, 0, ""),
    // Table 4-4: SyncManager communication objects.
    (0x1C00, 0, "SM comm type: number of used SMs", UInt8, RO, false, U8, 0, 4, ""),
    (0x1C00, 1, "Comm type SM0", UInt8, RO, false, U8, 0, 1, ""),
    (0x1C00, 2, "Comm type SM1", UInt8, RO, false, U8, 0, 2, ""),
    (0x1C00, 3, "Comm type SM2", UInt8, RO, false, U8, 0, 3, ""),
    (0x1C00, 4, "Comm type SM3", UInt8, RO, false, U8, 0, 4, ""),
    (0x1C10, 0, "SM0 PDO assignment", UInt8, RO, false, U8, 0, 0, ""),
    (0x1C11, 0, "SM1 PDO assignment", UInt8, RO, false, U8, 0, 0, ""),
    (0x1C12, 0, "SM2 PDO assignment: number of assigned RxPDOs", UInt8, RW, false, 2, 0, 1, ""),
    (0x1C12, 1, "PDO mapping index of assigned RxPDO 1", UInt16, RW, false, 0x1601, 0x1600, 0x1600, ""),
    (0x1C12, 2, "PDO mapping index of assigned RxPDO 2", UInt16, RW, false, 0x1601, 0x1600, 0x1601, ""),
    (0x1C13, 0, "SM3 PDO assignment: number of assigned TxPDOs", UInt8, RW, false, 2, 0, 1, ""),
    (0x1C13, 1, "PDO mapping index of assigned TxPDO 1", UInt16, RW, false, 0x1A01, 0x1A00, 0x1A00, ""),
    (0x1C13, 2, "PDO mapping index of assigned TxPDO 2", UInt16, RW, false, 0x1A01, 0x1A00, 0x1A01, ""),
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
    (0x60BC, 0, "Touch probe 2 positive edge", Int32, RO, true, I32_MAX, I32_MIN, 0, "count", TouchProbe2),
    (0x60BD, 0, "Touch probe 2 negative edge", Int32, RO, true, I32_MAX, I32_MIN, 0, "count", TouchProbe2),
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

/// Resolves an object of the drive at compile time; a missing object fails the build.
pub const fn id(index: u16, sub: u8) -> ObjId {
    crate::coe::id(OBJECTS, index, sub)
}

pub const ERROR_REGISTER: ObjId = id(0x1001, 0);
pub const SAVE_ALL_PARAMETERS: ObjId = id(0x1010, 1);
pub const PRODUCT_CODE: ObjId = id(0x1018, 2);
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
pub const TOUCH_PROBE_2_POSITIVE: ObjId = id(0x60BC, 0);
pub const TOUCH_PROBE_2_NEGATIVE: ObjId = id(0x60BD, 0);
pub const MAX_ACCELERATION: ObjId = id(0x60C5, 0);
pub const MAX_DECELERATION: ObjId = id(0x60C6, 0);
pub const FOLLOWING_ERROR_ACTUAL: ObjId = id(0x60F4, 0);
pub const POSITION_DEMAND_INTERNAL: ObjId = id(0x60FC, 0);
pub const DIGITAL_INPUTS: ObjId = id(0x60FD, 0);
pub const PHYSICAL_OUTPUTS: ObjId = id(0x60FE, 1);
pub const OUTPUT_MASK: ObjId = id(0x60FE, 2);
pub const TARGET_VELOCITY: ObjId = id(0x60FF, 0);

/// A drive's dictionary at power-up: the manual's defaults, with the model's product code;
/// 0x60BC/0x60BD only with the CiA 402 touch probe.
pub fn store(model: DriveModel, touch_probe: TouchProbeKind) -> ObjectStore {
    let probe = if touch_probe == TouchProbeKind::Cia402 { TOUCH_PROBE_2 } else { 0 };
    let mut store = ObjectStore::new(OBJECTS, variant(model) | probe);
    store.set(PRODUCT_CODE, model.product_code() as i64);
    store
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coe::DataType;
    use crate::ecat::mailbox::{SdoAbort, check_download, upload};

    fn d1() -> ObjectStore {
        store(DriveModel::D1, TouchProbeKind::Index)
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
        let d1n = store(DriveModel::D1N, TouchProbeKind::Cia402);
        assert_eq!(upload(&d1n, 0x6075, 0), Err(SdoAbort::NoObject));
        assert_eq!(upload(&d1n, 0x2060, 0), Err(SdoAbort::NoObject));
        assert_eq!(upload(&store(DriveModel::Abily, TouchProbeKind::Cia402), 0x2110, 0), Err(SdoAbort::NoObject));
        assert!(upload(&store(DriveModel::D2, TouchProbeKind::Index), 0x2110, 0).is_ok());
        assert!(upload(&d1n, 0x60BC, 0).is_ok(), "a CiA 402 touch probe has 0x60BC");
    }

    #[test]
    fn real32_range_is_checked_on_the_number() {
        let gain = |v: f32| check_download(&d1(), 0x2050, 0, &v.to_bits().to_le_bytes()).map(|_| ());
        assert_eq!(gain(20.0), Err(SdoAbort::ValueTooHigh), "common gain max 10");
        assert_eq!(gain(0.001), Err(SdoAbort::ValueTooLow), "common gain min 0.01");
        assert_eq!(gain(1.5), Ok(()));
    }

    /// The second PDO per direction: assignable in 0x1C12/0x1C13, empty until mapped.
    #[test]
    fn a_second_pdo_per_direction() {
        let store = d1();
        for (assignment, second) in [(0x1C12, 0x1601u16), (0x1C13, 0x1A01)] {
            assert_eq!(upload(&store, assignment, 0), Ok((1, 1)), "only the first assigned by default");
            assert_eq!(upload(&store, assignment, 2), Ok((second as i64, 2)));
            assert_eq!(upload(&store, second, 0), Ok((0, 1)), "0x{second:04X} maps nothing by default");
            assert_eq!(check_download(&store, assignment, 0, &[3]).map(|_| ()), Err(SdoAbort::ValueTooHigh));
            let next = (second + 1).to_le_bytes();
            assert_eq!(check_download(&store, assignment, 2, &next).map(|_| ()), Err(SdoAbort::ValueTooHigh));
        }
        assert_eq!(check_download(&store, 0x1C13, 1, &0x1601u16.to_le_bytes()).map(|_| ()), Err(SdoAbort::ValueTooLow));
        assert!(check_download(&store, 0x1A01, 7, &0x60BA_0020u32.to_le_bytes()).is_ok());
        assert_eq!(store.def(id(0x1A01, 1)).ty, DataType::UInt32);
    }

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
        let store = d1();
        assert_eq!(store.get_f32(id(0x2050, 0)), 0.3);
        assert_eq!(store.get_f32(id(0x2051, 0)), 0.001);
    }
}

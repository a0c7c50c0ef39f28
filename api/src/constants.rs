//! Global constants of the script environment.

/// A numeric constant a script sees as a global.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Constant {
    /// A Lua integer.
    Int(i64),
    /// A Lua float.
    Double(f64),
    /// A Lua string.
    Str(&'static str),
}

/// HMPL ch. 23.1 math constants, ch. 1.4 truth values and limits, the DRL `CR_LF`.
pub const CONSTANTS: &[(&str, Constant, &str)] = &[
    ("PI", Constant::Double(std::f64::consts::PI), "HMPL 23.1"),
    ("SQRT2", Constant::Double(std::f64::consts::SQRT_2), "HMPL 23.1"),
    ("SQRT1_2", Constant::Double(std::f64::consts::FRAC_1_SQRT_2), "HMPL 23.1"),
    ("TRUE", Constant::Int(1), "HMPL 1.4"),
    ("FALSE", Constant::Int(0), "HMPL 1.4"),
    ("HMPL_STR_MAX_LEN", Constant::Int(512), "HMPL 3.1"),
    ("CR_LF", Constant::Str("\r\n"), "DXMC 8.3 DRL"),
    ("HMPL_SLOT_1", Constant::Int(1 << 16), "HMPL 9.1 (value: luamotion)"),
    ("HMPL_SLOT_2", Constant::Int(2 << 16), "HMPL 9.1 (value: luamotion)"),
    ("HMPL_SLOT_3", Constant::Int(3 << 16), "HMPL 9.1 (value: luamotion)"),
    ("HMPL_SLOT_4", Constant::Int(4 << 16), "HMPL 9.1 (value: luamotion)"),
];

/// `HOME_METHOD_n` (HMPL 20.1) and `HMPL_AXIS_n` (HMPL 23) as globals.
pub fn numbered() -> impl Iterator<Item = (String, i64)> {
    let methods = [1, 2, 7, 8, 9, 10, 11, 12, 13, 14, 17, 18, 23, 24, 25, 26, 27, 28, 29, 30, 33, 34, 37];
    let homes = methods.into_iter().map(|m| (format!("HOME_METHOD_{m}"), m));
    let axes = (0..16).map(|a| (format!("HMPL_AXIS_{a}"), a));
    homes.chain(axes)
}

/// `slv_slot_id`: the slave id in the low 16 bits, `HMPL_SLOT_n` = n << 16 above them.
pub fn split_slave_slot(slv_slot_id: i64) -> (i64, i64) {
    (slv_slot_id & 0xFFFF, slv_slot_id >> 16)
}

/// Every error code name of HMPL ch. 18 with its error id (`EEEE`); scripts combine it
/// with the axis or group id, or compare `GetAxisLastErr(a) & 0xFFFF` with it.
pub fn error_ids() -> impl Iterator<Item = (&'static str, u16)> {
    use crate::errors::{AxisError, GroupError, SystemError};
    let system = SystemError::ALL.iter().map(|e| (e.name(), e.id()));
    let axis = AxisError::ALL.iter().map(|e| (e.name(), e.id()));
    let group = GroupError::ALL.iter().map(|e| (e.name(), e.id()));
    system.chain(axis).chain(group)
}

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
    // The manual names the group constants without their numbers (docs/decisions.md, "Groups").
    ("BM_BUFF", Constant::Int(0), "HMPL table 8.1.4.1 (value: luamotion)"),
    ("BM_ABORT", Constant::Int(1), "HMPL table 8.1.4.1 (value: luamotion)"),
    ("BM_LOW", Constant::Int(2), "HMPL table 8.1.4.1 (value: luamotion)"),
    ("BM_PREV", Constant::Int(3), "HMPL table 8.1.4.1 (value: luamotion)"),
    ("BM_NEXT", Constant::Int(4), "HMPL table 8.1.4.1 (value: luamotion)"),
    ("BM_HIGH", Constant::Int(5), "HMPL table 8.1.4.1 (value: luamotion)"),
    ("BM_LOOKAHEAD", Constant::Int(6), "HMPL table 8.1.4.1 (value: luamotion)"),
    ("TM_NONE", Constant::Int(0), "HMPL table 8.1.5.1 (value: luamotion)"),
    ("TM_CONST_VEL", Constant::Int(1), "HMPL table 8.1.5.1 (value: luamotion)"),
    ("TM_CORNER_DIST", Constant::Int(2), "HMPL table 8.1.5.1 (value: luamotion)"),
    ("TM_MAX_CORNER_DEV", Constant::Int(3), "HMPL table 8.1.5.1 (value: luamotion)"),
    ("TM_MAX_CORNER_CURV", Constant::Int(4), "HMPL table 8.1.5.1 (value: luamotion)"),
    ("TM_START_VEL", Constant::Int(5), "HMPL table 8.1.5.1, not available (value: luamotion)"),
    ("CS_MCS", Constant::Int(0x1), "HMPL table 8.1.2.1 (value: luamotion)"),
    ("CS_PCS", Constant::Int(0x2), "HMPL table 8.1.2.1 (value: luamotion)"),
    ("CS_OFFSET", Constant::Int(0x4), "HMPL table 8.1.2.1 (value: luamotion)"),
    ("CS_GLOBAL", Constant::Int(0x8), "HMPL table 8.1.2.1, not supported (value: luamotion)"),
    ("CS_ACS", Constant::Int(0x10), "HMPL table 8.1.2.1 (value: luamotion)"),
    ("SHAPER_NORMAL", Constant::Int(1), "HMPL 15.7"),
    ("SHAPER_ROBUST", Constant::Int(0), "HMPL 15.7"),
    // HMPL table 10.1.1 and 10.4.1: analog conversion types and the variables an output
    // follows (`crate::analog`, whose tests hold these values to its own).
    ("HMPL_DAC_NONE", Constant::Int(0), "HMPL table 10.1.1 (value: luamotion)"),
    ("HMPL_DAC_N10_P10", Constant::Int(1), "HMPL table 10.1.1 (value: luamotion)"),
    ("HMPL_DAC_P0_P10", Constant::Int(2), "HMPL table 10.1.1 (value: luamotion)"),
    ("HMPL_DAC_N5_P5", Constant::Int(3), "HMPL table 10.1.1 (value: luamotion)"),
    ("HMPL_DAC_P0_P5", Constant::Int(4), "HMPL table 10.1.1 (value: luamotion)"),
    ("HMPL_DAC_P0_P20", Constant::Int(5), "HMPL table 10.1.1 (value: luamotion)"),
    ("HMPL_DAC_P4_P20", Constant::Int(6), "HMPL table 10.1.1 (value: luamotion)"),
    ("HMPL_DAC_N20_P20", Constant::Int(7), "HMPL table 10.1.1 (value: luamotion)"),
    ("HMPL_DAC_SIGNED", Constant::Int(0x100), "HMPL table 10.1.1 (value: luamotion)"),
    ("HMPL_REF_POS", Constant::Int(0x100), "HMPL 10.4.1 (value: luamotion)"),
    ("HMPL_REF_VEL", Constant::Int(0x200), "HMPL 10.4.1 (value: luamotion)"),
    ("HMPL_REF_ACC", Constant::Int(0x300), "HMPL 10.4.1 (value: luamotion)"),
    ("HMPL_POS_FB", Constant::Int(0x400), "HMPL 10.4.1 (value: luamotion)"),
    ("HMPL_VEL_FB", Constant::Int(0x500), "HMPL 10.4.1 (value: luamotion)"),
    ("HMPL_ACC_FB", Constant::Int(0x600), "HMPL 10.4.1 (value: luamotion)"),
    ("HMPL_CUR_FB", Constant::Int(0x700), "HMPL 10.4.1 (value: luamotion)"),
];

/// `HOME_METHOD_n` (HMPL 20.1), `HMPL_AXIS_n` (HMPL 23) and `CS_WCSn` (HMPL 8.1.2) as globals.
pub fn numbered() -> impl Iterator<Item = (String, i64)> {
    let methods = [1, 2, 7, 8, 9, 10, 11, 12, 13, 14, 17, 18, 23, 24, 25, 26, 27, 28, 29, 30, 33, 34, 37];
    let homes = methods.into_iter().map(|m| (format!("HOME_METHOD_{m}"), m));
    let axes = (0..16).map(|a| (format!("HMPL_AXIS_{a}"), a));
    // HMPL table 8.1.2.1: the 15 workpiece systems, a 4-bit field above the flags.
    let workpieces = (1..=15).map(|n| (format!("CS_WCS{n}"), n << 8));
    homes.chain(axes).chain(workpieces)
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

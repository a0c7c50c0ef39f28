//! HMPL 17.1: the controller variables a program reaches by HCV id (`0xCCIIVVVV`: class
//! `CC` 0x00 system, 0x83 axis, 0x82 group; `II` the axis or group; `VVVV` the variable)
//! with `GetConfigVar` and `SetConfigVar`. luamotion has the ones below; an axis or group
//! variable is read and written through the registry's own getter and setter, so it is
//! checked and refused exactly as they are.

use crate::{Command, Query};

/// A system variable of HMPL table 17.1.1.1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SystemHcv {
    /// `HCV_ID_fclk` 0x012C: controller cycles (read-only).
    Fclk,
    /// `HCV_ID_timeInMs` 0x012E: controller time, ms (read-only).
    TimeInMs,
    /// `HCV_ID_ltest0..9` 0x2328..0x2331.
    LTest(usize),
    /// `HCV_ID_dtest0..9` 0x235A..0x2363.
    DTest(usize),
}

/// An axis or group variable: its `VVVV`, its manual name, its getter and its setter (none:
/// read-only). The getter and setter take the axis or group id first; the setter the value
/// second.
#[derive(Clone, Copy, Debug)]
pub struct MemberVar {
    /// `VVVV`.
    pub vvvv: u16,
    /// The manual's name, e.g. `HCV_ID_sw_RL`.
    pub name: &'static str,
    /// The query that reads it.
    pub get: Query,
    /// The command that writes it.
    pub set: Option<Command>,
}

/// A variable an HCV id names.
#[derive(Clone, Copy, Debug)]
pub enum Hcv {
    /// A system variable.
    System(SystemHcv),
    /// Variable `var` of axis or group `id`.
    Member {
        /// The axis or group id (`II`).
        id: i64,
        /// The variable.
        var: &'static MemberVar,
    },
}

const fn var(vvvv: u16, name: &'static str, get: Query, set: Option<Command>) -> MemberVar {
    MemberVar { vvvv, name, get, set }
}

/// HMPL table 17.1.1.2: the axis variables luamotion has (class 0x83).
pub const AXIS_VARS: &[MemberVar] = &[
    var(0x0033, "HCV_ID_pos_tr", Query::GetPosWindow, Some(Command::SetPosWindow)),
    var(0x0034, "HCV_ID_pos_tr_t", Query::GetPosWindowTime, Some(Command::SetPosWindowTime)),
    var(0x0065, "HCV_ID_sw_RL", Query::GetSWRL, Some(Command::SetSWRL)),
    var(0x0066, "HCV_ID_sw_LL", Query::GetSWLL, Some(Command::SetSWLL)),
    var(0x00A0, "HCV_ID_home_status", Query::IsHomed, Some(Command::SetHomedStatus)),
    var(0x00D3, "HCV_ID_max_vel", Query::GetVel, Some(Command::SetVel)),
    var(0x00D4, "HCV_ID_max_acc", Query::GetAcc, Some(Command::SetAcc)),
    var(0x00D5, "HCV_ID_max_dec", Query::GetDec, Some(Command::SetDec)),
    var(0x00D7, "HCV_ID_sm_factor", Query::GetSMTime, Some(Command::SetSMTime)),
    var(0x00DB, "HCV_ID_vel_scale", Query::GetVelScale, Some(Command::SetVelScale)),
    var(0x0117, "HCV_ID_rollover_turns", Query::GetRolloverTurns, None),
    var(0x0193, "HCV_ID_gant_pair", Query::GetGantryPairID, None),
    var(0x0263, "HCV_ID_last_err", Query::GetAxisLastErr, None),
    var(0x03C2, "HCV_ID_gear_ratio", Query::GetGearRatio, None),
];

/// HMPL table 17.1.1.3: the group variables luamotion has (class 0x82).
pub const GROUP_VARS: &[MemberVar] = &[
    var(0x00DD, "HCV_ID_grp_lin_vel", Query::GetGrpVel, Some(Command::SetGrpVel)),
    var(0x00DE, "HCV_ID_grp_lin_acc", Query::GetGrpAcc, Some(Command::SetGrpAcc)),
    var(0x00DF, "HCV_ID_grp_lin_dec", Query::GetGrpDec, Some(Command::SetGrpDec)),
    var(0x00E0, "HCV_ID_grp_lin_sf", Query::GetGrpSMTime, Some(Command::SetGrpSMTime)),
    var(0x00F1, "HCV_ID_grp_coord_sys", Query::GetGrpCoordSys, Some(Command::SetGrpCoordSys)),
    var(0x00F2, "HCV_ID_grp_buffer_mode", Query::GetGrpBufferMode, Some(Command::SetGrpBufferMode)),
    var(0x00F3, "HCV_ID_grp_trans_mode", Query::GetGrpTransMode, Some(Command::SetGrpTransMode)),
    var(0x0104, "HCV_ID_grp_vel_scale", Query::GetGrpVelScale, Some(Command::SetGrpVelScale)),
    var(0x038F, "HCV_ID_grp_last_err", Query::GetGrpLastErr, None),
];

/// HMPL table 17.1.1.1: the system variables luamotion has, with their ids.
pub const SYSTEM_VARS: &[(u32, &str, &str)] = &[
    (0x012C, "HCV_ID_fclk", "controller cycles (read-only)"),
    (0x012E, "HCV_ID_timeInMs", "controller time, ms (read-only)"),
    (0x2328, "HCV_ID_ltest0 .. HCV_ID_ltest9", "0x2328..0x2331: system_ltest0..9"),
    (0x235A, "HCV_ID_dtest0 .. HCV_ID_dtest9", "0x235A..0x2363: system_dtest0..9"),
];

const LTEST: u32 = 0x2328;
const DTEST: u32 = 0x235A;

/// The variable `hcv_id` names, if luamotion has it. The id is a C `int`: 0x83020065 may
/// come as that Lua integer or as its negative 32-bit value.
pub fn lookup(hcv_id: i64) -> Option<Hcv> {
    let id = u32::try_from(hcv_id).ok().or_else(|| i32::try_from(hcv_id).ok().map(|i| i as u32))?;
    let (class, member, vvvv) = (id >> 24, i64::from((id >> 16) & 0xFF), (id & 0xFFFF) as u16);
    let tests = crate::system_vars::TEST_VARS as u32;
    match class {
        0x00 if member == 0 => Some(Hcv::System(match id {
            0x012C => SystemHcv::Fclk,
            0x012E => SystemHcv::TimeInMs,
            _ if (LTEST..LTEST + tests).contains(&id) => SystemHcv::LTest((id - LTEST) as usize),
            _ if (DTEST..DTEST + tests).contains(&id) => SystemHcv::DTest((id - DTEST) as usize),
            _ => return None,
        })),
        0x83 => AXIS_VARS.iter().find(|v| v.vvvv == vvvv).map(|var| Hcv::Member { id: member, var }),
        0x82 => GROUP_VARS.iter().find(|v| v.vvvv == vvvv).map(|var| Hcv::Member { id: member, var }),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// HMPL 17.3.1, 17.3.2: the manual's ids, signed or not; the ids it lists that
    /// luamotion lacks are none of these.
    #[test]
    fn the_manuals_ids_name_their_variables() {
        let Some(Hcv::Member { id: 2, var }) = lookup(0x8302_0065) else { panic!("axis 2 SW right limit") };
        assert_eq!((var.name, var.get, var.set), ("HCV_ID_sw_RL", Query::GetSWRL, Some(Command::SetSWRL)));
        assert!(matches!(lookup(0x8300_0065_u32 as i32 as i64), Some(Hcv::Member { id: 0, .. })));
        assert!(matches!(lookup(0x820F_00DD), Some(Hcv::Member { id: 15, var }) if var.get == Query::GetGrpVel));
        assert!(matches!(lookup(0x0000_2331), Some(Hcv::System(SystemHcv::LTest(9)))));
        assert!(matches!(lookup(0x0000_235A), Some(Hcv::System(SystemHcv::DTest(0)))));
        assert!(matches!(lookup(0x0000_012C), Some(Hcv::System(SystemHcv::Fclk))));
        for missing in [0x0000_07D0, 0x0000_2332, 0x8300_0067, 0x8200_0002, 0x8100_0065, 0x0001_012C, -1, 1 << 40] {
            assert!(lookup(missing).is_none(), "0x{missing:X}");
        }
    }

    /// Every getter and setter takes the member's id first, and a setter a value second.
    #[test]
    fn getters_and_setters_take_the_id_and_the_value() {
        for v in AXIS_VARS.iter().chain(GROUP_VARS) {
            assert_eq!(v.get.spec().args.len(), 1, "{}", v.name);
            if let Some(set) = v.set {
                assert_eq!(set.spec().args.len(), 2, "{}", v.name);
            }
        }
    }
}

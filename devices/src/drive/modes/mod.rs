//! Modes of operation (CoE manual ch. 3, table 4-17): what the drive does in Operation
//! enabled, mode by mode. Each mode turns the controlword and its objects into a set-point
//! for the servo loops and reports its statusword bits 10, 12 and 13.

pub mod cyclic;
pub mod homing;
pub mod profile_position;
pub mod profile_torque;
pub mod profile_velocity;

use num_enum::{IntoPrimitive, TryFromPrimitive};

use crate::coe::{ObjId, ObjectStore};
use crate::drive::travel::{Edges, Travel};
use crate::profile::Kinematics;

/// 0x6060 values (CoE manual table 4-17); any other value is an error, which the drive
/// ignores (it keeps its mode).
#[derive(Clone, Copy, Debug, PartialEq, Eq, TryFromPrimitive, IntoPrimitive)]
#[repr(i8)]
pub enum ModeOfOperation {
    /// "Stand-alone mode" in table 4-17, "no mode" in the homing text: hold still.
    NoMode = 0,
    ProfilePosition = 1,
    ProfileVelocity = 3,
    ProfileTorque = 4,
    Homing = 6,
    CyclicSyncPosition = 8,
    CyclicSyncVelocity = 9,
    CyclicSyncTorque = 10,
}

impl ModeOfOperation {
    /// Software limits act in pp and csp only (CoE manual 3, "Limit functions by mode").
    pub fn software_limits_apply(self) -> bool {
        matches!(self, ModeOfOperation::ProfilePosition | ModeOfOperation::CyclicSyncPosition)
    }

    /// The following-error monitor runs in pp and csp (CoE manual 3.3.2).
    pub fn following_error_applies(self) -> bool {
        self.software_limits_apply()
    }
}

/// What a mode asks of the servo loops at the end of this cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Setpoint {
    /// Stay where the demand is.
    Hold,
    /// Be at `pos` with velocity `vel` (counts, counts/s, drive coordinates).
    Position { pos: f64, vel: f64 },
    /// Run at `vel` counts/s (velocity loop only).
    Velocity { vel: f64 },
    /// Produce a force, as a fraction of rated force.
    Force(f64),
}

/// Everything a mode reads in one cycle.
pub struct ModeInput<'a> {
    pub od: &'a ObjectStore,
    pub controlword: u16,
    /// The position demand at the end of the last cycle (drive coordinates).
    pub demand: Kinematics,
    pub actual: f64,
    pub actual_velocity: f64,
    /// The motor's force, as a fraction of rated force.
    pub force: f64,
    pub period_s: f64,
    /// Edges the motor crossed in the last cycle (raw coordinates).
    pub edges: &'a Edges,
    /// Drive coordinates = raw + shift.
    pub shift: f64,
    pub travel: &'a Travel,
}

impl ModeInput<'_> {
    pub fn halt(&self) -> bool {
        self.controlword & crate::cia402::controlword::HALT != 0
    }

    pub fn raw(&self, drive_position: f64) -> f64 {
        drive_position - self.shift
    }
}

/// Reads a UINT32 profile value, capped by a limit object where the limit is set (a
/// limit of 0 means "no limit": the manual's default of 0x607F would stop every move).
pub fn capped(od: &ObjectStore, value: ObjId, limit: ObjId) -> f64 {
    let v = od.get(value) as f64;
    let cap = od.get(limit) as f64;
    if cap > 0.0 { v.min(cap) } else { v }
}

#[cfg(test)]
mod tests {
    use super::ModeOfOperation;

    /// 0x6060 values, CoE manual table 4-17; the values it does not list are refused.
    #[test]
    fn mode_of_operation_codes() {
        use ModeOfOperation::*;
        let rows = [
            (NoMode, 0i8),
            (ProfilePosition, 1),
            (ProfileVelocity, 3),
            (ProfileTorque, 4),
            (Homing, 6),
            (CyclicSyncPosition, 8),
            (CyclicSyncVelocity, 9),
            (CyclicSyncTorque, 10),
        ];
        for (mode, code) in rows {
            assert_eq!(i8::from(mode), code, "{mode:?}");
            assert_eq!(ModeOfOperation::try_from(code), Ok(mode), "code {code}");
        }
        for code in [-1i8, 2, 5, 7, 11, i8::MIN, i8::MAX] {
            assert!(ModeOfOperation::try_from(code).is_err(), "code {code}");
        }
    }
}

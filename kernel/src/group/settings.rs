//! A group's settings (HMPL 8.3) and the ranges of its arguments (HMPL 8.3.6, 8.3.7,
//! 8.3.28, table 8.3.26.1), each refused with its code of table 18.1.3.1.

use crate::shaping::{GROUP_MIN_SHAPER_HZ, MAX_SHAPER_DAMPING};
use api::{GroupError, Quantity, Refusal};
use path::planner::{BufferMode, LookAhead, Motion, Profile};

/// HMPL 8.3.6: the linear (TCP) profile's defaults and limits.
pub const LIN_DEFAULT: Profile = Profile { vel: 100.0, acc: 5000.0, dec: 5000.0, smooth_ms: 50.0 };
const LIN_MAX_VEL: f64 = 5000.0;
const LIN_MAX_ACC: f64 = 50000.0;
/// HMPL 8.3.7: the angular profile's defaults and limits.
pub const ANG_DEFAULT: Profile = Profile { vel: 360.0, acc: 1800.0, dec: 1800.0, smooth_ms: 50.0 };
const ANG_MAX_VEL: f64 = 7200.0;
const ANG_MAX_ACC: f64 = 72000.0;
/// HMPL 8.3.6: the smooth time's limit, ms.
pub const MAX_SMOOTH_MS: f64 = 500.0;
/// A path coordinate's magnitude limit: far beyond any machine, short of losing precision.
const MAX_COORDINATE: f64 = 1e9;
/// The longest acceleration or deceleration time, ms: a minute, as an axis' (HMPL 5.3.5).
const MAX_TIME_MS: f64 = 60_000.0;
/// HMPL 8.3.35: the queue holds 2^n commands, n = 0..10; 512 by default (HMPL 8.1).
pub const DEFAULT_QUEUE_SIZE: usize = 512;
const MAX_QUEUE_EXPONENT: i64 = 10;

/// HMPL table 8.1.3.1: kinematics ids; only Cartesian is available.
pub const KIN_CARTESIAN: i64 = 1;

/// What a group's setters set, the defaults of HMPL 8.3 until then; a path command without
/// its own profile moves with them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroupSettings {
    /// The linear (TCP) profile, mm/s, mm/s², and the group's smooth time (HMPL 8.3.6).
    pub lin: Profile,
    /// The angular profile, deg/s, deg/s² (HMPL 8.3.7).
    pub ang: Profile,
    /// The buffer mode of later commands (HMPL 8.3.23).
    pub buffer: BufferMode,
    /// The velocity override, percent, 0 to 100 (HMPL 8.3.28).
    pub vel_scale: f64,
    /// SetGrpLookAheadPrm's parameters (HMPL 8.3.34).
    pub look_ahead: LookAhead,
}

impl Default for GroupSettings {
    fn default() -> Self {
        GroupSettings {
            lin: LIN_DEFAULT,
            ang: ANG_DEFAULT,
            buffer: BufferMode::Buff,
            vel_scale: 100.0,
            look_ahead: LookAhead::default(),
        }
    }
}

impl GroupSettings {
    /// The motion of a command that brings no profile of its own.
    pub fn motion(&self) -> Motion {
        Motion { lin: self.lin, ang: self.ang, buffer: self.buffer }
    }

    /// HMPL 8.3.23: BM_BUFF .. BM_LOOKAHEAD (docs/decisions.md: the manual's "0 ~ 5" leaves out
    /// BM_LOOKAHEAD, which it names).
    pub fn set_buffer_mode(&mut self, mode: i64) -> Result<(), GroupError> {
        self.buffer = BufferMode::try_from(mode)?;
        Ok(())
    }

    /// HMPL 8.3.14: acc = vel / time, within the acceleration's range.
    pub fn set_acc_time(&mut self, ms: f64) -> Result<(), GroupError> {
        let acc = self.lin.vel / (ms / 1000.0);
        admit(Quantity::PathAcceleration, 0, acc)?;
        self.lin.acc = acc;
        Ok(())
    }

    /// HMPL 8.3.17: dec = vel / time, within the deceleration's range.
    pub fn set_dec_time(&mut self, ms: f64) -> Result<(), GroupError> {
        let dec = self.lin.vel / (ms / 1000.0);
        admit(Quantity::PathDeceleration, 0, dec)?;
        self.lin.dec = dec;
        Ok(())
    }

    /// HMPL 8.3.34: 0 corner acceleration, 1 arc acceleration, 2 chord error.
    pub fn set_look_ahead(&mut self, prm_id: i64, value: f64) -> Result<(), GroupError> {
        let la = &mut self.look_ahead;
        match prm_id {
            0 if value > 0.0 => la.corner_acc = value,
            1 if value > 0.0 => la.arc_acc = value,
            2 => la.chord_error = value,
            _ => return Err(GroupError::CmdLookaheadInvalidParam),
        }
        Ok(())
    }
}

/// HMPL 8.3.35: the queue size from its exponent n, 0..10.
pub fn queue_size(n: i64) -> Result<usize, GroupError> {
    if (0..=MAX_QUEUE_EXPONENT).contains(&n) { Ok(1 << n) } else { Err(GroupError::CmdInvalidQueueSize) }
}

/// HMPL 8.5: `motion_profile` {vel, acc, dec, smooth_time}, checked per element as
/// SetGrpMotionProfile's arguments.
pub fn profile_from(values: &[f64]) -> Result<Profile, GroupError> {
    let [vel, acc, dec, smooth_ms] = values else { return Err(GroupError::CmdLinInvalidParam) };
    Ok(Profile { vel: *vel, acc: *acc, dec: *dec, smooth_ms: *smooth_ms })
}

/// Whether `value`, the `index`-th number of a group-bound argument, is in its range.
pub fn admit(quantity: Quantity, index: usize, value: f64) -> Result<(), GroupError> {
    let within = |lo: f64, hi: f64| value >= lo && value <= hi;
    let above = |hi: f64| value > 0.0 && value <= hi;
    let ok = match quantity {
        Quantity::PathCoordinate => value.is_finite() && value.abs() <= MAX_COORDINATE,
        Quantity::PathAngle => value.is_finite() && value.abs() < MAX_COORDINATE,
        Quantity::PathVelocity => within(0.0, LIN_MAX_VEL),
        Quantity::PathAcceleration | Quantity::PathDeceleration => above(LIN_MAX_ACC),
        Quantity::PathSmoothTime | Quantity::AngularSmoothTime => within(0.0, MAX_SMOOTH_MS),
        Quantity::PathAccTime | Quantity::PathDecTime => value > 0.0 && value <= MAX_TIME_MS,
        Quantity::AngularVelocity => within(0.0, ANG_MAX_VEL),
        Quantity::AngularAcceleration | Quantity::AngularDeceleration => above(ANG_MAX_ACC),
        Quantity::PathVelScale => within(0.0, 100.0),
        Quantity::GroupJogVelocity => within(-ANG_MAX_VEL, ANG_MAX_VEL),
        Quantity::MotionProfile => {
            let q = [
                Quantity::PathVelocity,
                Quantity::PathAcceleration,
                Quantity::PathDeceleration,
                Quantity::PathSmoothTime,
            ];
            return q.get(index).map_or(Err(GroupError::CmdLinInvalidParam), |&q| admit(q, 0, value));
        }
        // A length on the path no longer than the coordinates reach; the mode's own ranges
        // (table 8.3.26.1) are checked with the mode.
        Quantity::TransitionParameter | Quantity::LookAheadParameter => within(0.0, MAX_COORDINATE),
        Quantity::GroupShaperFrequency => within(GROUP_MIN_SHAPER_HZ, 300.0),
        Quantity::GroupShaperDamping => within(0.0, MAX_SHAPER_DAMPING),
        _ => true,
    };
    match (ok, quantity.error()) {
        (true, _) => Ok(()),
        (false, Refusal::Group(e)) => Err(e),
        (false, Refusal::Axis(_) | Refusal::System(_)) => Err(GroupError::CmdUnknown),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// HMPL 8.3.6, 8.3.7, 8.3.28, 8.3.35: one row per bound, with the code it records.
    #[test]
    fn ranges_of_the_group_settings() {
        let rows: &[(Quantity, f64, Result<(), GroupError>, &str)] = &[
            (Quantity::PathVelocity, 5000.0, Ok(()), "HMPL 8.3.6 vel 0..5000"),
            (Quantity::PathVelocity, 5001.0, Err(GroupError::CmdInvalidLinVel), "HMPL 8.3.6"),
            (Quantity::PathVelocity, f64::NAN, Err(GroupError::CmdInvalidLinVel), "NaN"),
            (Quantity::PathAcceleration, 0.0, Err(GroupError::CmdInvalidLinAcc), "HMPL 8.3.6 acc > 0"),
            (Quantity::PathAcceleration, 50000.0, Ok(()), "HMPL 8.3.6 acc ..50000"),
            (Quantity::PathAcceleration, 50001.0, Err(GroupError::CmdInvalidLinAcc), "HMPL 8.3.6"),
            (Quantity::PathDeceleration, 0.0, Err(GroupError::CmdInvalidLinDec), "HMPL 8.3.6 dec > 0"),
            (Quantity::PathSmoothTime, 500.0, Ok(()), "HMPL 8.3.6 smooth 0..500"),
            (Quantity::PathSmoothTime, 501.0, Err(GroupError::CmdInvalidLinSmTime), "HMPL 8.3.6"),
            (Quantity::AngularVelocity, 7200.0, Ok(()), "HMPL 8.3.7 vel 0..7200"),
            (Quantity::AngularVelocity, 7201.0, Err(GroupError::CmdInvalidAngVel), "HMPL 8.3.7"),
            (Quantity::AngularAcceleration, 72001.0, Err(GroupError::CmdInvalidAngAcc), "HMPL 8.3.7"),
            (Quantity::AngularDeceleration, 0.0, Err(GroupError::CmdInvalidAngDec), "HMPL 8.3.7"),
            (Quantity::AngularSmoothTime, 501.0, Err(GroupError::CmdInvalidAngSmTime), "HMPL 8.3.7"),
            (Quantity::PathVelScale, 100.0, Ok(()), "HMPL 8.3.28 0..100"),
            (Quantity::PathVelScale, 100.5, Err(GroupError::CmdInvalidVelScale), "HMPL 8.3.28"),
            (Quantity::PathCoordinate, f64::INFINITY, Err(GroupError::CmdInvalidPos), "table 18.1.3.1 0x00D2"),
            (Quantity::PathAccTime, 60_000.0, Ok(()), "a minute, as an axis' (HMPL 5.3.5)"),
            (Quantity::PathAccTime, 60_001.0, Err(GroupError::CmdInvalidLinAcc), "HMPL 8.3.14"),
            (Quantity::PathDecTime, 0.0, Err(GroupError::CmdInvalidLinDec), "HMPL 8.3.17 ms > 0"),
            (Quantity::TransitionParameter, 1e30, Err(GroupError::CmdInvalidTransVel), "table 8.3.26.1"),
            (Quantity::LookAheadParameter, -1.0, Err(GroupError::CmdLookaheadInvalidParam), "HMPL 8.3.34"),
        ];
        for (q, v, want, reference) in rows {
            assert_eq!(admit(*q, 0, *v), *want, "{q:?} {v} ({reference})");
        }
        assert_eq!(admit(Quantity::MotionProfile, 0, 5001.0), Err(GroupError::CmdInvalidLinVel));
        assert_eq!(admit(Quantity::MotionProfile, 3, 501.0), Err(GroupError::CmdInvalidLinSmTime));
        assert_eq!(admit(Quantity::MotionProfile, 4, 1.0), Err(GroupError::CmdLinInvalidParam));
    }

    /// HMPL 8.3.35: 2^n for n in 0..10.
    #[test]
    fn queue_sizes() {
        assert_eq!(queue_size(0), Ok(1));
        assert_eq!(queue_size(3), Ok(8));
        assert_eq!(queue_size(10), Ok(1024));
        assert_eq!(queue_size(11), Err(GroupError::CmdInvalidQueueSize));
        assert_eq!(queue_size(-1), Err(GroupError::CmdInvalidQueueSize));
    }

    /// HMPL 8.3.14: the time gives the acceleration, which must be in range.
    #[test]
    fn acceleration_from_a_time() {
        let mut s = GroupSettings::default();
        s.set_acc_time(20.0).unwrap();
        assert_eq!(s.lin.acc, 5000.0);
        assert_eq!(s.set_acc_time(1.0), Err(GroupError::CmdInvalidLinAcc), "100 mm/s in 1 ms is 100000 mm/s²");
        assert_eq!(s.lin.acc, 5000.0, "a refused setting changes nothing");
    }

    /// HMPL 8.3.34: parameter ids 0..2.
    #[test]
    fn look_ahead_parameters() {
        let mut s = GroupSettings::default();
        assert_eq!(s.look_ahead, LookAhead { corner_acc: 5000.0, arc_acc: 100.0, chord_error: 0.0 });
        s.set_look_ahead(2, 0.01).unwrap();
        assert_eq!(s.look_ahead.chord_error, 0.01);
        assert_eq!(s.set_look_ahead(3, 1.0), Err(GroupError::CmdLookaheadInvalidParam));
        assert_eq!(s.set_look_ahead(0, 0.0), Err(GroupError::CmdLookaheadInvalidParam));
    }
}

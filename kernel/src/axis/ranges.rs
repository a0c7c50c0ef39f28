//! The ranges of what commands bring to an axis (`api::Quantity`, declared per argument
//! in the registry): `dispatch` checks every such argument here before the command runs,
//! so NaN, infinities and values no drive could carry never enter the kernel (issue 11).
//! Choices where the manual gives no range are in docs/decisions.md, "Axes".

use api::{AxisError, Quantity, Refusal};

use super::Axis;
use crate::settings::MAX_SMOOTH_TIME_MS;
use crate::shaping::{AXIS_MIN_SHAPER_HZ, MAX_SHAPER_DAMPING};

/// The longest time argument (acceleration, deceleration and in-position times, PVT
/// times), ms: beyond a minute it is a mistake of units, not a setting.
pub const MAX_TIME_MS: f64 = 60_000.0;

/// The largest gear ratio, either sign (HMPL 6.4 has `eERR_AXIS_CMD_INVALID_GEAR_RATIO`).
pub const MAX_GEAR_RATIO: f64 = 1000.0;

/// The drive's target torque 0x6071 is an INT16 in per mille of rated torque.
const MAX_TORQUE_PER_MILLE: f64 = i16::MAX as f64;

impl Axis {
    /// Checks one argument of a command against its quantity; records a refusal as the
    /// axis' last error.
    pub fn admit(&mut self, quantity: Quantity, value: f64) -> Result<(), AxisError> {
        match (self.in_range(quantity, value), quantity.error()) {
            (true, _) => Ok(()),
            (false, Refusal::Axis(error)) => Err(self.fail(error)),
            // Group-bound quantities are the group's (`motion/group/settings.rs`), free ones
            // dispatch's.
            (false, Refusal::Group(_) | Refusal::System(_)) => Err(self.fail(AxisError::CmdInvalidParameter)),
        }
    }

    /// Whether a value of `quantity` is in the axis' range, recording nothing (a group's
    /// command checks its axes' targets so, and records its own error).
    pub fn accepts(&self, quantity: Quantity, value: f64) -> bool {
        self.in_range(quantity, value)
    }

    fn in_range(&self, quantity: Quantity, v: f64) -> bool {
        let s = &self.settings;
        // One count, in units: the least length, speed and acceleration a drive can carry.
        let count = self.link.units(1.0);
        // Comparisons with NaN are false: NaN is out of every range.
        let within = |low: f64, high: f64| low <= v && v <= high;
        match quantity {
            Quantity::Axis => true,
            Quantity::Position => self.fits_counts(v),
            Quantity::Target => self.reachable(v),
            Quantity::Distance => v.is_finite() && self.reachable(self.heading() + v),
            Quantity::Length => within(count, self.link.units(i32::MAX as f64)),
            Quantity::Rollover => v == 0.0 || within(count, self.link.units(i32::MAX as f64)),
            Quantity::Speed => within(count, s.max_vel),
            Quantity::Velocity | Quantity::PvtVelocity => within(-s.max_vel, s.max_vel),
            Quantity::Acceleration | Quantity::Deceleration | Quantity::KillDeceleration => within(count, s.max_acc),
            Quantity::AccTime | Quantity::DecTime | Quantity::Time => v > 0.0 && v <= MAX_TIME_MS,
            Quantity::SmoothTime => within(0.0, MAX_SMOOTH_TIME_MS),
            Quantity::Percent => within(0.0, 100.0),
            Quantity::GearRatio => within(-MAX_GEAR_RATIO, MAX_GEAR_RATIO),
            Quantity::Torque => {
                // A drive without a force constant refuses MoveTrq with its own code.
                let per_mille = self.link.per_mille_per_nm;
                v.is_finite()
                    && (!(per_mille.is_finite() && per_mille > 0.0) || (v * per_mille).abs() <= MAX_TORQUE_PER_MILLE)
            }
            Quantity::PvtTime => within(0.0, MAX_TIME_MS),
            Quantity::VsfFrequency => within(0.1, 200.0),
            Quantity::VsfDamping => within(0.7, 1.5),
            Quantity::ShaperFrequency => within(AXIS_MIN_SHAPER_HZ, 300.0),
            Quantity::ShaperDamping => within(0.0, MAX_SHAPER_DAMPING),
            Quantity::CompTable => self.fits_counts(v),
            Quantity::Group
            | Quantity::PathCoordinate
            | Quantity::PathAngle
            | Quantity::PathVelocity
            | Quantity::PathAcceleration
            | Quantity::PathDeceleration
            | Quantity::PathSmoothTime
            | Quantity::PathAccTime
            | Quantity::PathDecTime
            | Quantity::AngularVelocity
            | Quantity::AngularAcceleration
            | Quantity::AngularDeceleration
            | Quantity::AngularSmoothTime
            | Quantity::PathVelScale
            | Quantity::GroupJogVelocity
            | Quantity::MotionProfile
            | Quantity::TransitionParameter
            | Quantity::LookAheadParameter
            | Quantity::GroupShaperFrequency
            | Quantity::GroupShaperDamping
            | Quantity::Finite => false,
        }
    }

    /// A coordinate the axis can show: at most `i32::MAX` counts either way.
    fn fits_counts(&self, units: f64) -> bool {
        self.link.counts(units).abs() <= i32::MAX as f64
    }

    /// A place the axis can go to: a coordinate, and with the offset a drive position.
    fn reachable(&self, units: f64) -> bool {
        self.fits_counts(units) && self.fits_counts(units + self.pos_offset)
    }

    /// Where a relative move counts from (HMPL 5.2.5, docs/decisions.md "MoveRel base").
    fn heading(&self) -> f64 {
        self.generator.end_of_queue()
    }

    /// The travel the drive's counts allow, in axis coordinates: `(left, right)`. Motion
    /// stops before either end as at a software limit, whatever is ignored.
    pub(super) fn count_range(&self) -> (f64, f64) {
        let max = self.link.units(i32::MAX as f64);
        ((-max).max(-max - self.pos_offset), max.min(max - self.pos_offset))
    }
}

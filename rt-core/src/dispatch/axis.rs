//! HMPL ch. 5 (axis motion and settings), 18 (an axis' last error) and 20 (homing).

use api::call::Doubles;
use api::{AxisError, ErrorCode, SystemError};

use super::{Done, Failure, Outcome, now};
use crate::machine::Machine;
use devices::ecat::AlState;
use kernel::axis::Axis;
use kernel::pvt::{MAX_POINTS, PvtPoint};
use kernel::settings::HomeSettings;

/// A motion command needs EtherCAT in Op (HMPL 2.2; `eERR_HMPL_NOT_IN_OP_MODE`).
pub(super) fn motion(m: &mut Machine, f: impl FnOnce(&mut Machine) -> Outcome) -> Outcome {
    if m.network.state() != AlState::Op {
        return Err(SystemError::HmplNotInOpMode.into());
    }
    f(m)
}

/// Runs an axis command on axis `a`.
pub(super) fn axis(m: &mut Machine, a: i64, f: impl FnOnce(&mut Axis) -> Result<(), AxisError>) -> Outcome {
    motion(m, |m| {
        let ax = m.kernel.axis_mut(a)?;
        let id = ax.id();
        now(f(ax).map_err(|e| ErrorCode::axis(id, e)))
    })
}

/// HMPL 20.4 to 20.7: a homing number, its range checked before (`check_ranges`).
pub(super) fn home_number(m: &mut Machine, a: i64, value: f64, field: fn(&mut HomeSettings) -> &mut f64) -> Outcome {
    axis(m, a, |ax| {
        ax.set_home(|h| {
            *field(h) = value;
            Ok(())
        })
    })
}

/// MovePVT's points from its time, position and velocity tables (at least `num_pt`
/// numbers each).
fn pvt_points(tables: [&Doubles; 3], num_pt: i64) -> Result<([PvtPoint; MAX_POINTS + 1], usize), Failure> {
    let count = usize::try_from(num_pt).map_err(|_| SystemError::HmplArgOutOfRange)?;
    if tables.iter().any(|t| t.len() < count) {
        return Err(SystemError::HmplArgOutOfRange.into());
    }
    let mut points = [PvtPoint::default(); MAX_POINTS + 1];
    // One more than allowed lets the axis refuse a table that is too long.
    let count = count.min(MAX_POINTS + 1);
    let [time, pos, vel] = tables;
    for (i, point) in points.iter_mut().enumerate().take(count) {
        match (time.get(i), pos.get(i), vel.get(i)) {
            (Some(ms), Some(pos), Some(vel)) => *point = PvtPoint { t: ms / 1000.0, pos, vel },
            _ => return Err(SystemError::HmplInvalidArg.into()),
        }
    }
    Ok((points, count))
}

/// HMPL 5.2.8: moves through the points of the three tables.
pub(super) fn move_pvt(m: &mut Machine, a: i64, tables: [&Doubles; 3], num_pt: i64) -> Outcome {
    let (points, count) = pvt_points(tables, num_pt)?;
    axis(m, a, |ax| ax.move_pvt(&points[..count]))
}

/// HMPL 20.2: starts the drive's homing; the call answers when it is over (`resume`).
/// Not while compensating (HMPL 14.1: the coordinates are fixed).
pub(super) fn move_home(m: &mut Machine, a: i64) -> Outcome {
    motion(m, |m| {
        m.kernel.keep_coordinates(a)?;
        let Machine { kernel, network, .. } = m;
        let ax = kernel.axis_mut(a)?;
        let id = ax.id();
        ax.start_homing(network).map_err(|e| ErrorCode::axis(id, e))?;
        Ok(Done::Later)
    })
}

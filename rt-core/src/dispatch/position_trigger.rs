//! HMPL ch. 12: the position trigger, on axes whose drive has one (`[axes.pt]`).

use api::{AxisError, ErrorCode, SystemError};
use ipc::call::Reply;

use super::{Done, Failure, Outcome};
use crate::machine::Machine;
use crate::position_trigger::{PositionTriggers, PtError};

/// Runs a PT function on axis `a` (checked to exist before). An axis without a trigger is
/// refused with 0x1451 and the others with the axis' code, kept as its last error
/// (docs/decisions.md, "Position trigger").
pub(super) fn trigger(
    m: &mut Machine,
    a: i64,
    f: impl FnOnce(&mut PositionTriggers, usize, bool) -> Result<(), PtError>,
) -> Outcome {
    let axis = m.kernel.axis_mut(a)?;
    let homed = axis.home_state().is_homed();
    match f(&mut m.triggers, a as usize, homed) {
        Ok(()) => Ok(Done::Now),
        Err(PtError::NoTrigger) => Err(SystemError::HmplNotSupported.into()),
        Err(e) => {
            let error = match e {
                PtError::NotHomed => AxisError::CmdInvalidState,
                _ => AxisError::CmdInvalidParameter,
            };
            Err(ErrorCode::axis(axis.id(), axis.fail(error)).into())
        }
    }
}

/// `GetPTPulse`: 0, the pulse's position and its time in ms.
pub(super) fn pulse(m: &mut Machine, a: i64, n: i64, reply: &mut Reply) -> Outcome {
    let mut found = None;
    trigger(m, a, |t, axis, _| {
        found = Some(t.pulse(axis, n)?);
        Ok(())
    })?;
    let pulse = found.ok_or(Failure::Code(SystemError::HmplInternalError.into()))?;
    reply.push_int(0);
    reply.push_double(pulse.pos);
    reply.push_double(pulse.time_ms);
    Ok(Done::Now)
}

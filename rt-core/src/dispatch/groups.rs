//! HMPL ch. 8: axis groups. Every command needs EtherCAT in Op, like the axes' motion.

use api::call::Doubles;
use api::{ErrorCode, GroupError};
use ipc::messages::Reply;

use super::{Outcome, axis::motion, now};
use crate::machine::Machine;
use crate::motion::Kernel;
use crate::motion::group::motion::{Advanced, PathCommand};

/// A group command that changes the machine.
pub(super) fn group(m: &mut Machine, f: impl FnOnce(&mut Kernel) -> Result<(), ErrorCode>) -> Outcome {
    motion(m, |m| now(f(&mut m.kernel)))
}

/// A path command in the group's present settings (HMPL 8.2.9 to 8.2.17).
pub(super) fn path(m: &mut Machine, group_id: i64, command: PathCommand) -> Outcome {
    motion(m, |m| now(m.kernel.move_group(group_id, command, None)))
}

/// A path command of HMPL 8.5 with its own profile, coordinate system, buffer and
/// transition modes.
pub(super) fn advanced(
    m: &mut Machine,
    group_id: i64,
    command: PathCommand,
    motion_profile: &Doubles,
    modes: [i64; 3],
    trans_par: &Doubles,
) -> Outcome {
    let [coord_sys, buff_mode, trans_mode] = modes;
    let profile: Vec<f64> = motion_profile.iter().collect();
    let trans: Vec<f64> = trans_par.iter().collect();
    motion(m, |m| {
        let advanced = Advanced::new(&profile, coord_sys, buff_mode, trans_mode, &trans);
        let result = match advanced {
            Ok(advanced) => m.kernel.move_group(group_id, command, Some(advanced)),
            Err(e) => Err(m.kernel.group_refusal(group_id, e)),
        };
        now(result)
    })
}

/// The six numbers of a pose or a transform, or `CmdLinInvalidParam` for a table of
/// another length.
pub(super) fn six(values: &Doubles) -> Result<[f64; 6], GroupError> {
    if values.len() < 6 {
        return Err(GroupError::CmdLinInvalidParam);
    }
    Ok(std::array::from_fn(|i| values.get(i).unwrap_or(0.0)))
}

/// The three numbers of a center or a normal vector.
pub(super) fn three(values: &Doubles) -> Result<[f64; 3], GroupError> {
    if values.len() < 3 {
        return Err(GroupError::CmdCircInvalidParam);
    }
    Ok(std::array::from_fn(|i| values.get(i).unwrap_or(0.0)))
}

/// `rc, {6 numbers}` of GetGrpCoordTrans, GetGrpPoseCmd, GetGrpPoseFb (HMPL 8.3.30, 8.3.32, 8.3.33).
pub(super) fn six_out(reply: &mut Reply, result: Result<[f64; 6], ErrorCode>) -> Outcome {
    let values = result?;
    reply.push_int(0);
    for v in values {
        reply.push_double(v);
    }
    Ok(super::Done::Now)
}

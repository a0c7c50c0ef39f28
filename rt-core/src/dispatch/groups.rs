//! HMPL ch. 8: axis groups. Every command needs EtherCAT in Op, like the axes' motion.

use api::call::Doubles;
use api::{ErrorCode, GroupError};
use ipc::call::Reply;

use super::{Outcome, axis::motion, now};
use crate::machine::Machine;
use kernel::Kernel;
use kernel::group::motion::{Advanced, PathCommand};

/// A group command that changes the machine.
pub(super) fn group(m: &mut Machine, f: impl FnOnce(&mut Kernel) -> Result<(), ErrorCode>) -> Outcome {
    motion(m, |m| now(f(&mut m.kernel)))
}

/// A path command in the group's present settings (HMPL 8.2.9 to 8.2.17).
pub(super) fn path(m: &mut Machine, group_id: i64, command: PathCommand) -> Outcome {
    motion(m, |m| now(m.kernel.move_group(group_id, command, None)))
}

/// A path command of HMPL 8.5 with its own profile, coordinate system, buffer and
/// transition modes; `command` is the refusal when its tables were short.
pub(super) fn advanced(
    m: &mut Machine,
    group_id: i64,
    command: Result<PathCommand, GroupError>,
    motion_profile: &Doubles,
    modes: [i64; 3],
    trans_par: &Doubles,
) -> Outcome {
    let [coord_sys, buff_mode, trans_mode] = modes;
    // Fixed arrays, not vectors: this runs on the RT thread (ARCHITECTURE invariant 2).
    let profile = first::<4>(motion_profile);
    let trans = first::<4>(trans_par);
    let advanced = command.and_then(|command| {
        let profile = profile.as_ref().map_or(&[][..], |p| &p[..]);
        let trans = trans.as_ref().map_or(&[][..], |t| &t[..]);
        Ok((command, Advanced::new(profile, coord_sys, buff_mode, trans_mode, trans)?))
    });
    motion(m, |m| {
        now(match advanced {
            Ok((command, advanced)) => m.kernel.move_group(group_id, command, Some(advanced)),
            Err(e) => Err(m.kernel.group_refusal(group_id, e)),
        })
    })
}

/// The first `N` numbers of a table, `None` for a shorter one.
fn first<const N: usize>(values: &Doubles) -> Option<[f64; N]> {
    (values.len() >= N).then(|| std::array::from_fn(|i| values.get(i).unwrap_or(0.0)))
}

/// The six numbers of a pose or a transform, or `CmdLinInvalidParam` for a table of
/// another length.
pub(super) fn six(values: &Doubles) -> Result<[f64; 6], GroupError> {
    first(values).ok_or(GroupError::CmdLinInvalidParam)
}

/// CircleAbs, CircleRel (HMPL 8.5.3, 8.5.4): a center and a normal of three numbers, a
/// target or distance of six.
pub(super) fn circle(
    center: &Doubles,
    normal: &Doubles,
    turns: i64,
    target: &Doubles,
    relative: bool,
) -> Result<PathCommand, GroupError> {
    let three = |v| first::<3>(v).ok_or(GroupError::CmdCircInvalidParam);
    Ok(PathCommand::Circle { center: three(center)?, normal: three(normal)?, turns, target: six(target)?, relative })
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

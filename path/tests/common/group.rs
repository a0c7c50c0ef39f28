//! How rt-core's group queues a command's segment (`queue_path`), for tests that drive the
//! planner as the group does: a corner transition (HMPL 8.1.5) trims the tail where the
//! planner says the path can still slow down for it, the blend follows at trans_vel
//! (TM_CONST_VEL, TM_CORNER_DIST), then the trimmed segment.

use path::blend::{self, TransitionMode, TransitionParams};
use path::{BufferMode, Limits, Motion, Planner, Segment};

/// What one command queued.
pub struct Queued {
    /// The tail as the blend trimmed it.
    pub trimmed_tail: Option<Segment>,
    /// The blend and its motion.
    pub blend: Option<(Segment, Motion)>,
    /// The command's own segment, trimmed where blended.
    pub segment: Segment,
}

pub fn queue(
    planner: &mut Planner,
    segment: Segment,
    motion: Motion,
    mode: TransitionMode,
    trans: &TransitionParams,
    limits: &Limits,
) -> Queued {
    let mut queued = Queued { trimmed_tail: None, blend: None, segment };
    if motion.buffer != BufferMode::Abort
        && let Some((prev, travelled)) = planner.tail()
        && let Some((trimmed, corner, next)) = blend::corner(&prev, &segment, mode, trans)
        && trimmed.length() > travelled * prev.length()
    {
        planner.replace_tail(trimmed);
        let mut blended = motion;
        if matches!(mode, TransitionMode::ConstVel | TransitionMode::CornerDist) {
            blended.lin.vel = trans.trans_vel.min(motion.lin.vel);
        }
        planner.push(corner, blended, limits).expect("room in the queue");
        (queued.trimmed_tail, queued.blend, queued.segment) = (Some(trimmed), Some((corner, blended)), next);
    }
    planner.push(queued.segment, motion, limits).expect("room in the queue");
    queued
}

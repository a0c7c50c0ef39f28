//! What the planner hands on each cycle: the raw pose and where it is along the path, with
//! the corners and jogs the group's smoothing needs. Its own module, so that the smoothing
//! takes the planner's output without depending on the planner.

use crate::segment::Pose;

/// One cycle's output: the raw pose (before the group's smoothing) and the path generator's
/// position, velocity and acceleration along the path (grp_pg_pos/vel/acc, HMPL table
/// 8.1.1.1). `moving`: the generator still emits (IsGrpMoving, HMPL 8.4.2).
///
/// For the group's smoothing along the path (HMPL 8.3.19): `corners`, the junctions the path
/// passed in this cycle without stopping where the segments do not join tangentially, and
/// `jog`, a jog (off any path) moved the pose.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample {
    /// The raw pose in MCS.
    pub pose: Pose,
    /// grp_pg_pos: the path length travelled since `Planner::rest_at`, jogs included, mm.
    pub path_pos: f64,
    /// grp_pg_vel: the velocity along the path, mm/s.
    pub path_vel: f64,
    /// grp_pg_acc: the acceleration along the path, mm/s².
    pub path_acc: f64,
    /// The generator still emits: a jog, velocity left, or queued segments not halted.
    pub moving: bool,
    /// The corners without a blend the path passed in this cycle.
    pub corners: Corners,
    /// A jog moved the pose in this cycle.
    pub jog: bool,
}

/// The corners passed in one cycle: the sum of their steps in the pose's rate along the
/// path (dPose/ds after minus before) and of each step times the path position (`path_pos`)
/// where it is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Corners {
    /// Σ step: the change of dPose/ds at the corners, per coordinate.
    pub step: Pose,
    /// Σ step·s_corner, per coordinate, mm.
    pub moment: Pose,
}

impl Corners {
    /// Counts one more corner, its step at path position `at`.
    pub(crate) fn add(&mut self, step: &[f64; 6], at: f64) {
        for ((sum, moment), &d) in self.step.iter_mut().zip(&mut self.moment).zip(step) {
            *sum += d;
            *moment += d * at;
        }
    }
}

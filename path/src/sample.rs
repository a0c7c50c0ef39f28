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
    pub pose: Pose,
    pub path_pos: f64,
    pub path_vel: f64,
    pub path_acc: f64,
    pub moving: bool,
    pub corners: Corners,
    pub jog: bool,
}

/// The corners passed in one cycle: the sum of their steps in the pose's rate along the
/// path (dPose/ds after minus before) and of each step times the path position (`path_pos`)
/// where it is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Corners {
    pub step: Pose,
    pub moment: Pose,
}

impl Corners {
    pub fn is_none(&self) -> bool {
        self.step == [0.0; 6] && self.moment == [0.0; 6]
    }

    /// Counts one more corner, its step at path position `at`.
    pub(crate) fn add(&mut self, step: &[f64; 6], at: f64) {
        for ((sum, moment), &d) in self.step.iter_mut().zip(&mut self.moment).zip(step) {
            *sum += d;
            *moment += d * at;
        }
    }
}

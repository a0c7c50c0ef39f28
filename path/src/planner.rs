//! PLACEHOLDER until the planner branch merges (the API of the seams, no behaviour).
use api::GroupError;

use crate::segment::{Pose, Segment};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BufferMode {
    Buff,
    Abort,
    Low,
    Prev,
    Next,
    High,
    LookAhead,
}

impl TryFrom<i64> for BufferMode {
    type Error = GroupError;
    fn try_from(v: i64) -> Result<Self, GroupError> {
        Ok(match v {
            0 => BufferMode::Buff,
            1 => BufferMode::Abort,
            2 => BufferMode::Low,
            3 => BufferMode::Prev,
            4 => BufferMode::Next,
            5 => BufferMode::High,
            6 => BufferMode::LookAhead,
            _ => return Err(GroupError::CmdBlendModeUnknown),
        })
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    pub vel: f64,
    pub acc: f64,
    pub dec: f64,
    pub smooth_ms: f64,
}
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    pub lin: Profile,
    pub ang: Profile,
    pub buffer: BufferMode,
}
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LookAhead {
    pub corner_acc: f64,
    pub arc_acc: f64,
    pub chord_error: f64,
}
impl Default for LookAhead {
    fn default() -> Self {
        LookAhead { corner_acc: 5000.0, arc_acc: 100.0, chord_error: 0.0 }
    }
}
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    pub max_vel: [f64; 6],
    pub max_acc: [f64; 6],
}
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Sample {
    pub pose: Pose,
    pub path_pos: f64,
    pub path_vel: f64,
    pub path_acc: f64,
    pub moving: bool,
}
pub struct Planner {
    pose: Pose,
}
impl Planner {
    pub fn new(_period_s: f64) -> Planner {
        Planner { pose: [0.0; 6] }
    }
    pub fn set_queue_size(&mut self, _size: usize) -> Result<(), GroupError> {
        todo!()
    }
    pub fn queue_size(&self) -> usize {
        todo!()
    }
    pub fn commands(&self) -> usize {
        todo!()
    }
    pub fn rest_at(&mut self, pose: Pose) {
        self.pose = pose;
    }
    pub fn end_pose(&self) -> Pose {
        todo!()
    }
    pub fn push(&mut self, _segment: Segment, _motion: Motion, _limits: &Limits) -> Result<(), GroupError> {
        todo!()
    }
    pub fn tail(&self) -> Option<(Segment, f64)> {
        todo!()
    }
    pub fn replace_tail(&mut self, _segment: Segment) {
        todo!()
    }
    pub fn set_look_ahead(&mut self, _look_ahead: LookAhead) {
        todo!()
    }
    pub fn step(&mut self) -> Sample {
        todo!()
    }
    pub fn halt(&mut self) {
        todo!()
    }
    pub fn resume(&mut self) {
        todo!()
    }
    pub fn is_halted(&self) -> bool {
        todo!()
    }
    pub fn stop(&mut self) {
        todo!()
    }
    pub fn stopping_pose(&self) -> Pose {
        todo!()
    }
    pub fn set_velocity_scale(&mut self, _percent: f64) {
        todo!()
    }
    pub fn jog(&mut self, _coordinate: usize, _velocity: f64, _motion: Motion, _limits: &Limits) {
        todo!()
    }
    pub fn is_moving(&self) -> bool {
        todo!()
    }
}

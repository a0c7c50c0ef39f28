//! Who owns an axis' motion (DXMC 9, event 0x001F "command buffer busy": several
//! programs command the same axis at the same time; docs/decisions.md, "Axis ownership").
//!
//! The task whose command set an axis' motion going owns the axis until that motion is
//! over: the axis at rest with nothing planned, halted or queued, or disabled, or in error
//! stop (`Axis::owner`). An axis a group moves is the group's commander's for as long as
//! the group's path runs, and a gantry pair is one axis: either drive's owner owns both.
//! Dispatch refuses another task's motion on an owned axis, and records it on the axis
//! when another task's stop cut the motion short; the FUN147 boxes take no owned axis.

use api::alarms::Alarm;
use schema::MAX_TASKS;

use super::Kernel;
use super::group::GroupState;

/// The owner id of FUN147 box `gp` (docs/fun147.md): after the task ids, since a box is
/// declared by a program but runs on the PLC image after that program has ended.
pub const fn box_owner(gp: usize) -> u8 {
    (MAX_TASKS + gp) as u8
}

/// Whether `owner` is a FUN147 box rather than a task.
pub const fn is_box(owner: u8) -> bool {
    owner as usize >= MAX_TASKS
}

impl Kernel {
    /// The owner of axis `a`'s present motion, if it has one: its group's while the group
    /// moves it, its gantry partner's when the partner's is the motion that runs. An axis
    /// the machine does not have has none.
    pub fn axis_owner(&self, a: u8) -> Option<u8> {
        let own = |a: u8| {
            let axis = self.axes.get(a as usize)?;
            match axis.source().group() {
                Some(g) if axis.source().is_group_synced() => self.group_owner(g as usize),
                _ => axis.owner(),
            }
        };
        own(a).or_else(|| self.gantry.partner(a).and_then(own))
    }

    /// The owner of group `g`'s path: its commander while the path runs, is halted or has
    /// commands queued.
    pub fn group_owner(&self, g: usize) -> Option<u8> {
        let group = &self.groups[g];
        let runs = group.state() == GroupState::Standby && (group.is_moving() || group.commands() > 0);
        group.commander().filter(|_| runs)
    }

    /// Another task's (or the console's) stop cut short the motion `owner` owned on axis
    /// `a`: the axis' last error (HMPL 18.3) and, for a grouped axis, its group's
    /// (HMPL 18.5) become `alarm`, so that the owner's program, told "in position" at a
    /// place it did not command, can read why (docs/decisions.md, "Axis ownership").
    pub fn record_interruption(&mut self, a: u8, alarm: Alarm) {
        let axis = &mut self.axes[a as usize];
        axis.record_alarm(alarm);
        if let Some(g) = axis.source().group() {
            self.group_last_err[g as usize] = alarm.0;
        }
    }
}

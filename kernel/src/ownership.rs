//! Who owns an axis' motion (DXMC 9, event 0x001F "command buffer busy": several
//! programs command the same axis at the same time; docs/decisions.md, "Axis ownership").
//!
//! The task whose command set an axis' motion going (its claim, kept by the kernel per
//! axis) owns the axis until that motion is over: the axis at rest with nothing planned,
//! halted or queued, or disabled, or in error stop (`Axis::motion_lasts`). An axis a
//! group moves is the group's commander's for as long as the group's path runs, and a
//! gantry pair is one axis: either drive's owner owns both. Dispatch refuses another
//! task's motion on an owned axis, and records it on the axis when another task's stop
//! cut the motion short; the FUN147 boxes take no owned axis.

use api::alarms::Alarm;
use schema::MAX_TASKS;

use super::Kernel;
use super::group::GroupState;

/// Who commanded an axis' motion last, and the run speed of that program (DXMC A.3,
/// 0x6B03), which scales the motion's velocity: the kernel's, not the axis', which knows
/// only whether its motion lasts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Claim {
    /// The task (or FUN147 box) whose command set the present motion going: it owns the
    /// motion while it lasts, and its fault reaction applies to it.
    pub(crate) commander: Option<u8>,
    /// The commander's run speed, as a factor.
    pub(crate) run_speed: f64,
}

impl Default for Claim {
    fn default() -> Self {
        Claim { commander: None, run_speed: 1.0 }
    }
}

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
                _ => self.claims[a as usize].commander.filter(|_| axis.motion_lasts()),
            }
        };
        own(a).or_else(|| self.gantry.partner(a).and_then(own))
    }

    /// `task`, whose program runs at `run_speed` (a factor), commanded motion on axis `a`:
    /// it owns the axis' motion from now on.
    pub fn claim(&mut self, a: u8, task: u8, run_speed: f64) {
        if let Some(claim) = self.claims.get_mut(a as usize) {
            claim.commander = Some(task);
            self.follow_run_speed(a as usize, run_speed);
        }
    }

    /// DXMC A.3, 0x6B03: task `task`'s run speed changed; its motion follows.
    pub fn set_run_speed(&mut self, task: u8, factor: f64) {
        for a in 0..self.claims.len() {
            if self.claims[a].commander == Some(task) {
                self.follow_run_speed(a, factor);
            }
        }
    }

    /// Axis `a`'s motion at its commander's run speed `factor`, the move under way
    /// included; replanned only when the speed changes.
    fn follow_run_speed(&mut self, a: usize, factor: f64) {
        if factor != self.claims[a].run_speed {
            self.claims[a].run_speed = factor;
            self.axes[a].set_run_speed(factor);
        }
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

//! The group commands of HMPL 8.2 and 8.3 that change what a group is and whether it
//! moves: membership, enable, disable, reset, stop, halt, resume, jog, and the settings.
//! Each refusal is recorded as the group's last error (HMPL 18.5) with its code of
//! table 18.1.3.1.

use api::{ErrorCode, GroupError};
use schema::MAX_GROUP_AXES;

use super::settings::{self, KIN_CARTESIAN};
use super::{COORDINATES, GroupState};
use crate::Kernel;

impl Kernel {
    /// Runs `f` on group `group` and records its refusal as the group's last error.
    fn on_group<T>(
        &mut self,
        group: i64,
        f: impl FnOnce(&mut Kernel, usize) -> Result<T, GroupError>,
    ) -> Result<T, ErrorCode> {
        let g = self.group_id(group)?;
        f(self, g as usize).map_err(|e| self.refuse_group(g, e))
    }

    /// HMPL 8.3.1: appends an axis (X, Y, Z, A, B, C order, at most 9) to a disabled group.
    /// The axis must be driven by its own generator and stand still.
    pub fn add_axis_to_grp(&mut self, group: i64, axis: i64) -> Result<(), ErrorCode> {
        let a = self.axis_id(axis)?;
        self.on_group(group, |k, g| {
            let grp = &k.groups[g];
            if grp.is_enabled() {
                return Err(GroupError::CmdInvalidState);
            }
            if k.axes[a as usize].source().group().is_some() {
                return Err(GroupError::CmdAxisDuplicated);
            }
            if grp.count == MAX_GROUP_AXES {
                return Err(GroupError::CmdGrpSizeFull);
            }
            if k.axes[a as usize].is_moving() {
                return Err(GroupError::CmdInvalidMoving);
            }
            if k.gantry.pair_of(a).is_some() || k.gear_slaves[a as usize] > 0 {
                return Err(GroupError::CmdGrpAxisInvalid);
            }
            k.axes[a as usize].join_group(g as u8).map_err(|_| GroupError::CmdGrpAxisInvalid)?;
            let grp = &mut k.groups[g];
            grp.axes[grp.count] = a;
            grp.count += 1;
            Ok(())
        })
    }

    /// HMPL 8.3.2: removes the axis added last from a disabled group.
    pub fn remove_axis_from_grp(&mut self, group: i64) -> Result<(), ErrorCode> {
        self.on_group(group, |k, g| {
            let grp = &mut k.groups[g];
            if grp.is_enabled() {
                return Err(GroupError::CmdInvalidState);
            }
            if grp.count == 0 {
                return Err(GroupError::CmdGrpSizeEmpty);
            }
            grp.count -= 1;
            let a = grp.axes[grp.count];
            k.axes[a as usize].leave_group();
            Ok(())
        })
    }

    /// HMPL 8.3.4: disables the group and removes every axis; refused while it moves.
    pub fn ungrp_all_axes(&mut self, group: i64) -> Result<(), ErrorCode> {
        self.on_group(group, |k, g| {
            if k.groups[g].is_moving() {
                return Err(GroupError::CmdInvalidMoving);
            }
            k.release_group_axes(g, false);
            let grp = &mut k.groups[g];
            grp.state = GroupState::Disabled;
            grp.faults = 0;
            for &a in &grp.axes[..grp.count] {
                k.axes[a as usize].leave_group();
            }
            grp.count = 0;
            Ok(())
        })
    }

    /// HMPL 8.2.1: every axis of the group enabled and out of error stop first; the
    /// interpolator starts where the axes stand.
    pub fn enable_group(&mut self, group: i64) -> Result<(), ErrorCode> {
        self.on_group(group, |k, g| {
            let grp = &k.groups[g];
            if grp.count == 0 {
                return Err(GroupError::CmdGrpSizeEmpty);
            }
            if grp.state == GroupState::ErrorStop {
                return Err(GroupError::CmdInvalidState);
            }
            if grp.state == GroupState::Standby {
                return Ok(());
            }
            k.sync_group(g)
        })
    }

    /// The group's axes, all enabled and out of error stop, take their references from the
    /// interpolator, which starts where they stand.
    fn sync_group(&mut self, g: usize) -> Result<(), GroupError> {
        let members = self.groups[g].axes;
        let members = &members[..self.groups[g].count];
        if members.iter().any(|&a| !self.axes[a as usize].is_enabled() || self.axes[a as usize].is_error_stop()) {
            return Err(GroupError::CmdInvalidState);
        }
        if members.iter().any(|&a| self.axes[a as usize].is_moving()) {
            return Err(GroupError::CmdInvalidMoving);
        }
        let pose = self.pose_of_axes(g);
        self.groups[g].rest_at(pose);
        for &a in members {
            self.axes[a as usize].sync_group();
        }
        let grp = &mut self.groups[g];
        grp.state = GroupState::Standby;
        grp.faults = 0;
        Ok(())
    }

    /// HMPL 8.2.2: the axes stay grouped and enabled, each on its own generator; refused
    /// while the group moves (`StopGroup` first).
    pub fn disable_group(&mut self, group: i64) -> Result<(), ErrorCode> {
        self.on_group(group, |k, g| {
            if k.groups[g].is_moving() {
                return Err(GroupError::CmdInvalidMoving);
            }
            k.release_group_axes(g, false);
            k.groups[g].state = GroupState::Disabled;
            Ok(())
        })
    }

    /// HMPL 8.2.3: Group Error Stop -> Group Standby once every cause is gone.
    pub fn reset_group(&mut self, group: i64) -> Result<(), ErrorCode> {
        self.on_group(group, |k, g| match k.groups[g].state {
            GroupState::ErrorStop => k.sync_group(g),
            GroupState::Standby | GroupState::Disabled => Ok(()),
        })
    }

    /// The group may take motion commands: enabled, not in error stop.
    fn check_moves(&self, g: usize) -> Result<(), GroupError> {
        match self.groups[g].state {
            GroupState::Disabled => Err(GroupError::CmdInvalidDisabled),
            GroupState::ErrorStop => Err(GroupError::CmdInvalidState),
            GroupState::Standby => Ok(()),
        }
    }

    /// HMPL 8.2.4: decelerates along the path and clears the queue.
    pub fn stop_group(&mut self, group: i64) -> Result<(), ErrorCode> {
        self.on_group(group, |k, g| {
            k.check_moves(g)?;
            k.groups[g].planner.stop();
            Ok(())
        })
    }

    /// HMPL 8.2.5: the path velocity to 0, the path kept.
    pub fn halt_group(&mut self, group: i64) -> Result<(), ErrorCode> {
        self.on_group(group, |k, g| {
            k.check_moves(g)?;
            k.groups[g].planner.halt();
            Ok(())
        })
    }

    /// An immediate stop (no HMPL command; FUN147 with M1991 OFF, docs/decisions.md
    /// "FUN147"): the interpolator and the smoothing stand still at the commanded pose and
    /// the queue is dropped, so the axes' velocity falls to 0 within one cycle.
    pub fn rest_group(&mut self, group: i64) -> Result<(), ErrorCode> {
        self.on_group(group, |k, g| {
            k.check_moves(g)?;
            let pose = k.groups[g].pose_cmd.pos;
            k.groups[g].rest_at(pose);
            Ok(())
        })
    }

    /// HMPL 8.2.6: on along the halted path.
    pub fn resume_group(&mut self, group: i64) -> Result<(), ErrorCode> {
        self.on_group(group, |k, g| {
            k.check_moves(g)?;
            k.groups[g].planner.resume();
            Ok(())
        })
    }

    /// HMPL 8.2.7: jogs MCS coordinate `carte_dir` (0..5: X, Y, Z, A, B, C) that the group
    /// has an axis for; velocity 0 ramps the jog to rest.
    pub fn jog_group(&mut self, group: i64, carte_dir: i64, velocity: f64) -> Result<(), ErrorCode> {
        self.on_group(group, |k, g| {
            k.check_moves(g)?;
            let dir = usize::try_from(carte_dir).ok().filter(|&d| d < k.groups[g].coordinates());
            let dir = dir.ok_or(GroupError::CmdLinInvalidParam)?;
            // A jog moves the group off its path: not while path commands are queued.
            if k.groups[g].planner.commands() > 0 {
                return Err(GroupError::CmdInvalidMoving);
            }
            // HMPL 8.3.6, 8.3.7: the linear and the angular velocity limits.
            let limit = if dir < 3 { 5000.0 } else { 7200.0 };
            if velocity.abs() > limit {
                return Err(GroupError::CmdInvalidLinVel);
            }
            let limits = k.groups[g].limits(&k.axes);
            let motion = k.groups[g].settings.motion();
            k.groups[g].planner.jog(dir, velocity, motion, &limits);
            Ok(())
        })
    }

    /// HMPL 8.2.8: jogs axis `grp_axis` (0..8, in the order added) of the group. With
    /// Cartesian kinematics the first six axes are the MCS coordinates; the axes after them
    /// have no coordinate and refuse it (docs/decisions.md, "Groups").
    pub fn jog_group_axis(&mut self, group: i64, grp_axis: i64, velocity: f64) -> Result<(), ErrorCode> {
        let g = self.group_id(group)?;
        let count = self.groups[g as usize].count as i64;
        match grp_axis {
            a if (0..count.min(COORDINATES as i64)).contains(&a) => self.jog_group(group, a, velocity),
            a if (0..count).contains(&a) => Err(self.refuse_group(g, GroupError::CmdInvalidSpecificKin)),
            _ => Err(self.refuse_group(g, GroupError::CmdGrpAxisInvalid)),
        }
    }

    /// HMPL 8.3.6, 8.3.7, 8.3.11-8.3.19, 8.3.23, 8.3.28, 8.3.34: a setting; the ranges were
    /// checked with the arguments (`settings::admit`).
    pub fn set_group(
        &mut self,
        group: i64,
        f: impl FnOnce(&mut settings::GroupSettings) -> Result<(), GroupError>,
    ) -> Result<(), ErrorCode> {
        self.on_group(group, |k, g| {
            let grp = &mut k.groups[g];
            let mut s = grp.settings;
            f(&mut s)?;
            grp.settings = s;
            grp.planner.set_velocity_scale(s.vel_scale);
            grp.planner.set_look_ahead(s.look_ahead);
            Ok(())
        })
    }

    /// A setting that cannot fail once its argument is in range.
    pub fn set_group_value(
        &mut self,
        group: i64,
        f: impl FnOnce(&mut settings::GroupSettings),
    ) -> Result<(), ErrorCode> {
        self.set_group(group, |s| {
            f(s);
            Ok(())
        })
    }

    /// HMPL 8.3.9: only Cartesian (1) is available; 2 to 4 are named but not available.
    pub fn set_grp_kin(&mut self, group: i64, kin: i64) -> Result<(), ErrorCode> {
        self.on_group(group, |k, g| {
            if kin != KIN_CARTESIAN {
                return Err(GroupError::CmdInvalidKinSetting);
            }
            k.groups[g].kin = kin;
            Ok(())
        })
    }

    /// HMPL 8.3.35: 2^n commands, only while the queue is empty.
    pub fn set_grp_queue_size(&mut self, group: i64, n: i64) -> Result<(), ErrorCode> {
        self.on_group(group, |k, g| {
            let size = settings::queue_size(n)?;
            k.groups[g].planner.set_queue_size(size)
        })
    }
}

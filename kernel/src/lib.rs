//! The motion kernel: axes (HMPL ch. 5), gear (ch. 6) and gantry (ch. 7), computed once
//! per cycle from the drives' inputs and the commands of the cycle, never from the wall
//! clock. Each axis has one reference source (`source.rs`); the couplings between axes
//! (gear slaves per master, gantry pairs) are the kernel's state, changed only by its
//! commands. The cycle's stages are in `Kernel::step`.

pub mod axis;
pub mod compensation;
pub(crate) mod drive_link;
pub mod filter;
pub(crate) mod gantry;
pub(crate) mod gear;
pub mod generator;
pub mod group;
pub(crate) mod homing;
pub mod ownership;
pub(crate) mod power;
pub mod pvt;
pub mod settings;
pub mod shaping;
pub(crate) mod smoothing;
pub(crate) mod source;
pub mod touch_probe;

use api::{AxisError, ErrorCode, SystemError};
use schema::{AxisSnapshot, Snapshot, motion_status};

use axis::Axis;
use compensation::Compensations;
use config::{FaultReaction, MachineConfig};
use devices::ecat::Network;
use gantry::Gantries;
use group::Group;
use ownership::Claim;

pub use schema::MAX_GROUPS;

/// The motion kernel: every axis and group of the machine and the couplings between them,
/// stepped once per cycle (`Kernel::step`).
pub struct Kernel {
    axes: Vec<Axis>,
    /// Who commanded each axis' motion, and at what run speed, by axis id.
    claims: Vec<Claim>,
    gantry: Gantries,
    /// HMPL ch. 8: the groups, each with its interpolator.
    groups: Vec<Group>,
    /// How many gear slaves each axis has: a master has at least one (HMPL 6.2).
    gear_slaves: Vec<usize>,
    /// Drive commands of the cycle (after the gantry transform); kept to avoid allocating.
    commands: Vec<f64>,
    /// HMPL 18.5: each group's last error.
    group_last_err: [u32; MAX_GROUPS],
    /// HMPL 18.2: the last system error.
    system_last_err: u32,
    /// HMPL ch. 14: each axis' compensation table.
    compensation: Compensations,
}

impl Kernel {
    /// One axis per drive, in ring order, wired to the drive's mapped process data.
    pub fn new(config: &MachineConfig, network: &Network) -> Self {
        let period_s = config.period_ns() as f64 * 1e-9;
        let axes: Vec<Axis> =
            config.axes.iter().enumerate().map(|(i, axis)| Axis::new(i as u8, axis, network, period_s)).collect();
        let n = axes.len();
        Kernel {
            axes,
            claims: vec![Claim::default(); n],
            gantry: Gantries::new(n),
            groups: (0..MAX_GROUPS).map(|_| Group::new(period_s)).collect(),
            gear_slaves: vec![0; n],
            commands: vec![0.0; n],
            group_last_err: [0; MAX_GROUPS],
            system_last_err: 0,
            compensation: Compensations::new(n),
        }
    }

    /// The axes, by id (the machine file's order).
    pub fn axes(&self) -> &[Axis] {
        &self.axes
    }

    /// The axis a script names, or HMPL's "argument out of range".
    pub fn axis_mut(&mut self, id: i64) -> Result<&mut Axis, SystemError> {
        usize::try_from(id).ok().and_then(|i| self.axes.get_mut(i)).ok_or(SystemError::HmplArgOutOfRange)
    }

    fn axis_id(&self, id: i64) -> Result<u8, ErrorCode> {
        usize::try_from(id)
            .ok()
            .filter(|&i| i < self.axes.len())
            .map(|i| i as u8)
            .ok_or(ErrorCode::System(SystemError::HmplArgOutOfRange))
    }

    /// Records a refusal as axis `id`'s last error (HMPL 18.3) and returns its code.
    fn refuse(&mut self, id: u8, error: AxisError) -> ErrorCode {
        self.axes[id as usize].fail(error);
        ErrorCode::axis(id, error)
    }

    /// HMPL 5.2.1, 7.1: enabling one axis of a gantry pair enables both.
    pub fn enable(&mut self, id: i64) -> Result<(), ErrorCode> {
        let id = self.axis_id(id)?;
        for a in std::iter::once(id).chain(self.gantry.partner(id)) {
            let axis = &mut self.axes[a as usize];
            axis.enable().map_err(|e| ErrorCode::axis(a, e))?;
        }
        Ok(())
    }

    /// HMPL 5.2.2: disabling one axis of a gantry pair disables both.
    pub fn disable(&mut self, id: i64) -> Result<(), ErrorCode> {
        let id = self.axis_id(id)?;
        for a in std::iter::once(id).chain(self.gantry.partner(id)) {
            let _ = self.axes[a as usize].disable();
        }
        Ok(())
    }

    /// HMPL 5.3.19: refused on a gantry axis (`0x83II00DC`), whose position is a pair's,
    /// and while compensation fixes the axis' coordinates (`0x83II00D2`, HMPL 14.1).
    pub fn set_pos(&mut self, id: i64, pos: f64) -> Result<(), ErrorCode> {
        let id = self.axis_id(id)?;
        if self.gantry.pair_of(id).is_some() {
            return Err(self.refuse(id, AxisError::CmdInvalidGantryMode));
        }
        self.keep_coordinates(id as i64)?;
        self.axes[id as usize].set_pos(pos).map_err(|e| ErrorCode::axis(id, e))
    }

    /// HMPL 5.3.37: axis `id`'s velocity override, with its commander's run speed on top.
    pub fn set_vel_scale(&mut self, id: i64, percent: f64) -> Result<(), ErrorCode> {
        let a = self.axis_id(id)? as usize;
        self.axes[a].set_vel_scale(percent, self.claims[a].run_speed);
        Ok(())
    }

    /// Records `code` as the last system error (HMPL 18.2): a refused call or a task's
    /// runtime error.
    pub fn record_system_error(&mut self, code: u32) {
        self.system_last_err = code;
    }

    /// HMPL 18.6: the group's last error.
    pub fn clear_group_last_err(&mut self, group: i64) -> Result<(), ErrorCode> {
        let g = usize::try_from(group).ok().filter(|&g| g < MAX_GROUPS).ok_or(SystemError::HmplArgOutOfRange)?;
        self.group_last_err[g] = 0;
        Ok(())
    }

    /// One cycle against the frame just exchanged. Each stage runs for every axis before
    /// the next begins, so a stage sees what the earlier ones made of every axis:
    ///
    /// 1. sense: read each drive, step its power sequence;
    /// 2. couplings in: a gantry drive in ErrorStop disables its partner; the pairs' drive
    ///    positions become linear and yaw (HMPL 7.1);
    /// 3. references: each axis' source gives its reference (`Axis::plan`): the profile
    ///    generator through the filter chain, or the feedback while homing, in torque mode
    ///    or disabled; an engaged gear slave waits for stage 4;
    /// 4. couplings out: each enabled group steps its interpolator and its synced axes take
    ///    their references from it (HMPL ch. 8), or leaves sync when an axis faulted; then
    ///    engaged gear slaves follow their masters' references (HMPL 6.1; masters are never
    ///    slaves, and a group axis may be a master);
    /// 5. compensation: each compensated axis' value from its table at its reference axes'
    ///    references (HMPL ch. 14), so that output = reference + compensation;
    /// 6. limits and status: limits, position error, in position (`Axis::monitor`);
    /// 7. drive commands: output + offset, through the gantry transform, to the drives.
    pub fn step(&mut self, cycle: u64, network: &mut Network) {
        for axis in &mut self.axes {
            axis.sense(network, cycle);
        }
        self.couple_feedback();
        for axis in &mut self.axes {
            axis.plan();
        }
        self.step_groups();
        self.follow_gears();
        self.compensate();
        for axis in &mut self.axes {
            axis.monitor();
        }
        self.gantry.to_drives(&self.axes, &mut self.commands);
        for (axis, &command) in self.axes.iter_mut().zip(&self.commands) {
            axis.actuate(network, command);
        }
    }

    /// Stage 2: a gantry drive that drops out takes its partner along (docs/decisions.md,
    /// "Gantry"); then the pairs' feedback becomes linear and yaw.
    fn couple_feedback(&mut self) {
        for i in 0..self.axes.len() {
            if self.axes[i].is_error_stop()
                && let Some(p) = self.gantry.partner(i as u8)
                && self.axes[p as usize].is_enabled()
            {
                let _ = self.axes[p as usize].disable();
            }
        }
        self.gantry.to_axes(&mut self.axes);
    }

    /// Disables every axis (controller shutdown, DisableAll).
    pub fn disable_all(&mut self) {
        for axis in &mut self.axes {
            let _ = axis.disable();
        }
    }

    /// HMPL 2.8: every axis stops with its kill deceleration and stays enabled; every
    /// group stops along its path.
    pub fn stop_all(&mut self) {
        for group in &mut self.groups {
            group.stop();
        }
        for axis in &mut self.axes {
            axis.kill_stop();
        }
    }

    /// HMPL 2.9, 9.1: every axis disabled, motion refused until enabled again.
    pub fn emergency_stop(&mut self) {
        for axis in &mut self.axes {
            axis.emergency_stop();
        }
    }

    /// A task failed or was stopped: the motion it set going reacts as its fault reaction
    /// says (docs/decisions.md, "Fault reaction").
    pub fn react(&mut self, task: u8, reaction: FaultReaction) {
        self.react_groups(task, reaction);
        for id in 0..self.axes.len() {
            let axis = &self.axes[id];
            let commanded = self.claims[id].commander == Some(task);
            if !commanded || !(axis.is_moving() || axis.is_homing()) || self.is_grouped(id) {
                continue;
            }
            match reaction {
                FaultReaction::None => {}
                FaultReaction::Decelerate => self.axes[id].kill_stop(),
                FaultReaction::QuickStop => {
                    for a in std::iter::once(id as u8).chain(self.gantry.partner(id as u8)) {
                        self.axes[a as usize].quick_stop();
                    }
                }
                FaultReaction::Disable => {
                    let _ = self.disable(id as i64);
                }
            }
        }
    }

    /// Axis `id` as the status functions see it (HMPL tables 5.1.1.1 to 5.1.1.6), its
    /// couplings included.
    pub fn axis_snapshot(&self, id: usize) -> AxisSnapshot {
        let mut s = self.axes[id].snapshot();
        if let Some(pair) = self.gantry.pair_of(id as u8) {
            s.motion_status |= motion_status::GANTRY;
            s.gantry_pair_id = pair as i32;
        }
        s.gear_master = self.gear_slaves[id].min(1) as u32;
        s.comp_active = self.compensation.is_active(id) as u32;
        if let Some(g) = self.axes[id].source().group() {
            s.motion_status |= motion_status::GROUP;
            s.group_id = g as i32;
            if self.axes[id].source().is_group_synced() {
                s.motion_status |= motion_status::SYNCHRONOUS;
            }
        }
        s
    }

    /// Writes every axis, every group and the last errors into the snapshot the status
    /// functions read (HMPL tables 5.1.1.1 to 5.1.1.6, 8.1.1.1; ch. 18).
    pub fn fill(&self, snapshot: &mut Snapshot) {
        snapshot.axis_count = self.axes.len() as u32;
        for (id, slot) in snapshot.axes.iter_mut().enumerate().take(self.axes.len()) {
            *slot = self.axis_snapshot(id);
        }
        snapshot.group_last_err = self.group_last_err;
        for (slot, group) in snapshot.groups.iter_mut().zip(&self.groups) {
            *slot = group.snapshot(&self.axes);
        }
        snapshot.system_last_err = self.system_last_err;
    }
}

//! The motion kernel: axes (HMPL ch. 5), gear (ch. 6) and gantry (ch. 7), computed once
//! per cycle from the drives' inputs and the commands of the cycle, never from the wall
//! clock. Each cycle: read the drives, turn gantry drives into linear and yaw, move the
//! axes (masters before their gear slaves), watch limits, write the drives.

pub mod axis;
pub mod drive_link;
pub mod gantry;
pub mod gear;
pub mod generator;
pub mod homing;
pub mod power;
pub mod pvt;
pub mod settings;
pub mod smoothing;

use api::{ErrorCode, SystemError};
use ipc::messages::Snapshot;

use crate::config::{FaultReaction, MachineConfig};
use crate::ecat::Network;
use axis::Axis;
use gantry::Pair;

pub use ipc::messages::MAX_GROUPS;

pub struct Kernel {
    axes: Vec<Axis>,
    pairs: Vec<Option<Pair>>,
    /// Drive commands of the cycle (after the gantry transform); kept to avoid allocating.
    commands: Vec<f64>,
    /// HMPL 18.5: each group's last error.
    group_last_err: [u32; MAX_GROUPS],
    /// HMPL 18.2: the last system error.
    system_last_err: u32,
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
            pairs: vec![None; n / 2],
            commands: vec![0.0; n],
            group_last_err: [0; MAX_GROUPS],
            system_last_err: 0,
        }
    }

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

    /// HMPL 5.2.1, 7.1: enabling one axis of a gantry pair enables both.
    pub fn enable(&mut self, id: i64) -> Result<(), ErrorCode> {
        let id = self.axis_id(id)?;
        let partner = gantry::partner(&self.pairs, &self.axes[id as usize]);
        for a in std::iter::once(id).chain(partner) {
            let axis = &mut self.axes[a as usize];
            axis.enable().map_err(|e| ErrorCode::axis(a, e))?;
        }
        Ok(())
    }

    pub fn disable(&mut self, id: i64) -> Result<(), ErrorCode> {
        let id = self.axis_id(id)?;
        let partner = gantry::partner(&self.pairs, &self.axes[id as usize]);
        for a in std::iter::once(id).chain(partner) {
            let _ = self.axes[a as usize].disable();
        }
        Ok(())
    }

    pub fn enable_gear(&mut self, master: i64, slave: i64) -> Result<(), ErrorCode> {
        let (m, s) = (self.axis_id(master)?, self.axis_id(slave)?);
        gear::enable(&mut self.axes, m, s)
    }

    pub fn disable_gear(&mut self, slave: i64) -> Result<(), ErrorCode> {
        let s = self.axis_id(slave)?;
        gear::disable(&mut self.axes, s)
    }

    pub fn gear_in(&mut self, master: i64, slave: i64, ratio: f64) -> Result<(), ErrorCode> {
        let (m, s) = (self.axis_id(master)?, self.axis_id(slave)?);
        gear::gear_in(&mut self.axes, m, s, ratio)
    }

    pub fn gear_out(&mut self, slave: i64) -> Result<(), ErrorCode> {
        let s = self.axis_id(slave)?;
        gear::gear_out(&mut self.axes, s)
    }

    pub fn enable_gantry_pair(&mut self, rhs: i64, lhs: i64) -> Result<(), ErrorCode> {
        let (r, l) = (self.axis_id(rhs)?, self.axis_id(lhs)?);
        gantry::enable(&mut self.axes, &mut self.pairs, r, l)
    }

    pub fn disable_gantry_pair(&mut self, axis: i64) -> Result<(), ErrorCode> {
        let a = self.axis_id(axis)?;
        gantry::disable(&mut self.axes, &mut self.pairs, a)
    }

    pub fn record_system_error(&mut self, code: u32) {
        self.system_last_err = code;
    }

    /// HMPL 18.6: the group's last error; no group exists to raise one yet.
    pub fn clear_group_last_err(&mut self, group: i64) -> Result<(), ErrorCode> {
        let g = usize::try_from(group).ok().filter(|&g| g < MAX_GROUPS).ok_or(SystemError::HmplArgOutOfRange)?;
        self.group_last_err[g] = 0;
        Ok(())
    }

    /// One cycle of every axis against the frame just exchanged.
    pub fn step(&mut self, cycle: u64, network: &mut Network) {
        for axis in &mut self.axes {
            axis.sense(network, cycle);
        }
        // A gantry drive that drops out takes its partner along.
        for i in 0..self.axes.len() {
            if self.axes[i].is_error_stop()
                && let Some(p) = gantry::partner(&self.pairs, &self.axes[i])
                && self.axes[p as usize].is_enabled()
            {
                let _ = self.axes[p as usize].disable();
            }
        }
        gantry::to_axes(&mut self.axes, &self.pairs);
        for axis in &mut self.axes {
            axis.plan();
        }
        gear::follow(&mut self.axes);
        for axis in &mut self.axes {
            axis.monitor();
        }
        gantry::to_drives(&self.axes, &self.pairs, &mut self.commands);
        for (axis, &command) in self.axes.iter_mut().zip(&self.commands) {
            axis.actuate(network, command);
        }
    }

    /// Disables every axis (controller shutdown, DisableAll).
    pub fn disable_all(&mut self) {
        for axis in &mut self.axes {
            let _ = axis.disable();
        }
    }

    /// DXMC A.3, 0x6B03: task `task`'s run speed changed; its motion follows.
    pub fn set_run_speed(&mut self, task: u8, factor: f64) {
        for axis in self.axes.iter_mut().filter(|a| a.commander() == Some(task)) {
            axis.set_run_speed(factor);
        }
    }

    /// HMPL 2.8: every axis stops with its kill deceleration and stays enabled.
    pub fn stop_all(&mut self) {
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
        for id in 0..self.axes.len() {
            let axis = &self.axes[id];
            if axis.commander() != Some(task) || !(axis.is_moving() || axis.is_homing()) {
                continue;
            }
            match reaction {
                FaultReaction::None => {}
                FaultReaction::Decelerate => self.axes[id].kill_stop(),
                FaultReaction::QuickStop => {
                    let partner = gantry::partner(&self.pairs, &self.axes[id]);
                    for a in std::iter::once(id as u8).chain(partner) {
                        self.axes[a as usize].quick_stop();
                    }
                }
                FaultReaction::Disable => {
                    let _ = self.disable(id as i64);
                }
            }
        }
    }

    pub fn fill(&self, snapshot: &mut Snapshot) {
        snapshot.axis_count = self.axes.len() as u32;
        for (slot, axis) in snapshot.axes.iter_mut().zip(&self.axes) {
            *slot = axis.snapshot();
        }
        snapshot.group_last_err = self.group_last_err;
        snapshot.system_last_err = self.system_last_err;
    }
}

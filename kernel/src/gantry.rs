//! Gantry pairs (HMPL ch. 7): a right-hand (RHS) and a left-hand (LHS) axis become a
//! linear axis (commanded through the RHS id) and a yaw axis (through the LHS id):
//! linear = (R + L) / 2, yaw = (R - L) / 2, so R = linear + yaw, L = linear - yaw.
//! The pairs are the kernel's state; an axis does not know it is in one.

use api::{AxisError, ErrorCode};

use super::Kernel;
use crate::axis::Axis;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pair {
    pub rhs: u8,
    pub lhs: u8,
}

/// The pairs by id (HMPL 7.2: ids 0 .. axes/2 - 1, given in order) and each axis' pair.
pub struct Gantries {
    pairs: Vec<Option<Pair>>,
    of_axis: Vec<Option<u8>>,
}

impl Gantries {
    pub fn new(axes: usize) -> Self {
        Gantries { pairs: vec![None; axes / 2], of_axis: vec![None; axes] }
    }

    /// The id of the pair axis `id` is in.
    pub fn pair_of(&self, id: u8) -> Option<u8> {
        self.of_axis[id as usize]
    }

    /// The other axis of `id`'s pair.
    pub fn partner(&self, id: u8) -> Option<u8> {
        let pair = self.pairs[self.pair_of(id)? as usize]?;
        Some(if pair.rhs == id { pair.lhs } else { pair.rhs })
    }

    /// Feedback: the drives' positions become linear and yaw.
    pub fn to_axes(&self, axes: &mut [Axis]) {
        for pair in self.pairs.iter().flatten() {
            let (r, l) = (axes[pair.rhs as usize].drive_position(), axes[pair.lhs as usize].drive_position());
            axes[pair.rhs as usize].set_drive_position((r + l) / 2.0);
            axes[pair.lhs as usize].set_drive_position((r - l) / 2.0);
        }
    }

    /// Commands: linear and yaw become the drives' positions. Returns each axis' drive command.
    pub fn to_drives(&self, axes: &[Axis], commands: &mut [f64]) {
        for (command, axis) in commands.iter_mut().zip(axes) {
            *command = axis.drive_command();
        }
        for pair in self.pairs.iter().flatten() {
            let (linear, yaw) = (commands[pair.rhs as usize], commands[pair.lhs as usize]);
            commands[pair.rhs as usize] = linear + yaw;
            commands[pair.lhs as usize] = linear - yaw;
        }
    }
}

impl Kernel {
    /// HMPL 7.2: both axes disabled, distinct, in no pair and no gear.
    pub fn enable_gantry_pair(&mut self, rhs: i64, lhs: i64) -> Result<(), ErrorCode> {
        let (rhs, lhs) = (self.axis_id(rhs)?, self.axis_id(lhs)?);
        if rhs == lhs {
            return Err(self.refuse(lhs, AxisError::CmdInvalidParameter));
        }
        for id in [rhs, lhs] {
            let axis = &self.axes[id as usize];
            let error = if self.gantry.pair_of(id).is_some() {
                Some(AxisError::CmdInvalidGantryMode)
            } else if axis.is_gear_slave() || self.is_gear_master(id) {
                Some(AxisError::CmdInvalidInSync)
            } else if !axis.is_disabled() {
                Some(AxisError::CmdInvalidEnabled)
            } else {
                None
            };
            if let Some(e) = error {
                return Err(self.refuse(id, e));
            }
        }
        let Some(slot) = self.gantry.pairs.iter().position(Option::is_none) else {
            return Err(self.refuse(rhs, AxisError::CmdInvalidGantryMode));
        };
        self.gantry.pairs[slot] = Some(Pair { rhs, lhs });
        for id in [rhs, lhs] {
            self.gantry.of_axis[id as usize] = Some(slot as u8);
        }
        Ok(())
    }

    /// HMPL 7.3: split the pair of either axis; both must be disabled.
    pub fn disable_gantry_pair(&mut self, axis: i64) -> Result<(), ErrorCode> {
        let axis = self.axis_id(axis)?;
        let Some(slot) = self.gantry.pair_of(axis) else {
            return Err(self.refuse(axis, AxisError::CmdInvalidGantryMode));
        };
        let pair = self.gantry.pairs[slot as usize].expect("an axis' pair exists");
        for id in [pair.rhs, pair.lhs] {
            if !self.axes[id as usize].is_disabled() {
                return Err(self.refuse(id, AxisError::CmdInvalidEnabled));
            }
        }
        self.gantry.pairs[slot as usize] = None;
        for id in [pair.rhs, pair.lhs] {
            self.gantry.of_axis[id as usize] = None;
        }
        Ok(())
    }
}

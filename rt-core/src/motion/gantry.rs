//! Gantry pairs (HMPL ch. 7): a right-hand (RHS) and a left-hand (LHS) axis become a
//! linear axis (commanded through the RHS id) and a yaw axis (through the LHS id):
//! linear = (R + L) / 2, yaw = (R - L) / 2, so R = linear + yaw, L = linear - yaw.

use api::{AxisError, ErrorCode};

use crate::motion::axis::Axis;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pair {
    pub rhs: u8,
    pub lhs: u8,
}

fn refuse(axes: &mut [Axis], id: u8, error: AxisError) -> ErrorCode {
    axes[id as usize].fail(error);
    ErrorCode::axis(id, error)
}

/// HMPL 7.2: both axes disabled, distinct, in no pair and no gear.
pub fn enable(axes: &mut [Axis], pairs: &mut [Option<Pair>], rhs: u8, lhs: u8) -> Result<(), ErrorCode> {
    if rhs == lhs {
        return Err(refuse(axes, lhs, AxisError::CmdInvalidParameter));
    }
    for id in [rhs, lhs] {
        let axis = &axes[id as usize];
        let error = if axis.gantry.is_some() {
            Some(AxisError::CmdInvalidGantryMode)
        } else if axis.is_gear_slave() || axis.gear_master {
            Some(AxisError::CmdInvalidInSync)
        } else if !axis.is_disabled() {
            Some(AxisError::CmdInvalidEnabled)
        } else {
            None
        };
        if let Some(e) = error {
            return Err(refuse(axes, id, e));
        }
    }
    let Some(slot) = pairs.iter().position(Option::is_none) else {
        return Err(refuse(axes, rhs, AxisError::CmdInvalidGantryMode));
    };
    pairs[slot] = Some(Pair { rhs, lhs });
    axes[rhs as usize].gantry = Some((slot as u8, true));
    axes[lhs as usize].gantry = Some((slot as u8, false));
    Ok(())
}

/// HMPL 7.3: split the pair of either axis; both must be disabled.
pub fn disable(axes: &mut [Axis], pairs: &mut [Option<Pair>], axis: u8) -> Result<(), ErrorCode> {
    let Some((slot, _)) = axes[axis as usize].gantry else {
        return Err(refuse(axes, axis, AxisError::CmdInvalidGantryMode));
    };
    let pair = pairs[slot as usize].expect("an axis' pair exists");
    for id in [pair.rhs, pair.lhs] {
        if !axes[id as usize].is_disabled() {
            return Err(refuse(axes, id, AxisError::CmdInvalidEnabled));
        }
    }
    pairs[slot as usize] = None;
    axes[pair.rhs as usize].gantry = None;
    axes[pair.lhs as usize].gantry = None;
    Ok(())
}

/// The other axis of a pair.
pub fn partner(pairs: &[Option<Pair>], axis: &Axis) -> Option<u8> {
    let (slot, rhs) = axis.gantry?;
    let pair = pairs[slot as usize]?;
    Some(if rhs { pair.lhs } else { pair.rhs })
}

/// Feedback: the drives' positions become linear and yaw.
pub fn to_axes(axes: &mut [Axis], pairs: &[Option<Pair>]) {
    for pair in pairs.iter().flatten() {
        let (r, l) = (axes[pair.rhs as usize].drive_position(), axes[pair.lhs as usize].drive_position());
        axes[pair.rhs as usize].set_drive_position((r + l) / 2.0);
        axes[pair.lhs as usize].set_drive_position((r - l) / 2.0);
    }
}

/// Commands: linear and yaw become the drives' positions. Returns each axis' drive command.
pub fn to_drives(axes: &[Axis], pairs: &[Option<Pair>], commands: &mut [f64]) {
    for (command, axis) in commands.iter_mut().zip(axes) {
        *command = axis.drive_command();
    }
    for pair in pairs.iter().flatten() {
        let (linear, yaw) = (commands[pair.rhs as usize], commands[pair.lhs as usize]);
        commands[pair.rhs as usize] = linear + yaw;
        commands[pair.lhs as usize] = linear - yaw;
    }
}

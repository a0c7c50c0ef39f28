//! Electronic gearing (HMPL ch. 6): `EnableGear` links a slave to a master, `GearIn`
//! engages it at a ratio (slave += ratio x master's travel from the engage point),
//! `GearOut` disengages it, `DisableGear` unlinks it. One master, many slaves; no chains.

use api::{AxisError, ErrorCode};

use crate::motion::axis::{Axis, Engagement, GearLink};

fn axis_error(axes: &mut [Axis], id: u8, error: AxisError) -> ErrorCode {
    axes[id as usize].fail(error);
    ErrorCode::axis(id, error)
}

/// HMPL 6.2: both axes enabled; the slave is not yet a slave, nor a master, nor in a gantry.
pub fn enable(axes: &mut [Axis], master: u8, slave: u8) -> Result<(), ErrorCode> {
    let (m, s) = (master as usize, slave as usize);
    if m == s || axes[s].is_gear_slave() || axes[s].gear_master || axes[m].is_gear_slave() {
        return Err(axis_error(axes, slave, AxisError::CmdInvalidMasterSlaveConnection));
    }
    if axes[s].gantry.is_some() {
        return Err(axis_error(axes, slave, AxisError::CmdInvalidGantryMode));
    }
    for id in [master, slave] {
        if !axes[id as usize].is_enabled() {
            return Err(axis_error(axes, id, AxisError::CmdInvalidDisabled));
        }
    }
    if axes[s].is_moving() {
        return Err(axis_error(axes, slave, AxisError::CmdInvalidMoving));
    }
    axes[s].gear = Some(GearLink { master, engaged: None });
    axes[m].gear_master = true;
    Ok(())
}

/// HMPL 6.3: unlink (disengaging first).
pub fn disable(axes: &mut [Axis], slave: u8) -> Result<(), ErrorCode> {
    let Some(link) = axes[slave as usize].gear else {
        return Err(axis_error(axes, slave, AxisError::CmdGearDisabled));
    };
    if link.engaged.is_some() {
        axes[slave as usize].disengage();
    }
    axes[slave as usize].gear = None;
    let master = link.master as usize;
    axes[master].gear_master = axes.iter().any(|a| a.gear.is_some_and(|g| g.master as usize == master));
    Ok(())
}

/// HMPL 6.4: engage at `ratio` (negative too; its range is the registry's).
pub fn gear_in(axes: &mut [Axis], master: u8, slave: u8, ratio: f64) -> Result<(), ErrorCode> {
    let Some(link) = axes[slave as usize].gear else {
        return Err(axis_error(axes, slave, AxisError::CmdGearDisabled));
    };
    if link.master != master {
        return Err(axis_error(axes, slave, AxisError::CmdInvalidMasterSlaveConnection));
    }
    for id in [master, slave] {
        if !axes[id as usize].is_enabled() {
            return Err(axis_error(axes, id, AxisError::CmdInvalidDisabled));
        }
    }
    let engagement = Engagement {
        ratio,
        master_origin: axes[master as usize].reference().pos,
        slave_origin: axes[slave as usize].reference().pos,
    };
    axes[slave as usize].gear = Some(GearLink { master, engaged: Some(engagement) });
    Ok(())
}

/// HMPL 6.5: disengage; the slave comes to rest from its present motion.
pub fn gear_out(axes: &mut [Axis], slave: u8) -> Result<(), ErrorCode> {
    match axes[slave as usize].gear {
        Some(GearLink { engaged: Some(_), .. }) => {
            axes[slave as usize].disengage();
            Ok(())
        }
        _ => Err(axis_error(axes, slave, AxisError::CmdGearDisabled)),
    }
}

/// Each cycle, after the masters have moved: the engaged slaves follow.
pub fn follow(axes: &mut [Axis]) {
    for s in 0..axes.len() {
        if let Some(GearLink { master, engaged: Some(_) }) = axes[s].gear {
            let reference = axes[master as usize].reference();
            axes[s].follow(reference);
        }
    }
}

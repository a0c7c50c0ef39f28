//! Electronic gearing (HMPL ch. 6): `EnableGear` links a slave to a master, `GearIn`
//! engages it at a ratio (slave += ratio x master's travel from the engage point),
//! `GearOut` disengages it, `DisableGear` unlinks it. One master, many slaves; no chains.
//! The link is the slave's reference source (`source.rs`); the kernel counts each
//! master's slaves.

use api::{AxisError, ErrorCode};

use super::Kernel;
use crate::source::{Engagement, ReferenceSource};

impl Kernel {
    /// HMPL 6.2: both axes enabled; the slave is not yet a slave, nor a master, nor in a gantry.
    pub fn enable_gear(&mut self, master: i64, slave: i64) -> Result<(), ErrorCode> {
        let (m, s) = (self.axis_id(master)?, self.axis_id(slave)?);
        if m == s
            || self.axes[s as usize].is_gear_slave()
            || self.is_gear_master(s)
            || self.axes[m as usize].is_gear_slave()
        {
            return Err(self.refuse(s, AxisError::CmdInvalidMasterSlaveConnection));
        }
        if self.gantry.pair_of(s).is_some() {
            return Err(self.refuse(s, AxisError::CmdInvalidGantryMode));
        }
        for id in [m, s] {
            if !self.axes[id as usize].is_enabled() {
                return Err(self.refuse(id, AxisError::CmdInvalidDisabled));
            }
        }
        if self.axes[s as usize].is_moving() {
            return Err(self.refuse(s, AxisError::CmdInvalidMoving));
        }
        self.axes[s as usize].link_gear(m).map_err(|e| ErrorCode::axis(s, e))?;
        self.gear_slaves[m as usize] += 1;
        Ok(())
    }

    /// HMPL 6.3: unlink (disengaging first).
    pub fn disable_gear(&mut self, slave: i64) -> Result<(), ErrorCode> {
        let s = self.axis_id(slave)?;
        let master = self.axes[s as usize].unlink_gear().map_err(|e| ErrorCode::axis(s, e))?;
        self.gear_slaves[master as usize] -= 1;
        Ok(())
    }

    /// HMPL 6.4: engage at `ratio` (negative too; its range is the registry's).
    pub fn gear_in(&mut self, master: i64, slave: i64, ratio: f64) -> Result<(), ErrorCode> {
        let (m, s) = (self.axis_id(master)?, self.axis_id(slave)?);
        if let Err(e) = self.axes[s as usize].source().may_engage(m) {
            return Err(self.refuse(s, e));
        }
        for id in [m, s] {
            if !self.axes[id as usize].is_enabled() {
                return Err(self.refuse(id, AxisError::CmdInvalidDisabled));
            }
        }
        let engagement = Engagement {
            ratio,
            master_origin: self.axes[m as usize].reference().pos,
            slave_origin: self.axes[s as usize].reference().pos,
        };
        self.axes[s as usize].engage(m, engagement).map_err(|e| ErrorCode::axis(s, e))
    }

    /// HMPL 6.5: disengage; the slave comes to rest from its present motion.
    pub fn gear_out(&mut self, slave: i64) -> Result<(), ErrorCode> {
        let s = self.axis_id(slave)?;
        self.axes[s as usize].gear_out().map_err(|e| ErrorCode::axis(s, e))
    }

    pub(super) fn is_gear_master(&self, id: u8) -> bool {
        self.gear_slaves[id as usize] > 0
    }

    /// Each cycle, after the masters have moved: the engaged slaves follow (HMPL 6.1).
    pub(super) fn follow_gears(&mut self) {
        for s in 0..self.axes.len() {
            if let ReferenceSource::Gear { master, engaged: Some(_) } = *self.axes[s].source() {
                let reference = self.axes[master as usize].reference();
                self.axes[s].follow(reference);
            }
        }
    }
}

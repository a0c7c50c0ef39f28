//! HMPL homing (ch. 20) through the drive's homing mode (CoE manual 3.2): the master
//! writes method, speeds, acceleration and offset by SDO, switches the drive to mode 6,
//! raises controlword bit 4, and watches statusword bits 13, 12, 10 until the homing is
//! attained, fails, or takes longer than the timeout.

use api::AxisError;

use crate::drive_link::{DriveLink, Feedback, MODE_CSP, MODE_HOMING};
use devices::cia402::controlword::NEW_SET_POINT;
use devices::ecat::{Network, SdoError};

/// Table 3-7, `sw & 0x3400`.
const ATTAINED: u16 = 0x1400;
const ERROR: u16 = 0x2000;

/// A homing run, from the cycle it starts to the cycle its result is known; the axis'
/// reference source while it lasts (`motion/source.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Homing {
    /// Writing the homing objects by SDO, `written` of them done: at once in memory, one
    /// mailbox transfer after the other on a wire.
    Configuring {
        since: u64,
        written: usize,
    },
    /// Waiting for 0x6061 to show homing mode.
    Entering {
        since: u64,
    },
    Running {
        since: u64,
    },
    /// Back to csp, with the result to report once there.
    Leaving {
        result: Result<(), AxisError>,
    },
}

impl Homing {
    /// A run starting in `cycle`: the homing objects first (`configure`).
    pub fn new(cycle: u64) -> Self {
        Homing::Configuring { since: cycle, written: 0 }
    }

    /// Writes the homing objects `writes` (index, sub-index, bytes) to `slave` as far as
    /// its mailbox takes them now; once all are written, asks the drive for homing mode.
    /// A refused write fails the run.
    pub fn configure(
        &mut self,
        link: &mut DriveLink,
        network: &mut Network,
        writes: &[(u16, u8, &[u8])],
    ) -> Result<(), AxisError> {
        let Homing::Configuring { since, written } = self else { return Ok(()) };
        while let Some(&(index, sub, data)) = writes.get(*written) {
            match network.sdo_write(link.slave(), index, sub, data) {
                Ok(()) => *written += 1,
                Err(SdoError::Pending | SdoError::MailboxBusy) => return Ok(()),
                Err(_) => return Err(AxisError::DriveHomeFailed),
            }
        }
        *self = Homing::Entering { since: *since };
        Self::enter(link);
        Ok(())
    }

    fn enter(link: &mut DriveLink) {
        link.set_extra_bits(0);
        link.set_mode(MODE_HOMING);
    }

    /// Ends a run early (the axis was disabled or faulted): back to csp.
    pub fn abort(link: &mut DriveLink) {
        link.set_extra_bits(0);
        link.set_mode(MODE_CSP);
    }

    /// One cycle; the result when the run is over (the axis then ends it).
    pub fn step(
        &mut self,
        link: &mut DriveLink,
        fb: &Feedback,
        cycle: u64,
        timeout_cycles: u64,
    ) -> Option<Result<(), AxisError>> {
        let status = fb.statusword & 0x3400;
        match *self {
            Homing::Configuring { since, .. } => {
                if cycle.saturating_sub(since) > timeout_cycles {
                    self.leave(link, Err(AxisError::DriveHomeTout));
                }
                None
            }
            Homing::Entering { since } => {
                if fb.mode_display == Some(MODE_HOMING) {
                    link.set_extra_bits(NEW_SET_POINT);
                    *self = Homing::Running { since };
                } else if cycle.saturating_sub(since) > timeout_cycles {
                    self.leave(link, Err(AxisError::DriveHomeTout));
                }
                None
            }
            Homing::Running { since } => {
                if status == ATTAINED {
                    self.leave(link, Ok(()));
                } else if status & ERROR != 0 {
                    self.leave(link, Err(AxisError::DriveHomeFailed));
                } else if cycle.saturating_sub(since) > timeout_cycles {
                    self.leave(link, Err(AxisError::DriveHomeTout));
                }
                None
            }
            Homing::Leaving { result } => fb.mode_display.is_none_or(|m| m == MODE_CSP).then_some(result),
        }
    }

    fn leave(&mut self, link: &mut DriveLink, result: Result<(), AxisError>) {
        Self::abort(link);
        *self = Homing::Leaving { result };
    }
}

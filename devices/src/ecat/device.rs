//! What a slave holds: the application behind its EtherCAT interface (a drive, later I/O
//! and analog terminals). The slave's ESM, mailbox, PDO layout and sync checks work on
//! the device's object dictionary only; they know no kind of device.

use std::any::Any;

use crate::coe::ObjectStore;
use crate::ecat::mailbox::SdoAbort;

use config::DC_CYCLES_US;

/// One simulated device behind a slave's EtherCAT interface.
///
/// Its dictionary holds the communication objects a CoE slave needs besides its own:
/// 0x1000, 0x1018, the PDO mappings (0x1600/0x1601, 0x1A00/0x1A01), their assignments
/// (0x1C12/0x1C13) and the SyncManager sync parameters (0x1C32/0x1C33).
pub trait Device: Any + Send {
    /// The device's object dictionary, as the mailbox and the process data read it.
    fn od(&self) -> &ObjectStore;
    /// The dictionary for writing: the slave stores downloads and outputs into it.
    fn od_mut(&mut self) -> &mut ObjectStore;

    /// One bus cycle of `period_s` seconds: outputs are in the dictionary, inputs go back
    /// into it.
    fn step(&mut self, period_s: f64);

    /// A download the device acts on itself rather than storing it (the slave has checked
    /// access, length and range and its communication rules). `Ok(true)`: taken, do not
    /// store; `Ok(false)`: store the value.
    fn sdo_download(&mut self, index: u16, sub: u8, value: i64) -> Result<bool, SdoAbort> {
        let _ = (index, sub, value);
        Ok(false)
    }

    /// Whether the device runs DC SYNC0 with this cycle (0x1C32:02, ns).
    fn accepts_cycle_time(&self, cycle_ns: i64) -> bool {
        DC_CYCLES_US.iter().any(|&us| us as i64 * 1000 == cycle_ns)
    }

    /// Digital inputs and outputs its description declares (HMPL `GetSlvChNum`).
    fn digital_channels(&self) -> (u8, u8);

    /// Analog inputs and outputs its description declares (HMPL `GetSlvChNum`, ch. 10).
    fn analog_channels(&self) -> (u8, u8) {
        (0, 0)
    }

    /// The ESC's process data watchdog ran out in Op: the master's frames stopped (the
    /// cable, the master). A device that reacts to it does so here.
    fn process_data_lost(&mut self) {}
}

//! The bus the controller builds from the machine file: one drive per axis, in axis order
//! (slave n drives axis n), then the `[[slaves]]` devices in file order; and what the
//! simulation does to its drives. The master (`ecat/`) knows none of these devices.

use crate::config::{AxisConfig, MachineConfig};
use crate::drive::{Drive, FaultInjectionError};
use crate::ecat::Network;
use crate::ecat::network::SlaveSetup;

impl Network {
    /// One drive per axis, in ring order.
    pub fn new(axes: &[AxisConfig]) -> Self {
        Network::with_slaves(axes.iter().map(drive).collect())
    }

    /// The machine's bus: the axes' drives, then the `[[slaves]]` devices.
    pub fn for_machine(config: &MachineConfig) -> Self {
        let mut slaves: Vec<SlaveSetup> = config.axes.iter().map(drive).collect();
        slaves.extend(config.slaves.iter().map(|slave| match slave.device {}));
        Network::with_slaves(slaves)
    }

    /// Simulation only: a drive fault of CoE manual table 4-16.
    pub fn inject_fault(&mut self, slave: usize, code: u16) -> Result<(), FaultInjectionError> {
        match self.slaves_mut().get_mut(slave).and_then(|s| s.device_mut_as::<Drive>()) {
            Some(drive) => drive.inject_fault(code),
            None => Err(FaultInjectionError::UnknownCode(code)),
        }
    }
}

/// An axis' drive, with the PDO mapping the master writes to it.
fn drive(axis: &AxisConfig) -> SlaveSetup {
    SlaveSetup { device: Box::new(Drive::new(axis)), rx_pdo: axis.rx_pdo.clone(), tx_pdo: axis.tx_pdo.clone() }
}

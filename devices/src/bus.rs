//! The bus the controller builds from the machine file: one drive per axis, in axis order
//! (slave n drives axis n), then the `[[slaves]]` devices in file order; and what the
//! simulation does to its drives and terminals. The master (`ecat/`) knows none of these devices.

use crate::analog_terminal::AnalogIoTerminal;
use crate::drive::{Drive, FaultInjectionError};
use crate::ecat::network::SlaveSetup;
use crate::ecat::{Device, Network};
use crate::terminal::{DigitalIoTerminal, NoSuchChannel};
use config::{self, AxisConfig, MachineConfig, SlaveConfig, SlaveDevice};

impl Network {
    /// One drive per axis, in ring order.
    pub fn new(axes: &[AxisConfig]) -> Self {
        Network::with_slaves(axes.iter().map(drive).collect())
    }

    /// The machine's bus: the axes' drives, then the `[[slaves]]` devices.
    pub fn for_machine(config: &MachineConfig) -> Self {
        let mut slaves: Vec<SlaveSetup> = config.axes.iter().map(drive).collect();
        slaves.extend(config.slaves.iter().map(slave));
        Network::with_slaves(slaves)
    }

    /// Simulation only: a drive fault of CoE manual table 4-16.
    pub fn inject_fault(&mut self, slave: usize, code: u16) -> Result<(), FaultInjectionError> {
        if !self.is_simulated() {
            return Err(FaultInjectionError::NotSimulated(slave));
        }
        match self.slaves_mut().get_mut(slave).and_then(|s| s.device_mut_as::<Drive>()) {
            Some(drive) => drive.inject_fault(code),
            None => Err(FaultInjectionError::NotADrive(slave)),
        }
    }

    /// Simulation only: where the flexible load behind the drive at `slave` is (counts, drive
    /// coordinates); `None` for a rigid load, a slave that is not a drive, or on a wire.
    pub fn load_position(&self, slave: usize) -> Option<f64> {
        if !self.is_simulated() {
            return None;
        }
        self.slaves().get(slave).and_then(|s| s.device_as::<Drive>()).and_then(Drive::load_position)
    }

    /// Simulation only: the switch on input `channel` of the digital I/O terminal at
    /// `slave` (a drive's inputs are not simulated, nor is any input on a wire).
    pub fn set_terminal_input(&mut self, slave: usize, channel: i64, on: bool) -> Result<(), NoSuchChannel> {
        if !self.is_simulated() {
            return Err(NoSuchChannel(channel));
        }
        match self.slaves_mut().get_mut(slave).and_then(|s| s.device_mut_as::<DigitalIoTerminal>()) {
            Some(terminal) => terminal.set_input(channel, on),
            None => Err(NoSuchChannel(channel)),
        }
    }

    /// Simulation only: the word on input `channel` of the analog I/O terminal at `slave`
    /// (none on a wire).
    pub fn set_analog_input(&mut self, slave: usize, channel: i64, word: i64) -> Result<(), NoSuchChannel> {
        if !self.is_simulated() {
            return Err(NoSuchChannel(channel));
        }
        match self.slaves_mut().get_mut(slave).and_then(|s| s.device_mut_as::<AnalogIoTerminal>()) {
            Some(terminal) => terminal.set_input(channel, word),
            None => Err(NoSuchChannel(channel)),
        }
    }
}

/// A `[[slaves]]` device with its own PDO mapping.
fn slave(config: &SlaveConfig) -> SlaveSetup {
    let device: Box<dyn Device> = match config.device {
        SlaveDevice::DigitalIo => Box::new(DigitalIoTerminal::new(config.inputs, config.outputs)),
        SlaveDevice::AnalogIo => Box::new(AnalogIoTerminal::new(config.inputs, config.outputs, config.loopback)),
    };
    SlaveSetup::own_mapping(device)
}

/// An axis' drive, with the PDO mapping the master writes to it: the touch probe's objects
/// in the second PDOs unless the machine file says otherwise.
fn drive(axis: &AxisConfig) -> SlaveSetup {
    let probe = |entries: &[u32]| axis.touch_probe_pdo.then(|| entries.to_vec());
    SlaveSetup {
        device: Box::new(Drive::new(axis)),
        rx_pdo: axis.rx_pdo.clone(),
        tx_pdo: axis.tx_pdo.clone(),
        rx_pdo_2: probe(&config::TOUCH_PROBE_RX_PDO),
        tx_pdo_2: probe(axis.touch_probe_tx_pdo()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fault goes to a drive of table 4-16 only; a slave that is not one says so.
    #[test]
    fn faults_are_injected_into_drives_only() {
        let mut network = Network::new(&[AxisConfig::default()]);
        assert_eq!(network.inject_fault(0, 0x2310), Ok(()));
        assert_eq!(network.inject_fault(0, 0x1234), Err(FaultInjectionError::UnknownCode(0x1234)));
        assert_eq!(network.inject_fault(1, 0x2310), Err(FaultInjectionError::NotADrive(1)));
    }
}

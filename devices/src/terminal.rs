//! A simulated EtherCAT digital I/O terminal (`[[slaves]] device = "digital_io"`, HMPL
//! 9.3, 9.5): up to 32 inputs in one word the master reads (0x6000:01, TxPDO) and up to
//! 32 outputs in one word it writes (0x7000:01, RxPDO); channel n is bit n - 1. The
//! master reaches it through process data only; the simulator's switches on its inputs
//! (`SimSetSlvGPI`) go to the device directly, as `inject_fault` does for a drive.

use config::MAX_TERMINAL_CHANNELS;
use schema::channel_mask;

use crate::coe::{
    ALL_VARIANTS, DataType, ObjId, ObjectDef, ObjectStore, RO, RO_PDO, RW, RW_PDO, id, terminal_object as row,
};
use crate::ecat::Device;

/// Any value of a 32-bit word.
const ANY: (i64, i64) = (0, u32::MAX as i64);
use DataType::{UInt8, UInt16, UInt32};

/// The terminal's dictionary: the communication objects and its two process-data words.
static OBJECTS: &[ObjectDef] = &[
    // CiA 401 (generic I/O modules) as the device profile.
    row(0x1000, 0, "Device type", UInt32, RO, ANY, 401),
    row(0x1600, 0, "RxPDO mapping: number of objects", UInt8, RW, (0, 1), 1),
    row(0x1600, 1, "RxPDO mapping: outputs", UInt32, RW, ANY, 0x7000_0120),
    row(0x1A00, 0, "TxPDO mapping: number of objects", UInt8, RW, (0, 1), 1),
    row(0x1A00, 1, "TxPDO mapping: inputs", UInt32, RW, ANY, 0x6000_0120),
    row(0x1C12, 0, "SM2 PDO assignment: number of assigned RxPDOs", UInt8, RW, (0, 1), 1),
    row(0x1C12, 1, "PDO mapping index of assigned RxPDO 1", UInt16, RW, (0, 0x1600), 0x1600),
    row(0x1C13, 0, "SM3 PDO assignment: number of assigned TxPDOs", UInt8, RW, (0, 1), 1),
    row(0x1C13, 1, "PDO mapping index of assigned TxPDO 1", UInt16, RW, (0, 0x1A00), 0x1A00),
    row(0x1C32, 1, "Synchronization type", UInt16, RW, (0, 2), 0),
    row(0x1C32, 2, "Cycle time", UInt32, RW, ANY, 0),
    row(0x6000, 1, "Digital inputs, channel n = bit n - 1", UInt32, RO_PDO, ANY, 0),
    row(0x7000, 1, "Digital outputs, channel n = bit n - 1", UInt32, RW_PDO, ANY, 0),
];

const INPUTS: ObjId = id(OBJECTS, 0x6000, 1);
const OUTPUTS: ObjId = id(OBJECTS, 0x7000, 1);

/// A channel the terminal does not have.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the terminal has no input {0}")]
pub struct NoSuchChannel(pub i64);

/// A digital I/O terminal on the bus: its dictionary, its channel counts and the
/// simulator's input switches.
pub struct DigitalIoTerminal {
    od: ObjectStore,
    inputs: u8,
    outputs: u8,
    /// The simulator's input switches, bit n - 1 = channel n.
    levels: u32,
}

impl DigitalIoTerminal {
    /// A terminal with `inputs` and `outputs` channels (at most 32 each, more are cut).
    pub fn new(inputs: u8, outputs: u8) -> Self {
        let (inputs, outputs) = (inputs.min(MAX_TERMINAL_CHANNELS), outputs.min(MAX_TERMINAL_CHANNELS));
        DigitalIoTerminal { od: ObjectStore::new(OBJECTS, ALL_VARIANTS), inputs, outputs, levels: 0 }
    }

    /// Simulation only: the switch on input `channel` (1-based) on or off.
    pub fn set_input(&mut self, channel: i64, on: bool) -> Result<(), NoSuchChannel> {
        if !(1..=self.inputs as i64).contains(&channel) {
            return Err(NoSuchChannel(channel));
        }
        let bit = 1 << (channel - 1);
        if on {
            self.levels |= bit
        } else {
            self.levels &= !bit
        }
        Ok(())
    }

    /// The output word as the terminal drives its channels (what the master last sent).
    pub fn outputs(&self) -> u32 {
        self.od.get(OUTPUTS) as u32 & channel_mask(self.outputs)
    }
}

impl Device for DigitalIoTerminal {
    fn od(&self) -> &ObjectStore {
        &self.od
    }

    fn od_mut(&mut self) -> &mut ObjectStore {
        &mut self.od
    }

    fn step(&mut self, _period_s: f64) {
        self.od.set(INPUTS, (self.levels & channel_mask(self.inputs)) as i64);
    }

    fn digital_channels(&self) -> (u8, u8) {
        (self.inputs, self.outputs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecat::Network;
    use crate::ecat::network::SlaveSetup;

    /// The master lays the terminal out from its mapping objects and reaches its channels
    /// through the two process-data words only.
    #[test]
    fn channels_travel_in_process_data() {
        let setup = SlaveSetup::own_mapping(Box::new(DigitalIoTerminal::new(4, 8)));
        let mut net = Network::with_slaves(vec![setup]);
        net.start(1_000_000).expect("start-up to Op");
        let (inputs, outputs) = (net.input_field(0, 0x6000, 1).unwrap(), net.output_field(0, 0x7000, 1).unwrap());
        let terminal = net.slaves_mut()[0].device_mut_as::<DigitalIoTerminal>().unwrap();
        terminal.set_input(1, true).unwrap();
        terminal.set_input(4, true).unwrap();
        assert_eq!(terminal.set_input(5, true), Err(NoSuchChannel(5)), "4 inputs");
        assert_eq!(terminal.set_input(0, true), Err(NoSuchChannel(0)), "channels count from 1");
        outputs.write(net.images_mut().1, 0x1_0006);
        net.exchange(1e-3);
        assert_eq!(inputs.read(net.images_mut().0), 9, "inputs 1 and 4");
        let terminal = net.slaves()[0].device_as::<DigitalIoTerminal>().unwrap();
        assert_eq!(terminal.outputs(), 6, "outputs 2 and 3; bit 16 is no channel of 8");
    }
}

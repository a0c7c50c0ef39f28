//! A simulated EtherCAT analog I/O terminal (`[[slaves]] device = "analog_io"`, HMPL
//! ch. 10) with the objects of the CiA 401 profile: up to 4 inputs as "Read analogue
//! input 16-bit" 0x6401:01.. (INT16, TxPDO) and up to 4 outputs as "Write analogue output
//! 16-bit" 0x6411:01.. (INT16, RxPDO). A channel is the converter's 16-bit word; what it
//! means in volts or mA is the controller's conversion type (HMPL table 10.1.1). The
//! master reaches it through process data only; the simulator's signals on its inputs
//! (`SimSetSlvAIRaw`) go to the device directly, as `inject_fault` does for a drive. With
//! `loopback` output n is wired to input n.

use schema::{ANALOG_INPUTS, ANALOG_OUTPUTS, MAX_ANALOG_CHANNELS};

use crate::coe::{
    ALL_VARIANTS, DataType, ObjId, ObjectDef, ObjectStore, RO, RO_PDO, RW, RW_PDO, id, terminal_object as row,
};
use crate::ecat::Device;
use crate::terminal::NoSuchChannel;

/// An INT16 word, the channel counts, any 32-bit word.
const WORD: (i64, i64) = (i16::MIN as i64, i16::MAX as i64);
const CHANNELS: (i64, i64) = (0, MAX_ANALOG_CHANNELS as i64);
const ANY: (i64, i64) = (0, u32::MAX as i64);
use DataType::{Int16, UInt8, UInt16, UInt32};

/// A mapping entry of channel `n` of a 16-bit object (index, sub n, 16 bits).
const fn entry(index: u16, n: u8) -> i64 {
    ((index as i64) << 16) | ((n as i64) << 8) | 16
}

/// The terminal's dictionary: the communication objects, one PDO each way whose count
/// (sub 0) is set to the channels the terminal has, and the channels.
static OBJECTS: &[ObjectDef] = &[
    row(0x1000, 0, "Device type", UInt32, RO, ANY, 401),
    row(0x1600, 0, "RxPDO mapping: number of objects", UInt8, RW, CHANNELS, 0),
    row(0x1600, 1, "RxPDO mapping: output 1", UInt32, RW, ANY, entry(ANALOG_OUTPUTS, 1)),
    row(0x1600, 2, "RxPDO mapping: output 2", UInt32, RW, ANY, entry(ANALOG_OUTPUTS, 2)),
    row(0x1600, 3, "RxPDO mapping: output 3", UInt32, RW, ANY, entry(ANALOG_OUTPUTS, 3)),
    row(0x1600, 4, "RxPDO mapping: output 4", UInt32, RW, ANY, entry(ANALOG_OUTPUTS, 4)),
    row(0x1A00, 0, "TxPDO mapping: number of objects", UInt8, RW, CHANNELS, 0),
    row(0x1A00, 1, "TxPDO mapping: input 1", UInt32, RW, ANY, entry(ANALOG_INPUTS, 1)),
    row(0x1A00, 2, "TxPDO mapping: input 2", UInt32, RW, ANY, entry(ANALOG_INPUTS, 2)),
    row(0x1A00, 3, "TxPDO mapping: input 3", UInt32, RW, ANY, entry(ANALOG_INPUTS, 3)),
    row(0x1A00, 4, "TxPDO mapping: input 4", UInt32, RW, ANY, entry(ANALOG_INPUTS, 4)),
    row(0x1C12, 0, "SM2 PDO assignment: number of assigned RxPDOs", UInt8, RW, (0, 1), 1),
    row(0x1C12, 1, "PDO mapping index of assigned RxPDO 1", UInt16, RW, (0x1600, 0x1600), 0x1600),
    row(0x1C13, 0, "SM3 PDO assignment: number of assigned TxPDOs", UInt8, RW, (0, 1), 1),
    row(0x1C13, 1, "PDO mapping index of assigned TxPDO 1", UInt16, RW, (0x1A00, 0x1A00), 0x1A00),
    row(0x1C32, 1, "Synchronization type", UInt16, RW, (0, 2), 0),
    row(0x1C32, 2, "Cycle time", UInt32, RW, ANY, 0),
    row(ANALOG_INPUTS, 1, "Analogue input 1", Int16, RO_PDO, WORD, 0),
    row(ANALOG_INPUTS, 2, "Analogue input 2", Int16, RO_PDO, WORD, 0),
    row(ANALOG_INPUTS, 3, "Analogue input 3", Int16, RO_PDO, WORD, 0),
    row(ANALOG_INPUTS, 4, "Analogue input 4", Int16, RO_PDO, WORD, 0),
    row(ANALOG_OUTPUTS, 1, "Analogue output 1", Int16, RW_PDO, WORD, 0),
    row(ANALOG_OUTPUTS, 2, "Analogue output 2", Int16, RW_PDO, WORD, 0),
    row(ANALOG_OUTPUTS, 3, "Analogue output 3", Int16, RW_PDO, WORD, 0),
    row(ANALOG_OUTPUTS, 4, "Analogue output 4", Int16, RW_PDO, WORD, 0),
];

const RX_COUNT: ObjId = id(OBJECTS, 0x1600, 0);
const TX_COUNT: ObjId = id(OBJECTS, 0x1A00, 0);
const INPUTS: [ObjId; MAX_ANALOG_CHANNELS] = [
    id(OBJECTS, ANALOG_INPUTS, 1),
    id(OBJECTS, ANALOG_INPUTS, 2),
    id(OBJECTS, ANALOG_INPUTS, 3),
    id(OBJECTS, ANALOG_INPUTS, 4),
];
const OUTPUTS: [ObjId; MAX_ANALOG_CHANNELS] = [
    id(OBJECTS, ANALOG_OUTPUTS, 1),
    id(OBJECTS, ANALOG_OUTPUTS, 2),
    id(OBJECTS, ANALOG_OUTPUTS, 3),
    id(OBJECTS, ANALOG_OUTPUTS, 4),
];

/// An analog I/O terminal on the bus: its dictionary, its channel counts and the
/// simulator's input signals.
pub struct AnalogIoTerminal {
    od: ObjectStore,
    inputs: u8,
    outputs: u8,
    loopback: bool,
    /// The simulator's signals on the inputs, as converter words.
    levels: [i16; MAX_ANALOG_CHANNELS],
}

impl AnalogIoTerminal {
    /// A terminal with `inputs` and `outputs` channels (at most 4 each, more are cut),
    /// output n wired to input n when `loopback`.
    pub fn new(inputs: u8, outputs: u8, loopback: bool) -> Self {
        let max = MAX_ANALOG_CHANNELS as u8;
        let (inputs, outputs) = (inputs.min(max), outputs.min(max));
        let mut od = ObjectStore::new(OBJECTS, ALL_VARIANTS);
        od.set(RX_COUNT, outputs as i64);
        od.set(TX_COUNT, inputs as i64);
        AnalogIoTerminal { od, inputs, outputs, loopback, levels: [0; MAX_ANALOG_CHANNELS] }
    }

    /// Simulation only: the word the converter reads on input `channel` (1-based); its
    /// 16 bits, given as 0..65535 or -32768..32767. Refused on an input wired to an output.
    pub fn set_input(&mut self, channel: i64, word: i64) -> Result<(), NoSuchChannel> {
        let looped = self.loopback && channel <= self.outputs as i64;
        if !(1..=self.inputs as i64).contains(&channel)
            || looped
            || !(i16::MIN as i64..=u16::MAX as i64).contains(&word)
        {
            return Err(NoSuchChannel(channel));
        }
        self.levels[channel as usize - 1] = word as u16 as i16;
        Ok(())
    }

    /// The word on output `channel` (1-based) as the master last sent it.
    pub fn output(&self, channel: usize) -> Option<i16> {
        (1..=self.outputs as usize).contains(&channel).then(|| self.od.get(OUTPUTS[channel - 1]) as i16)
    }
}

impl Device for AnalogIoTerminal {
    fn od(&self) -> &ObjectStore {
        &self.od
    }

    fn od_mut(&mut self) -> &mut ObjectStore {
        &mut self.od
    }

    fn step(&mut self, _period_s: f64) {
        for n in 0..self.inputs as usize {
            let word = match self.loopback && n < self.outputs as usize {
                true => self.od.get(OUTPUTS[n]),
                false => self.levels[n] as i64,
            };
            self.od.set(INPUTS[n], word);
        }
    }

    fn digital_channels(&self) -> (u8, u8) {
        (0, 0)
    }

    fn analog_channels(&self) -> (u8, u8) {
        (self.inputs, self.outputs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecat::Network;
    use crate::ecat::network::SlaveSetup;

    fn network(terminal: AnalogIoTerminal) -> Network {
        let mut net = Network::with_slaves(vec![SlaveSetup::own_mapping(Box::new(terminal))]);
        net.start(1_000_000).expect("start-up to Op");
        net
    }

    /// The master lays out as many 16-bit words as the terminal has channels, from its
    /// mapping objects, and reaches the channels through them only.
    #[test]
    fn channels_travel_in_process_data() {
        let mut net = network(AnalogIoTerminal::new(2, 3, false));
        assert!(net.input_field(0, ANALOG_INPUTS, 3).is_none(), "2 inputs mapped");
        assert!(net.output_field(0, ANALOG_OUTPUTS, 4).is_none(), "3 outputs mapped");
        let (input, output) =
            (net.input_field(0, ANALOG_INPUTS, 2).unwrap(), net.output_field(0, ANALOG_OUTPUTS, 3).unwrap());
        let terminal = net.slaves_mut()[0].device_mut_as::<AnalogIoTerminal>().unwrap();
        terminal.set_input(2, 0xC000).unwrap();
        assert_eq!(terminal.set_input(3, 0), Err(NoSuchChannel(3)), "2 inputs");
        assert_eq!(terminal.set_input(1, 65536), Err(NoSuchChannel(1)), "a word has 16 bits");
        output.write(net.images_mut().1, -16384);
        net.exchange(1e-3);
        assert_eq!(input.read(net.images_mut().0), 0xC000_u16 as i16 as i64, "the word as sent, INT16");
        let terminal = net.slaves()[0].device_as::<AnalogIoTerminal>().unwrap();
        assert_eq!((terminal.output(3), terminal.output(4)), (Some(-16384), None));
    }

    /// With `loopback` output n comes back on input n; the simulator cannot drive it too.
    #[test]
    fn loopback_wires_outputs_to_inputs() {
        let mut net = network(AnalogIoTerminal::new(2, 1, true));
        let (input, output) =
            (net.input_field(0, ANALOG_INPUTS, 1).unwrap(), net.output_field(0, ANALOG_OUTPUTS, 1).unwrap());
        let terminal = net.slaves_mut()[0].device_mut_as::<AnalogIoTerminal>().unwrap();
        assert_eq!(terminal.set_input(1, 5), Err(NoSuchChannel(1)), "input 1 is wired to output 1");
        terminal.set_input(2, 7).unwrap();
        output.write(net.images_mut().1, 12345);
        net.exchange(1e-3);
        net.exchange(1e-3);
        assert_eq!(input.read(net.images_mut().0), 12345);
        let second = net.input_field(0, ANALOG_INPUTS, 2).unwrap();
        assert_eq!(second.read(net.images_mut().0), 7, "input 2 has no output to follow");
    }
}

//! The master's side of an axis' touch probes (HMPL ch. 13): the function word it sends
//! in 0x60B8 and the status and edge positions it reads from 0x60B9 and 0x60BA..0x60BD,
//! all through process data (the second PDOs by default, docs/decisions.md "Touch probe").
//! The word follows CiA 402 (CoE table 4-18 for probe 1; probe 2 in the high byte).

use api::AxisError;

use config::{AxisConfig, TouchProbeKind};
use devices::cia402::touch_probe::*;
use devices::ecat::{Field, Network};

/// What `SetTouchProbeNFunc` chose of one probe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Function {
    index: bool,
    continuous: bool,
    falling: bool,
}

impl Function {
    /// The probe's byte of 0x60B8, without the enable bit.
    fn bits(self) -> u16 {
        let source = if self.index { SOURCE_INDEX } else { 0 };
        let trigger = if self.continuous { CONTINUOUS } else { 0 };
        let edge = if self.falling { NEGATIVE_EDGE } else { POSITIVE_EDGE };
        source | trigger | edge
    }
}

/// Where one probe's handshake with the drive stands: 0x60B9's enable bit echoes 0x60B8's
/// (CoE table 4-18). A word the master changes reaches the probe through off, as a re-arm
/// does: the probe is off in the word until the status shows it off, then on with the new
/// word, and its status counts from when the drive shows it on. A frame may take any
/// number of cycles there and back (on a wire, more when one is lost), so the master
/// waits for the echo rather than counting cycles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Handshake {
    /// The status answers the present word.
    Settled,
    /// Off in the word until the status shows the probe off.
    SwitchingOff,
    /// On in the word until the status shows it on.
    SwitchingOn,
}

/// One probe's fields in the process data.
#[derive(Clone, Copy, Debug, Default)]
struct Fields {
    positive: Option<Field>,
    negative: Option<Field>,
}

/// An axis' two touch probes (HMPL 13.1): what the master asked of each and what the drive
/// latched.
pub struct TouchProbes {
    kind: TouchProbeKind,
    function_field: Option<Field>,
    status_field: Option<Field>,
    probes: [Fields; 2],
    /// Per probe: what it latches, and whether the master enabled it.
    functions: [Function; 2],
    enabled: [bool; 2],
    handshakes: [Handshake; 2],
    status: u16,
    /// [probe][positive, negative], counts.
    latched: [[i64; 2]; 2],
}

impl TouchProbes {
    pub(crate) fn new(slave: usize, config: &AxisConfig, network: &Network) -> Self {
        let inp = |i| network.input_field(slave, i, 0);
        TouchProbes {
            kind: config.drive_settings.touch_probe,
            function_field: network.output_field(slave, 0x60B8, 0),
            status_field: inp(0x60B9),
            probes: [
                Fields { positive: inp(0x60BA), negative: inp(0x60BB) },
                Fields { positive: inp(0x60BC), negative: inp(0x60BD) },
            ],
            // HMPL 13.12 lists the external signal first; the index is what every drive has.
            functions: [Function { index: true, continuous: false, falling: false }; 2],
            enabled: [false; 2],
            handshakes: [Handshake::Settled; 2],
            status: 0,
            latched: [[0; 2]; 2],
        }
    }

    /// The probe's objects are in the process data: the function, the status and the
    /// position of the edge it latches.
    pub fn mapped(&self, probe: usize) -> bool {
        let fields = &self.probes[probe];
        let edge = if self.functions[probe].falling { fields.negative } else { fields.positive };
        self.function_field.is_some() && self.status_field.is_some() && edge.is_some()
    }

    fn check_mapped(&self, probe: usize) -> Result<(), AxisError> {
        if self.mapped(probe) { Ok(()) } else { Err(AxisError::CmdInvalidNoSpecificPdo) }
    }

    /// HMPL 13.2, 13.3: armed anew, also when it was on.
    pub fn enable(&mut self, probe: usize) -> Result<(), AxisError> {
        self.check_mapped(probe)?;
        self.enabled[probe] = true;
        self.handshakes[probe] = Handshake::SwitchingOff;
        Ok(())
    }

    /// HMPL 13.4, 13.5.
    pub fn disable(&mut self, probe: usize) -> Result<(), AxisError> {
        self.check_mapped(probe)?;
        self.enabled[probe] = false;
        self.handshakes[probe] = Handshake::SwitchingOff;
        Ok(())
    }

    /// HMPL 13.12, 13.13: each argument 0 or 1; the probe input only on a drive that has
    /// one (docs/decisions.md, "Touch probe").
    pub fn set_function(&mut self, probe: usize, tp_input: i64, cont: i64, edge: i64) -> Result<(), AxisError> {
        if [tp_input, cont, edge].iter().any(|v| !(0..=1).contains(v)) {
            return Err(AxisError::CmdInvalidParameter);
        }
        if tp_input == 0 && self.kind == TouchProbeKind::Index {
            return Err(AxisError::CmdInvalidParameter);
        }
        let function = Function { index: tp_input == 1, continuous: cont == 1, falling: edge == 1 };
        let before = std::mem::replace(&mut self.functions[probe], function);
        if let Err(e) = self.check_mapped(probe) {
            self.functions[probe] = before;
            return Err(e);
        }
        if self.enabled[probe] {
            self.handshakes[probe] = Handshake::SwitchingOff;
        }
        Ok(())
    }

    /// Reads this cycle's inputs, and where each probe's handshake now stands.
    pub fn read(&mut self, inputs: &[u8]) {
        let read = |f: Option<Field>| f.map_or(0, |f| f.read(inputs));
        self.status = read(self.status_field) as u16;
        for probe in 0..2 {
            let on = self.probe_status(probe) & STATUS_ENABLED != 0;
            self.handshakes[probe] = match self.handshakes[probe] {
                Handshake::SwitchingOff if !on && self.enabled[probe] => Handshake::SwitchingOn,
                Handshake::SwitchingOff if !on => Handshake::Settled,
                Handshake::SwitchingOn if on => Handshake::Settled,
                waiting => waiting,
            };
        }
        for (probe, fields) in self.probes.iter().enumerate() {
            self.latched[probe] = [read(fields.positive), read(fields.negative)];
        }
    }

    /// Writes 0x60B8.
    pub fn write(&self, outputs: &mut [u8]) {
        if let Some(field) = self.function_field {
            let word = (0..2)
                .filter(|&p| self.enabled[p] && self.handshakes[p] != Handshake::SwitchingOff)
                .fold(0u16, |word, p| word | (self.functions[p].bits() | ENABLE) << (PROBE_2_SHIFT * p));
            field.write(outputs, word as i64);
        }
    }

    pub(crate) fn enabled(&self, probe: usize) -> bool {
        self.enabled[probe]
    }

    /// The drive stored the selected edge since the probe was armed with the present word.
    pub fn triggered(&self, probe: usize) -> bool {
        let stored = if self.functions[probe].falling { STATUS_NEGATIVE_STORED } else { STATUS_POSITIVE_STORED };
        self.enabled[probe] && self.handshakes[probe] == Handshake::Settled && self.probe_status(probe) & stored != 0
    }

    /// The probe's byte of 0x60B9.
    fn probe_status(&self, probe: usize) -> u16 {
        (self.status >> (PROBE_2_SHIFT * probe)) & 0xFF
    }

    /// The selected edge's latched position, counts.
    pub fn latched(&self, probe: usize) -> i64 {
        self.latched[probe][self.functions[probe].falling as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use config::{AxisConfig, MachineConfig};

    /// Probe 1 of a CiA 402 drive's axis, and where its status sits in the inputs.
    fn probe() -> (TouchProbes, Field, Field, Vec<u8>, Vec<u8>) {
        let mut axis = AxisConfig::default();
        axis.drive_settings.touch_probe = TouchProbeKind::Cia402;
        let config = MachineConfig { axes: vec![axis], ..MachineConfig::default() };
        let mut network = Network::new(&config.axes);
        network.start(config.period_ns()).unwrap();
        let probes = TouchProbes::new(0, &config.axes[0], &network);
        // Room for one drive's images, wherever the fields sit in them.
        let (inputs, outputs) = (vec![0; 512], vec![0; 512]);
        let status = network.input_field(0, 0x60B9, 0).unwrap();
        let function = network.output_field(0, 0x60B8, 0).unwrap();
        (probes, status, function, inputs, outputs)
    }

    /// A re-arm over a wire whose frames come back late: each row is one cycle, the status
    /// the frame back brings (0x60B9, CoE table 4-19: bit 0 enabled, bit 1 positive edge
    /// stored), and what the master then sends (0x60B8 bit 0) and reports as triggered.
    /// Stale statuses from before the re-arm never count as a new edge.
    #[test]
    fn a_re_arm_waits_for_the_drive_to_echo_off_and_on() {
        let (mut probes, status, function, mut inputs, mut outputs) = probe();
        probes.set_function(0, 1, 0, 0).unwrap();
        type Row = (&'static str, Option<fn(&mut TouchProbes)>, u16, bool, bool);
        let rows: [Row; 8] = [
            ("enabled", Some(|p| p.enable(0).unwrap()), 0x00, true, false),
            ("drive echoes on", None, 0x01, true, false),
            ("edge stored", None, 0x03, true, true),
            ("disabled", Some(|p| p.disable(0).unwrap()), 0x03, false, false),
            ("enabled again, stale status", Some(|p| p.enable(0).unwrap()), 0x03, false, false),
            ("still stale", None, 0x03, false, false),
            ("drive echoes off", None, 0x00, true, false),
            ("drive echoes on: armed", None, 0x01, true, false),
        ];
        for (what, call, back, sent_on, triggered) in rows {
            if let Some(call) = call {
                call(&mut probes);
            }
            status.write(&mut inputs, i64::from(back));
            probes.read(&inputs);
            probes.write(&mut outputs);
            assert_eq!(function.read(&outputs) & i64::from(ENABLE) != 0, sent_on, "{what}: 0x60B8 enable");
            assert_eq!(probes.triggered(0), triggered, "{what}: triggered");
        }
        status.write(&mut inputs, 0x03);
        probes.read(&inputs);
        assert!(probes.triggered(0), "an edge after the re-arm counts");
    }
}

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
    /// Frames until the drive's status answers the word last changed: the word goes out
    /// with the next frame, and the status of that frame is read the cycle after.
    echo_pending: u8,
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
            echo_pending: 0,
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

    /// HMPL 13.2, 13.3.
    pub fn enable(&mut self, probe: usize) -> Result<(), AxisError> {
        self.check_mapped(probe)?;
        self.enabled[probe] = true;
        self.echo_pending = 2;
        Ok(())
    }

    /// HMPL 13.4, 13.5.
    pub fn disable(&mut self, probe: usize) -> Result<(), AxisError> {
        self.check_mapped(probe)?;
        self.enabled[probe] = false;
        self.echo_pending = 2;
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
        self.echo_pending = 2;
        Ok(())
    }

    /// Reads this cycle's inputs.
    pub fn read(&mut self, inputs: &[u8]) {
        self.echo_pending = self.echo_pending.saturating_sub(1);
        let read = |f: Option<Field>| f.map_or(0, |f| f.read(inputs));
        self.status = read(self.status_field) as u16;
        for (probe, fields) in self.probes.iter().enumerate() {
            self.latched[probe] = [read(fields.positive), read(fields.negative)];
        }
    }

    /// Writes 0x60B8.
    pub fn write(&self, outputs: &mut [u8]) {
        if let Some(field) = self.function_field {
            let word = (0..2)
                .filter(|&p| self.enabled[p])
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
        self.enabled[probe] && self.echo_pending == 0 && (self.status >> (PROBE_2_SHIFT * probe)) & stored != 0
    }

    /// The selected edge's latched position, counts.
    pub fn latched(&self, probe: usize) -> i64 {
        self.latched[probe][self.functions[probe].falling as usize]
    }
}

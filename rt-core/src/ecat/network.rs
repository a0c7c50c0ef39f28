//! The simulated EtherCAT segment: the slaves in ring order and the process image the
//! master exchanges with them once per cycle, as one frame would.

use std::ops::Range;

use crate::config::AxisConfig;
use crate::drive::od::DataType;
use crate::ecat::esm::{AlState, AlStatusCode};
use crate::ecat::slave::Slave;

/// Where one mapped object sits in the master's process image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    offset: usize,
    ty: DataType,
}

impl Field {
    pub fn read(self, image: &[u8]) -> i64 {
        self.ty.decode(&image[self.offset..])
    }

    pub fn write(self, image: &mut [u8], value: i64) {
        self.ty.encode(value, &mut image[self.offset..]);
    }
}

/// Why the master could not bring the network to Op.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("slave {slave} refused {target:?} with AL status code {code:?} (0x{:04X})", *code as u16)]
pub struct StartError {
    pub slave: usize,
    pub target: AlState,
    pub code: AlStatusCode,
}

pub struct Network {
    slaves: Vec<Slave>,
    outputs: Vec<u8>,
    inputs: Vec<u8>,
    output_ranges: Vec<Range<usize>>,
    input_ranges: Vec<Range<usize>>,
}

impl Network {
    /// One drive per axis, in ring order.
    pub fn new(axes: &[AxisConfig]) -> Self {
        Network {
            slaves: axes.iter().map(Slave::new).collect(),
            outputs: Vec::new(),
            inputs: Vec::new(),
            output_ranges: Vec::new(),
            input_ranges: Vec::new(),
        }
    }

    pub fn slaves(&self) -> &[Slave] {
        &self.slaves
    }

    pub fn slave_mut(&mut self, index: usize) -> &mut Slave {
        &mut self.slaves[index]
    }

    /// The master's start-up: every slave Init -> PreOp (mailbox up, PDO mapping
    /// configured) -> SafeOp (mapping validated, process image laid out) -> Op. On a
    /// refusal the network stays where it stopped.
    pub fn start(&mut self) -> Result<(), StartError> {
        for target in [AlState::PreOp, AlState::SafeOp, AlState::Op] {
            for (slave, s) in self.slaves.iter_mut().enumerate() {
                s.request_state(target).map_err(|code| StartError { slave, target, code })?;
            }
            if target == AlState::SafeOp {
                self.lay_out_image();
            }
        }
        Ok(())
    }

    fn lay_out_image(&mut self) {
        let (mut out_len, mut in_len) = (0, 0);
        self.output_ranges.clear();
        self.input_ranges.clear();
        for s in &self.slaves {
            let (rx, tx) = s.pdo_lengths();
            self.output_ranges.push(out_len..out_len + rx);
            self.input_ranges.push(in_len..in_len + tx);
            out_len += rx;
            in_len += tx;
        }
        self.outputs = vec![0; out_len];
        self.inputs = vec![0; in_len];
    }

    /// The master state `GetECATSt` reports: the lowest state of any slave.
    pub fn state(&self) -> AlState {
        self.slaves.iter().map(|s| s.esm().state()).min().unwrap_or(AlState::Init)
    }

    /// One frame: every slave takes its outputs, runs one cycle and returns its inputs.
    pub fn exchange(&mut self, period_s: f64) {
        for (i, slave) in self.slaves.iter_mut().enumerate() {
            let outputs = &self.outputs[self.output_ranges.get(i).cloned().unwrap_or(0..0)];
            let inputs = match self.input_ranges.get(i) {
                Some(r) => &mut self.inputs[r.clone()],
                None => &mut [][..],
            };
            slave.cycle(outputs, inputs, period_s);
        }
    }

    /// The master's view of the last frame: inputs to read, outputs to write.
    pub fn images_mut(&mut self) -> (&[u8], &mut [u8]) {
        (&self.inputs, &mut self.outputs)
    }

    /// Where object `index:sub` of `slave` sits in the outputs (RxPDO), if mapped.
    pub fn output_field(&self, slave: usize, index: u16, sub: u8) -> Option<Field> {
        let base = self.output_ranges.get(slave)?.start;
        Self::find(self.slaves[slave].rx_mapping(), base, index, sub)
    }

    /// Where object `index:sub` of `slave` sits in the inputs (TxPDO), if mapped.
    pub fn input_field(&self, slave: usize, index: u16, sub: u8) -> Option<Field> {
        let base = self.input_ranges.get(slave)?.start;
        Self::find(self.slaves[slave].tx_mapping(), base, index, sub)
    }

    fn find(mapping: &[crate::ecat::pdo::Mapped], base: usize, index: u16, sub: u8) -> Option<Field> {
        let wanted = crate::drive::od::find(index, sub)?;
        mapping.iter().find(|m| m.obj == wanted).map(|m| Field { offset: base + m.offset, ty: m.ty })
    }
}

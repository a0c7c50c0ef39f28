//! The simulated EtherCAT segment: the slaves in ring order, the master's start-up, the
//! process image exchanged once per cycle as one frame would, and the mailbox.

use std::ops::Range;

use crate::config::AxisConfig;
use crate::drive::FaultInjectionError;
use crate::drive::od::DataType;
use crate::ecat::esm::{AlState, AlStatusCode};
use crate::ecat::mailbox::SdoError;
use crate::ecat::pdo::Mapped;
use crate::ecat::slave::{ESC_DC_SYNC0, ESC_SYNC_ACTIVATION, Slave};

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

    pub fn data_type(self) -> DataType {
        self.ty
    }
}

/// Why the master could not bring the network to Op. The network stays where it stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum StartError {
    #[error("slave {slave} refused {target:?} with AL status code 0x{:04X} ({code:?})", code.code())]
    Refused { slave: usize, target: AlState, code: AlStatusCode },
    #[error("slave {slave}: SDO 0x{index:04X}:{sub} failed during configuration: {error}")]
    Sdo { slave: usize, index: u16, sub: u8, error: SdoError },
}

/// The custom PDO mapping of one slave, written by the master in PreOp.
#[derive(Clone, Debug, Default)]
struct Mapping {
    rx: Option<Vec<u32>>,
    tx: Option<Vec<u32>>,
}

pub struct Network {
    slaves: Vec<Slave>,
    mappings: Vec<Mapping>,
    outputs: Vec<u8>,
    inputs: Vec<u8>,
    output_ranges: Vec<Range<usize>>,
    input_ranges: Vec<Range<usize>>,
    start_error: Option<StartError>,
}

impl Network {
    /// One drive per axis, in ring order.
    pub fn new(axes: &[AxisConfig]) -> Self {
        Network {
            slaves: axes.iter().map(Slave::new).collect(),
            mappings: axes.iter().map(|a| Mapping { rx: a.rx_pdo.clone(), tx: a.tx_pdo.clone() }).collect(),
            outputs: Vec::new(),
            inputs: Vec::new(),
            output_ranges: Vec::new(),
            input_ranges: Vec::new(),
            start_error: None,
        }
    }

    pub fn slaves(&self) -> &[Slave] {
        &self.slaves
    }

    /// The master's start-up (CoE manual 2.3): scan, every slave to PreOp, PDO mapping
    /// and the DC cycle configured over the mailbox, SafeOp (mapping and sync checked,
    /// process image laid out), Op. A failure leaves the network where it stopped.
    pub fn start(&mut self, cycle_ns: u64) -> Result<(), StartError> {
        let result = self.bring_up(cycle_ns);
        self.start_error = result.err();
        result
    }

    /// Why the last start-up stopped, if it did.
    pub fn start_error(&self) -> Option<StartError> {
        self.start_error
    }

    fn bring_up(&mut self, cycle_ns: u64) -> Result<(), StartError> {
        self.request_all(AlState::PreOp)?;
        for slave in 0..self.slaves.len() {
            self.configure(slave, cycle_ns)?;
        }
        self.request_all(AlState::SafeOp)?;
        self.lay_out_image();
        self.request_all(AlState::Op)
    }

    fn request_all(&mut self, target: AlState) -> Result<(), StartError> {
        for (slave, s) in self.slaves.iter_mut().enumerate() {
            s.request_state(target).map_err(|code| StartError::Refused { slave, target, code })?;
        }
        Ok(())
    }

    /// PreOp configuration of one slave: its custom PDO mapping (CoE manual 2.4 steps 2-4)
    /// and DC SYNC0 at the controller's cycle (2.5).
    fn configure(&mut self, slave: usize, cycle_ns: u64) -> Result<(), StartError> {
        let Mapping { rx, tx } = self.mappings[slave].clone();
        let mut write = |index: u16, sub: u8, data: &[u8]| {
            self.slaves[slave].sdo_write(index, sub, data).map_err(|error| StartError::Sdo { slave, index, sub, error })
        };
        for (entries, mapping, assignment) in [(rx, 0x1600, 0x1C12), (tx, 0x1A00, 0x1C13)] {
            let Some(entries) = entries else { continue };
            write(assignment, 0, &[0])?;
            write(mapping, 0, &[0])?;
            for (i, entry) in entries.iter().enumerate() {
                write(mapping, i as u8 + 1, &entry.to_le_bytes())?;
            }
            write(mapping, 0, &[entries.len() as u8])?;
            write(assignment, 0, &[1])?;
        }
        write(0x1C32, 2, &(cycle_ns as u32).to_le_bytes())?;
        write(0x1C32, 1, &2u16.to_le_bytes())?;
        self.slaves[slave].write_esc_register(ESC_SYNC_ACTIVATION, ESC_DC_SYNC0);
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

    /// One slave's part of the images: (outputs, inputs).
    pub fn slave_images(&self, slave: usize) -> (&[u8], &[u8]) {
        let range = |ranges: &[Range<usize>]| ranges.get(slave).cloned().unwrap_or(0..0);
        (&self.outputs[range(&self.output_ranges)], &self.inputs[range(&self.input_ranges)])
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

    fn find(mapping: &[Mapped], base: usize, index: u16, sub: u8) -> Option<Field> {
        let wanted = crate::drive::od::find(index, sub)?;
        mapping.iter().find(|m| m.obj == wanted).map(|m| Field { offset: base + m.offset, ty: m.ty })
    }

    fn slave(&self, slave: usize) -> Result<&Slave, SdoError> {
        self.slaves.get(slave).ok_or(SdoError::NoSlave(slave))
    }

    /// SDO upload through the slave's mailbox.
    pub fn sdo_read(&self, slave: usize, index: u16, sub: u8) -> Result<(i64, usize), SdoError> {
        self.slave(slave)?.sdo_read(index, sub)
    }

    /// SDO download through the slave's mailbox.
    pub fn sdo_write(&mut self, slave: usize, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoError> {
        self.slave(slave)?;
        self.slaves[slave].sdo_write(index, sub, data)
    }

    /// AL Control from outside the start-up (tests, tools).
    pub fn request_state(&mut self, slave: usize, target: AlState) -> Result<(), AlStatusCode> {
        self.slaves[slave].request_state(target)
    }

    /// Simulation only: a drive fault of CoE manual table 4-16.
    pub fn inject_fault(&mut self, slave: usize, code: u16) -> Result<(), FaultInjectionError> {
        match self.slaves.get_mut(slave) {
            Some(s) => s.inject_fault(code),
            None => Err(FaultInjectionError::UnknownCode(code)),
        }
    }
}

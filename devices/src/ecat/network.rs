//! The simulated EtherCAT segment: the slaves in ring order, the master's start-up, the
//! process image exchanged once per cycle as one frame would, and the mailbox.
//!
//! The master knows no device: it configures the slaves and lays the process image out
//! through their mailboxes only (the PDO assignments 0x1C12/0x1C13, the mappings they
//! name, and each mapped object's entry description), as a real master does.

use std::ops::Range;

use crate::coe::DataType;
use crate::ecat::device::Device;
use crate::ecat::esm::{AlState, AlStatusCode};
use crate::ecat::mailbox::{SdoAbort, SdoError};
use crate::ecat::pdo::{Direction, PdoEntry};
use crate::ecat::remote::{Exchange, Remote, SdoAccess, SdoAnswer, SdoRequest};
use crate::ecat::slave::{ESC_DC_SYNC0, ESC_SYNC_ACTIVATION, Slave};

/// Where one mapped object sits in the master's process image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    offset: usize,
    ty: DataType,
}

impl Field {
    /// The object's value in `image`, in stored form (REAL32 as its bits).
    pub fn read(self, image: &[u8]) -> i64 {
        self.ty.decode(&image[self.offset..])
    }

    /// Writes `value` into `image`, cut to the object's width.
    pub fn write(self, image: &mut [u8], value: i64) {
        self.ty.encode(value, &mut image[self.offset..]);
    }

    /// The mapped object's data type.
    pub fn data_type(self) -> DataType {
        self.ty
    }
}

/// Why the master could not bring the network to Op. The network stays where it stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum StartError {
    /// A slave refused a state request (its AL Status error indication).
    #[error("slave {slave} refused {target:?} with AL status code 0x{:04X} ({code:?})", code.code())]
    Refused {
        /// The slave's position in the ring.
        slave: usize,
        /// The state the master requested.
        target: AlState,
        /// Why it refused.
        code: AlStatusCode,
    },
    /// An SDO of the configuration in PreOp failed.
    #[error("slave {slave}: SDO 0x{index:04X}:{sub} failed during configuration: {error}")]
    Sdo {
        /// The slave's position in the ring.
        slave: usize,
        /// The object's index.
        index: u16,
        /// Its sub-index.
        sub: u8,
        /// The abort or mailbox error.
        error: SdoError,
    },
}

/// A slave as the controller puts it on the bus: its device, and the mapping entries
/// (`0xIIIISSLL`) the master writes to its first RxPDO (0x1600) and TxPDO (0x1A00) and to
/// its second ones (0x1601, 0x1A01, then assigned as 0x1C12:02/0x1C13:02) in PreOp; `None`
/// leaves the device's own.
pub struct SlaveSetup {
    /// The device behind the slave's interface.
    pub device: Box<dyn Device>,
    /// Entries for 0x1600, the first RxPDO (outputs).
    pub rx_pdo: Option<Vec<u32>>,
    /// Entries for 0x1A00, the first TxPDO (inputs).
    pub tx_pdo: Option<Vec<u32>>,
    /// Entries for 0x1601, the second RxPDO (a drive's touch probe function).
    pub rx_pdo_2: Option<Vec<u32>>,
    /// Entries for 0x1A01, the second TxPDO (a drive's touch probe status and positions).
    pub tx_pdo_2: Option<Vec<u32>>,
}

impl SlaveSetup {
    /// A slave whose mapping the master leaves as the device has it.
    pub fn own_mapping(device: Box<dyn Device>) -> Self {
        SlaveSetup { device, rx_pdo: None, tx_pdo: None, rx_pdo_2: None, tx_pdo_2: None }
    }
}

/// One SDO download of the master's start-up list: the object and the value's bytes, as
/// wide as the object.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SdoDownload {
    /// The object's index.
    pub index: u16,
    /// Its sub-index.
    pub sub: u8,
    /// The value, little-endian.
    pub data: Vec<u8>,
}

/// The custom PDO mapping of one slave, written by the master in PreOp: per direction the
/// first PDO's entries and the second's.
#[derive(Clone, Debug, Default)]
struct Mapping {
    rx: [Option<Vec<u32>>; 2],
    tx: [Option<Vec<u32>>; 2],
}

/// One object in the master's process image, as read from the slave's mapping objects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageEntry {
    /// The object's index.
    pub index: u16,
    /// Its sub-index.
    pub sub: u8,
    /// Its data type, from the entry description.
    pub ty: DataType,
    /// Bytes from the start of the slave's part of the image.
    pub offset: usize,
}

/// A slave's part of the process image: where it lies and what it holds.
#[derive(Clone, Debug, Default)]
struct SlaveImage {
    outputs: Range<usize>,
    inputs: Range<usize>,
    rx: Vec<ImageEntry>,
    tx: Vec<ImageEntry>,
}

/// Where the slaves are that the image goes to.
enum Transport {
    /// In this process: each exchange steps the device models.
    Memory,
    /// Behind a wire (`Remote`): the device models are the plan of what is there.
    Wire(Wire),
}

/// The master's side of a wire.
struct Wire {
    link: Box<dyn Remote>,
    /// One transfer at a time per slave, as a mailbox carries them.
    mailboxes: Vec<Mailbox>,
    counters: WireCounters,
    /// Exchanges in a row without a complete frame after which the segment counts as lost.
    lost_after: u32,
}

/// A slave's mailbox as the master sees it over a wire.
#[derive(Clone, Copy, Debug, Default)]
enum Mailbox {
    #[default]
    Idle,
    /// Queued or under way.
    Busy(SdoRequest),
    /// Finished, until the one who asked takes the answer.
    Answered(SdoAnswer),
}

/// What the process data on a wire did since start-up (ETG.1000.4 5.4: a frame is good
/// when it comes back with every slave's working counter).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WireCounters {
    /// Exchanges with a fresh, complete frame.
    pub good: u64,
    /// Exchanges without a frame back since the last one.
    pub missing: u64,
    /// Frames back short of the working counter.
    pub short: u64,
    /// Frames back that matched nothing sent (duplicated on the way, or late).
    pub unmatched: u64,
    /// Bad exchanges in a row, now.
    pub bad_in_a_row: u32,
}

/// The simulated segment as its master sees it: the slaves, their mappings and the
/// process image of outputs and inputs.
pub struct Network {
    slaves: Vec<Slave>,
    mappings: Vec<Mapping>,
    outputs: Vec<u8>,
    inputs: Vec<u8>,
    images: Vec<SlaveImage>,
    start_error: Option<StartError>,
    transport: Transport,
}

impl Network {
    /// The slaves in ring order.
    pub fn with_slaves(slaves: Vec<SlaveSetup>) -> Self {
        let mappings = slaves
            .iter()
            .map(|s| Mapping { rx: [s.rx_pdo.clone(), s.rx_pdo_2.clone()], tx: [s.tx_pdo.clone(), s.tx_pdo_2.clone()] })
            .collect();
        Network {
            slaves: slaves.into_iter().map(|s| Slave::new(s.device)).collect(),
            mappings,
            outputs: Vec::new(),
            inputs: Vec::new(),
            images: Vec::new(),
            start_error: None,
            transport: Transport::Memory,
        }
    }

    /// From now on the image goes over `link` (started, in Op) and the device models
    /// only describe what it reaches. `lost_after` exchanges in a row without a complete
    /// frame and the segment counts as lost (`state` Init) until frames come back.
    pub fn put_on_wire(&mut self, link: Box<dyn Remote>, lost_after: u32) {
        let mailboxes = vec![Mailbox::Idle; self.slaves.len()];
        let counters = WireCounters::default();
        self.transport = Transport::Wire(Wire { link, mailboxes, counters, lost_after: lost_after.max(1) });
    }

    /// True while the slaves are the device models in this process.
    pub fn is_simulated(&self) -> bool {
        matches!(self.transport, Transport::Memory)
    }

    /// What the process data on the wire did; `None` in memory.
    pub fn wire_counters(&self) -> Option<WireCounters> {
        match &self.transport {
            Transport::Memory => None,
            Transport::Wire(wire) => Some(WireCounters { unmatched: wire.link.unmatched(), ..wire.counters }),
        }
    }

    /// The slaves in ring order (slave n is position n).
    pub fn slaves(&self) -> &[Slave] {
        &self.slaves
    }

    /// The slaves themselves, for what the bus does not carry (the simulation's faults).
    pub fn slaves_mut(&mut self) -> &mut [Slave] {
        &mut self.slaves
    }

    /// The slaves in ring order, for another transport to carry (the wire's ESCs,
    /// `subdevice`): the same devices, without this network's master.
    pub fn into_slaves(self) -> Vec<Slave> {
        self.slaves
    }

    /// The master's start-up (CoE manual 2.3): scan, every slave to PreOp, PDO mapping
    /// and the DC cycle configured over the mailbox, SafeOp (mapping and sync checked),
    /// process image laid out from the mapping objects, Op. A failure leaves the network
    /// where it stopped.
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
        self.lay_out_image()?;
        self.request_all(AlState::Op)
    }

    fn request_all(&mut self, target: AlState) -> Result<(), StartError> {
        for (slave, s) in self.slaves.iter_mut().enumerate() {
            s.request_state(target).map_err(|code| StartError::Refused { slave, target, code })?;
        }
        Ok(())
    }

    /// PreOp configuration of one slave: the start-up list, downloaded through its
    /// mailbox, then SYNC0 activated.
    fn configure(&mut self, slave: usize, cycle_ns: u64) -> Result<(), StartError> {
        for SdoDownload { index, sub, data } in self.startup_list(slave, cycle_ns) {
            self.slaves[slave].sdo_write(index, sub, &data).map_err(|error| StartError::Sdo {
                slave,
                index,
                sub,
                error,
            })?;
        }
        self.slaves[slave].write_esc_register(ESC_SYNC_ACTIVATION, ESC_DC_SYNC0);
        Ok(())
    }

    /// The SDO downloads a master makes to `slave` in PreOp, in order: its custom PDO
    /// mapping (CoE manual 2.4 steps 2-4) and DC SYNC0 at the controller's cycle (2.5). A
    /// second PDO assigned beforehand (through SDO) stays assigned. Every transport downloads this list,
    /// made before the start-up from the slave's dictionary as it stands.
    pub fn startup_list(&self, slave: usize, cycle_ns: u64) -> Vec<SdoDownload> {
        let Mapping { rx, tx } = self.mappings[slave].clone();
        let assigned = |index: u16| self.slaves[slave].sdo_read(index, 0).map_or(1, |(n, _)| n.max(1) as u8);
        let assigned = [assigned(0x1C12), assigned(0x1C13)];
        let mut list = Vec::new();
        let mut write = |index: u16, sub: u8, data: &[u8]| list.push(SdoDownload { index, sub, data: data.to_vec() });
        for ([first, second], mapping, assignment, assigned) in
            [(rx, 0x1600u16, 0x1C12, assigned[0]), (tx, 0x1A00, 0x1C13, assigned[1])]
        {
            if first.is_none() && second.is_none() {
                continue;
            }
            write(assignment, 0, &[0]);
            for (pdo, entries) in [(mapping, first), (mapping + 1, second.clone())] {
                let Some(entries) = entries else { continue };
                write(pdo, 0, &[0]);
                for (i, entry) in entries.iter().enumerate() {
                    write(pdo, i as u8 + 1, &entry.to_le_bytes());
                }
                write(pdo, 0, &[entries.len() as u8]);
            }
            let assigned = match second {
                Some(entries) if !entries.is_empty() => {
                    write(assignment, 2, &(mapping + 1).to_le_bytes());
                    2
                }
                _ => assigned,
            };
            write(assignment, 0, &[assigned]);
        }
        write(0x1C32, 2, &(cycle_ns as u32).to_le_bytes());
        write(0x1C32, 1, &2u16.to_le_bytes());
        list
    }

    /// Each slave's part of the image, one after the other in ring order.
    fn lay_out_image(&mut self) -> Result<(), StartError> {
        let (mut out_len, mut in_len) = (0, 0);
        self.images.clear();
        for slave in 0..self.slaves.len() {
            let (rx, rx_len) = self.read_mapping(slave, Direction::Outputs)?;
            let (tx, tx_len) = self.read_mapping(slave, Direction::Inputs)?;
            self.images.push(SlaveImage {
                outputs: out_len..out_len + rx_len,
                inputs: in_len..in_len + tx_len,
                rx,
                tx,
            });
            out_len += rx_len;
            in_len += tx_len;
        }
        self.outputs = vec![0; out_len];
        self.inputs = vec![0; in_len];
        Ok(())
    }

    /// What one SyncManager of a slave carries, read through its mailbox: the PDOs its
    /// assignment names, their entries in order, each entry's type from its description.
    fn read_mapping(&self, slave: usize, direction: Direction) -> Result<(Vec<ImageEntry>, usize), StartError> {
        let s = &self.slaves[slave];
        let failed = |index, sub| move |error| StartError::Sdo { slave, index, sub, error };
        let read = |index: u16, sub: u8| s.sdo_read(index, sub).map(|(v, _)| v).map_err(failed(index, sub));
        let assignment = direction.assignment();
        let (mut entries, mut len) = (Vec::new(), 0);
        for k in 1..=read(assignment, 0)? as u8 {
            let pdo = read(assignment, k)? as u16;
            for e in 1..=read(pdo, 0)? as u8 {
                let entry = PdoEntry::from_u32(read(pdo, e)? as u32);
                let ty = s.sdo_describe(entry.index, entry.sub).map_err(failed(entry.index, entry.sub))?.ty;
                entries.push(ImageEntry { index: entry.index, sub: entry.sub, ty, offset: len });
                len += ty.bytes();
            }
        }
        Ok((entries, len))
    }

    /// The master state `GetECATSt` reports: the lowest state of any slave. On a wire,
    /// the lowest the last frame back reported, and Init while the segment is lost.
    pub fn state(&self) -> AlState {
        match &self.transport {
            Transport::Memory => self.slaves.iter().map(|s| s.esm().state()).min().unwrap_or(AlState::Init),
            Transport::Wire(wire) if wire.is_lost() => AlState::Init,
            Transport::Wire(wire) => wire.link.state(),
        }
    }

    /// Whether the input image holds what the slaves sent: in memory always; on a wire
    /// while the segment is in Op and not lost (else the inputs are the last ones that
    /// came, and say nothing of the drives now).
    pub fn inputs_valid(&self) -> bool {
        match &self.transport {
            Transport::Memory => true,
            Transport::Wire(wire) => !wire.is_lost() && wire.link.state() == AlState::Op,
        }
    }

    /// One frame: every slave takes its outputs, runs one cycle and returns its inputs;
    /// on a wire, the outputs are handed over and the last frame's inputs taken, and the
    /// mailbox answers that came in are filed by slave.
    pub fn exchange(&mut self, period_s: f64) {
        if let Transport::Wire(wire) = &mut self.transport {
            let counters = &mut wire.counters;
            match wire.link.exchange(&self.outputs, &mut self.inputs) {
                Exchange::Fresh => {
                    counters.good += 1;
                    counters.bad_in_a_row = 0;
                }
                Exchange::WorkingCounter { .. } => {
                    counters.short += 1;
                    counters.bad_in_a_row += 1;
                }
                Exchange::Missing => {
                    counters.missing += 1;
                    counters.bad_in_a_row += 1;
                }
            }
            while let Some(answer) = wire.link.answer() {
                if let Some(mailbox) = wire.mailboxes.get_mut(usize::from(answer.request.slave)) {
                    *mailbox = Mailbox::Answered(answer);
                }
            }
            return;
        }
        for (i, slave) in self.slaves.iter_mut().enumerate() {
            let image = self.images.get(i);
            let outputs = &self.outputs[image.map_or(0..0, |m| m.outputs.clone())];
            let inputs = match image {
                Some(m) => &mut self.inputs[m.inputs.clone()],
                None => &mut [][..],
            };
            slave.cycle(outputs, inputs, period_s);
        }
    }

    /// One slave's part of the images: (outputs, inputs).
    pub fn slave_images(&self, slave: usize) -> (&[u8], &[u8]) {
        match self.images.get(slave) {
            Some(m) => (&self.outputs[m.outputs.clone()], &self.inputs[m.inputs.clone()]),
            None => (&[], &[]),
        }
    }

    /// What one slave's part of the image holds: (outputs, inputs), in order.
    pub fn image_entries(&self, slave: usize) -> (&[ImageEntry], &[ImageEntry]) {
        self.images.get(slave).map_or((&[], &[]), |m| (&m.rx, &m.tx))
    }

    /// The master's view of the last frame: inputs to read, outputs to write.
    pub fn images_mut(&mut self) -> (&[u8], &mut [u8]) {
        (&self.inputs, &mut self.outputs)
    }

    /// Where object `index:sub` of `slave` sits in the outputs (RxPDO), if mapped.
    pub fn output_field(&self, slave: usize, index: u16, sub: u8) -> Option<Field> {
        let image = self.images.get(slave)?;
        find(&image.rx, image.outputs.start, index, sub)
    }

    /// Where object `index:sub` of `slave` sits in the inputs (TxPDO), if mapped.
    pub fn input_field(&self, slave: usize, index: u16, sub: u8) -> Option<Field> {
        let image = self.images.get(slave)?;
        find(&image.tx, image.inputs.start, index, sub)
    }

    fn slave(&self, slave: usize) -> Result<&Slave, SdoError> {
        self.slaves.get(slave).ok_or(SdoError::NoSlave(slave))
    }

    /// SDO upload through the slave's mailbox. On a wire the first call queues it and
    /// says `Pending`; asked again in a later cycle, the answer is given once it came.
    pub fn sdo_read(&mut self, slave: usize, index: u16, sub: u8) -> Result<(i64, usize), SdoError> {
        self.slave(slave)?;
        match &mut self.transport {
            Transport::Memory => self.slaves[slave].sdo_read(index, sub),
            Transport::Wire(wire) => {
                let (bytes, len) =
                    wire.transfer(SdoRequest { slave: slave as u16, index, sub, access: SdoAccess::Upload })?;
                // Signed as the device's dictionary describes the object.
                let signed = self.slaves[slave].sdo_describe(index, sub).is_ok_and(|d| d.ty.is_signed());
                let value = match (signed, len) {
                    (true, 1) => i64::from(bytes[0] as i8),
                    (true, 2) => i64::from(i16::from_le_bytes([bytes[0], bytes[1]])),
                    (true, _) => i64::from(i32::from_le_bytes(bytes)),
                    (false, _) => i64::from(u32::from_le_bytes(bytes)),
                };
                Ok((value, len))
            }
        }
    }

    /// SDO upload from the device model in this process, at once: in memory the slave
    /// itself; on a wire the plan of what is there (its identity, what it describes of
    /// itself), not the drive's present values.
    pub fn sdo_read_local(&self, slave: usize, index: u16, sub: u8) -> Result<(i64, usize), SdoError> {
        self.slave(slave)?.sdo_read(index, sub)
    }

    /// SDO download through the slave's mailbox; on a wire, as `sdo_read`.
    pub fn sdo_write(&mut self, slave: usize, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoError> {
        self.slave(slave)?;
        match &mut self.transport {
            Transport::Memory => self.slaves[slave].sdo_write(index, sub, data),
            Transport::Wire(wire) => {
                let mut bytes = [0; 4];
                let len = data.len().min(4);
                if data.len() > 4 {
                    return Err(SdoError::Abort(SdoAbort::LengthTooHigh));
                }
                bytes[..len].copy_from_slice(&data[..len]);
                let access = SdoAccess::Download { data: bytes, len: len as u8 };
                wire.transfer(SdoRequest { slave: slave as u16, index, sub, access }).map(|_| ())
            }
        }
    }

    /// AL Control from outside the start-up (tests, tools).
    pub fn request_state(&mut self, slave: usize, target: AlState) -> Result<(), AlStatusCode> {
        self.slaves[slave].request_state(target)
    }
}

impl Wire {
    fn is_lost(&self) -> bool {
        self.counters.bad_in_a_row >= self.lost_after
    }

    /// One step of the transfer `request`: its answer if it came, else queued (`Pending`)
    /// or refused while another transfer of that slave is under way (`MailboxBusy`).
    fn transfer(&mut self, request: SdoRequest) -> Result<([u8; 4], usize), SdoError> {
        let mailbox = &mut self.mailboxes[usize::from(request.slave)];
        match *mailbox {
            Mailbox::Answered(answer) if answer.request == request => {
                *mailbox = Mailbox::Idle;
                answer.result
            }
            Mailbox::Busy(under_way) if under_way == request => Err(SdoError::Pending),
            Mailbox::Busy(_) => Err(SdoError::MailboxBusy),
            // An answer nobody came back for is dropped for the next transfer.
            Mailbox::Idle | Mailbox::Answered(_) => {
                self.link.request(request)?;
                *mailbox = Mailbox::Busy(request);
                Err(SdoError::Pending)
            }
        }
    }
}

fn find(entries: &[ImageEntry], base: usize, index: u16, sub: u8) -> Option<Field> {
    entries.iter().find(|e| e.index == index && e.sub == sub).map(|e| Field { offset: base + e.offset, ty: e.ty })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coe::{Access, DataType, ObjectDef, ObjectStore, id, test_object};

    const fn row(index: u16, sub: u8, ty: DataType, access: Access, pdo: bool, max: f64, default: f64) -> ObjectDef {
        ObjectDef { access, pdo_mappable: pdo, min: 0.0, max, default, ..test_object(index, sub, ty) }
    }

    /// A device the bus has never seen: 8 inputs counting cycles, free run, one TxPDO.
    static COUNTER: &[ObjectDef] = &[
        row(0x1A00, 0, DataType::UInt8, Access::ReadWrite, false, 7.0, 1.0),
        row(0x1A00, 1, DataType::UInt32, Access::ReadWrite, false, u32::MAX as f64, 0x6000_0108u32 as f64),
        row(0x1C12, 0, DataType::UInt8, Access::ReadWrite, false, 0.0, 0.0),
        row(0x1C13, 0, DataType::UInt8, Access::ReadWrite, false, 1.0, 1.0),
        row(0x1C13, 1, DataType::UInt16, Access::ReadWrite, false, 0x1A00 as f64, 0x1A00 as f64),
        row(0x1C32, 1, DataType::UInt16, Access::ReadWrite, false, 2.0, 0.0),
        row(0x1C32, 2, DataType::UInt32, Access::ReadWrite, false, u32::MAX as f64, 0.0),
        row(0x6000, 1, DataType::UInt8, Access::ReadOnly, true, 255.0, 0.0),
    ];

    struct Counter(ObjectStore);

    impl Device for Counter {
        fn od(&self) -> &ObjectStore {
            &self.0
        }

        fn od_mut(&mut self) -> &mut ObjectStore {
            &mut self.0
        }

        fn step(&mut self, _period_s: f64) {
            let inputs = id(COUNTER, 0x6000, 1);
            self.0.set(inputs, (self.0.get(inputs) + 1) & 0xFF);
        }

        fn digital_channels(&self) -> (u8, u8) {
            (8, 0)
        }
    }

    /// The master brings any device to Op and lays its part of the image out from its
    /// mapping objects, beside a device of another kind.
    #[test]
    fn a_device_of_any_kind_is_laid_out_from_its_mapping_objects() {
        let counter = || SlaveSetup::own_mapping(Box::new(Counter(ObjectStore::new(COUNTER, 1))));
        let mut net = Network::with_slaves(vec![counter(), counter()]);
        net.start(1_000_000).expect("start-up to Op");
        assert_eq!(net.state(), AlState::Op);
        let entry = ImageEntry { index: 0x6000, sub: 1, ty: DataType::UInt8, offset: 0 };
        assert_eq!(net.image_entries(1), (&[][..], &[entry][..]));
        net.exchange(1e-3);
        net.exchange(1e-3);
        assert_eq!(net.images_mut().0, [2, 2], "each counter's byte, one after the other");
        assert_eq!(net.input_field(1, 0x6000, 1).map(|f| f.read(&[7, 9])), Some(9));
        assert_eq!(net.slaves()[0].device().digital_channels(), (8, 0));
        assert!(net.slaves()[0].device_as::<Counter>().is_some());
    }
}

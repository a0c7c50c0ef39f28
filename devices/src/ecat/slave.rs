//! One simulated slave: its EtherCAT state machine, its mailbox, its PDO mapping and the
//! device it holds. It knows the device only through its object dictionary and the
//! `Device` trait.

use crate::coe::ObjectStore;
use crate::ecat::device::Device;
use crate::ecat::esm::{AlState, AlStatusCode, Esm};
use crate::ecat::mailbox::{self, EntryDescription, SdoAbort, SdoError};
use crate::ecat::pdo::{self, Direction, Mapped};

/// ESC register 0x0980 (sync/latch activation): free run or DC SYNC0 (CoE manual 2.5).
pub(crate) const ESC_SYNC_ACTIVATION: u16 = 0x0980;
pub(crate) const ESC_FREE_RUN: u16 = 0x0000;
pub(crate) const ESC_DC_SYNC0: u16 = 0x0300;

/// The SyncManager 2 and 3 sync parameters (CoE manual table 4-4).
const SM2_SYNC: u16 = 0x1C32;
const SM3_SYNC: u16 = 0x1C33;
/// 0x1C32:01 synchronization types (CoE manual table 4-4).
const SYNC_FREE_RUN: i64 = 0;
const SYNC_DC: i64 = 2;

/// One slave on the ring: its ESM, its device, and the PDO layout checked on the way to
/// SafeOp.
pub struct Slave {
    esm: Esm,
    device: Box<dyn Device>,
    rx: Vec<Mapped>,
    tx: Vec<Mapped>,
    rx_len: usize,
    tx_len: usize,
    sync_activation: u16,
}

impl Slave {
    /// A slave in Init holding `device`, its PDO mapping not yet laid out.
    pub fn new(device: Box<dyn Device>) -> Self {
        Slave {
            esm: Esm::default(),
            device,
            rx: Vec::new(),
            tx: Vec::new(),
            rx_len: 0,
            tx_len: 0,
            sync_activation: ESC_FREE_RUN,
        }
    }

    /// Its EtherCAT state machine.
    pub fn esm(&self) -> &Esm {
        &self.esm
    }

    /// The device it holds, as the `Device` trait.
    pub fn device(&self) -> &dyn Device {
        &*self.device
    }

    /// The device as its own type, if it is one.
    pub fn device_as<T: Device>(&self) -> Option<&T> {
        (&*self.device as &dyn std::any::Any).downcast_ref()
    }

    /// The process data watchdog of the slave's ESC ran out (`Device::process_data_lost`).
    pub fn process_data_lost(&mut self) {
        self.device.process_data_lost();
    }

    pub(crate) fn device_mut_as<T: Device>(&mut self) -> Option<&mut T> {
        (&mut *self.device as &mut dyn std::any::Any).downcast_mut()
    }

    /// Bytes of outputs (RxPDOs) and inputs (TxPDOs) once in SafeOp.
    pub fn pdo_lengths(&self) -> (usize, usize) {
        (self.rx_len, self.tx_len)
    }

    /// The master writes an ESC register (only 0x0980 matters to the simulation).
    pub fn write_esc_register(&mut self, address: u16, value: u16) {
        if address == ESC_SYNC_ACTIVATION {
            self.sync_activation = value;
        }
    }

    /// Free run (0x0000) or DC SYNC0 (0x0300), as the master activated it.
    pub fn sync_activation(&self) -> u16 {
        self.sync_activation
    }

    /// AL Control: the master requests a state. On the way from PreOp to SafeOp the PDO
    /// mapping and the sync settings are checked (CoE manual 2.3, PS transition).
    pub fn request_state(&mut self, target: AlState) -> Result<(), AlStatusCode> {
        let device = &*self.device;
        let sync_activation = self.sync_activation;
        let mut layout = None;
        self.esm.request(target, |from, to| {
            if from == AlState::PreOp && to == AlState::SafeOp {
                check_sync(device, sync_activation)?;
                let store = device.od();
                let rx = assigned(store, Direction::Outputs).map_err(|_| AlStatusCode::InvalidOutputMapping)?;
                let tx = assigned(store, Direction::Inputs).map_err(|_| AlStatusCode::InvalidInputMapping)?;
                layout = Some((rx, tx));
            }
            Ok(())
        })?;
        if let Some(((rx, rx_len), (tx, tx_len))) = layout {
            (self.rx, self.rx_len, self.tx, self.tx_len) = (rx, rx_len, tx, tx_len);
        }
        Ok(())
    }

    /// SDO upload: the value and its length in bytes.
    pub fn sdo_read(&self, index: u16, sub: u8) -> Result<(i64, usize), SdoError> {
        self.mailbox()?;
        Ok(mailbox::upload(self.device.od(), index, sub)?)
    }

    /// SDO information, entry description: type, access and mappability of an object.
    pub fn sdo_describe(&self, index: u16, sub: u8) -> Result<EntryDescription, SdoError> {
        self.mailbox()?;
        Ok(mailbox::describe(self.device.od(), index, sub)?)
    }

    /// No mailbox in Init (CoE manual 2.3, table 2-3).
    fn mailbox(&self) -> Result<(), SdoError> {
        if self.esm.state() == AlState::Init { Err(SdoError::NoMailbox) } else { Ok(()) }
    }

    /// SDO download, with the communication objects' state rules (CoE manual 2.4, 2.5);
    /// then the device may act on it.
    pub fn sdo_write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoError> {
        self.mailbox()?;
        let (id, value) = mailbox::check_download(self.device.od(), index, sub, data)?;
        let in_pre_op = self.esm.state() == AlState::PreOp;
        // Mapping: in PreOp, with its SyncManager assignment switched off.
        if let Some(direction) = Direction::of_mapping(index)
            && (!in_pre_op || assignment_count(self.device.od(), direction) != 0)
        {
            return Err(SdoAbort::DeviceState.into());
        }
        match index {
            0x1C12 | 0x1C13 | SM2_SYNC if !in_pre_op => return Err(SdoAbort::DeviceState.into()),
            SM2_SYNC if sub == 1 && value != SYNC_FREE_RUN && value != SYNC_DC => {
                return Err(SdoAbort::ValueRange.into());
            }
            SM2_SYNC if sub == 2 && !self.device.accepts_cycle_time(value) => return Err(SdoAbort::ValueRange.into()),
            _ => {}
        }
        if self.device.sdo_download(index, sub, value)? {
            return Ok(());
        }
        let store = self.device.od_mut();
        store.set(id, value);
        // SM3 follows SM2's sync settings (0x1C33:01/02 are read-only).
        if index == SM2_SYNC
            && (sub == 1 || sub == 2)
            && let Some(inputs) = store.find(SM3_SYNC, sub)
        {
            store.set(inputs, value);
        }
        Ok(())
    }

    /// One bus cycle: outputs are applied in Op only, inputs are produced from SafeOp up,
    /// the device runs in every state.
    pub fn cycle(&mut self, outputs: &[u8], inputs: &mut [u8], period_s: f64) {
        let state = self.esm.state();
        if state == AlState::Op {
            let od = self.device.od_mut();
            for m in &self.rx {
                od.set(m.obj, m.ty.decode(&outputs[m.offset..]));
            }
        }
        self.device.step(period_s);
        if state >= AlState::SafeOp {
            let od = self.device.od();
            for m in &self.tx {
                m.ty.encode(od.get(m.obj), &mut inputs[m.offset..]);
            }
        }
    }
}

/// Sub 0 of a SyncManager's PDO assignment: how many PDOs it carries.
fn assignment_count(store: &ObjectStore, direction: Direction) -> i64 {
    store.find(direction.assignment(), 0).map_or(0, |id| store.get(id))
}

/// The objects a SyncManager carries: the entries of its assigned PDOs, one after the
/// other in the order of assignment; none when nothing is assigned.
fn assigned(store: &ObjectStore, direction: Direction) -> Result<(Vec<Mapped>, usize), pdo::MappingError> {
    let mut mapped = Vec::new();
    let mut len = 0;
    let mut pdos = Vec::new();
    for k in 1..=assignment_count(store, direction) {
        let pdo = store.find(direction.assignment(), k as u8).map_or(0, |id| store.get(id) as u16);
        let known = Direction::of_mapping(pdo) == Some(direction) && store.find(pdo, 0).is_some();
        if !known || pdos.contains(&pdo) {
            return Err(pdo::MappingError::NotAPdo(pdo));
        }
        pdos.push(pdo);
        let (entries, count) = pdo::entries(store, pdo);
        let (objects, bytes) = pdo::layout(store, direction, &entries[..count])?;
        mapped.extend(objects.into_iter().map(|m| Mapped { offset: m.offset + len, ..m }));
        len += bytes;
    }
    Ok((mapped, len))
}

/// DC mode needs the SYNC0 activation and a cycle the device runs; free run needs no
/// activation. A device without 0x1C32 runs free.
fn check_sync(device: &dyn Device, activation: u16) -> Result<(), AlStatusCode> {
    let store = device.od();
    let value = |sub| store.find(SM2_SYNC, sub).map(|id| store.get(id));
    match value(1).unwrap_or(SYNC_FREE_RUN) {
        SYNC_DC if activation != ESC_DC_SYNC0 => Err(AlStatusCode::InvalidDcSyncConfiguration),
        SYNC_DC if !value(2).is_some_and(|ns| device.accepts_cycle_time(ns)) => Err(AlStatusCode::InvalidSyncCycleTime),
        SYNC_FREE_RUN if activation != ESC_FREE_RUN => Err(AlStatusCode::InvalidDcSyncConfiguration),
        _ => Ok(()),
    }
}

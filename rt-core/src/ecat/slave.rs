//! One simulated slave: its EtherCAT state machine, its mailbox, its PDO mapping and its
//! drive application.

use crate::config::{AxisConfig, DC_CYCLES_US};
use crate::drive::od::{self, ObjectStore};
use crate::drive::{Drive, FaultInjectionError};
use crate::ecat::esm::{AlState, AlStatusCode, Esm};
use crate::ecat::mailbox::{self, SdoAbort, SdoError};
use crate::ecat::pdo::{self, Direction, Mapped};

/// ESC register 0x0980 (sync/latch activation): free run or DC SYNC0 (CoE manual 2.5).
pub const ESC_SYNC_ACTIVATION: u16 = 0x0980;
pub const ESC_FREE_RUN: u16 = 0x0000;
pub const ESC_DC_SYNC0: u16 = 0x0300;

/// 0x1C32:01 synchronization types (CoE manual table 4-4).
const SYNC_FREE_RUN: i64 = 0;
const SYNC_DC: i64 = 2;

pub struct Slave {
    esm: Esm,
    drive: Drive,
    rx: Vec<Mapped>,
    tx: Vec<Mapped>,
    rx_len: usize,
    tx_len: usize,
    sync_activation: u16,
}

impl Slave {
    pub fn new(axis: &AxisConfig) -> Self {
        Slave {
            esm: Esm::default(),
            drive: Drive::new(axis),
            rx: Vec::new(),
            tx: Vec::new(),
            rx_len: 0,
            tx_len: 0,
            sync_activation: ESC_FREE_RUN,
        }
    }

    pub fn esm(&self) -> &Esm {
        &self.esm
    }

    pub fn drive(&self) -> &Drive {
        &self.drive
    }

    pub fn inject_fault(&mut self, code: u16) -> Result<(), FaultInjectionError> {
        self.drive.inject_fault(code)
    }

    /// Bytes of outputs (RxPDO) and inputs (TxPDO) once in SafeOp.
    pub fn pdo_lengths(&self) -> (usize, usize) {
        (self.rx_len, self.tx_len)
    }

    pub fn rx_mapping(&self) -> &[Mapped] {
        &self.rx
    }

    pub fn tx_mapping(&self) -> &[Mapped] {
        &self.tx
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
        let store = self.drive.od();
        let sync_activation = self.sync_activation;
        let mut layout = None;
        self.esm.request(target, |from, to| {
            if from == AlState::PreOp && to == AlState::SafeOp {
                check_sync(store, sync_activation)?;
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
        if self.esm.state() == AlState::Init {
            return Err(SdoError::NoMailbox);
        }
        Ok(mailbox::upload(self.drive.od(), index, sub)?)
    }

    /// SDO download, with the communication objects' state rules (CoE manual 2.4, 2.5).
    pub fn sdo_write(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), SdoError> {
        let state = self.esm.state();
        if state == AlState::Init {
            return Err(SdoError::NoMailbox);
        }
        let (id, value) = mailbox::check_download(self.drive.od(), index, sub, data)?;
        let store = self.drive.od_mut();
        let in_pre_op = state == AlState::PreOp;
        match index {
            // Mapping: in PreOp, with its SyncManager assignment switched off.
            0x1600 if !in_pre_op || store.get(od::RX_ASSIGNMENT_COUNT) != 0 => return Err(SdoAbort::DeviceState.into()),
            0x1A00 if !in_pre_op || store.get(od::TX_ASSIGNMENT_COUNT) != 0 => return Err(SdoAbort::DeviceState.into()),
            0x1C12 | 0x1C13 | 0x1C32 if !in_pre_op => return Err(SdoAbort::DeviceState.into()),
            0x1C32 if sub == 1 && value != SYNC_FREE_RUN && value != SYNC_DC => return Err(SdoAbort::ValueRange.into()),
            0x1C32 if sub == 2 && !DC_CYCLES_US.iter().any(|&us| us as i64 * 1000 == value) => {
                return Err(SdoAbort::ValueRange.into());
            }
            0x1010 => {
                if !self.drive.store_parameters(value as u32) {
                    return Err(SdoAbort::DeviceState.into());
                }
                return Ok(());
            }
            _ => {}
        }
        store.set(id, value);
        // SM3 follows SM2's sync settings (0x1C33:01/02 are read-only).
        if index == 0x1C32 && sub == 1 {
            store.set(od::SYNC_TYPE_INPUTS, value);
        }
        if index == 0x1C32 && sub == 2 {
            store.set(od::CYCLE_TIME_INPUTS, value);
        }
        Ok(())
    }

    /// One bus cycle: outputs are applied in Op only, inputs are produced from SafeOp up,
    /// the drive runs in every state.
    pub fn cycle(&mut self, outputs: &[u8], inputs: &mut [u8], period_s: f64) {
        let state = self.esm.state();
        if state == AlState::Op {
            for m in &self.rx {
                self.drive.od_mut().set(m.obj, m.ty.decode(&outputs[m.offset..]));
            }
        }
        self.drive.step(period_s);
        if state >= AlState::SafeOp {
            for m in &self.tx {
                m.ty.encode(self.drive.od().get(m.obj), &mut inputs[m.offset..]);
            }
        }
    }
}

/// The objects a SyncManager carries: its PDO's entries when assigned (sub 0 = 1), none otherwise.
fn assigned(store: &ObjectStore, direction: Direction) -> Result<(Vec<Mapped>, usize), pdo::MappingError> {
    let (assignment, mapping) = match direction {
        Direction::Outputs => (od::RX_ASSIGNMENT_COUNT, 0x1600),
        Direction::Inputs => (od::TX_ASSIGNMENT_COUNT, 0x1A00),
    };
    if store.get(assignment) == 0 {
        return Ok((Vec::new(), 0));
    }
    let (entries, count) = pdo::entries(store, mapping);
    pdo::layout(store, direction, &entries[..count])
}

/// DC mode needs the SYNC0 activation and a DC cycle; free run needs no activation.
fn check_sync(store: &ObjectStore, activation: u16) -> Result<(), AlStatusCode> {
    match store.get(od::SYNC_TYPE) {
        SYNC_DC if activation != ESC_DC_SYNC0 => Err(AlStatusCode::InvalidDcSyncConfiguration),
        SYNC_DC if !DC_CYCLES_US.iter().any(|&us| us as i64 * 1000 == store.get(od::CYCLE_TIME)) => {
            Err(AlStatusCode::InvalidSyncCycleTime)
        }
        SYNC_FREE_RUN if activation != ESC_FREE_RUN => Err(AlStatusCode::InvalidDcSyncConfiguration),
        _ => Ok(()),
    }
}

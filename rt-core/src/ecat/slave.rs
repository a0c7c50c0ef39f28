//! One simulated slave: its EtherCAT state machine, PDO mapping and drive application.

use crate::config::AxisConfig;
use crate::drive::Drive;
use crate::ecat::esm::{AlState, AlStatusCode, Esm};
use crate::ecat::pdo::{self, Mapped, PdoEntry};

pub struct Slave {
    esm: Esm,
    drive: Drive,
    rx_entries: Vec<PdoEntry>,
    tx_entries: Vec<PdoEntry>,
    rx: Vec<Mapped>,
    tx: Vec<Mapped>,
    rx_len: usize,
    tx_len: usize,
}

impl Slave {
    pub fn new(axis: &AxisConfig) -> Self {
        Slave {
            esm: Esm::default(),
            drive: Drive::new(axis),
            rx_entries: pdo::DEFAULT_RX.to_vec(),
            tx_entries: pdo::DEFAULT_TX.to_vec(),
            rx: Vec::new(),
            tx: Vec::new(),
            rx_len: 0,
            tx_len: 0,
        }
    }

    pub fn esm(&self) -> &Esm {
        &self.esm
    }

    pub fn drive(&self) -> &Drive {
        &self.drive
    }

    pub fn drive_mut(&mut self) -> &mut Drive {
        &mut self.drive
    }

    /// Bytes of outputs (RxPDO) and inputs (TxPDO) once configured.
    pub fn pdo_lengths(&self) -> (usize, usize) {
        (self.rx_len, self.tx_len)
    }

    pub fn rx_mapping(&self) -> &[Mapped] {
        &self.rx
    }

    pub fn tx_mapping(&self) -> &[Mapped] {
        &self.tx
    }

    /// AL Control: the master requests a state. The PDO mapping is validated on the way
    /// from PreOp to SafeOp (CoE manual 2.3, PS transition).
    pub fn request_state(&mut self, target: AlState) -> Result<(), AlStatusCode> {
        let (rx_entries, tx_entries) = (&self.rx_entries, &self.tx_entries);
        let mut layout = None;
        self.esm.request(target, |from, to| {
            if from == AlState::PreOp && to == AlState::SafeOp {
                let rx = pdo::layout(rx_entries).map_err(|_| AlStatusCode::InvalidOutputMapping)?;
                let tx = pdo::layout(tx_entries).map_err(|_| AlStatusCode::InvalidInputMapping)?;
                layout = Some((rx, tx));
            }
            Ok(())
        })?;
        if let Some(((rx, rx_len), (tx, tx_len))) = layout {
            (self.rx, self.rx_len, self.tx, self.tx_len) = (rx, rx_len, tx, tx_len);
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

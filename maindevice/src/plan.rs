//! What the MainDevice must find and make on the wire, taken from the machine's
//! in-memory network: each slave's identity (0x1018 of its device model, the role an ESI
//! file plays for a real master), the start-up list the in-memory master downloads, and
//! the process image that network lays out from the mapping objects.

use std::ops::Range;

use devices::ecat::network::ImageEntry;
use devices::ecat::{Network, SdoDownload, StartError};

/// A slave's identity object 0x1018 (CoE manual table 4-1), as its SII also holds it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Identity {
    /// 0x1018:01.
    pub vendor: u32,
    /// 0x1018:02.
    pub product: u32,
    /// 0x1018:03.
    pub revision: u32,
}

/// One slave of the plan, in ring order.
#[derive(Clone, Debug)]
pub struct SlavePlan {
    /// What its EEPROM must say.
    pub identity: Identity,
    /// The SDO downloads of its PreOp configuration.
    pub startup: Vec<SdoDownload>,
    /// Its outputs (RxPDO objects), in order.
    pub rx: Vec<ImageEntry>,
    /// Its inputs (TxPDO objects), in order.
    pub tx: Vec<ImageEntry>,
    /// Where its outputs lie in the cycle's output image.
    pub outputs: Range<usize>,
    /// Where its inputs lie in the cycle's input image.
    pub inputs: Range<usize>,
}

impl SlavePlan {
    /// What an LRW of the whole image adds to the working counter for this slave
    /// (a read-write command counts 2 for a write and 1 for a read: Beckhoff ESC
    /// technology, Section I, table 5).
    pub fn working_counter(&self) -> u16 {
        2 * u16::from(!self.outputs.is_empty()) + u16::from(!self.inputs.is_empty())
    }
}

/// The whole segment's plan.
#[derive(Clone, Debug, Default)]
pub struct Plan {
    /// The slaves in ring order.
    pub slaves: Vec<SlavePlan>,
    /// Bytes of the output image.
    pub outputs_len: usize,
    /// Bytes of the input image.
    pub inputs_len: usize,
}

impl Plan {
    /// The plan of `network` before its start-up: the start-up lists are made from the
    /// dictionaries as they stand; then the network is started in memory, without a
    /// single cycle, to lay the image out from its mapping objects. The network stays
    /// the description of the devices the wire carries.
    pub fn new(network: &mut Network, cycle_ns: u64) -> Result<Plan, StartError> {
        let count = network.slaves().len();
        let lists: Vec<Vec<SdoDownload>> = (0..count).map(|slave| network.startup_list(slave, cycle_ns)).collect();
        network.start(cycle_ns)?;
        let (mut outputs_len, mut inputs_len) = (0, 0);
        let slaves = lists
            .into_iter()
            .enumerate()
            .map(|(slave, startup)| {
                let read = |sub| network.sdo_read_local(slave, 0x1018, sub).map_or(0, |(v, _)| v as u32);
                let (rx, tx) = network.image_entries(slave);
                let (out, inp) = network.slave_images(slave);
                let plan = SlavePlan {
                    identity: Identity { vendor: read(1), product: read(2), revision: read(3) },
                    startup,
                    rx: rx.to_vec(),
                    tx: tx.to_vec(),
                    outputs: outputs_len..outputs_len + out.len(),
                    inputs: inputs_len..inputs_len + inp.len(),
                };
                outputs_len += out.len();
                inputs_len += inp.len();
                plan
            })
            .collect();
        Ok(Plan { slaves, outputs_len, inputs_len })
    }

    /// The working counter of a whole-image exchange with every slave there.
    pub fn working_counter(&self) -> u16 {
        self.slaves.iter().map(SlavePlan::working_counter).sum()
    }
}

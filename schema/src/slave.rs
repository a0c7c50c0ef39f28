//! The slaves on the segment in the snapshot: their PDO mapping and process data, their
//! digital channels (HMPL 9.3, 9.5) and analog channels (HMPL ch. 10).

use crate::ids::MAX_AXES;

/// PDOs a slave may assign per direction (0x1600/0x1601 and 0x1A00/0x1A01).
pub const PDOS_PER_DIRECTION: usize = 2;
/// Mapped entries of one direction: each PDO holds at most 7 (CoE manual 2.4).
pub const MAX_PDO_ENTRIES: usize = 7 * PDOS_PER_DIRECTION;
/// Bytes of one direction's process data: each PDO carries at most 20 (CoE manual 2.4).
pub const MAX_PDO_BYTES: usize = 20 * PDOS_PER_DIRECTION;
/// One drive per axis.
pub const MAX_SLAVES: usize = MAX_AXES;

/// Where a slave's digital channels sit in its process data (HMPL 9.3, 9.5): an object
/// and the bit of channel 1; channel n is the bit n - 1 above it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DigitalWord {
    /// Object index.
    pub index: u16,
    /// Object sub-index.
    pub sub: u8,
    /// The bit of channel 1.
    pub first_bit: u8,
}

/// Digital inputs, the first object mapped wins: a digital I/O terminal's word, then a
/// CiA 402 drive's 0x60FD (bit 0 negative limit, 1 positive limit, 2 home switch).
pub const SLAVE_DIGITAL_INPUTS: [DigitalWord; 2] =
    [DigitalWord { index: 0x6000, sub: 1, first_bit: 0 }, DigitalWord { index: 0x60FD, sub: 0, first_bit: 0 }];
/// Digital outputs: a terminal's word, then a drive's 0x60FE:01, whose O1 is bit 17
/// (CoE manual tables 4-19 to 4-21; bit 16 is the brake).
pub const SLAVE_DIGITAL_OUTPUTS: [DigitalWord; 2] =
    [DigitalWord { index: 0x7000, sub: 1, first_bit: 0 }, DigitalWord { index: 0x60FE, sub: 1, first_bit: 17 }];

/// The bits of `n` channels from bit 0.
pub fn channel_mask(n: u8) -> u32 {
    if n >= 32 { u32::MAX } else { (1 << n) - 1 }
}

/// Analog channels an analog terminal has at most each way (HMPL ch. 10): one PDO of
/// 16-bit words.
pub const MAX_ANALOG_CHANNELS: usize = 4;
/// Slaves with analog channels a machine may have: their settings are in every snapshot,
/// and every snapshot is in shared memory some 250 times.
pub const MAX_ANALOG_TERMINALS: usize = 8;
/// CiA 401 "Read analogue input 16-bit": channel n is sub-index n (INT16, TxPDO).
pub const ANALOG_INPUTS: u16 = 0x6401;
/// CiA 401 "Write analogue output 16-bit": channel n is sub-index n (INT16, RxPDO).
pub const ANALOG_OUTPUTS: u16 = 0x6411;

/// An analog output's settings the controller keeps (HMPL 10.2.2, 10.4).
#[derive(Debug, Clone, Copy)]
#[repr(C)]
pub struct AnalogOutputSnapshot {
    /// `ao_scale` of `SetSlvAOParam`.
    pub scale: f64,
    /// `ao_offset` of `SetSlvAOParam`.
    pub offset: f64,
    /// The `var_id` of `SetSlvAOMonitor`, -1 before one is chosen.
    pub var_id: i32,
    /// The conversion type's code (`HMPL_DAC_*`).
    pub range_type: u16,
    /// 1 while the output follows its variable.
    pub bound: u8,
}

impl Default for AnalogOutputSnapshot {
    fn default() -> Self {
        AnalogOutputSnapshot { scale: 1.0, offset: 0.0, var_id: -1, range_type: 0, bound: 0 }
    }
}

/// A slave's analog channels: how many, and their settings (HMPL ch. 10, 21.1).
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
pub struct AnalogSnapshot {
    /// The slave's position on the bus; only an entry with channels names one.
    pub slave: u16,
    /// The outputs' settings, channel n at n - 1.
    pub outputs: [AnalogOutputSnapshot; MAX_ANALOG_CHANNELS],
    /// The inputs' conversion types, channel n at n - 1.
    pub input_types: [u16; MAX_ANALOG_CHANNELS],
    /// Analog input channels.
    pub input_count: u8,
    /// Analog output channels.
    pub output_count: u8,
}

/// One mapped object of a PDO and its byte offset in the slave's process data.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
pub struct PdoEntrySnapshot {
    /// Object index.
    pub index: u16,
    /// Object sub-index.
    pub sub: u8,
    /// Bit length.
    pub bits: u8,
    /// Byte offset in the process data.
    pub offset: u8,
    /// The object's type is signed (sign-extend when reading).
    pub signed: u8,
}

/// One slave as the master sees it: its AL state, its mapping and its process data.
#[derive(Debug, Clone, Copy)]
#[repr(C)]
pub struct SlaveSnapshot {
    /// 1 Init, 2 PreOp, 4 SafeOp, 8 Op.
    pub al_state: u8,
    /// Entries of the RxPDOs used in `rx` (the first PDO's, then the second's).
    pub rx_count: u8,
    /// Entries of the TxPDOs used in `tx`.
    pub tx_count: u8,
    /// Digital inputs and outputs of the slave (HMPL ch. 21).
    pub digital_inputs: u8,
    /// See `digital_inputs`.
    pub digital_outputs: u8,
    /// AL status code of the last refused state change (0: none).
    pub al_status_code: u16,
    /// The RxPDO mapping (master to slave).
    pub rx: [PdoEntrySnapshot; MAX_PDO_ENTRIES],
    /// The TxPDO mapping (slave to master).
    pub tx: [PdoEntrySnapshot; MAX_PDO_ENTRIES],
    /// RxPDO as the master last sent it, TxPDO as the slave last returned it.
    pub outputs: [u8; MAX_PDO_BYTES],
    /// See `outputs`.
    pub inputs: [u8; MAX_PDO_BYTES],
}

impl Default for SlaveSnapshot {
    fn default() -> Self {
        SlaveSnapshot {
            al_state: 0,
            rx_count: 0,
            tx_count: 0,
            digital_inputs: 0,
            digital_outputs: 0,
            al_status_code: 0,
            rx: [PdoEntrySnapshot::default(); MAX_PDO_ENTRIES],
            tx: [PdoEntrySnapshot::default(); MAX_PDO_ENTRIES],
            outputs: [0; MAX_PDO_BYTES],
            inputs: [0; MAX_PDO_BYTES],
        }
    }
}

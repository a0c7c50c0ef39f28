//! Why the MainDevice could not bring the segment to Op.

use crate::plan::Identity;

/// What stopped the start-up; the message names the slave and what was expected.
#[derive(Debug, thiserror::Error)]
pub enum WireError {
    /// The raw socket could not be opened on the interface.
    #[error("the EtherCAT interface {interface:?}: {error}")]
    Interface {
        /// The interface asked for.
        interface: String,
        /// Why (the socket says which capability it needs).
        error: subdevice::SocketError,
    },
    /// ethercrab's scan or a state change failed.
    #[error("EtherCAT {step}: {error}")]
    Master {
        /// What the master was doing.
        step: &'static str,
        /// ethercrab's error.
        error: ethercrab::error::Error,
    },
    /// Fewer or more slaves answered than the machine file has.
    #[error("the segment has {found} slaves; the machine file has {expected}")]
    SlaveCount {
        /// Slaves found by the scan.
        found: usize,
        /// Slaves the machine file declares.
        expected: usize,
    },
    /// A slave is not the device the machine file puts at its position.
    #[error("slave {slave} ({name:?}) is vendor 0x{:08X} product 0x{:08X} revision 0x{:08X}; the machine file expects vendor 0x{:08X} product 0x{:08X} revision 0x{:08X}", found.vendor, found.product, found.revision, expected.vendor, expected.product, expected.revision)]
    WrongSlave {
        /// The slave's position.
        slave: usize,
        /// The name in its SII.
        name: String,
        /// What its EEPROM says.
        found: Identity,
        /// What the machine file's device has in 0x1018.
        expected: Identity,
    },
    /// An SDO of the start-up list or of the mapping check failed.
    #[error("slave {slave}: SDO 0x{index:04X}:{sub} failed during start-up: {error}")]
    Sdo {
        /// The slave's position.
        slave: usize,
        /// The object's index.
        index: u16,
        /// Its sub-index.
        sub: u8,
        /// ethercrab's error (an abort names its code).
        error: ethercrab::error::Error,
    },
    /// A slave's process data is not what the plan laid out.
    #[error("slave {slave}: {what} on the wire, {planned} planned")]
    Mapping {
        /// The slave's position.
        slave: usize,
        /// What the slave reports.
        what: String,
        /// What the plan has.
        planned: String,
    },
    /// Not every slave reached Op with process data running, or a drive stayed in Not
    /// ready to switch on.
    #[error("not every slave reached Op (and every drive Switch on disabled) within {waited:?} of process data")]
    NotOp {
        /// How long the master exchanged process data waiting for it.
        waited: std::time::Duration,
    },
    /// The process image does not fit one frame.
    #[error("the process image is {bytes} bytes; one frame carries {max}: fewer slaves or smaller PDO mappings")]
    ImageTooLarge {
        /// Inputs and outputs of every slave.
        bytes: usize,
        /// What one LRW beside the DC time carries.
        max: usize,
    },
    /// The OS refused one of the master's threads.
    #[error("the EtherCAT {name} thread could not start: {error}")]
    Thread {
        /// The thread's name.
        name: &'static str,
        /// What the OS said.
        error: std::io::Error,
    },
    /// The master's thread ended before it said how the start-up went.
    #[error("the EtherCAT master thread ended during start-up")]
    ThreadEnded,
}

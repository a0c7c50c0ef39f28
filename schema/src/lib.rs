//! The domain's schema: what the controller, its scripts and its tools share, laid out in
//! `#[repr(C)]` types of plain numbers and atomics. The state snapshot of each cycle (the
//! axes, groups, slaves, tasks and I/O the status queries read), the shared data (HMPL
//! ch. 11's user table, 23.2's test variables, 2.22's mutexes, the task variables, the
//! Modbus user areas DV and DH of DXMC A.1, the FUN147 PLC image) and the debugger's
//! words of a task slot (DXMC A.3).
//!
//! How these reach another process is `ipc`'s business (shared-memory regions, the
//! snapshot board, futexes): this crate knows no transport. The call words (`Request`,
//! `Reply`) and the event record are not here: they are the wire formats of the task's
//! mailbox and of the `events` service, untyped words whose meaning the registry gives,
//! and the event record is an iceoryx2 payload, so they live with their transport in
//! `ipc`.

// Every public item is part of a contract with other processes or crates: say what it is.

pub mod axis;
pub mod debug;
pub mod group;
pub mod ids;
pub mod layout;
pub mod plc_image;
pub mod shared;
pub mod slave;
pub mod snapshot;
pub mod task;

pub use axis::{AxisSnapshot, fault_status, motion_status};
pub use group::{GroupSnapshot, MAX_GROUP_AXES, group_fault_status, group_motion_status};
pub use ids::{MAX_AXES, MAX_GROUPS, MAX_TASKS};
pub use slave::{
    ANALOG_INPUTS, ANALOG_OUTPUTS, AnalogOutputSnapshot, AnalogSnapshot, DigitalWord, MAX_ANALOG_CHANNELS,
    MAX_ANALOG_TERMINALS, MAX_PDO_BYTES, MAX_PDO_ENTRIES, MAX_SLAVES, PDOS_PER_DIRECTION, PdoEntrySnapshot,
    SLAVE_DIGITAL_INPUTS, SLAVE_DIGITAL_OUTPUTS, SlaveSnapshot, channel_mask,
};
pub use snapshot::{GPIO_PINS, GpioSnapshot, PtSnapshot, Snapshot, WireSnapshot};
pub use task::{TaskSnapshot, TaskState};

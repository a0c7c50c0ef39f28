//! The core as an EtherCAT MainDevice on a network interface (ETG.1000; ethercrab does
//! the frames, the scan and the ESM). The machine file's in-memory network is the plan:
//! its device models say what each slave must be (identity 0x1018, as an ESI file would),
//! its start-up list is what the master downloads to each slave in PreOp, and its process
//! image is the one the cycle reads and writes. On the wire that image goes through
//! ethercrab's process data image on a thread of its own (`bus.rs`), and the cycle only
//! hands it over (`handoff.rs`), so the cycle never waits for a frame.

pub mod bus;
pub mod error;
pub mod handoff;
pub mod mailbox;
pub mod plan;
pub mod txrx;

pub use bus::WireBus;
pub use devices::ecat::Exchange;
pub use error::WireError;
pub use plan::{Identity, Plan, SlavePlan};

//! The simulated EtherCAT network: slaves with their state machine, mailbox and process
//! data, reached by the master only as a real master reaches real slaves.

pub mod device;
pub mod esm;
pub mod mailbox;
pub mod network;
pub mod pdo;
pub mod remote;
pub mod slave;

pub use device::Device;
pub use esm::{AlState, AlStatusCode};
pub use mailbox::{SdoAbort, SdoError};
pub use network::{Field, Network, SdoDownload, SlaveSetup, StartError, WireCounters};
pub use remote::{Exchange, Remote, SdoAccess, SdoAnswer, SdoRequest};

//! The simulated EtherCAT segment on a real wire: one ESC (EtherCAT SubDevice Controller)
//! in front of each `devices::ecat::Slave`, answering the frames a master sends on a
//! network interface. The drive models, their CoE dictionaries, state machines and PDO
//! mappings are the ones the in-memory network uses: one model, two transports.
//!
//! From the wire inwards: `socket` (a raw AF_PACKET socket), `segment` (a frame through
//! the line of ESCs), `frame` and `command` (ETG.1000.4 frames, datagrams, addressing and
//! working counters), `esc` (one ESC), and its parts `registers`, `sync_manager`, `fmmu`,
//! `sii`, `mailbox` and `dc`. `realtime` gives the serving thread the priority of hardware.

pub mod command;
pub mod dc;
pub mod esc;
pub mod fmmu;
pub mod frame;
pub mod mailbox;
pub mod realtime;
pub mod registers;
pub mod segment;
pub mod sii;
pub mod socket;
pub mod sync_manager;

pub use esc::Esc;
pub use segment::Segment;
pub use socket::{RawSocket, SocketError, serve};

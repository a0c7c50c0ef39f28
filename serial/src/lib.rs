//! Serial port 1 of the controller (Delta DXMC manual 8.2, 8.3): a pseudo-terminal any
//! serial program can open, served by a thread of the controller process (`port.rs`),
//! in a FreePort protocol (framing by start and end bytes, `framing.rs`, shared with the
//! `FreePort.Eth` sessions), Modbus RTU (`rtu.rs`) or Modbus ASCII (`ascii.rs`). Parameter 5-1's protocol codes are in
//! `protocol.rs`, 5-5's format word in `format.rs`, the pseudo-terminal in `pty.rs`, and
//! the link scripts reach the port through in `link.rs`.

pub mod ascii;
pub mod format;
pub mod framing;
pub mod link;
pub mod port;
pub mod protocol;
pub(crate) mod pty;
pub mod rtu;

pub use port::{Handler, Port, Recorder, SerialError, Settings, SimLine};

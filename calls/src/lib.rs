//! The calls of the API between the transport (`ipc`, which carries bytes and shared
//! memory only) and the front ends and the core: typed commands on the wire (`wire`), the
//! status queries answered from a snapshot (`query`), and the Modbus address map of the
//! user areas DV and DH (`user_area`, DXMC A.1), the user table on disk (`user_table`, HMPL
//! 11.6/11.7).

// Every public item is part of a contract with other processes or crates: say what it is.
#![warn(missing_docs)]

pub mod clients;
pub mod freeport;
pub mod plc;
pub mod query;
pub mod scope;
pub mod user_area;
pub mod user_table;
pub mod watch;
pub mod wire;

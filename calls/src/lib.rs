//! The calls of the API between the transport (`ipc`, which carries bytes and shared
//! memory only) and the front ends and the core: typed commands on the wire (`wire`), their
//! replies as typed values and why one failed (`reply`), the status queries answered from
//! a snapshot (`query`), and the Modbus address map of the user areas DV and DH
//! (`user_area`, DXMC A.1), the user table on disk (`user_table`, HMPL 11.6/11.7).
//!
//! The contract: every argument of every API function is decoded as the registry
//! declares it (`api::functions`), never by its position. A front end reads a typed call
//! (`CommandCall`, `QueryCall`, `LocalCall`) from its own values with `api::call`'s neutral
//! rules (the Lua bindings from the Lua stack, the Native ASCII server and the tests from
//! `api::call::from_values`, the web view builds one) and matches on its variants; a
//! command goes to the core through `wire` and its reply comes back through `reply`, with
//! one `reply::explain` for every front end.

// Every public item is part of a contract with other processes or crates: say what it is.

pub mod clients;
pub mod freeport;
pub mod plc;
pub mod query;
pub mod reply;
pub mod scope;
pub mod user_area;
pub mod user_table;
pub mod watch;
pub mod wire;

//! The controller process: the RT cycle, the tasks and their supervisor, dispatch of the
//! scripts' calls, over the simulated EtherCAT segment (`devices`) and the motion kernel (`kernel`).
//! See ARCHITECTURE.md for the map and the invariants.

pub mod analog;
pub mod console;
pub mod controller;
pub mod cycle;
pub mod dispatch;
pub mod fun147_boxes;
pub mod huge_pages;
pub(crate) mod io;
pub mod machine;
pub mod master;
pub(crate) mod output;
pub mod overrun;
pub(crate) mod ownership;
pub(crate) mod pool;
pub mod position_trigger;
pub mod realtime;
pub mod replay;
pub mod scope;
pub mod signals;
pub mod sim_clock;
pub mod supervisor;
pub mod tasks;
pub(crate) mod trace;

/// The machine file lives in its own crate; re-exported so that `rt_core::config` and
/// `crate::config` paths name it.
pub use ::config;
pub use config::MachineConfig;
pub use controller::{ControllerError, RunOptions, RunReport, run};

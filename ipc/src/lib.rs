//! luamotion's inter-process contract, over iceoryx2 (see ARCHITECTURE.md, "IPC").
//!
//! | what | pattern | direction |
//! |---|---|---|
//! | `snapshots` | shared memory, latest value (`snapshot_board.rs`) | core -> everyone |
//! | `tasks`, calls | a mailbox per task in the task table (`mailbox.rs`) | task <-> core |
//! | `tasks`, wake-up | futex in the task table | core -> task |
//! | `tasks` | shared memory (atomics) | task -> core: heartbeat, run state, wait requests |
//! | `shared` | shared memory (atomics) | all: user table, test variables, mutexes, task variables |
//! | `events` | publish-subscribe | tasks and controller -> tools: SendEvent, SendMsgEvent, alarms |

// Every public item is part of a contract with other processes or crates: say what it is.
#![warn(missing_docs)]

pub mod clock;
mod core_side;
pub mod debug;
pub mod events;
pub mod files;
mod futex;
pub mod mailbox;
pub mod messages;
mod monitor;
mod namespace;
pub mod output;
pub mod plc_image;
pub mod pool;
pub mod scope;
pub mod services;
pub mod shared;
pub mod shm;
mod snapshot_board;
mod task_side;
pub mod task_table;
mod task_waker;

use iceoryx2::node::{NodeState, NodeView};
use iceoryx2::prelude::*;

pub use core_side::{CORE_NODE_NAME, CoreEndpoint, CoreIpcStats, Disposition, SnapshotSample};
pub use files::remove_namespace_files;
pub use monitor::Monitor;
pub use namespace::Namespace;
pub use task_side::{CallTiming, PreparedEndpoint, ReplyCounters, TaskEndpoint};

#[derive(Debug, thiserror::Error)]
/// Why an IPC operation failed.
pub enum IpcError {
    #[error("invalid namespace {0:?}: use 1 to 40 characters of A-Z a-z 0-9 _ -")]
    /// The `--ns` name breaks the rules of iceoryx2's service names.
    Namespace(String),
    #[error("iceoryx2: {0}")]
    /// iceoryx2 refused to create or open a service or port.
    Service(String),
    #[error("iceoryx2: {what}: {error}: {advice}")]
    /// Another user's files are in the way.
    Permissions {
        /// The service or file concerned.
        what: String,
        /// iceoryx2's error.
        error: String,
        /// What the operator can do.
        advice: String,
    },
    #[error("iceoryx2: {what}: {error}: {advice}")]
    /// A service's limits (nodes, ports, buffers) or the room in `/dev/shm` are used up.
    Capacity {
        /// The service or file concerned.
        what: String,
        /// iceoryx2's error.
        error: String,
        /// What the operator can do.
        advice: String,
    },
    #[error("shared memory: {0}")]
    /// Creating or mapping a shared-memory segment failed.
    Shm(String),
    #[error("protocol: {0}")]
    /// The other side sent something this side does not understand.
    Protocol(String),
    #[error("the controller is gone")]
    /// The controller's process ended while a script waited on it.
    ControllerGone,
    #[error("no reply to request {0} in time")]
    /// A request's reply did not come (its sequence number).
    ReplyLost(u64),
    #[error("a controller (pid {pid}) is already running in namespace {ns}")]
    /// Another live controller owns the namespace.
    NamespaceInUse {
        /// The namespace.
        ns: String,
        /// The other controller's pid.
        pid: u32,
    },
}

/// Makes the namespace ready for a new controller: removes what dead processes left
/// behind (so that a `kill -9` never blocks the next start) and refuses if a controller
/// is alive in it.
pub fn claim_namespace(ns: &Namespace) -> Result<(), IpcError> {
    match scan_nodes(ns, true)? {
        Some(pid) => Err(IpcError::NamespaceInUse { ns: ns.to_string(), pid }),
        None => Ok(()),
    }
}

/// Whether process `pid` exists (signal 0: nothing is sent); one of another user exists too.
pub fn process_alive(pid: u32) -> bool {
    // SAFETY: signal 0 only checks that the process exists.
    unsafe { libc::kill(pid as libc::pid_t, 0) == 0 || *libc::__errno_location() == libc::EPERM }
}

/// Pins the calling thread to `cpu`; whether it could.
#[cfg(test)]
fn pin_current_thread(cpu: usize) -> bool {
    // SAFETY: a zeroed cpu_set_t with one bit set, for the calling thread.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        libc::CPU_SET(cpu, &mut set);
        libc::sched_setaffinity(0, size_of::<libc::cpu_set_t>(), &set) == 0
    }
}

/// The pid of the controller alive in the namespace, if any.
pub fn controller_pid(ns: &Namespace) -> Result<Option<u32>, IpcError> {
    scan_nodes(ns, false)
}

/// Whether a live controller in `ns` serves everything a program attaches to: its event
/// stream, which its supervisor creates last, is up.
pub fn controller_ready(ns: &Namespace) -> Result<bool, IpcError> {
    if controller_pid(ns)?.is_none() {
        return Ok(false);
    }
    let node = services::node(ns, &format!("luamotion-probe-{}", std::process::id()))?;
    Ok(services::events(&node, ns, services::Open::Existing).is_ok())
}

/// Lists the namespace's nodes: the live controller's pid, removing dead nodes if asked.
fn scan_nodes(ns: &Namespace, remove_dead: bool) -> Result<Option<u32>, IpcError> {
    let mut alive_core = None;
    Node::<services::Ipc>::list(&ns.config(), |state| {
        match state {
            NodeState::Alive(view) => {
                if let Some(details) = view.details()
                    && details.name().as_str() == CORE_NODE_NAME
                {
                    alive_core = Some(details.process_id().value() as u32);
                }
            }
            NodeState::Dead(view) if remove_dead => {
                // Another process may be cleaning the same node; either way it is gone after.
                let _ = view.try_remove_stale_resources();
            }
            NodeState::Dead(_) | NodeState::Inaccessible(_) | NodeState::Undefined(_) => {}
        }
        CallbackProgression::Continue
    })
    .map_err(|e| services::failed("list nodes", e))?;
    Ok(alive_core)
}

/// Gives the process the default action again for the signals iceoryx2 (and Rust's
/// runtime) catch: SIGINT and SIGTERM end it, and a crash (SIGSEGV, SIGBUS, SIGILL,
/// SIGFPE, SIGABRT) kills it, whether the fault is real or the signal was sent. Script
/// processes use it, so that the controller can stop them and sees their crashes.
pub fn restore_default_signals() {
    // Creating iceoryx2's handler first: it is installed once, so it cannot replace ours later.
    let _ = iceoryx2_bb_posix::signal::SignalHandler::last_signal();
    for signal in [libc::SIGTERM, libc::SIGINT, libc::SIGSEGV, libc::SIGBUS, libc::SIGILL, libc::SIGFPE, libc::SIGABRT]
    {
        // SAFETY: resetting a signal to its default action.
        unsafe { libc::signal(signal, libc::SIG_DFL) };
    }
}

/// Removes the stale resources of dead processes (e.g. a killed script) in the namespace.
pub fn clean_dead_nodes(ns: &Namespace) {
    let _ = Node::<services::Ipc>::list(&ns.config(), |state| {
        if let NodeState::Dead(view) = state {
            let _ = view.try_remove_stale_resources();
        }
        CallbackProgression::Continue
    });
}

/// iceoryx2 logs to stderr on its own; keep it to errors unless `IOX2_LOG_LEVEL` says
/// otherwise. Its one routine warning (no config file: every luamotion node is configured
/// in code, see `Namespace::config`) would otherwise land in users' output.
pub fn quiet_transport_logs() {
    iceoryx2::prelude::set_log_level_from_env_or(iceoryx2::prelude::LogLevel::Error);
}

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
//!
//! The data these carry is the `schema` crate's; this crate is the transport. No file of
//! it imports from this one: each names the module it uses, so the files form no circle.

// Every public item is part of a contract with other processes or crates: say what it is.

pub mod advice;
pub mod call;
pub mod clock;
mod core_side;
pub mod error;
pub mod event_record;
pub mod events;
pub mod files;
mod futex;
pub mod limits;
pub mod mailbox;
mod monitor;
pub mod mutex;
mod namespace;
mod nodes;
pub mod output;
pub mod pool;
mod process;
pub mod room;
pub mod scope;
pub mod services;
pub mod shm;
mod snapshot_board;
mod task_side;
pub mod task_table;
mod task_waker;

pub use core_side::{CORE_NODE_NAME, CoreEndpoint, CoreIpcStats, Disposition, SnapshotSample};
pub use error::IpcError;
pub use files::remove_namespace_files;
pub use monitor::Monitor;
pub use namespace::Namespace;
pub use nodes::{claim_namespace, clean_dead_nodes, controller_pid, controller_ready};
pub use process::{process_alive, restore_default_signals};
pub use services::quiet_transport_logs;
pub use task_side::{CallTiming, PreparedEndpoint, ReplyCounters, TaskEndpoint};

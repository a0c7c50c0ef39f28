//! The iceoryx2 services of one controller and their settings, in one place so that the
//! core (which creates them) and the scripts (which open them) always agree.

use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use iceoryx2::service::port_factory::{event, publish_subscribe};

use crate::messages::{EventRecord, MAX_TASKS};
use crate::shared::SharedData;
use crate::snapshot_board::SnapshotBoard;
use crate::task_table::TaskTable;
use crate::{IpcError, Namespace, files};

/// The iceoryx2 service flavour every port uses (inter-process, shared memory).
pub type Ipc = ipc::Service;
/// A node of this process.
pub type IpcNode = Node<Ipc>;
/// The notifier of the soak's event floor.
pub type WakeNotifier = Notifier<Ipc>;
/// A publisher of `events` records.
pub type EventPublisher = Publisher<Ipc, EventRecord, ()>;
/// A reader of `events` records.
pub type EventSubscriber = Subscriber<Ipc, EventRecord, ()>;
/// The listener of the soak's event floor.
pub type WakeListener = Listener<Ipc>;

// Who attaches to one controller. Every limit of every service below is derived from
// these few numbers; iceoryx2's defaults (20 nodes per publish-subscribe service) would
// stop the 20th script.

/// Processes of one task at a time on the soak floor's wake events (`wake`): a restarted
/// side opens its port while the dead one's may still be being cleaned up.
const PROCESSES_PER_TASK: usize = 2;
/// Tools attached to a controller at once, each a node of its own: `luamotion tasks`,
/// `luamotion events`, the soak's monitor, the DRL console, the start-up probe, and at
/// least 4 more monitors, with room to spare.
pub const MAX_TOOLS: usize = 12;
/// Idle script processes the supervisor keeps ready (`[rt] script_pool`), each a node.
pub const MAX_POOL: usize = 4;
/// Of those, the ones that follow the event stream at once (`luamotion events`, monitors).
pub const MAX_EVENT_READERS: usize = 8;
/// Nodes of the controller process itself: the core's, the supervisor's.
const CONTROLLER_NODES: usize = 2;
/// Nodes of the service every process opens (`events`). A dead process' node is cleaned
/// when the next one opens the service, so each task counts once.
pub const MAX_NODES: usize = CONTROLLER_NODES + MAX_TASKS + MAX_POOL + MAX_TOOLS;
/// Records a reader may fall behind one writer by before the oldest are dropped: more
/// than a task's burst of events (100) or the supervisor's alarms when all 64 tasks fail
/// at once. Each writer's segment holds this many per reader.
const EVENT_BUFFER: usize = 128;
/// Records a reader that joins late still sees.
const EVENT_HISTORY: usize = 16;
/// Records a reader holds at once (it copies each out).
const EVENT_BORROWED: usize = 2;

#[derive(Clone, Copy, PartialEq, Eq)]
/// Whether a service is created (by its owner) or opened (by the others).
pub enum Open {
    /// The controller creates its services.
    Create,
    /// Scripts and tools open them.
    Existing,
}

/// An iceoryx2 failure. A refused permission says whose files are in the way and how to
/// get past them (a run as another user leaves them).
pub fn failed(what: &str, e: impl std::fmt::Debug) -> IpcError {
    classify(what, e, IpcError::Service)
}

/// As `failed`, for errors of the shared-memory layer; `other` wraps what is not about
/// permissions.
pub(crate) fn classify(what: &str, e: impl std::fmt::Debug, other: impl FnOnce(String) -> IpcError) -> IpcError {
    let error = format!("{e:?}");
    if error.contains("InsufficientPermissions") {
        let advice = files::permission_advice(&files::foreign_files());
        IpcError::Permissions { what: what.to_string(), error, advice }
    } else {
        other(format!("{what}: {error}"))
    }
}

/// A service or port the controller creates, sized for every task and tool, failed:
/// says what it was sized for and what the OS has.
pub(crate) fn too_big(what: &str, e: impl std::fmt::Debug) -> IpcError {
    match failed(what, e) {
        IpcError::Service(error) => IpcError::Capacity { what: what.to_string(), error, advice: room_advice() },
        other => other,
    }
}

/// Shared memory one controller takes when every task and tool is attached, bytes:
/// iceoryx2 gives each publisher a data segment of `subscribers * (buffer + borrowed) +
/// history + loaned` samples, each with a header; plus the snapshot board, the task table
/// (the tasks' call mailboxes in it) and shared data.
pub fn planned_shm_bytes() -> usize {
    const LOANED: usize = 2;
    // iceoryx2's sample header and alignment, as measured in 0.10 (52 bytes).
    const SAMPLE_OVERHEAD: usize = 64;
    let segment = |subscribers: usize, buffer: usize, borrowed: usize, history: usize, sample: usize| {
        (subscribers * (buffer + borrowed) + history + LOANED) * (sample + SAMPLE_OVERHEAD)
    };
    // One writer per task, the supervisor and the DRL console.
    let events = (MAX_TASKS + 2)
        * segment(MAX_EVENT_READERS, EVENT_BUFFER, EVENT_BORROWED, EVENT_HISTORY, size_of::<EventRecord>());
    events + size_of::<SnapshotBoard>() + size_of::<TaskTable>() + size_of::<SharedData>()
}

/// Refuses to start a controller where `/dev/shm` has no room for `planned_shm_bytes`,
/// rather than failing the 40th task when it attaches.
pub fn check_room() -> Result<(), IpcError> {
    match files::shm_free_bytes() {
        Some(free) if free < planned_shm_bytes() => Err(IpcError::Capacity {
            what: "shared memory".into(),
            error: format!("{} MiB free in /dev/shm", free >> 20),
            advice: room_advice(),
        }),
        _ => Ok(()),
    }
}

pub(crate) fn room_advice() -> String {
    let free = files::shm_free_bytes().map_or("unknown".to_string(), |b| format!("{} MiB", b >> 20));
    format!(
        "the services are sized for {MAX_TASKS} tasks and {MAX_TOOLS} attached tools ({MAX_NODES} nodes) and need \
         about {} MiB of shared memory; {free} free in /dev/shm. Give /dev/shm more room (a container: \
         `--shm-size=256m`) and, where luamotion may lock memory, raise `ulimit -l`",
        planned_shm_bytes().div_ceil(1 << 20)
    )
}

/// `<ns>/task/<id>/wake`: an iceoryx2 event. Tasks are woken through a futex in the task
/// table (see `task_table`); the soak test's transport floor uses this event.
pub fn wake(node: &Node<Ipc>, ns: &Namespace, task: u8, open: Open) -> Result<event::PortFactory<Ipc>, IpcError> {
    let builder = node
        .service_builder(&ns.service_name(&format!("task/{task}/wake"))?)
        .event()
        .max_notifiers(PROCESSES_PER_TASK)
        .max_listeners(PROCESSES_PER_TASK)
        .max_nodes(1 + PROCESSES_PER_TASK);
    match open {
        Open::Create => builder.create().map_err(|e| too_big(&format!("task {task} wake"), e)),
        Open::Existing => builder.open().map_err(|e| failed("open wake service", e)),
    }
}

/// `<ns>/events`: SendEvent, SendMsgEvent and alarms, from every task and the controller.
/// A reader that joins late still sees the last records.
pub fn events(
    node: &Node<Ipc>,
    ns: &Namespace,
    open: Open,
) -> Result<publish_subscribe::PortFactory<Ipc, EventRecord, ()>, IpcError> {
    let builder = node
        .service_builder(&ns.service_name("events")?)
        .publish_subscribe::<EventRecord>()
        .history_size(EVENT_HISTORY)
        .subscriber_max_buffer_size(EVENT_BUFFER)
        .subscriber_max_borrowed_samples(EVENT_BORROWED)
        .enable_safe_overflow(true)
        // Every node may write: the tasks, the supervisor, the DRL console.
        .max_publishers(MAX_NODES)
        .max_subscribers(MAX_EVENT_READERS)
        .max_nodes(MAX_NODES);
    match open {
        Open::Create => builder.create().map_err(|e| too_big("events", e)),
        Open::Existing => builder.open().map_err(|e| failed("open events service", e)),
    }
}

/// Who removes what a dead process left in the namespace (its node, its ports).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DeadNodes {
    /// The node itself, when it is created, opens a service and is dropped (iceoryx2's way).
    Cleaned,
    /// The supervisor, after each script process it reaps (`clean_dead_nodes`): the node
    /// lists no other node. Each listing reads and parses every node's details file (and
    /// iceoryx2 0.10 formats its whole config for each), three listings per start and end,
    /// so each script's start cost grew with the number of scripts: most of 64 autorun
    /// tasks' start (README, "Tasks").
    LeftToSupervisor,
}

/// A node of this namespace, with signal handling left to the application.
pub fn node(ns: &Namespace, name: &str) -> Result<Node<Ipc>, IpcError> {
    node_with(ns, name, DeadNodes::Cleaned)
}

/// A node of this namespace that leaves dead nodes to `dead`.
pub fn node_with(ns: &Namespace, name: &str, dead: DeadNodes) -> Result<Node<Ipc>, IpcError> {
    let mut config = ns.config();
    if dead == DeadNodes::LeftToSupervisor {
        config.global.node.cleanup_dead_nodes_on_creation = false;
        config.global.node.cleanup_dead_nodes_on_destruction = false;
        config.global.service.cleanup_dead_nodes_on_open = false;
    }
    NodeBuilder::new()
        .config(&config)
        .name(&NodeName::new(name).map_err(|e| failed("node name", e))?)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<Ipc>()
        .map_err(|e| failed("create node", e))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every task and tool at once must fit a container's default `/dev/shm` (64 MiB)
    /// with room to spare (measured: 39.8 MiB with 64 tasks and 96 axes; the snapshot, held
    /// by every reader, is most of it).
    #[test]
    fn the_services_of_64_tasks_fit_a_small_dev_shm() {
        let mib = planned_shm_bytes() as f64 / (1 << 20) as f64;
        println!("planned shared memory: {mib:.1} MiB");
        assert!(mib < 40.0, "{mib:.1} MiB");
    }
}

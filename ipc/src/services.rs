//! The iceoryx2 services of one controller and their settings, in one place so that the
//! core (which creates them) and the scripts (which open them) always agree. Their limits
//! are `limits.rs`'.

use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use iceoryx2::service::port_factory::{event, publish_subscribe};

use crate::advice::failed;
use crate::error::{IpcError, Refusal};
use crate::event_record::EventRecord;
use crate::limits::{EVENT_BORROWED, EVENT_BUFFER, EVENT_HISTORY, MAX_EVENT_READERS, MAX_NODES, PROCESSES_PER_TASK};
use crate::namespace::Namespace;
use crate::room::too_big;

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

#[derive(Clone, Copy, PartialEq, Eq)]
/// Whether a service is created (by its owner) or opened (by the others).
pub enum Open {
    /// The controller creates its services.
    Create,
    /// Scripts and tools open them.
    Existing,
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
        .name(&NodeName::new(name).map_err(|e| failed("node name", Refusal::NodeName(e)))?)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<Ipc>()
        .map_err(|e| failed("create node", e))
}

/// iceoryx2 logs to stderr on its own; keep it to errors unless `IOX2_LOG_LEVEL` says
/// otherwise. Its one routine warning (no config file: every luamotion node is configured
/// in code, see `Namespace::config`) would otherwise land in users' output.
pub fn quiet_transport_logs() {
    iceoryx2::prelude::set_log_level_from_env_or(iceoryx2::prelude::LogLevel::Error);
}

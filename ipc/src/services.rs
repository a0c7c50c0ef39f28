//! The iceoryx2 services of one controller and their settings, in one place so that the
//! core (which creates them) and the scripts (which open them) always agree.

use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use iceoryx2::service::port_factory::{event, publish_subscribe};

use crate::messages::{EventRecord, MAX_TASKS, Reply, Request, Snapshot};
use crate::{IpcError, Namespace};

pub type Ipc = ipc::Service;
pub type IpcNode = Node<Ipc>;
pub type StatePublisher = Publisher<Ipc, Snapshot, ()>;
pub type StateSubscriber = Subscriber<Ipc, Snapshot, ()>;
pub type RequestPublisher = Publisher<Ipc, Request, ()>;
pub type RequestSubscriber = Subscriber<Ipc, Request, ()>;
pub type ReplyPublisher = Publisher<Ipc, Reply, ()>;
pub type ReplySubscriber = Subscriber<Ipc, Reply, ()>;
pub type WakeNotifier = Notifier<Ipc>;
pub type EventPublisher = Publisher<Ipc, EventRecord, ()>;
pub type EventSubscriber = Subscriber<Ipc, EventRecord, ()>;
pub type WakeListener = Listener<Ipc>;

/// Readers of the state: every task, the gateways and the CLI tools.
const MAX_STATE_READERS: usize = MAX_TASKS + 32;
/// A restarted task opens its services while the dead process' ports are cleaned up.
const MAX_PORTS_PER_TASK_SIDE: usize = 2;
/// Requests one task may have in flight; scripts send one at a time.
pub const MAX_REQUESTS_IN_FLIGHT: usize = 4;

#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Open {
    /// The controller creates its services.
    Create,
    /// Scripts and tools open them.
    Existing,
}

pub(crate) fn failed(what: &str, e: impl std::fmt::Debug) -> IpcError {
    IpcError::Service(format!("{what}: {e:?}"))
}

/// `<ns>/state`: the latest snapshot, published every cycle.
pub fn state(
    node: &Node<Ipc>,
    ns: &Namespace,
    open: Open,
) -> Result<publish_subscribe::PortFactory<Ipc, Snapshot, ()>, IpcError> {
    let builder = node
        .service_builder(&ns.service_name("state")?)
        .publish_subscribe::<Snapshot>()
        .history_size(1)
        .subscriber_max_buffer_size(1)
        .subscriber_max_borrowed_samples(2)
        .enable_safe_overflow(true)
        .max_publishers(1)
        .max_subscribers(MAX_STATE_READERS);
    match open {
        Open::Create => builder.create().map_err(|e| failed("create state service", e)),
        Open::Existing => builder.open().map_err(|e| failed("open state service", e)),
    }
}

/// `<ns>/task/<id>/request` and `<ns>/task/<id>/reply`: one task's API calls to the core
/// and the core's replies, matched by sequence number. A publish-subscribe pair rather than
/// iceoryx2's request-response, whose server allocates per request (the RT thread must not).
fn call_channel<T: std::fmt::Debug + ZeroCopySend>(
    node: &Node<Ipc>,
    ns: &Namespace,
    task: u8,
    what: &str,
    open: Open,
) -> Result<publish_subscribe::PortFactory<Ipc, T, ()>, IpcError> {
    let builder = node
        .service_builder(&ns.service_name(&format!("task/{task}/{what}"))?)
        .publish_subscribe::<T>()
        .history_size(0)
        .subscriber_max_buffer_size(MAX_REQUESTS_IN_FLIGHT)
        .subscriber_max_borrowed_samples(MAX_REQUESTS_IN_FLIGHT)
        .enable_safe_overflow(false)
        .max_publishers(MAX_PORTS_PER_TASK_SIDE)
        .max_subscribers(MAX_PORTS_PER_TASK_SIDE);
    match open {
        Open::Create => builder.create().map_err(|e| failed(&format!("create {what} service"), e)),
        Open::Existing => builder.open().map_err(|e| failed(&format!("open {what} service"), e)),
    }
}

pub fn requests(
    node: &Node<Ipc>,
    ns: &Namespace,
    task: u8,
    open: Open,
) -> Result<publish_subscribe::PortFactory<Ipc, Request, ()>, IpcError> {
    call_channel(node, ns, task, "request", open)
}

pub fn replies(
    node: &Node<Ipc>,
    ns: &Namespace,
    task: u8,
    open: Open,
) -> Result<publish_subscribe::PortFactory<Ipc, Reply, ()>, IpcError> {
    call_channel(node, ns, task, "reply", open)
}

/// `<ns>/task/<id>/wake`: an iceoryx2 event. Tasks are woken through a futex in the task
/// table (see `task_table`); the soak test's transport floor uses this event.
pub fn wake(node: &Node<Ipc>, ns: &Namespace, task: u8, open: Open) -> Result<event::PortFactory<Ipc>, IpcError> {
    let builder = node
        .service_builder(&ns.service_name(&format!("task/{task}/wake"))?)
        .event()
        .max_notifiers(MAX_PORTS_PER_TASK_SIDE)
        .max_listeners(MAX_PORTS_PER_TASK_SIDE);
    match open {
        Open::Create => builder.create().map_err(|e| failed("create wake service", e)),
        Open::Existing => builder.open().map_err(|e| failed("open wake service", e)),
    }
}

/// Tools that follow the event stream at once (`luamotion events`).
const MAX_EVENT_READERS: usize = 4;
/// Records a reader may fall behind by before the oldest are dropped.
const EVENT_BUFFER: usize = 256;

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
        .history_size(16)
        .subscriber_max_buffer_size(EVENT_BUFFER)
        .enable_safe_overflow(true)
        .max_publishers(MAX_TASKS * MAX_PORTS_PER_TASK_SIDE + 2)
        .max_subscribers(MAX_EVENT_READERS);
    match open {
        Open::Create => builder.create().map_err(|e| failed("create events service", e)),
        Open::Existing => builder.open().map_err(|e| failed("open events service", e)),
    }
}

/// A node of this namespace, with signal handling left to the application.
pub fn node(ns: &Namespace, name: &str) -> Result<Node<Ipc>, IpcError> {
    NodeBuilder::new()
        .config(&ns.config())
        .name(&NodeName::new(name).map_err(|e| failed("node name", e))?)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<Ipc>()
        .map_err(|e| failed("create node", e))
}

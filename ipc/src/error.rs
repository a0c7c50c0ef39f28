//! Why an IPC operation failed: one variant per kind of failure, with iceoryx2's own typed
//! error for each operation it refused (`Refusal`).

use iceoryx2::node::{NodeCreationFailure, NodeListFailure};
use iceoryx2::port::listener::{ListenerCreateError, ListenerWaitError};
use iceoryx2::port::notifier::{NotifierCreateError, NotifierNotifyError};
use iceoryx2::port::publisher::PublisherCreateError;
use iceoryx2::port::subscriber::SubscriberCreateError;
use iceoryx2::port::update_connections::ConnectionFailure;
use iceoryx2::port::{ReceiveError, SendError};
use iceoryx2::service::builder::event::{EventCreateError, EventOpenError};
use iceoryx2::service::builder::publish_subscribe::{PublishSubscribeCreateError, PublishSubscribeOpenError};
use iceoryx2::service::service_name::ServiceNameError;
use iceoryx2_bb_container::semantic_string::SemanticStringError;
use iceoryx2_bb_posix::shared_memory::SharedMemoryCreationError;

/// What iceoryx2 (or its POSIX layer) refused: one variant per operation, holding the
/// operation's own error. Shown as iceoryx2 names it (`InsufficientPermissions`, ...), the
/// words operators and iceoryx2's issues use.
#[derive(Debug, thiserror::Error)]
pub enum Refusal {
    /// A node's name.
    #[error("{0:?}")]
    NodeName(SemanticStringError),
    /// Creating a node.
    #[error("{0:?}")]
    CreateNode(#[from] NodeCreationFailure),
    /// Listing the namespace's nodes.
    #[error("{0:?}")]
    ListNodes(#[from] NodeListFailure),
    /// A service's name.
    #[error("{0:?}")]
    ServiceName(#[from] ServiceNameError),
    /// Creating an event service.
    #[error("{0:?}")]
    CreateEvent(#[from] EventCreateError),
    /// Opening an event service.
    #[error("{0:?}")]
    OpenEvent(#[from] EventOpenError),
    /// Creating a publish-subscribe service.
    #[error("{0:?}")]
    CreatePublishSubscribe(#[from] PublishSubscribeCreateError),
    /// Opening a publish-subscribe service.
    #[error("{0:?}")]
    OpenPublishSubscribe(#[from] PublishSubscribeOpenError),
    /// Creating a publisher.
    #[error("{0:?}")]
    CreatePublisher(#[from] PublisherCreateError),
    /// Creating a subscriber.
    #[error("{0:?}")]
    CreateSubscriber(#[from] SubscriberCreateError),
    /// Sending a sample.
    #[error("{0:?}")]
    Send(#[from] SendError),
    /// Receiving a sample.
    #[error("{0:?}")]
    Receive(#[from] ReceiveError),
    /// Connecting a port to the ports that came since.
    #[error("{0:?}")]
    UpdateConnections(#[from] ConnectionFailure),
    /// Creating a notifier.
    #[error("{0:?}")]
    CreateNotifier(#[from] NotifierCreateError),
    /// Creating a listener.
    #[error("{0:?}")]
    CreateListener(#[from] ListenerCreateError),
    /// Notifying the listeners.
    #[error("{0:?}")]
    Notify(#[from] NotifierNotifyError),
    /// Waiting for a notification.
    #[error("{0:?}")]
    Wait(#[from] ListenerWaitError),
    /// A shared-memory file's name.
    #[error("{0:?}")]
    FileName(SemanticStringError),
    /// Creating or opening a shared-memory segment.
    #[error("{0:?}")]
    SharedMemory(#[from] SharedMemoryCreationError),
}

impl Refusal {
    /// Whether the OS refused this process the files (another user's are in the way).
    pub fn is_permission(&self) -> bool {
        self.to_string().contains("InsufficientPermissions")
    }
}

/// What a controller's services or shared memory found used up.
#[derive(Debug, thiserror::Error)]
pub enum Shortage {
    /// iceoryx2 refused a service or port sized for every task and tool.
    #[error("{0}")]
    Refused(Refusal),
    /// Shared memory refused a region sized for every task and tool.
    #[error("{what}: {source}")]
    Region {
        /// The region's file name under the namespace.
        what: String,
        /// Its refusal.
        source: Refusal,
    },
    /// `/dev/shm` has less room than the services need.
    #[error("{free_mib} MiB free in /dev/shm")]
    Room {
        /// MiB free.
        free_mib: usize,
    },
}

#[derive(Debug, thiserror::Error)]
/// Why an IPC operation failed.
pub enum IpcError {
    #[error("invalid namespace {0:?}: use 1 to 40 characters of A-Z a-z 0-9 _ -")]
    /// The `--ns` name breaks the rules of iceoryx2's service names.
    Namespace(String),
    #[error("iceoryx2: {what}: {source}")]
    /// iceoryx2 refused to create or open a service or port.
    Service {
        /// The service, port or operation concerned.
        what: String,
        /// iceoryx2's error.
        source: Refusal,
    },
    #[error("iceoryx2: {what}: {source}: {advice}")]
    /// Another user's files are in the way.
    Permissions {
        /// The service or file concerned.
        what: String,
        /// iceoryx2's error.
        source: Refusal,
        /// What the operator can do.
        advice: String,
    },
    #[error("iceoryx2: {what}: {shortage}: {advice}")]
    /// A service's limits (nodes, ports, buffers) or the room in `/dev/shm` are used up.
    Capacity {
        /// The service or file concerned.
        what: String,
        /// What was used up.
        shortage: Shortage,
        /// What the operator can do.
        advice: String,
    },
    #[error("shared memory: {what}: {source}")]
    /// Creating or mapping a shared-memory segment failed.
    Shm {
        /// The region's file name under the namespace.
        what: String,
        /// Its refusal.
        source: Refusal,
    },
    #[error("shared memory: {0}: size or alignment does not match this build")]
    /// A region another build made: its size or alignment is not this build's type's.
    ShmLayout(String),
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
    #[error("attached to task {0} already")]
    /// An endpoint attaches to one task only.
    AlreadyAttached(u8),
    #[error("task {0} is not configured in this controller")]
    /// The task a script attaches to has no slot in the running controller.
    TaskNotConfigured(u8),
    #[error("no state snapshot from the controller within {0} s")]
    /// The controller published no snapshot while a script started (seconds waited).
    NoSnapshotInTime(u64),
    #[error("no snapshot from the controller")]
    /// The controller has not published its first snapshot yet.
    NoSnapshot,
    #[error("{0} tools read this controller's state already")]
    /// Every tool reader of the snapshot board is taken by a live tool.
    ToolReadersTaken(usize),
    #[error("start the task waker: {0}")]
    /// The OS refused a task waker's thread.
    TaskWakerThread(std::io::Error),
    #[error("the task waker ended at its start")]
    /// A task waker's thread ended before it was ready.
    TaskWakerEnded,
    #[error("task wakers for {0} CPUs")]
    /// More CPUs than the task table has bells for.
    TaskWakerCpus(usize),
}

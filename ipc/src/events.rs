//! The event stream: what `SendEvent` and `SendMsgEvent` send and the alarms the
//! controller raises, for the tools that follow them (`luamotion events`).

use iceoryx2::prelude::*;

use crate::advice::failed;
use crate::error::IpcError;
use crate::event_record::EventRecord;
use crate::namespace::Namespace;
use crate::room::too_big;
use crate::services::{self, EventPublisher, EventSubscriber, Ipc, Open};

/// A writer of the stream: one per script process, one for the controller.
pub struct EventSender {
    publisher: EventPublisher,
}

impl EventSender {
    /// Opens (or, for the controller, creates) the `events` service with a publisher.
    pub fn new(node: &Node<Ipc>, ns: &Namespace, open: Open) -> Result<Self, IpcError> {
        let publisher = services::events(node, ns, open)?.publisher_builder().create().map_err(|e| match open {
            Open::Create => too_big("events publisher", e),
            Open::Existing => failed("events publisher", e),
        })?;
        Ok(EventSender { publisher })
    }

    /// Publishes one record; never blocks.
    pub fn send(&self, record: &EventRecord) -> Result<(), IpcError> {
        self.publisher.send_copy(*record).map(|_| ()).map_err(|e| failed("send event", e))
    }

    /// Hands the recent history to readers that started since the last send: iceoryx2
    /// delivers it only when the publisher looks at its connections. Called now and then
    /// by the long-lived writers, so that `luamotion events` shows the alarms it missed.
    pub fn greet_new_readers(&self) -> Result<(), IpcError> {
        use iceoryx2::port::update_connections::UpdateConnections;
        self.publisher.update_connections().map_err(|e| failed("update event readers", e))
    }
}

/// A reader of the stream, with its own node.
pub struct EventReader {
    subscriber: EventSubscriber,
    _node: Node<Ipc>,
}

impl EventReader {
    /// Opens the `events` service of namespace `ns` for reading.
    pub fn open(ns: &Namespace) -> Result<Self, IpcError> {
        let node = services::node(ns, &format!("luamotion-events-{}", std::process::id()))?;
        let subscriber = services::events(&node, ns, Open::Existing)?
            .subscriber_builder()
            .create()
            .map_err(|e| failed("events subscriber", e))?;
        Ok(EventReader { subscriber, _node: node })
    }

    /// The next record, if one is waiting.
    pub fn try_next(&self) -> Result<Option<EventRecord>, IpcError> {
        match self.subscriber.receive() {
            Ok(Some(sample)) => Ok(Some(*sample.payload())),
            Ok(None) => Ok(None),
            Err(e) => Err(failed("receive event", e)),
        }
    }
}

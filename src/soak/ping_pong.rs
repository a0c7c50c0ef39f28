//! The transport floor of the soak test: a ping-pong between two processes over the same
//! services, payloads and settings a task's calls use (`task/0/request`, `task/0/reply`,
//! and a wake event each way), with nothing else in between: what iceoryx2 alone costs
//! on this machine.

use std::time::Duration;

use iceoryx2::prelude::Node;

use ::ipc::clock::monotonic_ns;
use ::ipc::messages::{Reply, Request};
use ::ipc::services::{
    self, Ipc, Open, ReplyPublisher, ReplySubscriber, RequestPublisher, RequestSubscriber, WakeListener, WakeNotifier,
    failed,
};
use ::ipc::{IpcError, Namespace};

/// The task id whose services the floor borrows, and the one whose wake event carries pings.
const CHANNEL: u8 = 0;
const PING_WAKE: u8 = 1;

/// How long a blocked side waits before it looks whether it should stop.
const PATIENCE: Duration = Duration::from_millis(100);

/// The echoing side, in its own process.
pub struct Pong {
    requests: RequestSubscriber,
    replies: ReplyPublisher,
    wake_ping: WakeNotifier,
    woken: WakeListener,
    _node: Node<Ipc>,
}

/// One ping's timestamps (CLOCK_MONOTONIC, ns).
#[derive(Clone, Copy, Debug)]
pub struct Echo {
    /// The ping left.
    pub sent_ns: u64,
    /// The pong side had the ping.
    pub pong_received_ns: u64,
    /// The pong side sent the echo.
    pub pong_sent_ns: u64,
    /// The ping side had the echo.
    pub received_ns: u64,
}

impl Pong {
    /// Creates the services; the ping side opens them.
    pub fn create(ns: &Namespace) -> Result<Self, IpcError> {
        let node = services::node(ns, "luamotion-floor-pong")?;
        let requests = services::requests(&node, ns, CHANNEL, Open::Create)?
            .subscriber_builder()
            .create()
            .map_err(|e| failed("floor requests", e))?;
        let replies = services::replies(&node, ns, CHANNEL, Open::Create)?
            .publisher_builder()
            .create()
            .map_err(|e| failed("floor replies", e))?;
        let wake_ping = services::wake(&node, ns, CHANNEL, Open::Create)?
            .notifier_builder()
            .create()
            .map_err(|e| failed("floor wake ping", e))?;
        let woken = services::wake(&node, ns, PING_WAKE, Open::Create)?
            .listener_builder()
            .create()
            .map_err(|e| failed("floor wake pong", e))?;
        Ok(Pong { requests, replies, wake_ping, woken, _node: node })
    }

    /// Echoes pings until `stop()` says so.
    pub fn serve(&self, stop: impl Fn() -> bool) -> Result<u64, IpcError> {
        let mut echoed = 0;
        while !stop() {
            if let Err(e) = self.woken.timed_wait(|_| {}, PATIENCE) {
                // SIGTERM interrupts the wait: that is the end.
                if stop() {
                    break;
                }
                return Err(failed("floor pong wait", e));
            }
            while let Ok(Some(sample)) = self.requests.receive() {
                let received_ns = monotonic_ns();
                let mut reply = Reply::to(sample.payload());
                reply.received_ns = received_ns;
                reply.sent_ns = monotonic_ns();
                self.replies.send_copy(reply).map_err(|e| failed("floor echo", e))?;
                self.wake_ping.notify().map_err(|e| failed("floor notify ping", e))?;
                echoed += 1;
            }
        }
        Ok(echoed)
    }
}

/// The measuring side.
pub struct Ping {
    requests: RequestPublisher,
    replies: ReplySubscriber,
    wake_pong: WakeNotifier,
    woken: WakeListener,
    seq: u64,
    _node: Node<Ipc>,
}

impl Ping {
    /// Opens the ping-pong services of namespace `ns`.
    pub fn open(ns: &Namespace) -> Result<Self, IpcError> {
        let node = services::node(ns, "luamotion-floor-ping")?;
        let requests = services::requests(&node, ns, CHANNEL, Open::Existing)?
            .publisher_builder()
            .create()
            .map_err(|e| failed("floor requests", e))?;
        let replies = services::replies(&node, ns, CHANNEL, Open::Existing)?
            .subscriber_builder()
            .create()
            .map_err(|e| failed("floor replies", e))?;
        let wake_pong = services::wake(&node, ns, PING_WAKE, Open::Existing)?
            .notifier_builder()
            .create()
            .map_err(|e| failed("floor wake pong", e))?;
        let woken = services::wake(&node, ns, CHANNEL, Open::Existing)?
            .listener_builder()
            .create()
            .map_err(|e| failed("floor wake ping", e))?;
        Ok(Ping { requests, replies, wake_pong, woken, seq: 0, _node: node })
    }

    /// One ping: a request-sized payload there, a reply-sized one back.
    pub fn ping(&mut self) -> Result<Echo, IpcError> {
        self.seq += 1;
        let mut request = Request::new(0);
        request.seq = self.seq;
        request.sent_ns = monotonic_ns();
        self.requests.send_copy(request).map_err(|e| failed("floor ping", e))?;
        self.wake_pong.notify().map_err(|e| failed("floor notify pong", e))?;
        loop {
            self.woken.timed_wait(|_| {}, PATIENCE).map_err(|e| failed("floor ping wait", e))?;
            while let Ok(Some(sample)) = self.replies.receive() {
                let reply = sample.payload();
                if reply.seq == self.seq {
                    return Ok(Echo {
                        sent_ns: request.sent_ns,
                        pong_received_ns: reply.received_ns,
                        pong_sent_ns: reply.sent_ns,
                        received_ns: monotonic_ns(),
                    });
                }
            }
            if monotonic_ns() > request.sent_ns + 5_000_000_000 {
                return Err(IpcError::ReplyLost(self.seq));
            }
        }
    }
}

//! The transport floor of the soak test: a ping-pong between two processes over iceoryx2
//! publish-subscribe services (`floor/request`, `floor/reply`) with a task's call and reply
//! as payloads, with nothing else in between: what the tasks' calls cost before they went
//! through mailboxes in the task table. Each side is woken either by an iceoryx2 event (what
//! iceoryx2 alone costs on this machine) or as the core wakes a task: through its bell in
//! a task table (`TaskTable::wake`), the pong side sleeping as a task does, watching its
//! wake count for a moment first (`sleep_for_turn`), and the ping side, in the core's place,
//! sleeping at once: a waker that spins after its wake-up keeps its CPU from a wakee
//! placed there, which the core, back to its sleep, does not.

use std::time::Duration;

use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::{Node, ZeroCopySend};
use iceoryx2::service::port_factory::publish_subscribe;

use ::ipc::advice::failed;
use ::ipc::call::{Reply, Request};
use ::ipc::clock::monotonic_ns;
use ::ipc::services::{self, Ipc, Open, WakeListener, WakeNotifier};
use ::ipc::shm::Region;
use ::ipc::task_table::TaskTable;
use ::ipc::{IpcError, Namespace};

/// The task ids whose wake events (or futex words) carry the echoes and the pings.
const CHANNEL: u8 = 0;
const PING_WAKE: u8 = 1;
/// Pings or echoes a side may hold unread: one is in flight at a time.
const IN_FLIGHT: usize = 4;

/// `<ns>/floor/<what>`: one direction of the ping-pong.
fn channel<T: std::fmt::Debug + ZeroCopySend>(
    node: &Node<Ipc>,
    ns: &Namespace,
    what: &str,
    open: Open,
) -> Result<publish_subscribe::PortFactory<Ipc, T, ()>, IpcError> {
    let builder = node
        .service_builder(&ns.service_name(&format!("floor/{what}"))?)
        .publish_subscribe::<T>()
        .history_size(0)
        .subscriber_max_buffer_size(IN_FLIGHT)
        .subscriber_max_borrowed_samples(IN_FLIGHT)
        .enable_safe_overflow(false)
        .max_publishers(1)
        .max_subscribers(1)
        .max_nodes(2);
    match open {
        Open::Create => builder.create().map_err(|e| failed(&format!("floor {what}"), e)),
        Open::Existing => builder.open().map_err(|e| failed(&format!("open floor {what}"), e)),
    }
}

/// How long a blocked side waits before it looks whether it should stop.
const PATIENCE: Duration = Duration::from_millis(100);

/// How each side wakes the other.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WakeBy {
    Iceoryx2Event,
    Futex,
}

/// One side's wake-ups: it is woken on `mine` and wakes the other side on `other`.
enum Waker {
    Event { notifier: Box<WakeNotifier>, listener: Box<WakeListener> },
    Futex { table: Box<Region<TaskTable>>, mine: u8, other: u8, as_task: bool },
}

impl Waker {
    fn new(node: &Node<Ipc>, ns: &Namespace, by: WakeBy, mine: u8, other: u8, open: Open) -> Result<Self, IpcError> {
        Ok(match by {
            WakeBy::Iceoryx2Event => Waker::Event {
                notifier: Box::new(
                    services::wake(node, ns, other, open)?
                        .notifier_builder()
                        .create()
                        .map_err(|e| failed("floor wake notifier", e))?,
                ),
                listener: Box::new(
                    services::wake(node, ns, mine, open)?
                        .listener_builder()
                        .create()
                        .map_err(|e| failed("floor wake listener", e))?,
                ),
            },
            WakeBy::Futex => {
                let table = match open {
                    Open::Create => Region::<TaskTable>::create(ns, "tasks")?,
                    Open::Existing => Region::<TaskTable>::open(ns, "tasks")?,
                };
                // The side that creates the services (the pong side) plays the task.
                Waker::Futex { table: Box::new(table), mine, other, as_task: matches!(open, Open::Create) }
            }
        })
    }

    /// Wakes the other side; returns the time just before (CLOCK_MONOTONIC, ns).
    fn notify(&self) -> Result<u64, IpcError> {
        let now = monotonic_ns();
        match self {
            Waker::Event { notifier, .. } => {
                notifier.notify().map_err(|e| failed("floor notify", e))?;
            }
            Waker::Futex { table, other, .. } => table.wake(*other as usize, now),
        }
        Ok(now)
    }

    /// Runs `work` once woken (at most `PATIENCE` later), as the waiting side does: the
    /// event is waited for first; the futex word is read before `work` looks, which sleeps
    /// only when it found nothing. Returns what `work` found.
    fn wait_then<T>(&self, mut work: impl FnMut() -> Result<Option<T>, IpcError>) -> Result<Option<T>, IpcError> {
        match self {
            Waker::Event { listener, .. } => {
                listener.timed_wait(|_| {}, PATIENCE).map_err(|e| failed("floor wait", e))?;
                work()
            }
            Waker::Futex { table, mine, as_task, .. } => {
                let seen = table.slots[*mine as usize].wake_count();
                if let Some(found) = work()? {
                    return Ok(Some(found));
                }
                if *as_task {
                    table.sleep_for_turn(*mine as usize, seen, PATIENCE);
                } else {
                    table.sleep(*mine as usize, seen, PATIENCE);
                }
                work()
            }
        }
    }
}

/// The echoing side, in its own process.
pub struct Pong {
    requests: Subscriber<Ipc, Request, ()>,
    replies: Publisher<Ipc, Reply, ()>,
    waker: Waker,
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
    /// Just before the ping side woke the pong side.
    pub notified_ns: u64,
}

impl Pong {
    /// Creates the services; the ping side opens them.
    pub fn create(ns: &Namespace, by: WakeBy) -> Result<Self, IpcError> {
        let node = services::node(ns, "luamotion-floor-pong")?;
        let requests = channel::<Request>(&node, ns, "request", Open::Create)?
            .subscriber_builder()
            .create()
            .map_err(|e| failed("floor requests", e))?;
        let replies = channel::<Reply>(&node, ns, "reply", Open::Create)?
            .publisher_builder()
            .create()
            .map_err(|e| failed("floor replies", e))?;
        let waker = Waker::new(&node, ns, by, PING_WAKE, CHANNEL, Open::Create)?;
        Ok(Pong { requests, replies, waker, _node: node })
    }

    /// Echoes pings until `stop()` says so.
    pub fn serve(&self, stop: impl Fn() -> bool) -> Result<u64, IpcError> {
        let mut echoed = 0;
        while !stop() {
            match self.waker.wait_then(|| self.echo()) {
                Ok(n) => echoed += n.unwrap_or(0),
                // SIGTERM interrupts the wait: that is the end.
                Err(_) if stop() => break,
                Err(e) => return Err(e),
            }
        }
        Ok(echoed)
    }

    /// Echoes the pings waiting; `None` if there were none.
    fn echo(&self) -> Result<Option<u64>, IpcError> {
        let mut echoed = 0;
        while let Ok(Some(sample)) = self.requests.receive() {
            let received_ns = monotonic_ns();
            let mut reply = Reply::to(sample.payload());
            reply.received_ns = received_ns;
            reply.sent_ns = monotonic_ns();
            self.replies.send_copy(reply).map_err(|e| failed("floor echo", e))?;
            self.waker.notify()?;
            echoed += 1;
        }
        Ok((echoed > 0).then_some(echoed))
    }
}

/// The measuring side.
pub struct Ping {
    requests: Publisher<Ipc, Request, ()>,
    replies: Subscriber<Ipc, Reply, ()>,
    waker: Waker,
    seq: u64,
    _node: Node<Ipc>,
}

impl Ping {
    /// Opens the ping-pong services of namespace `ns`.
    pub fn open(ns: &Namespace, by: WakeBy) -> Result<Self, IpcError> {
        let node = services::node(ns, "luamotion-floor-ping")?;
        let requests = channel::<Request>(&node, ns, "request", Open::Existing)?
            .publisher_builder()
            .create()
            .map_err(|e| failed("floor requests", e))?;
        let replies = channel::<Reply>(&node, ns, "reply", Open::Existing)?
            .subscriber_builder()
            .create()
            .map_err(|e| failed("floor replies", e))?;
        let waker = Waker::new(&node, ns, by, CHANNEL, PING_WAKE, Open::Existing)?;
        Ok(Ping { requests, replies, waker, seq: 0, _node: node })
    }

    /// One ping: a request-sized payload there, a reply-sized one back.
    pub fn ping(&mut self) -> Result<Echo, IpcError> {
        self.seq += 1;
        let mut request = Request::new(0);
        request.seq = self.seq;
        request.sent_ns = monotonic_ns();
        self.requests.send_copy(request).map_err(|e| failed("floor ping", e))?;
        let notified_ns = self.waker.notify()?;
        let (replies, seq) = (&self.replies, self.seq);
        let mut echo = || {
            while let Ok(Some(sample)) = replies.receive() {
                let reply = sample.payload();
                if reply.seq == seq {
                    return Ok(Some(Echo {
                        sent_ns: request.sent_ns,
                        pong_received_ns: reply.received_ns,
                        pong_sent_ns: reply.sent_ns,
                        received_ns: monotonic_ns(),
                        notified_ns,
                    }));
                }
            }
            Ok(None)
        };
        loop {
            if let Some(echo) = self.waker.wait_then(&mut echo)? {
                return Ok(echo);
            }
            if monotonic_ns() > request.sent_ns + 5_000_000_000 {
                return Err(IpcError::ReplyLost(self.seq));
            }
        }
    }
}

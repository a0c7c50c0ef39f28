//! A script's end: read the latest snapshot, call the core, wait on core time.
//!
//! Waiting blocks the process on its wake-up word in the task table (a futex), never spins. Every wait also watches the
//! controller: when it is gone, the wait fails and the script process ends.

use std::time::Duration;

use iceoryx2::prelude::*;
use iceoryx2::sample::Sample;

use crate::clock::monotonic_ns;
use crate::events::EventSender;
use crate::messages::{Reply, Request, Snapshot};
use crate::services::failed;
use crate::services::{self, Ipc, Open, ReplySubscriber, RequestPublisher, StateSubscriber};
use crate::shm::Region;
use crate::task_table::{RunState, TaskSlot, TaskTable, WaitRequest};
use crate::{IpcError, Namespace};

/// How often a blocked script checks that its controller is still alive.
const LIVENESS_PERIOD: Duration = Duration::from_millis(100);

/// When the legs of the last call happened (CLOCK_MONOTONIC, ns), for the soak test.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CallTiming {
    /// The script sent the request.
    pub sent_ns: u64,
    /// The core took it (in the cycle that applied it).
    pub taken_ns: u64,
    /// The core sent the reply.
    pub replied_ns: u64,
    /// The core notified the task's wake event (after publishing the cycle's snapshot).
    pub notified_ns: u64,
    /// The script had the reply (after its wake-up).
    pub reply_seen_ns: u64,
    /// The call returned.
    pub returned_ns: u64,
}

/// Replies that did not match their call: each should stay 0.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReplyCounters {
    /// Calls whose reply did not come within the reply timeout.
    pub lost: u64,
    /// A reply for a call answered already.
    pub duplicated: u64,
    /// A reply for a call given up on, or for one not yet sent.
    pub out_of_order: u64,
}

/// What a script process opens before it knows its task (a pooled process waits with it,
/// `rt-core/src/pool.rs`): its node, the state subscriber, the task table. The subscriber
/// is connected by the time a task is handed over, so `attach` does not wait a cycle for
/// the first snapshot.
pub struct PreparedEndpoint {
    controller_pid: u32,
    state: StateSubscriber,
    table: Region<TaskTable>,
    node: Node<Ipc>,
}

impl PreparedEndpoint {
    /// A node named `name` in namespace `ns`, subscribed to the state.
    pub fn new(ns: &Namespace, name: &str, controller_pid: u32) -> Result<Self, IpcError> {
        let node = services::node(ns, name)?;
        let state = services::state(&node, ns, Open::Existing)?
            .subscriber_builder()
            .create()
            .map_err(|e| failed("state subscriber", e))?;
        let table = Region::<TaskTable>::open(ns, "tasks")?;
        Ok(PreparedEndpoint { controller_pid, state, table, node })
    }

    /// A writer of the event stream, on this process' node.
    pub fn event_sender(&self, ns: &Namespace) -> Result<EventSender, IpcError> {
        EventSender::new(&self.node, ns, Open::Existing)
    }

    /// Opens task `task`'s channels and takes over its slot.
    pub fn attach(self, ns: &Namespace, task: u8) -> Result<TaskEndpoint, IpcError> {
        let PreparedEndpoint { controller_pid, state, table, node } = self;
        let requests = services::requests(&node, ns, task, Open::Existing)?
            .publisher_builder()
            .create()
            .map_err(|e| failed(&format!("task {task} requests"), e))?;
        let replies = services::replies(&node, ns, task, Open::Existing)?
            .subscriber_builder()
            .create()
            .map_err(|e| failed(&format!("task {task} replies"), e))?;
        let wait_seq = table.slots[task as usize].wait_request().seq;
        let mut endpoint = TaskEndpoint {
            task,
            controller_pid,
            // Sequence numbers start from the pid: a reply meant for an earlier process of
            // this task can never match one of ours.
            seq: (std::process::id() as u64) << 32,
            answered: 0,
            given_up: [0; 8],
            reply_timeout: None,
            counters: ReplyCounters::default(),
            last_call: CallTiming::default(),
            wait_seq,
            latest: None,
            state,
            requests,
            replies,
            table,
            _node: node,
        };
        endpoint.slot().set_pid(std::process::id());
        endpoint.slot().set_state(RunState::Running);
        endpoint.first_snapshot()?;
        Ok(endpoint)
    }
}

/// A script's end of the IPC: sends its requests, waits on its wake word for the replies, reads the snapshot.
pub struct TaskEndpoint {
    task: u8,
    controller_pid: u32,
    seq: u64,
    /// The last call that got its reply, and the calls given up on (the newest few).
    answered: u64,
    given_up: [u64; 8],
    reply_timeout: Option<Duration>,
    counters: ReplyCounters,
    last_call: CallTiming,
    wait_seq: u16,
    latest: Option<Sample<Ipc, Snapshot, ()>>,
    state: StateSubscriber,
    requests: RequestPublisher,
    replies: ReplySubscriber,
    table: Region<TaskTable>,
    _node: Node<Ipc>,
}

impl TaskEndpoint {
    /// Opens task `task`'s channels in namespace `ns`; `controller_pid` is watched while blocked.
    pub fn open(ns: &Namespace, task: u8, controller_pid: u32) -> Result<Self, IpcError> {
        PreparedEndpoint::new(ns, &format!("luamotion-task-{task}"), controller_pid)?.attach(ns, task)
    }

    /// The task id.
    pub fn task(&self) -> u8 {
        self.task
    }

    /// A writer of the event stream, on this endpoint's node.
    pub fn event_sender(&self, ns: &Namespace) -> Result<EventSender, IpcError> {
        EventSender::new(&self._node, ns, Open::Existing)
    }

    /// This task's slot of the task table.
    pub fn slot(&self) -> &TaskSlot {
        &self.table.slots[self.task as usize]
    }

    /// The newest snapshot the core has published.
    pub fn snapshot(&mut self) -> &Snapshot {
        self.refresh();
        self.latest.as_ref().expect("opened with a snapshot")
    }

    fn refresh(&mut self) {
        while let Ok(Some(sample)) = self.state.receive() {
            self.latest = Some(sample);
        }
    }

    fn first_snapshot(&mut self) -> Result<(), IpcError> {
        let deadline = monotonic_ns() + 5_000_000_000;
        loop {
            self.refresh();
            if self.latest.is_some() {
                return Ok(());
            }
            if monotonic_ns() > deadline {
                return Err(IpcError::Service("no state snapshot from the controller within 5 s".into()));
            }
            self.check_controller()?;
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    /// Sends one request and blocks until its reply. Afterwards `snapshot()` shows the
    /// state of the cycle in which the core applied it.
    pub fn call(&mut self, request: &mut Request) -> Result<Reply, IpcError> {
        self.seq += 1;
        request.seq = self.seq;
        request.sent_ns = monotonic_ns();
        self.slot().set_state(RunState::InCall);
        let result = self.exchange(request);
        self.slot().set_state(RunState::Running);
        let (reply, reply_seen_ns) = result?;
        self.answered = reply.seq;
        loop {
            let seen = self.slot().wake_count();
            if self.snapshot().cycle >= reply.cycle {
                break;
            }
            self.sleep(seen)?;
        }
        self.last_call = CallTiming {
            sent_ns: request.sent_ns,
            taken_ns: reply.received_ns,
            replied_ns: reply.sent_ns,
            notified_ns: self.slot().notified_ns(),
            reply_seen_ns,
            returned_ns: monotonic_ns(),
        };
        Ok(reply)
    }

    /// The timing of the last call that got its reply.
    pub fn last_call(&self) -> CallTiming {
        self.last_call
    }

    /// The reply counters so far.
    pub fn reply_counters(&self) -> ReplyCounters {
        self.counters
    }

    /// Gives up on a call whose reply has not come within `timeout` (`IpcError::ReplyLost`);
    /// `None` (the default) waits as long as the controller lives: calls like `MoveHome`
    /// answer when the machine is done.
    pub fn set_reply_timeout(&mut self, timeout: Option<Duration>) {
        self.reply_timeout = timeout;
    }

    fn exchange(&mut self, request: &Request) -> Result<(Reply, u64), IpcError> {
        let delivered = self.requests.send_copy(*request).map_err(|e| failed("send request", e))?;
        if delivered == 0 {
            return Err(IpcError::ControllerGone);
        }
        let deadline = self.reply_timeout.map(|t| request.sent_ns + t.as_nanos() as u64);
        loop {
            let seen = self.slot().wake_count();
            match self.replies.receive() {
                Ok(Some(reply)) if reply.payload().seq == request.seq => return Ok((*reply.payload(), monotonic_ns())),
                Ok(Some(reply)) => self.unexpected(reply.payload().seq),
                Ok(None) => {}
                Err(e) => return Err(IpcError::Service(format!("receive reply: {e:?}"))),
            }
            if deadline.is_some_and(|d| monotonic_ns() > d) {
                self.counters.lost += 1;
                self.given_up[(self.counters.lost % 8) as usize] = request.seq;
                return Err(IpcError::ReplyLost(request.seq));
            }
            self.sleep(seen)?;
        }
    }

    /// A reply for another call than the one waiting: an earlier process' late reply is
    /// skipped quietly; anything else is counted.
    fn unexpected(&mut self, seq: u64) {
        let ours = seq >> 32 == self.seq >> 32;
        if !ours {
            return;
        }
        if seq <= self.answered && !self.given_up.contains(&seq) {
            self.counters.duplicated += 1;
        } else {
            self.counters.out_of_order += 1;
        }
    }

    /// Blocks until core cycle `cycle` has been published.
    pub fn wait_until_cycle(&mut self, cycle: u64) -> Result<(), IpcError> {
        loop {
            let seen = self.slot().wake_count();
            if self.snapshot().cycle >= cycle {
                return Ok(());
            }
            self.wait_seq = self.wait_seq.wrapping_add(1);
            let request = WaitRequest { seq: self.wait_seq, cycle };
            self.table.slots[self.task as usize].begin_wait(request);
            let woken = self.sleep(seen);
            self.slot().set_state(RunState::Running);
            woken?;
        }
    }

    /// Sleeps until the core wakes this task, unless it did since `seen` was read (or
    /// until the liveness period passes).
    fn sleep(&self, seen: u32) -> Result<(), IpcError> {
        self.slot().sleep(seen, LIVENESS_PERIOD);
        self.check_controller()
    }

    /// Fails when the controller is gone.
    pub fn check_controller(&self) -> Result<(), IpcError> {
        // SAFETY: signal 0 only checks that the process exists.
        let alive = unsafe { libc::kill(self.controller_pid as libc::pid_t, 0) } == 0;
        if alive { Ok(()) } else { Err(IpcError::ControllerGone) }
    }
}

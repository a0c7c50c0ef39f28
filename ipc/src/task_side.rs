//! A script's end: read the latest snapshot, call the core, wait on core time.
//!
//! Waiting blocks the process on its bell in the task table (a futex), never spins. Every
//! wait also watches the controller: when it is gone, the wait fails and the script
//! process ends.

use std::time::Duration;

use iceoryx2::prelude::*;

use schema::{MAX_TASKS, Snapshot};

use crate::call::{Reply, Request};
use crate::clock::monotonic_ns;
use crate::error::IpcError;
use crate::events::EventSender;
use crate::namespace::Namespace;
use crate::process::process_alive;
use crate::services::{self, DeadNodes, Ipc, Open};
use crate::shm::Region;
use crate::snapshot_board::{BoardReader, SnapshotBoard};
use crate::task_table::{RunState, TaskSlot, TaskTable, WaitRequest, WatchEntry};

/// How often a blocked script checks that its controller is still alive.
const LIVENESS_PERIOD: Duration = Duration::from_millis(100);
/// On the simulation clock, a task's share of a cycle: after this many API calls in one
/// cycle it waits for the next (docs/decisions.md, "A task's share of a simulated cycle").
pub const CALLS_PER_CYCLE: u32 = 200;

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
/// `rt-core/src/pool.rs`): its node, the snapshot board, the task table (which holds
/// every task's mailbox), so `attach` opens nothing.
pub struct PreparedEndpoint {
    controller_pid: u32,
    state: BoardReader<Snapshot>,
    table: Region<TaskTable>,
    node: Node<Ipc>,
}

impl PreparedEndpoint {
    /// A node named `name` in namespace `ns`, with the snapshot board open.
    pub fn new(ns: &Namespace, name: &str, controller_pid: u32, dead: DeadNodes) -> Result<Self, IpcError> {
        let node = services::node_with(ns, name, dead)?;
        let state = BoardReader::standby(SnapshotBoard::open(ns)?);
        let table = Region::<TaskTable>::open(ns, "tasks")?;
        Ok(PreparedEndpoint { controller_pid, state, table, node })
    }

    /// A writer of the event stream, on this process' node.
    pub fn event_sender(&self, ns: &Namespace) -> Result<EventSender, IpcError> {
        EventSender::new(&self.node, ns, Open::Existing)
    }

    /// Takes over task `task`'s slot and mailbox; fails for a task the controller does not serve.
    pub fn attach(self, task: u8) -> Result<TaskEndpoint, IpcError> {
        let mut endpoint = self.standby();
        endpoint.attach(task)?;
        Ok(endpoint)
    }

    /// The endpoint before it has a task (a pooled process makes its VM on it while it
    /// waits): nothing may be called through it until `TaskEndpoint::attach`.
    pub fn standby(self) -> TaskEndpoint {
        let PreparedEndpoint { controller_pid, state, table, node } = self;
        TaskEndpoint {
            task: UNATTACHED,
            controller_pid,
            // Sequence numbers start from the pid: a reply meant for an earlier process of
            // this task can never match one of ours.
            seq: (std::process::id() as u64) << 32,
            answered: 0,
            given_up: [0; 8],
            last_unexpected: 0,
            reply: Box::new(Reply::to(&Request::new(0))),
            reply_timeout: None,
            counters: ReplyCounters::default(),
            last_call: CallTiming::default(),
            wait_seq: 0,
            lockstep: false,
            calls_in_cycle: 0,
            share_cycle: 0,
            state,
            table,
            _node: node,
        }
    }
}

/// The task of an endpoint not attached yet: no slot (indexing with it panics).
const UNATTACHED: u8 = u8::MAX;

/// A script's end of the IPC: sends its requests, waits on its bell for the replies, reads the snapshot.
pub struct TaskEndpoint {
    task: u8,
    controller_pid: u32,
    seq: u64,
    /// The last call that got its reply, and the calls given up on (the newest few).
    answered: u64,
    given_up: [u64; 8],
    /// The last reply of another call counted (the mailbox shows it until the next reply).
    last_unexpected: u64,
    /// Where a reply is copied out of the mailbox.
    reply: Box<Reply>,
    reply_timeout: Option<Duration>,
    counters: ReplyCounters,
    last_call: CallTiming,
    wait_seq: u16,
    /// On the simulation clock: runs Lua only in the turns the core grants.
    lockstep: bool,
    /// API calls in the cycle `share_cycle`.
    calls_in_cycle: u32,
    share_cycle: u64,
    /// The snapshot board, read as this task's reader once attached.
    state: BoardReader<Snapshot>,
    table: Region<TaskTable>,
    _node: Node<Ipc>,
}

impl TaskEndpoint {
    /// Opens task `task`'s endpoint in namespace `ns`; `controller_pid` is watched while blocked.
    pub fn open(ns: &Namespace, task: u8, controller_pid: u32) -> Result<Self, IpcError> {
        Self::open_with(ns, task, controller_pid, DeadNodes::Cleaned)
    }

    /// `open`, leaving dead nodes to `dead` (a script process the supervisor started).
    pub fn open_with(ns: &Namespace, task: u8, controller_pid: u32, dead: DeadNodes) -> Result<Self, IpcError> {
        PreparedEndpoint::new(ns, &format!("luamotion-task-{task}"), controller_pid, dead)?.attach(task)
    }

    /// The task id.
    pub fn task(&self) -> u8 {
        self.task
    }

    /// Takes over task `task`'s slot and mailbox (once, on an endpoint in standby); fails
    /// for a task the controller does not serve.
    pub fn attach(&mut self, task: u8) -> Result<(), IpcError> {
        if self.task != UNATTACHED {
            return Err(IpcError::AlreadyAttached(self.task));
        }
        if (task as usize) >= MAX_TASKS || self.table.calls.configured() & 1 << task == 0 {
            return Err(IpcError::TaskNotConfigured(task));
        }
        self.task = task;
        self.state.attach_task(task);
        self.wait_seq = self.slot().wait_request().seq;
        self.lockstep = self.slot().lockstep();
        self.slot().set_pid(std::process::id());
        self.slot().set_state(RunState::Running);
        self.first_snapshot()
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
        self.state.latest().expect("attached after the first snapshot")
    }

    fn first_snapshot(&mut self) -> Result<(), IpcError> {
        let deadline = monotonic_ns() + 5_000_000_000;
        loop {
            if self.state.latest().is_some() {
                return Ok(());
            }
            if monotonic_ns() > deadline {
                return Err(IpcError::NoSnapshotInTime(5));
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
        let result = if self.lockstep { self.exchange_in_lockstep(request) } else { self.exchange(request) };
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
        self.send(request);
        let deadline = self.reply_timeout.map(|t| request.sent_ns + t.as_nanos() as u64);
        loop {
            let seen = self.slot().wake_count();
            if let Some(reply) = self.take_reply(request.seq)? {
                return Ok((reply, monotonic_ns()));
            }
            if deadline.is_some_and(|d| monotonic_ns() > d) {
                self.counters.lost += 1;
                self.given_up[(self.counters.lost % 8) as usize] = request.seq;
                return Err(IpcError::ReplyLost(request.seq));
            }
            self.sleep(seen)?;
        }
    }

    /// `exchange` on the simulation clock: the task parks once the request is sent and
    /// takes its next turn in the cycle the core answers (no reply timeout: the core
    /// answers every call it takes, and a lost controller ends the wait).
    fn exchange_in_lockstep(&mut self, request: &Request) -> Result<(Reply, u64), IpcError> {
        self.send(request);
        self.park();
        let mut reply = Ok(None);
        self.next_turn(|endpoint| {
            reply = endpoint.take_reply(request.seq);
            !matches!(reply, Ok(None))
        })?;
        Ok((reply?.expect("a turn is taken with the reply"), monotonic_ns()))
    }

    /// Posts the request into the task's mailbox (the controller's liveness is watched
    /// while the task waits for the reply).
    fn send(&self, request: &Request) {
        self.table.calls.post(self.task, request);
    }

    /// The reply to call `seq`, if it has come; a reply to another call is counted once.
    fn take_reply(&mut self, seq: u64) -> Result<Option<Reply>, IpcError> {
        match self.table.calls.mailbox(self.task).read_reply(&mut self.reply) {
            Some(got) if got == seq => Ok(Some(*self.reply)),
            Some(got) => {
                if std::mem::replace(&mut self.last_unexpected, got) != got {
                    self.unexpected(got);
                }
                Ok(None)
            }
            None => Ok(None),
        }
    }

    /// A reply for another call than the one waiting: an earlier process' reply, or the
    /// last call's (the mailbox holds it until the next), is skipped quietly; anything
    /// else is counted.
    fn unexpected(&mut self, seq: u64) {
        let ours = seq >> 32 == self.seq >> 32;
        if !ours || seq == self.answered {
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
        if self.lockstep {
            return self.wait_in_lockstep(cycle, &[]);
        }
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

    /// `wait_until_cycle` on the simulation clock: the wait request is published, the
    /// turn given back, and the next turn comes in cycle `cycle`.
    fn wait_in_lockstep(&mut self, cycle: u64, watch: &[WatchEntry]) -> Result<(), IpcError> {
        if self.snapshot().cycle >= cycle {
            return Ok(());
        }
        self.wait_seq = self.wait_seq.wrapping_add(1);
        self.slot().set_watch(watch);
        self.slot().begin_wait(WaitRequest { seq: self.wait_seq, cycle });
        self.park();
        let woken = self.next_turn(|endpoint| endpoint.snapshot().cycle >= cycle);
        self.slot().clear_watch();
        self.slot().set_state(RunState::Running);
        woken
    }

    /// `wait_until_cycle` for a `Till` condition that read `watch` and nothing else: on
    /// the simulation clock the core grants the next turn only in a cycle in which one of
    /// its answers changed. In real time, the same as `wait_until_cycle`.
    pub fn wait_watching(&mut self, cycle: u64, watch: &[WatchEntry]) -> Result<(), IpcError> {
        if self.lockstep {
            return self.wait_in_lockstep(cycle, watch);
        }
        self.wait_until_cycle(cycle)
    }

    /// Whether this task runs in lockstep with the simulation clock.
    pub fn lockstep(&self) -> bool {
        self.lockstep
    }

    /// Counts one API call; on the simulation clock, a task that has used its share of the
    /// cycle waits for the next one (so a loop polling `GetGPI` lets time advance).
    pub fn count_call(&mut self) -> Result<(), IpcError> {
        if !self.lockstep {
            return Ok(());
        }
        let cycle = self.snapshot().cycle;
        if cycle != self.share_cycle {
            (self.share_cycle, self.calls_in_cycle) = (cycle, 0);
        }
        self.calls_in_cycle += 1;
        if self.calls_in_cycle < CALLS_PER_CYCLE {
            return Ok(());
        }
        self.wait_in_lockstep(cycle + 1, &[])
    }

    /// On the simulation clock: the first turn, before the program's first line (a
    /// starting task holds the clock until then).
    pub fn first_turn(&mut self) -> Result<(), IpcError> {
        if !self.lockstep {
            return Ok(());
        }
        self.yield_turn()
    }

    /// On the simulation clock: lets the other tasks whose wait has come take their turns
    /// in this cycle first (`RunScheduler`).
    pub fn yield_turn(&mut self) -> Result<(), IpcError> {
        self.park();
        self.next_turn(|_| true)
    }

    /// On the simulation clock: blocks on mutex `id`; the core grants the next turn once
    /// it is free.
    pub fn wait_for_mutex_turn(&mut self, id: usize) -> Result<(), IpcError> {
        self.slot().set_blocked_on(id);
        self.slot().set_state(RunState::Blocked);
        self.park();
        let woken = self.next_turn(|_| true);
        self.slot().set_state(RunState::Running);
        woken
    }

    /// Gives the turn back (the core goes on with the other tasks or the next cycle).
    fn park(&mut self) {
        self.table.park(self.task);
    }

    /// Sleeps until a turn in which `ready` holds; a turn in which it does not is given back.
    fn next_turn(&mut self, mut ready: impl FnMut(&mut Self) -> bool) -> Result<(), IpcError> {
        loop {
            let seen = self.slot().wake_count();
            if self.slot().take_turn() {
                if ready(self) {
                    return Ok(());
                }
                self.park();
            }
            self.table.sleep_for_turn(self.task as usize, seen, LIVENESS_PERIOD);
            self.check_controller()?;
        }
    }

    /// Sleeps until the core wakes this task, unless it did since `seen` was read (or
    /// until the liveness period passes).
    fn sleep(&self, seen: u32) -> Result<(), IpcError> {
        self.table.sleep(self.task as usize, seen, LIVENESS_PERIOD);
        self.check_controller()
    }

    /// Fails when the controller is gone.
    pub fn check_controller(&self) -> Result<(), IpcError> {
        if process_alive(self.controller_pid) { Ok(()) } else { Err(IpcError::ControllerGone) }
    }
}

//! The controller's end: write the state snapshot, serve each task's calls, wake tasks.
//!
//! Everything here is called from the RT thread once per cycle. Ports are created before
//! the first cycle; serving, publishing and waking do not allocate.

use iceoryx2::prelude::*;

use schema::shared::SharedData;
use schema::{MAX_TASKS, Snapshot};

use crate::call::{Reply, Request};
use crate::clock::monotonic_ns;
use crate::error::IpcError;
use crate::namespace::Namespace;
use crate::room::region_too_big;
use crate::services::{self, Ipc};
use crate::shm::Region;
use crate::snapshot_board::{BoardWriter, SlotWrite, SnapshotBoard};
use crate::task_table::{RunState, TaskTable};
use crate::task_waker::TaskWakers;

/// Name of the controller's node; a live node of this name owns the namespace.
pub const CORE_NODE_NAME: &str = "luamotion-core";

/// What the core does with a request it has taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Disposition {
    /// The reply is complete: send it now.
    Reply,
    /// The call blocks (e.g. `MoveHome`): keep it and answer when `resume` says it is done.
    Defer,
}

/// A call kept until it completes, with the process it came from.
struct Deferred {
    request: Request,
    reply: Reply,
    pid: u32,
}

struct TaskChannel {
    id: u8,
    /// The sequence number of the last request taken: a hostile process that posts the
    /// same call again is not served twice.
    last_taken: u64,
    /// Sequence number of the last wait request this task was woken for.
    last_woken_wait: Option<u16>,
    replied: bool,
    deferred: Option<Deferred>,
}

/// The board slot a cycle writes its snapshot into, then `CoreEndpoint::send_snapshot`.
pub type SnapshotSample = SlotWrite<Snapshot>;

/// Counters the soak test and the logs read.
#[derive(Clone, Copy, Debug, Default)]
pub struct CoreIpcStats {
    /// Requests received from tasks.
    pub requests: u64,
    /// Replies written.
    pub replies: u64,
    /// Posted requests not taken: rewritten while copied (a new call of a task that gave
    /// up on the last), of another process than the slot's, taken already, or of a task
    /// the core does not serve.
    pub refused: u64,
    /// Futex wakes of tasks.
    pub wakes: u64,
    /// Snapshots that could not be published.
    pub publish_failures: u64,
    /// Of `wakes`, those whose futex wake a task waker made (`hand_wakes_to_threads`).
    pub handed_off: u64,
    /// Of `wakes`, those that found the task asleep, woken by a futex wake of its bell (the
    /// others were seen by the task before it slept).
    pub futex_wakes: u64,
    /// CPU time the task waker threads have used, ns: work the RT thread handed them.
    pub waker_cpu_ns: u64,
}

/// The controller's end of the IPC: publishes the snapshot, serves the tasks' requests and wakes them.
pub struct CoreEndpoint {
    board: BoardWriter<Snapshot>,
    tasks: Vec<TaskChannel>,
    /// The tasks served, bit t for task t.
    served: u64,
    /// Tasks whose posted call waits until their deferred one is answered.
    held: u64,
    /// Where the request being served is copied to (boxed: 1.6 KB, taken every cycle).
    scratch: Box<Request>,
    table: Region<TaskTable>,
    shared: Region<SharedData>,
    stats: CoreIpcStats,
    wakers: Option<TaskWakers>,
    // Dropped last: the ports above belong to it.
    _node: Node<Ipc>,
}

impl CoreEndpoint {
    /// Creates the snapshot board and the task table, with a mailbox for each configured task.
    pub fn create(ns: &Namespace, task_ids: &[u8]) -> Result<Self, IpcError> {
        let node = services::node(ns, CORE_NODE_NAME)?;
        // Without the room for it, says what the shared memory is sized for.
        let board = BoardWriter::new(SnapshotBoard::create(ns).map_err(|e| region_too_big("snapshot board", e))?);
        let tasks: Vec<TaskChannel> = task_ids
            .iter()
            .filter(|&&id| (id as usize) < MAX_TASKS)
            .map(|&id| TaskChannel { id, last_taken: 0, last_woken_wait: None, replied: false, deferred: None })
            .collect();
        let served = tasks.iter().fold(0, |mask, t| mask | 1 << t.id);
        let table = Region::<TaskTable>::create(ns, "tasks")?;
        table.calls.set_configured(served);
        let shared = Region::<SharedData>::create(ns, "shared")?;
        Ok(CoreEndpoint {
            board,
            tasks,
            served,
            held: 0,
            scratch: Box::new(Request::new(0)),
            table,
            shared,
            stats: CoreIpcStats::default(),
            wakers: None,
            _node: node,
        })
    }

    /// The task table in shared memory.
    pub fn table(&self) -> &TaskTable {
        &self.table
    }

    /// The shared data in shared memory.
    pub fn shared(&self) -> &SharedData {
        &self.shared
    }

    /// Bit t set: the core holds a call of task t to answer later.
    pub fn deferred_tasks(&self) -> u64 {
        self.tasks.iter().filter(|t| t.deferred.is_some()).fold(0, |mask, t| mask | 1 << t.id)
    }

    /// The counters so far.
    pub fn stats(&self) -> CoreIpcStats {
        let wakers = self.wakers.as_ref();
        CoreIpcStats {
            waker_cpu_ns: wakers.map_or(0, TaskWakers::cpu_ns),
            futex_wakes: self.stats.futex_wakes + wakers.map_or(0, TaskWakers::futex_wakes),
            ..self.stats
        }
    }

    /// Takes each task's posted call and answers it with `handle(task, request, reply)`.
    /// A reply is written at once unless the handler defers it; the task is woken by
    /// `wake`, after the snapshot that shows the command's effect is published. A task with
    /// a deferred call is served nothing else until it is answered.
    pub fn serve(&mut self, cycle: u64, mut handle: impl FnMut(u8, &Request, &mut Reply) -> Disposition) {
        // One load for every task: a task that sleeps or runs Lua costs no more than a bit test.
        let posted = self.table.calls.take_posted() | std::mem::take(&mut self.held);
        self.stats.refused += (posted & !self.served).count_ones() as u64;
        // In the machine file's order, as before: of two tasks commanding one axis in one
        // cycle, the later one is refused (docs/decisions.md, "Two tasks on one axis").
        for task in self.tasks.iter_mut().filter(|t| posted & 1 << t.id != 0) {
            let id = task.id;
            if task.deferred.is_some() {
                self.held |= 1 << id;
                continue;
            }
            let slot = &self.table.slots[id as usize];
            let request = &mut *self.scratch;
            let Some(seq) = self.table.calls.mailbox(id).read_request(request) else {
                // Rewritten while copied: the writer posts it again.
                self.stats.refused += 1;
                continue;
            };
            if seq == task.last_taken || seq >> 32 != slot.pid() as u64 {
                self.stats.refused += 1;
                continue;
            }
            task.last_taken = seq;
            let received_ns = monotonic_ns();
            self.stats.requests += 1;
            let mut reply = Reply::to(request);
            reply.received_ns = received_ns;
            reply.cycle = cycle;
            match handle(id, request, &mut reply) {
                Disposition::Reply => Self::send(&self.table, task, &mut self.stats, reply),
                Disposition::Defer => {
                    task.deferred = Some(Deferred { request: *request, reply, pid: slot.pid() });
                }
            }
        }
    }

    /// Answers the deferred calls `done(task, request, reply)` says are complete. A call
    /// whose process is gone is dropped.
    pub fn resume(&mut self, cycle: u64, mut done: impl FnMut(u8, &Request, &mut Reply) -> bool) {
        for task in &mut self.tasks {
            let Some(deferred) = &mut task.deferred else { continue };
            let slot = &self.table.slots[task.id as usize];
            if slot.pid() != deferred.pid || matches!(slot.state(), RunState::Idle | RunState::Finished) {
                task.deferred = None;
                continue;
            }
            if done(task.id, &deferred.request, &mut deferred.reply) {
                let mut reply = deferred.reply;
                reply.cycle = cycle;
                task.deferred = None;
                Self::send(&self.table, task, &mut self.stats, reply);
            }
        }
    }

    fn send(table: &TaskTable, task: &mut TaskChannel, stats: &mut CoreIpcStats, mut reply: Reply) {
        reply.sent_ns = monotonic_ns();
        table.calls.mailbox(task.id).write_reply(&reply);
        stats.replies += 1;
        task.replied = true;
    }

    /// The board slot the cycle's snapshot is written into in place, instead of being
    /// built aside and copied (at 96 axes the copy of ~70 KB was a tenth of the RT
    /// thread's time). The slot holds `layout` (what changes only with the bus:
    /// `generation` numbers each version of it), and the caller writes every other field.
    /// `None` when no slot can be had (counted): the cycle goes on without publishing.
    pub fn loan_snapshot(&mut self, layout: &Snapshot, generation: u64) -> Option<SnapshotSample> {
        let slot = self.board.begin(layout, generation);
        self.stats.publish_failures += slot.is_none() as u64;
        slot
    }

    /// Makes the snapshot written into `sample` the latest.
    pub fn send_snapshot(&mut self, mut sample: SnapshotSample) {
        sample.payload_mut().published_ns = monotonic_ns();
        self.board.publish(sample);
    }

    /// From now on, when more than one task is due in a cycle, their futex wakes are
    /// made by threads of their own, one per CPU of `cpus` ("task-waker<cpu>", each set up
    /// by `setup(cpu)`, e.g. pinned there with a real-time priority below the RT thread's),
    /// each waking the tasks that went to sleep on its CPU (`task_waker`); the RT thread
    /// wakes the first waker (`cpus[0]`: its own CPU), which wakes the others with work. A
    /// single task due is still woken directly: its wake-up stays one hop.
    pub fn hand_wakes_to_threads(
        &mut self,
        ns: &Namespace,
        cpus: &[usize],
        setup: impl Fn(usize) + Clone + Send + 'static,
    ) -> Result<(), IpcError> {
        self.wakers = Some(TaskWakers::start(ns, cpus, setup)?);
        Ok(())
    }

    /// Wakes every task whose reply was sent this cycle or whose wait cycle has come;
    /// returns them, bit t for task t.
    pub fn wake(&mut self, cycle: u64) -> u64 {
        let mut woken = 0u64;
        let now = monotonic_ns();
        for task in &mut self.tasks {
            let slot = &self.table.slots[task.id as usize];
            let mut due = std::mem::take(&mut task.replied);
            if slot.state() == RunState::Waiting {
                let wait = slot.wait_request();
                if wait.cycle <= cycle && task.last_woken_wait != Some(wait.seq) {
                    task.last_woken_wait = Some(wait.seq);
                    due = true;
                }
            }
            if due {
                slot.notify(now);
                woken |= 1 << task.id;
            }
        }
        self.stats.wakes += woken.count_ones() as u64;
        match &mut self.wakers {
            Some(wakers) if woken.count_ones() > 1 => {
                wakers.hand(&self.table, woken);
                self.stats.handed_off += woken.count_ones() as u64;
            }
            _ => self.stats.futex_wakes += self.table.wake_sleepers(woken),
        }
        woken
    }
}

//! A script's end: read the latest snapshot, call the core, wait on core time.
//!
//! Waiting blocks the process on its wake event, never spins. Every wait also watches the
//! controller: when it is gone, the wait fails and the script process ends.

use std::time::Duration;

use iceoryx2::prelude::*;
use iceoryx2::sample::Sample;

use crate::clock::monotonic_ns;
use crate::events::EventSender;
use crate::messages::{Reply, Request, Snapshot};
use crate::services::failed;
use crate::services::{self, Ipc, Open, ReplySubscriber, RequestPublisher, StateSubscriber, WakeListener};
use crate::shm::Region;
use crate::task_table::{RunState, TaskSlot, TaskTable, WaitRequest};
use crate::{IpcError, Namespace};

/// How often a blocked script checks that its controller is still alive.
const LIVENESS_PERIOD: Duration = Duration::from_millis(100);

pub struct TaskEndpoint {
    task: u8,
    controller_pid: u32,
    seq: u64,
    wait_seq: u16,
    latest: Option<Sample<Ipc, Snapshot, ()>>,
    state: StateSubscriber,
    requests: RequestPublisher,
    replies: ReplySubscriber,
    listener: WakeListener,
    table: Region<TaskTable>,
    _node: Node<Ipc>,
}

impl TaskEndpoint {
    pub fn open(ns: &Namespace, task: u8, controller_pid: u32) -> Result<Self, IpcError> {
        let node = services::node(ns, &format!("luamotion-task-{task}"))?;
        let state = services::state(&node, ns, Open::Existing)?
            .subscriber_builder()
            .create()
            .map_err(|e| failed("state subscriber", e))?;
        let requests = services::requests(&node, ns, task, Open::Existing)?
            .publisher_builder()
            .create()
            .map_err(|e| failed(&format!("task {task} requests"), e))?;
        let replies = services::replies(&node, ns, task, Open::Existing)?
            .subscriber_builder()
            .create()
            .map_err(|e| failed(&format!("task {task} replies"), e))?;
        let listener = services::wake(&node, ns, task, Open::Existing)?
            .listener_builder()
            .create()
            .map_err(|e| failed(&format!("task {task} listener"), e))?;
        let table = Region::<TaskTable>::open(ns, "tasks")?;
        let wait_seq = table.slots[task as usize].wait_request().seq;
        let mut endpoint = TaskEndpoint {
            task,
            controller_pid,
            // Sequence numbers start from the pid: a reply meant for an earlier process of
            // this task can never match one of ours.
            seq: (std::process::id() as u64) << 32,
            wait_seq,
            latest: None,
            state,
            requests,
            replies,
            listener,
            table,
            _node: node,
        };
        endpoint.slot().set_pid(std::process::id());
        endpoint.slot().set_state(RunState::Running);
        endpoint.first_snapshot()?;
        Ok(endpoint)
    }

    pub fn task(&self) -> u8 {
        self.task
    }

    /// A writer of the event stream, on this endpoint's node.
    pub fn event_sender(&self, ns: &Namespace) -> Result<EventSender, IpcError> {
        EventSender::new(&self._node, ns, Open::Existing)
    }

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
        let reply = result?;
        if reply.seq != request.seq {
            return Err(IpcError::Protocol(format!(
                "reply to request {} while waiting for {}",
                reply.seq, request.seq
            )));
        }
        while self.snapshot().cycle < reply.cycle {
            self.block()?;
        }
        Ok(reply)
    }

    fn exchange(&mut self, request: &Request) -> Result<Reply, IpcError> {
        let delivered = self.requests.send_copy(*request).map_err(|e| failed("send request", e))?;
        if delivered == 0 {
            return Err(IpcError::ControllerGone);
        }
        loop {
            match self.replies.receive() {
                Ok(Some(reply)) if reply.payload().seq == request.seq => return Ok(*reply.payload()),
                // A reply to an earlier call (one this process gave up on): skip it.
                Ok(Some(_)) => continue,
                Ok(None) => {}
                Err(e) => return Err(IpcError::Service(format!("receive reply: {e:?}"))),
            }
            self.block()?;
        }
    }

    /// Blocks until core cycle `cycle` has been published.
    pub fn wait_until_cycle(&mut self, cycle: u64) -> Result<(), IpcError> {
        while self.snapshot().cycle < cycle {
            self.wait_seq = self.wait_seq.wrapping_add(1);
            let request = WaitRequest { seq: self.wait_seq, cycle };
            self.table.slots[self.task as usize].begin_wait(request);
            let woken = self.block();
            self.slot().set_state(RunState::Running);
            woken?;
        }
        Ok(())
    }

    /// Sleeps on the wake event (or until the liveness period passes).
    fn block(&mut self) -> Result<(), IpcError> {
        self.listener.timed_wait(|_| {}, LIVENESS_PERIOD).map_err(|e| failed("wait on wake event", e))?;
        self.check_controller()
    }

    /// Fails when the controller is gone.
    pub fn check_controller(&self) -> Result<(), IpcError> {
        // SAFETY: signal 0 only checks that the process exists.
        let alive = unsafe { libc::kill(self.controller_pid as libc::pid_t, 0) } == 0;
        if alive { Ok(()) } else { Err(IpcError::ControllerGone) }
    }
}

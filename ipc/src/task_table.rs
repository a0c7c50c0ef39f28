//! The task table in shared memory: what each script process is doing, written by the
//! script, read by the core every cycle. Plain atomics, so that the Lua instruction hook
//! can bump a heartbeat at the cost of one store.

use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};

use crate::messages::MAX_TASKS;
use crate::shm::Shareable;

/// What a task's script is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum RunState {
    /// No process, or not started yet.
    Idle = 0,
    /// Running Lua: the heartbeat must advance.
    Running = 1,
    /// Blocked in `Sleep`, `Till` or `DELAY` until its wake cycle.
    Waiting = 2,
    /// Blocked on a reply from the core.
    InCall = 3,
    /// The program has ended (normally or with an error).
    Finished = 4,
}

impl RunState {
    fn from_u32(v: u32) -> Self {
        match v {
            1 => RunState::Running,
            2 => RunState::Waiting,
            3 => RunState::InCall,
            4 => RunState::Finished,
            _ => RunState::Idle,
        }
    }
}

/// A request to be woken at a cycle. Each wait has a new sequence number, so that the
/// core notifies every wait exactly once.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WaitRequest {
    pub seq: u16,
    pub cycle: u64,
}

const CYCLE_BITS: u32 = 48;
const CYCLE_MASK: u64 = (1 << CYCLE_BITS) - 1;

impl WaitRequest {
    fn pack(self) -> u64 {
        (self.seq as u64) << CYCLE_BITS | (self.cycle & CYCLE_MASK)
    }

    fn unpack(v: u64) -> Self {
        WaitRequest { seq: (v >> CYCLE_BITS) as u16, cycle: v & CYCLE_MASK }
    }
}

/// One task's slot.
#[repr(C)]
pub struct TaskSlot {
    heartbeat: AtomicU64,
    wait: AtomicU64,
    state: AtomicU32,
    line: AtomicU32,
    pid: AtomicU32,
}

impl TaskSlot {
    pub fn heartbeat(&self) -> u64 {
        self.heartbeat.load(Ordering::Relaxed)
    }

    pub fn beat(&self) {
        self.heartbeat.fetch_add(1, Ordering::Relaxed);
    }

    pub fn state(&self) -> RunState {
        RunState::from_u32(self.state.load(Ordering::Acquire))
    }

    pub fn set_state(&self, state: RunState) {
        self.state.store(state as u32, Ordering::Release);
    }

    /// Publishes a wait request, then marks the task waiting.
    pub fn begin_wait(&self, request: WaitRequest) {
        self.wait.store(request.pack(), Ordering::Release);
        self.set_state(RunState::Waiting);
    }

    pub fn wait_request(&self) -> WaitRequest {
        WaitRequest::unpack(self.wait.load(Ordering::Acquire))
    }

    /// The Lua line being run (main chunk or any function), for debugging and the watchdog report.
    pub fn line(&self) -> u32 {
        self.line.load(Ordering::Relaxed)
    }

    pub fn set_line(&self, line: u32) {
        self.line.store(line, Ordering::Relaxed);
    }

    pub fn pid(&self) -> u32 {
        self.pid.load(Ordering::Relaxed)
    }

    pub fn set_pid(&self, pid: u32) {
        self.pid.store(pid, Ordering::Relaxed);
    }

    /// Back to the state of a task that never ran; the supervisor does this before a start.
    /// The wait sequence is kept: a restarted script continues it, so that the core never
    /// mistakes a new wait for one it has already woken.
    pub fn reset(&self) {
        self.heartbeat.store(0, Ordering::Relaxed);
        self.line.store(0, Ordering::Relaxed);
        self.pid.store(0, Ordering::Relaxed);
        self.set_state(RunState::Idle);
    }
}

/// All 64 slots.
#[repr(C)]
pub struct TaskTable {
    pub slots: [TaskSlot; MAX_TASKS],
}

// SAFETY: repr(C), only atomics, valid when zeroed (Idle, no heartbeat).
unsafe impl Shareable for TaskTable {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wait_request_round_trips_through_one_word() {
        let w = WaitRequest { seq: 0xBEEF, cycle: 123_456_789_012 };
        assert_eq!(WaitRequest::unpack(w.pack()), w);
    }
}

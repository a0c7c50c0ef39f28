//! A task's watchdog (docs/decisions.md, "Watchdog"): a task is hung when it
//! runs Lua without reaching the controller for longer than its watchdog time. The
//! heartbeat advances with every API call and every change of run state, so an endless
//! loop, a hang inside a C function and a stopped process all leave it standing, while
//! a task waiting on the controller (Sleep, Till, a deferred call) or on another task (a
//! mutex) is never counted as hung.

use ipc::task_table::{RunState, TaskSlot};

#[derive(Clone, Copy, Debug, Default)]
pub struct Watchdog {
    limit_cycles: u64,
    /// How long a process that reported its end may take to be gone.
    exit_cycles: u64,
    last_beat: u64,
    last_progress: u64,
}

impl Watchdog {
    /// `limit_cycles`: the task's watchdog time; a finished program's process gets at least
    /// `exit_cycles` to end (its teardown is not the program's code).
    pub fn new(limit_cycles: u64, exit_cycles: u64) -> Self {
        Watchdog { limit_cycles, exit_cycles: exit_cycles.max(limit_cycles), ..Watchdog::default() }
    }

    /// Starts watching from `now`.
    pub fn arm(&mut self, now: u64, slot: &TaskSlot) {
        self.last_beat = slot.heartbeat();
        self.last_progress = now;
    }

    /// One cycle; true once the task has made no progress for the watchdog time. `deferred`: the core holds a call of this
    /// task that answers later (MoveHome, StartTask).
    pub fn hung(&mut self, now: u64, slot: &TaskSlot, deferred: bool) -> bool {
        let beat = slot.heartbeat();
        let waiting_on_others = match slot.state() {
            RunState::Running => false,
            // Woken at the end of its wake cycle: from then on it must move.
            // A watched `Till` condition waits for the controller's state to change.
            RunState::Waiting => slot.wait_request().cycle >= now || slot.watching(),
            RunState::InCall => deferred,
            RunState::Blocked | RunState::Paused | RunState::Idle => true,
            // The process must now end: one stuck after its program is a hung task too.
            RunState::Finished => false,
        };
        if beat != self.last_beat || waiting_on_others {
            self.last_beat = beat;
            self.last_progress = now;
            return false;
        }
        let limit = if slot.state() == RunState::Finished { self.exit_cycles } else { self.limit_cycles };
        now - self.last_progress >= limit
    }

    /// Cycles since the task last made progress.
    pub fn stalled_for(&self, now: u64) -> u64 {
        now.saturating_sub(self.last_progress)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ipc::task_table::{TaskTable, WaitRequest};

    fn table() -> Box<TaskTable> {
        schema::layout::zeroed()
    }

    /// The first cycle in `from..to` the watchdog, asked every cycle, calls the task hung.
    fn first_hung(w: &mut Watchdog, slot: &TaskSlot, from: u64, to: u64, deferred: bool) -> Option<u64> {
        (from..to).find(|&now| w.hung(now, slot, deferred))
    }

    /// One row per situation the watchdog must tell apart.
    #[test]
    fn what_counts_as_hung() {
        let t = table();
        let slot = &t.slots[0];
        let limit = 10;
        const EXIT: u64 = 50;

        // Running Lua without an API call: hung once the limit has passed.
        slot.set_state(RunState::Running);
        let mut w = Watchdog::new(limit, EXIT);
        w.arm(100, slot);
        assert_eq!(first_hung(&mut w, slot, 101, 200, false), Some(110));

        // Calling the API (queries included) keeps it alive.
        let mut w = Watchdog::new(limit, EXIT);
        w.arm(100, slot);
        for now in 101..200 {
            slot.beat();
            assert!(!w.hung(now, slot, false));
        }

        // Asleep until cycle 500 is waiting on the controller; woken and not moving is not.
        slot.begin_wait(WaitRequest { seq: 1, cycle: 500 });
        let mut w = Watchdog::new(limit, EXIT);
        w.arm(200, slot);
        assert_eq!(first_hung(&mut w, slot, 201, 1000, false), Some(510));

        // A call the core holds (MoveHome) may take as long as it takes; an answered one may not.
        slot.set_state(RunState::InCall);
        let mut w = Watchdog::new(limit, EXIT);
        w.arm(600, slot);
        assert_eq!(first_hung(&mut w, slot, 601, 700, true), None, "deferred");
        assert_eq!(first_hung(&mut w, slot, 700, 800, false), Some(709), "answered at 700, never picked up");

        // Blocked on a mutex: the owner's watchdog answers for it.
        slot.set_state(RunState::Blocked);
        let mut w = Watchdog::new(limit, EXIT);
        w.arm(800, slot);
        assert_eq!(first_hung(&mut w, slot, 801, 5000, false), None);

        // The program has ended, but its process does not go (a finalizer, a teardown that
        // hangs): hung once the exit time has passed, which is never shorter than the limit.
        slot.set_state(RunState::Finished);
        let mut w = Watchdog::new(limit, EXIT);
        w.arm(5000, slot);
        assert_eq!(first_hung(&mut w, slot, 5001, 6000, false), Some(5050));
        let mut w = Watchdog::new(100, EXIT);
        w.arm(5000, slot);
        assert_eq!(first_hung(&mut w, slot, 5001, 6000, false), Some(5100));
    }
}

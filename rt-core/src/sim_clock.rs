//! The simulation clock (`luamotion run --clock sim [--speed N|max]`, docs/decisions.md,
//! "Simulation clock"): the core runs cycle k+1 only once every task in lockstep is
//! quiescent, and the tasks run Lua one at a time, in task order, in turns the core
//! grants between two cycles. So a run is a function of the machine file, the programs
//! and the inputs, and its trace is the same run after run.
//!
//! A task is quiescent when it has given its turn back (`Baton::Parked`) and what it
//! waits for has not come: its wake cycle (Sleep, Till, DELAY, TON/TOF polling, its
//! share of the cycle used), the reply to its call, a mutex another task holds; or when
//! it is paused by its debugger, has ended, or its process is gone. A task that holds
//! the turn without an API call for its watchdog time (of its process' CPU time: a
//! process the OS has not run meanwhile has not hung, and letting it go would make the run
//! depend on the machine's load) is let go: the clock goes on without it, and the
//! watchdog, which counts cycles, catches it.
//!
//! Between two cycles the RT thread waits for the tasks on the task table's gate word
//! (a futex the parking task bumps). It watches the word for a few tens of microseconds
//! first, which catches a quick handover without a wake-up, and then sleeps: two cores
//! are shared by the core, the tasks and whatever else runs, and a longer spin would take
//! the CPU the task it waits for needs. Real-time mode never comes here.

use std::str::FromStr;

use calls::watch;
use config::TaskConfig;
use ipc::CoreEndpoint;
use ipc::clock::monotonic_ns;
use ipc::task_table::{Baton, RunState, TaskSlot, TaskTable};
use schema::shared::SharedData;
use schema::{Snapshot, TaskState};

use crate::machine::Machine;
use crate::replay::Feed;
use crate::tasks::Tasks;

/// How long the core waits for a starting process to reach its first line before it
/// lets the clock go on (the start timeout, counted in cycles, then applies).
const START_PATIENCE_NS: u64 = 5_000_000_000;
/// How long an ended program's process may take to be gone.
const EXIT_PATIENCE_NS: u64 = 1_000_000_000;
/// Wall time a process that uses no CPU (stopped, or not scheduled at all) may hold the
/// turn without an API call: the clock must not wait for ever.
const WALL_PATIENCE_NS: u64 = 60_000_000_000;
/// How long the gate sleeps before it looks again at tasks that cannot wake it (a
/// process that died, a program paused by its debugger).
const GATE_SLICE: std::time::Duration = std::time::Duration::from_millis(2);

/// How the cycles are paced.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Clock {
    /// One cycle per period on the wall clock (the default).
    #[default]
    RealTime,
    /// Cycles in lockstep with the programs, at most `speed` times real time.
    Sim {
        /// How fast the cycles may go.
        speed: Speed,
    },
}

/// How fast the simulation clock may go.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Speed {
    /// At most this many times real time.
    Times(f64),
    /// As fast as the programs allow: no sleep between cycles.
    Max,
}

/// A `--speed` that is neither a number above 0 nor `max`; the text given.
#[derive(Debug, thiserror::Error)]
#[error("speed must be a number > 0 or `max`, not `{0}`")]
pub struct SpeedError(String);

impl FromStr for Speed {
    type Err = SpeedError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s == "max" {
            return Ok(Speed::Max);
        }
        match s.parse::<f64>() {
            Ok(n) if n > 0.0 && n.is_finite() => Ok(Speed::Times(n)),
            _ => Err(SpeedError(s.to_string())),
        }
    }
}

impl Speed {
    /// The wall time between two cycles' deadlines, ns; `None` for no sleep.
    pub fn pace_ns(self, period_ns: u64) -> Option<u64> {
        match self {
            Speed::Times(n) => Some(((period_ns as f64 / n) as u64).max(1)),
            Speed::Max => None,
        }
    }
}

/// One task in lockstep.
struct Member {
    id: u8,
    /// CPU time the task's process may use holding the turn without an API call, ns.
    patience_ns: u64,
    /// Let go after holding the turn too long; back in lockstep once it parks.
    released: bool,
}

/// The tasks in lockstep with the simulation clock, and the gate between two cycles.
pub struct Lockstep {
    members: Vec<Member>,
    speed: Speed,
    /// The outside inputs, applied at the start of their cycle (`replay`).
    feed: Option<Feed>,
}

impl Lockstep {
    /// Puts the machine file's programs in lockstep (the external slots, which the
    /// controller's own threads hold, are not). Before any task starts.
    pub fn new(configs: &[TaskConfig], speed: Speed, endpoint: &CoreEndpoint) -> Self {
        let mut members = Vec::new();
        for config in configs {
            endpoint.table().slots[config.id as usize].set_lockstep(!config.external);
            if !config.external {
                let patience_ns = config.watchdog_ms as u64 * 1_000_000;
                members.push(Member { id: config.id, patience_ns, released: false });
            }
        }
        members.sort_by_key(|m| m.id);
        Lockstep { members, speed, feed: None }
    }

    /// Feeds the outside inputs (the register console's Modbus writes, a replay's).
    pub fn with_feed(mut self, feed: Option<Feed>) -> Self {
        self.feed = feed;
        self
    }

    /// Before cycle `cycle`, with no task's turn in progress: its outside inputs.
    pub fn begin(&mut self, cycle: u64, machine: &mut Machine, shared: &SharedData) {
        if let Some(feed) = &mut self.feed {
            feed.begin(cycle, shared, |input| crate::dispatch::simulate(machine, input));
        }
    }

    pub(crate) fn speed(&self) -> Speed {
        self.speed
    }

    /// Every program has ended (or was never started): the run's record is complete.
    pub fn all_ended(&self, tasks: &Tasks, endpoint: &CoreEndpoint) -> bool {
        self.members.iter().all(|m| {
            let slot = &endpoint.table().slots[m.id as usize];
            !active(tasks.state(m.id)) || slot.state() == RunState::Finished
        })
    }

    /// Between cycle `cycle` and the next: grants turns, in task order and pass after
    /// pass, to every task whose wait has come (`woken`: the tasks the cycle answered),
    /// until none is left. `watches_changed`: the tasks whose watched condition read
    /// something else in this cycle. `stop`: the controller is shutting down, wait for
    /// nobody.
    pub fn settle(
        &mut self,
        cycle: u64,
        mut woken: u64,
        watches_changed: u64,
        tasks: &Tasks,
        endpoint: &CoreEndpoint,
        stop: &dyn Fn() -> bool,
    ) {
        loop {
            let mut granted = false;
            for member in &mut self.members {
                let slot = &endpoint.table().slots[member.id as usize];
                if !wait_parked(member, slot, tasks, endpoint, stop)
                    || !runnable(slot, member.id, cycle, woken, watches_changed, endpoint)
                {
                    continue;
                }
                woken &= !(1 << member.id);
                endpoint.table().grant(member.id as usize, monotonic_ns());
                granted = true;
                wait_parked(member, slot, tasks, endpoint, stop);
            }
            if !granted {
                return;
            }
        }
    }
}

/// The tasks whose watched `Till` condition (calls::watch) would read something else in
/// `snapshot`, the cycle's, as the task reads it; bit t for task t. Before the snapshot is
/// published: a condition parks with a wake cycle after the one it read, so every watch
/// the settling of this cycle may look at is already set.
pub fn changed_watches(table: &TaskTable, snapshot: &Snapshot) -> u64 {
    let mut changed = 0;
    for (id, slot) in table.slots.iter().enumerate() {
        if slot.watching() && !slot.watch().all(|e| watch::unchanged(&e, snapshot)) {
            changed |= 1 << id;
        }
    }
    changed
}

fn active(state: TaskState) -> bool {
    matches!(state, TaskState::Starting | TaskState::Running)
}

/// Whether a parked task's wait has come.
fn runnable(slot: &TaskSlot, id: u8, cycle: u64, woken: u64, watches_changed: u64, endpoint: &CoreEndpoint) -> bool {
    match slot.state() {
        // A watched `Till` condition is evaluated again once one of its queries answers
        // something else (calls::watch).
        RunState::Waiting => slot.wait_request().cycle <= cycle && (!slot.watching() || watches_changed & 1 << id != 0),
        RunState::InCall => woken & (1 << id) != 0,
        RunState::Blocked => slot.blocked_on().is_none_or(|m| endpoint.shared().mutex_owner(m).is_none()),
        // Parked before its first line.
        RunState::Running => true,
        RunState::Idle | RunState::Finished | RunState::Paused => false,
    }
}

/// Waits until the task has parked; false when it is quiescent otherwise (paused, its
/// process gone, not starting or running) or let go.
fn wait_parked(
    member: &mut Member,
    slot: &TaskSlot,
    tasks: &Tasks,
    endpoint: &CoreEndpoint,
    stop: &dyn Fn() -> bool,
) -> bool {
    let table = endpoint.table();
    let mut beat = slot.heartbeat();
    let (mut since, mut cpu_since) = (monotonic_ns(), process_cpu_ns(slot.pid()));
    loop {
        let seen = table.gate_count();
        let state = tasks.state(member.id);
        if !active(state) || slot.state() == RunState::Paused {
            return false;
        }
        // An ended program's process is waited for until it is gone: its end would
        // otherwise reach the core after a number of cycles that depends on wall time.
        if slot.state() == RunState::Finished {
            if !process_alive(slot.pid()) {
                return false;
            }
        } else if slot.baton() == Baton::Parked {
            member.released = false;
            return true;
        }
        if member.released || stop() || !process_alive(slot.pid()) {
            return false;
        }
        let now = monotonic_ns();
        let patience = match (state, slot.state()) {
            (TaskState::Starting, _) => member.patience_ns.max(START_PATIENCE_NS),
            // As the watchdog gives an ended process (docs/decisions.md, "Watchdog").
            (_, RunState::Finished) => member.patience_ns.max(EXIT_PATIENCE_NS),
            _ => member.patience_ns,
        };
        let cpu = process_cpu_ns(slot.pid());
        if slot.heartbeat() != beat {
            (beat, since, cpu_since) = (slot.heartbeat(), now, cpu);
        } else if held_too_long(state, slot.state(), now - since, cpu.saturating_sub(cpu_since), patience) {
            member.released = true;
            return false;
        }
        table.gate_sleep(seen, GATE_SLICE);
    }
}

/// Whether a task that made no API call for `wall_ns` (its process using `cpu_ns`) has
/// held the turn too long. A starting or ending process is given wall time, as before its
/// first line and after its last its CPU time says little.
fn held_too_long(state: TaskState, run: RunState, wall_ns: u64, cpu_ns: u64, patience: u64) -> bool {
    match (state, run) {
        (TaskState::Starting, _) | (_, RunState::Finished) => wall_ns > patience,
        _ => cpu_ns > patience || wall_ns > patience.max(WALL_PATIENCE_NS),
    }
}

/// The CPU time process `pid` has used, ns; 0 when it cannot be read (not registered yet,
/// gone).
fn process_cpu_ns(pid: u32) -> u64 {
    let mut clock: libc::clockid_t = 0;
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: both out-pointers are valid for the calls.
    let read = pid != 0
        && unsafe { libc::clock_getcpuclockid(pid as libc::pid_t, &mut clock) } == 0
        && unsafe { libc::clock_gettime(clock, &mut ts) } == 0;
    if read { ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64 } else { 0 }
}

/// A process that has not registered yet (pid 0) counts as alive: it is starting.
fn process_alive(pid: u32) -> bool {
    pid == 0 || ipc::process_alive(pid)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_running_task_is_let_go_on_its_cpu_time_a_starting_or_ending_one_on_wall_time() {
        const MS: u64 = 1_000_000;
        let (running, starting) = (TaskState::Running, TaskState::Starting);
        // (task state, run state, wall ns, CPU ns, patience ns, let go)
        let rows = [
            (running, RunState::Running, 5_000 * MS, 10 * MS, 500 * MS, false),
            (running, RunState::Running, 600 * MS, 501 * MS, 500 * MS, true),
            (running, RunState::InCall, 61_000 * MS, 0, 500 * MS, true),
            (starting, RunState::Idle, 5_001 * MS, 0, 5_000 * MS, true),
            (starting, RunState::Idle, 4_000 * MS, 4_500 * MS, 5_000 * MS, false),
            (running, RunState::Finished, 1_001 * MS, 0, 1_000 * MS, true),
        ];
        for (state, run, wall, cpu, patience, let_go) in rows {
            assert_eq!(held_too_long(state, run, wall, cpu, patience), let_go, "{state:?} {run:?} {wall} {cpu}");
        }
    }

    #[test]
    fn process_cpu_time_is_read_for_this_process_and_0_for_none() {
        assert!(process_cpu_ns(std::process::id()) > 0);
        assert_eq!(process_cpu_ns(0), 0);
    }

    #[test]
    fn speeds_parse() {
        assert_eq!("max".parse::<Speed>().unwrap(), Speed::Max);
        assert_eq!("10".parse::<Speed>().unwrap(), Speed::Times(10.0));
        assert_eq!("0.5".parse::<Speed>().unwrap(), Speed::Times(0.5));
        for bad in ["0", "-1", "inf", "NaN", "fast"] {
            assert!(bad.parse::<Speed>().is_err(), "{bad}");
        }
        assert_eq!(Speed::Times(10.0).pace_ns(1_000_000), Some(100_000));
        assert_eq!(Speed::Max.pace_ns(1_000_000), None);
    }
}

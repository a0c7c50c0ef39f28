//! The task table in shared memory: what each script process is doing, written by the
//! script, read by the core every cycle; and what the controller tells the tools about
//! each task (its program, the CPU its process used). Plain atomics, so that a binding
//! can bump the heartbeat at the cost of one store.

use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};

use num_enum::{FromPrimitive, IntoPrimitive};
use schema::MAX_TASKS;
use schema::debug::DebugBlock;
use schema::layout::Shareable;

use crate::futex;
use crate::mailbox::Calls;
use crate::pool::Board;

/// What a task's script is doing. An unknown word reads as `Idle`: a slot no script
/// has written yet is zero, and a torn or foreign value must not look alive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, FromPrimitive, IntoPrimitive)]
#[repr(u32)]
pub enum RunState {
    /// No process, or not started yet.
    #[num_enum(default)]
    Idle = 0,
    /// Running Lua: the heartbeat must advance.
    Running = 1,
    /// Blocked in `Sleep`, `Till` or `DELAY` until its wake cycle.
    Waiting = 2,
    /// Blocked on a reply from the core.
    InCall = 3,
    /// The program has ended (normally or with an error).
    Finished = 4,
    /// Blocked on another task (`MutexLock`): that task's watchdog answers for the wait.
    Blocked = 5,
    /// Stopped by its debugger (a breakpoint, Pause, a step): the console holds it.
    Paused = 6,
}

/// A request to be woken at a cycle. Each wait has a new sequence number, so that the
/// core notifies every wait exactly once.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WaitRequest {
    /// The wait's sequence number.
    pub seq: u16,
    /// The cycle to be woken at.
    pub cycle: u64,
}

/// How long the core and a task watch for the turn before they sleep on the simulation
/// clock: a few times the handover itself, short beside the wake-up it saves.
const TURN_SPIN: std::time::Duration = std::time::Duration::from_micros(30);

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

/// Bytes of a program path the tools can show.
pub const PROGRAM_BYTES: usize = 256;

/// Queries a `Till` condition may read and still be watched by the core.
pub const WATCH_ENTRIES: usize = 8;
/// Argument words of a watched query.
pub const WATCH_ARGS: usize = 4;
/// Words of a watched query's answer.
pub const ANSWER_WORDS: usize = 3;
const ENTRY_WORDS: usize = 1 + WATCH_ARGS + ANSWER_WORDS;

/// On the simulation clock, a status query a waiting `Till` condition made and what it
/// answered (`calls::watch` encodes both): while every query of the condition still gives
/// its answer, the condition would give its value again, and the core need not grant the
/// task a turn to find out (docs/decisions.md, "Simulation clock").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WatchEntry {
    /// `api::Query::id()`.
    pub query: u16,
    /// Argument words used.
    pub argc: u8,
    /// The argument words, as `calls::wire` lays out a command's.
    pub args: [u64; WATCH_ARGS],
    /// The answer's words.
    pub answer: [u64; ANSWER_WORDS],
}

impl WatchEntry {
    fn words(&self) -> [u64; ENTRY_WORDS] {
        let mut w = [0; ENTRY_WORDS];
        w[0] = self.query as u64 | (self.argc as u64) << 16;
        w[1..1 + WATCH_ARGS].copy_from_slice(&self.args);
        w[1 + WATCH_ARGS..].copy_from_slice(&self.answer);
        w
    }

    fn from_words(w: [u64; ENTRY_WORDS]) -> Self {
        let mut entry = WatchEntry { query: w[0] as u16, argc: (w[0] >> 16) as u8, ..WatchEntry::default() };
        entry.args.copy_from_slice(&w[1..1 + WATCH_ARGS]);
        entry.answer.copy_from_slice(&w[1 + WATCH_ARGS..]);
        entry
    }
}

/// One task's slot.
#[repr(C)]
pub struct TaskSlot {
    /// Advanced by every API call and every change of run state: a task whose heartbeat
    /// stands still while it runs Lua is stuck in a loop or in a C function.
    heartbeat: AtomicU64,
    wait: AtomicU64,
    state: AtomicU32,
    line: AtomicU32,
    pid: AtomicU32,
    /// Set by the script once its entry point is found and about to run.
    started: AtomicU32,
    /// Why the program ended, when it failed: an HMPL code (e.g. 0x13EC) or an `EndCode`.
    end_code: AtomicU32,
    /// CPU time of the task's process (user + system), ms; written by the supervisor.
    cpu_ms: AtomicU64,
    /// When the core last woke the task (CLOCK_MONOTONIC, ns).
    notified_ns: AtomicU64,
    /// The task's wake-up count; the core bumps it to wake the task, which sleeps on a
    /// bell of the table while it stands still (`TaskTable::sleep`).
    wake: AtomicU32,
    /// The task's thread asleep, or about to be: a wake with none makes no futex syscall.
    sleepers: AtomicU32,
    /// The CPU the task last went to sleep on, plus one (0: not known): its wake goes to
    /// that CPU's task waker, and it sleeps on that CPU's bell.
    sleep_cpu: AtomicU32,
    /// On the simulation clock: nonzero when this task runs in lockstep with the core
    /// (written by the core before any start, never reset).
    lockstep: AtomicU32,
    /// On the simulation clock: whose turn it is (`Baton`).
    baton: AtomicU32,
    /// The mutex a `Blocked` task waits for, plus one (0: none).
    blocked_on: AtomicU32,
    /// On the simulation clock: how many of `watch` a `Waiting` task's condition made.
    watch_len: AtomicU32,
    watch: [[AtomicU64; ENTRY_WORDS]; WATCH_ENTRIES],
    program: [AtomicU64; PROGRAM_BYTES / 8],
    /// The debugger's words (DRL program control).
    pub debug: DebugBlock,
}

/// The simulation clock's turn word of a task in lockstep (docs/decisions.md, "Simulation
/// clock"): one task runs Lua at a time, and only with the turn the core granted it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, FromPrimitive, IntoPrimitive)]
#[repr(u32)]
pub enum Baton {
    /// The task holds the turn, or its process is starting: the core waits for it.
    #[num_enum(default)]
    Held = 0,
    /// The task gave its turn back and waits for the next one.
    Parked = 1,
    /// The core granted the task a turn it has not taken yet.
    Granted = 2,
}

/// Why a program ended, beyond HMPL's own codes. Written only: the end-code word also
/// carries HMPL codes, so readers compare it with these values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, IntoPrimitive)]
#[repr(u32)]
pub enum EndCode {
    /// A Lua error (syntax or runtime).
    LuaError = 1,
    /// The task's memory limit.
    OutOfMemory = 2,
}

impl TaskSlot {
    /// The heartbeat: the watchdog sees a task alive while it moves.
    pub fn heartbeat(&self) -> u64 {
        self.heartbeat.load(Ordering::Relaxed)
    }

    /// Advances the heartbeat (one atomic add).
    pub fn beat(&self) {
        self.heartbeat.fetch_add(1, Ordering::Relaxed);
    }

    /// What the script is doing.
    pub fn state(&self) -> RunState {
        RunState::from(self.state.load(Ordering::Acquire))
    }

    /// A new run state; the heartbeat advances with it.
    pub fn set_state(&self, state: RunState) {
        self.beat();
        self.state.store(state.into(), Ordering::Release);
    }

    /// Publishes a wait request, then marks the task waiting.
    pub fn begin_wait(&self, request: WaitRequest) {
        self.wait.store(request.pack(), Ordering::Release);
        self.set_state(RunState::Waiting);
    }

    /// The current wait request.
    pub fn wait_request(&self) -> WaitRequest {
        WaitRequest::unpack(self.wait.load(Ordering::Acquire))
    }

    /// The Lua line being run (main chunk or any function), for debugging and the watchdog report.
    pub fn line(&self) -> u32 {
        self.line.load(Ordering::Relaxed)
    }

    /// Records the line the program is at.
    pub fn set_line(&self, line: u32) {
        self.line.store(line, Ordering::Relaxed);
    }

    /// The script process' pid; 0 for none.
    pub fn pid(&self) -> u32 {
        self.pid.load(Ordering::Relaxed)
    }

    /// Records the script process' pid.
    pub fn set_pid(&self, pid: u32) {
        self.pid.store(pid, Ordering::Relaxed);
    }

    /// The script reported that it started.
    pub fn started(&self) -> bool {
        self.started.load(Ordering::Acquire) != 0
    }

    /// The script found its entry point and runs it (`StartTask` returns).
    pub fn mark_started(&self) {
        self.started.store(1, Ordering::Release);
    }

    /// Why the program failed: an HMPL code or an `EndCode`; 0 when it did not.
    pub fn end_code(&self) -> u32 {
        self.end_code.load(Ordering::Acquire)
    }

    /// Records how the program ended.
    pub fn set_end_code(&self, code: u32) {
        self.end_code.store(code, Ordering::Release);
    }

    /// CPU time the task's process used, ms.
    pub fn cpu_ms(&self) -> u64 {
        self.cpu_ms.load(Ordering::Relaxed)
    }

    /// Records the CPU time of the task's process (the supervisor).
    pub fn set_cpu_ms(&self, ms: u64) {
        self.cpu_ms.store(ms, Ordering::Relaxed);
    }

    /// When the core last woke this task (CLOCK_MONOTONIC, ns).
    pub fn notified_ns(&self) -> u64 {
        self.notified_ns.load(Ordering::Acquire)
    }

    /// The first half of a wake (`TaskTable::wake`): a task that looks at its count from
    /// now on does not sleep; one asleep already needs `TaskTable::wake_sleepers`.
    pub fn notify(&self, now_ns: u64) {
        self.notified_ns.store(now_ns, Ordering::Release);
        self.wake.fetch_add(1, Ordering::SeqCst);
    }

    /// Whether the task's thread sleeps, or is about to.
    #[cfg(test)]
    pub(crate) fn asleep(&self) -> bool {
        self.sleepers.load(Ordering::SeqCst) != 0
    }

    /// The CPU the task last went to sleep on, if known.
    pub fn sleep_cpu(&self) -> Option<usize> {
        (self.sleep_cpu.load(Ordering::Relaxed) as usize).checked_sub(1)
    }

    /// The wake-up count before a look at the condition the task waits for (then
    /// `TaskTable::sleep`).
    pub fn wake_count(&self) -> u32 {
        self.wake.load(Ordering::Acquire)
    }

    /// Whether this task runs in lockstep with the simulation clock.
    pub fn lockstep(&self) -> bool {
        self.lockstep.load(Ordering::Acquire) != 0
    }

    /// Puts the task in lockstep with the simulation clock (the core, before any start).
    pub fn set_lockstep(&self, on: bool) {
        self.lockstep.store(on as u32, Ordering::Release);
    }

    /// Who has the turn.
    pub fn baton(&self) -> Baton {
        Baton::from(self.baton.load(Ordering::Acquire))
    }

    /// The task gives its turn back (its caller wakes the core through the table's gate).
    pub fn park(&self) {
        self.baton.store(Baton::Parked.into(), Ordering::Release);
    }

    /// The core grants a parked task a turn (then wakes it: `TaskTable::grant`).
    fn grant(&self) {
        self.baton.store(Baton::Granted.into(), Ordering::Release);
    }

    /// The task takes a granted turn; false when none was granted.
    pub fn take_turn(&self) -> bool {
        self.baton
            .compare_exchange(Baton::Granted.into(), Baton::Held.into(), Ordering::AcqRel, Ordering::Acquire)
            .is_ok()
    }

    /// The mutex a `Blocked` task waits for.
    pub fn blocked_on(&self) -> Option<usize> {
        (self.blocked_on.load(Ordering::Acquire) as usize).checked_sub(1)
    }

    /// Publishes what the task's `Till` condition read, before it parks (at most
    /// `WATCH_ENTRIES`; an empty watch is none).
    pub fn set_watch(&self, entries: &[WatchEntry]) {
        let entries = &entries[..entries.len().min(WATCH_ENTRIES)];
        for (slot, entry) in self.watch.iter().zip(entries) {
            for (word, value) in slot.iter().zip(entry.words()) {
                word.store(value, Ordering::Relaxed);
            }
        }
        self.watch_len.store(entries.len() as u32, Ordering::Release);
    }

    /// The task has taken its turn: its condition is no longer watched.
    pub fn clear_watch(&self) {
        self.watch_len.store(0, Ordering::Release);
    }

    /// What the parked task's condition read; empty when it is not watched.
    pub fn watch(&self) -> impl Iterator<Item = WatchEntry> + '_ {
        let len = (self.watch_len.load(Ordering::Acquire) as usize).min(WATCH_ENTRIES);
        self.watch[..len]
            .iter()
            .map(|slot| WatchEntry::from_words(std::array::from_fn(|i| slot[i].load(Ordering::Relaxed))))
    }

    /// Whether a `Waiting` task's condition is watched.
    pub fn watching(&self) -> bool {
        self.watch_len.load(Ordering::Acquire) != 0
    }

    /// Records the mutex the task is about to block on.
    pub fn set_blocked_on(&self, mutex: usize) {
        self.blocked_on.store(mutex as u32 + 1, Ordering::Release);
    }

    /// The program path, as the controller wrote it (truncated to `PROGRAM_BYTES`).
    pub fn program(&self) -> String {
        let bytes: Vec<u8> = self.program.iter().flat_map(|w| w.load(Ordering::Relaxed).to_le_bytes()).collect();
        let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
        String::from_utf8_lossy(&bytes[..end]).into_owned()
    }

    /// Records the program path the tools show.
    pub fn set_program(&self, path: &str) {
        let mut bytes = [0u8; PROGRAM_BYTES];
        let mut n = path.len().min(PROGRAM_BYTES - 1);
        while !path.is_char_boundary(n) {
            n -= 1;
        }
        bytes[..n].copy_from_slice(&path.as_bytes()[..n]);
        for (word, chunk) in self.program.iter().zip(bytes.chunks(8)) {
            word.store(u64::from_le_bytes(chunk.try_into().expect("8 bytes")), Ordering::Relaxed);
        }
    }

    /// Back to the state of a task that never ran; the supervisor does this before a start.
    /// The wait sequence is kept: a restarted script continues it, so that the core never
    /// mistakes a new wait for one it has already woken.
    pub fn reset(&self) {
        self.heartbeat.store(0, Ordering::Relaxed);
        self.line.store(0, Ordering::Relaxed);
        self.pid.store(0, Ordering::Relaxed);
        self.started.store(0, Ordering::Relaxed);
        self.end_code.store(0, Ordering::Relaxed);
        self.cpu_ms.store(0, Ordering::Relaxed);
        self.baton.store(Baton::Held.into(), Ordering::Release);
        self.state.store(RunState::Idle.into(), Ordering::Release);
    }
}

/// All 64 slots.
#[repr(C)]
pub struct TaskTable {
    /// One slot per HMPL task.
    pub slots: [TaskSlot; MAX_TASKS],
    /// On the simulation clock: bumped by a task that parks; the core sleeps on it.
    gate: AtomicU32,
    /// The futex words the tasks sleep on, one for each CPU (modulo `BELL_CPUS`) and
    /// each 32 tasks, each task with its bit: a waker wakes the due sleepers of one bell
    /// in one syscall (the syscall, the lookup of the shared word and the hash were a
    /// fifth of a task waker's time).
    bells: [Bell; BELLS],
    /// The script pool's waiting processes, handed their tasks by the core.
    pub pool: Board,
    /// Each task's calls to the core and their replies.
    pub calls: Calls,
}

impl TaskTable {
    /// The core wakes task `task`: "your reply is ready", "your wake cycle has come" or
    /// "your turn". Never blocks.
    pub fn wake(&self, task: usize, now_ns: u64) {
        self.slots[task].notify(now_ns);
        self.wake_sleepers(1 << task);
    }

    /// The core grants parked task `task` a turn on the simulation clock and wakes it.
    pub fn grant(&self, task: usize, now_ns: u64) {
        self.slots[task].grant();
        self.wake(task, now_ns);
    }

    /// The second half of a wake, for tasks `tasks` (bit t for task t) notified already:
    /// the futex wakes of those asleep, one syscall per bell they sleep on; returns how
    /// many were asleep.
    pub fn wake_sleepers(&self, mut tasks: u64) -> u64 {
        // Pairs with `sleep`'s count: either the sleeper sees its count bumped, or this
        // sees the sleeper and the bell it chose (also when `notify` ran on another thread
        // that handed the wake over).
        std::sync::atomic::fence(Ordering::SeqCst);
        let mut rung = [0u32; BELLS];
        let mut asleep = 0;
        while tasks != 0 {
            let task = tasks.trailing_zeros() as usize;
            tasks &= tasks - 1;
            let slot = &self.slots[task];
            if slot.sleepers.load(Ordering::SeqCst) != 0 {
                let (bell, bit) = bell_of(task, slot.sleep_cpu.load(Ordering::SeqCst));
                rung[bell] |= bit;
                asleep += 1;
            }
        }
        for (bell, bits) in self.bells.iter().zip(rung) {
            if bits != 0 {
                // A sleeper between its look at the bell and its futex call finds the bell
                // changed and returns.
                bell.0.fetch_add(1, Ordering::SeqCst);
                futex::wake_bits(&bell.0, bits);
            }
        }
        asleep
    }

    /// Task `task`'s thread sleeps, unless a wake-up came since it read `seen` from
    /// `wake_count`; at most `timeout`. One thread of a task sleeps at a time.
    pub fn sleep(&self, task: usize, seen: u32, timeout: std::time::Duration) {
        let slot = &self.slots[task];
        // SAFETY: no arguments; -1 (not known) is stored as 0.
        let cpu = (unsafe { libc::sched_getcpu() } + 1).max(0) as u32;
        slot.sleep_cpu.store(cpu, Ordering::SeqCst);
        let (bell, bit) = bell_of(task, cpu);
        let bell = &self.bells[bell].0;
        let rung = bell.load(Ordering::SeqCst);
        // Counted before the count is looked at: see `wake_sleepers`.
        slot.sleepers.fetch_add(1, Ordering::SeqCst);
        if slot.wake.load(Ordering::SeqCst) == seen {
            futex::wait_bit(bell, rung, bit, timeout);
        }
        slot.sleepers.fetch_sub(1, Ordering::SeqCst);
    }

    /// `sleep` for the next turn on the simulation clock, watching the count for
    /// `TURN_SPIN` first (uncounted: the core's wake meanwhile makes no syscall).
    pub fn sleep_for_turn(&self, task: usize, seen: u32, timeout: std::time::Duration) {
        if futex::spin_while(&self.slots[task].wake, seen, TURN_SPIN) {
            self.sleep(task, seen, timeout);
        }
    }

    /// Task `task` gives its turn back and wakes the core.
    pub fn park(&self, task: u8) {
        self.slots[task as usize].park();
        self.gate.fetch_add(1, Ordering::Release);
        futex::wake(&self.gate);
    }

    /// The gate's count before the core looks at the slots...
    pub fn gate_count(&self) -> u32 {
        self.gate.load(Ordering::Acquire)
    }

    /// ...then its sleep until a task parks, at most `timeout`, watching the gate for
    /// `TURN_SPIN` first.
    pub fn gate_sleep(&self, seen: u32, timeout: std::time::Duration) {
        futex::wait_spinning(&self.gate, seen, TURN_SPIN, timeout);
    }
}

/// Tasks that share a bell: a futex wake's bitset has 32 bits.
const TASKS_PER_BELL: usize = 32;
/// CPUs the bells tell apart; tasks asleep on CPUs equal modulo this share bells.
const BELL_CPUS: usize = 8;
const BELLS: usize = BELL_CPUS * MAX_TASKS / TASKS_PER_BELL;

/// A bell on a cache line of its own: the tasks of one CPU touch only theirs.
#[repr(C, align(64))]
struct Bell(AtomicU32);

/// The bell task `task` sleeps on after it noted `sleep_cpu` (a CPU plus one, as stored),
/// and its bit there.
fn bell_of(task: usize, sleep_cpu: u32) -> (usize, u32) {
    let cpu = sleep_cpu as usize % BELL_CPUS;
    (cpu * (MAX_TASKS / TASKS_PER_BELL) + task / TASKS_PER_BELL, 1 << (task % TASKS_PER_BELL))
}

// SAFETY: repr(C), only atomics, valid when zeroed (Idle, no heartbeat, no pooled process,
// empty mailboxes).
unsafe impl Shareable for TaskTable {}

#[cfg(test)]
mod tests {
    use super::*;

    /// The run state word each script writes; an unknown word reads as `Idle`.
    #[test]
    fn run_state_words() {
        let rows = [
            (RunState::Idle, 0u32),
            (RunState::Running, 1),
            (RunState::Waiting, 2),
            (RunState::InCall, 3),
            (RunState::Finished, 4),
            (RunState::Blocked, 5),
            (RunState::Paused, 6),
        ];
        for (state, word) in rows {
            assert_eq!(u32::from(state), word, "{state:?}");
            assert_eq!(RunState::from(word), state, "word {word}");
        }
        for word in [7, u32::MAX] {
            assert_eq!(RunState::from(word), RunState::Idle, "word {word}");
        }
    }

    #[test]
    fn a_program_path_round_trips_and_is_cut_at_a_character() {
        let table: Box<TaskTable> = schema::layout::zeroed();
        let slot = &table.slots[3];
        slot.set_program("/tmp/a b/main.lua");
        assert_eq!(slot.program(), "/tmp/a b/main.lua");
        let long = "é".repeat(200);
        slot.set_program(&long);
        assert_eq!(slot.program(), "é".repeat(127), "254 bytes: whole characters only");
    }

    /// A turn is taken once: granted, taken, parked, and nothing to take until the next grant.
    #[test]
    fn a_turn_goes_round_once() {
        let table: Box<TaskTable> = schema::layout::zeroed();
        let slot = &table.slots[5];
        assert_eq!(slot.baton(), Baton::Held, "a starting task holds the clock");
        assert!(!slot.take_turn());
        table.park(5);
        assert_eq!((slot.baton(), table.gate_count()), (Baton::Parked, 1));
        table.grant(5, 0);
        assert_eq!(slot.wake_count(), 1, "a grant wakes the task");
        assert!(slot.take_turn());
        assert!(!slot.take_turn(), "taken once");
        assert_eq!(slot.baton(), Baton::Held);
        slot.set_blocked_on(7);
        assert_eq!(slot.blocked_on(), Some(7));
    }

    /// A wake makes the futex syscall only for a task asleep, and the one it makes
    /// reaches the sleeper (within 5 s: they sleep for up to 20) and no other: task 3
    /// sleeps on the same bell (the sleepers share a CPU), task 34 on the same bit of the
    /// next bell.
    #[test]
    fn a_wake_makes_the_syscall_only_for_a_sleeper() {
        let table: Box<TaskTable> = schema::layout::zeroed();
        let table = &*table;
        table.slots[2].notify(0);
        assert_eq!(table.wake_sleepers(1 << 2), 0, "nobody asleep: no syscall");
        // SAFETY: no arguments.
        let cpu = unsafe { libc::sched_getcpu() }.max(0) as usize;
        std::thread::scope(|s| {
            let sleepers: Vec<_> = [2, 3, 34]
                .into_iter()
                .map(|task| {
                    let seen = table.slots[task].wake_count();
                    s.spawn(move || {
                        crate::process::pin_current_thread(cpu);
                        table.sleep(task, seen, std::time::Duration::from_secs(20))
                    })
                })
                .collect();
            while ![2, 3, 34].iter().all(|&t| table.slots[t].asleep()) {
                std::thread::yield_now();
            }
            let bells = [2, 3, 34].map(|t| bell_of(t, table.slots[t].sleep_cpu.load(Ordering::SeqCst)));
            assert_eq!(bells[0].0, bells[1].0, "tasks 2 and 3 share a bell");
            assert_eq!(bells[0].1, bells[2].1, "tasks 2 and 34 share a bit");
            table.slots[2].notify(0);
            assert_eq!(table.wake_sleepers(1 << 2), 1, "a sleeper: the syscall");
            assert!(eventually(|| sleepers[0].is_finished()), "task 2 woken");
            std::thread::sleep(std::time::Duration::from_millis(20));
            assert!(table.slots[3].asleep() && table.slots[34].asleep(), "tasks 3 and 34 sleep on");
            for task in [3, 34] {
                table.slots[task].notify(0);
            }
            assert_eq!(table.wake_sleepers(1 << 3 | 1 << 34), 2);
            assert!(eventually(|| sleepers.iter().all(|s| s.is_finished())), "tasks 3 and 34 woken");
            for sleeper in sleepers {
                sleeper.join().expect("the sleeper returns");
            }
        });
        assert!(!table.slots[2].asleep(), "the sleeper is counted out");
        assert_eq!(table.wake_sleepers(1 << 2), 0);
    }

    fn eventually(condition: impl Fn() -> bool) -> bool {
        let until = std::time::Instant::now() + std::time::Duration::from_secs(5);
        while !condition() {
            if std::time::Instant::now() > until {
                return false;
            }
            std::thread::yield_now();
        }
        true
    }

    #[test]
    fn wait_request_round_trips_through_one_word() {
        let w = WaitRequest { seq: 0xBEEF, cycle: 123_456_789_012 };
        assert_eq!(WaitRequest::unpack(w.pack()), w);
    }
}

//! The script pool's board in the task table: where a waiting script process (`luamotion
//! script --pool <place>`, started by `rt-core/src/pool.rs`) says it is ready, and where
//! the core's RT thread hands it a task in the cycle the task starts, with one futex wake
//! and no supervisor in between.
//!
//! A place goes Empty → Coming (the supervisor starts a process for it) → Ready (the
//! process, once its node, its view of the snapshot board and VM are made) → Claimed (whoever hands it a task, alone: a compare-and-swap) → Handed (the task is
//! written) → Empty (the process has read it). The supervisor withdraws a waiting process
//! that died or must end with a compare-and-swap too, so a process is never both handed a
//! task and withdrawn. A start that finds no process Ready while one is Coming waits for
//! it: it is ready sooner than a process started for the task then.

use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};
use std::time::Duration;

use num_enum::{FromPrimitive, IntoPrimitive};
use schema::layout::Shareable;

use crate::futex;
use crate::limits::MAX_POOL;

/// Node name of a pooled process before it has a task.
pub const POOL_NODE_NAME: &str = "luamotion-script-pool";

/// Places on the board: twice the largest pool, so that a place whose process was handed
/// a task but has not read it yet never holds up the process that replaces it.
pub const PLACES: usize = 2 * MAX_POOL;

/// Bytes of a `StartTaskFunc` entry name a place holds.
pub const ENTRY_BYTES: usize = 64;

/// Where a place is in its round. An unknown word reads as `Empty`: nobody waits there.
#[derive(Clone, Copy, Debug, PartialEq, Eq, FromPrimitive, IntoPrimitive)]
#[repr(u32)]
pub enum PlaceState {
    /// No process waits here.
    #[num_enum(default)]
    Empty = 0,
    /// A started process waits for a task.
    Ready = 1,
    /// A task is being written into the place.
    Claimed = 2,
    /// A task is written; the process takes it.
    Handed = 3,
    /// The controller ends: the process waiting here ends too.
    Closed = 4,
    /// A process is being started for this place; it offers itself once ready.
    Coming = 5,
}

/// The task a pooled process is to run; its program is the one in the task's slot.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Assignment {
    /// The task slot.
    pub task: u8,
    /// The memory limit of its VM, MiB.
    pub memory_limit_mib: u32,
    /// `StartTaskFunc`: the function to run after the program's top level.
    pub entry: Option<String>,
}

/// One waiting process' place.
#[repr(C)]
pub struct Place {
    state: AtomicU32,
    pid: AtomicU32,
    task: AtomicU32,
    memory_limit_mib: AtomicU32,
    entry_len: AtomicU32,
    entry: [AtomicU64; ENTRY_BYTES / 8],
}

impl Place {
    /// Where the place is in its round.
    pub fn state(&self) -> PlaceState {
        PlaceState::from(self.state.load(Ordering::Acquire))
    }

    /// The process that waits (or waited) here.
    pub fn pid(&self) -> u32 {
        self.pid.load(Ordering::Acquire)
    }

    /// An empty place is given to a process being started (the supervisor): no pid is
    /// left from the last one, and the core knows a process is on its way.
    pub fn expect(&self) {
        self.pid.store(0, Ordering::Release);
        self.swap(PlaceState::Empty, PlaceState::Coming);
    }

    /// The process expected here could not be started: the place is empty again.
    pub fn abandon(&self) {
        self.swap(PlaceState::Coming, PlaceState::Empty);
    }

    /// The process `pid` waits here for a task (the pooled process, once ready); false
    /// when the place was closed meanwhile (the controller ends).
    pub fn offer(&self, pid: u32) -> bool {
        self.pid.store(pid, Ordering::Release);
        self.swap(PlaceState::Coming, PlaceState::Ready) || self.swap(PlaceState::Empty, PlaceState::Ready)
    }

    /// Hands task `task` to the process waiting here and wakes it; its pid, or `None` when
    /// none waits. Never blocks nor allocates (the RT thread calls it); an entry name
    /// longer than `ENTRY_BYTES` is refused (`None`).
    pub fn hand(&self, task: u8, memory_limit_mib: u32, entry: &[u8]) -> Option<u32> {
        if entry.len() > ENTRY_BYTES || !self.swap(PlaceState::Ready, PlaceState::Claimed) {
            return None;
        }
        self.task.store(task.into(), Ordering::Relaxed);
        self.memory_limit_mib.store(memory_limit_mib, Ordering::Relaxed);
        self.entry_len.store(entry.len() as u32, Ordering::Relaxed);
        for (i, word) in self.entry.iter().enumerate() {
            let mut bytes = [0u8; 8];
            let chunk = entry.get(i * 8..).unwrap_or_default();
            let n = chunk.len().min(8);
            bytes[..n].copy_from_slice(&chunk[..n]);
            word.store(u64::from_le_bytes(bytes), Ordering::Relaxed);
        }
        let pid = self.pid();
        self.state.store(PlaceState::Handed.into(), Ordering::Release);
        futex::wake(&self.state);
        Some(pid)
    }

    /// The waiting process' side: sleeps until it is handed a task and takes it (the
    /// place is empty again); `None` when the place is closed or withdrawn, or `alive`,
    /// asked every `period`, says the controller is gone.
    pub fn wait(&self, alive: impl Fn() -> bool, period: Duration) -> Option<Assignment> {
        loop {
            let word = self.state.load(Ordering::Acquire);
            match PlaceState::from(word) {
                PlaceState::Handed => break,
                PlaceState::Ready | PlaceState::Claimed if alive() => futex::wait(&self.state, word, period),
                _ => return None,
            }
        }
        let len = (self.entry_len.load(Ordering::Relaxed) as usize).min(ENTRY_BYTES);
        let bytes: Vec<u8> = self.entry.iter().flat_map(|w| w.load(Ordering::Relaxed).to_le_bytes()).collect();
        let assignment = Assignment {
            task: self.task.load(Ordering::Relaxed) as u8,
            memory_limit_mib: self.memory_limit_mib.load(Ordering::Relaxed),
            entry: (len > 0).then(|| String::from_utf8_lossy(&bytes[..len]).into_owned()),
        };
        self.state.store(PlaceState::Empty.into(), Ordering::Release);
        Some(assignment)
    }

    /// The supervisor takes process `pid` off this place: it died (`to` Empty) or the
    /// controller ends (`to` Closed, which also wakes it). False when a task was handed to
    /// it first: the hand-out stands.
    pub fn withdraw(&self, pid: u32, to: PlaceState) -> bool {
        let done = if self.pid() == pid {
            // Only while it waits: once handed a task (taken or not), it is the task's.
            self.swap(PlaceState::Ready, to)
        } else {
            // It never offered itself.
            self.swap(PlaceState::Coming, to) || self.swap(PlaceState::Empty, to) || self.state() == to
        };
        futex::wake(&self.state);
        done
    }

    /// Whether process `pid` was handed a task here and has not taken it yet.
    pub fn untaken(&self, pid: u32) -> bool {
        self.pid() == pid && matches!(self.state(), PlaceState::Claimed | PlaceState::Handed)
    }

    /// A task handed to process `pid`, which ended before it took it: the place is free again.
    pub fn forget(&self, pid: u32) {
        if self.pid() == pid {
            self.swap(PlaceState::Handed, PlaceState::Empty);
        }
    }

    fn swap(&self, from: PlaceState, to: PlaceState) -> bool {
        self.state.compare_exchange(from.into(), to.into(), Ordering::AcqRel, Ordering::Acquire).is_ok()
    }
}

/// The board: every place of the pool.
#[repr(C)]
pub struct Board {
    /// The places, indexed by the `--pool` argument of the process waiting there.
    pub places: [Place; PLACES],
}

// SAFETY: repr(C), only atomics, valid when zeroed (every place empty).
unsafe impl Shareable for Board {}

impl Board {
    /// Hands task `task` to the first process waiting (see `Place::hand`): its place and
    /// pid, or `None` when none waits.
    pub fn hand(&self, task: u8, memory_limit_mib: u32, entry: &[u8]) -> Option<(usize, u32)> {
        self.places.iter().enumerate().find_map(|(i, place)| Some((i, place.hand(task, memory_limit_mib, entry)?)))
    }

    /// Whether a process is being started for a place (`Place::expect`).
    pub fn coming(&self) -> bool {
        self.places.iter().any(|place| place.state() == PlaceState::Coming)
    }
}

#[cfg(test)]
mod tests {
    use schema::layout::zeroed;

    use super::*;

    /// A task handed to a waiting process reaches it whole, once; the place is empty again.
    #[test]
    fn a_task_handed_out_reaches_the_waiting_process() {
        let board: Box<Board> = zeroed();
        assert_eq!(board.hand(1, 64, b""), None, "nobody waits");
        assert!(board.places[3].offer(4242));
        let entry = "e".repeat(ENTRY_BYTES);
        assert_eq!(board.hand(9, 32, entry.as_bytes()), Some((3, 4242)));
        assert_eq!(board.hand(10, 32, b""), None, "one task per process");
        let got = board.places[3].wait(|| true, Duration::from_millis(1));
        assert_eq!(got, Some(Assignment { task: 9, memory_limit_mib: 32, entry: Some(entry) }));
        assert_eq!(board.places[3].state(), PlaceState::Empty);
        assert_eq!(board.places[3].wait(|| true, Duration::from_millis(1)), None, "taken once");
        assert!(board.places[0].offer(7));
        assert_eq!(board.hand(2, 64, &[b'x'; ENTRY_BYTES + 1]), None, "an entry name too long");
        assert_eq!(board.hand(2, 64, b""), Some((0, 7)));
        assert_eq!(board.places[0].wait(|| true, Duration::from_millis(1)).unwrap().entry, None, "the top level");
    }

    /// A process asleep on its place wakes when a task is handed to it from another thread.
    #[test]
    fn a_sleeping_process_wakes_on_its_task() {
        let board: std::sync::Arc<Box<Board>> = std::sync::Arc::new(zeroed());
        assert!(board.places[1].offer(1));
        let waiter = {
            let board = board.clone();
            // A long period: only the hand-out's wake ends the sleep in time.
            std::thread::spawn(move || board.places[1].wait(|| true, Duration::from_secs(30)))
        };
        std::thread::sleep(Duration::from_millis(50));
        let since = std::time::Instant::now();
        assert_eq!(board.hand(5, 64, b"go"), Some((1, 1)));
        let got = waiter.join().unwrap().unwrap();
        assert!(since.elapsed() < Duration::from_secs(20), "woken by the hand-out, not the period");
        assert_eq!((got.task, got.entry.as_deref()), (5, Some("go")));
    }

    /// A withdrawn or closed place is handed nothing and ends its wait; a withdrawal after a
    /// hand-out fails (the hand-out stands), and a hand-out nobody took can be forgotten.
    #[test]
    fn withdrawal_and_hand_out_exclude_each_other() {
        let board: Box<Board> = zeroed();
        let place = &board.places[0];
        assert!(place.offer(11));
        assert!(!place.withdraw(12, PlaceState::Empty), "another process' offer stands");
        assert!(place.withdraw(11, PlaceState::Closed));
        assert_eq!(board.hand(1, 64, b""), None);
        assert_eq!(place.wait(|| true, Duration::from_millis(1)), None, "closed: the process ends");
        assert!(!place.offer(12), "no offer on a closed place");

        let place = &board.places[1];
        assert!(place.withdraw(13, PlaceState::Empty), "a process that died before its offer");
        assert!(place.offer(14));
        assert_eq!(board.hand(1, 64, b""), Some((1, 14)));
        assert!(!place.withdraw(14, PlaceState::Empty), "handed first");
        place.forget(99);
        assert_eq!(place.state(), PlaceState::Handed, "another process' hand-out stays");
        place.forget(14);
        assert_eq!(place.state(), PlaceState::Empty);
        assert!(place.offer(15));
        assert_eq!(place.wait(|| false, Duration::from_millis(1)), None, "the controller is gone");
        assert!(place.withdraw(15, PlaceState::Empty), "it died waiting");

        let place = &board.places[3];
        place.expect();
        assert!(board.coming(), "a process is on its way");
        assert!(place.withdraw(18, PlaceState::Empty), "it died before its offer");
        assert!(!board.coming());
        place.expect();
        place.abandon();
        assert!(!board.coming(), "it could not be started");
        place.expect();
        assert!(place.offer(19), "a process offers itself where it was expected");
        assert!(!board.coming());
        assert_eq!(board.hand(5, 64, b""), Some((3, 19)));

        let place = &board.places[2];
        assert!(place.offer(16));
        assert_eq!(board.hand(4, 64, b""), Some((2, 16)));
        assert!(place.untaken(16) && !place.untaken(17));
        assert!(place.wait(|| true, Duration::from_millis(1)).is_some());
        assert!(!place.untaken(16), "taken");
        assert!(!place.withdraw(16, PlaceState::Empty), "a process that took its task is the task's, ended or not");
    }
}

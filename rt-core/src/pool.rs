//! The supervisor's pool of started script processes (`[rt] script_pool`). A process
//! start (spawn, exec, the iceoryx2 node, the shared memory opened) takes many cycles; a pooled
//! process has done it and waits on its place of the task table's board
//! (`ipc::pool`) until the core hands it a task, in the cycle the task starts. It makes
//! that task's VM only then: a process serves one task start and ends, so no program
//! ever sees another's globals. The supervisor starts the processes, replaces the ones
//! handed a task or dead, and takes a handed one over as the task's process.

use std::io::Read;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use ipc::pool::{Board, PLACES, PlaceState};

/// How long after a waiting process died before the next is started: a start that keeps
/// failing (a broken install) does not start a process every poll.
const RETRY_AFTER_DEATH: Duration = Duration::from_secs(1);
/// How long after the controller's start the first waiting process is started: the
/// autorun tasks' processes start first, alone (the pool would be empty for them anyway).
const FIRST_FILL_AFTER: Duration = Duration::from_secs(1);

struct Waiting {
    child: Child,
    place: usize,
}

pub struct Pool {
    size: usize,
    waiting: Vec<Waiting>,
    next_start: Instant,
}

impl Pool {
    pub fn new(size: usize) -> Self {
        Pool { size, waiting: Vec::with_capacity(size), next_start: Instant::now() + FIRST_FILL_AFTER }
    }

    /// Every place of the pool has its waiting process (a pool of none is full).
    pub fn is_full(&self) -> bool {
        self.waiting.len() >= self.size
    }

    /// The waiting process `pid`, which the core handed a task; `None` when it died
    /// before it took the task (the caller starts one the usual way). One that took it
    /// and ended already (a short program) is the task's process all the same: its end is
    /// reaped and reported as any task's. Its stdout and stderr are still in the `Child`.
    pub fn take(&mut self, pid: u32, board: &Board) -> Option<Child> {
        let i = self.waiting.iter().position(|w| w.child.id() == pid)?;
        let Waiting { mut child, place } = self.waiting.swap_remove(i);
        if matches!(child.try_wait(), Ok(None)) || !board.places[place].untaken(pid) {
            return Some(child);
        }
        board.places[place].forget(pid);
        self.ended(child);
        None
    }

    /// Drops the waiting processes that died; says whether any did (their iceoryx2 node
    /// is left to clean). One the core handed a task just before it died stays until
    /// the supervisor hears of the hand-out (`take`).
    pub fn reap(&mut self, board: &Board) -> bool {
        let before = self.waiting.len();
        let mut alive = Vec::with_capacity(self.size);
        for mut waiting in std::mem::take(&mut self.waiting) {
            let pid = waiting.child.id();
            match waiting.child.try_wait() {
                Ok(None) => alive.push(waiting),
                _ if !board.places[waiting.place].withdraw(pid, PlaceState::Empty) => alive.push(waiting),
                _ => self.ended(waiting.child),
            }
        }
        self.waiting = alive;
        self.waiting.len() < before
    }

    /// Starts one process with `command(place)` if the pool is short of one (one per
    /// call: the supervisor's orders are not held up by several starts).
    pub fn refill(&mut self, board: &Board, command: impl FnOnce(usize) -> Command) {
        if self.waiting.len() >= self.size || Instant::now() < self.next_start {
            return;
        }
        // A place whose process was handed a task but has not read it yet is not free.
        let free = (0..PLACES).find(|&place| {
            board.places[place].state() == PlaceState::Empty && !self.waiting.iter().any(|w| w.place == place)
        });
        let Some(place) = free else { return };
        board.places[place].expect();
        match command(place).stdin(Stdio::null()).spawn() {
            Ok(child) => self.waiting.push(Waiting { child, place }),
            Err(e) => {
                board.places[place].abandon();
                tracing::warn!("cannot start a waiting script process: {e}");
                self.next_start = Instant::now() + RETRY_AFTER_DEATH;
            }
        }
    }

    /// Ends the waiting processes: a closed place ends its process in order (its node
    /// removed); one that does not end within a second is killed. One the core handed a
    /// task meanwhile is the task's now, and is stopped with the tasks.
    pub fn close(&mut self, board: &Board) {
        for waiting in &self.waiting {
            board.places[waiting.place].withdraw(waiting.child.id(), PlaceState::Closed);
        }
        let mut children: Vec<Child> = self.waiting.drain(..).map(|w| w.child).collect();
        let deadline = Instant::now() + Duration::from_secs(1);
        while !children.is_empty() {
            children.retain_mut(|c| matches!(c.try_wait(), Ok(None)));
            if Instant::now() > deadline {
                for child in &mut children {
                    let _ = child.kill();
                    let _ = child.wait();
                }
                return;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    /// A waiting process is gone: says why in the log, holds off the next start.
    fn ended(&mut self, mut child: Child) {
        let _ = child.kill();
        let status = child.wait();
        let mut stderr = String::new();
        if let Some(mut pipe) = child.stderr.take() {
            let _ = pipe.read_to_string(&mut stderr);
        }
        tracing::warn!(pid = child.id(), ?status, "a waiting script process ended: {}", stderr.trim());
        self.next_start = Instant::now() + RETRY_AFTER_DEATH;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ipc::task_table::TaskTable;

    /// A process that has ended (and whose end the `Child` has seen).
    fn ended_child() -> Child {
        let mut child = Command::new("true").stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
        while child.try_wait().unwrap().is_none() {
            std::thread::sleep(Duration::from_millis(1));
        }
        child
    }

    /// A pooled process that took its task and ended before the supervisor heard of the
    /// hand-out (a short program) is the task's process: its end is the task's, and the
    /// task does not run a second time. One that ended before it took its task is replaced.
    #[test]
    fn a_handed_process_that_ended_counts_as_the_task_s_once_it_took_the_task() {
        let table: Box<TaskTable> = schema::layout::zeroed();
        let board = &table.pool;
        let mut pool = Pool::new(2);
        for place in 0..2 {
            let child = ended_child();
            assert!(board.places[place].offer(child.id()));
            pool.waiting.push(Waiting { child, place });
        }
        let (took, died) = (pool.waiting[0].child.id(), pool.waiting[1].child.id());
        assert_eq!(board.hand(1, 64, b""), Some((0, took)));
        assert!(board.places[0].wait(|| true, Duration::from_millis(1)).is_some());
        assert_eq!(board.hand(2, 64, b""), Some((1, died)));
        assert!(!pool.reap(board), "both were handed a task: they stay until the supervisor hears of it");
        assert!(pool.take(took, board).is_some(), "it ran its task");
        assert!(pool.take(died, board).is_none(), "it never took its task: the task is started anew");
        assert_eq!(board.places[1].state(), PlaceState::Empty, "its place is free again");
    }
}

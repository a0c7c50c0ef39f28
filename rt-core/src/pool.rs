//! The supervisor's pool of started script processes (`[rt] script_pool`). A process
//! start (fork, exec, the iceoryx2 node, the state subscriber) takes many cycles; a pooled
//! process has done it and waits on its stdin for the one task it will run
//! (`script_host::run_pooled`). It makes that task's VM only then: a process serves one
//! task start and ends, so no program ever sees another's globals.

use std::collections::VecDeque;
use std::io::{Read, Write};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::time::{Duration, Instant};

use ipc::pool::Assignment;

/// How long after a waiting process died before the next is started: a start that keeps
/// failing (a broken install) does not fork a process every poll.
const RETRY_AFTER_DEATH: Duration = Duration::from_secs(1);
/// How long after the controller's start the first waiting process is started: the
/// autorun tasks' processes start first, alone (the pool would be empty for them anyway).
const FIRST_FILL_AFTER: Duration = Duration::from_secs(1);

struct Waiting {
    child: Child,
    stdin: ChildStdin,
}

pub struct Pool {
    size: usize,
    waiting: VecDeque<Waiting>,
    next_start: Instant,
}

impl Pool {
    pub fn new(size: usize) -> Self {
        Pool { size, waiting: VecDeque::with_capacity(size), next_start: Instant::now() + FIRST_FILL_AFTER }
    }

    /// A waiting process, told to run `assignment`; `None` when none is left (the caller
    /// starts one the usual way). Its stdout and stderr are still in the `Child`.
    pub fn hand_out(&mut self, assignment: &Assignment) -> Option<Child> {
        let line = assignment.encode();
        while let Some(Waiting { child, mut stdin }) = self.waiting.pop_front() {
            // A process that died while waiting cannot take the line (EPIPE).
            if stdin.write_all(line.as_bytes()).is_ok() {
                return Some(child);
            }
            self.ended(child);
        }
        None
    }

    /// Drops the waiting processes that died; says whether any did (their iceoryx2 node
    /// is left to clean).
    pub fn reap(&mut self) -> bool {
        let before = self.waiting.len();
        let mut alive = VecDeque::with_capacity(self.size);
        while let Some(mut waiting) = self.waiting.pop_front() {
            match waiting.child.try_wait() {
                Ok(None) => alive.push_back(waiting),
                _ => self.ended(waiting.child),
            }
        }
        self.waiting = alive;
        self.waiting.len() < before
    }

    /// Starts one process with `command` if the pool is short of one (one per call: the
    /// supervisor's orders are not held up by several starts).
    pub fn refill(&mut self, command: impl FnOnce() -> Command) {
        if self.waiting.len() >= self.size || Instant::now() < self.next_start {
            return;
        }
        let spawned = command().stdin(Stdio::piped()).spawn();
        match spawned {
            Ok(mut child) => {
                let stdin = child.stdin.take().expect("piped");
                self.waiting.push_back(Waiting { child, stdin });
            }
            Err(e) => {
                tracing::warn!("cannot start a waiting script process: {e}");
                self.next_start = Instant::now() + RETRY_AFTER_DEATH;
            }
        }
    }

    /// Ends the waiting processes: closing its stdin ends one in order (its node
    /// removed); one that does not end within a second is killed.
    pub fn close(&mut self) {
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

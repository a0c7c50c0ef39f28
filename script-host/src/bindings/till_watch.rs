//! On the simulation clock, what a `Till` condition read (docs/decisions.md, "Simulation
//! clock"). A condition that made only status queries is a function of the snapshot: the
//! task hands the queries and their answers to the core (`calls::watch`), which grants it
//! its next turn only in a cycle in which an answer changed. Anything else the condition
//! does (a command, a shared variable, a system variable, output, a timer) spoils the
//! record, and the condition is evaluated every cycle, as in real time.

use api::{ErrorCode, QueryCall};
use calls::query::Answer;
use calls::watch;
use ipc::task_table::{WATCH_ENTRIES, WatchEntry};

use super::Host;

/// The record of the condition being evaluated.
#[derive(Debug, Default)]
pub(super) enum Recording {
    /// No condition is evaluated on the simulation clock.
    #[default]
    Off,
    /// The queries so far, each once.
    Reading(Vec<WatchEntry>),
    /// The condition did something else: it cannot be watched.
    Spoiled,
}

impl Host {
    /// Before a condition is evaluated: records what it reads, on the simulation clock.
    pub(super) fn start_watch(&self) {
        if self.endpoint.borrow().lockstep() {
            *self.watch.borrow_mut() = Recording::Reading(Vec::new());
        }
    }

    /// The condition did something other than a status query.
    pub(super) fn spoil_watch(&self) {
        let mut recording = self.watch.borrow_mut();
        if matches!(*recording, Recording::Reading(_)) {
            *recording = Recording::Spoiled;
        }
    }

    /// The condition made status query `call`, which answered `answer`.
    pub(super) fn watch_query(&self, call: &QueryCall, answer: &Result<Answer, ErrorCode>) {
        let mut recording = self.watch.borrow_mut();
        let Recording::Reading(entries) = &mut *recording else { return };
        match watch::entry(call, answer) {
            Some(entry) if entries.contains(&entry) => {}
            Some(entry) if entries.len() < WATCH_ENTRIES => entries.push(entry),
            _ => *recording = Recording::Spoiled,
        }
    }

    /// After the condition: its queries, if it made only queries (and at least one).
    pub(super) fn take_watch(&self) -> Vec<WatchEntry> {
        match std::mem::take(&mut *self.watch.borrow_mut()) {
            Recording::Reading(entries) if !super::agent::listening() => entries,
            _ => Vec::new(),
        }
    }
}

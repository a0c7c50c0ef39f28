//! The HMPL ch. 22 clients on the simulation clock: each call's outcome is an outside input
//! the program sees in its turn after the cycle the call ended in. With `run --record` the
//! task writes each outcome, in call order, as a record line (`<cycle> client <task>
//! <function> <rc> [<value>]`, docs/replay.md) into a file of its own that the controller
//! merges in; with `run --replay` each call takes the task's next such line and opens no
//! socket. The choices: docs/decisions.md, "Replay".

use std::collections::VecDeque;
use std::fs::File;
use std::io::Write;
use std::path::PathBuf;

pub use calls::clients::ClientOutcome as Outcome;

use super::freeport_sim::{FreePortInputs, RecordSide};

/// A task's client outcomes on the simulation clock.
pub struct Sim {
    task: u8,
    record: Option<File>,
    /// Replaying: the record's path and its outcomes of this task, in call order.
    replay: Option<(PathBuf, VecDeque<(u64, Outcome)>)>,
}

impl Sim {
    /// The task's file in the record directory is `clients-<task>.txt`; a replay reads the
    /// record (checked by the controller before the task started).
    pub fn new(task: u8, inputs: &FreePortInputs) -> std::io::Result<Sim> {
        let (record, replay) = match inputs.open(&format!("clients-{task}.txt"))? {
            RecordSide::Live => (None, None),
            RecordSide::Record(file) => (Some(file), None),
            RecordSide::Replay(path, text) => (None, Some((path, task_outcomes(&text, task)))),
        };
        Ok(Sim { task, record, replay })
    }

    pub fn replaying(&self) -> bool {
        self.replay.is_some()
    }

    /// Writes an outcome seen at `cycle` into the task's record file (with `--record`).
    pub fn note(&mut self, cycle: u64, outcome: &Outcome) {
        if let Some(file) = &mut self.record {
            // A line that cannot be written is missing from the record, which the replay
            // then tells; the program goes on.
            let _ = file.write_all(format!("{cycle} client {} {outcome}\n", self.task).as_bytes());
        }
    }

    /// Replaying: the recorded outcome of the program's next call, a call of `function`,
    /// and the cycle it is seen at; what is wrong with the record otherwise.
    pub fn next(&mut self, function: api::Local) -> Result<(u64, Outcome), String> {
        let Some((path, outcomes)) = self.replay.as_mut() else { return Err("not replaying".into()) };
        let name = function.spec().name;
        match outcomes.pop_front() {
            None => {
                Err(format!("{name}: the record {} has no more client calls of task {}", path.display(), self.task))
            }
            Some((cycle, outcome)) if outcome.function != function => Err(format!(
                "{name}: the record {} has {} next for task {} (cycle {cycle}): the program differs from the recorded one",
                path.display(),
                outcome.function.spec().name,
                self.task
            )),
            Some(next) => Ok(next),
        }
    }
}

/// The `client` lines of `task` in a record's text, in order.
fn task_outcomes(text: &str, task: u8) -> VecDeque<(u64, Outcome)> {
    let task = task.to_string();
    text.lines()
        .filter_map(|line| {
            let words: Vec<&str> = line.split_ascii_whitespace().collect();
            match words.as_slice() {
                [cycle, "client", t, outcome @ ..] if *t == task => {
                    Some((cycle.parse().ok()?, Outcome::parse(outcome)?))
                }
                _ => None,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::Local;

    #[test]
    fn a_replay_takes_the_tasks_calls_in_order_and_tells_a_different_program() {
        let text = "luamotion-inputs 1\n3 client 0 Modbus_ClientConnect 0 1\n4 client 1 ASCII_ClientSend 0\n\
                    5 client 0 Modbus_ClientRead_HoldReg 0 0007\n6 client 0 Modbus_ClientDisconnect 0\n";
        let outcomes = task_outcomes(text, 0);
        let mut sim = Sim { task: 0, record: None, replay: Some(("rec.txt".into(), outcomes)) };
        let (cycle, connect) = sim.next(Local::Modbus_ClientConnect).unwrap();
        assert_eq!((cycle, connect.rc, connect.socket), (3, 0, 1));
        let (cycle, read) = sim.next(Local::Modbus_ClientRead_HoldReg).unwrap();
        assert_eq!((cycle, read.value), (5, vec![0, 7]));
        let error = sim.next(Local::ASCII_ClientSend).unwrap_err();
        assert!(error.contains("rec.txt has Modbus_ClientDisconnect next for task 0 (cycle 6)"), "{error}");
        let error = sim.next(Local::ASCII_ClientSend).unwrap_err();
        assert!(error.contains("rec.txt has no more client calls of task 0"), "{error}");
    }
}

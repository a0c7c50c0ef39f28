//! `FreePort.Eth` on the simulation clock: what a session's socket brings (a peer that
//! connects, bytes, the end of its stream) is an outside input, stamped with the cycle it
//! takes effect at, and a program sees in its turn after cycle c only what is stamped <= c.
//! With `run --record` each task writes these inputs as record lines
//! (`<cycle> eth <task> <session> <event>`, docs/replay.md) into a file of its own as its
//! program sees them (so a session's lines are in the order they were seen, and what a
//! closed session never showed is not in the record), which the controller merges in; with `run --replay` the task reads its lines from
//! the record and its sessions have no sockets. The choices: docs/decisions.md, "Replay".

use std::collections::VecDeque;
use std::fs::File;
use std::io::Write;
use std::path::PathBuf;

pub use calls::freeport::EthEvent as Event;

/// Where a task's FreePort inputs come from and go to on the simulation clock.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum FreePortInputs {
    /// The sockets, stamped but not written down.
    #[default]
    Live,
    /// The sockets, each input also written to `<dir>/task-<id>.txt`.
    Record(PathBuf),
    /// This record file's `eth` lines for the task; no sockets.
    Replay(PathBuf),
}

/// A task's side of the record, shared by the FreePort and the client inputs.
pub enum RecordSide {
    /// Live sockets: nothing is written down.
    Live,
    /// The task's own file in the record directory, appended to.
    Record(File),
    /// The record's path and text.
    Replay(PathBuf, String),
}

impl FreePortInputs {
    /// Opens the task's file `file_name` in the record directory, or reads the record.
    pub fn open(&self, file_name: &str) -> std::io::Result<RecordSide> {
        Ok(match self {
            FreePortInputs::Live => RecordSide::Live,
            FreePortInputs::Record(dir) => {
                RecordSide::Record(File::options().create(true).append(true).open(dir.join(file_name))?)
            }
            FreePortInputs::Replay(path) => RecordSide::Replay(path.clone(), std::fs::read_to_string(path)?),
        })
    }
}

/// A task's FreePort inputs on the simulation clock.
pub struct Sim {
    task: u8,
    record: Option<File>,
    /// Replaying: the record's events of this task, in order: (cycle, session, event).
    replay: Option<VecDeque<(u64, i64, Event)>>,
}

impl Sim {
    /// `None` when the inputs cannot be read or written (the controller checked the record
    /// before the task started).
    pub fn new(task: u8, inputs: &FreePortInputs) -> std::io::Result<Sim> {
        let (record, replay) = match inputs.open(&format!("task-{task}.txt"))? {
            RecordSide::Live => (None, None),
            RecordSide::Record(file) => (Some(file), None),
            RecordSide::Replay(_, text) => (None, Some(task_events(&text, task))),
        };
        Ok(Sim { task, record, replay })
    }

    pub fn replaying(&self) -> bool {
        self.replay.is_some()
    }

    /// Writes an input of `session` into the task's record file (with `--record`).
    pub fn note(&mut self, cycle: u64, session: i64, event: &Event) {
        if let Some(file) = &mut self.record {
            // A record that cannot be written is a warning of the controller's at the end
            // (a line missing); the program goes on.
            let _ = file.write_all(format!("{cycle} eth {} {session} {event}\n", self.task).as_bytes());
        }
    }

    /// Replaying: the next recorded event of `session` if it is due by `cycle`.
    pub fn next_due(&mut self, session: i64, cycle: u64) -> Option<Event> {
        let replay = self.replay.as_mut()?;
        let at = replay.iter().position(|(_, s, _)| *s == session)?;
        (replay[at].0 <= cycle).then(|| replay.remove(at).expect("found").2)
    }

    /// Replaying: whether the session's next recorded event is a `refused` due by
    /// `cycle` (then taken).
    pub fn refused(&mut self, session: i64, cycle: u64) -> bool {
        let Some(replay) = self.replay.as_mut() else { return false };
        let at = replay.iter().position(|(_, s, _)| *s == session);
        match at {
            Some(at) if replay[at].0 <= cycle && replay[at].2 == Event::Refused => replay.remove(at).is_some(),
            _ => false,
        }
    }
}

/// The `eth` lines of `task` in a record's text (checked by the controller: a line that
/// does not parse is skipped).
fn task_events(text: &str, task: u8) -> VecDeque<(u64, i64, Event)> {
    let task = task.to_string();
    text.lines()
        .filter_map(|line| {
            let words: Vec<&str> = line.split_ascii_whitespace().collect();
            match words.as_slice() {
                [cycle, "eth", t, session, event @ ..] if *t == task => {
                    Some((cycle.parse().ok()?, session.parse().ok()?, Event::parse(event)?))
                }
                _ => None,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_task_reads_its_own_lines_in_order() {
        let text = "luamotion-inputs 1\n3 eth 0 1 connect\n4 eth 1 1 connect\n5 eth 0 1 data 6869\n\
                    5 modbus 0x0000 1\n6 eth 0 1 end\n7 eth 0 1 refused\n";
        let events = task_events(text, 0);
        let expected =
            [(3, 1, Event::Connect), (5, 1, Event::Data(b"hi".to_vec())), (6, 1, Event::End), (7, 1, Event::Refused)];
        assert_eq!(events, expected);
        let mut sim = Sim { task: 0, record: None, replay: Some(events) };
        assert_eq!(sim.next_due(1, 2), None, "not before its cycle");
        assert_eq!(sim.next_due(1, 5), Some(Event::Connect));
        assert!(!sim.refused(1, 9), "not the next event");
        assert_eq!(sim.next_due(1, 5), Some(Event::Data(b"hi".to_vec())));
        assert_eq!(sim.next_due(1, 5), None, "the end is due at 6");
        assert_eq!(sim.next_due(1, 6), Some(Event::End));
        assert!(sim.refused(1, 7));
    }
}

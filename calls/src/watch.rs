//! A watched `Till` condition on the simulation clock (docs/decisions.md, "Simulation
//! clock"): the status queries the condition made, with their answers, as words in the
//! task's slot (`ipc::task_table::WatchEntry`). The core answers each query again from the
//! snapshot of the cycle it has just published, with the same `query::evaluate` the script
//! used; while no answer changes, the condition would give its value again.

use std::borrow::Cow;

use api::call::{Doubles, Sink, Source, TypedCall};
use api::{ErrorCode, Query, QueryCall};
use ipc::task_table::{ANSWER_WORDS, WATCH_ARGS, WatchEntry};
use schema::Snapshot;

use crate::query::{self, Answer, Value};

/// The entry for `call`, which answered `answer`; `None` for a query whose arguments do
/// not fit the entry's words.
pub fn entry(call: &QueryCall, answer: &Result<Answer, ErrorCode>) -> Option<WatchEntry> {
    let mut words = Words::default();
    call.write(&mut words).ok()?;
    Some(WatchEntry { query: call.func().id(), argc: words.len as u8, args: words.words, answer: answer_words(answer) })
}

/// Whether `entry`'s query still answers what it did, in `snapshot`. An entry that does not
/// decode counts as changed: the task then takes its turn and evaluates its condition.
pub fn unchanged(entry: &WatchEntry, snapshot: &Snapshot) -> bool {
    let Some(func) = Query::from_id(entry.query) else { return false };
    let args = &entry.args[..(entry.argc as usize).min(WATCH_ARGS)];
    let Ok(call) = QueryCall::read(func, &mut Words::reading(args)) else { return false };
    if call.func().spec().args.len() != args.len() {
        return false;
    }
    answer_words(&query::evaluate(&call, snapshot)) == entry.answer
}

/// An answer as words: tags and lengths in the first, each value's bits after it, an
/// error's code in place of the first value.
fn answer_words(answer: &Result<Answer, ErrorCode>) -> [u64; ANSWER_WORDS] {
    match answer {
        Ok(Answer(first, second)) => {
            let (t1, b1) = value_words(Some(first));
            let (t2, b2) = value_words(second.as_ref());
            [t1 | t2 << 16, b1, b2]
        }
        Err(code) => [u64::MAX, code.code() as u64, 0],
    }
}

/// A value's tag (with a byte buffer's length) and bits.
fn value_words(value: Option<&Value>) -> (u64, u64) {
    match value {
        None => (0, 0),
        Some(Value::Int(i)) => (1, *i as u64),
        Some(Value::Double(d)) => (2, d.to_bits()),
        Some(Value::Bool(b)) => (3, *b as u64),
        Some(Value::Bytes { data, len }) => (4 | (*len as u64) << 8, u64::from_le_bytes(*data)),
    }
}

/// Argument words, written or read in the declaration's order (scalars only).
#[derive(Default)]
struct Words {
    words: [u64; WATCH_ARGS],
    len: usize,
    read: usize,
}

impl Words {
    fn reading(args: &[u64]) -> Self {
        let mut words = Words { len: args.len(), ..Words::default() };
        words.words[..args.len()].copy_from_slice(args);
        words
    }

    fn push(&mut self, word: u64) -> Result<(), NotScalar> {
        *self.words.get_mut(self.len).ok_or(NotScalar)? = word;
        self.len += 1;
        Ok(())
    }

    fn next(&mut self) -> Result<u64, NotScalar> {
        let word = *self.words[..self.len].get(self.read).ok_or(NotScalar)?;
        self.read += 1;
        Ok(word)
    }
}

/// An argument a watch entry cannot hold: a string, a table, or one past `WATCH_ARGS`.
#[derive(Debug)]
struct NotScalar;

impl Sink for Words {
    type Error = NotScalar;
    fn int(&mut self, value: i64) -> Result<(), NotScalar> {
        self.push(value as u64)
    }
    fn double(&mut self, value: f64) -> Result<(), NotScalar> {
        self.push(value.to_bits())
    }
    fn bool(&mut self, value: bool) -> Result<(), NotScalar> {
        self.push(value as u64)
    }
    fn str(&mut self, _: &[u8]) -> Result<(), NotScalar> {
        Err(NotScalar)
    }
    fn bytes(&mut self, _: &[u8]) -> Result<(), NotScalar> {
        Err(NotScalar)
    }
    fn doubles(&mut self, _: &Doubles) -> Result<(), NotScalar> {
        Err(NotScalar)
    }
}

impl<'a> Source<'a> for Words {
    type Error = NotScalar;
    fn int(&mut self) -> Result<i64, NotScalar> {
        self.next().map(|w| w as i64)
    }
    fn double(&mut self) -> Result<f64, NotScalar> {
        self.next().map(f64::from_bits)
    }
    fn bool(&mut self) -> Result<bool, NotScalar> {
        self.next().map(|w| w != 0)
    }
    fn str(&mut self) -> Result<Cow<'a, [u8]>, NotScalar> {
        Err(NotScalar)
    }
    fn bytes(&mut self) -> Result<Cow<'a, [u8]>, NotScalar> {
        Err(NotScalar)
    }
    fn doubles(&mut self) -> Result<Doubles<'a>, NotScalar> {
        Err(NotScalar)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use schema::motion_status;

    fn snapshot(axes: u32) -> Box<Snapshot> {
        let mut s: Box<Snapshot> = Box::default();
        s.axis_count = axes;
        s
    }

    fn watched(call: QueryCall, s: &Snapshot) -> WatchEntry {
        let answer = query::evaluate(&call, s);
        entry(&call, &answer).expect("scalar arguments fit")
    }

    #[test]
    fn an_answer_that_stays_is_unchanged_and_one_that_moves_is_not() {
        let mut s = snapshot(2);
        let in_pos = watched(QueryCall::IsInPos { axis_id: 1 }, &s);
        let fb = watched(QueryCall::GetPosFb { axis_id: 1 }, &s);
        assert!(unchanged(&in_pos, &s) && unchanged(&fb, &s));
        s.axes[0].motion_status |= motion_status::IN_POSITION;
        s.axes[0].pos_fb = 3.0;
        assert!(unchanged(&in_pos, &s) && unchanged(&fb, &s), "another axis moved");
        s.axes[1].pos_fb = 1e-12;
        assert!(unchanged(&in_pos, &s) && !unchanged(&fb, &s), "the feedback moved by one bit's worth");
        s.axes[1].motion_status |= motion_status::IN_POSITION;
        assert!(!unchanged(&in_pos, &s), "in position now");
    }

    #[test]
    fn an_error_answer_is_watched_as_well() {
        let mut s = snapshot(1);
        let missing = watched(QueryCall::IsMoving { axis_id: 5 }, &s);
        assert_eq!(missing.answer[0], u64::MAX, "no axis 5: an error");
        assert!(unchanged(&missing, &s));
        s.axis_count = 6;
        assert!(!unchanged(&missing, &s), "axis 5 exists now");
    }

    #[test]
    fn an_entry_that_does_not_decode_counts_as_changed() {
        let s = snapshot(1);
        let good = watched(QueryCall::IsInPos { axis_id: 0 }, &s);
        assert!(unchanged(&good, &s));
        let hostile = [
            WatchEntry { query: u16::MAX, ..good },
            WatchEntry { argc: 0, ..good },
            WatchEntry { argc: 2, ..good },
            WatchEntry { argc: 200, ..good },
        ];
        for entry in hostile {
            assert!(!unchanged(&entry, &s), "{entry:?}");
        }
    }
}

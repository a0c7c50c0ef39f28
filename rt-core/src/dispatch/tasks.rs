//! HMPL ch. 16: task control. A start answers once the task runs (`resume`); a task that
//! stops itself gets no answer; a front end's slot is never stopped, so a stop it carries
//! out is answered at once.

use api::SystemError;

use super::{Done, Outcome};
use crate::machine::Machine;
use crate::tasks::Entry;

/// HMPL 16.2: starts a task at `entry`.
pub(super) fn start(m: &mut Machine, task: i64, entry: Entry) -> Outcome {
    let cycle = m.cycle;
    m.tasks.start(task, entry, cycle)?;
    Ok(Done::Later)
}

/// HMPL 16.3: starts a task at a function of its program.
pub(super) fn start_func(m: &mut Machine, task: i64, func_name: &[u8]) -> Outcome {
    let entry = Entry::function(func_name).ok_or(SystemError::FuncNotInTask)?;
    start(m, task, entry)
}

/// HMPL 16.4: stops a task; the caller that stops itself waits for its end.
pub(super) fn stop(m: &mut Machine, caller: u8, task: i64) -> Outcome {
    let cycle = m.cycle;
    let Machine { tasks, kernel, .. } = m;
    tasks.stop(task, cycle, &mut |t, reaction| kernel.react(t, reaction))?;
    Ok(answer_unless_stopped(m, caller))
}

/// HMPL 16.5: stops every task, the caller too (a front end's slot, which carries the
/// call, is no task: it is answered).
pub(super) fn stop_all(m: &mut Machine, caller: u8) -> Outcome {
    m.stop_all_tasks();
    Ok(answer_unless_stopped(m, caller))
}

/// HMPL 2.9: every axis disabled, every task stopped, as `stop_all`.
pub(super) fn emergency_stop(m: &mut Machine, caller: u8) -> Outcome {
    m.emergency_stop();
    Ok(answer_unless_stopped(m, caller))
}

/// A caller that a stop stopped gets no answer (its process ends); one that still runs
/// is answered now.
fn answer_unless_stopped(m: &Machine, caller: u8) -> Done {
    if m.tasks.accepts_commands(caller) { Done::Now } else { Done::Later }
}

//! HMPL ch. 16: task control. A start answers once the task runs (`resume`); a task that
//! stops itself gets no answer.

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
    let stopped = tasks.stop(task, cycle, &mut |t, reaction| kernel.react(t, reaction))?;
    Ok(if stopped == caller { Done::Later } else { Done::Now })
}

/// HMPL 16.5: stops every task, the caller too.
pub(super) fn stop_all(m: &mut Machine) -> Outcome {
    let cycle = m.cycle;
    let Machine { tasks, kernel, .. } = m;
    tasks.stop_all(cycle, &mut |t, reaction| kernel.react(t, reaction));
    Ok(Done::Later)
}

//! The 64 HMPL tasks as the core sees them (HMPL ch. 16) and their watchdogs. The core
//! decides each task's state; the supervisor carries out its orders (start a process,
//! kill one) and reports what the processes did (`link.rs`). A task that fails or is
//! stopped has the motion it commanded handled by its fault reaction, in the cycle the
//! core learns of it.

mod link;
mod watchdog;

use api::SystemError;
use api::alarms::{Alarm, Event};
use ipc::task_table::{EndCode, PROGRAM_BYTES, RunState, TaskTable};
use schema::shared::SharedData;
use schema::{MAX_TASKS, TaskSnapshot, TaskState};

use crate::config::{FaultReaction, TaskConfig};
pub use link::{AlarmReport, CoreLink, ENTRY_BYTES, Entry, Exit, Order, Report, SupervisorEnd, link};
use watchdog::Watchdog;

/// How long a process may take from `StartTask` to running its entry (then 0x1772).
const START_TIMEOUT_MS: u64 = 5000;
/// How long a process whose program has ended may take to be gone, at least.
const EXIT_TIMEOUT_MS: u64 = 1000;
/// How long a start with no pooled process ready waits for one on its way before the
/// supervisor starts one for it (a pooled process is ready 5 to 20 ms after its start).
const POOL_WAIT_MS: u64 = 100;

#[derive(Clone, Copy, Debug)]
struct Spec {
    watchdog_ms: u32,
    reaction: FaultReaction,
    /// Attached to by a process the user starts: running from the start, no watchdog.
    external: bool,
    /// Carries a front end's calls (the Native ASCII agent): no stop command stops it, so
    /// a stop it carries out is answered and the front end goes on serving.
    front_end: bool,
    memory_limit_mib: u32,
    /// The pool's waiting processes can run it: they read its program from the task
    /// table, which holds a path of fewer than `PROGRAM_BYTES` bytes of UTF-8 whole.
    poolable: bool,
}

#[derive(Clone, Copy, Debug)]
struct Task {
    /// `None`: no program configured (HMPL's "task empty").
    spec: Option<Spec>,
    state: TaskState,
    /// The task's process, until the supervisor reports it gone.
    pid: Option<u32>,
    /// Cycle the present state began.
    since: u64,
    entry: Entry,
    /// The start order went out (it waits for a previous process to be gone).
    ordered: bool,
    /// What a `StartTask` waiting for this task answers.
    start_result: Option<Result<(), SystemError>>,
    alarm: u32,
    watchdog: Watchdog,
}

/// The 64 HMPL tasks (ch. 16): each one's state, program and process, and the RT thread's
/// end of the link to the supervisor.
pub struct Tasks {
    tasks: [Task; MAX_TASKS],
    link: CoreLink,
    period_ns: u64,
    /// The system error of the last program that ended with a runtime error, until the
    /// kernel takes it as its last system error (HMPL 18.2).
    runtime_error: Option<SystemError>,
}

/// HMPL 18.2: the system error a program's failed end leaves for `GetSystemLastErr`: the
/// HMPL code it ended with (0x13EC a mutex locked twice, 0x138A a stack overflow), else
/// 0x1770 for a Lua error, 0x138A for its memory limit and 0x176F for a process that died
/// (docs/decisions.md, "System").
fn runtime_error(exit: Exit) -> SystemError {
    match exit {
        Exit::Failed { end_code } if end_code == u32::from(EndCode::OutOfMemory) => SystemError::HmplStackOverflow,
        Exit::Failed { end_code } if end_code == u32::from(EndCode::LuaError) => SystemError::HmplExecFailed,
        Exit::Failed { end_code } => u16::try_from(end_code)
            .ok()
            .and_then(|id| SystemError::ALL.iter().copied().find(|e| e.id() == id))
            .unwrap_or(SystemError::HmplExecFailed),
        Exit::Signal(_) => SystemError::HmplInternalError,
        Exit::Finished => SystemError::HmplExecFailed,
    }
}

/// Why a task leaves Running other than by ending.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopCause {
    /// `StopTask`, `StopAllTask` or an E-stop.
    Stopped,
    /// An alarm ended it (a watchdog, a lost process, a fault of its motion).
    Fault(Alarm),
}

impl Tasks {
    /// The tasks of the machine file (`configs`), none running, ordering the supervisor
    /// through `link`.
    pub fn new(configs: &[TaskConfig], period_ns: u64, link: CoreLink) -> Self {
        let empty = Task {
            spec: None,
            state: TaskState::Empty,
            pid: None,
            since: 0,
            entry: Entry::TOP_LEVEL,
            ordered: false,
            start_result: None,
            alarm: 0,
            watchdog: Watchdog::default(),
        };
        let mut tasks = [empty; MAX_TASKS];
        for config in configs {
            let task = &mut tasks[config.id as usize];
            task.spec = Some(Spec {
                watchdog_ms: config.watchdog_ms,
                reaction: config.fault_reaction,
                external: config.external,
                front_end: config.front_end,
                memory_limit_mib: config.memory_limit_mib,
                poolable: config.program.to_str().is_some_and(|p| p.len() < PROGRAM_BYTES),
            });
            task.state = if config.external { TaskState::Running } else { TaskState::Stopped };
        }
        let mut all = Tasks { tasks, link, period_ns, runtime_error: None };
        // HMPL 19.2 `_AUTORUN_`: started with the controller.
        for config in configs.iter().filter(|c| c.autorun) {
            let _ = all.start(config.id as i64, Entry::TOP_LEVEL, 0);
        }
        all
    }

    fn cycles(&self, ms: u64) -> u64 {
        (ms * 1_000_000).div_ceil(self.period_ns)
    }

    fn task_id(id: i64) -> Result<u8, SystemError> {
        u8::try_from(id).ok().filter(|&t| (t as usize) < MAX_TASKS).ok_or(SystemError::NotValidTaskid)
    }

    /// Where task `task` is in its life (what IsTaskStop, HMPL 16.6, reads).
    pub fn state(&self, task: u8) -> TaskState {
        self.tasks[task as usize].state
    }

    /// Commands are served from a task that is starting (its top level runs) or running.
    pub fn accepts_commands(&self, task: u8) -> bool {
        matches!(self.state(task), TaskState::Starting | TaskState::Running)
    }

    /// Programs that are starting, running or being stopped (external slots are not).
    pub fn active(&self) -> usize {
        self.tasks
            .iter()
            // An external slot is a client's (the ASCII agent of `run --http`), not a program.
            .filter(|t| !t.spec.is_some_and(|s| s.external))
            .filter(|t| matches!(t.state, TaskState::Starting | TaskState::Running | TaskState::Stopping))
            .count()
    }

    /// HMPL 16.2/16.3: starts task `id` at `entry`. The reply waits for `start_result`.
    pub fn start(&mut self, id: i64, entry: Entry, cycle: u64) -> Result<u8, SystemError> {
        let t = Self::task_id(id)?;
        let Some(spec) = self.tasks[t as usize].spec else { return Err(SystemError::TaskEmpty) };
        let limit = self.cycles(spec.watchdog_ms as u64);
        let exit_limit = self.cycles(EXIT_TIMEOUT_MS);
        let task = &mut self.tasks[t as usize];
        if matches!(task.state, TaskState::Starting | TaskState::Running) {
            return Err(SystemError::TaskIsRunning);
        }
        if spec.external {
            // Its program attaches by itself: it runs again as soon as it is allowed to.
            task.state = TaskState::Running;
            task.start_result = Some(Ok(()));
            return Ok(t);
        }
        task.state = TaskState::Starting;
        task.since = cycle;
        task.entry = entry;
        task.ordered = false;
        task.start_result = None;
        task.watchdog = Watchdog::new(limit, exit_limit);
        Ok(t)
    }

    /// The answer for a `StartTask` waiting on task `t`, once there is one.
    pub fn take_start_result(&mut self, t: u8) -> Option<Result<(), SystemError>> {
        self.tasks[t as usize].start_result.take()
    }

    /// Whether slot `t` carries a front end's calls rather than a program.
    fn is_front_end(&self, t: u8) -> bool {
        self.tasks[t as usize].spec.is_some_and(|s| s.front_end)
    }

    /// HMPL 16.4: stops task `id`; its commanded motion reacts as configured. A front
    /// end's slot is no HMPL task: 0x0107, whoever asks (docs/decisions.md, "Stops and
    /// the front ends' slot").
    pub fn stop(&mut self, id: i64, cycle: u64, react: &mut dyn FnMut(u8, FaultReaction)) -> Result<u8, SystemError> {
        let t = Self::task_id(id)?;
        if self.is_front_end(t) {
            return Err(SystemError::NotValidTaskid);
        }
        if !self.accepts_commands(t) {
            return Err(SystemError::TaskNotRunning);
        }
        self.leave(t, cycle, StopCause::Stopped, react);
        Ok(t)
    }

    /// HMPL 16.5, 2.9: stops every task that runs, the front ends' slots excepted (they
    /// carry out the stop and answer it).
    pub fn stop_all(&mut self, cycle: u64, react: &mut dyn FnMut(u8, FaultReaction)) {
        for t in 0..MAX_TASKS as u8 {
            if self.accepts_commands(t) && !self.is_front_end(t) {
                self.leave(t, cycle, StopCause::Stopped, react);
            }
        }
    }

    /// A running (or starting) task stops: its motion reacts, its process is killed unless
    /// it is ending by itself.
    fn leave(&mut self, t: u8, cycle: u64, cause: StopCause, react: &mut dyn FnMut(u8, FaultReaction)) {
        self.leave_with(t, cycle, cause, true, react);
    }

    fn leave_with(
        &mut self,
        t: u8,
        cycle: u64,
        cause: StopCause,
        kill: bool,
        react: &mut dyn FnMut(u8, FaultReaction),
    ) {
        let task = &mut self.tasks[t as usize];
        if let Some(spec) = task.spec {
            react(t, spec.reaction);
        }
        let starting = task.state == TaskState::Starting;
        if starting && task.start_result.is_none() {
            task.start_result = Some(Err(SystemError::HmplExecFailed));
        }
        // A process exists or is on its way: the task is stopped once it is gone.
        let process = task.pid.is_some() || (starting && task.ordered);
        task.since = cycle;
        task.state = match cause {
            StopCause::Stopped if process => TaskState::Stopping,
            StopCause::Stopped => TaskState::Stopped,
            StopCause::Fault(alarm) => {
                task.alarm = alarm.0;
                TaskState::Error
            }
        };
        if let Some(pid) = task.pid.filter(|_| kill) {
            self.link.order(Order::Kill { task: t, pid });
        }
    }

    fn raise(&mut self, alarm: Alarm, task: u8, cycle: u64, line: u32, detail: i64) {
        self.link.order(Order::Alarm(AlarmReport { alarm: alarm.0, task, cycle, line, detail }));
    }

    /// Raises an alarm of the controller as a whole (no task's outcome changes).
    pub fn general_alarm(&mut self, event: Event, cycle: u64) {
        self.raise(Alarm::general(event), 0, cycle, 0, 0);
    }

    /// Records an alarm about an axis a task commanded (0x001F) on that task.
    pub fn axis_alarm(&mut self, task: u8, axis: u8, event: Event, cycle: u64) -> Alarm {
        let alarm = Alarm::axis(axis, event);
        if let Some(t) = self.tasks.get_mut(task as usize) {
            t.alarm = alarm.0;
        }
        self.raise(alarm, task, cycle, 0, axis as i64);
        alarm
    }

    /// One cycle: the supervisor's reports, starts, watchdogs. `deferred` has bit t set
    /// when the core holds a call of task t.
    pub fn step(
        &mut self,
        cycle: u64,
        table: &TaskTable,
        shared: &SharedData,
        deferred: u64,
        react: &mut dyn FnMut(u8, FaultReaction),
    ) {
        while let Some(report) = self.link.next_report() {
            self.on_report(report, cycle, table, shared, react);
        }
        let start_timeout = self.cycles(START_TIMEOUT_MS);
        let pool_wait = self.cycles(POOL_WAIT_MS);
        for t in 0..MAX_TASKS as u8 {
            let slot = &table.slots[t as usize];
            let task = &mut self.tasks[t as usize];
            match task.state {
                TaskState::Starting if !task.ordered && task.pid.is_none() => {
                    let entry = task.entry;
                    // A waiting process of the pool takes the task in this cycle; else one
                    // on its way takes it once ready (sooner than one started now would
                    // be); else the supervisor starts one.
                    slot.reset();
                    let spec = task.spec.filter(|s| s.poolable);
                    match spec.and_then(|s| table.pool.hand(t, s.memory_limit_mib, entry.name())) {
                        Some((place, pid)) => {
                            task.ordered = true;
                            task.pid = Some(pid);
                            self.link.order(Order::Handed { task: t, entry, place, pid });
                        }
                        None if spec.is_some() && table.pool.coming() && cycle - task.since < pool_wait => {}
                        None => {
                            task.ordered = true;
                            self.link.order(Order::Start { task: t, entry });
                        }
                    }
                }
                TaskState::Starting if task.ordered && task.pid.is_some_and(|p| slot.pid() == p) && slot.started() => {
                    task.state = TaskState::Running;
                    task.since = cycle;
                    task.start_result = Some(Ok(()));
                    task.watchdog.arm(cycle, slot);
                }
                TaskState::Starting if cycle - task.since > start_timeout => {
                    task.start_result = Some(Err(SystemError::HmplStarttaskTimeout));
                    self.leave(t, cycle, StopCause::Fault(Alarm::task(t, Event::StartTimeout)), react);
                    self.raise(Alarm::task(t, Event::StartTimeout), t, cycle, 0, 0);
                }
                // A program that failed says so before its process is gone: react now.
                TaskState::Running if slot.state() == RunState::Finished && slot.end_code() != 0 => {
                    self.fail(t, Exit::Failed { end_code: slot.end_code() }, cycle, table, react);
                }
                TaskState::Running
                    if !task.spec.is_some_and(|s| s.external)
                        && task.watchdog.hung(cycle, slot, deferred & (1 << t) != 0) =>
                {
                    let stalled_ms = task.watchdog.stalled_for(cycle) * self.period_ns / 1_000_000;
                    let alarm = Alarm::task(t, Event::Watchdog);
                    self.leave(t, cycle, StopCause::Fault(alarm), react);
                    self.raise(alarm, t, cycle, slot.line(), stalled_ms as i64);
                }
                _ => {}
            }
        }
    }

    fn on_report(
        &mut self,
        report: Report,
        cycle: u64,
        table: &TaskTable,
        shared: &SharedData,
        react: &mut dyn FnMut(u8, FaultReaction),
    ) {
        match report {
            Report::Spawned { task: t, pid } => {
                let task = &mut self.tasks[t as usize];
                if task.state == TaskState::Starting {
                    task.pid = Some(pid);
                } else {
                    // Stopped while its process was being started.
                    task.pid = Some(pid);
                    self.link.order(Order::Kill { task: t, pid });
                }
            }
            Report::SpawnFailed { task: t } => {
                let task = &mut self.tasks[t as usize];
                match task.state {
                    TaskState::Starting => {
                        task.state = TaskState::Error;
                        task.start_result = Some(Err(SystemError::HmplExecFailed));
                    }
                    // Stopped while its process was being started, and none came.
                    TaskState::Stopping => task.state = TaskState::Stopped,
                    _ => return,
                }
                task.since = cycle;
            }
            Report::Exited { task: t, pid, exit } => {
                let task = &mut self.tasks[t as usize];
                if task.pid != Some(pid) {
                    return;
                }
                task.pid = None;
                // Only now that the process is gone can its mutexes go to another task.
                ipc::mutex::release_mutexes_of(shared, t);
                if task.state == TaskState::Starting && !task.ordered {
                    // The previous run's process: the new one can start now.
                    return;
                }
                // A short program may run to its end before the core saw it start.
                let ran = task.state == TaskState::Running
                    || (task.state == TaskState::Starting && table.slots[t as usize].started());
                if ran && task.state == TaskState::Starting {
                    task.start_result = Some(Ok(()));
                }
                match (task.state, ran) {
                    (TaskState::Starting | TaskState::Running, true) if exit == Exit::Finished => {
                        task.state = TaskState::Stopped;
                        task.since = cycle;
                    }
                    (TaskState::Starting | TaskState::Running, true) => self.fail(t, exit, cycle, table, react),
                    (TaskState::Starting, false) => {
                        let code = match exit {
                            Exit::Failed { end_code } if end_code == SystemError::FuncNotInTask.id() as u32 => {
                                SystemError::FuncNotInTask
                            }
                            _ => SystemError::HmplExecFailed,
                        };
                        task.start_result = Some(Err(code));
                        self.fail(t, exit, cycle, table, react);
                    }
                    (TaskState::Stopping, _) => {
                        task.state = TaskState::Stopped;
                        task.since = cycle;
                    }
                    _ => {}
                }
            }
        }
    }

    /// A program that ended by itself with a failure (its process is gone or going): the
    /// alarm its end calls for.
    fn fail(&mut self, t: u8, exit: Exit, cycle: u64, table: &TaskTable, react: &mut dyn FnMut(u8, FaultReaction)) {
        let (event, detail) = match exit {
            Exit::Signal(signal) => (Event::ProcessDied, signal as i64),
            Exit::Failed { end_code } if end_code == u32::from(EndCode::OutOfMemory) => (Event::MemoryLimit, 0),
            Exit::Failed { end_code } if end_code == u32::from(EndCode::LuaError) || end_code == 0 => {
                (Event::ProgramError, 0)
            }
            Exit::Failed { end_code } => (Event::Hmpl(end_code as u16), 0),
            Exit::Finished => (Event::ProgramError, 0),
        };
        self.runtime_error = Some(runtime_error(exit));
        let alarm = Alarm::task(t, event);
        self.leave_with(t, cycle, StopCause::Fault(alarm), false, react);
        self.raise(alarm, t, cycle, table.slots[t as usize].line(), detail);
    }

    /// The system error of a program that ended with a runtime error since the last call.
    pub fn take_runtime_error(&mut self) -> Option<SystemError> {
        self.runtime_error.take()
    }

    /// Each task's slot of the snapshot, with the run speeds the machine keeps.
    pub fn fill(&self, out: &mut [TaskSnapshot; MAX_TASKS], run_speed_pct: &[u32; MAX_TASKS]) {
        for ((slot, task), &run_speed_pct) in out.iter_mut().zip(&self.tasks).zip(run_speed_pct) {
            *slot = TaskSnapshot {
                state: task.state.into(),
                alarm: task.alarm,
                pid: task.pid.unwrap_or(0),
                watchdog_ms: task.spec.map_or(0, |s| s.watchdog_ms),
                run_speed_pct,
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use schema::layout::zeroed;

    struct Rig {
        tasks: Tasks,
        supervisor: SupervisorEnd,
        table: Box<TaskTable>,
        shared: Box<SharedData>,
        cycle: u64,
        reactions: Vec<(u8, FaultReaction)>,
    }

    impl Rig {
        fn new() -> Self {
            let config = |id, reaction| TaskConfig {
                autorun: false,
                fault_reaction: reaction,
                watchdog_ms: 10,
                ..TaskConfig::autorun(id, "p.lua".into())
            };
            let (link, supervisor) = link().expect("the bell");
            // Slot 62 as `with_ascii_task` adds it: the Native ASCII agent's.
            let agent = TaskConfig { external: true, front_end: true, ..config(62, FaultReaction::Decelerate) };
            let configs = [config(0, FaultReaction::Decelerate), config(1, FaultReaction::Disable), agent];
            let tasks = Tasks::new(&configs, 1_000_000, link);
            Rig { tasks, supervisor, table: zeroed(), shared: zeroed(), cycle: 0, reactions: Vec::new() }
        }

        fn step(&mut self) {
            self.cycle += 1;
            let reactions = &mut self.reactions;
            self.tasks.step(self.cycle, &self.table, &self.shared, 0, &mut |t, r| reactions.push((t, r)));
        }

        fn orders(&self) -> Vec<Order> {
            std::iter::from_fn(|| self.supervisor.next_order()).collect()
        }

        /// The script of task `t` with `pid` opened its endpoint and runs its entry.
        fn script_runs(&mut self, t: u8, pid: u32) {
            let slot = &self.table.slots[t as usize];
            slot.set_pid(pid);
            slot.set_state(RunState::Running);
            slot.mark_started();
        }
    }

    /// HMPL ch. 16 as the core sees it: one row per transition.
    #[test]
    fn a_task_from_start_to_end() {
        let mut rig = Rig::new();
        assert_eq!(rig.tasks.start(0, Entry::TOP_LEVEL, 0), Ok(0));
        assert_eq!(rig.tasks.state(0), TaskState::Starting, "Stopped -> Starting");
        rig.step();
        assert_eq!(rig.orders(), vec![Order::Start { task: 0, entry: Entry::TOP_LEVEL }], "the supervisor starts it");
        rig.supervisor.report(Report::Spawned { task: 0, pid: 42 });
        rig.step();
        assert_eq!(rig.tasks.state(0), TaskState::Starting, "spawned, not yet at its entry");
        rig.script_runs(0, 42);
        rig.step();
        assert_eq!(rig.tasks.state(0), TaskState::Running, "Starting -> Running");
        assert_eq!(rig.tasks.take_start_result(0), Some(Ok(())), "StartTask answers 0");
        rig.supervisor.report(Report::Exited { task: 0, pid: 42, exit: Exit::Finished });
        rig.step();
        assert_eq!(rig.tasks.state(0), TaskState::Stopped, "Running -> Stopped when the program ends");
        assert!(rig.reactions.is_empty(), "a program that ends is no fault");
    }

    /// A start with a pooled process waiting is handed to it in the cycle of the start,
    /// with its entry and memory limit; the next start, with nobody waiting, goes to the
    /// supervisor.
    #[test]
    fn a_start_is_handed_to_a_waiting_process_in_its_cycle() {
        let mut rig = Rig::new();
        assert!(rig.table.pool.places[2].offer(77));
        let entry = Entry::function(b"go").unwrap();
        rig.tasks.start(1, entry, 0).unwrap();
        rig.step();
        assert_eq!(rig.orders(), vec![Order::Handed { task: 1, entry, place: 2, pid: 77 }]);
        let handed = rig.table.pool.places[2].wait(|| true, std::time::Duration::from_millis(1)).unwrap();
        assert_eq!((handed.task, handed.memory_limit_mib, handed.entry.as_deref()), (1, 64, Some("go")));
        rig.script_runs(1, 77);
        rig.step();
        assert_eq!(rig.tasks.state(1), TaskState::Running, "no report from the supervisor needed");
        rig.tasks.start(0, Entry::TOP_LEVEL, rig.cycle).unwrap();
        rig.step();
        assert_eq!(rig.orders(), vec![Order::Start { task: 0, entry: Entry::TOP_LEVEL }], "the pool is empty");
    }

    /// A start that finds no waiting process while one is on its way waits for it, up to
    /// `POOL_WAIT_MS`; then the supervisor starts one.
    #[test]
    fn a_start_waits_for_a_pooled_process_on_its_way() {
        let mut rig = Rig::new();
        rig.table.pool.places[0].expect();
        rig.tasks.start(1, Entry::TOP_LEVEL, 0).unwrap();
        rig.step();
        rig.step();
        assert!(rig.orders().is_empty(), "no process started for it");
        assert!(rig.table.pool.places[0].offer(55));
        rig.step();
        assert_eq!(rig.orders(), vec![Order::Handed { task: 1, entry: Entry::TOP_LEVEL, place: 0, pid: 55 }]);

        rig.table.pool.places[1].expect();
        rig.tasks.start(0, Entry::TOP_LEVEL, rig.cycle).unwrap();
        let since = rig.cycle;
        let orders = loop {
            assert!(rig.cycle - since < POOL_WAIT_MS, "it waits no longer");
            rig.step();
            let orders = rig.orders();
            if !orders.is_empty() {
                break orders;
            }
        };
        assert_eq!(orders, vec![Order::Start { task: 0, entry: Entry::TOP_LEVEL }], "then one is started for it");
        assert_eq!(rig.cycle - since, POOL_WAIT_MS, "after its wait, at 1 ms cycles");
    }

    #[test]
    fn a_crash_is_a_fault_with_an_alarm_and_a_reaction() {
        let mut rig = Rig::new();
        rig.tasks.start(1, Entry::TOP_LEVEL, 0).unwrap();
        rig.step();
        rig.supervisor.report(Report::Spawned { task: 1, pid: 7 });
        rig.script_runs(1, 7);
        rig.step();
        rig.orders();
        rig.shared.try_lock(3, 1);
        rig.supervisor.report(Report::Exited { task: 1, pid: 7, exit: Exit::Signal(11) });
        rig.step();
        assert_eq!(rig.tasks.state(1), TaskState::Error);
        assert_eq!(rig.reactions, vec![(1, FaultReaction::Disable)], "its fault reaction");
        assert_eq!(rig.shared.mutex_owner(3), None, "its mutex is free once the process is gone");
        let alarm = match rig.orders().as_slice() {
            [Order::Alarm(report)] => report.alarm,
            other => panic!("{other:?}"),
        };
        assert_eq!(alarm, 0x3001_4104, "RL core, task 1, process died");
    }

    /// A program that fails says so in its slot before its process is gone: the core
    /// reacts in the next cycle and lets the process end by itself.
    #[test]
    fn a_failed_program_is_handled_before_its_process_is_gone() {
        let mut rig = Rig::new();
        rig.tasks.start(0, Entry::TOP_LEVEL, 0).unwrap();
        rig.step();
        rig.supervisor.report(Report::Spawned { task: 0, pid: 3 });
        rig.script_runs(0, 3);
        rig.step();
        rig.orders();
        let slot = &rig.table.slots[0];
        slot.set_end_code(EndCode::OutOfMemory.into());
        slot.set_state(RunState::Finished);
        rig.step();
        assert_eq!(rig.tasks.state(0), TaskState::Error);
        assert_eq!(rig.reactions, vec![(0, FaultReaction::Decelerate)]);
        let orders = rig.orders();
        assert!(
            matches!(orders.as_slice(), [Order::Alarm(AlarmReport { alarm: 0x3000_4103, .. })]),
            "the memory-limit alarm, and no kill: {orders:?}"
        );
        rig.supervisor.report(Report::Exited { task: 0, pid: 3, exit: Exit::Failed { end_code: 2 } });
        rig.step();
        assert_eq!((rig.tasks.state(0), rig.orders().len()), (TaskState::Error, 0), "its exit changes nothing");
    }

    #[test]
    fn a_hung_task_is_stopped_in_the_cycle_its_watchdog_runs_out() {
        let mut rig = Rig::new();
        rig.tasks.start(0, Entry::TOP_LEVEL, 0).unwrap();
        rig.step();
        rig.supervisor.report(Report::Spawned { task: 0, pid: 9 });
        rig.script_runs(0, 9);
        rig.step();
        rig.orders();
        let running_since = rig.cycle;
        while rig.tasks.state(0) == TaskState::Running {
            rig.step();
        }
        assert_eq!(rig.cycle - running_since, 10, "watchdog of 10 ms at 1 ms cycles");
        assert_eq!(rig.tasks.state(0), TaskState::Error);
        assert_eq!(rig.reactions, vec![(0, FaultReaction::Decelerate)]);
        let orders = rig.orders();
        assert_eq!(orders[0], Order::Kill { task: 0, pid: 9 }, "its process is killed");
        assert!(matches!(orders[1], Order::Alarm(AlarmReport { alarm: 0x3000_4102, .. })));
    }

    #[test]
    fn stops_and_restarts_wait_for_the_process() {
        let mut rig = Rig::new();
        rig.tasks.start(0, Entry::TOP_LEVEL, 0).unwrap();
        rig.step();
        rig.supervisor.report(Report::Spawned { task: 0, pid: 5 });
        rig.script_runs(0, 5);
        rig.step();
        rig.orders();
        let cycle = rig.cycle;
        let reactions = &mut rig.reactions;
        assert_eq!(rig.tasks.stop(0, cycle, &mut |t, r| reactions.push((t, r))), Ok(0));
        assert_eq!(rig.tasks.state(0), TaskState::Stopping, "Running -> Stopping");
        assert_eq!(rig.orders(), vec![Order::Kill { task: 0, pid: 5 }]);
        assert_eq!(rig.tasks.start(0, Entry::TOP_LEVEL, cycle), Ok(0), "a start while the old process dies");
        rig.step();
        assert!(rig.orders().is_empty(), "no second process before the first is gone");
        rig.supervisor.report(Report::Exited { task: 0, pid: 5, exit: Exit::Signal(9) });
        rig.step();
        rig.step();
        assert_eq!(rig.orders(), vec![Order::Start { task: 0, entry: Entry::TOP_LEVEL }], "now the new one");
        let mut stopped = rig.tasks.stop(0, rig.cycle, &mut |_, _| {});
        assert_eq!(stopped, Ok(0), "stopped while being started");
        rig.supervisor.report(Report::SpawnFailed { task: 0 });
        rig.step();
        assert_eq!(rig.tasks.state(0), TaskState::Stopped, "Stopping -> Stopped when no process came");
        stopped = rig.tasks.stop(0, rig.cycle, &mut |_, _| {});
        assert_eq!(stopped, Err(SystemError::TaskNotRunning));
        assert_eq!(rig.tasks.start(2, Entry::TOP_LEVEL, 0), Err(SystemError::TaskEmpty));
        assert_eq!(rig.tasks.start(64, Entry::TOP_LEVEL, 0), Err(SystemError::NotValidTaskid));
    }

    /// HMPL 16.4, 16.5, 2.9: stops end the programs, never a front end's slot, which
    /// carries the stop out and must answer it; naming that slot is 0x0107 (issue 36.3).
    #[test]
    fn no_stop_stops_a_front_ends_slot() {
        let mut rig = Rig::new();
        assert_eq!(rig.tasks.state(62), TaskState::Running, "attached from the start");
        for (t, pid) in [(0, 11), (1, 12)] {
            rig.tasks.start(t as i64, Entry::TOP_LEVEL, 0).unwrap();
            rig.step();
            rig.supervisor.report(Report::Spawned { task: t, pid });
            rig.script_runs(t, pid);
        }
        rig.step();
        rig.orders();
        let cycle = rig.cycle;
        assert_eq!(rig.tasks.stop(62, cycle, &mut |_, _| {}), Err(SystemError::NotValidTaskid), "StopTask(62)");
        assert_eq!(rig.tasks.state(62), TaskState::Running);
        let reactions = &mut rig.reactions;
        rig.tasks.stop_all(cycle, &mut |t, r| reactions.push((t, r)));
        assert_eq!(rig.tasks.state(62), TaskState::Running, "StopAllTask leaves the agent serving");
        assert!(rig.tasks.accepts_commands(62));
        assert_eq!((rig.tasks.state(0), rig.tasks.state(1)), (TaskState::Stopping, TaskState::Stopping));
        assert_eq!(
            rig.reactions,
            vec![(0, FaultReaction::Decelerate), (1, FaultReaction::Disable)],
            "no reaction for 62"
        );
        assert_eq!(rig.orders(), vec![Order::Kill { task: 0, pid: 11 }, Order::Kill { task: 1, pid: 12 }]);
    }
}

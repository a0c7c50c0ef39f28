//! DRL program control, DXMC manual appendix A.3: the state machine behind registers
//! 0x6B00..0x6B0E. A command is answered at once with its "in progress" or "cannot"
//! status; `poll` settles it to "done" as the task and its debugger move on, as a Modbus
//! poller would observe on a DXMC.
//!
//! The manual names the commands but not every transition; the choices (Stop closes the
//! project, Block Run stops before the first line, ...) are in docs/decisions.md.
//!
//! A debugger command waits for the script's next line of `main.lua`, so a Pause sent
//! during a `DELAY` or a `Till` stays on its way until the wait ends. A command that comes
//! meanwhile is never dropped: a run or a step replaces the command on its way (the newest
//! command rules, as in the script's debugger), and a command the state refuses keeps its
//! CANNOT_x status: the earlier command, settling later, does not write over it.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use schema::TaskState;
use schema::debug::{DebugBlock, DebugCommand, Halt, RunMode};

use crate::codes::{Control, ExecState, Status};
use crate::projects::{MAX_ID, Projects};
use crate::registers::BREAKPOINT_REGISTERS;

/// How long a start may go unseen before it counts as refused (the core answers within a
/// cycle or two).
const START_UNSEEN: Duration = Duration::from_secs(2);

/// What program control needs of the controller: the DRL task slot and its orders.
pub trait Host {
    /// The DRL task's state as the core publishes it.
    fn task_state(&self) -> TaskState;
    /// The debugger's words in the DRL task's slot: breakpoints, commands, the line.
    fn debug(&self) -> &DebugBlock;
    /// The DRL task's run speed, %, as the core publishes it (DXMC A.3, 0x6B03).
    fn run_speed(&self) -> u16;
    /// Orders a new run speed; false when the core is too busy.
    fn set_run_speed(&self, pct: u16) -> bool;
    /// Writes the program the next start runs into the task's slot.
    fn set_program(&self, path: &Path);
    /// Orders the start of the DRL task; false when the core is too busy.
    fn start(&self) -> bool;
    /// Orders the stop of the DRL task; false when the core is too busy.
    fn stop(&self) -> bool;
    /// Wakes the script after a debugger command.
    fn wake(&self);
}

/// What `control` waits for before the status settles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Pending {
    /// The task to run (status RUNNING). Until the core shows it starting, the task's
    /// state is the previous run's (a failed one reads Error): `seen` says it has moved.
    Start { seen: bool, since: Instant },
    /// The task to end (status STOPPED).
    Stop,
    /// A debugger command to be carried out, then this status.
    Debug { seq: u32, done: Status },
}

/// The DRL registers' program control (0x6B00..0x6B0E) over the projects on disk: what is
/// selected, opened and running, and the status of the last command.
#[derive(Debug)]
pub struct ProgramControl {
    projects: Projects,
    selected: u16,
    current: u16,
    state: ExecState,
    status: Status,
    control: u16,
    breakpoint_registers: [u16; BREAKPOINT_REGISTERS],
    /// Set BP's lines, given to the debugger when the program starts.
    breakpoints: Vec<u32>,
    opened: Option<PathBuf>,
    pending: Option<Pending>,
}

impl ProgramControl {
    /// Closed, nothing selected, status STOPPED.
    pub fn new(projects: Projects) -> Self {
        ProgramControl {
            projects,
            selected: 0,
            current: 0,
            state: ExecState::Close,
            status: Status::Stopped,
            control: 0,
            breakpoint_registers: [0; BREAKPOINT_REGISTERS],
            breakpoints: Vec::new(),
            opened: None,
            pending: None,
        }
    }

    /// 0x6B00: the id of the project opened (0 before any).
    pub fn current_id(&self) -> u16 {
        self.current
    }

    /// 0x6B01: the execution state.
    pub fn state(&self) -> ExecState {
        self.state
    }

    /// 0x6B06: the status of the last command.
    pub fn status(&self) -> Status {
        self.status
    }

    /// 0x6B04: the id the next Open opens.
    pub fn selected(&self) -> u16 {
        self.selected
    }

    /// 0x6B05 as last written, known code or not.
    pub fn last_control(&self) -> u16 {
        self.control
    }

    /// Breakpoint register `i` (0x6B07 + i): a line of `main.lua`, 0 for none.
    pub fn breakpoint_register(&self, i: usize) -> u16 {
        self.breakpoint_registers[i]
    }

    /// Writes breakpoint register `i`; Set, Add or Delete BP reads it.
    pub fn set_breakpoint_register(&mut self, i: usize, line: u16) {
        self.breakpoint_registers[i] = line;
    }

    /// 0x6B04 takes 0..9999 (DXMC A.3).
    pub fn valid_id(id: u16) -> bool {
        id <= MAX_ID
    }

    /// 0x6B03 takes 1..100 %.
    pub fn valid_speed(pct: u16) -> bool {
        (1..=100).contains(&pct)
    }

    /// 0x6B04: false for an id over 9999.
    pub fn select(&mut self, id: u16) -> bool {
        let ok = Self::valid_id(id);
        if ok {
            self.selected = id;
        }
        ok
    }

    /// 0x6B03, 1..100 %: the core keeps it (one store, in the controller) and the
    /// project's motion follows at once; false out of range or when the core is busy.
    pub fn set_speed(&self, pct: u16, host: &dyn Host) -> bool {
        Self::valid_speed(pct) && host.set_run_speed(pct)
    }

    /// 0x6B05. `None` for a code the manual does not list: alarm 0x7000, nothing changes.
    pub fn control(&mut self, code: u16, host: &dyn Host) -> Option<Status> {
        let command = Control::try_from(code).ok()?;
        self.control = code;
        self.status = self.carry_out(command, host);
        Some(self.status)
    }

    fn carry_out(&mut self, command: Control, host: &dyn Host) -> Status {
        match command {
            Control::Open => self.open(host),
            Control::ReleaseRun => self.run(RunMode::Release, host),
            Control::DebugRun => self.run(RunMode::Debug, host),
            Control::BlockRun => self.run(RunMode::Block, host),
            Control::OpenAndReleaseRun => self.open_and_run(RunMode::Release, host),
            Control::OpenAndDebugRun => self.open_and_run(RunMode::Debug, host),
            Control::OpenAndBlockRun => self.open_and_run(RunMode::Block, host),
            Control::Stop => self.stop(host),
            Control::Pause => self.pause(host),
            Control::StepInto => self.step(DebugCommand::StepInto, host),
            Control::StepOver => self.step(DebugCommand::StepOver, host),
            Control::StepOut => self.step(DebugCommand::StepOut, host),
            Control::SetBp => self.set_breakpoints(),
            Control::AddBp => self.add_breakpoint(host),
            Control::DeleteBp => self.delete_breakpoint(host),
            Control::ExportProject => self.export(),
            Control::ImportProject => self.import(),
        }
    }

    fn open(&mut self, host: &dyn Host) -> Status {
        if self.state.is_running() || self.pending.is_some() {
            return Status::CannotOpen;
        }
        match self.projects.check(self.selected) {
            Ok(path) => {
                host.set_program(&path);
                self.opened = Some(path);
                self.current = self.selected;
                self.state = ExecState::PreRun;
                Status::Opened
            }
            Err(e) => {
                tracing::warn!("DRL open: {e}");
                Status::CannotOpen
            }
        }
    }

    fn open_and_run(&mut self, mode: RunMode, host: &dyn Host) -> Status {
        match self.open(host) {
            Status::Opened => self.run(mode, host),
            refused => refused,
        }
    }

    /// Release Run, Debug Run, Block Run: from Pre-Run the program starts; from a stop,
    /// or with a debugger command on its way (a Pause during a `DELAY`), it runs on in the
    /// new mode; while running or starting, the mode changes.
    fn run(&mut self, mode: RunMode, host: &dyn Host) -> Status {
        match (self.state, self.pending) {
            (ExecState::PreRun, None) => {
                let lines: Vec<u32> = if mode == RunMode::Release { Vec::new() } else { self.breakpoints.clone() };
                host.debug().prepare(mode, &lines);
                if !host.start() {
                    return Status::CannotRun;
                }
                self.pending = Some(Pending::Start { seen: false, since: Instant::now() });
                self.state = ExecState::Running;
                Status::Busy
            }
            (ExecState::BreakPoint | ExecState::Pause, None) | (_, Some(Pending::Debug { .. })) => {
                host.debug().set_mode(mode);
                self.debug_command(DebugCommand::Continue, Status::Running, host)
            }
            (ExecState::Running, None) => {
                host.debug().set_mode(mode);
                Status::Running
            }
            // The start under way settles to RUNNING, in the new mode.
            (ExecState::Running, Some(Pending::Start { .. })) => {
                host.debug().set_mode(mode);
                Status::Busy
            }
            _ => Status::CannotRun,
        }
    }

    /// Pause: while the program runs, or replacing a debugger command on its way.
    fn pause(&mut self, host: &dyn Host) -> Status {
        match (self.state, self.pending) {
            (ExecState::Running, None | Some(Pending::Debug { .. })) => {
                self.debug_command(DebugCommand::Pause, Status::Paused, host)
            }
            _ => Status::CannotPause,
        }
    }

    fn stop(&mut self, host: &dyn Host) -> Status {
        match self.state {
            ExecState::PreRun => {
                self.close();
                Status::Stopped
            }
            s if s.is_running() => {
                if matches!(host.task_state(), TaskState::Stopped | TaskState::Error | TaskState::Empty) {
                    // Ended already: nothing to stop.
                    self.close();
                    return Status::Stopped;
                }
                if !host.stop() {
                    return Status::CannotStop;
                }
                self.pending = Some(Pending::Stop);
                Status::Stopping
            }
            _ => Status::CannotStop,
        }
    }

    /// A step: from Break Point or Pause, or replacing a debugger command on its way (a
    /// step during a pending Pause stops at the next line of `main.lua`, as the Pause would).
    fn step(&mut self, command: DebugCommand, host: &dyn Host) -> Status {
        match (self.state, self.pending) {
            (ExecState::BreakPoint | ExecState::Pause, None) | (_, Some(Pending::Debug { .. })) => {
                self.debug_command(command, Status::Stepped, host)
            }
            _ => Status::CannotStep,
        }
    }

    /// Sends a debugger command, replacing one still on its way (the script carries out
    /// the newest); the status reads BUSY and settles to `done` once it is carried out.
    fn debug_command(&mut self, command: DebugCommand, done: Status, host: &dyn Host) -> Status {
        let seq = host.debug().send(command);
        host.wake();
        self.pending = Some(Pending::Debug { seq, done });
        if command != DebugCommand::Pause {
            self.state = ExecState::Running;
        }
        Status::Busy
    }

    /// Set BP: before a run, the lines in 0x6B07..0x6B0E (0 = unused) replace the set.
    fn set_breakpoints(&mut self) -> Status {
        if self.state.is_running() {
            return Status::CannotSetBp;
        }
        let lines: Vec<u32> = self.breakpoint_registers.iter().filter(|&&l| l != 0).map(|&l| l as u32).collect();
        if let Some(path) = &self.opened
            && let Ok(source) = std::fs::read_to_string(path)
        {
            let last = source.lines().count() as u32;
            if lines.iter().any(|&l| l > last) {
                return Status::CannotSetBp;
            }
        }
        self.breakpoints = lines;
        Status::BpSet
    }

    /// Add BP: one line (0x6B07); while running it reaches the debugger at once.
    fn add_breakpoint(&mut self, host: &dyn Host) -> Status {
        let line = self.breakpoint_registers[0] as u32;
        let added = if self.state.is_running() {
            host.debug().add_breakpoint(line)
        } else {
            let fits = line != 0 && !self.breakpoints.contains(&line) && self.breakpoints.len() < BREAKPOINT_REGISTERS;
            if fits {
                self.breakpoints.push(line);
            }
            fits
        };
        if added { Status::BpAdded } else { Status::CannotAddBp }
    }

    fn delete_breakpoint(&mut self, host: &dyn Host) -> Status {
        let line = self.breakpoint_registers[0] as u32;
        let was_set = self.breakpoints.contains(&line);
        self.breakpoints.retain(|&l| l != line);
        let deleted = if self.state.is_running() { host.debug().delete_breakpoint(line) } else { was_set };
        if deleted { Status::BpDeleted } else { Status::CannotDeleteBp }
    }

    fn export(&mut self) -> Status {
        if !self.projects.has_project(self.selected) {
            return Status::FtpIdError;
        }
        match self.projects.export(self.selected) {
            Ok(()) => Status::ExportDone,
            Err(e) => {
                tracing::warn!("DRL export: {e}");
                Status::UsbMountError
            }
        }
    }

    fn import(&mut self) -> Status {
        if !self.projects.has_export(self.selected) {
            return Status::UsbIdError;
        }
        if self.state != ExecState::Close && self.current == self.selected {
            // The project in use is not replaced under the running program.
            return Status::Failed;
        }
        match self.projects.import(self.selected) {
            Ok(()) => Status::ImportDone,
            Err(e) => {
                tracing::warn!("DRL import: {e}");
                Status::Failed
            }
        }
    }

    fn close(&mut self) {
        self.state = ExecState::Close;
        self.opened = None;
        self.pending = None;
    }

    /// Follows the task and its debugger: settles pending commands, notices stops and
    /// the end of the program. Called every few milliseconds.
    pub fn poll(&mut self, host: &dyn Host) {
        let task = host.task_state();
        let alive = matches!(task, TaskState::Starting | TaskState::Running | TaskState::Stopping);
        match self.pending {
            Some(Pending::Start { seen, since }) => match task {
                TaskState::Starting => self.pending = Some(Pending::Start { seen: true, since }),
                TaskState::Running => {
                    self.pending = None;
                    self.settle(Status::Running);
                }
                // Ended before a poll saw it run: a short program, or one that failed.
                TaskState::Stopped | TaskState::Error if seen => {
                    let failed = task == TaskState::Error;
                    self.close();
                    self.status = if failed { Status::Failed } else { Status::Stopped };
                    return;
                }
                _ if since.elapsed() > START_UNSEEN => {
                    self.close();
                    self.settle(Status::CannotRun);
                    return;
                }
                _ => {}
            },
            Some(Pending::Stop) if !alive => {
                self.close();
                self.settle(Status::Stopped);
            }
            Some(Pending::Debug { seq, done }) if host.debug().done() == seq || !alive => {
                self.pending = None;
                self.settle(done);
            }
            _ => {}
        }
        let starting = matches!(self.pending, Some(Pending::Start { .. }));
        if self.state.is_running() && !starting && !alive {
            // The program ended by itself, or failed.
            let failed = task == TaskState::Error;
            self.close();
            self.status = if failed { Status::Failed } else { Status::Stopped };
            return;
        }
        if self.state.is_running() && self.pending.is_none_or(|p| p != Pending::Stop) {
            self.state = match host.debug().halt() {
                Halt::BreakPoint => ExecState::BreakPoint,
                Halt::Pause => ExecState::Pause,
                Halt::None => ExecState::Running,
            };
        }
    }

    /// The pending command is carried out: its status replaces BUSY or STOPPING, but not
    /// the answer to a later command (a CANNOT_x of one refused meanwhile stays readable).
    fn settle(&mut self, done: Status) {
        if matches!(self.status, Status::Busy | Status::Stopping) {
            self.status = done;
        }
    }

    /// 0x6B02: the line of `main.lua` the program is at.
    pub fn line(&self, host: &dyn Host) -> u16 {
        if self.state == ExecState::Close { 0 } else { host.debug().main_line().min(u16::MAX as u32) as u16 }
    }
}

#[cfg(test)]
mod tests {
    use std::cell::{Cell, RefCell};

    use super::*;

    /// A DRL slot without a controller: the test plays the core and the script.
    struct FakeHost {
        block: Box<DebugBlock>,
        state: Cell<TaskState>,
        program: RefCell<Option<PathBuf>>,
        speed: Cell<u16>,
    }

    impl Host for FakeHost {
        fn task_state(&self) -> TaskState {
            self.state.get()
        }
        fn debug(&self) -> &DebugBlock {
            &self.block
        }
        fn run_speed(&self) -> u16 {
            self.speed.get()
        }
        fn set_run_speed(&self, pct: u16) -> bool {
            self.speed.set(pct);
            true
        }
        fn set_program(&self, path: &Path) {
            *self.program.borrow_mut() = Some(path.to_path_buf());
        }
        fn start(&self) -> bool {
            self.state.set(TaskState::Starting);
            true
        }
        fn stop(&self) -> bool {
            self.state.set(TaskState::Stopping);
            true
        }
        fn wake(&self) {}
    }

    fn setup() -> (tempfile::TempDir, ProgramControl, FakeHost) {
        let dir = tempfile::tempdir().unwrap();
        let projects = Projects { dir: dir.path().join("p"), export: dir.path().join("usb") };
        std::fs::create_dir_all(dir.path().join("p/5")).unwrap();
        std::fs::write(projects.main_lua(5), "local a = 1\nlocal b = 2\nmy_print(a + b)\n").unwrap();
        let host = FakeHost {
            // SAFETY: only atomics, valid when zeroed.
            block: Box::new(unsafe { std::mem::zeroed() }),
            state: Cell::new(TaskState::Stopped),
            program: RefCell::new(None),
            speed: Cell::new(100),
        };
        (dir, ProgramControl::new(projects), host)
    }

    #[test]
    fn open_then_run_then_the_program_ends() {
        let (_dir, mut p, host) = setup();
        assert!(!p.select(10000), "DRL ids are 0..9999");
        assert!(p.select(5));
        assert_eq!(p.control(1, &host), Some(Status::Opened));
        assert_eq!(p.state(), ExecState::PreRun);
        assert!(host.program.borrow().as_ref().unwrap().ends_with("5/main.lua"));
        assert_eq!(p.control(2, &host), Some(Status::Busy));
        host.state.set(TaskState::Running);
        p.poll(&host);
        assert_eq!((p.state(), p.status()), (ExecState::Running, Status::Running));
        host.state.set(TaskState::Stopped);
        p.poll(&host);
        assert_eq!((p.state(), p.status()), (ExecState::Close, Status::Stopped));
    }

    #[test]
    fn a_new_run_is_not_judged_by_the_last_runs_end() {
        let (_dir, mut p, host) = setup();
        p.select(5);
        host.state.set(TaskState::Error);
        assert_eq!(p.control(6, &host), Some(Status::Busy));
        host.state.set(TaskState::Error);
        p.poll(&host);
        assert_eq!((p.state(), p.status()), (ExecState::Running, Status::Busy), "the old Error is stale");
        host.state.set(TaskState::Starting);
        p.poll(&host);
        host.state.set(TaskState::Stopped);
        p.poll(&host);
        assert_eq!((p.state(), p.status()), (ExecState::Close, Status::Stopped), "ended between two polls");
    }

    #[test]
    fn commands_that_do_not_fit_the_state_are_refused() {
        let (_dir, mut p, host) = setup();
        assert_eq!(p.control(2, &host), Some(Status::CannotRun), "nothing opened");
        assert_eq!(p.control(3, &host), Some(Status::CannotStop));
        assert_eq!(p.control(4, &host), Some(Status::CannotPause));
        assert_eq!(p.control(12, &host), Some(Status::CannotStep));
        p.select(6);
        assert_eq!(p.control(1, &host), Some(Status::CannotOpen), "no project 6");
        assert_eq!(p.control(5, &host), None, "code 5: alarm 0x7000");
        assert_eq!(p.status(), Status::CannotOpen, "an invalid code changes nothing");
        assert_eq!(p.last_control(), 1);
    }

    #[test]
    fn a_breakpoint_stop_a_step_and_stop() {
        let (_dir, mut p, host) = setup();
        p.select(5);
        assert_eq!(p.control(1, &host), Some(Status::Opened));
        p.set_breakpoint_register(0, 9);
        assert_eq!(p.control(41, &host), Some(Status::CannotSetBp), "main.lua has 3 lines");
        p.set_breakpoint_register(0, 2);
        assert_eq!(p.control(41, &host), Some(Status::BpSet));
        assert_eq!(p.control(44, &host), Some(Status::Busy));
        assert_eq!(host.block.mode(), RunMode::Debug);
        assert_eq!(host.block.breakpoint_lines(), vec![2]);
        host.state.set(TaskState::Running);
        host.block.set_main_line(2);
        host.block.set_halt(Halt::BreakPoint);
        p.poll(&host);
        assert_eq!((p.state(), p.line(&host)), (ExecState::BreakPoint, 2));
        assert_eq!(p.control(12, &host), Some(Status::Busy));
        let (seq, command) = host.block.pending().unwrap();
        assert_eq!(command, DebugCommand::StepOver);
        host.block.set_main_line(3);
        host.block.set_halt(Halt::Pause);
        host.block.mark_done(seq);
        p.poll(&host);
        assert_eq!((p.state(), p.status(), p.line(&host)), (ExecState::Pause, Status::Stepped, 3));
        assert_eq!(p.control(41, &host), Some(Status::CannotSetBp), "Set BP only before a run");
        p.set_breakpoint_register(0, 3);
        assert_eq!(p.control(42, &host), Some(Status::BpAdded));
        assert_eq!(p.control(43, &host), Some(Status::BpDeleted));
        assert_eq!(p.control(43, &host), Some(Status::CannotDeleteBp));
        assert_eq!(p.control(3, &host), Some(Status::Stopping));
        host.state.set(TaskState::Stopped);
        p.poll(&host);
        assert_eq!((p.state(), p.status()), (ExecState::Close, Status::Stopped));
    }

    /// Opens project 5 and runs it (Release Run) until the core shows it running.
    fn running(p: &mut ProgramControl, host: &FakeHost) {
        p.select(5);
        assert_eq!(p.control(6, host), Some(Status::Busy));
        host.state.set(TaskState::Running);
        p.poll(host);
        assert_eq!((p.state(), p.status()), (ExecState::Running, Status::Running));
    }

    /// A Pause is on its way while the script waits (`DELAY`, `Till`): it reaches no line.
    fn pause_pending(p: &mut ProgramControl, host: &FakeHost) -> u32 {
        assert_eq!(p.control(4, host), Some(Status::Busy));
        p.poll(host);
        assert_eq!((p.state(), p.status()), (ExecState::Running, Status::Busy), "the Pause waits for a line");
        let (seq, command) = host.block.pending().unwrap();
        assert_eq!(command, DebugCommand::Pause);
        seq
    }

    #[test]
    fn a_release_run_while_a_pause_is_pending_runs_on() {
        let (_dir, mut p, host) = setup();
        running(&mut p, &host);
        let pause = pause_pending(&mut p, &host);
        assert_eq!(p.control(2, &host), Some(Status::Busy), "Release Run is carried out, not refused");
        let (seq, command) = host.block.pending().unwrap();
        assert_eq!(command, DebugCommand::Continue, "the newest command replaces the Pause");
        assert_ne!(seq, pause);
        host.block.mark_done(pause);
        p.poll(&host);
        assert_eq!(p.status(), Status::Busy, "the Pause's end does not settle the Release Run");
        host.block.mark_done(seq);
        p.poll(&host);
        assert_eq!((p.state(), p.status()), (ExecState::Running, Status::Running));
    }

    #[test]
    fn a_step_while_a_pause_is_pending_replaces_it() {
        let (_dir, mut p, host) = setup();
        running(&mut p, &host);
        pause_pending(&mut p, &host);
        assert_eq!(p.control(12, &host), Some(Status::Busy));
        let (seq, command) = host.block.pending().unwrap();
        assert_eq!(command, DebugCommand::StepOver);
        host.block.set_halt(Halt::Pause);
        host.block.mark_done(seq);
        p.poll(&host);
        assert_eq!((p.state(), p.status()), (ExecState::Pause, Status::Stepped));
    }

    #[test]
    fn a_stop_while_a_pause_is_pending_stops() {
        let (_dir, mut p, host) = setup();
        running(&mut p, &host);
        pause_pending(&mut p, &host);
        assert_eq!(p.control(3, &host), Some(Status::Stopping));
        host.state.set(TaskState::Stopped);
        p.poll(&host);
        assert_eq!((p.state(), p.status()), (ExecState::Close, Status::Stopped));
    }

    #[test]
    fn a_refusal_is_not_overwritten_by_the_command_settling_before_it() {
        let (_dir, mut p, host) = setup();
        running(&mut p, &host);
        assert_eq!(p.control(3, &host), Some(Status::Stopping));
        assert_eq!(p.control(2, &host), Some(Status::CannotRun), "no run while stopping");
        host.state.set(TaskState::Stopped);
        p.poll(&host);
        assert_eq!((p.state(), p.status()), (ExecState::Close, Status::CannotRun), "the refusal stays readable");
    }

    #[test]
    fn run_speed_is_1_to_100_percent() {
        let (_dir, p, host) = setup();
        assert!(!p.set_speed(0, &host) && !p.set_speed(101, &host));
        assert_eq!(host.run_speed(), 100, "a refused speed is not ordered");
        assert!(p.set_speed(50, &host));
        assert_eq!(host.run_speed(), 50);
    }
}

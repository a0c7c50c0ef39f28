//! The debugger of a program: DRL program control (DXMC manual A.3, registers 0x6B01 to
//! 0x6B05). The console drives it through the `DebugBlock` of the task's slot: the run
//! mode, breakpoints on lines of the main chunk, and the commands Pause, Continue,
//! StepInto, StepOver and StepOut; the debugger reports why the program stopped and the
//! main chunk's line.
//!
//! It lives in the VM's hook, which is off while nothing needs it: any count or line hook
//! makes Lua 5.4 run `luaG_traceexec` before every instruction (see `arming`). The hook
//! is armed by `arming::Watcher`'s signal while the program runs Lua, once every
//! `arming::SAMPLE_PERIOD`: it records the line for the watchdog's report, follows the
//! main line for 0x6B02, looks for work (new breakpoints, a command) and bounds the depth,
//! then disarms itself. Breakpoints in Debug or Block Run, a step, a Pause and Block Run's
//! first stop need single lines: the hook then stays a line hook until they are gone, so
//! the debugger costs only while debugging.
//!
//! Why `Lua::set_global_hook` rather than `Lua::set_hook`: mlua's per-thread hook looks
//! its callback up by thread in the registry, finds none for a coroutine and removes the
//! hook there (`hook_proc` in mlua 0.12's `state/raw.rs`); the global hook's callback
//! serves every thread. It is registered once; arming a thread is a `lua_sethook` with its
//! procedure, on the running thread (`arming` hands a resumer's hook to the coroutine it
//! resumes).
//!
//! The hook is no progress for the watchdog: it never advances the heartbeat. A stop marks
//! the task Paused, which the watchdog does not count as hung. It takes line events until
//! the program's first line, so that the watchdog never reports line 0 for a program that
//! hangs before it is first sampled (in a C function such as `string.find`).
//!
//! It also bounds the depth of nested calls (`MAX_DEPTH`) when it runs: Lua's own limit
//! (about 500 000 calls) takes longer to reach than a sample period and more memory than a
//! task's default limit, and a runaway recursion would read as a hang or a memory error
//! instead of a stack overflow at its line.

use std::cell::{Cell, RefCell};
use std::ops::Deref;
use std::rc::Rc;
use std::time::Duration;

use ipc::IpcError;
use ipc::task_table::{RunState, TaskSlot, TaskTable};
use mlua::debug::{Debug, DebugEvent};
use mlua::ffi;
use mlua::thread::ThreadStatus;
use mlua::{HookTriggers, Lua, Thread, VmState};
use schema::debug::{DebugBlock, DebugCommand, Halt, RunMode};

/// VM instructions between two count events of the line hook (the depth check while
/// debugging): a few microseconds of Lua.
pub const LINE_INSTRUCTIONS: u32 = 1000;

/// Nested calls a program may make; one more is a stack overflow.
pub const MAX_DEPTH: usize = 50_000;

/// How often a stopped program checks that its controller is still alive.
const LIVENESS_PERIOD: Duration = Duration::from_millis(100);

/// The watcher's question each sample (`arming::Watcher`): arm the hook now? While the
/// program runs Lua (its slot says `Running`), and once for each news of the console (new
/// breakpoints or mode, a command) even while the program waits in a call or a `DELAY`:
/// the hook then takes it at the program's next instruction. A program that mostly waits
/// is seldom caught running Lua by a sample, and would not see a breakpoint for seconds.
#[derive(Default)]
pub struct ArmWhen {
    /// The debug block's generation and pending command at the last look.
    seen: Cell<Option<(u32, Option<u32>)>>,
}

impl ArmWhen {
    /// Whether to arm the hook of the program in `slot` now.
    pub fn now(&self, slot: &TaskSlot) -> bool {
        let news = (slot.debug.generation(), slot.debug.pending().map(|(seq, _)| seq));
        let fresh = self.seen.replace(Some(news)) != Some(news);
        slot.state() == RunState::Running || fresh
    }
}

/// The task table the debugger works in: in shared memory in a script process, a plain
/// allocation in tests.
pub type SharedTable = Rc<dyn Deref<Target = TaskTable>>;

/// One program's debugger; `install` puts it in the VM's hook.
pub struct Debugger {
    table: SharedTable,
    task: usize,
    /// The chunk name of the program file (`@<path>`): only its lines stop the program.
    main_chunk: String,
    controller_alive: Box<dyn Fn() -> bool>,
    /// The controller went away while the program was stopped. The error that ends the
    /// program is raised again at every event, so that a `pcall` or a coroutine cannot
    /// swallow it and run on.
    controller_gone: Cell<bool>,
    /// The hook procedure `set_global_hook` installed, to arm threads with.
    hook: Cell<Option<ffi::lua_Hook>>,
    /// The breakpoints' generation last seen.
    generation: Cell<u32>,
    /// Debug or Block Run with at least one breakpoint.
    breakpoints_armed: Cell<bool>,
    /// Block Run: the first line of the main chunk is still to come.
    block_start: Cell<bool>,
    /// No line has been run yet.
    first_line: Cell<bool>,
    step: RefCell<Option<Step>>,
}

/// A step under way (DXMC A.3, 0x6B05 codes 11, 12, 13).
struct Step {
    seq: u32,
    kind: StepKind,
    /// Where the step began: the running coroutine and its stack depth.
    thread: Thread,
    depth: usize,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum StepKind {
    Into,
    Over,
    Out,
}

impl StepKind {
    fn of(command: DebugCommand) -> Option<StepKind> {
        match command {
            DebugCommand::StepInto => Some(StepKind::Into),
            DebugCommand::StepOver => Some(StepKind::Over),
            DebugCommand::StepOut => Some(StepKind::Out),
            DebugCommand::Pause | DebugCommand::Continue => None,
        }
    }
}

/// How a stopped program goes on.
enum Resume {
    Continue(u32),
    Step(Step),
}

impl Debugger {
    /// A debugger for the program whose chunk is named `main_chunk` (`@<path>`), in task
    /// `task`'s slot. `controller_alive` is asked while the program is stopped: when it
    /// says no, the program ends with `IpcError::ControllerGone`.
    pub fn new(
        table: SharedTable,
        task: usize,
        main_chunk: impl Into<String>,
        controller_alive: impl Fn() -> bool + 'static,
    ) -> Rc<Self> {
        Rc::new(Debugger {
            table,
            task,
            main_chunk: main_chunk.into(),
            controller_alive: Box::new(controller_alive),
            controller_gone: Cell::new(false),
            hook: Cell::new(None),
            generation: Cell::new(0),
            breakpoints_armed: Cell::new(false),
            block_start: Cell::new(false),
            first_line: Cell::new(true),
            step: RefCell::new(None),
        })
    }

    /// Sets the VM's hook, before the program starts: the console has prepared the run
    /// mode and the breakpoints. The hook takes line events until the first line.
    pub fn install(self: &Rc<Self>, lua: &Lua) -> mlua::Result<()> {
        let debug = self.debug();
        debug.set_halt(Halt::None);
        self.block_start.set(debug.mode() == RunMode::Block);
        self.reread_breakpoints();
        let this = Rc::clone(self);
        lua.set_global_hook(line_triggers(), move |lua, event| this.on_event(lua, event))?;
        // SAFETY: the running (main) thread, alive while `lua` is.
        self.hook.set(unsafe { ffi::lua_gethook(lua.current_thread().state()) });
        Ok(())
    }

    /// The program has ended. A command still pending (a step that never reached its line,
    /// a Pause that found no line to stop on) counts as carried out, so that the console
    /// never waits for a stop that cannot come.
    pub fn finish(&self) {
        let debug = self.debug();
        debug.set_halt(Halt::None);
        if let Some((seq, _)) = debug.pending() {
            debug.mark_done(seq);
        }
    }

    fn slot(&self) -> &TaskSlot {
        &self.table.slots[self.task]
    }

    fn debug(&self) -> &DebugBlock {
        &self.slot().debug
    }

    /// Arms the running thread with line events, or takes its hook off.
    fn arm(&self, lua: &Lua, lines: bool) {
        let state = lua.current_thread().state();
        let mask = ffi::LUA_MASKLINE | ffi::LUA_MASKCOUNT;
        // SAFETY: the running thread, on the thread that runs it.
        unsafe {
            match self.hook.get() {
                Some(hook) if lines => ffi::lua_sethook(state, Some(hook), mask, LINE_INSTRUCTIONS as i32),
                _ => ffi::lua_sethook(state, None, 0, 0),
            }
        }
    }

    fn on_event(&self, lua: &Lua, event: &Debug) -> mlua::Result<VmState> {
        if self.controller_gone.get() {
            return Err(controller_gone());
        }
        let Some(line) = event.current_line() else { return Ok(VmState::Continue) };
        let line = line as u32;
        self.slot().set_line(line);
        self.first_line.set(false);
        if event.event() == DebugEvent::Count {
            self.check_depth(lua, event, line)?;
        }
        if self.debug().generation() != self.generation.get() {
            self.reread_breakpoints();
        }
        self.take_command(lua);
        if event.event() == DebugEvent::Line {
            if self.may_stop_at(line) && self.is_main_chunk(event) {
                self.on_main_line(lua, line)?;
            }
            // This thread runs at line speed: off once nothing needs lines.
            if !self.wants_lines() {
                self.arm(lua, false);
            }
        } else {
            // 0x6B02 follows a running program too, at the sampling's pace.
            if self.is_main_chunk(event) {
                self.debug().set_main_line(line);
            }
            // A sample (or the line hook's count event): lines from here on, or no hook.
            self.arm(lua, self.wants_lines());
        }
        Ok(VmState::Continue)
    }

    /// A stack overflow, at the line being run, once the calls nest deeper than `MAX_DEPTH`.
    /// Looking costs one step per level, up to `MAX_DEPTH`.
    fn check_depth(&self, lua: &Lua, event: &Debug, line: u32) -> mlua::Result<()> {
        if lua.inspect_stack(MAX_DEPTH, |_| ()).is_none() {
            return Ok(());
        }
        let file = event.source().short_src.map(|s| s.to_string()).unwrap_or_default();
        Err(mlua::Error::runtime(format!("{file}:{line}: stack overflow (more than {MAX_DEPTH} nested calls)")))
    }

    fn reread_breakpoints(&self) {
        let debug = self.debug();
        self.generation.set(debug.generation());
        let armed = debug.mode() != RunMode::Release && !debug.breakpoint_lines().is_empty();
        self.breakpoints_armed.set(armed);
    }

    /// Whether anything needs line events: breakpoints to honour, a step under way, a
    /// Pause to carry out, Block Run's first stop.
    fn wants_lines(&self) -> bool {
        self.first_line.get()
            || self.breakpoints_armed.get()
            || self.block_start.get()
            || self.step.borrow().is_some()
            || matches!(self.debug().pending(), Some((_, DebugCommand::Pause)))
    }

    /// Whether this line could stop the program. With only breakpoints armed, just their
    /// lines can: the others skip the costlier question of which chunk they are in.
    fn may_stop_at(&self, line: u32) -> bool {
        self.block_start.get()
            || self.step.borrow().is_some()
            || matches!(self.debug().pending(), Some((_, DebugCommand::Pause)))
            || (self.breakpoints_armed.get() && self.debug().has_breakpoint(line))
    }

    fn is_main_chunk(&self, event: &Debug) -> bool {
        event.source().source.as_deref() == Some(self.main_chunk.as_str())
    }

    /// A command that came while the program runs. The newest command rules: it replaces
    /// a step under way. Pause is carried out by the stop at the next line of the main
    /// chunk; a step starts from here.
    fn take_command(&self, lua: &Lua) {
        let Some((seq, command)) = self.debug().pending() else { return };
        if self.step.borrow().as_ref().is_some_and(|step| step.seq == seq) {
            return;
        }
        if command == DebugCommand::Continue {
            self.debug().mark_done(seq);
        }
        *self.step.borrow_mut() = StepKind::of(command).map(|kind| Step::begin(lua, seq, kind));
    }

    /// A line event of the main chunk (DXMC A.3, 0x6B02 shows its line).
    fn on_main_line(&self, lua: &Lua, line: u32) -> mlua::Result<()> {
        let debug = self.debug();
        debug.set_main_line(line);
        let on_breakpoint = debug.mode() != RunMode::Release && debug.has_breakpoint(line);
        // Block Run's first stop is used up by the first line, whatever else stops there.
        let first_block_line = self.block_start.replace(false);
        let asked =
            first_block_line || matches!(debug.pending(), Some((_, DebugCommand::Pause))) || self.step_reached(lua);
        match (on_breakpoint, asked) {
            (true, _) => self.stop(lua, Halt::BreakPoint),
            (false, true) => self.stop(lua, Halt::Pause),
            (false, false) => Ok(()),
        }
    }

    fn step_reached(&self, lua: &Lua) -> bool {
        self.step.borrow().as_ref().is_some_and(|step| step.reached(lua))
    }

    /// Holds the program on this line until the console lets it go on (DXMC A.3, 0x6B01
    /// reads `halt`). The stop carries out the step under way and a pending Pause.
    fn stop(&self, lua: &Lua, halt: Halt) -> mlua::Result<()> {
        let slot = self.slot();
        let debug = self.debug();
        let state = slot.state();
        slot.set_state(RunState::Paused);
        debug.set_halt(halt);
        // Done after the halt is set: a console that sees the command done sees the stop.
        if let Some(step) = self.step.take() {
            debug.mark_done(step.seq);
        }
        if let Some((seq, DebugCommand::Pause)) = debug.pending() {
            debug.mark_done(seq);
        }
        let resume = self.wait_for_resume(lua)?;
        debug.set_halt(Halt::None);
        slot.set_state(state);
        match resume {
            Resume::Continue(seq) => debug.mark_done(seq),
            Resume::Step(step) => *self.step.borrow_mut() = Some(step),
        }
        Ok(())
    }

    /// Sleeps on the task's bell (the console wakes it after a command) until a
    /// Continue or a step; ends the program when the controller is gone.
    fn wait_for_resume(&self, lua: &Lua) -> mlua::Result<Resume> {
        let slot = self.slot();
        loop {
            let seen = slot.wake_count();
            if let Some((seq, command)) = slot.debug.pending() {
                match StepKind::of(command) {
                    Some(kind) => return Ok(Resume::Step(Step::begin(lua, seq, kind))),
                    None if command == DebugCommand::Continue => return Ok(Resume::Continue(seq)),
                    // Pause: stopped already.
                    None => slot.debug.mark_done(seq),
                }
            }
            self.table.sleep(self.task, seen, LIVENESS_PERIOD);
            if !(self.controller_alive)() {
                self.controller_gone.set(true);
                return Err(controller_gone());
            }
        }
    }
}

impl Step {
    /// A step from where the program is now.
    fn begin(lua: &Lua, seq: u32, kind: StepKind) -> Step {
        Step { seq, kind, thread: lua.current_thread(), depth: stack_depth(lua) }
    }

    /// Whether a line of the main chunk, run now, ends the step: StepInto stops at any,
    /// StepOver at one of the step's function or a caller, StepOut at one of a caller.
    fn reached(&self, lua: &Lua) -> bool {
        if self.kind == StepKind::Into {
            return true;
        }
        if lua.current_thread().to_pointer() != self.thread.to_pointer() {
            // Another coroutine: one the step's thread resumed (which then waits, Normal),
            // or its resumer, after the step's thread yielded or ended: a caller.
            return self.thread.status() != ThreadStatus::Normal;
        }
        let depth = stack_depth(lua);
        match self.kind {
            StepKind::Over => depth <= self.depth,
            _ => depth < self.depth,
        }
    }
}

/// The line hook's triggers (as `arm` sets them); its count events bound the depth while
/// debugging.
fn line_triggers() -> HookTriggers {
    HookTriggers::new().every_nth_instruction(LINE_INSTRUCTIONS).every_line()
}

fn controller_gone() -> mlua::Error {
    mlua::Error::external(IpcError::ControllerGone)
}

/// The number of call levels of the running thread, Lua and C functions alike. Looking a
/// level up walks the stack from the top, so the depth is found by doubling and bisection.
fn stack_depth(lua: &Lua) -> usize {
    let exists = |level: usize| lua.inspect_stack(level, |_| ()).is_some();
    // Level 0 (the function the hook runs in) exists; `high` is the first level known absent.
    let (mut low, mut high) = (0, 1);
    while exists(high) {
        low = high;
        high *= 2;
    }
    while high - low > 1 {
        let mid = low + (high - low) / 2;
        if exists(mid) {
            low = mid;
        } else {
            high = mid;
        }
    }
    high
}

#[cfg(test)]
mod tests {
    use std::path::Path;
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::thread::{self, JoinHandle};
    use std::time::Instant;

    use super::*;
    use crate::arming::{self, Watcher};
    use crate::{ScriptError, describe, sandbox};

    const TASK: usize = 3;
    const TIMEOUT: Duration = Duration::from_secs(20);

    /// How a program ended.
    #[derive(Debug, PartialEq)]
    enum Ended {
        Normally,
        ControllerGone,
        Error(String),
    }

    /// The line of `source` that holds `marker`.
    fn line_of(source: &str, marker: &str) -> u32 {
        source.lines().position(|l| l.contains(marker)).expect(marker) as u32 + 1
    }

    fn eventually(what: &str, condition: impl Fn() -> bool) {
        let deadline = Instant::now() + TIMEOUT;
        while !condition() {
            assert!(Instant::now() < deadline, "timed out waiting for {what}");
            thread::sleep(Duration::from_micros(200));
        }
    }

    /// The console's side of a program that runs in a thread of its own, as it would in its
    /// script process: the debugger installed, the main chunk named after its file.
    struct Console {
        table: Arc<TaskTable>,
        alive: Arc<AtomicBool>,
        program: Option<JoinHandle<Ended>>,
        _folder: tempfile::TempDir,
    }

    impl Console {
        /// Writes `main.lua` and `modules` (file name, text) into a folder, prepares the run
        /// mode and the breakpoints, and starts the program.
        fn start(main: &str, modules: &[(&str, &str)], mode: RunMode, breakpoints: &[u32]) -> Console {
            let folder = tempfile::tempdir().unwrap();
            for (file, text) in modules {
                std::fs::write(folder.path().join(file), text).unwrap();
            }
            let program = folder.path().join("main.lua");
            std::fs::write(&program, main).unwrap();
            let table: Arc<TaskTable> = Arc::from(schema::layout::zeroed::<TaskTable>());
            table.slots[TASK].debug.prepare(mode, breakpoints);
            let alive = Arc::new(AtomicBool::new(true));
            let handle = {
                let (table, alive) = (table.clone(), alive.clone());
                thread::spawn(move || run_program(table, alive, &program))
            };
            Console { table, alive, program: Some(handle), _folder: folder }
        }

        fn slot(&self) -> &TaskSlot {
            &self.table.slots[TASK]
        }

        fn send(&self, command: DebugCommand) -> u32 {
            let seq = self.slot().debug.send(command);
            self.table.wake(TASK, 0);
            seq
        }

        /// Waits for the program to stop: why, and on which line of the main chunk.
        fn stopped(&self) -> (Halt, u32) {
            let debug = &self.slot().debug;
            eventually("a stop", || debug.halt() != Halt::None);
            assert_eq!(self.slot().state(), RunState::Paused);
            (debug.halt(), debug.main_line())
        }

        /// Sends a command and waits until it is carried out; then the halt (None: the
        /// program runs on, or has ended) and the main chunk's line.
        fn command(&self, command: DebugCommand) -> (Halt, u32) {
            let seq = self.send(command);
            let debug = &self.slot().debug;
            eventually(&format!("{command:?} done"), || debug.done() == seq);
            (debug.halt(), debug.main_line())
        }

        /// The controller goes away: a stopped program ends at its next look.
        fn kill_controller(&self) {
            self.alive.store(false, Ordering::Relaxed);
            self.table.wake(TASK, 0);
        }

        fn end(&mut self) -> Ended {
            let program = self.program.take().unwrap();
            eventually("the program's end", || program.is_finished());
            program.join().unwrap()
        }
    }

    impl Drop for Console {
        /// A failed test leaves no program behind: it stops at its next main line and ends.
        fn drop(&mut self) {
            if self.program.is_some() {
                self.alive.store(false, Ordering::Relaxed);
                self.send(DebugCommand::Pause);
            }
        }
    }

    fn run_program(table: Arc<TaskTable>, alive: Arc<AtomicBool>, program: &Path) -> Ended {
        let lua = sandbox::new_vm(64 << 20).unwrap();
        crate::require::install(&lua, program).unwrap();
        let chunk_name = format!("@{}", program.display());
        let debugger = Debugger::new(Rc::new(table.clone()) as SharedTable, TASK, chunk_name.clone(), move || {
            alive.load(Ordering::Relaxed)
        });
        debugger.install(&lua).unwrap();
        let watched = table.clone();
        let when = ArmWhen::default();
        let watcher = Watcher::start(&lua, move || move || when.now(&watched.slots[TASK])).unwrap();
        let slot = &table.slots[TASK];
        slot.set_state(RunState::Running);
        let probe = table.clone();
        let line_now = lua.create_function(move |_, ()| Ok(probe.slots[TASK].line())).unwrap();
        lua.globals().set("line_now", line_now).unwrap();
        // An API call that waits, as `DELAY` does: the slot says `Waiting` meanwhile.
        let waiting = table.clone();
        let wait_ms = lua
            .create_function(move |_, ms: u64| {
                waiting.slots[TASK].set_state(RunState::Waiting);
                thread::sleep(Duration::from_millis(ms));
                waiting.slots[TASK].set_state(RunState::Running);
                Ok(())
            })
            .unwrap();
        lua.globals().set("wait_ms", wait_ms).unwrap();
        let hook_mask = lua.create_function(|_, ()| Ok(arming::running_hook_mask())).unwrap();
        lua.globals().set("hook_mask", hook_mask).unwrap();
        let source = std::fs::read_to_string(program).unwrap();
        let result = lua.load(source).set_name(chunk_name).exec();
        drop(watcher);
        debugger.finish();
        slot.set_state(RunState::Finished);
        match result.map_err(|e| describe(e, "main.lua", 0, 0)) {
            Ok(()) => Ended::Normally,
            Err(ScriptError::ControllerGone) => Ended::ControllerGone,
            Err(e) => Ended::Error(e.to_string()),
        }
    }

    const LOOP_FOREVER: &str = "\
local n = 0
while true do
  n = n + 1 -- @loop
end
";

    const CALLS: &str = "\
local function double(a)
  local b = a * 2 -- @body
  return b -- @return
end
local r = double(1) -- @call
r = double(r) -- @next
result = r -- @last
";

    #[test]
    fn a_breakpoint_stops_on_its_line() {
        let main = "\
local total = 0
for i = 1, 10 do
  total = total + i
end
local after = total -- @bp
finished = after
";
        let bp = line_of(main, "@bp");
        let mut console = Console::start(main, &[], RunMode::Debug, &[bp]);
        assert_eq!(console.stopped(), (Halt::BreakPoint, bp));
        assert_eq!(console.command(DebugCommand::Pause), (Halt::BreakPoint, bp), "Pause while stopped");
        assert_eq!(console.command(DebugCommand::Continue).0, Halt::None);
        assert_eq!(console.end(), Ended::Normally);
    }

    #[test]
    fn breakpoints_are_ignored_in_release_run() {
        let mut console = Console::start(CALLS, &[], RunMode::Release, &[line_of(CALLS, "@call")]);
        assert_eq!(console.end(), Ended::Normally);
        assert_eq!(console.slot().debug.main_line(), 0, "the hook only counted");
    }

    #[test]
    fn the_hook_is_no_progress_for_the_watchdog() {
        let main = "\
local s = 0
for i = 1, 100000 do
  s = s + i
end
local stop = s -- @bp
";
        let mut console = Console::start(main, &[], RunMode::Debug, &[line_of(main, "@bp")]);
        console.stopped();
        // One beat for Running, one for Paused: 300 000 lines ran between them.
        assert_eq!(console.slot().heartbeat(), 2);
        console.command(DebugCommand::Continue);
        assert_eq!(console.end(), Ended::Normally);
    }

    #[test]
    fn step_over_stops_at_the_next_line_of_the_same_function() {
        let mut console = Console::start(CALLS, &[], RunMode::Debug, &[line_of(CALLS, "@call")]);
        assert_eq!(console.stopped(), (Halt::BreakPoint, line_of(CALLS, "@call")));
        assert_eq!(console.command(DebugCommand::StepOver), (Halt::Pause, line_of(CALLS, "@next")));
        assert_eq!(console.command(DebugCommand::StepOver), (Halt::Pause, line_of(CALLS, "@last")));
        console.command(DebugCommand::Continue);
        assert_eq!(console.end(), Ended::Normally);
    }

    #[test]
    fn step_into_enters_a_function_of_the_main_chunk() {
        let mut console = Console::start(CALLS, &[], RunMode::Debug, &[line_of(CALLS, "@call")]);
        console.stopped();
        assert_eq!(console.command(DebugCommand::StepInto), (Halt::Pause, line_of(CALLS, "@body")));
        assert_eq!(console.command(DebugCommand::StepOver), (Halt::Pause, line_of(CALLS, "@return")));
        assert_eq!(console.command(DebugCommand::StepOver), (Halt::Pause, line_of(CALLS, "@next")), "out at the end");
        console.command(DebugCommand::Continue);
        assert_eq!(console.end(), Ended::Normally);
    }

    #[test]
    fn step_over_skips_the_lines_of_a_recursive_call() {
        let main = "\
local function fact(n)
  if n <= 1 then return 1 end -- @base
  return n * fact(n - 1) -- @rec
end
local r = fact(3) -- @call
result = r -- @after
";
        let mut console = Console::start(main, &[], RunMode::Debug, &[line_of(main, "@call")]);
        console.stopped();
        assert_eq!(console.command(DebugCommand::StepInto), (Halt::Pause, line_of(main, "@base")));
        assert_eq!(console.command(DebugCommand::StepOver), (Halt::Pause, line_of(main, "@rec")));
        assert_eq!(console.command(DebugCommand::StepOver), (Halt::Pause, line_of(main, "@after")));
        console.command(DebugCommand::Continue);
        assert_eq!(console.end(), Ended::Normally);
    }

    #[test]
    fn step_out_returns_to_the_caller() {
        let mut console = Console::start(CALLS, &[], RunMode::Debug, &[line_of(CALLS, "@call")]);
        console.stopped();
        assert_eq!(console.command(DebugCommand::StepInto), (Halt::Pause, line_of(CALLS, "@body")));
        assert_eq!(console.command(DebugCommand::StepOut), (Halt::Pause, line_of(CALLS, "@next")));
        console.command(DebugCommand::Continue);
        assert_eq!(console.end(), Ended::Normally);
    }

    #[test]
    fn a_breakpoint_in_a_function_stepped_over_stops_there_and_ends_the_step() {
        let (call, ret) = (line_of(CALLS, "@call"), line_of(CALLS, "@return"));
        let mut console = Console::start(CALLS, &[], RunMode::Debug, &[call, ret]);
        console.stopped();
        assert_eq!(console.command(DebugCommand::StepOver), (Halt::BreakPoint, ret));
        assert!(console.slot().debug.pending().is_none());
        console.slot().debug.delete_breakpoint(ret);
        console.command(DebugCommand::Continue);
        assert_eq!(console.end(), Ended::Normally);
    }

    #[test]
    fn pause_in_release_run_stops_within_milliseconds() {
        let mut console = Console::start(LOOP_FOREVER, &[], RunMode::Release, &[]);
        eventually("the loop", || console.slot().line() != 0);
        let asked = Instant::now();
        let (halt, line) = console.command(DebugCommand::Pause);
        let latency = asked.elapsed();
        eprintln!("Pause stopped the loop after {latency:?}");
        assert_eq!(halt, Halt::Pause);
        assert!((2..=4).contains(&line), "stopped on line {line}, in the loop");
        assert!(latency < Duration::from_secs(1), "{latency:?}");
        console.kill_controller();
        assert_eq!(console.end(), Ended::ControllerGone);
    }

    #[test]
    fn pause_reaches_a_loop_inside_a_coroutine() {
        let main = "\
local co = coroutine.create(function()
  local n = 0
  while true do
    n = n + 1 -- @loop
  end
end)
assert(not coroutine.resume(co))
while true do end -- a program that swallowed the error would loop here
";
        let mut console = Console::start(main, &[], RunMode::Release, &[]);
        eventually("the loop", || console.slot().line() != 0);
        let (halt, line) = console.command(DebugCommand::Pause);
        assert_eq!(halt, Halt::Pause);
        assert!((3..=5).contains(&line), "stopped on line {line}, in the coroutine's loop");
        console.kill_controller();
        assert_eq!(console.end(), Ended::ControllerGone);
    }

    #[test]
    fn steps_follow_the_main_function_across_a_coroutine() {
        let main = "\
local co = coroutine.wrap(function()
  local x = 1 -- @inside
  coroutine.yield(x)
  return x
end)
local v = co() -- @resume
v = v + 1 -- @next
result = v
";
        let resume = line_of(main, "@resume");
        let mut console = Console::start(main, &[], RunMode::Debug, &[resume]);
        assert_eq!(console.stopped(), (Halt::BreakPoint, resume));
        assert_eq!(console.command(DebugCommand::StepInto), (Halt::Pause, line_of(main, "@inside")));
        assert_eq!(console.command(DebugCommand::StepOut), (Halt::Pause, line_of(main, "@next")), "out at the yield");
        console.command(DebugCommand::Continue);
        assert_eq!(console.end(), Ended::Normally);

        let mut console = Console::start(main, &[], RunMode::Debug, &[resume]);
        console.stopped();
        assert_eq!(console.command(DebugCommand::StepOver), (Halt::Pause, line_of(main, "@next")));
        console.command(DebugCommand::Continue);
        assert_eq!(console.end(), Ended::Normally);
    }

    #[test]
    fn lines_of_a_module_never_stop_the_program() {
        let main = "\
local util = require('util')
local s = util.sum(4) -- @call
result = s -- @after
";
        let util = "\
local M = {}

function M.sum(n)
  local s = 0
  for i = 1, n do
    s = s + i
  end
  return s
end

return M
";
        let call = line_of(main, "@call");
        // Lines 4 to 11 exist in the module only; the module's lines 1 to 3 run too.
        let breakpoints = [call, 4, 5, 6, 7, 8, 9, 10, 11];
        let mut console = Console::start(main, &[("util.lua", util)], RunMode::Debug, &breakpoints);
        assert_eq!(console.stopped(), (Halt::BreakPoint, call));
        assert_eq!(console.command(DebugCommand::StepInto), (Halt::Pause, line_of(main, "@after")));
        console.command(DebugCommand::Continue);
        assert_eq!(console.end(), Ended::Normally);
    }

    #[test]
    fn block_run_stops_before_the_first_line_and_continue_runs_to_the_end() {
        let main = "local a = 1\nlocal b = a + 1\nresult = b\n";
        let mut console = Console::start(main, &[], RunMode::Block, &[]);
        assert_eq!(console.stopped(), (Halt::Pause, 1));
        assert_eq!(console.command(DebugCommand::Continue).0, Halt::None);
        assert_eq!(console.end(), Ended::Normally);
        assert_eq!(console.slot().state(), RunState::Finished);
    }

    #[test]
    fn a_breakpoint_added_while_running_is_honoured() {
        let mut console = Console::start(LOOP_FOREVER, &[], RunMode::Debug, &[]);
        eventually("the loop", || console.slot().line() != 0);
        eventually("0x6B02 follows the running loop", || console.slot().debug.main_line() != 0);
        let bp = line_of(LOOP_FOREVER, "@loop");
        assert!(console.slot().debug.add_breakpoint(bp));
        assert_eq!(console.stopped(), (Halt::BreakPoint, bp));
        console.kill_controller();
        assert_eq!(console.end(), Ended::ControllerGone);
    }

    /// A program that spends nearly all its time waiting: a sample seldom finds it running
    /// Lua, but the breakpoint's news arms the hook for its next instruction.
    #[test]
    fn a_breakpoint_added_while_the_program_waits_is_honoured_at_once() {
        let main = "while true do\n  wait_ms(20) -- @wait\nend\n";
        let mut console = Console::start(main, &[], RunMode::Debug, &[]);
        eventually("the loop", || console.slot().state() == RunState::Waiting);
        let bp = line_of(main, "@wait");
        let added = Instant::now();
        assert!(console.slot().debug.add_breakpoint(bp));
        assert_eq!(console.stopped(), (Halt::BreakPoint, bp));
        let took = added.elapsed();
        assert!(took < Duration::from_secs(1), "stopped {took:?} after the breakpoint was added");
        console.kill_controller();
        assert_eq!(console.end(), Ended::ControllerGone);
    }

    #[test]
    fn a_step_the_program_ends_during_is_done_at_the_end() {
        let main = "local a = 1\nresult = a\n";
        let mut console = Console::start(main, &[], RunMode::Debug, &[2]);
        assert_eq!(console.stopped(), (Halt::BreakPoint, 2));
        assert_eq!(console.command(DebugCommand::StepOver), (Halt::None, 2));
        assert_eq!(console.end(), Ended::Normally);
    }

    /// No hook while nothing needs one: the first line's hook and a sample each take
    /// themselves off (with the old count hook the mask was never 0).
    #[test]
    fn the_hook_is_off_after_a_sample() {
        let main = "\
local spins = 0
while line_now() ~= 2 do spins = spins + 1 end -- @spin
assert(hook_mask() == 0, 'a hook after the sample')
";
        assert_eq!(line_of(main, "@spin"), 2);
        let mut console = Console::start(main, &[], RunMode::Release, &[]);
        assert_eq!(console.end(), Ended::Normally);
        assert_eq!(console.slot().line(), 2, "sampled in the loop, not since");
        assert_eq!(console.table.slots[TASK].debug.main_line(), 2, "0x6B02 follows the sample");
    }

    /// A program that never calls the API is sampled: the watchdog's report names the line
    /// it hangs on, in the main chunk, in a coroutine, and in a loop of C string calls.
    #[test]
    fn a_hung_loop_is_sampled_at_its_line() {
        let programs = [
            "local n = 0\nn = n + 1\nwhile true do n = n + 1 end -- @hang\n",
            "local co = coroutine.wrap(function()\n  local n = 0\n  while true do n = n + 1 end -- @hang\nend)\nco()\n",
            "local s = string.rep('ab', 50)\n\nwhile true do local t = s:rep(3) .. s; local a = t:find('ba', 1, true) end -- @hang\n",
        ];
        for main in programs {
            let hang = line_of(main, "@hang");
            let mut console = Console::start(main, &[], RunMode::Release, &[]);
            eventually(&format!("line {hang} of {main}"), || console.slot().line() == hang);
            // Pause reaches it too, and ends it with the controller gone.
            let (halt, line) = console.command(DebugCommand::Pause);
            assert_eq!((halt, line), (Halt::Pause, hang), "{main}");
            console.kill_controller();
            assert_eq!(console.end(), Ended::ControllerGone, "{main}");
        }
    }
}

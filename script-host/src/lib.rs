//! A script process: one user program in one sandboxed Lua VM, talking to its controller.
//!
//! Every API call advances the task's heartbeat (see `bindings`), so that the controller's
//! watchdog can tell a program stuck in Lua from a waiting one; the VM's hook (`debugger`),
//! armed by a signal while the program runs Lua (`arming`), records the line being run, for
//! the watchdog's report, and carries out the console's program control (DXMC manual A.3).

pub(crate) mod arming;
pub mod bindings;
pub mod debugger;
pub(crate) mod printf;
pub(crate) mod require;
pub mod sandbox;

use std::path::PathBuf;
use std::rc::Rc;

use api::SystemError;
use ipc::pool::{Assignment, POOL_NODE_NAME};
use ipc::services::DeadNodes;
use ipc::shm::Region;
use ipc::task_table::{EndCode, RunState, TaskSlot, TaskTable};
use ipc::{IpcError, Namespace, PreparedEndpoint, TaskEndpoint};
use schema::shared::SharedData;

use bindings::Host;
pub use bindings::freeport_sim::FreePortInputs;
use debugger::{Debugger, SharedTable};

/// What a script process (`luamotion script`) is started with: its task and program, and
/// where the outside world is.
pub struct ScriptArgs {
    /// The controller's namespace (`--ns`), which names every shared-memory service.
    pub ns: Namespace,
    /// The HMPL task id, 0..63, whose slot and mailbox the program uses.
    pub task: u8,
    /// The controller's pid: the process ends at once if its parent is not (or no longer)
    /// that controller.
    pub controller_pid: u32,
    /// The Lua VM's memory limit, MiB (the task's `memory_limit_mib`).
    pub memory_limit_mib: u32,
    /// Where `SaveUserTable` keeps its file.
    pub data_dir: PathBuf,
    /// `StartTaskFunc`: the function to run after the program's top level.
    pub entry: Option<String>,
    /// The Lua file to run; its folder is where `require` looks.
    pub program: PathBuf,
    /// Where `START_ASCII_AGENT` listens, `host:port` (HMPL 22.1).
    pub user_ascii: String,
    /// Where `FreePort.Eth.OpenAsServer` listens.
    pub freeport_bind: std::net::IpAddr,
    /// On the simulation clock: where FreePort's inputs are recorded or replayed from.
    pub freeport_inputs: FreePortInputs,
}

/// A pooled process (`script --pool <place>`): what it knows before the core hands it a task.
pub struct PoolArgs {
    /// The controller's namespace, as `ScriptArgs::ns`.
    pub ns: Namespace,
    /// Its place on the task table's pool board.
    pub place: usize,
    /// The controller's pid, as `ScriptArgs::controller_pid`.
    pub controller_pid: u32,
    /// Where `SaveUserTable` keeps its file, as `ScriptArgs::data_dir`.
    pub data_dir: PathBuf,
    /// Where `START_ASCII_AGENT` listens, as `ScriptArgs::user_ascii`.
    pub user_ascii: String,
    /// Where `FreePort.Eth.OpenAsServer` listens, as `ScriptArgs::freeport_bind`.
    pub freeport_bind: std::net::IpAddr,
    /// The FreePort inputs on the simulation clock, as `ScriptArgs::freeport_inputs`.
    pub freeport_inputs: FreePortInputs,
}

impl PoolArgs {
    fn assign(self, assignment: Assignment, program: PathBuf) -> ScriptArgs {
        ScriptArgs {
            ns: self.ns,
            task: assignment.task,
            controller_pid: self.controller_pid,
            memory_limit_mib: assignment.memory_limit_mib,
            data_dir: self.data_dir,
            entry: assignment.entry,
            program,
            user_ascii: self.user_ascii,
            freeport_bind: self.freeport_bind,
            freeport_inputs: self.freeport_inputs,
        }
    }
}

/// Why a program did not end normally.
#[derive(Debug, thiserror::Error)]
pub enum ScriptError {
    /// A syntax or runtime error: `file:line: message`, and the Lua traceback if any.
    #[error("{message}")]
    Lua {
        /// `file:line: message`, as Lua's own interpreter writes it.
        message: String,
        /// Lua's `stack traceback:` lines, when the error carried them.
        traceback: Option<String>,
    },
    /// The program's file could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The program.
        path: PathBuf,
        /// Why it could not be read.
        source: std::io::Error,
    },
    /// The task's endpoint, the shared data or the event stream could not be opened.
    #[error("cannot reach the controller: {0}")]
    Ipc(#[from] IpcError),
    /// The controller ended (or was never this process' parent): nothing to report to.
    #[error("the controller is gone")]
    ControllerGone,
    /// A pooled process was started for a place the pool's board does not have.
    #[error("no place {0} on the pool's board")]
    NoPlace(usize),
    /// The VM went over its memory limit; the task ends with the memory-limit alarm.
    #[error("{message}")]
    OutOfMemory {
        /// `file: not enough memory near line N (the task's limit is M MiB)`.
        message: String,
    },
}

impl ScriptError {
    fn lua(message: String) -> Self {
        ScriptError::Lua { message, traceback: None }
    }

    /// What the controller reads in the task's slot about this end.
    fn end_code(&self) -> u32 {
        match self {
            ScriptError::OutOfMemory { .. } => EndCode::OutOfMemory.into(),
            // Lua's C stack or call depth ran out (endless recursion): HMPL's stack overflow.
            ScriptError::Lua { message, .. } if message.contains("stack overflow") => {
                SystemError::HmplStackOverflow.id() as u32
            }
            _ => EndCode::LuaError.into(),
        }
    }
}

/// Runs the program to its end.
pub fn run(args: ScriptArgs) -> Result<(), ScriptError> {
    die_with_controller(args.controller_pid)?;
    let source = read_program(&args)?;
    let endpoint = TaskEndpoint::open_with(&args.ns, args.task, args.controller_pid, DeadNodes::LeftToSupervisor)?;
    ipc::restore_default_signals();
    let host = Host::new(endpoint, &args.ns, args.data_dir.clone())?
        .with_user_ascii(args.user_ascii.clone())
        .with_freeport(args.freeport_bind, args.freeport_inputs.clone());
    let vm = Vm::new(host)?;
    run_attached(args, &source, vm)
}

/// How often a waiting process checks that its controller is still there.
const POOL_LIVENESS: std::time::Duration = std::time::Duration::from_millis(100);

/// A pooled process: everything a start does before it knows its task (the exec, the
/// node, the snapshot board opened, the VM with the API bound in it) is done while it waits on
/// its place of the pool's board; the core hands it a task there, and it runs that one
/// task as `run` does, and ends. The VM is this task's alone: no other program ran in it.
pub fn run_pooled(pool: PoolArgs) -> Result<(), ScriptError> {
    die_with_controller(pool.controller_pid)?;
    set_process_name(WAITING_NAME);
    let prepared = PreparedEndpoint::new(&pool.ns, POOL_NODE_NAME, pool.controller_pid, DeadNodes::LeftToSupervisor)?;
    let events = prepared.event_sender(&pool.ns)?;
    let shared = Region::<SharedData>::open(&pool.ns, "shared")?;
    let table = Region::<TaskTable>::open(&pool.ns, "tasks")?;
    ipc::restore_default_signals();
    let host = Host::from_parts(prepared.standby(), events, shared, &pool.ns, pool.data_dir.clone())
        .with_user_ascii(pool.user_ascii.clone())
        .with_freeport(pool.freeport_bind, pool.freeport_inputs.clone());
    let vm = Vm::new(host)?;
    let place = table.pool.places.get(pool.place).ok_or(ScriptError::NoPlace(pool.place))?;
    let controller_pid = pool.controller_pid;
    // Closed or withdrawn: the controller is ending or gone.
    let assignment = place
        .offer(std::process::id())
        .then(|| place.wait(|| ipc::process_alive(controller_pid), POOL_LIVENESS))
        .flatten()
        .ok_or(ScriptError::ControllerGone)?;
    set_process_name(RUNNING_NAME);
    let program = PathBuf::from(table.slots[assignment.task as usize].program());
    let args = pool.assign(assignment, program);
    let source = read_program(&args)?;
    vm.host.attach(args.task)?;
    run_attached(args, &source, vm)
}

/// A VM with the API bound to its host: all of a start that does not depend on the task
/// (1 ms of CPU, most of what a pooled process did after it was handed its task). The
/// task's own part (its memory limit, `_TASKID_`, its program's `require`, the debugger,
/// the watcher) is `run_attached`'s.
struct Vm {
    lua: mlua::Lua,
    host: Rc<Host>,
}

impl Vm {
    fn new(host: Host) -> Result<Self, ScriptError> {
        let lua_error = |e: mlua::Error| ScriptError::lua(e.to_string());
        // No limit (0) until the task's is known.
        let lua = sandbox::new_vm(0).map_err(lua_error)?;
        let host = Rc::new(host);
        bindings::install(&lua, host.clone()).map_err(lua_error)?;
        bindings::install_system_variables(&lua, host.clone()).map_err(lua_error)?;
        bindings::install_print(&lua, host.clone()).map_err(lua_error)?;
        Ok(Vm { lua, host })
    }
}

/// Dies with the controller: SIGKILL when the controller's thread that started this
/// process ends, even on its `kill -9`. Set here rather than between fork and exec, so
/// that the controller can start scripts with `posix_spawn` (a fork copies its locked
/// memory's page tables, and exec throws the copy away: most of a start's CPU time).
fn die_with_controller(controller_pid: u32) -> Result<(), ScriptError> {
    // SAFETY: plain prctl with constant arguments; getppid cannot fail.
    let parent = unsafe {
        libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL);
        libc::getppid()
    };
    // A controller that died before the prctl left this process to another parent.
    if parent as u32 != controller_pid {
        return Err(ScriptError::ControllerGone);
    }
    Ok(())
}

/// What `ps` shows of a waiting process, and of one that runs its task (the executable's
/// own name, as a process started for the task shows).
const WAITING_NAME: &std::ffi::CStr = c"luamotion-pool";
const RUNNING_NAME: &std::ffi::CStr = c"luamotion";

fn set_process_name(name: &std::ffi::CStr) {
    // SAFETY: PR_SET_NAME reads a NUL-terminated string of at most 16 bytes.
    unsafe { libc::prctl(libc::PR_SET_NAME, name.as_ptr()) };
}

fn read_program(args: &ScriptArgs) -> Result<String, ScriptError> {
    std::fs::read_to_string(&args.program).map_err(|source| ScriptError::Read { path: args.program.clone(), source })
}

fn run_attached(args: ScriptArgs, source: &str, vm: Vm) -> Result<(), ScriptError> {
    let Vm { lua, host } = vm;
    let table = Rc::new(Region::<TaskTable>::open(&args.ns, "tasks")?);
    let task = args.task as usize;

    let memory_limit = args.memory_limit_mib as usize * 1024 * 1024;
    let lua_error = |e: mlua::Error| ScriptError::lua(e.to_string());
    lua.set_memory_limit(memory_limit).map_err(lua_error)?;
    bindings::set_task_id(&lua, args.task).map_err(lua_error)?;
    require::install(&lua, &args.program).map_err(lua_error)?;

    let name = args.program.display().to_string();
    let controller_pid = args.controller_pid;
    let debugger = Debugger::new(table.clone() as SharedTable, task, chunk_name(&name), move || {
        ipc::process_alive(controller_pid)
    });
    debugger.install(&lua).map_err(|e| ScriptError::lua(e.to_string()))?;
    // The watcher maps the task table for itself: a mapping belongs to one thread.
    let ns = args.ns.clone();
    let watcher = arming::Watcher::start(&lua, move || {
        let watched = Region::<TaskTable>::open(&ns, "tasks").ok();
        let when = debugger::ArmWhen::default();
        move || watched.as_ref().is_some_and(|t| when.now(&t.slots[task]))
    })
    .map_err(|e| ScriptError::lua(e.to_string()))?;
    let slot = &table.slots[task];
    // HMPL 22.2.1: an agent the program started outlives it, until the task is stopped.
    let result = start(&lua, source, &name, args.entry.as_deref(), slot, &host)
        .and_then(|()| bindings::expectations_verdict(&host, &name))
        .and_then(|()| bindings::serve_agent_forever(&lua, &host))
        .map_err(|e| describe(e, &name, slot.line(), memory_limit));
    // Closing the VM runs the finalizers (`__gc`) left: user code, so still under the
    // watchdog as a running task, before the controller hears the program has ended. The
    // watcher goes first: it keeps the VM alive.
    drop(watcher);
    drop(lua);
    // Before Finished: a console waiting for a step sees it carried out when the program ends.
    debugger.finish();
    if let Err(e) = &result
        && slot.end_code() == 0
    {
        slot.set_end_code(e.end_code());
    }
    // The end code first: the core reacts to a failed end as soon as it sees Finished.
    slot.set_state(RunState::Finished);
    // On the simulation clock the core may be waiting for this turn to end.
    table.park(args.task);
    result
}

/// The program file's chunk name: Lua's messages give `<name>:<line>`, and the debugger
/// stops in this chunk only.
fn chunk_name(name: &str) -> String {
    format!("@{name}")
}

/// HMPL 16.2/16.3: a program runs from its top level; with an entry, its top level runs
/// first (declarations) and then the named function. The controller hears the task has
/// started once the entry is known to exist.
fn start(
    lua: &mlua::Lua,
    source: &str,
    name: &str,
    entry: Option<&str>,
    slot: &TaskSlot,
    host: &Host,
) -> mlua::Result<()> {
    let chunk = lua.load(source).set_name(chunk_name(name)).into_function()?;
    // On the simulation clock a started program waits for its first turn.
    let started = || {
        slot.mark_started();
        host.endpoint.borrow_mut().first_turn().map_err(mlua::Error::external)
    };
    let Some(entry) = entry else {
        started()?;
        return sandbox::call_program(lua, &chunk);
    };
    sandbox::call_program(lua, &chunk)?;
    match lua.globals().raw_get::<mlua::Value>(entry)? {
        mlua::Value::Function(function) => {
            started()?;
            sandbox::call_program(lua, &function)
        }
        _ => {
            slot.set_end_code(SystemError::FuncNotInTask.id() as u32);
            Err(mlua::Error::runtime(format!("{name}: no function {entry} (0x0109 eERR_FUNC_NOT_IN_TASK)")))
        }
    }
}

/// Turns a Lua error into the one line a user needs: `file:line: message`.
fn describe(error: mlua::Error, program: &str, last_line: u32, memory_limit: usize) -> ScriptError {
    match sandbox::root_cause(&error) {
        mlua::Error::ExternalError(e) if matches!(e.downcast_ref::<IpcError>(), Some(IpcError::ControllerGone)) => {
            ScriptError::ControllerGone
        }
        mlua::Error::SyntaxError { message, .. } => ScriptError::lua(message.clone()),
        mlua::Error::RuntimeError(text) => match text.split_once("\nstack traceback:") {
            Some((message, traceback)) => ScriptError::Lua {
                message: message.to_string(),
                traceback: Some(format!("stack traceback:{traceback}")),
            },
            None => ScriptError::lua(text.clone()),
        },
        // Lua reports no position for memory errors; the heartbeat hook saw the line last run.
        mlua::Error::MemoryError(_) => {
            let near = if last_line > 0 { format!(" near line {last_line}") } else { String::new() };
            ScriptError::OutOfMemory {
                message: format!("{program}: not enough memory{near} (the task's limit is {} MiB)", memory_limit >> 20),
            }
        }
        other => ScriptError::lua(format!("{program}: {other}")),
    }
}

//! A script process: one user program in one sandboxed Lua VM, talking to its controller.
//!
//! The VM's instruction hook bumps the task's heartbeat and records the line being run,
//! so that the controller's watchdog can tell a hung program from a waiting one.

pub mod bindings;
pub mod printf;
pub mod sandbox;

use std::path::PathBuf;
use std::rc::Rc;

use ipc::shm::Region;
use ipc::task_table::{RunState, TaskTable};
use ipc::{IpcError, Namespace, TaskEndpoint};
use mlua::{HookTriggers, VmState};

use bindings::Host;

/// VM instructions between two heartbeats: a few microseconds of Lua.
const HEARTBEAT_INSTRUCTIONS: u32 = 1000;

pub struct ScriptArgs {
    pub ns: Namespace,
    pub task: u8,
    pub controller_pid: u32,
    pub memory_limit_mib: u32,
    pub program: PathBuf,
}

/// Why a program did not end normally.
#[derive(Debug, thiserror::Error)]
pub enum ScriptError {
    /// A syntax or runtime error: `file:line: message`, and the Lua traceback if any.
    #[error("{message}")]
    Lua { message: String, traceback: Option<String> },
    #[error("cannot read {path}: {source}")]
    Read { path: PathBuf, source: std::io::Error },
    #[error("cannot reach the controller: {0}")]
    Ipc(#[from] IpcError),
    #[error("the controller is gone")]
    ControllerGone,
}

impl ScriptError {
    fn lua(message: String) -> Self {
        ScriptError::Lua { message, traceback: None }
    }
}

/// Runs the program to its end.
pub fn run(args: ScriptArgs) -> Result<(), ScriptError> {
    let source = std::fs::read_to_string(&args.program)
        .map_err(|source| ScriptError::Read { path: args.program.clone(), source })?;
    let endpoint = TaskEndpoint::open(&args.ns, args.task, args.controller_pid)?;
    ipc::restore_default_termination();
    let table = Region::<TaskTable>::open(&args.ns, "tasks")?;
    let task = args.task as usize;

    let memory_limit = args.memory_limit_mib as usize * 1024 * 1024;
    let lua = sandbox::new_vm(memory_limit).map_err(|e| ScriptError::lua(e.to_string()))?;
    let host = Rc::new(Host { endpoint: std::cell::RefCell::new(endpoint) });
    bindings::install(&lua, host.clone()).map_err(|e| ScriptError::lua(e.to_string()))?;
    bindings::install_system_variables(&lua, host).map_err(|e| ScriptError::lua(e.to_string()))?;
    bindings::install_print(&lua).map_err(|e| ScriptError::lua(e.to_string()))?;

    let name = args.program.display().to_string();
    let table = Rc::new(table);
    let result = {
        let hook_table = table.clone();
        lua.set_hook(HookTriggers::new().every_nth_instruction(HEARTBEAT_INSTRUCTIONS), move |_, debug| {
            let slot = &hook_table.slots[task];
            slot.beat();
            if let Some(line) = debug.current_line() {
                slot.set_line(line as u32);
            }
            Ok(VmState::Continue)
        })
        .map_err(|e| ScriptError::lua(e.to_string()))?;
        let result = lua.load(source).set_name(format!("@{name}")).exec();
        table.slots[task].set_state(RunState::Finished);
        result
    };
    let last_line = table.slots[task].line();
    result.map_err(|e| describe(e, &name, last_line, memory_limit))
}

/// Turns a Lua error into the one line a user needs: `file:line: message`.
fn describe(error: mlua::Error, program: &str, last_line: u32, memory_limit: usize) -> ScriptError {
    let mut cause = &error;
    loop {
        match cause {
            mlua::Error::CallbackError { cause: inner, .. } => cause = inner,
            mlua::Error::WithContext { cause: inner, .. } => cause = inner,
            _ => break,
        }
    }
    match cause {
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
            ScriptError::lua(format!(
                "{program}: not enough memory{near} (the task's limit is {} MiB)",
                memory_limit >> 20
            ))
        }
        other => ScriptError::lua(format!("{program}: {other}")),
    }
}

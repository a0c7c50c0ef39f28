//! The Lua globals of the API, derived from the registry: every function of
//! `api::registry::all()` becomes a global of the same name, with its arguments checked
//! against the registry's types and its results returned as the registry says. Commands
//! and queries are here; the functions that run in the script process are in `locals`,
//! the system variables in `system_vars`.

mod locals;
mod system_vars;
mod timer;

use std::cell::{Cell, RefCell};
use std::io::Write;
use std::path::PathBuf;
use std::rc::Rc;

use api::constants::{CONSTANTS, Constant, error_ids, numbered};
use api::{ArgType, Command, Func, FunctionSpec, Query, SdoAbort, ValueType};
use calls::query::{self, Words};
use ipc::events::EventSender;
use ipc::messages::Request;
use ipc::output::{Lines, MAX_LINE_BYTES, cut_marker};
use ipc::shared::SharedData;
use ipc::shm::Region;
use ipc::{IpcError, Namespace, TaskEndpoint};
use mlua::{BorrowedBytes, Function, Lua, MultiValue, Value};

use locals::Throttle;
pub use system_vars::install_system_variables;

/// What the bindings share: the link to the controller, the shared data, the event stream.
pub struct Host {
    pub endpoint: RefCell<TaskEndpoint>,
    pub shared: Region<SharedData>,
    pub task: u8,
    /// Where `SaveUserTable` keeps its file.
    pub data_dir: PathBuf,
    events: EventSender,
    throttle: Cell<Throttle>,
}

impl Host {
    pub fn new(endpoint: TaskEndpoint, ns: &Namespace, data_dir: PathBuf) -> Result<Self, IpcError> {
        let events = endpoint.event_sender(ns)?;
        let shared = Region::<SharedData>::open(ns, "shared")?;
        let task = endpoint.task();
        Ok(Host {
            endpoint: RefCell::new(endpoint),
            shared,
            task,
            data_dir,
            events,
            throttle: Cell::new(Throttle::default()),
        })
    }

    /// Every API call advances the heartbeat: a task that calls nothing while it runs Lua
    /// is what the watchdog looks for.
    fn beat(&self) {
        self.endpoint.borrow().slot().beat();
    }
}

/// Installs every API function and constant as a global.
pub fn install(lua: &Lua, host: Rc<Host>) -> mlua::Result<()> {
    let globals = lua.globals();
    for spec in api::registry::all() {
        let function = match spec.func {
            Func::Command(c) => command(lua, host.clone(), c)?,
            Func::Query(q) => status_query(lua, host.clone(), q)?,
            Func::Local(l) => locals::local(lua, host.clone(), l)?,
        };
        globals.set(spec.name, function)?;
    }
    for (name, value, _) in CONSTANTS {
        let value = match value {
            Constant::Int(i) => Value::Integer(*i),
            Constant::Double(d) => Value::Number(*d),
            Constant::Str(s) => Value::String(lua.create_string(s)?),
        };
        globals.set(*name, value)?;
    }
    for (name, id) in error_ids() {
        globals.set(name, id as i64)?;
    }
    for (name, value) in numbered() {
        globals.set(name, value)?;
    }
    Ok(())
}

/// An error at the Lua line that called the binding (through `pcall` too), as
/// `luaL_error` words it.
pub fn error_here(lua: &Lua, message: impl std::fmt::Display) -> mlua::Error {
    mlua::Error::runtime(format!("{}{message}", crate::sandbox::raised_at(lua)))
}

fn bad_argument(lua: &Lua, spec: &FunctionSpec, i: usize, expected: &str, got: &Value) -> mlua::Error {
    error_here(lua, format!("bad argument #{} to '{}' ({expected} expected, got {})", i + 1, spec.name, type_name(got)))
}

/// A value as a message names it: numbers with their value.
fn type_name(v: &Value) -> String {
    match v {
        Value::Integer(n) => format!("integer {n}"),
        Value::Number(n) => format!("number {n}"),
        other => other.type_name().to_string(),
    }
}

fn int_arg(lua: &Lua, spec: &FunctionSpec, args: &MultiValue, i: usize) -> mlua::Result<i64> {
    let v = args.get(i).cloned().unwrap_or(Value::Nil);
    match v {
        Value::Integer(n) => Ok(n),
        Value::Number(n) if n.fract() == 0.0 && n.abs() < 9.0e15 => Ok(n as i64),
        other => Err(bad_argument(lua, spec, i, "integer", &other)),
    }
}

fn double_arg(lua: &Lua, spec: &FunctionSpec, args: &MultiValue, i: usize) -> mlua::Result<f64> {
    match args.get(i).cloned().unwrap_or(Value::Nil) {
        Value::Integer(n) => Ok(n as f64),
        Value::Number(n) => Ok(n),
        other => Err(bad_argument(lua, spec, i, "number", &other)),
    }
}

/// A C `int` condition: a boolean, or a number where 0 is false.
fn bool_arg(lua: &Lua, spec: &FunctionSpec, args: &MultiValue, i: usize) -> mlua::Result<bool> {
    match args.get(i).cloned().unwrap_or(Value::Nil) {
        Value::Boolean(b) => Ok(b),
        Value::Integer(n) => Ok(n != 0),
        Value::Number(n) => Ok(n != 0.0),
        other => Err(bad_argument(lua, spec, i, "boolean or number", &other)),
    }
}

fn string_arg(lua: &Lua, spec: &FunctionSpec, args: &MultiValue, i: usize) -> mlua::Result<String> {
    match args.get(i).cloned().unwrap_or(Value::Nil) {
        Value::String(s) => match s.to_str() {
            Ok(text) => Ok(text.to_string()),
            Err(_) => Err(bad_argument(lua, spec, i, "UTF-8 string", &Value::String(s))),
        },
        Value::Integer(n) => Ok(n.to_string()),
        Value::Number(n) => Ok(n.to_string()),
        other => Err(bad_argument(lua, spec, i, "string", &other)),
    }
}

/// A string argument as the Lua string it is (a number as its text), any bytes.
fn lua_string_arg(lua: &Lua, spec: &FunctionSpec, args: &MultiValue, i: usize) -> mlua::Result<mlua::LuaString> {
    match args.get(i).cloned().unwrap_or(Value::Nil) {
        Value::String(s) => Ok(s),
        Value::Integer(n) => lua.create_string(n.to_string()),
        Value::Number(n) => lua.create_string(n.to_string()),
        other => Err(bad_argument(lua, spec, i, "string", &other)),
    }
}

/// `uint8_t*` arguments: a table of integers 0..255, or a string.
fn bytes_arg(lua: &Lua, spec: &FunctionSpec, args: &MultiValue, i: usize) -> mlua::Result<Vec<u8>> {
    match args.get(i).cloned().unwrap_or(Value::Nil) {
        Value::String(s) => Ok(s.as_bytes().to_vec()),
        Value::Table(t) => t
            .sequence_values::<Value>()
            .map(|v| match v? {
                Value::Integer(b) if (0..=255).contains(&b) => Ok(b as u8),
                other => Err(bad_argument(lua, spec, i, "table of integers 0..255", &other)),
            })
            .collect(),
        other => Err(bad_argument(lua, spec, i, "table of bytes or string", &other)),
    }
}

/// `double*` arguments: a table of numbers.
fn doubles_arg(lua: &Lua, spec: &FunctionSpec, args: &MultiValue, i: usize) -> mlua::Result<Vec<f64>> {
    match args.get(i).cloned().unwrap_or(Value::Nil) {
        Value::Table(t) => t
            .sequence_values::<Value>()
            .map(|v| match v? {
                Value::Integer(n) => Ok(n as f64),
                Value::Number(n) => Ok(n),
                other => Err(bad_argument(lua, spec, i, "table of numbers", &other)),
            })
            .collect(),
        other => Err(bad_argument(lua, spec, i, "table of numbers", &other)),
    }
}

/// Encodes the arguments as the registry types them: scalars as words, bytes and arrays in
/// the blob, one after the other, with their lengths as words.
fn encode(lua: &Lua, spec: &FunctionSpec, args: &MultiValue, request: &mut Request) -> mlua::Result<()> {
    for (i, arg) in spec.args.iter().enumerate() {
        match arg.ty {
            ArgType::Int => request.push_int(int_arg(lua, spec, args, i)?),
            ArgType::Double => request.push_double(double_arg(lua, spec, args, i)?),
            ArgType::Bytes => {
                let bytes = bytes_arg(lua, spec, args, i)?;
                append(lua, spec, request, &bytes)?;
                request.push_int(bytes.len() as i64);
            }
            ArgType::Doubles => {
                let numbers = doubles_arg(lua, spec, args, i)?;
                let bytes: Vec<u8> = numbers.iter().flat_map(|n| n.to_le_bytes()).collect();
                append(lua, spec, request, &bytes)?;
                request.push_int(numbers.len() as i64);
            }
            ArgType::Str => {
                let text = string_arg(lua, spec, args, i)?;
                append(lua, spec, request, text.as_bytes())?;
                request.push_int(text.len() as i64);
            }
            ArgType::Bool => request.push_int(bool_arg(lua, spec, args, i)? as i64),
            ArgType::Func | ArgType::Rest | ArgType::Timer => {
                return Err(error_here(lua, format!("{}: not callable with a {:?} argument", spec.name, arg.ty)));
            }
        }
    }
    Ok(())
}

fn append(lua: &Lua, spec: &FunctionSpec, request: &mut Request, bytes: &[u8]) -> mlua::Result<()> {
    if !request.append_blob(bytes) {
        return Err(error_here(lua, format!("{}: the arguments exceed {} bytes", spec.name, request.blob.len())));
    }
    Ok(())
}

fn bytes_table(lua: &Lua, bytes: &[u8]) -> mlua::Result<Value> {
    Ok(Value::Table(lua.create_sequence_from(bytes.iter().map(|&b| b as i64))?))
}

/// A command: one round trip to the core; returns what the registry says it returns.
fn command(lua: &Lua, host: Rc<Host>, command: Command) -> mlua::Result<Function> {
    let spec = command.spec();
    lua.create_function(move |lua, args: MultiValue| {
        host.beat();
        let mut request = Request::new(command.id());
        encode(lua, spec, &args, &mut request)?;
        let reply = host.endpoint.borrow_mut().call(&mut request).map_err(mlua::Error::external)?;
        let first = reply.values[0] as i64;
        if first == -1 && reply.rc != 0 {
            // Ch. 17 says only -1; say why, once, where the user sees it.
            eprintln!("warning: {}: {}", spec.name, explain(reply.rc));
        }
        let mut results = MultiValue::new();
        for (i, ty) in spec.returns.iter().enumerate() {
            results.push_back(match ty {
                ValueType::Bytes => bytes_table(lua, reply.blob())?,
                ValueType::Bool => Value::Boolean(reply.values[i] != 0),
                _ => Value::Integer(reply.values[i] as i64),
            });
        }
        Ok(results)
    })
}

/// Why a call failed, from its reply's `rc`: an SDO abort code or an HMPL error code.
fn explain(rc: u32) -> String {
    match SdoAbort::try_from(rc) {
        Ok(abort) => abort.to_string(),
        Err(_) => api::errors::describe(rc),
    }
}

/// A status query: read the local snapshot, no round trip.
fn status_query(lua: &Lua, host: Rc<Host>, query: Query) -> mlua::Result<Function> {
    let spec = query.spec();
    lua.create_function(move |lua, args: MultiValue| {
        host.beat();
        let mut request = Request::new(0);
        encode(lua, spec, &args, &mut request)?;
        let answer = {
            let mut endpoint = host.endpoint.borrow_mut();
            query::evaluate(query, Words(&request.args[..request.argc as usize]), endpoint.snapshot())
        };
        let query::Answer(first, second) = answer.map_err(|code| error_here(lua, format!("{}: {code}", spec.name)))?;
        let mut results = MultiValue::new();
        for value in std::iter::once(first).chain(second) {
            results.push_back(match value {
                query::Value::Bool(b) => Value::Boolean(b),
                query::Value::Int(i) => Value::Integer(i),
                query::Value::Double(d) => Value::Number(d),
                query::Value::Bytes { data, len } => bytes_table(lua, &data[..len as usize])?,
            });
        }
        Ok(results)
    })
}

/// Program output, one call's worth: the pieces are written one after the other, each line
/// cut to `MAX_LINE_BYTES` with a marker, and a newline added unless the text ends with one.
/// The controller puts the task id in front.
pub fn write_output(pieces: &[&[u8]]) {
    let mut out = std::io::stdout().lock();
    let mut lines = Lines::new(MAX_LINE_BYTES);
    {
        let mut write = |line: &[u8], cut: u64| {
            let _ = out.write_all(line);
            if cut > 0 {
                let _ = out.write_all(cut_marker(cut).as_bytes());
            }
            let _ = out.write_all(b"\n");
        };
        for piece in pieces {
            lines.feed(piece, &mut write);
        }
        if pieces.iter().rev().find(|p| !p.is_empty()).is_none_or(|p| !p.ends_with(b"\n")) {
            lines.feed(b"\n", &mut write);
        }
    }
    let _ = out.flush();
}

/// Lua's own `print`, through the same output. Values become text with the VM's own
/// `tostring` (taken before the program runs), in the program's memory.
pub fn install_print(lua: &Lua) -> mlua::Result<()> {
    let tostring: Function = lua.globals().get("tostring")?;
    let print = lua.create_function(move |_, args: MultiValue| {
        let texts: Vec<mlua::LuaString> = args
            .into_iter()
            .map(|v| match v {
                Value::String(s) => Ok(s),
                other => tostring.call(other),
            })
            .collect::<mlua::Result<_>>()?;
        let bytes: Vec<BorrowedBytes> = texts.iter().map(mlua::LuaString::as_bytes).collect();
        let mut pieces: Vec<&[u8]> = Vec::with_capacity(2 * bytes.len());
        for (i, text) in bytes.iter().enumerate() {
            if i > 0 {
                pieces.push(b"\t");
            }
            pieces.push(text);
        }
        write_output(&pieces);
        Ok(())
    })?;
    lua.globals().set("print", print)
}

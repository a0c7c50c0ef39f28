//! The Lua globals of the API, derived from the registry: every function of
//! `api::registry::all()` becomes a global of the same name, with its arguments checked
//! against the registry's types and its results returned as the registry says. Commands
//! and queries are here; the functions that run in the script process are in `locals`,
//! the system variables in `system_vars`.

mod agent;
#[cfg(test)]
mod call_tests;
mod clients;
mod clients_sim;
mod expect;
mod freeport;
pub(crate) mod freeport_sim;
mod library;
mod locals;
mod plc;
mod print;
mod serial;
mod system_vars;
mod till_watch;
mod timer;

use std::cell::{Cell, RefCell};
use std::io::Write;
use std::path::PathBuf;
use std::rc::Rc;

use std::borrow::Cow;

use api::call::{self, ArgError, Doubles, Expected, Got, Source, TypedCall, ValueSource};
use api::constants::{CONSTANTS, Constant, error_ids, numbered};
use api::event_rate::Throttle;
use api::{
    ArgType, Command, CommandCall, ErrorCode, Func, FunctionSpec, Local, LocalCall, Query, QueryCall, SystemError,
};
use calls::{query, reply, wire};
use ipc::call::{Reply, Request};
use ipc::events::EventSender;
use ipc::output::{Lines, MAX_LINE_BYTES, cut_marker};
use ipc::shm::Region;
use ipc::{IpcError, Namespace, TaskEndpoint};
use mlua::{BorrowedBytes, Function, IntoLuaMulti, Lua, MultiValue, Value};
use schema::shared::SharedData;

pub use agent::{DEFAULT_ADDRESS as DEFAULT_USER_ASCII, serve as serve_agent, serve_forever as serve_agent_forever};
pub use expect::verdict as expectations_verdict;
pub use system_vars::{install_system_variables, set_task_id};

/// What the bindings share: the link to the controller, the shared data, the event stream.
pub struct Host {
    /// The script's end of the IPC: it posts the calls, waits on its bell for the replies
    /// and reads the snapshot.
    pub endpoint: RefCell<TaskEndpoint>,
    /// The data every process of the namespace maps: user table, test variables, mutexes,
    /// task variables, DV and DH.
    pub shared: Region<SharedData>,
    /// The task, once the endpoint is attached (`attach`).
    task: Cell<u8>,
    /// The controller's namespace (serial port 1's socket is named after it).
    pub ns: Namespace,
    /// Where `SaveUserTable` keeps its file.
    pub data_dir: PathBuf,
    /// Where `START_ASCII_AGENT` listens (HMPL 22.1, `[ascii]` of the machine file).
    pub user_ascii: String,
    /// Where `FreePort.Eth.OpenAsServer` listens (`[freeport] bind`).
    pub freeport_bind: std::net::IpAddr,
    /// On the simulation clock: where FreePort's and the ch. 22 clients' inputs are recorded
    /// or replayed from.
    pub freeport_inputs: freeport_sim::FreePortInputs,
    events: EventSender,
    throttle: Cell<Throttle>,
    /// The program's expectations so far (`luamotion test`).
    tally: Cell<expect::Tally>,
    /// What the `Till` condition being evaluated reads, on the simulation clock.
    watch: RefCell<till_watch::Recording>,
}

impl Host {
    /// The bindings' host of an attached task `endpoint`: it opens the task's event
    /// stream
    /// and the shared data of namespace `ns`.
    pub fn new(endpoint: TaskEndpoint, ns: &Namespace, data_dir: PathBuf) -> Result<Self, IpcError> {
        let events = endpoint.event_sender(ns)?;
        let shared = Region::<SharedData>::open(ns, "shared")?;
        Ok(Self::from_parts(endpoint, events, shared, ns, data_dir))
    }

    /// As `new`, with the event writer and the shared data opened before (a pooled
    /// process opens them while it waits for its task).
    pub fn from_parts(
        endpoint: TaskEndpoint,
        events: EventSender,
        shared: Region<SharedData>,
        ns: &Namespace,
        data_dir: PathBuf,
    ) -> Self {
        let task = endpoint.task();
        Host {
            endpoint: RefCell::new(endpoint),
            shared,
            task: Cell::new(task),
            ns: ns.clone(),
            data_dir,
            user_ascii: agent::DEFAULT_ADDRESS.to_string(),
            freeport_bind: std::net::IpAddr::from([127, 0, 0, 1]),
            freeport_inputs: freeport_sim::FreePortInputs::Live,
            events,
            throttle: Cell::new(Throttle::default()),
            tally: Cell::new(expect::Tally::default()),
            watch: RefCell::new(till_watch::Recording::Off),
        }
    }

    /// The task this process runs.
    pub fn task(&self) -> u8 {
        self.task.get()
    }

    /// Attaches an endpoint made in standby to task `task` (a pooled process, handed its task).
    pub fn attach(&self, task: u8) -> Result<(), IpcError> {
        self.endpoint.borrow_mut().attach(task)?;
        self.task.set(task);
        Ok(())
    }

    /// The User ASCII agent listens on `address` (`host:port`).
    pub fn with_user_ascii(mut self, address: String) -> Self {
        self.user_ascii = address;
        self
    }

    /// FreePort servers listen on `address`; on the simulation clock their inputs are
    /// recorded or replayed as `inputs` says.
    pub fn with_freeport(mut self, address: std::net::IpAddr, inputs: freeport_sim::FreePortInputs) -> Self {
        self.freeport_bind = address;
        self.freeport_inputs = inputs;
        self
    }

    /// Every API call advances the heartbeat: a task that calls nothing while it runs Lua
    /// is what the watchdog looks for. On the simulation clock it also counts toward the
    /// task's share of the cycle.
    fn beat(&self) {
        self.spoil_watch();
        self.count_call();
    }

    /// `beat` for a status query, which a watched `Till` condition may make.
    fn count_call(&self) {
        let Ok(mut endpoint) = self.endpoint.try_borrow_mut() else {
            // A call made while the endpoint is looked at (inside a wait) is only a beat.
            return self.endpoint.borrow().slot().beat();
        };
        endpoint.slot().beat();
        // A share's wait ends early when the controller is gone; the next call says so.
        let _ = endpoint.count_call();
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
        // A dotted name (`FreePort.Eth.Tx`) lives in nested tables, made on first use.
        let mut table = globals.clone();
        let mut path = spec.name.split('.').peekable();
        while let Some(part) = path.next() {
            if path.peek().is_none() {
                table.set(part, function.clone())?;
            } else {
                table = match table.get::<Value>(part)? {
                    Value::Table(t) => t,
                    _ => {
                        let t = lua.create_table()?;
                        table.set(part, &t)?;
                        t
                    }
                };
            }
        }
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

/// `Till` keeps waiting while its condition returns false, nil or 0.
pub(super) fn is_true(v: &Value) -> bool {
    match v {
        Value::Nil | Value::Boolean(false) => false,
        Value::Integer(0) => false,
        Value::Number(n) => *n != 0.0,
        _ => true,
    }
}

/// A ch. 2 system error as the code a local returns.
pub(super) fn system_code(e: SystemError) -> i64 {
    ErrorCode::System(e).code() as i64
}

/// An error at the Lua line that called the binding (through `pcall` too), as
/// `luaL_error` words it.
pub fn error_here(lua: &Lua, message: impl std::fmt::Display) -> mlua::Error {
    mlua::Error::runtime(format!("{}{message}", crate::sandbox::raised_at(lua)))
}

/// Words a neutral argument error as `luaL_argerror` would.
fn arg_error(lua: &Lua, spec: &FunctionSpec, error: ArgError) -> mlua::Error {
    let (index, expected, got) = match error {
        ArgError::Type { index, expected, got } => (index, expected, got),
        ArgError::TooMany { given, .. } => return error_here(lua, spec.too_many_args(given)),
    };
    let (expected, hint) = match expected {
        Expected::Integer => ("integer", ""),
        Expected::Number => ("number", ""),
        Expected::BoolOrNumber => ("boolean or number", ""),
        Expected::Utf8String => ("UTF-8 string", ""),
        Expected::String => ("string", ""),
        Expected::ByteTable => ("table of integers 0..255", ""),
        Expected::BytesOrString => ("table of bytes or string", ""),
        Expected::Numbers => ("table of numbers", ""),
        Expected::Function if spec.func == Func::Local(Local::Till) => {
            ("function", "; write Till(function() return IsInPos(0) end)")
        }
        Expected::Function => ("function", ""),
        Expected::Timer => ("Timer", "; make one with TimerInit()"),
    };
    let got = got_name(got);
    error_here(lua, format!("bad argument #{} to '{}' ({expected} expected, got {got}){hint}", index + 1, spec.name))
}

/// What came instead of an argument, as Lua names it: numbers with their value.
fn got_name(got: Got) -> String {
    match got {
        Got::Missing | Got::Nil => "nil".to_string(),
        Got::Bool => "boolean".to_string(),
        Got::Int(n) => format!("integer {n}"),
        Got::Double(n) => format!("number {n}"),
        Got::Str => "string".to_string(),
        Got::List => "table".to_string(),
        Got::Other(name) => name.to_string(),
    }
}

/// What a Lua value is, for an error.
fn got(value: &Value) -> Got {
    match value {
        Value::Table(_) => Got::List,
        other => Got::of(&neutral_element(other)),
    }
}

/// A value as a message names it: numbers with their value.
fn type_name(v: &Value) -> String {
    got_name(got(v))
}

/// A Lua value as the neutral encoder takes it: a table as its sequence `1..n`, whose
/// elements are taken as they are (a table inside is only named, so a table that holds
/// itself cannot loop).
fn neutral(value: &Value) -> mlua::Result<call::Value> {
    Ok(match value {
        Value::Table(t) => call::Value::List(
            t.sequence_values::<Value>().map(|v| v.map(|v| neutral_element(&v))).collect::<mlua::Result<_>>()?,
        ),
        other => neutral_element(other),
    })
}

fn neutral_element(value: &Value) -> call::Value {
    match value {
        Value::Nil => call::Value::Nil,
        Value::Boolean(b) => call::Value::Bool(*b),
        Value::Integer(n) => call::Value::Int(*n),
        Value::Number(n) => call::Value::Double(*n),
        Value::String(s) => call::Value::Str(s.as_bytes().to_vec()),
        other => call::Value::Other(other.type_name()),
    }
}

/// A call's Lua arguments as the encoder's source: each one becomes a neutral value when
/// it is read and is taken by the neutral encoder's rules (`call::Values`), so numbers
/// cost no more than their conversion. Their count was checked before (`binding`).
struct LuaArgs<'a> {
    args: &'a MultiValue,
    next: usize,
    /// A local's `char*` is any bytes, as C reads it (HMPL ch. 3); the core's commands take
    /// UTF-8 only.
    any_bytes: bool,
}

/// A local's argument that only Lua has the type of (`ArgType::Func`, `Timer`, `Any`,
/// `Memory`, `Rest`): its value, and where it was in the call, for an error that names it.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct LuaArg {
    /// Its position in the call, from 0.
    pub at: usize,
    /// The value (nil when left out).
    pub value: Value,
}

impl LuaArg {
    /// The value as a C `int`, by the neutral encoder's rules.
    fn int(&self, lua: &Lua, spec: &FunctionSpec) -> mlua::Result<i64> {
        let args = MultiValue::from_vec(vec![self.value.clone()]);
        LuaArgs::new(&args).read(|v| v.int()).map_err(|e| match e {
            ArgError::Type { expected, got, .. } => {
                arg_error(lua, spec, ArgError::Type { index: self.at, expected, got })
            }
            other => arg_error(lua, spec, other),
        })
    }
}

impl<'a> LuaArgs<'a> {
    fn new(args: &'a MultiValue) -> Self {
        LuaArgs { args, next: 0, any_bytes: false }
    }

    /// The next argument through `read`, with its own position in an error; what it
    /// borrows from the neutral value is copied (strings and tables only).
    fn read<T>(&mut self, read: impl FnOnce(&mut call::Values) -> Result<T, ArgError>) -> Result<T, ArgError> {
        let index = self.next;
        self.next += 1;
        // A table's sequence is read raw, which cannot fail: the error is only named.
        let value = match self.args.get(index).map(neutral).transpose() {
            Ok(value) => value,
            Err(_) => return Err(ArgError::Type { index, expected: Expected::Numbers, got: Got::List }),
        };
        read(&mut call::Values::new(value.as_slice())).map_err(|e| match e {
            ArgError::Type { expected, got, .. } => ArgError::Type { index, expected, got },
            other => other,
        })
    }
}

impl<'a> Source<'a> for LuaArgs<'a> {
    type Error = ArgError;

    fn int(&mut self) -> Result<i64, ArgError> {
        self.read(|v| v.int())
    }

    fn double(&mut self) -> Result<f64, ArgError> {
        self.read(|v| v.double())
    }

    fn bool(&mut self) -> Result<bool, ArgError> {
        self.read(|v| v.bool())
    }

    fn str(&mut self) -> Result<Cow<'a, [u8]>, ArgError> {
        if let (true, Some(Value::String(s))) = (self.any_bytes, self.args.get(self.next)) {
            self.next += 1;
            return Ok(Cow::Owned(s.as_bytes().to_vec()));
        }
        self.read(|v| v.str().map(|s| Cow::Owned(s.into_owned())))
    }

    fn bytes(&mut self) -> Result<Cow<'a, [u8]>, ArgError> {
        self.read(|v| v.bytes().map(|b| Cow::Owned(b.into_owned())))
    }

    fn doubles(&mut self) -> Result<Doubles<'a>, ArgError> {
        self.read(|v| v.doubles().map(|d| Doubles::Values(Cow::Owned(d.iter().collect()))))
    }
}

impl<'a> ValueSource<'a> for LuaArgs<'a> {
    type Value = LuaArg;

    fn value(&mut self, ty: ArgType) -> Result<LuaArg, ArgError> {
        let at = self.next;
        self.next += 1;
        let value = self.args.get(at).cloned().unwrap_or(Value::Nil);
        let expected = match (ty, &value) {
            (ArgType::Func, Value::Function(_)) => None,
            (ArgType::Func, _) => Some(Expected::Function),
            (ArgType::Timer, Value::UserData(ud)) if ud.is::<timer::Timer>() => None,
            (ArgType::Timer, _) => Some(Expected::Timer),
            _ => None,
        };
        match expected {
            Some(expected) => Err(ArgError::Type { index: at, expected, got: got(&value) }),
            None => Ok(LuaArg { at, value }),
        }
    }

    fn rest(&mut self) -> Result<Vec<LuaArg>, ArgError> {
        let first = self.next;
        self.next = self.next.max(self.args.len());
        Ok((first..self.args.len()).map(|at| LuaArg { at, value: self.args[at].clone() }).collect())
    }

    fn absent(&mut self) -> bool {
        let absent = matches!(self.args.get(self.next), None | Some(Value::Nil));
        if absent {
            self.next += 1;
        }
        absent
    }
}

/// The Lua function of `spec`: a call that passes more values than the registry declares
/// is an error at the caller's line, raised before `body` does anything (issue 36.4);
/// every binding is made here.
pub(super) fn binding<R: IntoLuaMulti>(
    lua: &Lua,
    spec: &'static FunctionSpec,
    body: impl Fn(&Lua, MultiValue) -> mlua::Result<R> + 'static,
) -> mlua::Result<Function> {
    lua.create_function(move |lua, args: MultiValue| {
        call::check_count(spec, args.len()).map_err(|e| arg_error(lua, spec, e))?;
        body(lua, args)
    })
}

/// The typed command `args` make, by the registry's rules (`binding` counted them).
fn command_call<'a>(lua: &Lua, command: Command, args: &'a MultiValue) -> mlua::Result<CommandCall<'a>> {
    CommandCall::read(command, &mut LuaArgs::new(args)).map_err(|e| arg_error(lua, command.spec(), e))
}

/// The typed status query `args` make, as `command_call`.
fn query_call(lua: &Lua, query: Query, args: &MultiValue) -> mlua::Result<QueryCall> {
    QueryCall::read(query, &mut LuaArgs::new(args)).map_err(|e| arg_error(lua, query.spec(), e))
}

/// The typed local call `args` make, as `command_call`; a `char*` is any bytes.
fn local_call<'a>(lua: &Lua, local: Local, args: &'a MultiValue) -> Result<LocalCall<'a, LuaArg>, mlua::Error> {
    let mut source = LuaArgs { any_bytes: true, ..LuaArgs::new(args) };
    LocalCall::read(local, &mut source).map_err(|e| locals::arg_error(lua, local, e))
}

fn bytes_table(lua: &Lua, bytes: &[u8]) -> mlua::Result<Value> {
    Ok(Value::Table(lua.create_sequence_from(bytes.iter().map(|&b| b as i64))?))
}

/// Sends a typed command to the core and waits for its reply.
fn round_trip(lua: &Lua, host: &Host, call: &CommandCall) -> mlua::Result<Reply> {
    let mut request = Request::new(call.func().id());
    wire::encode(call, &mut request).map_err(|e| error_here(lua, format!("{}: {e}", call.func().spec().name)))?;
    host.endpoint.borrow_mut().call(&mut request).map_err(mlua::Error::external)
}

/// A command: one round trip to the core; returns what the registry says it returns.
fn command(lua: &Lua, host: Rc<Host>, command: Command) -> mlua::Result<Function> {
    let spec = command.spec();
    binding(lua, spec, move |lua, args| {
        host.beat();
        let call = command_call(lua, command, &args)?;
        let reply = round_trip(lua, &host, &call)?;
        if reply.values[0] as i64 == -1 && reply.rc != 0 {
            // Ch. 17 says only -1; say why, once, where the user sees it.
            eprintln!("warning: {}: {}", spec.name, reply::explain(reply.rc));
        }
        let mut results = MultiValue::new();
        for value in reply::decode(command, &reply) {
            results.push_back(match value {
                reply::Value::Int(i) => Value::Integer(i),
                reply::Value::Double(d) => Value::Number(d),
                reply::Value::Bool(b) => Value::Boolean(b),
                reply::Value::Bytes(bytes) => bytes_table(lua, bytes)?,
                reply::Value::Doubles(numbers) => Value::Table(lua.create_sequence_from(numbers)?),
            });
        }
        Ok(results)
    })
}

/// A status query: read the local snapshot, no round trip.
fn status_query(lua: &Lua, host: Rc<Host>, query: Query) -> mlua::Result<Function> {
    let spec = query.spec();
    binding(lua, spec, move |lua, args| {
        host.count_call();
        let call = query_call(lua, query, &args)?;
        let answer = query::evaluate(&call, host.endpoint.borrow_mut().snapshot());
        host.watch_query(&call, &answer);
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
pub fn install_print(lua: &Lua, host: Rc<Host>) -> mlua::Result<()> {
    let tostring: Function = lua.globals().get("tostring")?;
    let print = lua.create_function(move |_, args: MultiValue| {
        host.spoil_watch();
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

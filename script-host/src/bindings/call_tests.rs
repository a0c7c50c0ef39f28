//! Calls of the registry's functions from Lua, in a VM as the script host builds it, against
//! the registry itself (issue 36): a call with more values than a function takes is an
//! error at the caller's line that names the function and its signature, for every
//! function; and random Lua values in random counts never panic, each call works or raises
//! an error naming its function, and a refused call reaches no core.
//!
//! The decoding from Lua values into typed calls runs without a controller; the bindings
//! run against a stand-in core on a thread of the test (the core's end of the IPC, which
//! answers every request with 0 and counts them), so that a call that reached the core is
//! seen. End to end, with a real controller: tests/hostile_input.rs, tests/extra_arguments.rs.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

use api::FunctionSpec;
use ipc::call::Request;
use ipc::{CoreEndpoint, Disposition, Namespace, TaskEndpoint};
use mlua::{Function, Lua, MultiValue, Value};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use schema::Snapshot;

use super::{Host, binding, command_call, query_call};
use crate::sandbox;

/// The chunk every call is made from: the call is on line 2 (not a tail call, which would
/// leave no line of the chunk on the stack).
const CHUNK: &str = "local f = ...\nlocal ok, e = pcall(f, select(2, ...)) return ok, e";
const CHUNK_NAME: &str = "@calls.lua";
const AT: &str = "calls.lua:2: ";
const TASK: u8 = 1;

/// A Lua value, as the fuzz makes it (the VM makes the value itself).
#[derive(Clone, Debug)]
enum Arg {
    Nil,
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(Vec<u8>),
    /// A string of this many bytes.
    Huge(usize),
    Table(Vec<Arg>),
    /// A sequence of this many integers.
    BigTable(usize),
    /// A table that holds itself, with a hole before it.
    SelfTable,
    /// A function returning this.
    Func(bool),
    /// A function that raises an error.
    FailingFunc,
    /// A timer of `TimerInit` (bindings only).
    Timer,
}

fn arg() -> impl Strategy<Value = Arg> {
    let int = prop_oneof![
        Just(i64::MIN),
        Just(i64::MAX),
        Just(0),
        Just(-1),
        Just(255),
        Just(256),
        Just(0x7FFF_FFFF),
        Just(1 << 53),
        0i64..8,
        any::<i64>(),
    ];
    let float = prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(-0.0),
        Just(0.5),
        Just(1e308),
        Just(5e-324),
        Just(9.0e15),
        Just(1e16),
        any::<f64>(),
    ];
    // Printf-like text too (`Print`, `StringPrint`, `SendMsgEvent`).
    let text = "(%[-+ #0-9.*]{0,4}(l|ll|h)?[sdfxXcgieuopn%]|[a-zA-Z0-9 ]){0,6}".prop_map(|s| Arg::Str(s.into_bytes()));
    let leaf = prop_oneof![
        4 => Just(Arg::Nil),
        2 => any::<bool>().prop_map(Arg::Bool),
        10 => int.prop_map(Arg::Int),
        8 => float.prop_map(Arg::Float),
        4 => prop::collection::vec(any::<u8>(), 0..24).prop_map(Arg::Str),
        4 => text,
        1 => prop_oneof![Just(4096usize), Just(65_536), Just(1 << 20)].prop_map(Arg::Huge),
        1 => prop_oneof![Just(256usize), Just(5000)].prop_map(Arg::BigTable),
        1 => Just(Arg::SelfTable),
        2 => any::<bool>().prop_map(Arg::Func),
        1 => Just(Arg::FailingFunc),
        1 => Just(Arg::Timer),
    ];
    leaf.prop_recursive(2, 24, 6, |inner| prop::collection::vec(inner, 0..6).prop_map(Arg::Table))
}

fn lua_value(lua: &Lua, arg: &Arg) -> mlua::Result<Value> {
    Ok(match arg {
        Arg::Nil => Value::Nil,
        Arg::Bool(b) => Value::Boolean(*b),
        Arg::Int(n) => Value::Integer(*n),
        Arg::Float(x) => Value::Number(*x),
        Arg::Str(s) => Value::String(lua.create_string(s)?),
        Arg::Huge(n) => Value::String(lua.create_string(vec![b'y'; *n])?),
        Arg::Table(items) => {
            let table = lua.create_table()?;
            for (i, item) in items.iter().enumerate() {
                table.raw_set(i + 1, lua_value(lua, item)?)?;
            }
            Value::Table(table)
        }
        Arg::BigTable(n) => Value::Table(lua.create_sequence_from((0..*n as i64).map(|i| i % 300))?),
        Arg::SelfTable => {
            let table = lua.create_table()?;
            table.raw_set(1, 1)?;
            table.raw_set(3, &table)?;
            Value::Table(table)
        }
        Arg::Func(result) => Value::Function(lua.load(format!("return function() return {result} end")).eval()?),
        Arg::FailingFunc => Value::Function(lua.load("return function() error('condition failed') end").eval()?),
        Arg::Timer => match lua.globals().get::<Value>("TimerInit")? {
            Value::Function(init) => init.call(())?,
            _ => Value::Nil,
        },
    })
}

/// Calls `f` with `args` from line 2 of `calls.lua`: `Ok` or the error's message.
fn call(lua: &Lua, f: &Function, args: MultiValue) -> Result<(), String> {
    let chunk = lua.load(CHUNK).set_name(CHUNK_NAME).into_function().expect("the chunk compiles");
    let mut all = MultiValue::new();
    all.push_back(Value::Function(f.clone()));
    all.extend(args);
    let (ok, error): (bool, Value) = chunk.call(all).expect("pcall returns");
    match (ok, error) {
        (true, _) => Ok(()),
        (false, Value::String(s)) => Err(s.to_string_lossy()),
        (false, other) => Err(format!("an error that is no string: {other:?}")),
    }
}

/// What a call's values must give: more than the function takes is refused with the
/// registry's words; otherwise it works or its error is at the caller's line and names it.
fn judge(spec: &FunctionSpec, given: usize, outcome: &Result<(), String>) -> Result<(), TestCaseError> {
    let too_many = spec.max_args().is_some_and(|max| given > max);
    match outcome {
        Err(message) if too_many => {
            prop_assert_eq!(message, &format!("{AT}{}", spec.too_many_args(given)));
        }
        Ok(()) => prop_assert!(!too_many, "{} took {given} values", spec.name),
        Err(message) => {
            prop_assert!(message.starts_with(AT), "{}: not at the caller's line: {message}", spec.name);
            let short = spec.name.rsplit('.').next().unwrap_or(spec.name);
            prop_assert!(message.contains(short), "{}: the error does not name it: {message}", spec.name);
        }
    }
    Ok(())
}

/// The decoding alone, without a controller: each command and query of the registry as a
/// Lua function that reads its typed call as the bindings do (`binding`, then
/// `command_call` or `query_call`); a command's call is written into a request and read
/// back as the core reads it, a query is answered from an empty snapshot.
fn decoders(lua: &Lua) -> Vec<(&'static FunctionSpec, Function)> {
    let snapshot: &'static Snapshot = Box::leak(Box::default());
    api::registry::all()
        .filter_map(|spec| {
            let f = match spec.func {
                api::Func::Command(command) => binding(lua, spec, move |lua, args| {
                    let call = command_call(lua, command, &args)?;
                    let mut request = Request::new(0);
                    if calls::wire::encode(&call, &mut request).is_ok() {
                        // As printed: a NaN argument reads back NaN, which `==` never is.
                        let back = format!("{:?}", calls::wire::decode(&request));
                        assert_eq!(back, format!("{:?}", Ok::<_, ()>(&call)), "{}", spec.name);
                    }
                    Ok(())
                }),
                api::Func::Query(query) => binding(lua, spec, move |lua, args| {
                    let call = query_call(lua, query, &args)?;
                    let _ = calls::query::evaluate(&call, snapshot);
                    Ok(())
                }),
                api::Func::Local(_) => return None,
            };
            Some((spec, f.expect("a binding")))
        })
        .collect()
}

/// A function of `functions` and up to three values more than it takes.
fn calls_of(functions: Vec<&'static FunctionSpec>) -> impl Strategy<Value = (&'static FunctionSpec, Vec<Arg>)> {
    prop::sample::select(functions).prop_flat_map(|spec| {
        let most = spec.max_args().unwrap_or(spec.args.len() + 3) + 3;
        (Just(spec), prop::collection::vec(arg(), 0..=most))
    })
}

/// 10^4 random calls of the commands and queries, decoded from Lua values: none panics,
/// and each works or is refused in words that name the function, at the caller's line.
#[test]
fn lua_values_decode_into_typed_calls_or_a_clear_error() {
    let lua = sandbox::new_vm(0).unwrap();
    let decoders = decoders(&lua);
    let functions: Vec<&'static FunctionSpec> = decoders.iter().map(|(spec, _)| *spec).collect();
    let mut runner = TestRunner::new(Config {
        cases: 10_000,
        failure_persistence: None,
        max_shrink_iters: 500,
        ..Config::default()
    });
    let result = runner.run(&calls_of(functions), |(spec, args)| {
        let f = &decoders.iter().find(|(s, _)| s.name == spec.name).expect("a decoder").1;
        let values = args.iter().map(|a| lua_value(&lua, a)).collect::<mlua::Result<MultiValue>>().unwrap();
        judge(spec, args.len(), &call(&lua, f, values))
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// Crashes the fuzz found, kept as rows (issue 36: every one becomes a regression case).
/// `SetupGroup(0, 1, "x")` added axis 1 to group 0 and then refused "x": a refused call
/// that had changed the machine.
#[test]
fn regression_rows() {
    let core = StandIn::start("rows");
    let lua = core.vm();
    let before = core.requests();
    let f: Function = lua.globals().get("SetupGroup").unwrap();
    let values = [Arg::Int(0), Arg::Int(1), Arg::Str(b"x".to_vec())].map(|a| lua_value(&lua, &a).unwrap());
    let outcome = call(&lua, &f, values.into_iter().collect());
    assert!(outcome.as_ref().is_err_and(|m| m.contains("bad argument #3 to 'SetupGroup'")), "{outcome:?}");
    assert_eq!(core.requests(), before, "the refused SetupGroup reached the core");
}

/// A stand-in for the controller's core: the task table, the shared data and the snapshot
/// board of a namespace of its own, every request answered with 0 and counted, a cycle a
/// millisecond.
struct StandIn {
    ns: Namespace,
    stop: Arc<AtomicBool>,
    requests: Arc<AtomicU64>,
    thread: Option<std::thread::JoinHandle<()>>,
    data: tempfile::TempDir,
}

impl StandIn {
    fn start(tag: &str) -> Self {
        let ns = Namespace::new(&format!("t{}-calls-{tag}", std::process::id())).unwrap();
        let (stop, requests, ready): (_, Arc<AtomicU64>, _) =
            (Arc::new(AtomicBool::new(false)), Arc::default(), Arc::new(AtomicBool::new(false)));
        let thread = {
            let (ns, stop, requests, ready) = (ns.clone(), stop.clone(), Arc::clone(&requests), ready.clone());
            std::thread::spawn(move || {
                ipc::claim_namespace(&ns).unwrap();
                let mut core = CoreEndpoint::create(&ns, &[TASK]).unwrap();
                // The event stream is the supervisor's: `SendEvent` writes into it.
                let node = ipc::services::node(&ns, "stand-in-events").unwrap();
                let _events = ipc::events::EventSender::new(&node, &ns, ipc::services::Open::Create).unwrap();
                let mut snapshot = Snapshot { period_ns: 1_000_000, ..Snapshot::default() };
                ready.store(true, Ordering::Release);
                while !stop.load(Ordering::Acquire) {
                    snapshot.cycle += 1;
                    core.serve(snapshot.cycle, |_, _, reply| {
                        requests.fetch_add(1, Ordering::Relaxed);
                        reply.rc = 0;
                        reply.values.fill(0);
                        reply.valuec = 1;
                        Disposition::Reply
                    });
                    if let Some(mut sample) = core.loan_snapshot(&snapshot, 0) {
                        sample.payload_mut().cycle = snapshot.cycle;
                        sample.payload_mut().period_ns = snapshot.period_ns;
                        core.send_snapshot(sample);
                    }
                    core.wake(snapshot.cycle);
                    std::thread::sleep(Duration::from_micros(200));
                }
            })
        };
        let deadline = std::time::Instant::now() + Duration::from_secs(10);
        while !ready.load(Ordering::Acquire) {
            assert!(std::time::Instant::now() < deadline, "the stand-in core did not start in 10 s");
            std::thread::sleep(Duration::from_millis(1));
        }
        StandIn { ns, stop, requests, thread: Some(thread), data: tempfile::tempdir().unwrap() }
    }

    /// A VM as a script process builds it, its task attached to this core.
    fn vm(&self) -> Lua {
        let endpoint = TaskEndpoint::open(&self.ns, TASK, std::process::id()).unwrap();
        let host = Host::new(endpoint, &self.ns, self.data.path().to_path_buf()).unwrap();
        let vm = crate::Vm::new(host).unwrap_or_else(|e| panic!("{e}"));
        vm.lua
    }

    fn requests(&self) -> u64 {
        self.requests.load(Ordering::Relaxed)
    }
}

impl Drop for StandIn {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Release);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
        ipc::remove_namespace_files(&self.ns);
    }
}

/// A value of each argument's type that the function would take.
fn plausible(lua: &Lua, ty: api::ArgType) -> Value {
    use api::ArgType;
    let source = match ty {
        ArgType::Int | ArgType::Rest | ArgType::Any => "return 0",
        ArgType::Double => "return 1.5",
        ArgType::Str => "return 'R0'",
        ArgType::Bytes | ArgType::Memory => "return {1, 2}",
        ArgType::Doubles => "return {0, 1}",
        ArgType::Func => "return function() return true end",
        ArgType::Bool => "return true",
        ArgType::Timer => "return TimerInit()",
    };
    lua.load(source).eval().unwrap()
}

/// The global a registry name is (`FreePort.Eth.Tx` in nested tables).
fn global(lua: &Lua, name: &str) -> Function {
    let mut value = Value::Table(lua.globals());
    for part in name.split('.') {
        value = match value {
            Value::Table(t) => t.get(part).unwrap(),
            other => panic!("{name}: {other:?} is no table"),
        };
    }
    match value {
        Value::Function(f) => f,
        other => panic!("{name} is no function: {other:?}"),
    }
}

/// Issue 36.4, derived from the registry: every function that is not variadic, called
/// with one and with three values more than it takes (each of a type it takes), raises
/// `calls.lua:2: NAME takes N argument(s), got M: SIGNATURE`, and none of these calls
/// reaches the core.
#[test]
fn every_function_refuses_more_values_than_it_takes() {
    let core = StandIn::start("sweep");
    let lua = core.vm();
    let mut swept = 0;
    for spec in api::registry::all() {
        let Some(max) = spec.max_args() else { continue };
        let f = global(&lua, spec.name);
        for extra in [1, 3] {
            let mut values: MultiValue = spec.args.iter().map(|a| plausible(&lua, a.ty)).collect();
            values.extend((0..extra).map(|_| Value::Integer(7)));
            let outcome = call(&lua, &f, values);
            let want = format!("{AT}{}", spec.too_many_args(max + extra));
            assert_eq!(outcome, Err(want), "{}", spec.name);
        }
        swept += 1;
    }
    assert_eq!(core.requests(), 0, "a refused call reached the core");
    let variadic: Vec<&str> = api::registry::all().filter(|f| f.max_args().is_none()).map(|f| f.name).collect();
    assert_eq!(variadic, ["Print", "SendMsgEvent", "StringPrint", "SetupGroup"]);
    assert_eq!(swept, api::registry::all().count() - variadic.len());
}

/// Functions whose accepted calls the bindings fuzz does not make: they wait on
/// conditions or time that random values make endless (`Sleep`, `DELAY`, `Till`), end the
/// process (`MutexLock` taken twice, HMPL 2.22), open sockets or listeners on random
/// addresses, or write to the test's output. Their refused calls are made.
const NOT_ACCEPTED: &[&str] = &[
    "Sleep",
    "DELAY",
    "Till",
    "MutexLock",
    "START_ASCII_AGENT",
    "FreePort.Eth.OpenAsServer",
    "FreePort.Eth.OpenAsClient",
    "FreePort.Serial.Init",
    "ASCII_ClientConnect",
    "Modbus_ClientConnect",
    "Print",
    "my_print",
];

/// Random values in random counts through the bindings themselves, every kind of
/// function: none panics, each call works or raises an error at the caller's line that
/// names the function, and a call refused for its values sends the core nothing.
#[test]
fn random_lua_values_through_the_bindings() {
    let core = StandIn::start("fuzz");
    let lua = core.vm();
    let functions: Vec<&'static FunctionSpec> =
        api::registry::all().filter(|f| !(NOT_ACCEPTED.contains(&f.name) && f.max_args().is_none())).collect();
    let mut runner = TestRunner::new(Config {
        cases: 10_000,
        failure_persistence: None,
        max_shrink_iters: 500,
        ..Config::default()
    });
    let result = runner.run(&calls_of(functions), |(spec, mut args)| {
        if let Some(max) = spec.max_args().filter(|_| NOT_ACCEPTED.contains(&spec.name)) {
            args.resize(args.len().max(max + 1), Arg::Int(0));
        }
        let f = global(&lua, spec.name);
        let values = args.iter().map(|a| lua_value(&lua, a)).collect::<mlua::Result<MultiValue>>().unwrap();
        let before = core.requests();
        let outcome = call(&lua, &f, values);
        judge(spec, args.len(), &outcome)?;
        if outcome.is_err() {
            prop_assert_eq!(core.requests(), before, "{}: a refused call reached the core: {:?}", spec.name, outcome);
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

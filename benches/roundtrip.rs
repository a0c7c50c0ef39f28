//! How long a script waits for `MoveAbs`, and what a status query (`GetPosFb`) costs,
//! measured from Lua against a real controller process.
//!
//! `cargo bench --bench roundtrip` starts `luamotion run` with an external task slot (the
//! controller starts no process for it), then plays that task itself: a sandboxed VM with
//! the real bindings, plus one extra global, `clock_ns()`, to time the calls.

use std::cell::RefCell;
use std::process::{Command, Stdio};
use std::rc::Rc;
use std::time::{Duration, Instant};

use hdrhistogram::Histogram;
use ipc::{Namespace, TaskEndpoint};
use script_host::bindings::{self, Host};

const MOVES: u64 = 5_000;
const QUERIES: u64 = 200_000;

const SCRIPT: &str = r#"
Enable(0)
Till(function() return IsEnabled(0) end)
-- Back to back: each call leaves right after a cycle, so it waits a whole period.
for i = 1, MOVES do
  local t0 = clock_ns()
  MoveAbs(0, (i % 2) * 0.5)
  record_move(clock_ns() - t0)
end
-- At a random phase of the cycle, as calls come in a real program.
local seed = 12345
for i = 1, MOVES do
  seed = (seed * 1103515245 + 12345) % 2147483648
  local start = clock_ns() + seed % 1000000
  while clock_ns() < start do end
  local t0 = clock_ns()
  MoveAbs(0, (i % 2) * 0.5)
  record_random(clock_ns() - t0)
end
local t0 = clock_ns()
for i = 1, QUERIES do GetPosFb(0) end
local queries = clock_ns() - t0
local noop = function(a) return a end
t0 = clock_ns()
for i = 1, QUERIES do noop(0) end
record_queries(queries, clock_ns() - t0)
Disable(0)
"#;

fn main() {
    let dir = tempfile::tempdir().expect("temp dir");
    let idle = dir.path().join("idle.lua");
    std::fs::write(&idle, "").unwrap();
    let config = dir.path().join("machine.toml");
    // The bench is task 0's process: a controller that serves without programs of its own.
    std::fs::write(&config, "[[axes]]\n[[tasks]]\nid = 0\nprogram = \"idle.lua\"\nexternal = true\n").unwrap();
    let ns = format!("bench-{}", std::process::id());
    let mut controller = Command::new(env!("CARGO_BIN_EXE_luamotion"))
        .args(["serve", "--ns", &ns, "--config", config.to_str().unwrap()])
        .arg("--data-dir")
        .arg(dir.path())
        .stdout(Stdio::null())
        .spawn()
        .expect("start the controller");

    let ns = Namespace::new(&ns).unwrap();
    let deadline = Instant::now() + Duration::from_secs(10);
    let endpoint = loop {
        // The event stream comes up last: the bindings open it too.
        let ready = ipc::controller_ready(&ns).unwrap_or(false);
        match TaskEndpoint::open(&ns, 0, controller.id()) {
            Ok(endpoint) if ready => break endpoint,
            Ok(_) => std::thread::sleep(Duration::from_millis(20)),
            Err(_) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => panic!("the controller did not come up: {e}"),
        }
    };

    let moves = Rc::new(RefCell::new(Histogram::<u64>::new(3).unwrap()));
    let random = Rc::new(RefCell::new(Histogram::<u64>::new(3).unwrap()));
    let queries = Rc::new(RefCell::new((0u64, 0u64)));
    let lua = script_host::sandbox::new_vm(64 << 20).unwrap();
    bindings::install(&lua, Rc::new(Host::new(endpoint, &ns, dir.path().to_path_buf()).unwrap())).unwrap();
    let g = lua.globals();
    g.set("MOVES", MOVES).unwrap();
    g.set("QUERIES", QUERIES).unwrap();
    g.set("clock_ns", lua.create_function(|_, ()| Ok(ipc::clock::monotonic_ns())).unwrap()).unwrap();
    let m = moves.clone();
    g.set(
        "record_move",
        lua.create_function(move |_, ns: u64| m.borrow_mut().record(ns).map_err(mlua::Error::external)).unwrap(),
    )
    .unwrap();
    let r = random.clone();
    g.set(
        "record_random",
        lua.create_function(move |_, ns: u64| r.borrow_mut().record(ns).map_err(mlua::Error::external)).unwrap(),
    )
    .unwrap();
    let q = queries.clone();
    g.set(
        "record_queries",
        lua.create_function(move |_, (a, b): (u64, u64)| {
            *q.borrow_mut() = (a, b);
            Ok(())
        })
        .unwrap(),
    )
    .unwrap();
    lua.load(SCRIPT).exec().expect("benchmark script");
    // Leave the controller's services before it removes them.
    drop(lua);

    // SAFETY: signalling the child we started.
    unsafe { libc::kill(controller.id() as i32, libc::SIGTERM) };
    let _ = controller.wait();

    let (query_ns, noop_ns) = *queries.borrow();
    println!("MoveAbs round trip from Lua, {MOVES} calls each, 1 ms cycle:");
    for (what, h) in [("back to back", moves.borrow()), ("random phase", random.borrow())] {
        let us = |q: f64| h.value_at_quantile(q) as f64 / 1000.0;
        println!(
            "  {what}: p50 {:.0} us   p90 {:.0} us   p99 {:.0} us   max {:.0} us",
            us(0.5),
            us(0.9),
            us(0.99),
            h.max() as f64 / 1000.0
        );
    }
    println!("GetPosFb from Lua, {QUERIES} calls:");
    println!(
        "  {:.0} ns per call ({:.0} ns for an empty Lua function call)",
        query_ns as f64 / QUERIES as f64,
        noop_ns as f64 / QUERIES as f64
    );
}

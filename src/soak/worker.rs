//! One soak worker process (`luamotion soak-worker`): a sandboxed Lua VM with the real
//! bindings, attached to an external task slot, running a mix of commands and queries
//! for a while, then writing what it measured as JSON.
//!
//! Per command it records the legs of the call from the endpoint's timestamps:
//! - `command round trip`: the Lua call to its return;
//! - `script -> core`: sent to taken by the core (waits for the next cycle);
//! - `core -> script`: the reply sent to the script having it (the rest of the cycle,
//!   the wake-up);
//! - `wake-up`: the core notifying the task's wake event (after it published the cycle's
//!   snapshot) to the script having the reply: the transport and the wake-up;
//!
//! and per round of queries `snapshot age`: how old the snapshot a query reads is; and the
//! CPU time the process used over the workload, for the wake-up's fairness.

use std::cell::RefCell;
use std::path::PathBuf;
use std::rc::Rc;
use std::time::Duration;

use anyhow::{Context, Result};
use hdrhistogram::Histogram;
use ipc::clock::monotonic_ns;
use ipc::{Namespace, TaskEndpoint};
use script_host::bindings::{self, Host};

use super::metrics::{self, WorkerResult};

pub const ROUND_TRIP: &str = "command round trip";
pub const REQUEST: &str = "script -> core";
pub const REPLY: &str = "core -> script";
pub const WAKE: &str = "wake-up";
pub const SNAPSHOT_AGE: &str = "snapshot age";

/// A call whose reply takes longer than this counts as lost.
const REPLY_TIMEOUT: Duration = Duration::from_secs(1);

/// Commands in turn (MoveAbs, SetVel, an SDO read, MoveAbs), each followed by a round of
/// status queries. `AXIS`, `DEADLINE_NS` and the `soak_*` functions come from the worker.
const WORKLOAD: &str = r#"
Enable(AXIS)
Till(function() return IsEnabled(AXIS) end)
local i = 0
local commands = {
  function() return MoveAbs(AXIS, (i % 8) * 0.25) end,
  function() return SetVel(AXIS, 100 + i % 50) end,
  function() return ReadSDO(AXIS, 0x6041, 0, 2) end,
  function() return MoveAbs(AXIS, 0) end,
}
while clock_ns() < DEADLINE_NS do
  i = i + 1
  local t0 = clock_ns()
  local ok = pcall(commands[i % 4 + 1])
  soak_call(clock_ns() - t0, ok)
  for q = 1, 4 do
    GetPosFb(AXIS)
    IsMoving(AXIS)
  end
  soak_queries(8)
end
"#;

pub struct WorkerArgs {
    pub ns: String,
    pub task: u8,
    pub axis: u8,
    pub duration_ms: u64,
    pub controller_pid: u32,
    pub out: PathBuf,
}

#[derive(Default)]
struct Recorder {
    round_trip: Option<Histogram<u64>>,
    request: Option<Histogram<u64>>,
    reply: Option<Histogram<u64>>,
    wake: Option<Histogram<u64>>,
    snapshot_age: Option<Histogram<u64>>,
    result: WorkerResult,
}

fn h(slot: &mut Option<Histogram<u64>>) -> &mut Histogram<u64> {
    slot.get_or_insert_with(metrics::histogram)
}

pub fn run(args: WorkerArgs) -> Result<()> {
    let ns = Namespace::new(&args.ns)?;
    let mut endpoint = TaskEndpoint::open(&ns, args.task, args.controller_pid).context("attach to the task slot")?;
    ipc::restore_default_signals();
    endpoint.set_reply_timeout(Some(REPLY_TIMEOUT));
    let data_dir = tempfile::tempdir()?;
    let host = Rc::new(Host::new(endpoint, &ns, data_dir.path().to_path_buf())?);
    let recorder = Rc::new(RefCell::new(Recorder::default()));
    let (cpu_start_ns, wall_start_ns) = (process_cpu_ns(), monotonic_ns());
    // mlua's errors are not Send; say them as text.
    play(&host, &recorder, args.axis, args.duration_ms).map_err(|e| anyhow::anyhow!("soak workload: {e}"))?;
    let (cpu_ns, wall_ns) = (process_cpu_ns() - cpu_start_ns, monotonic_ns() - wall_start_ns);

    let counters = host.endpoint.borrow().reply_counters();
    let mut r = recorder.borrow_mut();
    let Recorder { round_trip, request, reply, wake, snapshot_age, result } = &mut *r;
    for (name, histogram) in
        [(ROUND_TRIP, round_trip), (REQUEST, request), (REPLY, reply), (WAKE, wake), (SNAPSHOT_AGE, snapshot_age)]
    {
        if let Some(histogram) = histogram {
            result.put(name, histogram);
        }
    }
    result.counts.lost = counters.lost;
    result.counts.duplicated = counters.duplicated;
    result.counts.out_of_order = counters.out_of_order;
    (result.cpu_ns, result.wall_ns) = (cpu_ns, wall_ns);
    std::fs::write(&args.out, serde_json::to_vec(result)?).with_context(|| format!("write {}", args.out.display()))?;
    Ok(())
}

/// CPU time of this process (all its threads), ns.
fn process_cpu_ns() -> u64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `ts` is valid for the call.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

/// Runs the workload in a VM with the real bindings and the soak's instruments.
fn play(host: &Rc<Host>, recorder: &Rc<RefCell<Recorder>>, axis: u8, duration_ms: u64) -> mlua::Result<()> {
    let lua = script_host::sandbox::new_vm(64 << 20)?;
    bindings::install(&lua, host.clone())?;
    let g = lua.globals();
    g.set("AXIS", axis)?;
    g.set("DEADLINE_NS", monotonic_ns() + duration_ms * 1_000_000)?;
    g.set("clock_ns", lua.create_function(|_, ()| Ok(monotonic_ns()))?)?;
    let (r, calls) = (recorder.clone(), host.clone());
    g.set(
        "soak_call",
        lua.create_function(move |_, (lua_ns, ok): (u64, bool)| {
            let mut r = r.borrow_mut();
            if !ok {
                r.result.counts.call_errors += 1;
                return Ok(());
            }
            r.result.counts.commands += 1;
            let t = calls.endpoint.borrow().last_call();
            metrics::record(h(&mut r.round_trip), lua_ns);
            metrics::record(h(&mut r.request), t.taken_ns.saturating_sub(t.sent_ns));
            metrics::record(h(&mut r.reply), t.reply_seen_ns.saturating_sub(t.replied_ns));
            if t.notified_ns >= t.replied_ns && t.notified_ns <= t.reply_seen_ns {
                metrics::record(h(&mut r.wake), t.reply_seen_ns - t.notified_ns);
            }
            Ok(())
        })?,
    )?;
    let (r, snapshots) = (recorder.clone(), host.clone());
    g.set(
        "soak_queries",
        lua.create_function(move |_, n: u64| {
            let published = snapshots.endpoint.borrow_mut().snapshot().published_ns;
            let mut r = r.borrow_mut();
            r.result.counts.queries += n;
            metrics::record(h(&mut r.snapshot_age), monotonic_ns().saturating_sub(published));
            Ok(())
        })?,
    )?;
    lua.load(WORKLOAD).set_name("soak workload").exec()
}

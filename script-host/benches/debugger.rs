//! What the debugger's hook costs a CPU-bound program (DXMC manual A.3 program control):
//! the same Lua run with no hook, with the count hook the script host had before the hook
//! was armed only when needed, with the debugger in Debug Run without breakpoints (no hook
//! after the first line; a script process adds a sample every 10 ms, see
//! benches/lua_speed.rs), and with one breakpoint on a line never reached (the line hook).
//! Best of 5 runs each.
//!
//! `cargo bench -p script-host --bench debugger`

use std::rc::Rc;
use std::time::{Duration, Instant};

use ipc::task_table::TaskTable;
use mlua::{HookTriggers, Lua, VmState};
use schema::debug::RunMode;
use script_host::debugger::{Debugger, LINE_INSTRUCTIONS, SharedTable};
use script_host::sandbox;

const RUNS: usize = 5;
const TASK: usize = 0;
const CHUNK: &str = "@bench.lua";

/// 20 M iterations of arithmetic and a table write, then 5 M calls of a small function.
const PROGRAM: &str = include_str!("../../benches/lua/compute.lua");

/// How the VM is set up before the program runs.
#[derive(Clone, Copy)]
enum Setup {
    NoHook,
    CountHookOnly,
    Debugger { breakpoint: bool },
}

impl Setup {
    fn name(self) -> &'static str {
        match self {
            Setup::NoHook => "(a) no hook",
            Setup::CountHookOnly => "(ref) count hook recording the line (before issue 19)",
            Setup::Debugger { breakpoint: false } => "(b) debugger, Debug Run, no breakpoint",
            Setup::Debugger { breakpoint: true } => "(c) debugger, Debug Run, breakpoint never reached",
        }
    }

    fn prepare(self, lua: &Lua, table: &SharedTable) -> mlua::Result<()> {
        match self {
            Setup::NoHook => Ok(()),
            Setup::CountHookOnly => {
                let table = table.clone();
                lua.set_global_hook(HookTriggers::new().every_nth_instruction(LINE_INSTRUCTIONS), move |_, debug| {
                    if let Some(line) = debug.current_line() {
                        table.slots[TASK].set_line(line as u32);
                    }
                    Ok(VmState::Continue)
                })
            }
            Setup::Debugger { breakpoint } => {
                let lines = if breakpoint { vec![never_reached_line()] } else { vec![] };
                table.slots[TASK].debug.prepare(RunMode::Debug, &lines);
                Debugger::new(table.clone(), TASK, CHUNK, || true).install(lua)
            }
        }
    }
}

fn never_reached_line() -> u32 {
    PROGRAM.lines().position(|l| l.contains("@never")).expect("marker") as u32 + 1
}

/// One run in a fresh VM: the time and the program's result.
fn run_once(setup: Setup) -> mlua::Result<(Duration, i64)> {
    let table: SharedTable = Rc::new(schema::layout::zeroed::<TaskTable>());
    let lua = sandbox::new_vm(256 << 20)?;
    setup.prepare(&lua, &table)?;
    let program = lua.load(PROGRAM).set_name(CHUNK).into_function()?;
    let started = Instant::now();
    let result: i64 = program.call(())?;
    Ok((started.elapsed(), result))
}

/// The best of `RUNS` runs, and the program's result (the same in every run).
fn best_of(setup: Setup) -> mlua::Result<(Duration, i64)> {
    let mut best: Option<(Duration, i64)> = None;
    for _ in 0..RUNS {
        let (time, result) = run_once(setup)?;
        if let Some((_, expected)) = best {
            assert_eq!(result, expected, "{}: the program's result changed", setup.name());
        }
        best = Some(best.map_or((time, result), |(t, _)| (t.min(time), result)));
    }
    Ok(best.expect("RUNS > 0"))
}

fn main() -> mlua::Result<()> {
    let setups = [
        Setup::NoHook,
        Setup::CountHookOnly,
        Setup::Debugger { breakpoint: false },
        Setup::Debugger { breakpoint: true },
    ];
    println!("best of {RUNS} runs: 20 M loop iterations with a table write, 5 M Lua calls");
    let mut baseline = None;
    for setup in setups {
        let (time, result) = best_of(setup)?;
        let base = *baseline.get_or_insert((time, result));
        assert_eq!(result, base.1, "{}: a hook changed the program's result", setup.name());
        let ratio = time.as_secs_f64() / base.0.as_secs_f64();
        println!("{:<60} {:>9.1} ms   x{ratio:.3}", setup.name(), time.as_secs_f64() * 1e3);
    }
    Ok(())
}

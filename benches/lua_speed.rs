//! Lua in a luamotion task beside the distribution's stock `lua5.4`, in one run: a
//! compute-bound program (20 M loop iterations with a table write, then 5 M calls) and a
//! string-heavy one (`string.format`, `gsub`, `find`, `match`, concatenation). The task
//! runs under its watchdog (60 s here, long enough for the programs) with the debugger
//! installed, as every task does.
//!
//! `cargo bench --bench lua_speed` (release). Figures are CPU time, so that builds sharing
//! the machine inflate them less than wall time: the task's process from /proc (utime +
//! stime, all its threads, read while the program sleeps before and after the work), the
//! stock interpreter's from `getrusage(RUSAGE_CHILDREN)`. Best of `RUNS`, the two run
//! alternately. `LUAMOTION_BIN=<path>` measures another build of luamotion (a commit
//! before this one, say).

#[path = "../tests/common/mod.rs"]
mod common;

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::mpsc::channel;
use std::time::Duration;

const RUNS: usize = 3;

/// The debugger bench's program too (`script-host/benches/debugger.rs`).
const COMPUTE: &str = include_str!("lua/compute.lua");

const STRINGS: &str = "\
local kept, found = {}, 0
for i = 1, 400000 do
  local s = string.format('axis %d at %.3f mm, %s', i % 96, i * 0.125, i % 3 == 0 and 'moving' or 'still')
  s = s:gsub('%d+', '#')
  if s:find('moving', 1, true) then found = found + 1 end
  kept[i % 64 + 1] = s .. ';' .. i
  local a, b = s:match('^(%a+) #.- (%a+)$')
  if b == 'still' then found = found + #a end
end
return found + #table.concat(kept)
";

fn main() {
    let luamotion = std::env::var("LUAMOTION_BIN").unwrap_or_else(|_| common::BIN.to_string());
    let lua = common::debian_tool("lua5.4");
    let dir = tempfile::tempdir().expect("temp dir");
    println!("best of {RUNS} runs, CPU time; luamotion: {luamotion}");
    println!("{:<10} {:>12} {:>12} {:>8}", "program", "lua5.4", "luamotion", "ratio");
    for (name, body) in [("compute", COMPUTE), ("strings", STRINGS)] {
        let (mut stock, mut task) = (f64::MAX, f64::MAX);
        for _ in 0..RUNS {
            let (ms, stock_result) = stock_lua(&lua, dir.path(), body);
            stock = stock.min(ms);
            let (ms, task_result) = in_task(&luamotion, dir.path(), body);
            task = task.min(ms);
            assert_eq!(stock_result, task_result, "{name}: the two gave different results");
        }
        println!("{name:<10} {stock:>9.0} ms {task:>9.0} ms {:>7.3}x", task / stock);
    }
}

/// CPU time of the finished children of this process, ms.
fn children_cpu_ms() -> f64 {
    // SAFETY: getrusage fills the struct it is given.
    let usage = unsafe {
        let mut usage = std::mem::zeroed::<libc::rusage>();
        libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage);
        usage
    };
    let ms = |t: libc::timeval| t.tv_sec as f64 * 1e3 + t.tv_usec as f64 / 1e3;
    ms(usage.ru_utime) + ms(usage.ru_stime)
}

/// The stock interpreter: its CPU time and the program's result.
fn stock_lua(lua: &Path, dir: &Path, body: &str) -> (f64, String) {
    let file = dir.join("stock.lua");
    std::fs::write(&file, format!("local result = (function()\n{body}end)()\nprint(result)\n")).unwrap();
    let before = children_cpu_ms();
    let out = Command::new(lua).arg(&file).output().expect("run lua5.4");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    (children_cpu_ms() - before, String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// CPU time of a process, all threads, ms (clock ticks of 10 ms).
fn process_cpu_ms(pid: u32) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).expect("the task's process");
    let fields: Vec<&str> = stat.rsplit_once(')').expect("stat").1.split_whitespace().collect();
    // utime and stime are fields 14 and 15 of stat, 12 and 13 after the name.
    let ticks: f64 = fields[11].parse::<f64>().unwrap() + fields[12].parse::<f64>().unwrap();
    // SAFETY: sysconf has no preconditions.
    ticks * 1e3 / unsafe { libc::sysconf(libc::_SC_CLK_TCK) } as f64
}

/// The program in task 0 of a controller: the CPU time of its process between the two
/// marks (each followed by a sleep, so the process is idle when it is read) and the result.
fn in_task(luamotion: &str, dir: &Path, body: &str) -> (f64, String) {
    std::fs::write(
        dir.join("task.lua"),
        format!(
            "print('lua_speed start')\nSleep(300)\nlocal result = (function()\n{body}end)()\n\
             print('lua_speed done ' .. tostring(result))\nSleep(300)\n"
        ),
    )
    .unwrap();
    std::fs::write(
        dir.join("machine.toml"),
        // No script pool: the task's process is the controller's only child, the one timed.
        "[rt]\nscript_pool = 0\n[[tasks]]\nid = 0\nprogram = \"task.lua\"\nautorun = true\nwatchdog_ms = 60000\n",
    )
    .unwrap();
    let ns = common::unique_ns("lua-speed");
    let mut controller = Command::new(luamotion)
        .args(["run", "--ns", &ns, "--config"])
        .arg(dir.join("machine.toml"))
        .arg("--data-dir")
        .arg(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start luamotion");
    let (tx, lines) = channel();
    let stdout = controller.stdout.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let mark = |what: &str| {
        let line = loop {
            let line = lines.recv_timeout(Duration::from_secs(600)).unwrap_or_else(|_| panic!("no '{what}'"));
            if let Some(rest) = line.split_once("lua_speed ").map(|(_, r)| r.to_string()) {
                assert!(rest.starts_with(what), "{line}");
                break rest;
            }
        };
        let script = common::children_of(controller.id());
        assert_eq!(script.len(), 1, "one script process");
        (process_cpu_ms(script[0]), line.trim_start_matches(what).trim().to_string())
    };
    let (start, _) = mark("start");
    let (done, result) = mark("done");
    assert!(controller.wait().expect("luamotion").success());
    (done - start, result)
}

//! How many cycles pass from `StartTask` (and `StartTaskFunc`) to the first line of the
//! started task, with 64 tasks configured, and how long a controller with 64 autorun tasks
//! takes until every task runs its first line; with `[rt] script_pool = 0` (a process
//! started per task start) and with the pool, side by side in one run. Also the resident
//! memory of the controller and of the script processes with 64 tasks running.
//!
//! `cargo bench --bench start_task` (a release build: figures of a debug build say little).

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

const STARTS: usize = 200;
const POOLS: [usize; 3] = [0, 2, 4];

/// Task 0 starts task 1 `STARTS` times each way; task 1's first line writes the cycle it
/// runs in. Cycles are counted from the snapshot task 0 saw before its call.
const DRIVER: &str = r#"
local function measure(start)
  local d = {}
  for i = 1, STARTS do
    system_user_table[0] = -1
    local c0 = system_fclk
    start()
    Till(function() return system_user_table[0] >= 0 end)
    d[i] = system_user_table[0] - c0
    Till(function() return IsTaskStop(1) end)
  end
  table.sort(d)
  return d[math.ceil(STARTS * 0.5)], d[math.ceil(STARTS * 0.99)], d[STARTS]
end
-- The pool is filled from a second after the controller's start.
Sleep(2000)
Print("StartTask %d %d %d", measure(function() StartTask(1) end))
Print("StartTaskFunc %d %d %d", measure(function() StartTaskFunc(1, "entry") end))
"#;
const TARGET: &str = "system_user_table[0] = system_fclk\nfunction entry() system_user_table[0] = system_fclk end\n";

/// Every one of the 64 autorun tasks writes the cycle of its first line; task 0 waits for
/// all of them and says the last one's cycle.
const AUTORUN: &str = r#"
system_user_table[100 + TASK] = system_fclk + 1
if TASK == 0 then
  Till(function()
    for t = 0, 63 do if system_user_table[100 + t] == 0 then return false end end
    return true
  end)
  local last = 0
  for t = 0, 63 do last = math.max(last, system_user_table[100 + t] - 1) end
  Print("all running, the last from cycle %d", last)
end
while true do Sleep(100) end
"#;

fn machine(dir: &Path, pool: usize, tasks: impl Fn(usize) -> (String, bool)) -> std::path::PathBuf {
    let mut toml = format!("[rt]\nscript_pool = {pool}\n[[axes]]\n");
    for id in 0..64 {
        let (program, autorun) = tasks(id);
        toml += &format!("[[tasks]]\nid = {id}\nprogram = {program:?}\nautorun = {autorun}\n");
    }
    let path = dir.join(format!("machine-{pool}.toml"));
    std::fs::write(&path, toml).unwrap();
    path
}

fn controller(ns: &str, config: &Path, dir: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_luamotion"));
    command
        .args(["run", "--ns", ns, "--config", config.to_str().unwrap()])
        .arg("--data-dir")
        .arg(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::null());
    command
}

/// p50, p99 and max of each way to start, in cycles.
fn starts(dir: &Path, pool: usize) -> Vec<(String, [u64; 3])> {
    std::fs::write(dir.join("driver.lua"), DRIVER.replace("STARTS", &STARTS.to_string())).unwrap();
    std::fs::write(dir.join("target.lua"), TARGET).unwrap();
    std::fs::write(dir.join("idle.lua"), "").unwrap();
    let config = machine(dir, pool, |id| match id {
        0 => ("driver.lua".into(), true),
        1 => ("target.lua".into(), false),
        _ => ("idle.lua".into(), false),
    });
    let ns = format!("bench-start-{}-{pool}", std::process::id());
    let out = controller(&ns, &config, dir).output().expect("run the controller");
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.strip_prefix("[task 0] "))
        .filter_map(|l| {
            let mut words = l.split_whitespace();
            let what = words.next()?.to_string();
            let numbers: Vec<u64> = words.filter_map(|w| w.parse().ok()).collect();
            Some((what, numbers.try_into().ok()?))
        })
        .collect()
}

/// Resident memory of a process, KiB.
fn rss_kib(pid: u32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    let line = status.lines().find(|l| l.starts_with("VmRSS:")).unwrap_or("VmRSS: 0 kB");
    line.split_whitespace().nth(1).and_then(|v| v.parse().ok()).unwrap_or(0)
}

/// Script processes of the controller `pid`.
fn children(pid: u32) -> Vec<u32> {
    let Ok(tasks) = std::fs::read_to_string(format!("/proc/{pid}/task/{pid}/children")) else { return Vec::new() };
    tasks.split_whitespace().filter_map(|p| p.parse().ok()).collect()
}

struct Autorun {
    wall_ms: f64,
    last_cycle: u64,
    controller_mib: f64,
    scripts: usize,
    script_mib: f64,
}

/// A controller with 64 autorun tasks: from its start until task 0 says every task ran
/// its first line; then the memory.
fn autorun(dir: &Path, pool: usize) -> Autorun {
    for id in 0..64 {
        std::fs::write(dir.join(format!("auto{id}.lua")), AUTORUN.replace("TASK", &id.to_string())).unwrap();
    }
    let config = machine(dir, pool, |id| (format!("auto{id}.lua"), true));
    let ns = format!("bench-auto-{}-{pool}", std::process::id());
    let started = Instant::now();
    let mut child = controller(&ns, &config, dir).spawn().expect("start the controller");
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let line =
        lines.find_map(|l| l.ok()?.strip_prefix("[task 0] all running, the last from cycle ").map(str::to_string));
    let wall_ms = started.elapsed().as_secs_f64() * 1000.0;
    let scripts = children(child.id());
    let script_kib: u64 = scripts.iter().map(|&p| rss_kib(p)).sum();
    let controller_mib = rss_kib(child.id()) as f64 / 1024.0;
    // SAFETY: signalling the child we started.
    unsafe { libc::kill(child.id() as i32, libc::SIGTERM) };
    let _ = child.wait();
    Autorun {
        wall_ms,
        last_cycle: line.and_then(|l| l.parse().ok()).expect("every task ran"),
        controller_mib,
        scripts: scripts.len(),
        script_mib: script_kib as f64 / 1024.0,
    }
}

fn main() {
    let dir = tempfile::tempdir().expect("temp dir");
    println!("StartTask to the first line of the started task, 64 tasks configured, 1 ms cycle, {STARTS} starts:");
    for pool in POOLS {
        for (what, [p50, p99, max]) in starts(dir.path(), pool) {
            println!("  script_pool = {pool}  {what:<14} p50 {p50:>3}  p99 {p99:>3}  max {max:>3} cycles");
        }
    }
    println!("A controller with 64 autorun tasks, from its start to every task's first line:");
    for pool in POOLS {
        let a = autorun(dir.path(), pool);
        println!(
            "  script_pool = {pool}  {:.0} ms (the last task's first line in cycle {}); RSS: controller {:.1} MiB, \
             {} script processes {:.1} MiB ({:.1} MiB each)",
            a.wall_ms,
            a.last_cycle,
            a.controller_mib,
            a.scripts,
            a.script_mib,
            a.script_mib / a.scripts.max(1) as f64
        );
    }
}

//! End to end: HMPL tasks (HMPL ch. 2, 16, 19; E-stop 2.9, 9.2.6), mutexes under
//! contention between processes, the user table surviving `kill -9` in the middle of a
//! save, and the `tasks` and `events` tools.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::*;

fn tasks_dir() -> PathBuf {
    repo_path("tests/lua/tasks")
}

/// A machine file in `dir`: two axes, task 0 runs `main`, tasks 1.. run `others`.
fn machine(dir: &Path, cycle_us: u32, main: &Path, others: &[&Path]) -> PathBuf {
    let mut toml = format!("cycle_us = {cycle_us}\n[[axes]]\n[[axes]]\n");
    toml += &format!("[[tasks]]\nid = 0\nprogram = {:?}\nautorun = true\n", main.display().to_string());
    for (i, program) in others.iter().enumerate() {
        toml += &format!("[[tasks]]\nid = {}\nprogram = {:?}\n", i + 1, program.display().to_string());
    }
    let path = dir.join("machine.toml");
    std::fs::write(&path, toml).unwrap();
    path
}

fn run_machine(config: &Path, extra: &[&str]) -> Finished {
    let ns = unique_ns("tasks");
    let mut args = vec!["--config", config.to_str().unwrap()];
    args.extend_from_slice(extra);
    run(&ns, &args)
}

#[test]
fn tasks_system_functions_and_user_table() {
    let out = run_machine(&tasks_dir().join("machine.toml"), &[]);
    let context = format!("{}\n{}", out.stdout, out.stderr);
    assert_eq!(out.lines_of_task(0).last().map(String::as_str), Some("task facts passed"), "{context}");
    // HMPL 2.22, 2.23: the second MutexLock stopped task 6 with 0x13EC, before its Print.
    assert!(out.stderr.contains("MutexLock(5): this task holds the mutex already (0x13EC"), "{context}");
    assert!(out.stderr.contains("(alarm 0x300613EC)"), "{context}");
    assert!(!out.stdout.contains("never printed"), "{context}");
}

#[test]
fn stop_all_task_stops_the_caller() {
    let dir = tempfile::tempdir().unwrap();
    let config = machine(dir.path(), 1000, &tasks_dir().join("stop_all.lua"), &[&tasks_dir().join("helpers.lua")]);
    let out = run_machine(&config, &[]);
    assert_eq!(out.lines_of_task(0), vec!["before StopAllTask"], "{}", out.stderr);
    assert!(
        out.stderr.contains("stop_all.lua): stopped") && out.stderr.contains("helpers.lua): stopped"),
        "{}",
        out.stderr
    );
}

/// The first cycle from which axis `a` stays disabled, in a trace.
fn disabled_from(trace: &str, a: usize) -> Option<u64> {
    let mut lines = trace.lines();
    let header: Vec<&str> = lines.next()?.split(',').collect();
    let column = header.iter().position(|h| *h == format!("a{a}_motion_status"))?;
    let mut since = None;
    let mut was_enabled = false;
    for line in lines {
        let fields: Vec<&str> = line.split(',').collect();
        let enabled = fields[column].parse::<u32>().ok()? & 1 != 0;
        if enabled {
            was_enabled = true;
            since = None;
        } else if was_enabled && since.is_none() {
            since = fields[0].parse().ok();
        }
    }
    since
}

/// Both axes disabled in the same cycles, and neither program got past the stop.
fn assert_emergency_stopped(out: &Finished, trace: &Path, main: &str) {
    let context = format!("{}\n{}", out.stdout, out.stderr);
    assert!(!out.stdout.contains("never printed") && !out.stderr.contains("FAILED"), "{context}");
    assert!(
        out.stderr.contains(&format!("{main}): stopped")) && out.stderr.contains("helpers.lua): stopped"),
        "{context}"
    );
    let trace = std::fs::read_to_string(trace).unwrap();
    let (a0, a1) = (disabled_from(&trace, 0), disabled_from(&trace, 1));
    assert!(a0.is_some() && a1.is_some(), "both axes were enabled, then disabled: {context}");
    assert!(a0.unwrap().abs_diff(a1.unwrap()) <= 2, "disabled together: {a0:?} {a1:?}");
}

#[test]
fn estop_stops_every_task_and_disables_every_axis() {
    let dir = tempfile::tempdir().unwrap();
    let config = machine(dir.path(), 1000, &tasks_dir().join("estop.lua"), &[&tasks_dir().join("helpers.lua")]);
    let trace = dir.path().join("trace.csv");
    let out = run_machine(&config, &["--trace", trace.to_str().unwrap()]);
    assert_eq!(out.lines_of_task(0), vec!["before EStop"], "{}", out.stderr);
    assert_emergency_stopped(&out, &trace, "estop.lua");
}

#[test]
fn the_estop_input_stops_every_task_and_disables_every_axis() {
    let dir = tempfile::tempdir().unwrap();
    let config = machine(dir.path(), 1000, &tasks_dir().join("emo.lua"), &[&tasks_dir().join("helpers.lua")]);
    let trace = dir.path().join("trace.csv");
    let out = run_machine(&config, &["--trace", trace.to_str().unwrap()]);
    assert_eq!(out.lines_of_task(0), vec!["raising GPI 3"], "{}", out.stderr);
    assert_emergency_stopped(&out, &trace, "emo.lua");
}

#[test]
fn system_clock_at_250_us() {
    let dir = tempfile::tempdir().unwrap();
    let main = program(
        dir.path(),
        "clock.lua",
        "local c, t = system_fclk, system_timeInMs\nSleep(100)\n\
         Print('%d cycles, %d ms', system_fclk - c, system_timeInMs - t)\n",
    );
    let out = run_machine(&machine(dir.path(), 250, &main, &[]), &[]);
    let line = out.lines_of_task(0).pop().unwrap_or_default();
    let (cycles, ms) = line.split_once(" cycles, ").expect(&out.stderr);
    let (cycles, ms): (u64, u64) = (cycles.parse().unwrap(), ms.trim_end_matches(" ms").parse().unwrap());
    // Sleep(100) waits 400 cycles; more only when the OS wakes the script late.
    assert!((400..600).contains(&cycles), "HMPL 2.18: {line}");
    assert!(cycles.abs_diff(4 * ms) <= 4, "HMPL 23.2: 4 cycles per ms at 250 us: {line}");
}

/// Four processes add 1 to the same user-table cell 25 000 times each under mutex 0.
#[test]
fn no_lost_update_under_a_mutex() {
    let dir = tempfile::tempdir().unwrap();
    let adder = program(
        dir.path(),
        "adder.lua",
        "for i = 1, 25000 do\n  MutexLock(0)\n  system_user_table[0] = system_user_table[0] + 1\n  MutexUnlock(0)\nend\n",
    );
    let main = program(
        dir.path(),
        "main.lua",
        "system_user_table[0] = 0\nfor t = 1, 4 do StartTask(t) end\n\
         Till(function() return IsTaskStop(1) and IsTaskStop(2) and IsTaskStop(3) and IsTaskStop(4) end)\n\
         Print('total %d', system_user_table[0])\n",
    );
    let out = run_machine(&machine(dir.path(), 1000, &main, &[&adder, &adder, &adder, &adder]), &[]);
    assert!(out.status.success(), "{}", out.stderr);
    assert_eq!(out.lines_of_task(0), vec!["total 100000"], "{}", out.stderr);
}

/// HMPL 11.6: a `kill -9` while the table is saved leaves the old table or the new one.
#[test]
fn a_save_killed_midway_leaves_a_whole_table() {
    let dir = tempfile::tempdir().unwrap();
    // Each save writes the whole 4 MB file; the first 20 000 values carry the save's number.
    let saver = program(
        dir.path(),
        "saver.lua",
        "local k = system_ltest0\nwhile true do\n  k = k + 1\n  system_ltest0 = k\n\
         for i = 0, 19999 do system_user_table[i] = k end\n  SaveUserTable(0, 20000)\nend\n",
    );
    let main =
        program(dir.path(), "main.lua", "while true do\n  if IsTaskStop(1) then StartTask(1) end\n  Sleep(5)\nend\n");
    let config = machine(dir.path(), 1000, &main, &[&saver]);
    let ns = unique_ns("save");
    let table = data_dir(&ns).join("user_table.bin");
    let child = start_run(&ns, &["--config", config.to_str().unwrap()]);
    assert!(eventually(Duration::from_secs(20), || table.exists()), "a first save");
    let namespace = ipc::Namespace::new(&ns).unwrap();
    let mut monitor = ipc::Monitor::open(&namespace).unwrap();
    let mut seed = 0x2545_F491u64;
    let mut values_seen = std::collections::BTreeSet::new();
    for _ in 0..12 {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        std::thread::sleep(Duration::from_millis(50 + (seed >> 33) % 250));
        let pid = monitor.snapshot().unwrap().tasks[1].pid;
        if pid != 0 {
            // SAFETY: killing the saver's script process.
            unsafe { libc::kill(pid as i32, libc::SIGKILL) };
        }
        let bytes = std::fs::read(&table).unwrap();
        assert_eq!(bytes.len(), 512_000 * 8, "a whole table");
        let values: Vec<f64> = bytes.chunks(8).map(|c| f64::from_le_bytes(c.try_into().unwrap())).collect();
        assert!(values[..20_000].iter().all(|&v| v == values[0]), "one save's values, not a mix");
        assert!(values[20_000..].iter().all(|&v| v == 0.0), "nothing else written");
        values_seen.insert(values[0] as u64);
    }
    // SAFETY: asking the controller to shut down, as Ctrl-C does.
    unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
    let out = finish(child, Duration::from_secs(20));
    assert!(values_seen.len() > 1, "saves went on between the kills: {values_seen:?}\n{}", out.stderr);
}

fn tool(args: &[&str]) -> std::process::Output {
    Command::new(BIN).args(args).stdout(Stdio::piped()).stderr(Stdio::piped()).output().unwrap()
}

#[test]
fn the_tasks_and_events_tools() {
    let dir = tempfile::tempdir().unwrap();
    let main = program(
        dir.path(),
        "main.lua",
        "Sleep(300)\nSendEvent(7)\nSendMsgEvent('axis %d at %.1f', 0, 12.5)\nStartTask(1)\nSleep(1500)\n",
    );
    let looping = program(dir.path(), "loop.lua", "while true do end\n");
    let config = machine(dir.path(), 1000, &main, &[&looping]);
    let toml = std::fs::read_to_string(&config).unwrap() + "watchdog_ms = 100\n";
    std::fs::write(&config, toml).unwrap();
    let ns = unique_ns("tools");
    let child = start_run(&ns, &["--config", config.to_str().unwrap()]);
    assert!(eventually(Duration::from_secs(10), || tool(&["tasks", "--ns", &ns]).status.success()), "controller up");

    let events = Command::new(BIN)
        .args(["events", "--ns", &ns, "--count", "3"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let listing = || String::from_utf8_lossy(&tool(&["tasks", "--ns", &ns]).stdout).into_owned();
    let task0_running = |l: &str| l.starts_with("0 ") && l.contains("running");
    assert!(eventually(Duration::from_secs(10), || listing().lines().any(task0_running)), "{}", listing());
    let listing = listing();
    let task0 = listing.lines().find(|l| l.starts_with("0 ")).expect(&listing).to_string();
    assert!(task0.contains("500ms") && task0.contains("main.lua"), "{listing}");
    assert!(listing.lines().any(|l| l.starts_with("1 ") && l.contains("stopped")), "{listing}");

    let started = Instant::now();
    let events = events.wait_with_output().unwrap();
    let printed = String::from_utf8_lossy(&events.stdout).into_owned();
    let lines: Vec<&str> = printed.lines().collect();
    assert_eq!(lines.len(), 3, "{printed}\n{}", String::from_utf8_lossy(&events.stderr));
    assert!(lines[0].ends_with("task 0 event 7"), "{printed}");
    assert!(lines[1].ends_with("task 0 message \"axis 0 at 12.5\""), "{printed}");
    assert!(lines[2].contains("task 1 alarm 0x30014102: task 1: watchdog"), "{printed}");
    assert!(started.elapsed() < Duration::from_secs(10));

    let listing = String::from_utf8_lossy(&tool(&["tasks", "--ns", &ns]).stdout).into_owned();
    assert!(
        listing.lines().any(|l| l.starts_with("1 ") && l.contains("error") && l.contains("0x30014102")),
        "{listing}"
    );
    let out = finish(child, Duration::from_secs(20));
    assert!(out.stderr.contains("loop.lua): failed: task 1: watchdog"), "{}", out.stderr);
    assert!(!tool(&["tasks", "--ns", &ns]).status.success(), "no controller any more");
}

/// DXMC 0x001F end to end: two programs command axis 0 every cycle; in the cycles where
/// both commands land, the second is refused and the alarm is recorded.
#[test]
fn two_tasks_commanding_one_axis_in_one_cycle() {
    let dir = tempfile::tempdir().unwrap();
    // Both programs command on the cycles that are multiples of 4, so their commands land
    // in the same cycle unless one of them is woken a whole cycle late.
    let hammer = "local refused, other = 0, 0\n\
        for i = 1, 300 do\n\
          local next = (system_fclk // 4 + 1) * 4\n\
          Till(function() return system_fclk >= next end)\n\
          local rc = MoveAbs(0, (i % 2) * 0.01)\n\
          if rc == 0x1000001F then refused = refused + 1 elseif rc ~= 0 then other = other + 1 end\n\
        end\n\
        Print('refused %d other %d', refused, other)\n";
    let main = program(
        dir.path(),
        "main.lua",
        &format!("Enable(0) Till(function() return IsEnabled(0) end)\nStartTask(1)\n{hammer}"),
    );
    let second = program(dir.path(), "second.lua", hammer);
    let out = run_machine(&machine(dir.path(), 1000, &main, &[&second]), &[]);
    let refused = |task| {
        let line = out.lines_of_task(task).pop().unwrap_or_default();
        let fields: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(fields.get(3), Some(&"0"), "no other refusal: {line}\n{}", out.stderr);
        fields.get(1).and_then(|n| n.parse::<u32>().ok()).unwrap_or(0)
    };
    let total = refused(0) + refused(1);
    assert!(total > 0, "the two programs collided in some cycle\n{}\n{}", out.stdout, out.stderr);
    let alarms = out.stderr.matches("command buffer busy: axis 0").count() as u32;
    assert_eq!(alarms, total, "one alarm per refusal\n{}", out.stderr);
}

/// HMPL 16.4: `StopTask` ends the task's process within a few cycles.
#[test]
fn a_stopped_task_s_process_is_gone_within_a_few_cycles() {
    let dir = tempfile::tempdir().unwrap();
    let main = program(
        dir.path(),
        "main.lua",
        "StartTask(1)\nSleep(500)\nPrint('stopping at cycle %d', system_fclk)\nStopTask(1)\nSleep(500)\n",
    );
    let forever = program(dir.path(), "forever.lua", "while true do Sleep(10) end\n");
    let ns = unique_ns("stop");
    let child = start_run(&ns, &["--config", machine(dir.path(), 1000, &main, &[&forever]).to_str().unwrap()]);
    let namespace = ipc::Namespace::new(&ns).unwrap();
    assert!(eventually(Duration::from_secs(10), || ipc::controller_pid(&namespace).ok().flatten().is_some()));
    let mut monitor = ipc::Monitor::open(&namespace).unwrap();
    let mut pid = 0;
    assert!(eventually(Duration::from_secs(10), || {
        pid = monitor.snapshot().unwrap().tasks[1].pid;
        pid != 0
    }));
    let deadline = Instant::now() + Duration::from_secs(10);
    let gone_at = loop {
        let snapshot = monitor.snapshot().unwrap();
        if snapshot.tasks[1].pid == 0 && !process_alive(pid) {
            break Some(snapshot.cycle);
        }
        if Instant::now() > deadline {
            break None;
        }
        std::thread::sleep(Duration::from_millis(1));
    };
    let out = finish(child, Duration::from_secs(20));
    let line = out.lines_of_task(0).pop().expect(&out.stderr);
    let stopped_at: u64 = line.trim_start_matches("stopping at cycle ").parse().unwrap();
    let gone_at = gone_at.unwrap();
    // The StopTask call is applied in the cycle after the one the program read.
    assert!(gone_at > stopped_at && gone_at <= stopped_at + 20, "stopped at {stopped_at}, gone at {gone_at}");
    assert!(out.stderr.contains("forever.lua): stopped"), "{}", out.stderr);
}

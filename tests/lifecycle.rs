//! A task's whole life under the watchdog, and the controller's own life: a hang in any
//! phase of a program (top level, entry function, a finalizer, the VM's close, holding a
//! mutex) is caught and frees what the task held; every stop signal ends a run in order,
//! with no alarm and nothing left in shared memory; a run with nothing to run says so.

mod common;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::sync::mpsc::{Receiver, channel};
use std::time::Duration;

use common::*;

const WATCHDOG_MS: u64 = 100;

/// Task 0 hangs in one phase of its life; task 1 waits for mutex 0, which task 0 takes first.
struct Phase {
    name: &'static str,
    hung: &'static str,
    /// Started by task 1 at this function (`StartTaskFunc`) instead of autorun.
    entry: Option<&'static str>,
}

const PHASES: [Phase; 6] = [
    Phase { name: "top level", hung: "MutexLock(0)\nPrint('hanging')\nwhile true do end\n", entry: None },
    Phase {
        name: "entry function",
        hung: "function Hang()\n  MutexLock(0)\n  Print('hanging')\n  while true do end\nend\n",
        entry: Some("Hang"),
    },
    Phase {
        name: "finalizer run by a collection",
        hung: "MutexLock(0)\nsetmetatable({}, {__gc = function() while true do end end})\n\
               Print('hanging')\ncollectgarbage()\nPrint('not reached')\n",
        entry: None,
    },
    Phase {
        name: "finalizer run at VM close",
        hung: "MutexLock(0)\nkeep = setmetatable({}, {__gc = function() while true do end end})\nPrint('hanging')\n",
        entry: None,
    },
    Phase {
        name: "VM close after an error",
        hung: "MutexLock(0)\nkeep = setmetatable({}, {__gc = function() local x = 0 while true do x = x + 1 end end})\n\
               Print('hanging')\nerror('the program fails')\n",
        entry: None,
    },
    Phase {
        name: "a coroutine's finalizer at VM close",
        hung: "MutexLock(0)\nlocal co = coroutine.create(function() local t = setmetatable({}, {__gc = function() \
               while true do end end}) coroutine.yield(t) end)\nkeep = {coroutine.resume(co)}\nPrint('hanging')\n",
        entry: None,
    },
];

const WAITER: &str = "Sleep(20)\nMutexLock(0)\nPrint('got the mutex')\nMutexUnlock(0)\n";

fn hang(phase: &Phase) {
    let dir = tempfile::tempdir().unwrap();
    program(dir.path(), "hung.lua", phase.hung);
    let waiter = match phase.entry {
        Some(entry) => format!("StartTaskFunc(0, \"{entry}\")\n{WAITER}"),
        None => WAITER.to_string(),
    };
    program(dir.path(), "waiter.lua", &waiter);
    let machine = format!(
        "[[tasks]]\nid = 0\nprogram = \"hung.lua\"\nautorun = {}\nwatchdog_ms = {WATCHDOG_MS}\n\
         [[tasks]]\nid = 1\nprogram = \"waiter.lua\"\nautorun = true\n",
        phase.entry.is_none()
    );
    std::fs::write(dir.path().join("machine.toml"), machine).unwrap();
    let ns = unique_ns("hang");
    let config = dir.path().join("machine.toml");
    let out = run(&ns, &["--config", config.to_str().unwrap()]);
    let what = format!("{}\nstdout:\n{}\nstderr:\n{}", phase.name, out.stdout, out.stderr);

    assert_eq!(out.status.code(), Some(1), "{what}");
    assert_eq!(out.lines_of_task(0).first().map(String::as_str), Some("hanging"), "{what}");
    assert!(!out.stdout.contains("not reached"), "{what}");
    // Alarm 0x3TTT4102 with TTT = task 0, within the watchdog time plus 2 cycles.
    let alarm = out.stderr.lines().find(|l| l.contains("alarm 0x30004102")).unwrap_or_else(|| panic!("{what}"));
    let stalled: u64 = alarm
        .split("no progress for ")
        .nth(1)
        .and_then(|r| r.split(" ms").next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{what}"));
    assert!((WATCHDOG_MS..=WATCHDOG_MS + 2).contains(&stalled), "{what}");
    assert!(alarm.contains("watchdog_ms"), "the alarm says what to raise: {what}");
    // Its mutex went free with its process: the other task got it and ended.
    assert_eq!(out.lines_of_task(1), ["got the mutex"], "{what}");
    assert!(out.stderr.contains("waiter.lua): finished"), "{what}");
    assert!(shm_files(&ns).is_empty(), "{what}");
}

#[test]
fn a_hang_is_caught_in_every_phase_of_a_task_life() {
    for phase in &PHASES {
        hang(phase);
    }
}

fn lines_of(stream: impl std::io::Read + Send + 'static) -> Receiver<String> {
    let (tx, rx) = channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stream).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    rx
}

/// A controller running two programs that move axes and wait, sent `signals` once both run.
fn stop_with(signals: &[i32]) -> (Option<i32>, String, String) {
    let dir = tempfile::tempdir().unwrap();
    let source = "Enable(_TASKID_)\nTill(function() return IsEnabled(_TASKID_) end)\nMoveVel(_TASKID_, 10)\n\
                  Print('running')\nwhile true do Sleep(5) end\n";
    let a = program(dir.path(), "a.lua", source);
    let b = program(dir.path(), "b.lua", source);
    let ns = unique_ns("signal");
    let mut child = Command::new(BIN)
        .args(["run", "--ns", &ns, "--data-dir"])
        .arg(data_dir(&ns))
        .args([&a, &b])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stdout = lines_of(child.stdout.take().unwrap());
    let mut running = 0;
    while running < 2 {
        let line = stdout.recv_timeout(Duration::from_secs(30)).expect("both programs run");
        running += line.ends_with("running") as usize;
    }
    for &signal in signals {
        // SAFETY: signalling the controller this test started.
        unsafe { libc::kill(child.id() as i32, signal) };
    }
    let out = finish(child, Duration::from_secs(20));
    let files = shm_files(&ns);
    assert!(files.is_empty(), "after {signals:?}: left in shared memory: {files:?}");
    (out.status.code(), out.stdout, out.stderr)
}

/// Every stop signal ends a run in order, whatever comes after it (GNU `timeout` and
/// systemd send SIGCONT right behind SIGTERM); the stop the user asked for is no alarm.
#[test]
fn every_stop_signal_ends_a_run_in_order() {
    let cases: [(&[i32], i32); 5] = [
        (&[libc::SIGTERM, libc::SIGCONT], 128 + libc::SIGTERM),
        (&[libc::SIGINT], 128 + libc::SIGINT),
        (&[libc::SIGHUP], 128 + libc::SIGHUP),
        (&[libc::SIGQUIT, libc::SIGCHLD], 128 + libc::SIGQUIT),
        (&[libc::SIGTERM], 128 + libc::SIGTERM),
    ];
    for (signals, code) in cases {
        let (status, stdout, stderr) = stop_with(signals);
        let what = format!("{signals:?}\nstdout:\n{stdout}\nstderr:\n{stderr}");
        assert_eq!(status, Some(code), "{what}");
        for task in 0..2 {
            let name = if task == 0 { "a.lua" } else { "b.lua" };
            let stopped =
                |l: &str| l.starts_with(&format!("task {task} (")) && l.ends_with(&format!("{name}): stopped"));
            assert!(stderr.lines().any(stopped), "{what}");
        }
        assert!(!stderr.contains("alarm"), "an orderly stop raises no alarm: {what}");
        assert!(!stderr.contains("died of signal"), "{what}");
        assert!(!stderr.contains("failed"), "{what}");
    }
}

/// `luamotion run` with nothing to run says so and exits with 2, instead of waiting forever
/// or ending at once: no program, a task not autorun, an autorun task that is external
/// (the user's to start).
#[test]
fn a_run_with_nothing_to_run_says_so() {
    let dir = tempfile::tempdir().unwrap();
    program(dir.path(), "idle.lua", "Print('never started')\n");
    std::fs::write(dir.path().join("machine.toml"), "[[tasks]]\nid = 3\nprogram = \"idle.lua\"\nautorun = false\n")
        .unwrap();
    std::fs::write(
        dir.path().join("external.toml"),
        "[[tasks]]\nid = 0\nprogram = \"idle.lua\"\nautorun = true\nexternal = true\n",
    )
    .unwrap();
    let (config, external) = (dir.path().join("machine.toml"), dir.path().join("external.toml"));
    for args in [vec![], vec!["--config", config.to_str().unwrap()], vec!["--config", external.to_str().unwrap()]] {
        let ns = unique_ns("idle");
        let out = finish(start_run(&ns, &args), Duration::from_secs(20));
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", out.stderr);
        assert!(out.stderr.contains("nothing to run"), "{args:?}: {}", out.stderr);
        assert!(shm_files(&ns).is_empty());
    }
}

/// A second `serve` or `run` in a namespace a served controller holds is refused: the
/// first line it prints names that controller and its pid, nothing comes before it, and
/// the first controller goes on serving.
#[test]
fn a_second_controller_in_a_namespace_in_use_names_the_first() {
    let ns = unique_ns("in-use");
    let dir = tempfile::tempdir().unwrap();
    let first = common::serve::serve(&ns, dir.path(), &[]);
    let expected = format!("error: a controller (pid {}) is already running in namespace {ns}", first.pid());
    let second = tempfile::tempdir().unwrap();
    let data_dir = second.path().to_str().unwrap();
    let program = program(second.path(), "second.lua", "Print('the second ran')\n");
    let serve_again = ["serve", "--ns", &ns, "--data-dir", data_dir, "--modbus-port", "0", "--ascii-port", "0"];
    let run_again = ["run", "--ns", &ns, "--data-dir", data_dir, program.to_str().unwrap()];
    for args in [&serve_again[..], &run_again[..]] {
        let child = Command::new(BIN).args(args).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
        let out = finish(child, Duration::from_secs(30));
        assert_eq!(out.status.code(), Some(1), "{args:?}: {}", out.stderr);
        assert_eq!(out.stderr.lines().next(), Some(expected.as_str()), "{args:?}, stderr:\n{}", out.stderr);
        assert_eq!(out.stderr.lines().count(), 1, "{args:?} says one thing only:\n{}", out.stderr);
        assert!(out.stdout.is_empty(), "{args:?} printed {:?}", out.stdout);
    }
    let tasks = finish(
        Command::new(BIN).args(["tasks", "--ns", &ns]).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap(),
        Duration::from_secs(30),
    );
    assert!(tasks.status.success() && tasks.stdout.contains("cycle"), "the first still runs: {}", tasks.stderr);
    let logged = first.stderr();
    assert!(!logged.contains("WARN") && !logged.contains("ERROR"), "the first controller was disturbed: {logged}");
}

//! The fault-injection matrix (fault kind x fault reaction), end to end: a faulty program
//! moves axis 0 and a healthy one moves axis 1. Each run checks that the fault is detected
//! within the watchdog time + 2 cycles, that axis 0 reacts as configured in the cycle of
//! detection, that axis 1's trajectory is sample for sample the one of a run without the
//! fault, that the core missed no cycle because of it, and that the alarm is visible.

mod common;

use std::collections::HashMap;
use std::process::{Child, Command, Stdio};
use std::sync::{Mutex, OnceLock};
use std::time::Duration;

use common::*;

const WATCHDOG_MS: u64 = 200;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Fault {
    /// `while true do end`
    EndlessLoop,
    /// A 1 GiB string built two bytes at a time: a second inside one C function.
    HangInC,
    /// The process stopped with SIGSTOP.
    Stopped,
    Segfault,
    Abort,
    Kill9,
    /// The task's memory limit.
    OutOfMemory,
}

impl Fault {
    /// The alarm event the fault raises (DXMC format, source 3, task 0).
    fn alarm(self) -> &'static str {
        match self {
            Fault::EndlessLoop | Fault::HangInC | Fault::Stopped => "(alarm 0x30004102)",
            Fault::Segfault | Fault::Abort | Fault::Kill9 => "(alarm 0x30004104)",
            Fault::OutOfMemory => "(alarm 0x30004103)",
        }
    }

    fn signal(self) -> Option<i32> {
        match self {
            Fault::Stopped => Some(libc::SIGSTOP),
            Fault::Segfault => Some(libc::SIGSEGV),
            Fault::Abort => Some(libc::SIGABRT),
            Fault::Kill9 => Some(libc::SIGKILL),
            _ => None,
        }
    }

    /// What the faulty program does once axis 0 moves.
    fn lua(self) -> &'static str {
        match self {
            Fault::EndlessLoop => "while true do end",
            Fault::HangInC => "local s = string.rep('ab', 1 << 29)",
            Fault::OutOfMemory => "local s = string.rep('x', 1 << 26)",
            // The test sends the signal; meanwhile the program keeps calling the controller.
            _ => "while true do Sleep(1) end",
        }
    }

    fn memory_limit_mib(self) -> u32 {
        match self {
            Fault::HangInC => 4096,
            _ => 32,
        }
    }
}

const REACTIONS: [&str; 4] = ["none", "decelerate", "quick_stop", "disable"];

/// Task 0 sets axis 0 going, then faults (or, in the reference run, ends quietly).
fn faulty_program(fault: Option<Fault>) -> String {
    let act = match fault {
        Some(f) => f.lua(),
        None => "Sleep(1500)",
    };
    format!(
        "Enable(0) Till(function() return IsEnabled(0) end)\n\
         MoveAbs(0, 1000)\n\
         Sleep(300)\n\
         Print('fault at cycle %d', system_fclk)\n\
         {act}\n"
    )
}

/// Task 1 moves axis 1 while task 0 faults, and says in which cycle its move began.
const HEALTHY: &str = "Enable(1) Till(function() return IsEnabled(1) end)\n\
    Sleep(100)\n\
    MoveAbs(1, 100)\n\
    local c0 = system_fclk\n\
    Till(function() return IsInPos(1) end)\n\
    Print('moved from cycle %d to %d', c0, system_fclk)\n";

struct Run {
    stdout: Vec<String>,
    stderr: String,
    trace: Vec<HashMap<String, f64>>,
    /// The cycle the test read right before it sent its signal.
    signalled_at: Option<u64>,
}

impl Run {
    fn line(&self, prefix: &str) -> Option<&str> {
        self.stdout.iter().find_map(|l| l.strip_prefix(prefix))
    }

    /// The cycle in which the core raised the alarm.
    fn detected_at(&self) -> u64 {
        let line = self.stderr.lines().find(|l| l.contains("(alarm 0x3000")).expect("an alarm in the log");
        let cycle = line.split("cycle=").nth(1).expect("cycle= in the alarm line");
        cycle.split_whitespace().next().unwrap().parse().unwrap()
    }

    fn row(&self, cycle: u64) -> &HashMap<String, f64> {
        self.trace
            .iter()
            .find(|r| r["cycle"] as u64 == cycle)
            .unwrap_or_else(|| panic!("no trace row for cycle {cycle}"))
    }

    fn healthy_move(&self) -> (u64, u64) {
        let line = self.line("[task 1] moved from cycle ").expect("the healthy task moved");
        let (from, to) = line.split_once(" to ").unwrap();
        (from.parse().unwrap(), to.parse().unwrap())
    }
}

fn run(fault: Option<Fault>, reaction: &str) -> Run {
    let dir = tempfile::tempdir().unwrap();
    program(dir.path(), "faulty.lua", &faulty_program(fault));
    program(dir.path(), "healthy.lua", HEALTHY);
    let memory = fault.map_or(32, Fault::memory_limit_mib);
    let machine = format!(
        "[[axes]]\n[[axes]]\n\
         [[tasks]]\nid = 0\nprogram = \"faulty.lua\"\nautorun = true\nwatchdog_ms = {WATCHDOG_MS}\n\
         fault_reaction = \"{reaction}\"\nmemory_limit_mib = {memory}\n\
         [[tasks]]\nid = 1\nprogram = \"healthy.lua\"\nautorun = true\n"
    );
    std::fs::write(dir.path().join("machine.toml"), machine).unwrap();
    let ns = unique_ns("fault");
    let trace = dir.path().join("trace.csv");
    let mut child: Child = Command::new(BIN)
        .args(["run", "--ns", &ns, "--config"])
        .arg(dir.path().join("machine.toml"))
        .arg("--trace")
        .arg(&trace)
        .arg("--data-dir")
        .arg(data_dir(&ns))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stdout = lines_of(child.stdout.take().unwrap());
    let stderr = lines_of(child.stderr.take().unwrap());
    let mut out = Vec::new();
    let mut signalled_at = None;
    if let Some(signal) = fault.and_then(Fault::signal) {
        loop {
            let line = stdout.recv_timeout(Duration::from_secs(20)).expect("the faulty task says when");
            let ready = line.starts_with("[task 0] fault at cycle");
            out.push(line);
            if ready {
                break;
            }
        }
        let mut monitor = ipc::Monitor::open(&ipc::Namespace::new(&ns).unwrap()).unwrap();
        let snapshot = monitor.snapshot().unwrap();
        let pid = snapshot.tasks[0].pid;
        signalled_at = Some(snapshot.cycle);
        assert!(pid > 0, "task 0 has a process");
        // SAFETY: signalling the script process of task 0.
        unsafe { libc::kill(pid as i32, signal) };
    }
    let finished = finish(child, Duration::from_secs(60));
    out.extend(rest_of(&stdout, Duration::from_secs(10)));
    out.extend(finished.stdout.lines().map(str::to_string));
    let mut err = rest_of(&stderr, Duration::from_secs(10));
    err.push(finished.stderr);
    Run { stdout: out, stderr: err.join("\n"), trace: e2e::read_trace(&trace), signalled_at }
}

/// The run without a fault: axis 1's reference, cycle by cycle from its move's start.
fn reference() -> &'static Vec<(f64, f64)> {
    static REFERENCE: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    REFERENCE.get_or_init(|| {
        let run = run(None, "decelerate");
        assert!(!run.stderr.contains("alarm"), "{}", run.stderr);
        healthy_trajectory(&run)
    })
}

/// Axis 1's (reference, feedback) from the cycle its one move began to the cycle it was in
/// position, both read from the trace's status words (HMPL table 5.1.1.5: bit 1 Moving,
/// bit 2 InPos): the cycle number the program read after `MoveAbs` may be a cycle later,
/// or, on a loaded machine, several.
fn healthy_trajectory(run: &Run) -> Vec<(f64, f64)> {
    let (told, _) = run.healthy_move();
    let status = |c: u64| run.row(c)["a1_motion_status"] as u32;
    let first = run.trace.first().expect("a trace")["cycle"] as u64;
    let start = (first..).find(|&c| status(c) & 0b010 != 0).unwrap();
    assert!(start <= told + 3, "axis 1 moved at cycle {start}, after the program said {told}");
    let end = (start..).find(|&c| status(c) & 0b110 == 0b100).unwrap();
    (start..=end).map(|c| (run.row(c)["a1_ref_pos"], run.row(c)["a1_pos_fb"])).collect()
}

/// HMPL table 5.1.1.5: motion_status bit 0, Enabled.
fn enabled(row: &HashMap<String, f64>) -> bool {
    row["a0_motion_status"] as u32 & 1 != 0
}

fn check(fault: Fault, reaction: &str) {
    // One faulty controller at a time: the per-cycle bound below is about the fault
    // handling's own work, which seven debug controllers sharing 2 CPUs would blur.
    static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    // A cycle over the CPU budget with neither page faults nor preemptions in it is a
    // stall of the virtual machine charged as CPU time (12.9 ms seen once): the run is
    // made once more; the fault handling's own work would be over again.
    match check_once(fault, reaction) {
        Over::None => {}
        Over::Stalled(first) => {
            eprintln!("{fault:?} / {reaction}: a stall of the machine, run again: {first}");
            if let Over::Stalled(message) | Over::Work(message) = check_once(fault, reaction) {
                panic!("{message}\n(the run before: {first})");
            }
        }
        Over::Work(message) => panic!("{message}"),
    }
}

/// Cycles over the CPU budget after a fault: none, only stall-like ones, or others.
enum Over {
    None,
    Stalled(String),
    Work(String),
}

/// One run of `fault` with `reaction`, every check asserted but the CPU budget's, which is
/// returned.
fn check_once(fault: Fault, reaction: &str) -> Over {
    let run = run(Some(fault), reaction);
    let context = format!("{fault:?} / {reaction}\n{}\n{}", run.stdout.join("\n"), run.stderr);

    // The alarm is visible: in the log, and as the task's outcome.
    assert!(run.stderr.contains(fault.alarm()), "alarm {}: {context}", fault.alarm());
    assert!(run.stderr.contains("faulty.lua): failed"), "{context}");

    // Detected within the watchdog time + 2 cycles of the fault (1 ms cycles). The test's
    // own reading of the cycle before a signal may be one cycle old.
    let faulted_at: u64 = match run.signalled_at {
        Some(cycle) => cycle,
        None => run.line("[task 0] fault at cycle ").expect("fault line").parse().unwrap(),
    };
    let detected = run.detected_at();
    let slack = if run.signalled_at.is_some() { 1 } else { 0 };
    assert!(
        detected <= faulted_at + WATCHDOG_MS + 2 + slack,
        "detected at {detected}, fault at {faulted_at}: {context}"
    );

    // Axis 0 reacts as configured, from the cycle of detection.
    let before = run.row(detected - 1);
    let at = run.row(detected);
    let later = run.row(detected + 100);
    let advanced = |r: &HashMap<String, f64>| r["a0_ref_pos"] - before["a0_ref_pos"];
    assert!(enabled(before) && advanced(at) > 0.0, "axis 0 was moving: {context}");
    match reaction {
        "none" => assert!(
            enabled(later) && (advanced(later) - 10.1).abs() < 0.2,
            "none: axis 0 goes on at 100 mm/s: {context}"
        ),
        "decelerate" => {
            // 100 mm/s at the kill deceleration (50 000 mm/s²) stops within 2 ms.
            assert!(advanced(run.row(detected + 3)) == advanced(later), "decelerate: stopped: {context}");
            assert!(advanced(at) < 0.1, "decelerate: already slower in the cycle of detection: {context}");
            assert!(enabled(later), "decelerate: axis 0 stays enabled: {context}");
        }
        "quick_stop" => {
            assert!(!enabled(at), "quick stop: the drive leaves Operation enabled at once: {context}");
            assert!(!enabled(later), "quick stop: axis 0 ends disabled: {context}");
            let fb = |c: u64| run.row(c)["a0_pos_fb"];
            assert!((fb(detected + 100) - fb(detected + 90)).abs() < 1e-3, "quick stop: the motor stands: {context}");
        }
        "disable" => {
            assert!(!enabled(run.row(detected + 2)), "disable: disabled within the bus delay: {context}");
        }
        other => panic!("unknown reaction {other}"),
    }

    // Axis 1: the same trajectory, sample for sample, as without the fault.
    let trajectory = healthy_trajectory(&run);
    assert_eq!(trajectory.len(), reference().len(), "axis 1's move took as long: {context}");
    for (k, (got, want)) in trajectory.iter().zip(reference()).enumerate() {
        assert_eq!(got.0, want.0, "axis 1 reference, {k} cycles into its move: {context}");
        assert!((got.1 - want.1).abs() < 1e-9, "axis 1 feedback, {k} cycles into its move: {context}");
    }

    // The core missed no cycle because of it: the cycles that detect the fault, react,
    // order the kill and handle the process' end (ARCHITECTURE.md invariant 1) each use
    // less CPU time than their period, in a debug build too (at most 0.31 ms seen). CPU
    // time, not wall time: on two cores shared with the other tests a cycle can be
    // preempted, which is the OS's doing, not the fault handling's (its wall time is in
    // the trace too).
    // Each over the budget is told with the RT thread's page faults and preemptions in it:
    // work on memory it had not touched shows as faults, a stall charged as CPU time as none.
    let budget_us = 1000.0;
    let rows: Vec<(u64, &HashMap<String, f64>)> = (detected..detected + 50)
        .map(|c| (c, run.row(c + 1)))
        .filter(|(_, next)| next["previous_cpu_us"] >= budget_us)
        .collect();
    let over: Vec<String> = rows
        .iter()
        .map(|(c, next)| {
            let column = |name: &str| next[name];
            format!(
                "cycle {c}: {} us of CPU time in {} us, {} page faults, {} preemptions",
                column("previous_cpu_us"),
                column("previous_execution_us"),
                column("previous_faults"),
                column("previous_preemptions")
            )
        })
        .collect();
    let message = format!("cycles over {budget_us} us of CPU time: {over:?}: {context}");
    let stall = |next: &HashMap<String, f64>| next["previous_faults"] == 0.0 && next["previous_preemptions"] == 0.0;
    match rows.is_empty() {
        true => Over::None,
        false if rows.iter().all(|(_, next)| stall(next)) => Over::Stalled(message),
        false => Over::Work(message),
    }
}

fn matrix(fault: Fault) {
    for reaction in REACTIONS {
        check(fault, reaction);
    }
}

#[test]
fn endless_lua_loop() {
    matrix(Fault::EndlessLoop);
}

#[test]
fn hang_inside_a_c_function() {
    matrix(Fault::HangInC);
}

#[test]
fn process_stopped_with_sigstop() {
    matrix(Fault::Stopped);
}

#[test]
fn segmentation_fault() {
    matrix(Fault::Segfault);
}

#[test]
fn abort() {
    matrix(Fault::Abort);
}

#[test]
fn kill_9() {
    matrix(Fault::Kill9);
}

#[test]
fn memory_limit() {
    matrix(Fault::OutOfMemory);
}

/// The lines a child wrote just before it ended are kept: they are read until its pipe
/// closes, not taken from what the reader thread had passed on when the child was reaped.
#[test]
fn the_last_lines_of_an_ended_child_are_kept() {
    let mut child = Command::new("sh")
        .args(["-c", "for i in $(seq 1 2000); do echo line $i; done"])
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let lines = lines_of(child.stdout.take().unwrap());
    child.wait().unwrap();
    let got = rest_of(&lines, Duration::from_secs(10));
    assert_eq!(got.len(), 2000, "last: {:?}", got.last());
    assert_eq!(got.last().map(String::as_str), Some("line 2000"));
}

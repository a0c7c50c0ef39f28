//! End to end: the simulation clock (`run --clock sim`): simulated time for the programs'
//! waits, the same trace and digest run after run, the watchdog still honest.

mod common;

use std::path::{Path, PathBuf};
use std::time::Duration;

use common::*;

/// A machine file with `axes` axes in `dir`.
fn machine(dir: &Path, axes: usize) -> PathBuf {
    let path = dir.join("machine.toml");
    std::fs::write(&path, "[[axes]]\n".repeat(axes)).unwrap();
    path
}

/// `luamotion run --clock sim --speed max` of `programs` (tasks 0, 1, ...) on a machine
/// with `axes` axes, with a trace into `dir`; at most `timeout` of wall time.
fn run_sim(dir: &Path, axes: usize, programs: &[PathBuf], trace: &str, timeout: Duration) -> Finished {
    let ns = unique_ns("sim");
    let config = machine(dir, axes);
    let trace = dir.join(trace);
    let mut args = vec!["--config", config.to_str().unwrap(), "--clock", "sim", "--speed", "max", "--trace"];
    args.push(trace.to_str().unwrap());
    args.extend(programs.iter().map(|p| p.to_str().unwrap()));
    finish(start_run(&ns, &args), timeout)
}

/// The digest line's `fnv1a64:...` and its cycle count.
fn digest(out: &Finished) -> (String, u64) {
    let line = out.stderr.lines().find(|l| l.contains("trace digest")).unwrap_or_else(|| panic!("{}", out.stderr));
    let words: Vec<&str> = line.split_whitespace().collect();
    let at = words.iter().position(|w| w.starts_with("fnv1a64:")).expect("a digest");
    (words[at].to_string(), words[at + 2].parse().expect("cycles"))
}

#[test]
fn sleep_follows_simulated_time() {
    let dir = tempfile::tempdir().unwrap();
    let program = program(
        dir.path(),
        "sleep.lua",
        "local c, t = system_fclk, system_timeInMs\n\
         Sleep(1000)\n\
         Print('slept %d cycles, %d ms', system_fclk - c, system_timeInMs - t)\n\
         c = system_fclk\n\
         Sleep(30000)\n\
         Print('slept %d cycles', system_fclk - c)\n",
    );
    // 31 s of simulated time in less than 25 s of wall time: the clock does not wait for
    // the wall (the run takes a few seconds even in a debug build on a loaded machine).
    let out = run_sim(dir.path(), 1, &[program], "trace.csv", Duration::from_secs(25));
    assert!(out.status.success(), "{}", out.stderr);
    assert_eq!(out.lines_of_task(0), ["slept 1000 cycles, 1000 ms", "slept 30000 cycles"], "{}", out.stderr);
    let (_, cycles) = digest(&out);
    assert!((31_000..31_010).contains(&cycles), "the record ends with the program: {cycles} cycles");
}

/// Task `axis` of `tasks`: takes mutex 0 in turn with the others, counts in the user
/// table, holds the mutex across a Sleep, moves its axis to where its count says (so the
/// trace shows the order the tasks took the mutex in), sends an event.
fn contender(dir: &Path, axis: usize) -> PathBuf {
    let source = format!(
        "local axis = {axis}\n\
         Enable(axis)\n\
         Till(function() return IsEnabled(axis) end)\n\
         local n = 0\n\
         for round = 1, 4 do\n\
           MutexLock(0)\n\
           local rc, v = GetUserTable(0, 1)\n\
           n = v[1] + 1\n\
           SetUserTable(0, 1, {{n}})\n\
           Sleep(1 + axis)\n\
           MutexUnlock(0)\n\
           SendEvent(100 + axis)\n\
           MoveAbs(axis, n * 5)\n\
           Till(function() return IsInPos(axis) end)\n\
         end\n\
         Print('last count %d', n)\n"
    );
    program(dir, &format!("contender{axis}.lua"), &source)
}

/// Polls without a wait until the others have counted to `total`, letting them go first
/// now and then: its share of each cycle lets the clock go on.
fn poller(dir: &Path, total: usize) -> PathBuf {
    let source = format!(
        "local polls = 0\n\
         while true do\n\
           local rc, v = GetUserTable(0, 1)\n\
           if v[1] >= {total} then break end\n\
           polls = polls + GetGPI(0) + 1\n\
           if polls % 7 == 0 then RunScheduler() end\n\
         end\n\
         Print('polled %d times', polls)\n"
    );
    program(dir, "poller.lua", &source)
}

/// Runs `programs` twice; both runs must give the same digest, trace file and output.
fn twice_the_same(dir: &Path, axes: usize, programs: &[PathBuf]) -> Vec<Finished> {
    let runs: Vec<Finished> =
        ["a.csv", "b.csv"].iter().map(|trace| run_sim(dir, axes, programs, trace, Duration::from_secs(120))).collect();
    for out in &runs {
        assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    }
    assert_eq!(digest(&runs[0]), digest(&runs[1]), "{}\n{}", runs[0].stderr, runs[1].stderr);
    let (a, b) = (std::fs::read(dir.join("a.csv")).unwrap(), std::fs::read(dir.join("b.csv")).unwrap());
    assert!(a == b, "the trace files differ");
    for task in 0..programs.len() as u8 {
        assert_eq!(runs[0].lines_of_task(task), runs[1].lines_of_task(task), "task {task}");
    }
    runs
}

#[test]
fn two_runs_with_mutexes_events_and_motion_give_the_same_trace() {
    let dir = tempfile::tempdir().unwrap();
    let programs: Vec<PathBuf> = (0..3).map(|axis| contender(dir.path(), axis)).collect();
    let runs = twice_the_same(dir.path(), 3, &programs);
    // The tasks really interleaved: the counts went up to 3 x 4 in all.
    let last: Vec<String> = (0..3).flat_map(|t| runs[0].lines_of_task(t)).collect();
    assert!(last.contains(&"last count 12".to_string()), "{last:?}");
}

#[test]
fn eight_tasks_and_a_busy_poller_give_the_same_trace() {
    let dir = tempfile::tempdir().unwrap();
    let mut programs: Vec<PathBuf> = (0..8).map(|axis| contender(dir.path(), axis)).collect();
    programs.push(poller(dir.path(), 8 * 4));
    let runs = twice_the_same(dir.path(), 8, &programs);
    let polled = runs[0].lines_of_task(8);
    assert!(polled.len() == 1 && polled[0].starts_with("polled "), "{polled:?}");
}

/// A `Till` condition that makes only status queries is evaluated again only in a cycle in
/// which one of their answers changed (calls::watch): the run is the same as with a
/// condition that also reads the time and is evaluated every cycle, and a 2 s move, four
/// times the watchdog time, is no hang.
#[test]
fn a_watched_till_condition_gives_the_same_run_with_fewer_evaluations() {
    let dir = tempfile::tempdir().unwrap();
    let mut runs = Vec::new();
    for (name, also) in [("watched", ""), ("every_cycle", "local _ = system_fclk; ")] {
        let source = format!(
            "Enable(0)\n\
             Till(function() return IsEnabled(0) end)\n\
             SetVel(0, 50)\n\
             MoveAbs(0, 100)\n\
             local n = 0\n\
             Till(function() n = n + 1; {also}return IsInPos(0) end)\n\
             Print('%d evaluations, in position at cycle %d', n, system_fclk)\n"
        );
        let program = program(dir.path(), &format!("{name}.lua"), &source);
        let out = run_sim(dir.path(), 1, &[program], &format!("{name}.csv"), Duration::from_secs(60));
        assert!(out.status.success(), "{}", out.stderr);
        let line = out.lines_of_task(0).pop().unwrap_or_else(|| panic!("{}", out.stderr));
        let evaluations: u64 = line.split_whitespace().next().unwrap().parse().unwrap();
        let at = line.rsplit(' ').next().unwrap().to_string();
        runs.push((digest(&out), std::fs::read(dir.path().join(format!("{name}.csv"))).unwrap(), evaluations, at));
    }
    let (watched, every) = (&runs[0], &runs[1]);
    assert_eq!(watched.0, every.0, "the same digest");
    assert!(watched.1 == every.1, "the same trace file");
    assert_eq!(watched.3, every.3, "in position at the same cycle");
    assert!(every.2 >= 2000, "evaluated every cycle of the 2 s move: {}", every.2);
    // Once at the move's start, once in the cycle the axis came in position; the bit's
    // flicker as it settles may add a few.
    assert!(watched.2 <= 6, "evaluated only when IsInPos changed: {}", watched.2);
}

#[test]
fn a_hung_task_is_still_caught_and_the_others_go_on() {
    let dir = tempfile::tempdir().unwrap();
    let hung = program(dir.path(), "hung.lua", "Sleep(10)\nwhile true do end\n");
    let sleeper = program(dir.path(), "sleeper.lua", "Sleep(3000)\nPrint('slept %d', system_fclk)\n");
    let out = run_sim(dir.path(), 1, &[hung, sleeper], "trace.csv", Duration::from_secs(60));
    assert!(!out.status.success(), "{}", out.stderr);
    // Let go after its watchdog time of wall time, caught after as many cycles (500 ms).
    assert!(out.stderr.contains("task 0: watchdog: no progress for 500 ms"), "{}", out.stderr);
    assert!(out.stderr.contains("sleeper.lua): finished"), "{}", out.stderr);
    assert_eq!(out.lines_of_task(1).len(), 1, "{}", out.stderr);
}

/// A Modbus client holds the clock while it waits for the server (here another
/// controller's, `luamotion serve`): its answers come at the same cycle in every run.
#[test]
fn a_modbus_client_beside_mutexes_gives_the_same_trace() {
    let dir = tempfile::tempdir().unwrap();
    let server = common::serve::serve(&unique_ns("sim-mb"), dir.path(), &[]);
    let client = program(
        dir.path(),
        "client.lua",
        &format!(
            "local rc, s = Modbus_ClientConnect('127.0.0.1:{port}')\n\
             Enable(3)\n\
             Till(function() return IsEnabled(3) end)\n\
             for i = 1, 6 do\n\
               MutexLock(0)\n\
               Modbus_ClientWrite_HoldReg(s, 0x0100, 1, {{i * 7}})\n\
               local rc, bytes = Modbus_ClientRead_HoldReg(s, 0x0100, 1)\n\
               MutexUnlock(0)\n\
               MoveAbs(3, bytes[2] + i)\n\
               Sleep(2)\n\
             end\n\
             Till(function() return IsInPos(3) end)\n\
             Print('read %.0f', GetPosFb(3))\n\
             Modbus_ClientDisconnect(s)\n",
            port = server.port
        ),
    );
    let mut programs: Vec<PathBuf> = (0..3).map(|axis| contender(dir.path(), axis)).collect();
    programs.push(client);
    let runs = twice_the_same(dir.path(), 4, &programs);
    assert_eq!(runs[0].lines_of_task(3), ["read 48"], "{}", runs[0].stderr);
}

//! Issue 36.4 end to end: a call with more values than its function takes is an error at
//! the caller's line that names the function and its signature, and does nothing. The
//! issue's own calls, on a real controller with a second task running beside the first.
//! Every function of the registry: script-host's `bindings::call_tests`.

mod common;

use std::time::Duration;

use common::*;

/// Task 1 counts in the user table until it is stopped.
const COUNTER: &str = "local n = 0\nwhile true do n = n + 1 SetTableValue(1, n) Sleep(5) end\n";

/// Task 0: waits for task 1 to count, makes the issue's calls (each line its own, so that
/// each error names its line), checks that none did anything, then ends on one uncaught.
const CALLS: &str = r#"local deadline = system_timeInMs + 5000
Till(function() return GetTableValue(1) > 0 or system_timeInMs > deadline end)
local vel = GetVel(0)
Print("%s", select(2, pcall(MoveAbs, 0, 100, 5, 7)))
Print("%s", select(2, pcall(Enable, 0, 1)))
Print("%s", select(2, pcall(SetVel, 0, 100, 1)))
Print("%s", select(2, pcall(SetPos, 0, 0, 0)))
Print("%s", select(2, pcall(StopTask, 1, 2)))
Print("%s", select(2, pcall(SaveUserTable, 0, 1, 2, 3)))
Print("%s", select(2, pcall(FreePort.Eth.Close, 0, 1)))
local counted = GetTableValue(1)
Sleep(100)
Print("task 1 counts on: %s", tostring(GetTableValue(1) > counted and not IsTaskStop(1)))
Print("axis 0 enabled: %s, vel kept: %s", tostring(IsEnabled(0)), tostring(GetVel(0) == vel))
Print("%d %d %d %s", 1, 2, 3, "variadic")
StopTask(1)
SetVel(0, 100, 1)
Print("never printed")
"#;

#[test]
fn the_issues_calls_are_refused_and_do_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let calls = program(dir.path(), "extra.lua", CALLS);
    let counter = program(dir.path(), "counter.lua", COUNTER);
    let ns = unique_ns("extra-args");
    // The check refuses these calls before the start (tests/check.rs); here the VM's own
    // refusal is what is tested.
    let args = ["--no-check", calls.to_str().unwrap(), counter.to_str().unwrap()];
    let out = finish(start_run(&ns, &args), Duration::from_secs(60));
    let context = format!("{}\n{}", out.stdout, out.stderr);
    let at = |line: u32, message: &str| format!("extra.lua:{line}: {message}");
    let want = [
        at(4, "MoveAbs takes 2 argument(s), got 4: int MoveAbs(int axis_id, double pos)"),
        at(5, "Enable takes 1 argument(s), got 2: int Enable(int axis_id)"),
        at(6, "SetVel takes 2 argument(s), got 3: int SetVel(int axis_id, double vel)"),
        at(7, "SetPos takes 2 argument(s), got 3: int SetPos(int axis_id, double pos)"),
        at(8, "StopTask takes 1 argument(s), got 2: int StopTask(int task_id)"),
        at(9, "SaveUserTable takes 2 argument(s), got 4: int SaveUserTable(int start_idx, int num_data)"),
        at(10, "FreePort.Eth.Close takes 1 argument(s), got 2: int FreePort.Eth.Close(int SessionID)"),
    ];
    let lines = out.lines_of_task(0);
    assert_eq!(lines.len(), want.len() + 3, "{context}");
    for (line, want) in lines.iter().zip(&want) {
        assert!(line.ends_with(want.as_str()), "{line:?} does not end with {want:?}\n{context}");
    }
    assert_eq!(
        lines[want.len()..],
        ["task 1 counts on: true", "axis 0 enabled: false, vel kept: true", "1 2 3 variadic"],
        "{context}"
    );
    // Uncaught, the error ends the program at its line.
    let uncaught = at(17, "SetVel takes 2 argument(s), got 3: int SetVel(int axis_id, double vel)");
    assert!(out.stderr.contains(&uncaught), "{context}");
    assert!(!out.stderr.contains("panicked"), "{context}");
    // SaveUserTable(0, 1, 2, 3) wrote no file.
    let saved = std::fs::read_dir(data_dir(&ns)).map(|d| d.count()).unwrap_or(0);
    assert_eq!(saved, 0, "files in the data directory: {context}");
}

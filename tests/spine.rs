//! End to end: the real binary, a controller and its script processes.

mod common;

use std::time::Duration;

use common::*;

/// The acceptance run of the README: hello_axis prints positions and ends at 0.
#[test]
fn hello_axis_moves_there_and_back() {
    let ns = unique_ns("hello");
    let out = run(&ns, &[repo_path("scripts/examples/hello_axis.lua").to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    let lines = out.lines_of_task(0);
    assert!(lines.iter().any(|l| l == "axis 0 in position: ref 100.000 mm, feedback 100.000 mm"), "{lines:?}");
    assert_eq!(
        lines.iter().rfind(|l| l.contains("in position")).unwrap(),
        "axis 0 in position: ref 0.000 mm, feedback 0.000 mm"
    );
    assert_eq!(lines.last().unwrap(), "done");
    assert!(out.stderr.contains("task 0 (") && out.stderr.contains("finished"), "{}", out.stderr);
    assert!(shm_files(&ns).is_empty(), "IPC resources removed: {:?}", shm_files(&ns));
}

#[test]
fn api_facts_of_the_first_subset_hold() {
    let ns = unique_ns("facts");
    let out = run(&ns, &[repo_path("tests/lua/axis_basics.lua").to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(out.lines_of_task(0), vec!["all checks passed"]);
}

/// Two programs run at once, one process each, and both finish.
#[test]
fn two_programs_run_at_once_in_their_own_processes() {
    let ns = unique_ns("two");
    let a = repo_path("scripts/examples/two_programs/axis0.lua");
    let b = repo_path("scripts/examples/two_programs/axis1.lua");
    let child = start_run(&ns, &[a.to_str().unwrap(), b.to_str().unwrap()]);
    let controller = child.id();
    assert!(
        eventually(Duration::from_secs(5), || children_of(controller).len() == 2),
        "one script process per program, found {:?}",
        children_of(controller)
    );
    let out = finish(child, Duration::from_secs(60));
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(out.lines_of_task(0).len(), 2);
    assert_eq!(out.lines_of_task(1), vec!["axis 1 at -80.000 mm", "axis 1 back at 0.000 mm"]);
    // They overlapped: task 1 reports before task 0 is done.
    let first_of_1 = out.stdout.find("[task 1]").unwrap();
    let last_of_0 = out.stdout.rfind("[task 0]").unwrap();
    assert!(first_of_1 < last_of_0, "{}", out.stdout);
}

/// A syntax error and a runtime error end their own programs with `file:line: message`;
/// the healthy program beside them finishes.
#[test]
fn broken_programs_fail_alone_with_a_clear_message() {
    let dir = tempfile::tempdir().unwrap();
    let syntax = program(dir.path(), "syntax.lua", "Enable(0\nx = = 1\n");
    let runtime = program(dir.path(), "runtime.lua", "local t = nil\nSleep(20)\nprint(t.x)\n");
    let healthy = program(
        dir.path(),
        "healthy.lua",
        "Enable(1)\nTill(function() return IsEnabled(1) end)\nMoveAbs(1, 5)\nTill(function() return IsInPos(1) end)\nPrint('healthy at %.1f', GetPosFb(1))\n",
    );
    let ns = unique_ns("broken");
    // The VM's own messages: the check would refuse the start (tests/check.rs).
    let out = run(&ns, &["--no-check", syntax.to_str().unwrap(), runtime.to_str().unwrap(), healthy.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1), "{}", out.stderr);
    let s = syntax.display();
    let r = runtime.display();
    assert!(out.stderr.contains(&format!("task 0 ({s}): failed: {s}:2: ')' expected")), "{}", out.stderr);
    assert!(
        out.stderr.contains(&format!("task 1 ({r}): failed: {r}:3: attempt to index a nil value")),
        "{}",
        out.stderr
    );
    assert_eq!(out.lines_of_task(2), vec!["healthy at 5.0"]);
    assert!(out.stderr.contains("healthy.lua): finished"), "{}", out.stderr);
}

/// Two controllers in two namespaces run side by side without touching each other.
#[test]
fn two_controllers_side_by_side() {
    let dir = tempfile::tempdir().unwrap();
    let a = program(
        dir.path(),
        "a.lua",
        "Enable(0)\nTill(function() return IsEnabled(0) end)\nMoveAbs(0, 30)\nTill(function() return IsInPos(0) end)\nPrint('%.1f', GetPosFb(0))\n",
    );
    let b = program(
        dir.path(),
        "b.lua",
        "Enable(0)\nTill(function() return IsEnabled(0) end)\nMoveAbs(0, -20)\nTill(function() return IsInPos(0) end)\nPrint('%.1f', GetPosFb(0))\n",
    );
    let (ns_a, ns_b) = (unique_ns("sideA"), unique_ns("sideB"));
    let first = start_run(&ns_a, &[a.to_str().unwrap()]);
    let second = start_run(&ns_b, &[b.to_str().unwrap()]);
    let (out_a, out_b) = (finish(first, Duration::from_secs(60)), finish(second, Duration::from_secs(60)));
    assert!(out_a.status.success() && out_b.status.success(), "{}\n{}", out_a.stderr, out_b.stderr);
    assert_eq!(out_a.lines_of_task(0), vec!["30.0"]);
    assert_eq!(out_b.lines_of_task(0), vec!["-20.0"]);
}

/// A second controller in a namespace that is in use is refused, and says by whom.
#[test]
fn a_namespace_in_use_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let wait = program(dir.path(), "wait.lua", "Sleep(3000)\n");
    let ns = unique_ns("busy");
    let first = start_run(&ns, &[wait.to_str().unwrap()]);
    assert!(eventually(Duration::from_secs(5), || children_of(first.id()).len() == 1));
    let second = run(&ns, &[wait.to_str().unwrap()]);
    assert!(!second.status.success());
    assert!(second.stderr.contains(&format!("already running in namespace {ns}")), "{}", second.stderr);
    let first = finish(first, Duration::from_secs(30));
    assert!(first.status.success(), "{}", first.stderr);
}

/// `kill -9` of a controller: its scripts die with it, and the next controller in the
/// same namespace cleans up and runs.
#[test]
fn after_kill_9_the_next_controller_starts() {
    let dir = tempfile::tempdir().unwrap();
    let forever = program(dir.path(), "forever.lua", "Enable(0)\nwhile true do Sleep(100) end\n");
    let ns = unique_ns("kill9");
    let mut child = start_run(&ns, &[forever.to_str().unwrap()]);
    let controller = child.id();
    assert!(eventually(Duration::from_secs(5), || children_of(controller).len() == 1));
    let script = children_of(controller)[0];
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(eventually(Duration::from_secs(2), || !process_alive(script)), "the script exits with its controller");
    assert!(!shm_files(&ns).is_empty(), "a killed controller leaves its resources behind");

    let hello = repo_path("scripts/examples/hello_axis.lua");
    let out = run(&ns, &[hello.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert!(shm_files(&ns).is_empty());
}

/// Ctrl-C: scripts stopped, axes disabled, resources removed, exit code 130.
#[test]
fn ctrl_c_shuts_down_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let forever = program(
        dir.path(),
        "forever.lua",
        "Enable(0)\nTill(function() return IsEnabled(0) end)\nPrint('enabled')\nwhile true do MoveAbs(0, 1000) Sleep(10) end\n",
    );
    let ns = unique_ns("ctrlc");
    let child = start_run(&ns, &[forever.to_str().unwrap()]);
    let controller = child.id();
    assert!(eventually(Duration::from_secs(5), || children_of(controller).len() == 1));
    let script = children_of(controller)[0];
    std::thread::sleep(Duration::from_millis(500));
    // SAFETY: signalling the child we started.
    unsafe { libc::kill(controller as i32, libc::SIGINT) };
    let out = finish(child, Duration::from_secs(10));
    assert_eq!(out.status.code(), Some(130), "{}", out.stderr);
    assert!(!process_alive(script));
    assert!(shm_files(&ns).is_empty(), "{:?}", shm_files(&ns));
    assert!(out.stderr.contains("stopped"), "{}", out.stderr);
}

/// A bad machine file names the key and starts nothing.
#[test]
fn an_invalid_machine_file_names_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let hello = repo_path("scripts/examples/hello_axis.lua");
    let cases = [
        ("cycle_us = 750\n[[axes]]\n", "cycle_us"),
        ("[[axes]]\ncounts_per_unit = -1\n", "axes[0].counts_per_unit"),
        ("[[axes]]\nvelocity = 3\n", "unknown field `velocity`"),
        ("[[axes]]\ndrive = \"D9\"\n", "unknown variant `D9`"),
        ("[[axes]]\n[[tasks]]\nid = 64\nprogram = \"x.lua\"\n", "tasks[0].id"),
    ];
    for (text, expected) in cases {
        let path = dir.path().join("machine.toml");
        std::fs::write(&path, text).unwrap();
        let ns = unique_ns("badcfg");
        let out = run(&ns, &["--config", path.to_str().unwrap(), hello.to_str().unwrap()]);
        assert!(!out.status.success(), "{text}");
        assert!(out.stderr.contains(expected), "{text}: {}", out.stderr);
        assert!(out.stdout.is_empty(), "nothing ran: {}", out.stdout);
    }
}

/// The machine file's per-task memory limit ends a memory bomb, and only that program.
#[test]
fn a_memory_bomb_hits_its_task_limit_alone() {
    let dir = tempfile::tempdir().unwrap();
    program(dir.path(), "bomb.lua", "local t = {}\nfor i = 1, 10000 do t[i] = string.rep('x', 64 * 1024) .. i end\n");
    program(dir.path(), "fine.lua", "Sleep(50)\nPrint('fine')\n");
    let config = dir.path().join("machine.toml");
    std::fs::write(
        &config,
        "[[axes]]\n[[tasks]]\nid = 3\nprogram = \"bomb.lua\"\nautorun = true\nmemory_limit_mib = 16\n\
         [[tasks]]\nid = 4\nprogram = \"fine.lua\"\nautorun = true\n",
    )
    .unwrap();
    let ns = unique_ns("bomb");
    let out = run(&ns, &["--config", config.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1), "{}", out.stderr);
    assert!(
        out.stderr.contains("bomb.lua: not enough memory near line 2 (the task's limit is 16 MiB)"),
        "{}",
        out.stderr
    );
    assert_eq!(out.lines_of_task(4), vec!["fine"]);
}

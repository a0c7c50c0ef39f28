//! DRL program control over Modbus TCP (DXMC manual appendix A.3), driven by pymodbus, a
//! client luamotion did not write. The tests install it themselves into a virtualenv under
//! cargo's temp dir (`tests/python/requirements.txt`): Python 3 and network access to PyPI
//! on the first run are all they need.

mod common;

use std::process::{Command, Stdio};
use std::time::Duration;

use common::serve::serve;
use common::{BIN, unique_ns};

/// The project the HMI drives: it moves axis 0 back and forth and writes the axis'
/// velocity into DV 0x0010, so that the client sees the run speed act.
const PROJECT: &str = "\
Enable(0)
Till(function() return IsEnabled(0) end)
SetVel(0, 100)
local function watch() WriteModbusWord(0x10, math.floor(math.abs(GetVelFb(0)) + 0.5)) return IsInPos(0) end
while true do
  MoveAbs(0, 300)
  Till(watch)
  MoveAbs(0, 0)
  Till(watch)
end
";

/// Commands a move every 50 ms and shows its return code in DV 0x21 (low word) and 0x22
/// (high word); echoes DV 0x30 into DV 0x31.
const MOVER: &str = "\
Enable(0)
Till(function() return IsEnabled(0) end)
local target = 10
while true do
  local rc = MoveAbs(0, target)
  target = -target
  WriteModbusWord(0x21, rc & 0xFFFF)
  WriteModbusWord(0x22, (rc >> 16) & 0xFFFF)
  WriteModbusWord(0x31, ReadModbusWord(0x30))
  DELAY(0.05)
end
";

fn client(port: u16, args: &[&str]) -> String {
    python_client("drl_client.py", port, args)
}

/// Runs `tests/python/<script> PORT args...` with pymodbus; its stdout, or a failure.
fn python_client(script: &str, port: u16, args: &[&str]) -> String {
    let output = Command::new(common::pymodbus_python())
        .arg(common::repo_path(&format!("tests/python/{script}")))
        .arg(port.to_string())
        .args(args)
        .output()
        .expect("run the Modbus client");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "client {args:?} failed\nstdout:\n{stdout}\nstderr:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

#[test]
fn an_hmi_runs_steps_and_stops_a_drl_project() {
    let ns = unique_ns("drl");
    let dir = tempfile::tempdir().unwrap();
    let project = dir.path().join("projects/5");
    std::fs::create_dir_all(&project).unwrap();
    std::fs::write(project.join("main.lua"), PROJECT).unwrap();
    let server = serve(&ns, dir.path(), &[]);
    let port = server.port;
    let events = Command::new(BIN)
        .args(["events", "--ns", &ns, "--count", "1"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("luamotion events");
    let out = client(port, &["scenario"]);
    let events = common::finish(events, Duration::from_secs(10));
    drop(server);
    assert!(out.contains("break point at line 7") && out.contains("stepped to line 8"), "{out}");
    assert!(events.stdout.contains("0x30007000"), "an invalid DRL control code raises alarm 0x7000: {}", events.stdout);
}

#[test]
fn motion_only_in_run_or_diagnosis_and_projects_export_and_import() {
    let ns = unique_ns("state");
    let dir = tempfile::tempdir().unwrap();
    let project = dir.path().join("projects/6");
    std::fs::create_dir_all(&project).unwrap();
    std::fs::write(project.join("main.lua"), MOVER).unwrap();
    let server = serve(&ns, dir.path(), &[]);
    let port = server.port;
    let out = client(port, &["controller-state"]);
    drop(server);
    assert!(out.contains("as the manual says"), "{out}");
    assert_eq!(std::fs::read_to_string(dir.path().join("export/6/main.lua")).unwrap(), MOVER);
}

#[test]
fn dh_is_kept_across_restarts() {
    let ns = unique_ns("dh");
    let dir = tempfile::tempdir().unwrap();
    let server = serve(&ns, dir.path(), &[]);
    let port = server.port;
    client(port, &["dh-write", "4321"]);
    drop(server);
    let server = serve(&ns, dir.path(), &[]);
    let port = server.port;
    let out = client(port, &["dh-read"]);
    drop(server);
    assert!(out.contains("DH 4321"), "{out}");
}

/// `luamotion drl <args> --at 127.0.0.1:<port>`, to its end.
fn drl(port: u16, args: &[&str]) -> common::Finished {
    let at = format!("127.0.0.1:{port}");
    let child = Command::new(BIN)
        .arg("drl")
        .args(args)
        .args(["--at", &at])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("luamotion drl");
    common::finish(child, Duration::from_secs(30))
}

#[test]
fn drl_commands_the_controller_refuses_fail_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve(&unique_ns("drl-cli"), dir.path(), &[]);
    for args in [&["open", "42"][..], &["open", "42", "--run"]] {
        let out = drl(server.port, args);
        assert!(!out.status.success(), "drl {args:?} of a missing project: {}", out.stdout);
        assert!(
            out.stderr.contains("cannot open project 42") && out.stderr.contains("CANNOT_OPEN"),
            "drl {args:?}: {}",
            out.stderr
        );
    }
    let out = drl(server.port, &["run"]);
    assert!(!out.status.success() && out.stderr.contains("CANNOT_RUN"), "run with nothing open: {}", out.stderr);
}

#[test]
fn drl_status_names_the_codes_and_takes_at_before_or_after_the_subcommand() {
    let dir = tempfile::tempdir().unwrap();
    let project = dir.path().join("projects/5");
    std::fs::create_dir_all(&project).unwrap();
    std::fs::write(project.join("main.lua"), PROJECT).unwrap();
    let server = serve(&unique_ns("drl-status"), dir.path(), &[]);
    let out = drl(server.port, &["status"]);
    assert!(out.status.success(), "drl status --at: {}", out.stderr);
    assert!(out.stdout.contains("state 0 (Close)") && out.stdout.contains("status 32 (STOPPED)"), "{}", out.stdout);
    let out = drl(server.port, &["open", "5"]);
    assert!(out.status.success(), "{}", out.stderr);
    assert!(out.stdout.contains("state 4 (Pre-Run)") && out.stdout.contains("status 12 (OPENED)"), "{}", out.stdout);
    let at = format!("127.0.0.1:{}", server.port);
    let out = common::finish(
        Command::new(BIN)
            .args(["drl", "--at", &at, "status"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
        Duration::from_secs(30),
    );
    assert!(out.status.success() && out.stdout.contains("id 5"), "drl --at ... status: {}{}", out.stdout, out.stderr);
}

/// What the project does after its wait: DV 0x40 = 1..20, one every 50 ms.
const AFTER_THE_WAIT: &str = "for i = 1, 20 do WriteModbusWord(0x40, i) DELAY(0.05) end\n";

/// A served controller with project 7 (waits in `DELAY(2)`) and project 8 (waits in a
/// `Till` on DV 0x41 whose condition is a module's, so no line of `main.lua` runs in it).
fn serve_waiting_projects(name: &str) -> (tempfile::TempDir, common::serve::Serving) {
    let dir = tempfile::tempdir().unwrap();
    let delay = dir.path().join("projects/7");
    std::fs::create_dir_all(&delay).unwrap();
    std::fs::write(delay.join("main.lua"), format!("DELAY(2)\n{AFTER_THE_WAIT}")).unwrap();
    let till = dir.path().join("projects/8");
    std::fs::create_dir_all(&till).unwrap();
    std::fs::write(till.join("released.lua"), "return function() return ReadModbusWord(0x41) == 1 end\n").unwrap();
    std::fs::write(till.join("main.lua"), format!("Till(require(\"released\"))\n{AFTER_THE_WAIT}")).unwrap();
    let server = serve(&unique_ns(name), dir.path(), &[]);
    (dir, server)
}

/// DXMC A.3: a Release Run sent while a Pause waits for the end of a `DELAY` is carried
/// out; the program runs on to its end, never pausing.
#[test]
fn a_release_run_while_a_pause_is_pending_in_a_delay_runs_on() {
    let (_dir, server) = serve_waiting_projects("pend-delay");
    let out = python_client("drl_pending.py", server.port, &["delay-run"]);
    assert!(out.contains("the program ran on to its end"), "{out}");
}

/// The same in a `Till`.
#[test]
fn a_release_run_while_a_pause_is_pending_in_a_till_runs_on() {
    let (_dir, server) = serve_waiting_projects("pend-till");
    let out = python_client("drl_pending.py", server.port, &["till-run"]);
    assert!(out.contains("the program ran on to its end"), "{out}");
}

/// A Stop sent while a Pause is pending stops the program in its wait.
#[test]
fn a_stop_while_a_pause_is_pending_stops_the_program() {
    let (_dir, server) = serve_waiting_projects("pend-stop");
    let out = python_client("drl_pending.py", server.port, &["delay-stop"]);
    assert!(out.contains("the program stopped in its wait"), "{out}");
}

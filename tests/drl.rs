//! DRL program control over Modbus TCP (DXMC manual appendix A.3), driven by pymodbus, a
//! client luamotion did not write. The tests install it themselves into a virtualenv under
//! cargo's temp dir (`tests/python/requirements.txt`): Python 3 and network access to PyPI
//! on the first run are all they need.

mod common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::OnceLock;
use std::time::Duration;

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

/// The virtualenv's python, with pymodbus installed once per build directory.
fn python() -> &'static Path {
    static PYTHON: OnceLock<PathBuf> = OnceLock::new();
    PYTHON.get_or_init(|| {
        let venv = Path::new(env!("CARGO_TARGET_TMPDIR")).join("pymodbus-venv");
        let python = venv.join("bin/python");
        let requirements = common::repo_path("tests/python/requirements.txt");
        let marker = venv.join("installed.txt");
        let wanted = std::fs::read_to_string(&requirements).expect("requirements");
        if std::fs::read_to_string(&marker).ok().as_deref() != Some(wanted.as_str()) {
            let _ = std::fs::remove_dir_all(&venv);
            let ok = |c: &mut Command| c.status().map(|s| s.success()).unwrap_or(false);
            assert!(ok(Command::new("python3").args(["-m", "venv"]).arg(&venv)), "python3 -m venv failed");
            assert!(
                ok(Command::new(&python).args(["-m", "pip", "install", "-q", "-r"]).arg(&requirements)),
                "pip install -r {} failed",
                requirements.display()
            );
            std::fs::write(&marker, wanted).expect("marker");
        }
        python
    })
}

/// A running `luamotion serve`, stopped with SIGTERM when dropped (also when a test fails).
struct Serving(Child);

impl Drop for Serving {
    fn drop(&mut self) {
        // SAFETY: plain kill(2) of our own child.
        unsafe { libc::kill(self.0.id() as i32, libc::SIGTERM) };
        if !common::eventually(Duration::from_secs(10), || self.0.try_wait().ok().flatten().is_some()) {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
}

/// `luamotion serve` on a free port; returns the process and the port.
fn serve(ns: &str, dir: &Path) -> (Serving, u16) {
    let mut child = Command::new(BIN)
        .args(["serve", "--ns", ns, "--modbus-port", "0"])
        .arg("--data-dir")
        .arg(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start luamotion serve");
    let mut line = String::new();
    BufReader::new(child.stdout.take().expect("stdout")).read_line(&mut line).expect("first line");
    let port = line
        .split_once("Modbus TCP on ")
        .and_then(|(_, rest)| rest.split(';').next())
        .and_then(|address| address.rsplit(':').next())
        .and_then(|port| port.parse().ok())
        .unwrap_or_else(|| panic!("no port in {line:?}"));
    (Serving(child), port)
}

fn client(port: u16, args: &[&str]) -> String {
    let output = Command::new(python())
        .arg(common::repo_path("tests/python/drl_client.py"))
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
    let (server, port) = serve(&ns, dir.path());
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
    let (server, port) = serve(&ns, dir.path());
    let out = client(port, &["controller-state"]);
    drop(server);
    assert!(out.contains("as the manual says"), "{out}");
    assert_eq!(std::fs::read_to_string(dir.path().join("export/6/main.lua")).unwrap(), MOVER);
}

#[test]
fn dh_is_kept_across_restarts() {
    let ns = unique_ns("dh");
    let dir = tempfile::tempdir().unwrap();
    let (server, port) = serve(&ns, dir.path());
    client(port, &["dh-write", "4321"]);
    drop(server);
    let (server, port) = serve(&ns, dir.path());
    let out = client(port, &["dh-read"]);
    drop(server);
    assert!(out.contains("DH 4321"), "{out}");
}

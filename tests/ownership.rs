//! Axis ownership end to end (DXMC 9, 0x001F; docs/decisions.md, "Axis ownership"): a
//! program moves an axis of `luamotion serve` while `nc`, a Native ASCII client (task
//! slot 62), commands it. The client is refused while the program's motion runs, and the
//! program ends where it commanded, or, when the client's stop cut its move short, can
//! read why.

mod common;

use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::time::Duration;

use common::serve::{Serving, serve};
use common::*;

/// `nc` on the Native ASCII port: one line out, one line back.
struct Nc {
    child: Child,
    to: ChildStdin,
    from: BufReader<ChildStdout>,
}

impl Nc {
    fn connect(port: u16) -> Self {
        let mut child = Command::new(debian_tool("nc"))
            .args(["-q", "1", "127.0.0.1", &port.to_string()])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .expect("nc");
        let to = child.stdin.take().unwrap();
        let from = BufReader::new(child.stdout.take().unwrap());
        Nc { child, to, from }
    }

    fn ask(&mut self, line: &str) -> String {
        writeln!(self.to, "{line}").unwrap();
        let (tx, rx) = std::sync::mpsc::channel();
        let mut answer = String::new();
        std::thread::scope(|s| {
            s.spawn(|| {
                let _ = self.from.read_line(&mut answer);
                let _ = tx.send(());
            });
            if rx.recv_timeout(Duration::from_secs(20)).is_err() {
                // The reader thread ends with the connection.
                let _ = self.child.kill();
            }
        });
        assert!(answer.ends_with("\r\n"), "{line}: a whole answer line within 20 s, got {answer:?}");
        answer.trim_end().to_string()
    }
}

impl Drop for Nc {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `luamotion serve` with task 0 running `program` at start.
fn serve_program(ns: &str, dir: &Path, program: &str) -> Serving {
    let path = dir.join("task0.lua");
    std::fs::write(&path, program).unwrap();
    let config = dir.join("machine.toml");
    std::fs::write(&config, format!("[[tasks]]\nid = 0\nprogram = {:?}\nautorun = true\n", path.display().to_string()))
        .unwrap();
    serve(ns, dir, &["--config", config.to_str().unwrap()])
}

/// The line task 0 prints after `prefix`, within 60 s.
fn said(serving: &Serving, prefix: &str) -> String {
    serving.await_line(0, prefix, Duration::from_secs(60)).unwrap_or_else(|| {
        panic!("task 0 did not print {prefix:?}\nstdout:\n{}\nstderr:\n{}", serving.stdout(), serving.stderr())
    })
}

/// Enables axis 0 and moves it to 100 mm at 25 mm/s (4 s), telling when it has started,
/// then waits until it is in position and says where, with the move's rc and the axis'
/// last error.
const MOVE_TO_100: &str = r#"
    Till(IsSystemOper)
    Enable(0)
    Till(function() return IsEnabled(0) end)
    SetVel(0, 25)
    local rc = MoveAbs(0, 100)
    Till(function() return IsMoving(0) end)
    Print('moving')
    Till(function() return IsInPos(0) end)
    Print(string.format('in position at %.3f rc %d last error 0x%X', GetPosFb(0), rc, GetAxisLastErr(0)))
"#;

/// The issue's case: during the program's MoveAbs(0, 100), the client's MoveRel(0, 30),
/// twice, and its Disable(0) are refused with 0x1000001F, and the program is in position
/// at 100.000 with rc 0 and no last error.
#[test]
fn a_native_client_cannot_move_a_programs_axis() {
    let ns = unique_ns("own-rel");
    let dir = tempfile::tempdir().unwrap();
    let serving = serve_program(&ns, dir.path(), MOVE_TO_100);
    said(&serving, "moving");
    let mut nc = Nc::connect(serving.ascii_port);
    for line in ["MoveRel(0, 30)", "MoveRel(0, 30)", "MoveVel(0, 10)", "Disable(0)"] {
        let answer = nc.ask(line);
        assert!(answer.starts_with("ERROR 0x1000001F alarm: command buffer busy"), "{line}: {answer}");
    }
    assert_eq!(said(&serving, "in position at "), "100.000 rc 0 last error 0x0", "{}", serving.stderr());
    assert!(
        serving.stderr().contains("task 62: command buffer busy: axis 0"),
        "the client's alarm: {}",
        serving.stderr()
    );
    assert_eq!(nc.ask("MoveRel(0, 30)"), "0", "the program's motion is over: the client may");
}

/// A stop must stop: the client's Stop(0) is carried out, and the program, in position
/// short of 100, reads 0x1000001F from GetAxisLastErr.
#[test]
fn a_native_clients_stop_stops_a_programs_axis_and_the_program_sees_it() {
    let ns = unique_ns("own-stop");
    let dir = tempfile::tempdir().unwrap();
    let serving = serve_program(&ns, dir.path(), MOVE_TO_100);
    said(&serving, "moving");
    let mut nc = Nc::connect(serving.ascii_port);
    assert_eq!(nc.ask("Stop(0)"), "0");
    let line = said(&serving, "in position at ");
    let fields: Vec<&str> = line.split_whitespace().collect();
    let at: f64 = fields[0].parse().unwrap_or_else(|_| panic!("a position: {line}"));
    assert!(at < 99.0, "stopped short of 100: {line}");
    assert_eq!(fields[1..], ["rc", "0", "last", "error", "0x1000001F"], "{line}");
    assert!(
        serving.stderr().contains("task 0: command buffer busy: axis 0"),
        "the owner's alarm: {}",
        serving.stderr()
    );
}

/// A variant the rule was not written for: a group's path. During the program's
/// LineAbs2D the client's LineAbs2D on the group and its Disable(1) of a member axis are
/// refused, and the program's path ends at (100, 50).
#[test]
fn a_native_client_cannot_take_a_programs_group() {
    let ns = unique_ns("own-grp");
    let dir = tempfile::tempdir().unwrap();
    let program = r#"
        Till(IsSystemOper)
        for a = 0, 1 do
          Enable(a)
          Till(function() return IsEnabled(a) end)
          AddAxisToGrp(0, a)
        end
        EnableGroup(0)
        SetGrpVel(0, 25)
        local rc = LineAbs2D(0, 100, 50)
        Till(function() return IsGrpMoving(0) end)
        Print('moving')
        Till(function() return IsGrpInPos(0) end)
        Print(string.format('in position at %.3f %.3f rc %d', GetPosFb(0), GetPosFb(1), rc))
    "#;
    let serving = serve_program(&ns, dir.path(), program);
    said(&serving, "moving");
    let mut nc = Nc::connect(serving.ascii_port);
    for (line, alarm) in
        [("LineAbs2D(0, 0, 0)", "0x1000001F"), ("Disable(1)", "0x1001001F"), ("MoveAbs(0, 0)", "0x1000001F")]
    {
        let answer = nc.ask(line);
        assert!(answer.starts_with(&format!("ERROR {alarm} alarm: command buffer busy")), "{line}: {answer}");
    }
    assert_eq!(said(&serving, "in position at "), "100.000 50.000 rc 0", "{}", serving.stderr());
}

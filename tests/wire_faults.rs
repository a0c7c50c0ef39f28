//! Issue 39, item 4: faults on the wire, as a real controller meets them. The controller
//! runs a program against `luamotion subdevices` across a veth pair; the test pulls the
//! cable (the veth link down) and puts it back, or makes the link lose, delay and
//! duplicate frames (`tc netem`). Needs root or CAP_NET_ADMIN and CAP_NET_RAW; with
//! `CI=true` a missing capability fails, never skips.

mod common;

use std::process::Command;
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

use common::wire::{End, Segment, Wire, wire};
use common::*;

/// One wire test at a time: the cable test failed once on a clean clone beside an
/// impaired one (never back in Op within 60 s; cause not found, see the issue's note).
fn one_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    static TURN: std::sync::Mutex<()> = std::sync::Mutex::new(());
    TURN.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// A controller that is killed, with what it started, if the test ends before it does.
struct Running(Option<std::process::Child>);

impl Running {
    fn child(&mut self) -> &mut std::process::Child {
        self.0.as_mut().expect("running")
    }

    fn finish(mut self, timeout: Duration) -> Finished {
        finish(self.0.take().expect("running"), timeout)
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        if let Some(child) = &mut self.0 {
            kill_all(child);
        }
    }
}

/// The controller on the outside end with `machine` (programs relative to `dir`) and
/// `[bus]`; the segment of the built-in machine on the inside end.
fn start_on_wire(wire: &Wire, dir: &std::path::Path, machine: &str) -> (Segment, Running) {
    let segment = Segment::serve(wire, End::Inside);
    let file = dir.join("wire.toml");
    std::fs::write(&file, format!("{machine}\n[bus]\ninterface = {:?}\n", wire.outside)).unwrap();
    let ns = unique_ns("wire-fault");
    (segment, Running(Some(start_run(&ns, &["--config", file.to_str().unwrap()]))))
}

/// Waits for `line` on the output of `child`, with a deadline that names it and says
/// what the controller printed.
fn wait_for(child: &mut std::process::Child, lines: &Receiver<String>, seen: &mut Vec<String>, line: &str) {
    let deadline = Instant::now() + Duration::from_secs(30);
    while Instant::now() < deadline {
        if let Ok(got) = lines.recv_timeout(Duration::from_millis(100)) {
            let found = got.ends_with(line);
            seen.push(got);
            if found {
                return;
            }
        }
    }
    kill_all(child);
    let stderr = child.stderr.take().map(|mut e| {
        let mut text = String::new();
        let _ = std::io::Read::read_to_string(&mut e, &mut text);
        text
    });
    panic!("no {line:?} within 30 s: {seen:?}\n{}", stderr.unwrap_or_default());
}

/// A program that moves axis 0, loses it with the cable, and brings it back with `Reset`
/// and `Enable` once the segment is in Op again (HMPL 5.2.1, 5.2.3, 2.5).
const PULLED: &str = r#"
Enable(0) Till(function() return IsEnabled(0) end)
MoveVel(0, 20)
Print("moving")
Till(function() return not IsEnabled(0) end)
Print("lost: last error 0x%08X, EtherCAT state %d", GetAxisLastErr(0), GetECATSt())
Print("move refused: 0x%08X", MoveAbs(0, 0))
Till(function() return GetECATSt() == 8 end)
Print("back in Op")
Print("reset %d", Reset(0))
Sleep(100)
Print("enable %d", Enable(0))
Till(function() return IsEnabled(0) end)
local at = GetPosFb(0)
MoveAbs(0, at + 5)
Till(function() return IsInPos(0) end)
Print("moved again by %.3f mm", GetPosFb(0) - at)
"#;

/// The cable is pulled during a move: the axes count as faulted with HMPL's abnormal
/// disable (0x83II03FC), the controller raises DXMC event 0x6103 (EtherCAT disconnected),
/// motion is refused (0x14B4, not in Op); the cable back, the master restores the slaves
/// to Op, and `Reset` and `Enable` bring the drive back (its fault: CoE manual table 4-16,
/// 0x7580).
#[test]
fn the_cable_pulled_during_a_move_and_put_back() {
    cable_pulled_and_put_back(End::Outside);
}

/// As above, the cable pulled at the segment's end: its interface goes down under it
/// (the socket reports the network down), and the segment answers again once it is up.
#[test]
fn the_cable_pulled_at_the_segment_and_put_back() {
    cable_pulled_and_put_back(End::Inside);
}

/// The link of `end` down during a move and up again.
fn cable_pulled_and_put_back(end: End) {
    let _turn = one_at_a_time();
    let wire = wire().expect("CI=true: the wire");
    let dir = tempfile::tempdir().unwrap();
    program(dir.path(), "pulled.lua", PULLED);
    let machine =
        "[[axes]]\n[[axes]]\n[[axes]]\n[[axes]]\n[[tasks]]\nid = 0\nprogram = \"pulled.lua\"\nautorun = true\n";
    let (segment, mut controller) = start_on_wire(&wire, dir.path(), machine);
    let lines = lines_of(controller.child().stdout.take().unwrap());
    let mut seen = Vec::new();
    wait_for(controller.child(), &lines, &mut seen, "moving");
    std::thread::sleep(Duration::from_millis(200));
    let link = |state: &str| match end {
        End::Outside => wire.run(&["link", "set", &wire.outside, state]),
        End::Inside => wire.run(&["-n", &wire.namespace, "link", "set", &wire.inside, state]),
    };
    link("down").unwrap();
    wait_for(controller.child(), &lines, &mut seen, "move refused: 0x000014B4");
    std::thread::sleep(Duration::from_millis(300));
    assert!(!seen.iter().any(|l| l.contains("back in Op")), "back in Op with the cable out: {seen:?}");
    link("up").unwrap();
    let finished = controller.finish(Duration::from_secs(60));
    seen.extend(common::rest_of(&lines, Duration::from_secs(2)));
    let served = segment.stop();
    let out: Vec<String> = seen.iter().filter_map(|l| l.strip_prefix("[task 0] ").map(str::to_string)).collect();
    let context = format!("{out:?}\n{}\nsegment: {}", finished.stderr, served.stderr);
    assert!(finished.status.success(), "{context}");
    assert_eq!(out[1], "lost: last error 0x830003FC, EtherCAT state 1", "{context}");
    assert_eq!(out[2], "move refused: 0x000014B4", "{context}");
    assert_eq!(out[4], "reset 0", "{context}");
    assert_eq!(out[5], "enable 0", "{context}");
    // Read as IsInPos turns true: within the in-position window of the 5 mm.
    let moved: f64 =
        out.last().and_then(|l| l.strip_prefix("moved again by ")).unwrap().trim_end_matches(" mm").parse().unwrap();
    assert!((moved - 5.0).abs() <= 0.0055, "{context}");
    assert!(
        finished.stderr.contains("controller: EtherCAT disconnected") && finished.stderr.contains("(alarm 0x00006103)"),
        "{context}"
    );
}

/// A segment switched on after the controller: the first scan finds nothing and times
/// out, the master scans again, and the program runs as with a segment there from the
/// start.
#[test]
fn a_segment_switched_on_late_is_found_by_the_next_scan() {
    let _turn = one_at_a_time();
    let wire = wire().expect("CI=true: the wire");
    let dir = tempfile::tempdir().unwrap();
    program(dir.path(), "late.lua", "Enable(0) Till(function() return IsEnabled(0) end)\nPrint(\"enabled\")\n");
    let file = dir.path().join("wire.toml");
    let machine = "[[axes]]\n[[axes]]\n[[axes]]\n[[axes]]\n[[tasks]]\nid = 0\nprogram = \"late.lua\"\nautorun = true\n";
    std::fs::write(&file, format!("{machine}\n[bus]\ninterface = {:?}\n", wire.outside)).unwrap();
    let mut controller = Running(Some(start_run(&unique_ns("wire-late"), &["--config", file.to_str().unwrap()])));
    let logs = lines_of(controller.child().stderr.take().unwrap());
    let mut seen = Vec::new();
    wait_for(controller.child(), &logs, &mut seen, "scanning again in 500ms");
    let segment = Segment::serve(&wire, End::Inside);
    let finished = controller.finish(Duration::from_secs(30));
    seen.extend(common::rest_of(&logs, Duration::from_secs(2)));
    drop(segment);
    let context = format!("{}\n{seen:#?}", finished.stdout);
    assert!(finished.status.success(), "{context}");
    assert_eq!(finished.lines_of_task(0), ["enabled"], "{context}");
    assert_eq!(seen.iter().filter(|l| l.contains("EtherCAT scan ")).count(), 1, "the second scan found it: {context}");
}

/// `tests/python/impair.py` between the wire's inside end and a second veth pair in its
/// namespace, the segment on the far end: a cable that loses, delays or duplicates frames.
struct Impaired {
    forwarder: std::process::Child,
}

impl Impaired {
    fn between(wire: &Wire, far: &str, loss: f64, delay_us: u32, duplicate: f64) -> Impaired {
        let peer = format!("{}y", wire.inside);
        wire.run(&["-n", &wire.namespace, "link", "add", far, "type", "veth", "peer", "name", &peer]).unwrap();
        for end in [far, peer.as_str()] {
            wire.run(&["-n", &wire.namespace, "link", "set", end, "up"]).unwrap();
        }
        let script = repo_path("tests/python/impair.py");
        let mut forwarder = wire
            .in_namespace(pymodbus_python())
            .arg(script)
            .args([&wire.inside, &peer, &loss.to_string(), &delay_us.to_string(), &duplicate.to_string()])
            .stdout(std::process::Stdio::piped())
            .spawn()
            .expect("the forwarder");
        let lines = lines_of(forwarder.stdout.take().unwrap());
        assert_eq!(lines.recv_timeout(Duration::from_secs(20)).ok().as_deref(), Some("forwarding"));
        Impaired { forwarder }
    }
}

impl Impaired {
    /// From now on the cable loses, delays or duplicates.
    fn start(&self) {
        // SAFETY: signalling our own child.
        unsafe { libc::kill(self.forwarder.id() as libc::pid_t, libc::SIGUSR1) };
    }
}

impl Drop for Impaired {
    fn drop(&mut self) {
        let _ = self.forwarder.kill();
        let _ = self.forwarder.wait();
    }
}

/// What `luamotion tasks` says of the wire: (back, missing, short, matching nothing).
fn wire_counts(ns: &str) -> (u64, u64, u64, u64) {
    let out = Command::new(BIN).args(["tasks", "--ns", ns]).output().expect("luamotion tasks");
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    let line = text.lines().find(|l| l.starts_with("EtherCAT on a wire: ")).unwrap_or_else(|| panic!("{text}"));
    let numbers: Vec<u64> = line.split(|c: char| !c.is_ascii_digit()).filter_map(|n| n.parse().ok()).collect();
    (numbers[0], numbers[1], numbers[2], numbers[3])
}

const STEADY: &str = r#"
Enable(0) Till(function() return IsEnabled(0) end)
Print("enabled")
Sleep(300)
MoveAbs(0, 50) Till(function() return IsInPos(0) end)
Print("in position at %.3f", GetPosFb(0))
Sleep(1000)
Print("done")
"#;

/// A program that moves over the impaired cable; what `luamotion tasks` counted while it
/// was impaired.
fn over_impaired_cable(loss: f64, delay_us: u32, duplicate: f64) -> (u64, u64, u64, u64) {
    let _turn = one_at_a_time();
    let wire = wire().expect("CI=true: the wire");
    let far = format!("{}x", wire.inside);
    let cable = Impaired::between(&wire, &far, loss, delay_us, duplicate);
    let segment = Segment::serve_on(wire.in_namespace(BIN), &far, None);
    let dir = tempfile::tempdir().unwrap();
    program(dir.path(), "steady.lua", STEADY);
    let file = dir.path().join("wire.toml");
    let machine =
        "[[axes]]\n[[axes]]\n[[axes]]\n[[axes]]\n[[tasks]]\nid = 0\nprogram = \"steady.lua\"\nautorun = true\n";
    std::fs::write(&file, format!("{machine}\n[bus]\ninterface = {:?}\n", wire.outside)).unwrap();
    let ns = unique_ns("wire-impaired");
    let mut controller = Running(Some(start_run(&ns, &["--config", file.to_str().unwrap()])));
    let lines = lines_of(controller.child().stdout.take().unwrap());
    let mut seen = Vec::new();
    // In Op through a whole cable, then impaired: a start-up's mailbox does not survive
    // a lost answer (the master sends the write again into a full mailbox).
    wait_for(controller.child(), &lines, &mut seen, "enabled");
    let before = wire_counts(&ns);
    cable.start();
    wait_for(controller.child(), &lines, &mut seen, "done");
    let after = wire_counts(&ns);
    let counts = (after.0 - before.0, after.1 - before.1, after.2 - before.2, after.3 - before.3);
    let finished = controller.finish(Duration::from_secs(30));
    drop(segment);
    let context = format!("{seen:?}\n{}", finished.stderr);
    eprintln!("loss {loss}, delay {delay_us} us, duplicate {duplicate}: back, missing, short, unmatched = {counts:?}");
    assert!(finished.status.success(), "{context}");
    let at: f64 = seen.iter().find_map(|l| l.strip_prefix("[task 0] in position at ")).unwrap().parse().unwrap();
    // Read as IsInPos turns true: within its window (0.005 mm), as printed.
    assert!((at - 50.0).abs() <= 0.0055, "in position: {context}");
    assert!(!finished.stderr.contains("0x00006103"), "the segment was never lost: {context}");
    counts
}

/// Item 4: 2 % of the frames lost on the cable are counted as missing; the program moves
/// as in memory and the segment is never lost.
#[test]
fn lost_frames_are_counted() {
    let (back, missing, _, _) = over_impaired_cable(0.02, 0, 0.0);
    assert!(back > 500 && missing > 0, "back {back}, missing {missing}");
}

/// Item 4: frames delayed 300 us each way still come back within the 1 ms cycle.
#[test]
fn delayed_frames_keep_the_cycle() {
    let (back, _, short, _) = over_impaired_cable(0.0, 300, 0.0);
    assert!(back > 500 && short == 0, "back {back}, short {short}");
}

/// Item 4: 5 % of the frames duplicated on the cable: the copies match nothing sent and
/// are counted and dropped, ethercrab's PDU loop goes on.
#[test]
fn duplicated_frames_are_counted_and_dropped() {
    let (back, _, _, unmatched) = over_impaired_cable(0.0, 0, 0.05);
    assert!(back > 500 && unmatched > 0, "back {back}, unmatched {unmatched}");
}

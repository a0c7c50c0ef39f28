//! Issue 39: the same programs over the wire. Each test runs a program of the in-memory
//! end-to-end set with `[bus] interface` naming one end of a veth pair, and `luamotion
//! subdevices` serving the same machine file's drives on the other end, in a namespace of
//! the test's own; the assertions are the in-memory test's. Needs root or CAP_NET_ADMIN
//! and CAP_NET_RAW; with `CI=true` a missing capability fails, never skips.

mod common;

use std::path::{Path, PathBuf};

use common::wire::{End, Segment, wire};
use common::*;

/// The machine file `machine` (tasks' programs relative to `dir`), served as a segment on
/// the inside end of a fresh wire, and `luamotion run --config` of it with `[bus]` naming
/// the outside end, with `args` after.
fn run_on_wire(dir: &Path, machine: &str, args: &[&str]) -> Finished {
    let wire = wire().expect("CI=true: the wire");
    let segment_file = dir.join("machine.toml");
    std::fs::write(&segment_file, machine).unwrap();
    let wire_file = dir.join("wire.toml");
    std::fs::write(&wire_file, format!("{machine}\n[bus]\ninterface = {:?}\n", wire.outside)).unwrap();
    let segment = Segment::serve_machine(&wire, End::Inside, Some(&segment_file));
    let mut all = vec!["--config", wire_file.to_str().unwrap()];
    all.extend_from_slice(args);
    let out = run(&unique_ns("wire"), &all);
    let served = segment.stop();
    assert!(served.stderr.is_empty() || !served.stderr.contains("panicked"), "the segment: {}", served.stderr);
    out
}

/// A machine file with nothing in it is the built-in machine.
const BUILT_IN: &str = "";

/// tests/spine.rs: hello_axis unchanged moves axis 0 there and back. The feedback is read
/// when `IsInPos` turns true, so over the wire it is within the in-position window
/// rather than the in-memory 0.000 (a frame lost on the wire holds the target a cycle).
#[test]
fn hello_axis_moves_there_and_back() {
    let dir = tempfile::tempdir().unwrap();
    let out = run_on_wire(dir.path(), BUILT_IN, &[repo_path("scripts/examples/hello_axis.lua").to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    let lines = out.lines_of_task(0);
    let feedback = |target: &str| -> f64 {
        let prefix = format!("axis 0 in position: ref {target} mm, feedback ");
        let line = lines.iter().find_map(|l| l.strip_prefix(&prefix)).unwrap_or_else(|| panic!("{prefix}: {lines:?}"));
        line.trim_end_matches(" mm").parse().unwrap()
    };
    assert!((feedback("100.000") - 100.0).abs() <= 0.005, "{lines:?}");
    assert!(feedback("0.000").abs() <= 0.005, "{lines:?}");
    assert_eq!(lines.last().unwrap(), "done");
    assert!(out.stderr.contains("task 0 (") && out.stderr.contains("finished"), "{}", out.stderr);
}

/// tests/hmpl_axis.rs: the homing facts of HMPL ch. 20; the homing objects go down by SDO
/// through the wire's mailbox before the drive's homing mode starts.
#[test]
fn homing() {
    let dir = tempfile::tempdir().unwrap();
    let out = run_on_wire(dir.path(), BUILT_IN, &[repo_path("tests/lua/hmpl_homing.lua").to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(out.lines_of_task(0).last().map(String::as_str), Some("homing facts passed"), "{}", out.stdout);
}

/// tests/drive.rs: an integrator walks drive 1 through the FSA by SDO alone (ReadSDO and
/// WriteSDO wait for the wire's mailbox), and a refused write is explained.
#[test]
fn an_integrator_walks_the_fsa_by_sdo() {
    let dir = tempfile::tempdir().unwrap();
    let machine = e2e::fsa_walk(dir.path());
    e2e::check_fsa_walk(&run_on_wire(dir.path(), &machine, &[]));
}

/// tests/groups.rs: the contour example, a group path of lines and arcs with look-ahead.
#[test]
fn the_contour_example_moves_both_axes_together_along_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let trace: PathBuf = dir.path().join("contour.csv");
    let script = repo_path("scripts/examples/contour.lua");
    let out = run_on_wire(dir.path(), BUILT_IN, &["--trace", trace.to_str().unwrap(), script.to_str().unwrap()]);
    e2e::check_contour(&out, &trace);
}

/// tests/touch_probe.rs: touch probes latch the encoder index and an external sensor in
/// the drive, and the program reads the positions back through the process data.
#[test]
fn a_program_latches_the_index_and_an_external_sensor() {
    let dir = tempfile::tempdir().unwrap();
    let machine = e2e::touch_probe(dir.path());
    e2e::check_touch_probe(&run_on_wire(dir.path(), &machine, &[]));
}

/// tests/faults.rs: a program caught in an endless loop while its axis moves is stopped
/// by its watchdog, with the alarm the core raises, and the quick stop takes the drive on
/// the wire out of Operation enabled.
#[test]
fn a_watchdog_fault_stops_the_axis() {
    let dir = tempfile::tempdir().unwrap();
    program(
        dir.path(),
        "faulty.lua",
        "Enable(0) Till(function() return IsEnabled(0) end)\nMoveAbs(0, 1000)\nSleep(300)\nwhile true do end\n",
    );
    // Keeps the controller running past the fault's consequences.
    program(dir.path(), "keeper.lua", "Sleep(1500)\n");
    let machine = "[[axes]]\n[[tasks]]\nid = 0\nprogram = \"faulty.lua\"\nautorun = true\nwatchdog_ms = 200\n\
                   fault_reaction = \"quick_stop\"\n[[tasks]]\nid = 1\nprogram = \"keeper.lua\"\nautorun = true\n";
    let trace = dir.path().join("trace.csv");
    let out = run_on_wire(dir.path(), machine, &["--trace", trace.to_str().unwrap()]);
    let context = format!("{}\n{}", out.stdout, out.stderr);
    assert!(out.stderr.contains("(alarm 0x30004102)"), "the watchdog's alarm: {context}");
    assert!(out.stderr.contains("faulty.lua): failed"), "{context}");
    let line = out.stderr.lines().find(|l| l.contains("(alarm 0x3000")).unwrap();
    let detected: u64 = line.split("cycle=").nth(1).unwrap().split_whitespace().next().unwrap().parse().unwrap();
    let rows = e2e::read_trace(&trace);
    let row = |cycle: u64| {
        rows.iter().find(|r| r["cycle"] as u64 == cycle).unwrap_or_else(|| panic!("trace row {cycle}: {context}"))
    };
    let enabled = |cycle| row(cycle)["a0_motion_status"] as u32 & 1 != 0;
    assert!(enabled(detected - 1), "axis 0 was moving: {context}");
    // The controlword goes out a cycle later, and the statusword comes back a cycle after.
    assert!(!enabled(detected + 3), "quick stop: the drive leaves Operation enabled: {context}");
    let fb = |c: u64| row(c)["a0_pos_fb"];
    assert!((fb(detected + 100) - fb(detected + 90)).abs() < 1e-3, "quick stop: the motor stands: {context}");
}

/// The controller of `wire_machine` against a segment of the built-in machine: it must not
/// start, and says why.
fn refused_start(wire_machine: &str) -> String {
    let wire = wire().expect("CI=true: the wire");
    let dir = tempfile::tempdir().unwrap();
    let wire_file = dir.path().join("wire.toml");
    std::fs::write(&wire_file, format!("{wire_machine}\n[bus]\ninterface = {:?}\n", wire.outside)).unwrap();
    let segment = Segment::serve(&wire, End::Inside);
    let hello = repo_path("scripts/examples/hello_axis.lua");
    let out = run(&unique_ns("wire-refused"), &["--config", wire_file.to_str().unwrap(), hello.to_str().unwrap()]);
    drop(segment);
    assert!(!out.status.success(), "the controller started: {}\n{}", out.stdout, out.stderr);
    assert!(out.lines_of_task(0).is_empty(), "no program ran: {}", out.stdout);
    out.stderr
}

/// Item 4: a slave missing at start (the machine file has a fifth axis) stops the start.
#[test]
fn a_missing_slave_stops_the_start() {
    let stderr = refused_start(&"[[axes]]\n".repeat(5));
    assert!(stderr.contains("the segment has 4 slaves; the machine file has 5"), "{stderr}");
}

/// Item 4: a slave of the wrong type (a D2 where the segment has a D1) stops the start,
/// naming the slave and both identities.
#[test]
fn a_slave_of_the_wrong_type_stops_the_start() {
    let stderr = refused_start("[[axes]]\n[[axes]]\n[[axes]]\ndrive = \"D2\"\n[[axes]]\n");
    assert!(stderr.contains("slave 2 (\"HIWIN D1 CoE drive\")"), "{stderr}");
    assert!(stderr.contains("product 0x00000002") && stderr.contains("the machine file expects"), "{stderr}");
}

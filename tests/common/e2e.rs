//! End-to-end programs that run both in memory and over a wire (`tests/wire_run.rs`):
//! each writes its program into a directory and gives its machine file, and one check
//! judges a run of it whatever carried its frames.

use std::collections::HashMap;
use std::path::Path;

use super::{Finished, program};

/// HMPL ch. 13 (`tests/touch_probe.rs`): touch probes on an axis whose counts per unit,
/// index pitch and offset are not round (2000 counts/mm, a mark every 7.5 mm from 1.25 mm,
/// the sensor over [12.3, 12.8] mm), with the axis' origin moved by SetPos. Writes
/// `main.lua` into `dir`; the machine file, with it as task 0.
pub fn touch_probe(dir: &Path) -> String {
    program(dir, "main.lua", TOUCH_PROBE);
    "[[axes]]\nname = \"x\"\ncounts_per_unit = 2000.0\n\
     travel = { index_pitch = 7.5, index_offset = 1.25, probe_input_1 = [12.3, 12.8] }\n\
     drive_settings = { touch_probe = \"cia402\" }\n\n\
     [[tasks]]\nid = 0\nprogram = \"main.lua\"\nautorun = true\n"
        .to_string()
}

const TOUCH_PROBE: &str = r#"
        local A = 0
        local function move(pos) MoveAbs(A, pos) Till(function() return IsInPos(A) end) end
        local function b(flag) return flag and 1 or 0 end
        Enable(A) Till(function() return IsEnabled(A) end)
        -- The origin moved: the machine's 0 reads 100 mm.
        SetPos(A, 100)
        -- Probe 1: external sensor, single, falling; probe 2: index, continuous, rising.
        SetTouchProbe1Func(A, 0, 0, 1) SetTouchProbe2Func(A, 1, 1, 0)
        EnableTouchProbe1(A) EnableTouchProbe2(A)
        move(120)
        local rc1, p1 = GetTouchProbe1Pos(A)
        local rc2, p2 = GetTouchProbe2Pos(A)
        Print("forward: tp1 %d %d %.4f tp2 %d %d %.4f", b(IsTouchProbe1Triggered(A)), rc1, p1, b(IsTouchProbe2Triggered(A)), rc2, p2)
        -- Back and forth across the sensor: a single trigger keeps its first edge; re-armed
        -- it takes the sensor's other end (moving negative the signal falls at L).
        move(110)
        rc1, p1 = GetTouchProbe1Pos(A)
        Print("back, single: %.4f", p1)
        move(120)
        DisableTouchProbe1(A) EnableTouchProbe1(A)
        Print("re-armed: triggered %d", b(IsTouchProbe1Triggered(A)))
        move(110)
        rc1, p1 = GetTouchProbe1Pos(A)
        rc2, p2 = GetTouchProbe2Pos(A)
        Print("again: tp1 %.4f tp2 %.4f", p1, p2)
        -- Bad arguments: the manual's non-0, never a stopped program.
        Print("bad: %X %X %X %d", SetTouchProbe1Func(A, 1, 2, 0), EnableTouchProbe1(7), SetTouchProbe2Func(A, -1, 0, 0), (GetTouchProbe1Pos(9)))
        Print("off: %d", DisableTouchProbe1(A) + DisableTouchProbe2(A) + b(IsTouchProbe1Enabled(A)) + b(IsTouchProbe2Enabled(A)))
    "#;

/// The positions the probes latched, and the refusals of bad arguments.
pub fn check_touch_probe(out: &Finished) {
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(
        out.lines_of_task(0),
        vec![
            // Marks at 1.25 + 7.5 k: 8.75 and 16.25 mm of the machine are 108.75 and 116.25.
            "forward: tp1 1 0 112.8000 tp2 1 0 116.2500",
            "back, single: 112.8000",
            "re-armed: triggered 0",
            // Moving back over the mark at 16.25 mm the index pulse rises at its end (mark
            // + 0.075 mm, 1 % of the pitch).
            "again: tp1 112.3000 tp2 116.3250",
            // No axis 7 or 9: HMPL's argument out of range (0x138F = 5007).
            "bad: 8300012C 138F 8300012C 5007",
            "off: 0",
        ],
        "{}\n{}",
        out.stdout,
        out.stderr
    );
}

/// HMPL ch. 17 (`tests/drive.rs`): an integrator brings drive 1 to Operation enabled by
/// SDO alone (`tests/lua/sdo_fsa_walk.lua`). Writes `walk.lua` into `dir`; the machine
/// file, which leaves 0x6040 out of slave 1's RxPDO.
pub fn fsa_walk(dir: &Path) -> String {
    let script = std::fs::read_to_string(super::repo_path("tests/lua/sdo_fsa_walk.lua")).unwrap();
    program(dir, "walk.lua", &script);
    "[[axes]]\n[[axes]]\nrx_pdo = [0x607A0020]\n[[tasks]]\nid = 0\nprogram = \"walk.lua\"\nautorun = true\n".to_string()
}

/// Every state of the walk reached, and the refused write explained.
pub fn check_fsa_walk(out: &Finished) {
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    let lines = out.lines_of_task(0);
    assert_eq!(lines.first().map(String::as_str), Some("0x0006 -> ready to switch on"));
    assert!(lines.iter().any(|l| l == "0x000F -> operation enabled"));
    assert_eq!(lines.last().map(String::as_str), Some("done"));
    assert!(out.stderr.contains("attempt to write a read-only object"), "the SDO abort is explained: {}", out.stderr);
}

/// The rows of a `--trace` file by column name.
pub fn read_trace(path: &Path) -> Vec<HashMap<String, f64>> {
    let text = std::fs::read_to_string(path).expect("trace written");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines.map(|l| header.iter().zip(l.split(',')).map(|(h, v)| (h.to_string(), v.parse().unwrap())).collect()).collect()
}

/// The reference positions of axes 0 and 1 from a trace file, from the cycle both are
/// enabled while each is moving or in position (HMPL table 5.1.1.5, bits 0 to 2). When the
/// program ends its axes let go, and a reference then follows the feedback, which over a
/// wire comes a cycle later than in memory: the wire's latency, not the group's motion.
fn trace_xy(path: &Path) -> Vec<(f64, f64)> {
    let status = |row: &HashMap<String, f64>, axis: u8| row[&format!("a{axis}_motion_status")] as u32;
    let held =
        |row: &HashMap<String, f64>| (0..2).all(|axis| status(row, axis) & 1 != 0 && status(row, axis) & 0b110 != 0);
    read_trace(path)
        .iter()
        .skip_while(|row| !held(row))
        .take_while(|row| held(row))
        .map(|row| (row["a0_ref_pos"], row["a1_ref_pos"]))
        .collect()
}

/// HMPL ch. 8 (`scripts/examples/contour.lua` under `--trace`): both axes move together
/// along the path and stop in the same cycle, within the profile's speed.
pub fn check_contour(out: &Finished, trace: &Path) {
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    let lines = out.lines_of_task(0);
    assert!(lines.iter().any(|l| l.contains("contour done at (0.000, 0.000)")), "{}", out.stdout);
    let xy = trace_xy(trace);
    let changes =
        |f: fn(&(f64, f64)) -> f64| -> Vec<usize> { (1..xy.len()).filter(|&i| f(&xy[i]) != f(&xy[i - 1])).collect() };
    let (x, y) = (changes(|p| p.0), changes(|p| p.1));
    assert!(!x.is_empty() && !y.is_empty(), "both axes move");
    assert_eq!(x.last(), y.last(), "HMPL 8.1: the axes of a group stop in the same cycle");
    let far_right = xy.iter().map(|p| p.0).fold(f64::MIN, f64::max);
    let top = xy.iter().map(|p| p.1).fold(f64::MIN, f64::max);
    assert!((far_right - 190.0).abs() < 0.5, "the half circle of radius 40 about (150, 40) reaches X 190: {far_right}");
    assert!((top - 80.0).abs() < 1e-6, "the top edge at Y 80: {top}");
    // The path speed stays within the profile's 200 mm/s (1 ms cycles).
    let fastest = xy.windows(2).map(|w| ((w[1].0 - w[0].0).powi(2) + (w[1].1 - w[0].1).powi(2)).sqrt() / 1e-3);
    let fastest = fastest.fold(0.0, f64::max);
    assert!(fastest <= 200.0 + 1e-6 && fastest > 150.0, "path speed {fastest} mm/s");
}

//! HMPL ch. 15 end to end: a program moves an axis with a flexible load (the machine file
//! of `scripts/reference/ch15_filters.toml`) with and then without its input shaper (in
//! this order: a shaper stills what its own move excites, not a ringing left from before),
//! and the trace (`--trace`) shows the load still after the first move and ringing after
//! the second.
//! The exact ratios against theory are rt-core's `tests/input_shaping.rs`.

mod common;

use std::collections::HashMap;

use common::*;

const PROGRAM: &str = r#"
Enable(0)
Till(function() return IsEnabled(0) end)
SetAxisInShape(0, 8.0, 0.02, SHAPER_NORMAL)
EnableAxisInShape(0)
Sleep(200)
MoveRel(0, 50)
Till(function() return not IsMoving(0) end)
Sleep(1000)
DisableAxisInShape(0)
MoveRel(0, -50)
Till(function() return not IsMoving(0) end)
Sleep(1000)
Print("done")
"#;

/// The largest |load - motor target| over 0.1..0.6 s after each time the Moving bit falls.
fn ringing_after_moves(rows: &[HashMap<String, String>]) -> Vec<f64> {
    let moving = |r: &HashMap<String, String>| r["a0_motion_status"].parse::<u32>().unwrap() & 0b10 != 0;
    let number = |r: &HashMap<String, String>, k: &str| r[k].parse::<f64>().unwrap();
    let mut out = Vec::new();
    for i in 1..rows.len() {
        if moving(&rows[i - 1]) && !moving(&rows[i]) {
            let target = number(&rows[i], "a0_ref_pos");
            let window = rows.iter().skip(i + 100).take(500);
            out.push(window.map(|r| (number(r, "a0_load_pos") - target).abs()).fold(0.0, f64::max));
        }
    }
    out
}

#[test]
fn the_trace_shows_the_shaper_stilling_the_load() {
    let dir = tempfile::tempdir().unwrap();
    let script = program(dir.path(), "shape.lua", PROGRAM);
    let trace = dir.path().join("trace.csv");
    let machine = repo_path("scripts/reference/ch15_filters.toml");
    let args = [script.to_str().unwrap(), "--config", machine.to_str().unwrap(), "--trace", trace.to_str().unwrap()];
    let out = run(&unique_ns("shape"), &args);
    assert!(
        out.status.success() && out.lines_of_task(0).iter().any(|l| l.contains("done")),
        "{}\n{}",
        out.stdout,
        out.stderr
    );

    let text = std::fs::read_to_string(&trace).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert!(header.contains(&"a0_load_pos"), "axis 0's load is traced: {header:?}");
    assert!(!header.contains(&"a1_load_pos"), "axis 1 is rigid: no column");
    let rows: Vec<HashMap<String, String>> =
        lines.map(|l| header.iter().zip(l.split(',')).map(|(h, v)| (h.to_string(), v.to_string())).collect()).collect();
    let ringing = ringing_after_moves(&rows);
    assert_eq!(ringing.len(), 2, "two moves: {ringing:?}");
    let (shaped, plain) = (ringing[0], ringing[1]);
    println!("load ringing after the move: {plain:.4} mm unshaped, {shaped:.5} mm shaped");
    assert!(plain > 0.1, "a 50 mm move at 4000 mm/s² rings the 8 Hz load: {plain} mm");
    assert!(shaped < 0.02 * plain, "the tuned ZV shaper stills it: {shaped} mm");
}

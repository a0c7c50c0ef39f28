//! The controller's cycle over a wire against in memory, in the same run: `luamotion soak`
//! at 1 kHz with 8 and then 32 drives, once with the simulated network in memory and once
//! with `--interface` on one end of a veth pair, `luamotion subdevices` serving as many D1
//! drives on the other end in a namespace. Prints one table row per run: cycle lateness and
//! execution, the scripts' wake-ups, the master threads' CPU per cycle, and the frames.
//!
//! `cargo bench --bench wire_cycle` (as root: it makes a network namespace and a veth pair,
//! and removes them). `SOAK_SECONDS` sets each run's length (default 10).

#[path = "../tests/common/mod.rs"]
mod common;

use std::process::Command;

use common::wire::{End, Segment, Wire};

const DRIVES: [usize; 2] = [8, 32];

/// One soak's JSON report, with `interface` when over the wire.
fn soak(drives: usize, interface: Option<&str>, seconds: &str) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("soak.json");
    let drives = drives.to_string();
    let mut command = Command::new(common::BIN);
    command.args(["soak", "--duration", seconds, "--scripts", "2", "--axes", &drives, "--json"]).arg(&json);
    if let Some(interface) = interface {
        command.args(["--interface", interface]);
    }
    let out = command.output().expect("luamotion soak");
    assert!(out.status.success(), "{}\n{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap()
}

fn metric<'a>(report: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    report["metrics"].as_array().unwrap().iter().find(|m| m["name"] == name).unwrap()
}

fn row(drives: usize, transport: &str, report: &serde_json::Value) {
    let q = |name: &str, k: &str| metric(report, name)[k].as_f64().unwrap();
    let wire = &report["counters"]["wire"];
    let master = wire["master_cpu_us_per_cycle"].as_f64().map_or("-".to_string(), |us| format!("{us:.1} us"));
    let frames = if wire.is_null() {
        "-".to_string()
    } else {
        format!("{} back, {} missing, {} short", wire["back"], wire["missing"], wire["short"])
    };
    println!(
        "| {drives} | {transport} | {:.1} / {:.1} / {:.1} | {:.1} / {:.1} / {:.1} | {:.1} / {:.1} | {} | {master} | {frames} |",
        q("cycle lateness", "p50"),
        q("cycle lateness", "p99"),
        q("cycle lateness", "p99_9"),
        q("cycle execution", "p50"),
        q("cycle execution", "p99"),
        q("cycle execution", "p99_9"),
        q("wake-up", "p50"),
        q("wake-up", "p99"),
        report["counters"]["overruns"],
    );
}

fn main() {
    let seconds = std::env::var("SOAK_SECONDS").unwrap_or_else(|_| "10".into());
    println!(
        "| drives | transport | cycle lateness p50 / p99 / p99.9, us | execution p50 / p99 / p99.9, us | \
         wake-up p50 / p99, us | overruns | master CPU per cycle | frames |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for drives in DRIVES {
        let wire = Wire::new().expect("the bench makes a veth pair: it needs root or CAP_NET_ADMIN");
        let dir = tempfile::tempdir().unwrap();
        let machine = dir.path().join("machine.toml");
        std::fs::write(&machine, "[[axes]]\n".repeat(drives)).unwrap();
        let segment = Segment::serve_machine(&wire, End::Inside, Some(&machine));
        row(drives, "memory", &soak(drives, None, &seconds));
        row(drives, "wire", &soak(drives, Some(&wire.outside), &seconds));
        drop(segment);
    }
}

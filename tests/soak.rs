//! The soak test's smoke versions: 5 seconds with 2 scripts, and a short one with all 64.
//! No reply lost, duplicated or out of order; a well-formed report on stdout, in JSON and
//! as a plot. (The long run is `luamotion soak`, see the README.)

mod common;

use std::process::Command;

use common::*;

/// Runs `luamotion soak` with `args`; checks it succeeded with no reply lost, duplicated or
/// out of order, and every row in the table, and returns its report and its table.
fn soak(args: &[&str], json: &std::path::Path) -> (serde_json::Value, String) {
    // One soak at a time: each counts the cycles its 5 s hold, which 64 debug script
    // processes of the other on the same 2 CPUs would take from it.
    static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let ns = unique_ns("soak");
    let out = Command::new(BIN).arg("soak").args(args).args(["--ns", &ns, "--json"]).arg(json).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}\n{stderr}");

    let report: serde_json::Value = serde_json::from_slice(&std::fs::read(json).unwrap()).unwrap();
    let counters = &report["counters"];
    for zero in ["lost", "duplicated", "out_of_order", "call_errors"] {
        assert_eq!(counters[zero], 0, "{zero}: {stdout}");
    }
    let metrics = report["metrics"].as_array().unwrap();
    for name in [
        "command round trip",
        "script -> core",
        "core -> script",
        "wake-up",
        "snapshot age",
        "cycle lateness",
        "cycle execution",
        "floor: iceoryx2 one way",
        "floor: iceoryx2 round trip",
        "floor: bare loop lateness",
    ] {
        let m = metrics.iter().find(|m| m["name"] == name).unwrap_or_else(|| panic!("{name} in {report}"));
        assert!(m["count"].as_u64().unwrap() > 0, "{name}");
        let q: Vec<f64> =
            ["p50", "p90", "p99", "p99_9", "p99_99", "max"].iter().map(|k| m[k].as_f64().unwrap()).collect();
        assert!(q.windows(2).all(|w| w[0] <= w[1]) && q[0] > 0.0, "{name}: percentiles in order: {q:?}");
        assert!(stdout.contains(name), "{name} in the table");
    }
    (report, stdout)
}

#[test]
fn a_five_second_soak() {
    let dir = tempfile::tempdir().unwrap();
    let (json, plot) = (dir.path().join("soak.json"), dir.path().join("soak.svg"));
    let (report, stdout) = soak(&["--duration", "5", "--scripts", "2", "--plot", plot.to_str().unwrap()], &json);
    let counters = &report["counters"];
    assert!(counters["commands"].as_u64().unwrap() > 1000, "{stdout}");
    assert!(counters["cycles"].as_u64().unwrap() >= 5000, "{stdout}");
    let metrics = report["metrics"].as_array().unwrap();
    let round_trip = metrics.iter().find(|m| m["name"] == "command round trip").unwrap();
    assert!(round_trip["ratio_p50"].as_f64().unwrap() > 1.0, "beside its floor");
    assert_eq!(report["targets"].as_array().unwrap().len(), 5);

    let svg = std::fs::read_to_string(&plot).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("command round trip") && svg.contains("polyline"), "a plot");
}

/// Issue 11, defect 1: the soak's help says 1..64 scripts; with 64 every worker attaches
/// and every call is answered.
#[test]
fn a_soak_with_64_scripts() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("soak.json");
    let (report, stdout) = soak(&["--duration", "2", "--scripts", "64"], &json);
    assert_eq!(report["run"]["scripts"], 64, "{stdout}");
    assert!(report["counters"]["commands"].as_u64().unwrap() > 0, "{stdout}");
}

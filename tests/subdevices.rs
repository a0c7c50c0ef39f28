//! Issue 38: the simulated drives on a real (virtual) wire, with a master nobody here wrote.
//! `luamotion subdevices` serves the built-in machine's drives on one end of a veth pair;
//! SOEM (pysoem, tests/python/soem_master.py) is the master on the other end, in a network
//! namespace. The test makes the namespace and the pair itself, with names of its own, and
//! removes them when it ends, also when it fails. It needs root or CAP_NET_ADMIN and
//! CAP_NET_RAW; with `CI=true` a missing capability or install fails, never skips.

mod common;

use std::process::{Command, Stdio};
use std::time::Duration;

use common::wire::{End, Segment, Wire, wire};
use common::{finish, pymodbus_python, repo_path};
use config::MachineConfig;

/// The master's script in the namespace, with a deadline; its JSON report.
fn soem_master(wire: &Wire, counts_per_mm: f64) -> serde_json::Value {
    let python = pymodbus_python();
    let child = Command::new(&wire.ip)
        .args(["netns", "exec", &wire.namespace])
        .arg(python)
        .arg(repo_path("tests/python/soem_master.py"))
        .arg(&wire.inside)
        .arg(counts_per_mm.to_string())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start the pysoem master");
    let finished = finish(child, Duration::from_secs(120));
    assert!(
        finished.status.success(),
        "the pysoem master failed or ran past its 120 s ({}):\n{}",
        finished.status,
        finished.stderr
    );
    serde_json::from_str(finished.stdout.trim()).unwrap_or_else(|e| panic!("its report: {e}\n{}", finished.stdout))
}

/// Issue 38 item 2, each point against the machine file and the CoE manual.
#[test]
fn soem_scans_configures_and_moves_the_simulated_drives() {
    let Some(wire) = wire() else { return };
    let machine = MachineConfig::default();
    let axes = machine.axes.len();
    let segment = Segment::serve(&wire, End::Outside);
    let report = soem_master(&wire, machine.axes[0].counts_per_unit);
    let stopped = segment.stop();
    let int = |key: &str| report[key].as_i64().unwrap_or_else(|| panic!("{key} in {report}"));
    let list = |key: &str| -> Vec<i64> {
        report[key].as_array().unwrap_or_else(|| panic!("{key}")).iter().map(|v| v.as_i64().unwrap()).collect()
    };

    // config_init: every drive, with the identity of its 0x1018 (CoE manual tables 4-1, 4-2).
    assert_eq!(int("count"), axes as i64, "{report}");
    for (slave, identity) in report["identity"].as_array().unwrap().iter().enumerate() {
        let product = i64::from(machine.axes[slave].drive.product_code());
        assert_eq!(identity, &serde_json::json!([0xAAAA, product, 1]), "slave {slave}");
    }
    assert_eq!(list("after_init"), vec![2; axes], "PreOp after config_init");
    // config_map: the default mapping (CoE manual table 2-4): RxPDO controlword and target
    // position, 6 bytes; TxPDO statusword, position, following error, 10 bytes.
    assert_eq!(int("image"), 16 * axes as i64);
    assert_eq!(int("expected_wkc"), 3 * axes as i64, "LRW: outputs 2, inputs 1 per slave");
    // OP via SafeOp.
    assert_eq!(int("safe_op"), 4);
    assert_eq!(list("after_map"), vec![4; axes]);
    assert_eq!(int("op"), 8);
    assert_eq!(list("after_op"), vec![8; axes]);
    // SDOs (CoE manual tables 4-1 and 4-15) and the aborts.
    let sdo = &report["sdo"];
    assert_eq!(sdo["0x1000"], 0x0002_0192, "device type");
    assert_eq!(sdo["0x1018"], serde_json::json!([0xAAAA, machine.axes[0].drive.product_code(), 1, 0]));
    assert_eq!(sdo["0x6060"], 8, "modes of operation: csp by default");
    assert_eq!(sdo["0x6502"], 0x03AD, "supported drive modes");
    assert_eq!(int("abort_missing"), 0x0602_0000, "a missing object");
    assert_eq!(int("abort_read_only"), 0x0601_0002, "a write to a read-only object");
    // The DC.
    assert_eq!(report["dc"], 1, "config_dc found DC-capable slaves");
    assert!(report["dc_time"].as_u64().unwrap() > 0, "the reference clock's system time came back");
    // The second variant: raw FPRD of the AL status (PreOp then) and the EEPROM by word.
    assert_eq!(list("al_status_fprd"), vec![2; axes]);
    for words in report["eeprom"].as_array().unwrap() {
        let rx_mailbox = 0x1800 | 246 << 16;
        assert_eq!(words, &serde_json::json!([0xAAAA, 2, 1, rx_mailbox, 0x0004]), "identity, mailbox, CoE");
    }
    // The CSP loop: Operation enabled, 10 mm, 0x6064 following within 0x6065.
    assert_eq!(int("statusword_enabled") & 0x6F, 0x27, "Operation enabled");
    assert!(!report["fault"].as_bool().unwrap(), "no fault, no following error bit: {report}");
    let moved = int("end") - int("start");
    assert!((moved - int("distance")).abs() <= 50, "moved {moved} counts of {}", int("distance"));
    assert!(int("worst_following_error") <= int("window"), "{report}");
    assert!(int("worst_following_error") > 0, "the drive followed a moving target");
    assert!(int("wkc_low") * 100 <= int("frames"), "process data frames short of the working counter: {report}");
    assert!(stopped.status.success(), "the segment ends on SIGTERM: {}", stopped.stderr);
    let answered = stopped.stderr.lines().find(|l| l.contains("frames answered")).unwrap_or_default().to_string();
    assert!(answered.contains(" 0 dropped"), "{answered}");
}

//! End to end: a Lua program arms touch probes (HMPL ch. 13) on a running controller and
//! reads back the positions they latched crossing the encoder index and an external mark
//! sensor, in user units of an axis whose counts per unit, index pitch and offset are not
//! round (2000 counts/mm, a mark every 7.5 mm from 1.25 mm, the sensor over [12.3, 12.8]
//! mm), with the axis' origin moved by SetPos.

mod common;

use common::*;

#[test]
fn a_program_latches_the_index_and_an_external_sensor() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("machine.toml");
    std::fs::write(&config, e2e::touch_probe(dir.path())).unwrap();
    let out = run(&unique_ns("tprobe"), &["--config", config.to_str().unwrap()]);
    e2e::check_touch_probe(&out);
}

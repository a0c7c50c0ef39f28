//! End to end: HMPL chapters 5, 6, 7, 18 and 20, each file a table of checks naming the
//! manual section each covers (tests/lua/hmpl_*.lua).

mod common;

use common::*;

fn passes(script: &str, last_line: &str) {
    let out = run(&unique_ns("hmpl"), &[repo_path(&format!("tests/lua/{script}")).to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(out.lines_of_task(0).last().map(String::as_str), Some(last_line), "{}", out.stdout);
}

#[test]
fn axis_motion_and_settings() {
    passes("hmpl_motion_facts.lua", "motion facts passed");
}

#[test]
fn axis_faults_state_and_error_codes() {
    passes("hmpl_state_facts.lua", "state facts passed");
}

#[test]
fn gear_and_gantry() {
    passes("hmpl_gear_gantry.lua", "gear and gantry facts passed");
}

#[test]
fn homing() {
    passes("hmpl_homing.lua", "homing facts passed");
}

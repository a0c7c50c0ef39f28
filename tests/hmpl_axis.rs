//! End to end: the HMPL Part 6 facts of chapters 5, 6, 7, 18 and 20, each file a table of
//! checks naming its facts (tests/lua/hmpl_*.lua).

mod common;

use common::*;

fn passes(script: &str, last_line: &str) {
    let out = run(&unique_ns("hmpl"), &[repo_path(&format!("tests/lua/{script}")).to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(out.lines_of_task(0).last().map(String::as_str), Some(last_line), "{}", out.stdout);
}

#[test]
fn motion_facts_35_to_43() {
    passes("hmpl_motion_facts.lua", "motion facts passed");
}

#[test]
fn state_facts_44_to_49_91_92() {
    passes("hmpl_state_facts.lua", "state facts passed");
}

#[test]
fn gear_and_gantry_facts_51_52() {
    passes("hmpl_gear_gantry.lua", "gear and gantry facts passed");
}

#[test]
fn homing_facts_93_to_95() {
    passes("hmpl_homing.lua", "homing facts passed");
}

//! End to end: the drives through the Lua functions of HMPL ch. 2, 17 and 21.

mod common;

use common::*;

fn machine_file(dir: &std::path::Path, text: &str) -> std::path::PathBuf {
    let path = dir.join("machine.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn an_integrator_walks_the_fsa_by_sdo() {
    let dir = tempfile::tempdir().unwrap();
    let config = machine_file(dir.path(), &e2e::fsa_walk(dir.path()));
    let out = run(&unique_ns("sdo"), &["--config", config.to_str().unwrap()]);
    e2e::check_fsa_walk(&out);
}

#[test]
fn ecat_state_slave_info_and_process_data() {
    let out = run(&unique_ns("ecat"), &[repo_path("tests/lua/ecat_queries.lua").to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(out.lines_of_task(0), vec!["all checks passed"]);
}

/// A start-up that fails leaves the network where it stopped, and says so: in the log,
/// in `GetECATSt`, in `IsSystemError`; motion is refused, the mailbox still works.
#[test]
fn a_failed_start_up_stays_in_pre_op() {
    let dir = tempfile::tempdir().unwrap();
    program(
        dir.path(),
        "check.lua",
        "Print('%d %s %s', GetECATSt(), tostring(IsSystemOper()), tostring(IsSystemError()))\n\
         Print('enable 0x%08x', Enable(0))\n\
         Print('device type 0x%08x', ReadSDO(0, 0x1000, 0, 4))\n",
    );
    let config = machine_file(
        dir.path(),
        "[[axes]]\ntx_pdo = [0x60410010, 0x60630020]\n[[tasks]]\nid = 0\nprogram = \"check.lua\"\nautorun = true\n",
    );
    let out = run(&unique_ns("badmap"), &["--config", config.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(
        out.lines_of_task(0),
        vec!["2 false true", "enable 0x000014b4", "device type 0x00020192"],
        "PreOp; eERR_HMPL_NOT_IN_OP_MODE; SDO still works"
    );
    assert!(out.stderr.contains("AL status code 0x0024"), "{}", out.stderr);
}

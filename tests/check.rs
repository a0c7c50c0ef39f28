//! Issue 40: `luamotion check` on the project's own programs and on mistakes, the check
//! `run` makes before anything moves, the environment held to a real script VM's globals,
//! and luacheck (Debian's lua-check, which luamotion did not write) with the generated
//! `.luacheckrc`.

mod common;

use std::process::Command;

use common::*;

fn luamotion(args: &[&str]) -> std::process::Output {
    Command::new(BIN).args(args).current_dir(repo_path(".")).output().expect("luamotion")
}

/// The project's programs: the examples, the manual's reference programs, the Lua tests
/// and the benchmarks' programs. Every one checks clean: no false alarm.
const PROGRAMS: [&str; 3] = ["scripts", "tests/lua", "benches/lua"];

#[test]
fn every_program_of_the_project_checks_clean() {
    let out = luamotion(&[&["check"][..], &PROGRAMS].concat());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    let last = text.lines().last().unwrap_or_default();
    assert!(last.ends_with("file(s) checked: 0 error(s), 0 warning(s)"), "{text}");
    let files: usize = last.split(' ').next().unwrap().parse().unwrap();
    assert!(files >= 40, "{text}");
}

#[test]
fn findings_as_json_and_warnings_allowed_one_by_one() {
    let dir = tempfile::tempdir().unwrap();
    let file = program(dir.path(), "bad.lua", "Enable(0)\nMoveAbsolute(0, 10)\nif Enable(0) == true then end\n");
    let out = luamotion(&["check", "--format", "json", file.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1), "an error: exit 1");
    let found: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let found = found.as_array().unwrap();
    assert_eq!(found.len(), 2, "{found:?}");
    assert_eq!(
        (found[0]["code"].as_str(), found[0]["line"].as_u64(), found[0]["column"].as_u64()),
        (Some("E101"), Some(2), Some(1))
    );
    assert!(found[0]["help"].as_str().unwrap().contains("MoveAbs"), "{found:?}");
    assert_eq!((found[1]["code"].as_str(), found[1]["severity"].as_str()), (Some("W201"), Some("warning")));

    let warning_only = program(dir.path(), "warn.lua", "if Enable(0) == true then end\n");
    let out = luamotion(&["check", warning_only.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(out.status.success(), "warnings alone: exit 0: {text}");
    assert!(text.contains("warn.lua:1:17: warning[W201]") && text.contains("^^^^"), "{text}");
    let out = luamotion(&["check", "--allow", "W201", warning_only.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("0 error(s), 0 warning(s)"));
    let out = luamotion(&["check", "--allow", "E101", warning_only.to_str().unwrap()]);
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("E101 is an error"));
}

/// Item 2: a program with an unknown API name does not start: nothing moves, no cycle is
/// traced; `--no-check` starts it, and the VM fails where the check said.
#[test]
fn run_refuses_a_program_with_an_unknown_name_before_anything_moves() {
    let dir = tempfile::tempdir().unwrap();
    let file = program(dir.path(), "main.lua", "Enable(0)\nMoveAbs(0, 10)\nMoveAbsolute(0, 20)\n");
    let trace = dir.path().join("trace.csv");
    let out = run(&unique_ns("check-run"), &["--trace", trace.to_str().unwrap(), file.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1), "{}", out.stderr);
    assert!(out.stderr.contains("main.lua:3:1: error[E101]: unknown global `MoveAbsolute`"), "{}", out.stderr);
    assert!(out.stderr.contains("nothing was started"), "{}", out.stderr);
    assert!(!trace.exists(), "no controller started, no cycle traced");
    let out = run(&unique_ns("check-run"), &["--no-check", file.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(out.stderr.contains("main.lua:3:") && out.stderr.contains("MoveAbsolute"), "{}", out.stderr);
}

/// The environment is the script VM's: every global a running program sees is known to
/// the check (a program that reads them all checks clean).
#[test]
fn the_check_knows_every_global_of_a_script_vm() {
    let dir = tempfile::tempdir().unwrap();
    let lister = program(
        dir.path(),
        "globals.lua",
        "local names = {}\nfor name in pairs(_G) do names[#names + 1] = name end\n\
         table.sort(names)\nfor _, name in ipairs(names) do Print('global %s', name) end\n",
    );
    let out = run(&unique_ns("check-globals"), &[lister.to_str().unwrap()]);
    assert!(out.status.success(), "{}", out.stderr);
    let names: Vec<String> =
        out.lines_of_task(0).iter().filter_map(|l| l.strip_prefix("global ")).map(str::to_string).collect();
    assert!(names.len() > 300, "{names:?}");
    // And the other way: every Lua global the check allows is in the VM.
    let missing: Vec<&&str> =
        check::environment::LUA_GLOBALS.iter().filter(|n| !names.iter().any(|m| m == *n)).collect();
    assert!(missing.is_empty(), "the check allows what the sandbox does not have: {missing:?}");
    let reads: String = names.iter().map(|n| format!("local _ = {n}\n")).collect();
    let reader = program(dir.path(), "reader.lua", &reads);
    let out = luamotion(&["check", reader.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stdout));
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("0 error(s), 0 warning(s)"),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
}

/// Item 5: the real luacheck with `luamotion api luacheckrc` finds no undefined global in
/// the project's programs, and does find one that is not the API's.
#[test]
fn luacheck_with_the_generated_luacheckrc() {
    let Ok(luacheck) = try_debian_tool("luacheck") else {
        assert!(!in_ci(), "CI=true: luacheck (Debian's lua-check) is needed");
        return eprintln!("skipped: no luacheck");
    };
    let dir = tempfile::tempdir().unwrap();
    let rc = dir.path().join(".luacheckrc");
    let out = luamotion(&["api", "luacheckrc"]);
    assert!(out.status.success());
    std::fs::write(&rc, &out.stdout).unwrap();
    let lint = |paths: &[&str]| {
        let out = Command::new(&luacheck)
            .args(["--config", rc.to_str().unwrap(), "--codes", "--no-color"])
            .args(paths)
            // Last: the option takes every word after it.
            .args(["--exclude-files", "scripts/luamotion.d.lua"])
            .current_dir(repo_path("."))
            .output()
            .expect("luacheck");
        String::from_utf8_lossy(&out.stdout).to_string()
    };
    let report = lint(&PROGRAMS);
    assert!(report.contains("Total:"), "{report}");
    assert!(!report.contains("(W113)") && !report.contains("(E0"), "undefined globals or errors:\n{report}");
    let bad = program(dir.path(), "bad.lua", "MoveAbsolute(0, 10)\nlocal t = os.time()\n");
    let report = lint(&[bad.to_str().unwrap()]);
    assert!(report.contains("(W113) accessing undefined variable 'MoveAbsolute'"), "{report}");
    assert!(report.contains("(W113) accessing undefined variable 'os'"), "{report}");
}

/// `serve` checks the machine file's task programs (what `StartTask` may start) before
/// anything starts; `--no-check` is the way round it.
#[test]
fn serve_refuses_a_task_program_with_an_unknown_name() {
    let dir = tempfile::tempdir().unwrap();
    program(dir.path(), "later.lua", "Enable(0)\nMoveAbsolute(0, 20)\n");
    let machine = dir.path().join("machine.toml");
    std::fs::write(&machine, "[[axes]]\n[[tasks]]\nid = 3\nprogram = \"later.lua\"\n").unwrap();
    let ns = unique_ns("check-serve");
    let child = Command::new(BIN)
        .args(["serve", "--ns", &ns, "--modbus-port", "0", "--ascii-port", "0", "--config", machine.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let out = finish(child, std::time::Duration::from_secs(30));
    assert_eq!(out.status.code(), Some(1), "{}", out.stderr);
    assert!(out.stderr.contains("later.lua:2:1: error[E101]: unknown global `MoveAbsolute`"), "{}", out.stderr);
    assert!(out.stderr.contains("nothing was started"), "{}", out.stderr);
}

//! `luamotion test`: Lua test programs on fresh controllers, the summary, JUnit XML, the
//! exit code, and what it says about paths it cannot use.

mod common;

use std::ffi::OsStr;
use std::io::{BufRead, BufReader, Write};
use std::net::TcpListener;
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use common::*;

/// `luamotion test <args>` to its end.
fn luamotion_test<S: AsRef<OsStr>>(args: &[S]) -> Finished {
    let child = Command::new(BIN)
        .arg("test")
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        // Its own group, with the controllers it starts: a timeout kills them all.
        .process_group(0)
        .spawn()
        .expect("start luamotion test");
    finish(child, Duration::from_secs(300))
}

fn junit(path: &Path) -> String {
    std::fs::read_to_string(path).expect("the JUnit file")
}

/// The `testcase` named `name` in a parsed JUnit document.
fn testcase<'a>(doc: &'a roxmltree::Document, name: &str) -> roxmltree::Node<'a, 'a> {
    doc.descendants()
        .find(|n| n.has_tag_name("testcase") && n.attribute("name") == Some(name))
        .unwrap_or_else(|| panic!("no testcase {name}"))
}

#[test]
fn a_passing_file_passes_with_its_machine_file_and_expected_lines() {
    let dir = tempfile::tempdir().unwrap();
    let file = program(
        dir.path(),
        "two_axes.lua",
        r#"
expect_eq(GetAxisNum(), 2, "the machine file beside the program")
Enable(0)
Till(function() return IsEnabled(0) end)
MoveAbs(0, 25)
Till(function() return not IsMoving(0) end)
expect_near(GetPosFb(0), 25, 1e-3)
expect_true(IsEnabled(0), "still enabled")
Print("at %.1f mm", GetPosFb(0))
Print("done")
"#,
    );
    std::fs::write(dir.path().join("two_axes.toml"), "[[axes]]\nname = \"x\"\n\n[[axes]]\nname = \"y\"\n").unwrap();
    std::fs::write(dir.path().join("two_axes.expected"), "# a comment\nat 25.0 mm\n~ don\n").unwrap();
    let out = luamotion_test(&[file.as_os_str()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert!(out.stdout.contains("PASS  "), "{}", out.stdout);
    assert!(out.stdout.contains("1 files: 1 passed, 0 failed, 0 errors"), "{}", out.stdout);
}

#[test]
fn failed_expectations_are_all_reported_with_their_lines_and_fail_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let file = program(
        dir.path(),
        "fails.lua",
        r#"Enable(0)
expect_near(1.5, 1, 0.1, "first")
expect_eq("a<b>&\"'", "x")
expect_true(0)
Print("went on: %s", tostring(expect_eq(3, 3.0)))
"#,
    );
    std::fs::write(dir.path().join("fails.expected"), "went on: true\nnever printed\n").unwrap();
    let report = dir.path().join("junit.xml");
    let out = luamotion_test(&[file.as_os_str(), "--junit".as_ref(), report.as_os_str()]);
    assert_eq!(out.status.code(), Some(1), "{}\n{}", out.stdout, out.stderr);
    for line in [
        "fails.lua:2: expect_near failed: got 1.5, expected 1.0 ± 0.1 (off by 0.5) (first)",
        r#"fails.lua:3: expect_eq failed: got "a<b>&\"'", expected "x""#,
        "fails.lua:4: expect_true failed: got 0",
        "fails.expected:2: the line \"never printed\" was not printed (in order)",
        "1 files: 0 passed, 1 failed, 0 errors",
    ] {
        assert!(out.stdout.contains(line), "no {line:?} in\n{}", out.stdout);
    }
    // The expectations' own count is no failure of its own in the summary.
    let listed = |l: &str| l.starts_with("  ") && !l.starts_with("   ");
    assert!(!out.stdout.lines().any(|l| listed(l) && l.contains("expectations failed")), "{}", out.stdout);

    let xml = junit(&report);
    let doc = roxmltree::Document::parse(&xml).expect("valid XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "testsuites");
    let suite = root.children().find(|n| n.has_tag_name("testsuite")).expect("testsuite");
    assert_eq!(["tests", "failures", "errors"].map(|a| suite.attribute(a)), [Some("1"), Some("1"), Some("0")]);
    let case = testcase(&doc, "fails.lua");
    assert!(case.attribute("time").and_then(|t| t.parse::<f64>().ok()).is_some());
    let failure = case.children().find(|n| n.has_tag_name("failure")).expect("a failure");
    assert!(
        failure
            .attribute("message")
            .unwrap()
            .ends_with("fails.lua:2: expect_near failed: got 1.5, expected 1.0 ± 0.1 (off by 0.5) (first)")
    );
    let text = failure.text().unwrap();
    assert!(text.contains(r#"expect_eq failed: got "a<b>&\"'""#), "{text}");
    assert_eq!(text.lines().count(), 4, "{text}");
    let system_out = case.children().find(|n| n.has_tag_name("system-out")).and_then(|n| n.text()).unwrap();
    assert!(system_out.contains("[task 0] went on: true"), "{system_out}");
}

#[test]
fn a_syntax_error_is_an_error_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let file = program(dir.path(), "broken.lua", "Print(\"fine\")\nlocal x = = 1\n");
    let report = dir.path().join("junit.xml");
    let out = luamotion_test(&[file.as_os_str(), "--junit".as_ref(), report.as_os_str()]);
    assert_eq!(out.status.code(), Some(1), "{}\n{}", out.stdout, out.stderr);
    assert!(out.stdout.contains("ERROR "), "{}", out.stdout);
    assert!(out.stdout.contains("broken.lua:2: unexpected symbol near '='"), "{}", out.stdout);
    let xml = junit(&report);
    let doc = roxmltree::Document::parse(&xml).expect("valid XML");
    let error = testcase(&doc, "broken.lua").children().find(|n| n.has_tag_name("error")).expect("an error");
    assert!(error.attribute("message").unwrap().contains("broken.lua:2:"), "{xml}");
    let suite = doc.descendants().find(|n| n.has_tag_name("testsuite")).unwrap();
    assert_eq!((suite.attribute("failures"), suite.attribute("errors")), (Some("0"), Some("1")));
}

/// Four files that can only pass together: each says hello to the test's listener and
/// waits for the word that comes once all four have (a run one at a time would wait
/// forever). Files of a folder in name order, each on its own controller.
#[test]
fn files_run_in_parallel_each_on_its_own_controller() {
    const FILES: usize = 4;
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let meeting = std::thread::spawn(move || {
        let mut peers = Vec::new();
        let mut names = Vec::new();
        for _ in 0..FILES {
            let (stream, _) = accept_within(&listener, Duration::from_secs(120), "each test file's program");
            let mut line = String::new();
            BufReader::new(&stream).read_line(&mut line).unwrap();
            names.push(line.trim().to_string());
            peers.push(stream);
        }
        for mut peer in peers {
            peer.write_all(b"go\n").unwrap();
        }
        names.sort();
        names
    });
    let dir = tempfile::tempdir().unwrap();
    for i in 0..FILES {
        program(
            dir.path(),
            &format!("meet{i}.lua"),
            &format!(
                r#"local rc, s = ASCII_ClientConnect("127.0.0.1", "{port}")
expect_eq(rc, 0, "connect")
ASCII_ClientSend(s, 7, "meet{i}\n")
local text = ""
repeat rc, text = ASCII_ClientRecv(s, 16) until rc ~= 0x17DE
expect_eq(text, "go\n")
-- Its own controller: the user table starts empty in every one.
expect_eq(GetTableValue(7), 0)
SetTableValue(7, {i} + 1)
"#
            ),
        );
    }
    std::fs::write(dir.path().join("notes.txt"), "not a program").unwrap();
    let report = dir.path().join("parallel.xml");
    let jobs = FILES.to_string();
    let out =
        luamotion_test(&[dir.path().as_os_str(), "-j".as_ref(), jobs.as_ref(), "--junit".as_ref(), report.as_os_str()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(meeting.join().unwrap(), ["meet0", "meet1", "meet2", "meet3"]);
    assert!(out.stdout.contains("4 files: 4 passed, 0 failed, 0 errors"), "{}", out.stdout);
    let xml = junit(&report);
    let doc = roxmltree::Document::parse(&xml).expect("valid XML");
    let names: Vec<&str> =
        doc.descendants().filter(|n| n.has_tag_name("testcase")).filter_map(|n| n.attribute("name")).collect();
    assert_eq!(names, ["meet0.lua", "meet1.lua", "meet2.lua", "meet3.lua"]);
}

#[test]
fn paths_it_cannot_use_are_refused_before_anything_runs() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("no-such.lua");
    let out = luamotion_test(&[missing.as_os_str()]);
    assert_eq!(out.status.code(), Some(2), "{}\n{}", out.stdout, out.stderr);
    assert!(out.stderr.contains("no-such.lua: No such file or directory"), "{}", out.stderr);

    let empty = tempfile::tempdir().unwrap();
    let out = luamotion_test(&[empty.path().as_os_str()]);
    assert_eq!(out.status.code(), Some(2), "{}", out.stderr);
    assert!(out.stderr.contains("no Lua test programs (*.lua) in this folder"), "{}", out.stderr);

    let text = dir.path().join("readme.txt");
    std::fs::write(&text, "x").unwrap();
    let good = program(dir.path(), "good.lua", "expect_true(true)\n");
    let out = luamotion_test(&[good.as_os_str(), text.as_os_str()]);
    assert_eq!(out.status.code(), Some(2), "{}", out.stderr);
    assert!(out.stderr.contains("readme.txt: not a Lua program"), "{}", out.stderr);
    assert!(!out.stdout.contains("PASS"), "nothing runs: {}", out.stdout);

    let out = luamotion_test::<&str>(&[]);
    assert_eq!(out.status.code(), Some(2), "{}", out.stderr);
}

/// The example a user starts from (`scripts/tests/`) passes.
#[test]
fn the_example_tests_pass() {
    let out = luamotion_test(&[repo_path("scripts/tests")]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert!(out.stdout.contains("PASS  ") && out.stdout.contains("hello_axis.lua"), "{}", out.stdout);
}

/// Outside `luamotion test` too, a program whose expectation failed fails its task, after
/// running to its end.
#[test]
fn under_luamotion_run_a_failed_expectation_fails_the_task() {
    let dir = tempfile::tempdir().unwrap();
    let file = program(dir.path(), "run.lua", "expect_eq(1, 2, \"one is two\")\nexpect_eq(2, 2)\nPrint(\"end\")\n");
    let out = run(&unique_ns("expect-run"), &[file.to_str().unwrap()]);
    assert!(!out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(out.lines_of_task(0).last().map(String::as_str), Some("end"), "{}", out.stdout);
    assert!(out.stdout.contains("run.lua:1: expect_eq failed: got 1, expected 2 (one is two)"), "{}", out.stdout);
    assert!(out.stderr.contains("run.lua: 1 of 2 expectations failed"), "{}", out.stderr);
}

/// The expectations take bad input as any function does: NaN, infinities, a negative
/// tolerance and two tables never hold; a wrong type is a Lua error and no expectation;
/// a huge message is cut as program output is.
#[test]
fn expectations_take_hostile_arguments_without_harm() {
    let dir = tempfile::tempdir().unwrap();
    let file = program(
        dir.path(),
        "hostile.lua",
        r#"expect_near(0/0, 1, 1)
expect_near(1, 1, 0/0)
expect_near(1, 1, -1)
expect_near(math.huge, math.huge, 1)
expect_eq({}, {})
expect_eq(nil, nil)
expect_true(string.rep('y', 100000))
expect_eq(1, 2, string.rep('m', 100000))
Print("type errors %s %s", tostring(pcall(expect_near, 'x', 1, 1)), tostring(pcall(expect_eq, 1, 1, {})))
Print("survived")
"#,
    );
    let out = run(&unique_ns("expect-hostile"), &[file.to_str().unwrap()]);
    assert!(!out.stderr.contains("panicked"), "{}", out.stderr);
    assert!(out.stderr.contains("hostile.lua: 6 of 8 expectations failed"), "{}\n{}", out.stdout, out.stderr);
    let lines = out.lines_of_task(0);
    assert_eq!(lines.iter().filter(|l| l.contains(" failed: ")).count(), 6, "{}", out.stdout);
    assert!(lines.iter().all(|l| l.len() <= 4200), "a line is cut: {}", out.stdout.len());
    assert_eq!(lines[lines.len() - 2..], ["type errors false false", "survived"], "{}", out.stdout);
}

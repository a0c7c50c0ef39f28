//! The scripts of `scripts/reference/` are tests of `luamotion test`: each runs on the
//! built-in machine, or on the machine file of the same name beside it (`ch10_analog.toml`
//! for `ch10_analog.lua`), and prints the lines of its `.expected` file (one fact each,
//! with the manual's place), in order.

mod common;

use common::*;

#[test]
fn luamotion_test_passes_every_reference_script_and_says_so_in_junit() {
    let dir = tempfile::tempdir().unwrap();
    let junit = dir.path().join("reference.xml");
    let folder = repo_path("scripts/reference");
    let out = finish(
        std::process::Command::new(BIN)
            .arg("test")
            .arg(&folder)
            .arg("--junit")
            .arg(&junit)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("start luamotion test"),
        std::time::Duration::from_secs(600),
    );
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);

    let mut scripts: Vec<String> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".lua"))
        .collect();
    scripts.sort();
    // Every reference script states what it must print.
    for script in &scripts {
        let expected = folder.join(script.replace(".lua", ".expected"));
        assert!(expected.is_file(), "{script} has no {}", expected.display());
    }

    let xml = std::fs::read_to_string(&junit).unwrap();
    let doc = roxmltree::Document::parse(&xml).expect("valid XML");
    let suite = doc.descendants().find(|n| n.has_tag_name("testsuite")).expect("a testsuite");
    assert_eq!(suite.attribute("tests"), Some(scripts.len().to_string().as_str()));
    assert_eq!((suite.attribute("failures"), suite.attribute("errors")), (Some("0"), Some("0")));
    let mut cases: Vec<&str> =
        suite.children().filter(|n| n.has_tag_name("testcase")).filter_map(|n| n.attribute("name")).collect();
    cases.sort();
    assert_eq!(cases, scripts);
}

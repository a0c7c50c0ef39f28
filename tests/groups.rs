//! Axis groups (HMPL ch. 8) from Lua, as a user runs them: the contour example under
//! `luamotion run --trace`, SetupGroup's undo, jogging, and hostile group calls.

mod common;

use common::*;

#[test]
fn the_contour_example_moves_both_axes_together_along_the_path() {
    let ns = unique_ns("contour");
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("contour.csv");
    let script = repo_path("scripts/examples/contour.lua");
    let out = run(&ns, &["--trace", trace.to_str().unwrap(), script.to_str().unwrap()]);
    e2e::check_contour(&out, &trace);
}

#[test]
fn setup_group_undoes_what_it_added_and_hostile_calls_get_codes() {
    let ns = unique_ns("grp-hostile");
    let dir = tempfile::tempdir().unwrap();
    let script = program(
        dir.path(),
        "hostile.lua",
        r#"
        Enable(0); Enable(1); Enable(2)
        Till(function() return IsEnabled(0) and IsEnabled(1) and IsEnabled(2) end)
        Print("duplicate %08X", SetupGroup(0, 0, 1, 0))
        Print("after undo: %d axes grouped", (GetGroupID(0) >= 0 and 1 or 0) + (GetGroupID(1) >= 0 and 1 or 0))
        Print("bad group %08X", EnableGroup(99))
        Print("NaN target %08X", SetupGroup(1, 0, 1) | LineAbs2D(1, 0/0, 1))
        Print("no such axis %08X", AddAxisToGrp(2, 77))
        Print("axis of another group %08X", AddAxisToGrp(2, 0))
        Print("line of 5 numbers %08X", LineAbs(1, {1, 2, 3, 4, 5}, {100, 1000, 1000, 0}, CS_MCS, BM_BUFF, TM_NONE, 0))
        Print("jog dir 6 %08X, axis 9 %08X", JogGroup(1, 6, 10), JogGroupAxis(1, 9, 10))
        local ok, err = pcall(LineAbs2D, 1, "x", 2)
        Print("string argument: %s", tostring(not ok))
        JogGroup(1, 0, 10)
        Sleep(500)
        JogGroup(1, 0, 0)
        Till(function() return not IsGrpMoving(1) end)
        Print("jogged X to %.1f, Y %.1f", GetPosFb(0), GetPosFb(1))
        "#,
    );
    let out = run(&ns, &[script.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    let lines = out.lines_of_task(0);
    let want = [
        "duplicate 82000028",
        "after undo: 0 axes grouped",
        "bad group 0000138F",
        "NaN target 820100D2",
        "no such axis 0000138F",
        "axis of another group 82020028",
        "line of 5 numbers 820101FE",
        "jog dir 6 820101FE, axis 9 82010082",
        "string argument: true",
    ];
    let mut rest = lines.iter();
    for w in want {
        assert!(rest.any(|l| l.contains(w)), "no line with {w:?} (in order)\n{}", out.stdout);
    }
    let jog = lines.iter().find(|l| l.starts_with("jogged X to")).expect("jog line");
    let x: f64 = jog.split_whitespace().nth(3).unwrap().trim_end_matches(',').parse().unwrap();
    assert!((4.0..6.0).contains(&x), "HMPL 8.2.7: 10 mm/s for 0.5 s is about 5 mm, got {jog}");
    assert!(jog.ends_with("Y 0.0"), "only X jogs: {jog}");
}

//! Dynamic error compensation (HMPL ch. 14) through the running controller: the manual's
//! three examples (14.1.1) checked at table points, between them and outside the table
//! against values worked out by hand from the examples' data; the spline against the
//! linear table at a known point; the 1 mm limit (0x83II0802); the preconditions and
//! refusals (not homed, enabled, SetPos while active, setups no axis can have).

mod common;

use std::collections::HashMap;

use common::*;

/// Lua helpers every program here starts with: `show(tag, a)` prints axis `a`'s
/// compensation, output minus reference and drive feedback minus reference once the axis
/// is in position; `code(rc)` prints a return code in hex.
const PRELUDE: &str = r#"
local function on(a) Enable(a) Till(function() return IsEnabled(a) end) end
local function show(tag, a)
  Sleep(3)
  Till(function() return IsInPos(a) end)
  Sleep(20)
  Print("%s %.9f %.9f %.9f %.9f", tag, GetCompPos(a), GetPosOut(a) - GetRefPos(a), GetPosFbComp(a) - GetRefPos(a), GetPosFb(a) - GetRefPos(a))
end
local function code(tag, rc) Print("%s 0x%08X", tag, rc) end
"#;

/// Runs `body` as task 0 on the built-in machine (4 axes): each printed line `tag v...`.
fn run_program(tag: &str, body: &str) -> (HashMap<String, Vec<String>>, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = program(dir.path(), "main.lua", &format!("{PRELUDE}\n{body}\nPrint(\"done\")\n"));
    let out = run(&unique_ns(tag), &[path.to_str().unwrap()]);
    let context = format!("{}\n{}", out.stdout, out.stderr);
    assert!(out.status.success(), "{context}");
    let lines = out.lines_of_task(0);
    assert_eq!(lines.last().map(String::as_str), Some("done"), "{context}");
    let map = lines
        .iter()
        .filter_map(|l| l.split_once(' '))
        .map(|(k, v)| (k.to_string(), v.split_whitespace().map(str::to_string).collect()))
        .collect();
    (map, context)
}

/// Checks a `show` line: the compensation is `want`, the output is reference + it (to
/// rounding), the drive stands at reference + it (within the servo's settling), and the
/// feedback without it is the reference.
fn assert_comp(lines: &HashMap<String, Vec<String>>, tag: &str, want: f64, context: &str) {
    let v: Vec<f64> = lines
        .get(tag)
        .unwrap_or_else(|| panic!("no line {tag}\n{context}"))
        .iter()
        .map(|s| s.parse().unwrap())
        .collect();
    let [comp, out_minus_ref, drive_minus_ref, fb_minus_ref] = v[..] else { panic!("{tag}: {v:?}") };
    assert!((comp - want).abs() < 1e-9, "{tag}: compensation {comp}, want {want}\n{context}");
    assert!((out_minus_ref - want).abs() < 1e-9, "{tag}: output - reference {out_minus_ref}, want {want}\n{context}");
    assert!(
        (drive_minus_ref - want).abs() < 5e-3,
        "{tag}: the drive stands {drive_minus_ref} off the reference, want {want}\n{context}"
    );
    assert!(
        fb_minus_ref.abs() < 5e-3,
        "{tag}: feedback without compensation {fb_minus_ref} off the reference\n{context}"
    );
}

fn assert_code(lines: &HashMap<String, Vec<String>>, tag: &str, want: &str, context: &str) {
    assert_eq!(lines.get(tag).map(|v| v.join(" ")).as_deref(), Some(want), "{tag}\n{context}");
}

/// HMPL 14.1.1 example 1: axis 0 compensated from axis 1's position, points -100..700
/// every 200 mm: {-0.2, 0.1, -0.3, 0.4, -0.1}. Axis 1 is placed by `SetPos` (disabled, its
/// reference is where it stands) and by a move; then the manual's way to disable.
#[test]
fn example_1_one_dimensional_table() {
    let (lines, context) = run_program(
        "comp1d",
        r#"
        SetUserTable(1, 5, {-0.2, 0.1, -0.3, 0.4, -0.1})
        SetHomedStatus(0, 1) SetHomedStatus(1, 1)
        code("setup", SetupComp(0, 1, -100, 200, 5, 1))
        code("enable", EnableComp(0))
        Print("active %s", tostring(IsCompActive(0)))
        on(0)
        for _, x in ipairs({-100, 100, 300, 500, 700, 0, 250, 550, -150, -1000, 800}) do
          SetPos(1, x) show("at" .. x, 0)
        end
        -- Moving the reference axis carries the compensation along.
        SetPos(1, 0) on(1) SetVel(1, 1000) SetAcc(1, 10000) SetDec(1, 10000) MoveAbs(1, 200) Till(function() return IsInPos(1) end) show("moved", 0)
        Disable(0) Till(function() return not IsEnabled(0) end)
        local standing = GetPosFbComp(0)
        code("disablecomp", DisableComp(0))
        Sleep(3)
        Print("after %s %.9f %.9f %.9f", tostring(IsCompActive(0)), GetCompPos(0), GetRefPos(0) - standing, GetPosOut(0) - standing)
        code("again", EnableComp(0))
        "#,
    );
    assert_code(&lines, "setup", "0x00000000", &context);
    assert_code(&lines, "enable", "0x00000000", &context);
    assert_code(&lines, "active", "true", &context);
    // At the points, the table's values.
    for (x, want) in [(-100, -0.2), (100, 0.1), (300, -0.3), (500, 0.4), (700, -0.1)] {
        assert_comp(&lines, &format!("at{x}"), want, &context);
    }
    // Between them, linear: 0 is half way from -0.2 to 0.1; 250 three quarters from 0.1
    // to -0.3; 550 a quarter from 0.4 to -0.1.
    assert_comp(&lines, "at0", -0.05, &context);
    assert_comp(&lines, "at250", 0.1 + 0.75 * (-0.3 - 0.1), &context);
    assert_comp(&lines, "at550", 0.4 + 0.25 * (-0.1 - 0.4), &context);
    // Outside, the nearest end point's value.
    assert_comp(&lines, "at-150", -0.2, &context);
    assert_comp(&lines, "at-1000", -0.2, &context);
    assert_comp(&lines, "at800", -0.1, &context);
    // Axis 1 moved from 0 to 200: half way from 0.1 to -0.3.
    assert_comp(&lines, "moved", -0.1, &context);
    // HMPL 14.3: off, no compensation, the reference where the axis stands; the setup is
    // gone, so enabling again needs a new one (0x83000190).
    assert_code(&lines, "disablecomp", "0x00000000", &context);
    let after = &lines["after"];
    assert_eq!(after[0], "false", "{context}");
    for v in &after[1..] {
        assert!(v.parse::<f64>().unwrap().abs() < 1e-6, "after DisableComp: {after:?}\n{context}");
    }
    assert_code(&lines, "again", "0x83000190", &context);
}

/// HMPL 14.1.1 example 2: axis 2 compensated from axes 0 (x: -100, 100, 300) and 1 (y:
/// -100, 0, 100), the 9 values from user table index 3, x varying fastest:
///   y = -100: 0.3  0.1 -0.4
///   y =    0: -0.4 0.0  0.2
///   y =  100: 0.2 -0.1  0.5
#[test]
fn example_2_two_dimensional_table() {
    let (lines, context) = run_program(
        "comp2d",
        r#"
        SetUserTable(3, 9, {0.3, 0.1, -0.4, -0.4, 0.0, 0.2, 0.2, -0.1, 0.5})
        for a = 0, 2 do SetHomedStatus(a, 1) end
        code("setup", SetupComp2D(2, 3, {-100, -100}, {200, 100}, {3, 3}, {0, 1}))
        code("enable", EnableComp(2))
        on(2)
        for _, p in ipairs({{100, 0}, {300, 100}, {-100, 100}, {300, -100}, {0, 50}, {200, 50}, {500, -300}, {200, 500}}) do
          SetPos(0, p[1]) SetPos(1, p[2]) show("at" .. p[1] .. "," .. p[2], 2)
        end
        "#,
    );
    assert_code(&lines, "setup", "0x00000000", &context);
    assert_code(&lines, "enable", "0x00000000", &context);
    for (at, want) in [("100,0", 0.0), ("300,100", 0.5), ("-100,100", 0.2), ("300,-100", -0.4)] {
        assert_comp(&lines, &format!("at{at}"), want, &context);
    }
    // (0, 50): row y=0 at x=0 is (-0.4 + 0.0)/2, row y=100 is (0.2 - 0.1)/2; half way.
    assert_comp(&lines, "at0,50", (-0.2 + 0.05) / 2.0, &context);
    // (200, 50): rows (0.0 + 0.2)/2 and (-0.1 + 0.5)/2; half way.
    assert_comp(&lines, "at200,50", (0.1 + 0.2) / 2.0, &context);
    // Outside: (500, -300) is the corner (300, -100); (200, 500) is on the row y = 100.
    assert_comp(&lines, "at500,-300", -0.4, &context);
    assert_comp(&lines, "at200,500", (-0.1 + 0.5) / 2.0, &context);
}

/// HMPL 14.1.1 example 3: axis 2 compensated from axes 0 (x: -10, 10, 30), 1 (y: 5, 15,
/// 25) and 2 itself (z: 0, 30, 60), three 3 x 3 tables (one per z), x fastest. Axis 2 is
/// its own reference, so it moves (SetPos is refused while compensation is active).
#[test]
fn example_3_three_dimensional_table() {
    let (lines, context) = run_program(
        "comp3d",
        r#"
        SetUserTable(3, 27, {0.3, 0.1, 0.2, -0.2, 0.0, 0.1, -0.1, 0.3, 0.4,
                             0.2, -0.1, 0.4, 0.2, 0.0, 0.2, 0.3, 0.1, 0.1,
                             0.4, 0.3, -0.2, -0.2, 0.1, 0.2, -0.2, 0.1, -0.4})
        for a = 0, 2 do SetHomedStatus(a, 1) end
        code("spline", SetCompAlgType(2, 1))
        code("spline3d", SetupComp3D(2, 3, {-10, 5, 0}, {20, 10, 30}, {3, 3, 3}, {0, 1, 2}))
        SetCompAlgType(2, 0)
        code("setup", SetupComp3D(2, 3, {-10, 5, 0}, {20, 10, 30}, {3, 3, 3}, {0, 1, 2}))
        code("splinelater", SetCompAlgType(2, 1))
        code("enable", EnableComp(2))
        code("setpos", SetPos(2, 5))
        on(2) SetVel(2, 500) SetAcc(2, 5000) SetDec(2, 5000)
        for _, p in ipairs({{10, 15, 30}, {30, 25, 60}, {-10, 5, 0}, {0, 10, 15}, {100, -100, 200}}) do
          SetPos(0, p[1]) SetPos(1, p[2]) MoveAbs(2, p[3])
          show("at" .. p[1] .. "," .. p[2] .. "," .. p[3], 2)
        end
        "#,
    );
    // HMPL 14.8: no spline on a 3-D table, in either order (0x83II012C).
    assert_code(&lines, "spline", "0x00000000", &context);
    assert_code(&lines, "spline3d", "0x8302012C", &context);
    assert_code(&lines, "setup", "0x00000000", &context);
    assert_code(&lines, "splinelater", "0x8302012C", &context);
    assert_code(&lines, "enable", "0x00000000", &context);
    // HMPL 14.1: the origin is fixed while compensation is active.
    assert_code(&lines, "setpos", "0x830200D2", &context);
    // Points: the centre of table 2, the last value of table 3, the first of table 1.
    assert_comp(&lines, "at10,15,30", 0.0, &context);
    assert_comp(&lines, "at30,25,60", -0.4, &context);
    assert_comp(&lines, "at-10,5,0", 0.3, &context);
    // (0, 10, 15): the middle of the first cell, the mean of its 8 corners:
    // table 1 0.3 0.1 -0.2 0.0, table 2 0.2 -0.1 0.2 0.0.
    assert_comp(&lines, "at0,10,15", (0.3 + 0.1 - 0.2 + 0.0 + 0.2 - 0.1 + 0.2 + 0.0) / 8.0, &context);
    // Outside: (100, -100, 200) is clamped to (30, 5, 60), the third value of table 3.
    assert_comp(&lines, "at100,-100,200", -0.2, &context);
}

/// HMPL 14.8: the natural cubic spline through example 1's points at x = 0. Its second
/// derivatives M (M0 = M4 = 0, h = 200) solve M[i-1] + 4 M[i] + M[i+1] = 6/h² (y[i+1] -
/// 2 y[i] + y[i-1]): 4 M1 + M2 = -1.05e-4, M1 + 4 M2 + M3 = 1.65e-4, M2 + 4 M3 = -1.8e-4,
/// so M1 = -0.43125e-4. At the middle of the first interval (t = 1/2):
/// S = (y0 + y1)/2 + h²/6 ((1/8 - 1/2) M0 + (1/8 - 1/2) M1) = -0.05 + 0.1078125 = 0.0578125,
/// where the linear table gives -0.05. At the points both give the table's values.
#[test]
fn the_spline_differs_from_the_linear_table_between_the_points() {
    let (lines, context) = run_program(
        "compspline",
        r#"
        SetUserTable(1, 5, {-0.2, 0.1, -0.3, 0.4, -0.1})
        SetHomedStatus(0, 1) SetHomedStatus(1, 1)
        code("alg", SetCompAlgType(0, 1))
        code("badalg", SetCompAlgType(0, 2))
        SetupComp(0, 1, -100, 200, 5, 1)
        EnableComp(0)
        code("alglater", SetCompAlgType(0, 0))
        on(0)
        for _, x in ipairs({0, 100, 500, -300}) do SetPos(1, x) show("at" .. x, 0) end
        "#,
    );
    assert_code(&lines, "alg", "0x00000000", &context);
    assert_code(&lines, "badalg", "0x8300012C", &context);
    assert_code(&lines, "alglater", "0x830000D2", &context);
    assert_comp(&lines, "at0", 0.0578125, &context);
    assert_comp(&lines, "at100", 0.1, &context);
    assert_comp(&lines, "at500", 0.4, &context);
    assert_comp(&lines, "at-300", -0.2, &context);
}

/// HMPL 14.1: at most 1 mm by default; beyond, 0x83II0802, the axis in ErrorStop with the
/// compensation held at the limit. Both signs.
#[test]
fn a_compensation_past_the_limit_stops_the_axis() {
    let (lines, context) = run_program(
        "complimit",
        r#"
        SetUserTable(0, 3, {0.0, 1.5, 0.0})
        SetUserTable(10, 3, {0.0, -2.0, 0.0})
        for a = 0, 3 do SetHomedStatus(a, 1) end
        SetupComp(0, 0, 0, 100, 3, 1)
        SetupComp(2, 10, 0, 100, 3, 3)
        EnableComp(0) EnableComp(2)
        on(0) on(2)
        for _, a in ipairs({0, 2}) do
          local ref = a + 1
          SetPos(ref, 20) Sleep(5)
          Print("inside%d %s %.9f", a, tostring(IsErrorStop(a)), GetCompPos(a))
          SetPos(ref, 100) Sleep(5)
          Print("past%d %s %.9f 0x%08X", a, tostring(IsErrorStop(a)), GetCompPos(a), GetAxisLastErr(a))
        end
        "#,
    );
    // A fifth of the way to 1.5 (to -2.0) is within the limit; at 1.5 (-2.0) held at it.
    assert_eq!(lines["inside0"].join(" "), "false 0.300000000", "{context}");
    assert_eq!(lines["past0"].join(" "), "true 1.000000000 0x83000802", "{context}");
    assert_eq!(lines["inside2"].join(" "), "false -0.400000000", "{context}");
    assert_eq!(lines["past2"].join(" "), "true -1.000000000 0x83020802", "{context}");
}

/// The manual's preconditions: homed axes, a setup, a disabled axis; refusals keep the
/// state; a table with a value that is no number is refused when it is read.
#[test]
fn compensation_is_refused_where_the_manual_forbids_it() {
    let (lines, context) = run_program(
        "comppre",
        r#"
        SetUserTable(0, 3, {0.1, 0.2, 0.3})
        code("nosetup", EnableComp(0))
        code("setup", SetupComp(0, 0, 0, 10, 3, 1))
        code("nothomed", EnableComp(0))
        SetHomedStatus(0, 1)
        code("refnothomed", EnableComp(0))
        SetHomedStatus(1, 1)
        on(0)
        code("enabled", EnableComp(0))
        Disable(0) Till(function() return not IsEnabled(0) end)
        code("badref", SetupComp(0, 0, 0, 10, 3, 9))
        code("onepoint", SetupComp(0, 0, 0, 10, 1, 1))
        code("nointerval", SetupComp(0, 0, 0, 0, 3, 1))
        code("pasttable", SetupComp(0, 511999, 0, 10, 3, 1))
        code("toolarge", SetupComp2D(0, 0, {0, 0}, {1, 1}, {50, 50}, {1, 2}))
        code("sameref", SetupComp2D(0, 0, {0, 0}, {1, 1}, {3, 3}, {1, 1}))
        code("short", SetupComp2D(0, 0, {0}, {1, 1}, {3, 3}, {1, 2}))
        code("ok", EnableComp(0))
        Print("active %s", tostring(IsCompActive(0)))
        code("setupwhileactive", SetupComp(0, 0, 0, 10, 3, 1))
        code("setpos", SetPos(0, 5))
        code("home", MoveHome(0))
        on(0)
        code("disableenabled", DisableComp(0))
        Print("stillactive %s", tostring(IsCompActive(0)))
        Disable(0) Till(function() return not IsEnabled(0) end)
        code("off", DisableComp(0))
        code("setposoff", SetPos(0, 5))
        SetUserTable(21, 1, {0/0})
        SetupComp(0, 20, 0, 10, 3, 1)
        code("nan", EnableComp(0))
        Print("nanactive %s", tostring(IsCompActive(0)))
        "#,
    );
    for (tag, want) in [
        ("nosetup", "0x83000190"),
        ("setup", "0x00000000"),
        ("nothomed", "0x83000064"),
        ("refnothomed", "0x83000064"),
        ("enabled", "0x8300006E"),
        ("badref", "0x8300012C"),
        ("onepoint", "0x8300012C"),
        ("nointerval", "0x8300012C"),
        ("pasttable", "0x8300012C"),
        ("toolarge", "0x8300012C"),
        ("sameref", "0x8300012C"),
        ("short", "0x8300012C"),
        ("ok", "0x00000000"),
        ("active", "true"),
        ("setupwhileactive", "0x830000D2"),
        ("setpos", "0x830000D2"),
        ("home", "0x830000D2"),
        ("disableenabled", "0x8300006E"),
        ("stillactive", "true"),
        ("off", "0x00000000"),
        ("setposoff", "0x00000000"),
        ("nan", "0x8300012C"),
        ("nanactive", "false"),
    ] {
        assert_code(&lines, tag, want, &context);
    }
}

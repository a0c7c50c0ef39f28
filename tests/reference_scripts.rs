//! The scripts of `scripts/reference/` run on the built-in machine, or on the machine file
//! of the same name beside them (`ch10_analog.toml` for `ch10_analog.lua`), and print what
//! the manual's examples lead a user to expect.

mod common;

use common::*;

/// (script, lines its task must print, in order).
const SCRIPTS: &[(&str, &[&str])] = &[
    (
        "ch02_system.lua",
        &[
            "system: init false, oper true, pre-op false, error false", // HMPL 2.1-2.4
            "EtherCAT state 8, slave 0 state 8, 4 slaves",              // HMPL 2.5, 2.6, 2.10
            concat!(env!("CARGO_PKG_VERSION")),                         // HMPL 2.11: Print("%s", ver_buf)
            concat!("firmware ", env!("CARGO_PKG_VERSION"), " of 20"),  // HMPL 2.12, 2.13
            "model luamotion-sim, serial LM00000000",                   // HMPL 2.14, 2.15
            "ScanNetwork with every axis disabled: 0",                  // HMPL 2.16
            "ScanNetwork with axis 0 enabled: 0x138C, last system error 0x138C",
            "after a rescan: 0, EtherCAT state 8",
            "moved 10.000 mm after the rescan",
            "SetHMIScope(1) 0, SetHMIScope(0) 0, SetHMIScope(2) 0x138F", // HMPL 2.17
            "TON: false at first, true after 100 ms",                    // HMPL 2.24
            "chapter 2 done",
        ],
    ),
    (
        "ch03_strings.lua",
        &[
            "var1: 321, var2: 1428.570000, str: hello world", // HMPL 3.2
            "var2: 1.428570e+03",
            "var2: 1428.57",
            "var1: 321, var2: 1428.570000, str: hello world", // HMPL 3.3
            "var2: 1.428570e+03",
            "var2: 1428.57 (13 characters)",
            "len = 11",     // HMPL 3.4
            "is_equal = 1", // HMPL 3.5
            "is_equal = 0",
            "StrFindChar h 0, l 2, z -1",      // HMPL 3.6
            "StrFindCharEx 2 0 -1 4",          // HMPL 3.7
            "StrFindStr hel 0, wor 6, wol -1", // HMPL 3.8
            "hello world",                     // HMPL 3.9
            "wor",                             // HMPL 3.10
            "world",
            "hello world",
            "hello world", // HMPL 3.11
            "[hello my ]", // HMPL 3.12
            "hello my friends",
            "v = 1.234",                                                             // HMPL 3.13
            "StringCat past HMPL_STR_MAX_LEN (512): 0x138D, destination kept (500)", // HMPL 3.1
            "array1: 11, 22, 33, 44, 55",                                            // HMPL 3.14
            "array1: 345, 456, 567, 44, 55",
            "array1: 345, 456, 567, 678, 789",
            "array1: 0, 0, 0, 0, 0", // HMPL 3.15
            "array1: 16843009, 0, 0, 0, 0 (0x01010101)",
            "is_equal = false", // HMPL 3.16
            "is_equal = true",
            "chapter 3 done",
        ],
    ),
    (
        "ch04_math.lua",
        &[
            "sine of 30.0 degrees is 0.500000.",                   // HMPL 4.1
            "cosine of 60.0 degrees is 0.500000.",                 // HMPL 4.2
            "tangent of 45.0 degrees is 1.000000.",                // HMPL 4.3
            "arc sine of 0.5 is 30.000000 degrees",                // HMPL 4.4
            "arc cosine of 0.5 is 60.000000 degrees",              // HMPL 4.5
            "arc tangent of 1.0 is 45.000000 degrees",             // HMPL 4.6
            "arc tangent for (x=-10, y=10) is 135.000000 degrees", // HMPL 4.7
            "absolute value of -3591 is 3591.",                    // HMPL 4.8
            "absolute value of -35.91 is 35.910000.",              // HMPL 4.9
            "ceil of 2.3 is 3",                                    // HMPL 4.10
            "ceil of 3.8 is 4",
            "ceil of -2.3 is -2",
            "ceil of -3.8 is -3",
            "floor of 2.3 is 2", // HMPL 4.11
            "floor of 3.8 is 3",
            "floor of -2.3 is -3",
            "floor of -3.8 is -4",
            "0.95 * 2^4 = 15.200000",                      // HMPL 4.12
            "The exponential value of 5.0 is 148.413159.", // HMPL 4.13
            "7.0 ^ 3.0 = 343.000000",                      // HMPL 4.14
            "4.73 ^ 12.0 = 125410439.217423",
            "32.01 ^ 1.54 = 208.036691",
            "log(5.5) = 1.704748",                                        // HMPL 4.15
            "log10(1000.0) = 3.000000",                                   // HMPL 4.16
            "sqrt(1024.0) = 32.000000",                                   // HMPL 4.17
            "cbrt (27.0) = 3.000000",                                     // HMPL 4.18
            "hypot(3.0, 4.0) = 5.000000.",                                // HMPL 4.19
            "exp(1000) is the largest double: true",                      // HMPL 4.13
            "pow(10, 400) = 1.79769e+308, ldexp(1, 5000) = 1.79769e+308", // HMPL 4.12, 4.14
            "PI 3.1415926535897931 SQRT2 1.4142135623730951 SQRT1_2 0.70710678118654757", // HMPL 23.1
            "bits: 9 8 24",                                               // HMPL 23.3
            "bit 5 is 1",
            "chapter 4 done",
        ],
    ),
    (
        "ch05_axis_motion.lua",
        &[
            "at 70.000 mm",
            "jogging at -50.0 mm/s",
            "resumed to 150.000 mm",
            "PVT ended at 83.333 mm",
            "chapter 5.2 done",
        ],
    ),
    (
        "ch05_axis_settings.lua",
        &[
            "vel 100 acc 2000 dec 2000 smooth 20 ms",
            "at 50 % override: 50.0 mm/s",
            "after SetPos(0): fb 0.000, offset 50.000",
            "last error 0x830107DA",
            "2 moves waiting",
            "rollover: 80.000 after 2 turns",
            "4 axes; chapter 5.3/5.4 done",
        ],
    ),
    (
        "ch06_gear.lua",
        &[
            "slave 1 (ratio 1.0, in gear true) at 100.000 mm",
            "slave 2 (ratio 2.0, in gear true) at 200.000 mm",
            "slave 3 (ratio -1.0, in gear true) at -100.000 mm",
            "master false, slave false: chapter 6 done",
        ],
    ),
    ("ch07_gantry.lua", &["gantry pair 0", "drives R 52.000 L 48.000 -> linear 50.000 yaw 2.000", "chapter 7 done"]),
    (
        "ch08_arcs.lua",
        &[
            "Arc2D via (100,100) to (200,0)   ends at (200.000, 0.000)",
            "ArcAngle2D about (10,10) by 45   ends at (10.000, -4.142)",
            "Circle2D (100,0) to (200,0), 1   ends at (200.000, 0.000)",
            "ArcCW2D about (50,0) to (100,0)  ends at (100.000, 0.000)",
            "ArcCCW2D about (50,0) to (0,0)   ends at (0.000, 0.000)",
            "ArcCW2D with radii 10 and 30: 0x82000280",
            "last group error 0x82000280; chapter 8 arcs done",
        ],
    ),
    (
        "ch08_blending.lua",
        &[
            "3 paths queued: 3 commands",
            "example 2 back at (0.000, 0.000)",
            "rounded rectangle queued as 8 segments",
            "example 3-2 ends at (20.000, 0.000), transition mode 2",
            "chapter 8 blending done",
        ],
    ),
    (
        "ch08_coordinates.lua",
        &[
            "5-1: PCS (10.000, 10.000) is MCS (400.000, 214.142)",
            "5-3: arrow 1 ends at MCS (500.000, 364.142)",
            "5-3: arrow 2 ends at MCS (700.000, -35.858)",
            "5-3: arrow 3 ends at MCS (900.000, -435.858)",
            "PCS reset to {0, 0, 0, 0, 0, 0}; coord sys 1",
            "chapter 8 coordinates done",
        ],
    ),
    (
        "ch08_group_line.lua",
        &[
            "group of axis 0: 0, of axis 2: -1; enabled true",
            "vel 100 acc 5000 dec 5000 smooth 200 ms",
            "moving true",
            "at (100.000, 100.000)",
            "2 commands queued",
            "LineRel2D ends at (200.000, 300.000)",
            "MoveAbs on a grouped axis: 0x830000E6",
            "after UngrpAllAxes: group of axis 0 -1; chapter 8 lines done",
        ],
    ),
    (
        "ch08_helix.lua",
        &[
            "three circles: Y reached 100.0, Z reached 100.0",
            "helix ends at (0.000, 0.000, 100.000)",
            "chapter 8 helix done",
        ],
    ),
    (
        "ch09_io.lua",
        &[
            "GetAllGPI with GPI 1 and 4 on: 9",                                  // HMPL 9.1, 9.4.3
            "GetAllGPO with GPO 2 and 3 on: 6",                                  // HMPL 9.4.4
            "example 1: rising edge seen true, axis 0 enabled false, GPO 3 = 1", // HMPL 9.1.2
            "example 2: slave 1 output 2 = 1, controller outputs 0xFF",
            "GetSlvAllGPIByStartIdx(1, 8) with inputs 8 and 11 on: 9", // HMPL 9.5.5
            "GetSlvAllGPOByStartIdx(1, 8) with outputs 9 and 10 on: 6", // HMPL 9.5.6
            "SetSlvAllGPO(1, 0x6): GetSlvAllGPO 6",                    // HMPL 9.3.3, 9.5.4
            "inverted: GPI 2 reads 1, invert masks 0x2 0x10",          // HMPL 9.2.4, 9.2.5, 9.4.5, 9.4.6
            "GetGPI(9) -1, SetGPO(0, 1) -1, SetSlvGPO(1, 17, 1) -1, GetSlvGPI(5, 1) -1", // HMPL 9.1: -1
            "SetSlvGPO(1 | HMPL_SLOT_2, 3, 1) -1",
            "chapter 9 done",
        ],
    ),
    (
        "ch10_analog.lua",
        &[
            "65535",    // HMPL 10.1.1 example 1
            "65535",    // example 2, looped back
            "5.000000", // example 3
            "output 9.999695 raw 65535",
            "reset: types 0 0, output raw 32768",
            "65535->9.9997 49152->5.0000 32768->0.0000 16384->-5.0000 0->-10.0000", // table 10.1.1
            "32767->9.9997 16384->5.0000 0->0.0000 -16384->-5.0000 -32768->-10.0000",
            "bound 1, scale 0.5, offset 1.0", // HMPL 10.4
            "at 8.000 mm the output is 5.0000",
            "unbound 0; chapter 10 done",
        ],
    ),
    (
        "ch12_position_trigger.lua",
        &[
            "EnablePT on axis 0: 0x1451",         // HMPL 12.1: no E1 drive
            "EnablePT before homing: 0x83010064", // HMPL 12.1: homing first
            "IsPTEnabled true",                   // HMPL 12.4
            "example 1 forward: 11 pulses at 10 11 12 13 14 15 16 17 18 19 20, 0 missed", // HMPL 12.1.3
            "IsPTEnabled false",
            "example 1 backward: 11 pulses at 20 19 18 17 16 15 14 13 12 11 10, 0 missed",
            "example 2 forward: 11 pulses at 10 12 13 16 17 20 22 25 26 28 30, 0 missed",
            "example 2 backward: 11 pulses at 30 28 26 25 22 20 17 16 13 12 10, 0 missed",
            "states 0x7ED forward: 9 pulses at 10 13 16 20 22 25 26 28 30, 0 missed", // HMPL 12.10
            "width 10 ns: 0x8301012C, 1010 ns: 0x8301012C; index 256: 0x8301012C; state word 8: 0x8301012C; interval 0: 0x8301012C",
            "chapter 12 done",
        ],
    ),
    (
        "ch13_touch_probe.lua",
        &[
            "13.6/13.8: enabled 1, triggered 0",
            "13.10: single, rising: triggered 1, rc 0, 10.0000 mm", // the first mark of 10, 20, 30
            "13.10: continuous, falling, moving back: rc 0, 10.0000 mm", // 30, 20, 10: the last
            "13.4: enabled 0, triggered 0",
            "13.3 on axis 0: 0x83000258; external input on axis 0: 0x8300012C",
            "13.9/13.11: probe 1 1 at 30.0000 mm (rc 0), probe 2 1 at 40.0000 mm (rc 0)",
            "after SetPos(1000) at 45 mm: probe 2 at 995.0000 mm",
            "chapter 13 done",
        ],
    ),
    (
        "ch14_compensation.lua",
        &[
            // HMPL 14.1.1 example 1: -100..700 every 200 mm; linear between, the end's outside.
            "example 1: compensation active true",
            "example 1: axis 1 at -100.0 -> compensation -0.2000, position output - reference -0.2000",
            "example 1: axis 1 at    0.0 -> compensation -0.0500, position output - reference -0.0500",
            "example 1: axis 1 at  100.0 -> compensation 0.1000, position output - reference 0.1000",
            "example 1: axis 1 at  550.0 -> compensation 0.2750, position output - reference 0.2750",
            "example 1: axis 1 at  800.0 -> compensation -0.1000, position output - reference -0.1000",
            "example 1: disabled, active false, compensation 0.0000, reference at the drive's position true",
            // Example 2: x fastest in the table.
            "example 2: axes 0, 1 at (-100, -100) -> compensation 0.3000",
            "example 2: axes 0, 1 at (100, 0) -> compensation 0.0000",
            "example 2: axes 0, 1 at (0, 50) -> compensation -0.0750",
            "example 2: axes 0, 1 at (300, 200) -> compensation 0.5000",
            // Example 3: three 3 x 3 tables, one per position of axis 2; linear only.
            "example 3: cubic spline on a 3-D table: 0x8302012C",
            "example 3: axes 0, 1, 2 at (10, 15, 30) -> compensation 0.0000",
            "example 3: axes 0, 1, 2 at (30, 25, 60) -> compensation -0.4000",
            "example 3: axes 0, 1, 2 at (0, 10, 15) -> compensation 0.0625",
            "example 3: SetPos while compensating: 0x830200D2",
            "limit: error stop true, compensation 1.0000, last error 0x83030802",
            "chapter 14 done",
        ],
    ),
    (
        "ch15_filters.lua",
        &[
            "example 1: SetAxisInShape 0, EnableAxisInShape 0", // HMPL 15.1.1, 15.5, 15.7
            "EnableAxisVsf with InShape on: 0x830000C8",        // HMPL 15.1
            "no filter: move",
            "ZV at 8 Hz: move",
            "the shaper adds 63 ms: half the load's period (62.5 ms) in whole cycles",
            "ZVD at 8 Hz: move",
            "the robust shaper adds 126 ms: the load's period (125 ms) in whole cycles",
            "SetAxisInShape while moving: 0x83000082", // HMPL 15.7 remark 1
            "DisableAxisInShape while moving: 0x83000082",
            "SetAxisVsf 0, EnableAxisVsf 0", // HMPL 15.2, 15.4
            "EnableAxisInShape with VSF on: 0x83000064",
            "VSF at 8 Hz: move",
            "the notch's tail adds",
            "SetAxisVsf(0, 0.05, 1.0): 0x8300047E, SetAxisVsf(0, 10, 0.5): 0x83000474",
            "SetAxisInShape(0, 1.0, 0.03, 1): 0x8300047E",
            "example 2: SetGrpInShape 0, EnableGrpInShape 0", // HMPL 15.1.1, 15.8, 15.10
            "EnableGrpInShape while moving: 0x82000046",
            "the shaped line moved by (20.000, 10.000)",
            "SetGrpInShape(gid, 2.0, 0.1, 1): 0x82000118",
            "chapter 15 done",
        ],
    ),
    (
        "ch18_errors.lua",
        &[
            "MoveAbs on a disabled axis   0x83020078",
            "after ClearAxisLastErr       0x00000000",
            "SetVelScale(120)             0x8302017C",
            "drive fault                  0x830203F2",
            "the drive reports 0x2310 (0x603F); IsDriveErr true",
            "GetSystemLastErr             0x0000138F",
            "chapter 18 done",
        ],
    ),
    ("ch20_homing.lua", &["Home success", "switch edge is the origin; homed true", "chapter 20 done"]),
    (
        "ch22_command_parser.lua",
        &[
            // HMPL 22.2.1 example 2: the manual's valid commands.
            "\"ENABLE 0\"        -> [ENABLE|0] response 0",
            "\"MOVEABS 0  0.05\" -> [MOVEABS|0|0.05] response 0",
            "\"MOVEREL 0  0.01\" -> [MOVEREL|0|0.01] response 0",
            "\"STOP 0\"          -> [STOP|0] response 0",
            "axis 0 at 0.060 mm",
            "\"JUMP 0 1\": response ?",
            "chapter 22 parser done",
        ],
    ),
];

/// Scripts whose every expected line is a whole line (the manual's printed results, where
/// "wor" must not pass for "world").
const WHOLE_LINES: &[&str] = &["ch03_strings.lua", "ch04_math.lua", "ch10_analog.lua", "ch22_command_parser.lua"];

fn check(script: &str) {
    let (_, expected) = SCRIPTS.iter().find(|(s, _)| *s == script).expect("in SCRIPTS");
    let whole = WHOLE_LINES.contains(&script);
    let path = repo_path(&format!("scripts/reference/{script}"));
    let machine = path.with_extension("toml");
    let mut args = vec![path.to_str().unwrap()];
    if machine.exists() {
        args.extend(["--config", machine.to_str().unwrap()]);
    }
    let out = run(&unique_ns("ref"), &args);
    assert!(out.status.success(), "{script}\n{}\n{}", out.stdout, out.stderr);
    let lines = out.lines_of_task(0);
    let mut rest = lines.iter();
    for want in expected.iter() {
        let found = rest.any(|line| if whole { line == want } else { line.contains(want) });
        assert!(found, "{script}: no line with {want:?} (in order)\n{}", out.stdout);
    }
}

#[test]
fn chapter_5_motion() {
    check("ch05_axis_motion.lua");
}

#[test]
fn chapter_5_settings_and_status() {
    check("ch05_axis_settings.lua");
}

#[test]
fn chapter_6_gear() {
    check("ch06_gear.lua");
}

#[test]
fn chapter_7_gantry() {
    check("ch07_gantry.lua");
}

#[test]
fn chapter_8_arcs() {
    check("ch08_arcs.lua");
}

#[test]
fn chapter_8_blending() {
    check("ch08_blending.lua");
}

#[test]
fn chapter_8_coordinates() {
    check("ch08_coordinates.lua");
}

#[test]
fn chapter_8_group_line() {
    check("ch08_group_line.lua");
}

#[test]
fn chapter_8_helix() {
    check("ch08_helix.lua");
}

#[test]
fn chapter_9_digital_io() {
    check("ch09_io.lua");
}

#[test]
fn chapter_10_analog() {
    check("ch10_analog.lua");
}

#[test]
fn chapter_12_position_trigger() {
    check("ch12_position_trigger.lua");
}

#[test]
fn chapter_15_filters() {
    check("ch15_filters.lua");
}

#[test]
fn chapter_18_errors() {
    check("ch18_errors.lua");
}

#[test]
fn chapter_14_compensation() {
    check("ch14_compensation.lua");
}

#[test]
fn chapter_20_homing() {
    check("ch20_homing.lua");
}

#[test]
fn chapter_2_system() {
    check("ch02_system.lua");
}

#[test]
fn chapter_3_strings_and_memory() {
    check("ch03_strings.lua");
}

#[test]
fn chapter_4_math() {
    check("ch04_math.lua");
}

#[test]
fn chapter_22_command_parser() {
    check("ch22_command_parser.lua");
}

#[test]
fn chapter_13_touch_probe() {
    check("ch13_touch_probe.lua");
}

#[test]
fn every_reference_script_is_tested() {
    let mut on_disk: Vec<String> = std::fs::read_dir(repo_path("scripts/reference"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".lua"))
        .collect();
    on_disk.sort();
    let tested: Vec<String> = SCRIPTS.iter().map(|(s, _)| s.to_string()).collect();
    assert_eq!(on_disk, tested);
}

//! The scripts of `scripts/reference/` run on the built-in machine and print what the
//! manual's examples lead a user to expect.

mod common;

use common::*;

/// (script, lines its task must print, in order).
const SCRIPTS: &[(&str, &[&str])] = &[
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
];

fn check(script: &str, expected: &[&str]) {
    let path = repo_path(&format!("scripts/reference/{script}"));
    let out = run(&unique_ns("ref"), &[path.to_str().unwrap()]);
    assert!(out.status.success(), "{script}\n{}\n{}", out.stdout, out.stderr);
    let lines = out.lines_of_task(0);
    let mut rest = lines.iter();
    for want in expected {
        assert!(rest.any(|line| line.contains(want)), "{script}: no line with {want:?} (in order)\n{}", out.stdout);
    }
}

#[test]
fn chapter_5_motion() {
    check(SCRIPTS[0].0, SCRIPTS[0].1);
}

#[test]
fn chapter_5_settings_and_status() {
    check(SCRIPTS[1].0, SCRIPTS[1].1);
}

#[test]
fn chapter_6_gear() {
    check(SCRIPTS[2].0, SCRIPTS[2].1);
}

#[test]
fn chapter_7_gantry() {
    check(SCRIPTS[3].0, SCRIPTS[3].1);
}

#[test]
fn chapter_8_arcs() {
    check(SCRIPTS[4].0, SCRIPTS[4].1);
}

#[test]
fn chapter_8_blending() {
    check(SCRIPTS[5].0, SCRIPTS[5].1);
}

#[test]
fn chapter_8_coordinates() {
    check(SCRIPTS[6].0, SCRIPTS[6].1);
}

#[test]
fn chapter_8_group_line() {
    check(SCRIPTS[7].0, SCRIPTS[7].1);
}

#[test]
fn chapter_8_helix() {
    check(SCRIPTS[8].0, SCRIPTS[8].1);
}

#[test]
fn chapter_18_errors() {
    check(SCRIPTS[9].0, SCRIPTS[9].1);
}

#[test]
fn chapter_20_homing() {
    check(SCRIPTS[10].0, SCRIPTS[10].1);
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

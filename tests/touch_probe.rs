//! End to end: a Lua program arms touch probes (HMPL ch. 13) on a running controller and
//! reads back the positions they latched crossing the encoder index and an external mark
//! sensor, in user units of an axis whose counts per unit, index pitch and offset are not
//! round (2000 counts/mm, a mark every 7.5 mm from 1.25 mm, the sensor over [12.3, 12.8]
//! mm), with the axis' origin moved by SetPos.

mod common;

use common::*;

#[test]
fn a_program_latches_the_index_and_an_external_sensor() {
    let dir = tempfile::tempdir().unwrap();
    let main = r#"
        local A = 0
        local function move(pos) MoveAbs(A, pos) Till(function() return IsInPos(A) end) end
        local function b(flag) return flag and 1 or 0 end
        Enable(A) Till(function() return IsEnabled(A) end)
        -- The origin moved: the machine's 0 reads 100 mm.
        SetPos(A, 100)
        -- Probe 1: external sensor, single, falling; probe 2: index, continuous, rising.
        SetTouchProbe1Func(A, 0, 0, 1) SetTouchProbe2Func(A, 1, 1, 0)
        EnableTouchProbe1(A) EnableTouchProbe2(A)
        move(120)
        local rc1, p1 = GetTouchProbe1Pos(A)
        local rc2, p2 = GetTouchProbe2Pos(A)
        Print("forward: tp1 %d %d %.4f tp2 %d %d %.4f", b(IsTouchProbe1Triggered(A)), rc1, p1, b(IsTouchProbe2Triggered(A)), rc2, p2)
        -- Back and forth across the sensor: a single trigger keeps its first edge; re-armed
        -- it takes the sensor's other end (moving negative the signal falls at L).
        move(110)
        rc1, p1 = GetTouchProbe1Pos(A)
        Print("back, single: %.4f", p1)
        move(120)
        DisableTouchProbe1(A) EnableTouchProbe1(A)
        Print("re-armed: triggered %d", b(IsTouchProbe1Triggered(A)))
        move(110)
        rc1, p1 = GetTouchProbe1Pos(A)
        rc2, p2 = GetTouchProbe2Pos(A)
        Print("again: tp1 %.4f tp2 %.4f", p1, p2)
        -- Bad arguments: the manual's non-0, never a stopped program.
        Print("bad: %X %X %X %d", SetTouchProbe1Func(A, 1, 2, 0), EnableTouchProbe1(7), SetTouchProbe2Func(A, -1, 0, 0), (GetTouchProbe1Pos(9)))
        Print("off: %d", DisableTouchProbe1(A) + DisableTouchProbe2(A) + b(IsTouchProbe1Enabled(A)) + b(IsTouchProbe2Enabled(A)))
    "#;
    let program = program(dir.path(), "main.lua", main);
    let toml = format!(
        "[[axes]]\nname = \"x\"\ncounts_per_unit = 2000.0\n\
         travel = {{ index_pitch = 7.5, index_offset = 1.25, probe_input_1 = [12.3, 12.8] }}\n\
         drive_settings = {{ touch_probe = \"cia402\" }}\n\n\
         [[tasks]]\nid = 0\nprogram = {:?}\nautorun = true\n",
        program.display().to_string()
    );
    let config = dir.path().join("machine.toml");
    std::fs::write(&config, toml).unwrap();
    let out = run(&unique_ns("tprobe"), &["--config", config.to_str().unwrap()]);
    assert_eq!(
        out.lines_of_task(0),
        vec![
            // Marks at 1.25 + 7.5 k: 8.75 and 16.25 mm of the machine are 108.75 and 116.25.
            "forward: tp1 1 0 112.8000 tp2 1 0 116.2500",
            "back, single: 112.8000",
            "re-armed: triggered 0",
            // Moving back over the mark at 16.25 mm the index pulse rises at its end (mark
            // + 0.075 mm, 1 % of the pitch).
            "again: tp1 112.3000 tp2 116.3250",
            // No axis 7 or 9: HMPL's argument out of range (0x138F = 5007).
            "bad: 8300012C 138F 8300012C 5007",
            "off: 0",
        ],
        "{}\n{}",
        out.stdout,
        out.stderr
    );
}

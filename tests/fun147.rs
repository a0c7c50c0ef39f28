//! The Fatek FUN147 step table (docs/fun147.md) run by the core every cycle on the group
//! interpolator: the manual's example on the built-in machine, pause and stop, the error
//! register, hostile calls, and the register image over Modbus with pymodbus.

mod common;

use std::process::Command;

use common::serve::serve;
use common::*;

/// Enables axes 0-3, loads `table` at R2000 and declares the Gp 0 box (EN M100, PAU M101,
/// ABT M102, ACT M110, ERR M111, DN M112, WR at D0).
fn prelude(table: &str) -> String {
    format!(
        "for a = 0, 3 do Enable(a) end\n\
         Till(function() return IsEnabled(0) and IsEnabled(1) and IsEnabled(2) and IsEnabled(3) end)\n\
         MHSPOLoad(\"R2000\", [[\n{table}\n]])\n\
         assert(MHSPO(0, \"R2000\", \"D0\", \"M100\", \"M101\", \"M102\", \"M110\", \"M111\", \"M112\") == 0)\n\
         local function ps(i) return GetPlcReg(\"DD\" .. (4088 + 2 * i)) end\n"
    )
}

fn run_lua(tag: &str, source: &str) -> Vec<String> {
    let dir = tempfile::tempdir().unwrap();
    let path = program(dir.path(), "main.lua", source);
    let out = run(&unique_ns(tag), &[path.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    out.lines_of_task(0)
}

fn expect_lines(lines: &[String], expected: &[&str]) {
    let mut rest = lines.iter();
    for want in expected {
        assert!(rest.any(|l| l.contains(want)), "no line with {want:?} (in order) in\n{}", lines.join("\n"));
    }
}

/// The manual's program example: step 1 ends at 500, 400, 300, 200 pulses; steps 2 and 3
/// add DD100/DD200 and DR300/DR400 (0.001 mm a pulse); WAIT X0 holds step 3 (WR+1 B9),
/// X0 goes back to step 1; EN = 0 stops and frees the axes.
#[test]
fn the_manual_example_runs_on_the_machine() {
    let path = repo_path("scripts/examples/fun147_table.lua");
    let out = run(&unique_ns("f147-example"), &[path.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    expect_lines(
        &out.lines_of_task(0),
        &[
            "001 SPD 5000",
            "    LIN ADR,D100,D200,,,Ut",
            "step 1 done at Ps0 500 Ps1 400 Ps2 300 Ps3 200",
            "step 3 done at Ps0 -500 Ps1 2900 Ps2 1500 Ps3 -400 (-0.500 2.900 1.500 -0.400 mm), waiting for X0: true",
            "running step 1 again, ERR false",
            "stopped: ACT false, Ready M1992 true",
        ],
    );
}

const ONE_STEP: &str = "001 SPD 5000\n LIN ADR,4000,-3000,,,Ps\n MEND";

/// FUN147 expl. 6: PAU holds the move (frequency 0, WR+1 B8) and PAU = 0 outputs exactly
/// the rest, with M1991 OFF (cut at once) and ON (decelerating).
#[test]
fn pause_holds_and_resumes_to_the_exact_travel() {
    let source = prelude(ONE_STEP)
        + "for _, decel in ipairs({false, true}) do\n\
             SetPlcRelay(\"M1991\", decel)\n\
             local x0, y0 = ps(0), ps(1)\n\
             SetPlcRelay(\"M100\", true)\n\
             Sleep(300)\n\
             SetPlcRelay(\"M101\", true)\n\
             Sleep(200)\n\
             local held, f = ps(0), GetPlcReg(\"DD4080\")\n\
             Sleep(200)\n\
             Print(\"paused decel=%s: moved %s, held %s, freq %d, B8 %s, left %d\", tostring(decel), tostring(held ~= x0), \
                   tostring(ps(0) == held), f, tostring(GetPlcReg(\"D1\") & 0x100 ~= 0), GetPlcReg(\"DD4072\"))\n\
             SetPlcRelay(\"M101\", false)\n\
             Till(function() return GetPlcRelay(\"M112\") end)\n\
             Print(\"resumed decel=%s: travel %d %d, DN D4062 %d\", tostring(decel), ps(0) - x0, ps(1) - y0, GetPlcReg(\"D4062\"))\n\
             SetPlcRelay(\"M100\", false) SetPlcReg(\"D1\", 0) Sleep(5)\n\
           end\n";
    let lines = run_lua("f147-pause", &source);
    for decel in ["false", "true"] {
        let paused = lines.iter().find(|l| l.starts_with(&format!("paused decel={decel}"))).expect("paused line");
        assert!(paused.contains("moved true, held true, freq 0, B8 true"), "{paused}");
        let left: i64 = paused.rsplit(' ').next().unwrap().parse().unwrap();
        assert!(left > 0 && left < 4000, "{paused}");
    }
    expect_lines(
        &lines,
        &["resumed decel=false: travel 4000 -3000, DN D4062 1", "resumed decel=true: travel 4000 -3000, DN D4062 1"],
    );
}

/// FUN147 expl. 5: EN = 0 stops (M1991 OFF: at once), ACT goes off, the axes are Ready
/// again and no longer grouped: an HMPL move of axis 0 is accepted. What was not output
/// stays in the pulses-left register.
#[test]
fn en_off_stops_and_frees_the_axes() {
    let source = prelude(ONE_STEP)
        + "SetPlcRelay(\"M100\", true)\n\
           Sleep(300)\n\
           Print(\"running: ACT %s, Ready %s, grouped %d\", tostring(GetPlcRelay(\"M110\")), tostring(GetPlcRelay(\"M1992\")), GetGroupID(0))\n\
           SetPlcRelay(\"M100\", false)\n\
           Sleep(20)\n\
           local x = ps(0)\n\
           Sleep(100)\n\
           Print(\"stopped: ACT %s, Ready %s, grouped %d, still %s, output+left %d\", tostring(GetPlcRelay(\"M110\")), \
                 tostring(GetPlcRelay(\"M1992\")), GetGroupID(0), tostring(ps(0) == x), ps(0) + GetPlcReg(\"DD4072\"))\n\
           Print(\"MoveAbs after: %d\", MoveAbs(0, 1))\n";
    let lines = run_lua("f147-stop", &source);
    expect_lines(
        &lines,
        &[
            "running: ACT true, Ready false, grouped 14",
            "stopped: ACT false, Ready true, grouped -1, still true, output+left 4000",
            "MoveAbs after: 0",
        ],
    );
}

/// Axes that stop following under a running box (disabled: its group goes to Group
/// Error Stop; or StopAll, HMPL 2.8, ending the move short) end the step with ERR and 90,
/// not with DN; the axes go free. The box owns its axes' motion: a program's `Disable` of
/// one is refused with 0x1AAA001F (docs/decisions.md, "Axis ownership"), `DisableAll`,
/// a stop, is not.
#[test]
fn an_axis_disabled_under_a_box_gives_90_not_dn() {
    box_interrupted_by("assert(Disable(1) == 0x1001001F)\nDisableAll()");
}

#[test]
fn stop_all_under_a_box_gives_90_not_dn() {
    box_interrupted_by("StopAll()");
}

fn box_interrupted_by(call: &str) {
    let source = prelude(ONE_STEP)
        + "SetPlcRelay(\"M100\", true)\n\
           Sleep(300)\n"
        + call
        + "\n\
           Till(function() return GetPlcRelay(\"M111\") end)\n\
           Print(\"ERR D4060 %d DN %s ACT %s Ready %s grouped %d\", GetPlcReg(\"D4060\"), tostring(GetPlcRelay(\"M112\")), \
                 tostring(GetPlcRelay(\"M110\")), tostring(GetPlcRelay(\"M1992\")), GetGroupID(0))\n";
    expect_lines(&run_lua("f147-disable", &source), &["ERR D4060 90 DN false ACT false Ready true grouped -1"]);
}

/// FUN147 expl. 2: Gp0 on Ps0/Ps1 and Gp1 on Ps2/Ps3 run side by side, each through its
/// own group (14, 15), each with its own D4062/D4063.
#[test]
fn two_boxes_run_side_by_side() {
    let source = prelude("001 SPD 8000\n LIN ADR,800,-600,,,Ps")
        + "MHSPOLoad(\"R3000\", \"001 SPD 6000\\n LIN ADR,,,-300,400,Ps\")\n\
           assert(MHSPO(1, \"R3000\", \"D20\", \"M200\", \"M201\", \"M202\", \"M210\", \"M211\", \"M212\") == 0)\n\
           SetPlcRelay(\"M100\", true) SetPlcRelay(\"M200\", true)\n\
           Sleep(20)\n\
           Print(\"groups %d %d %d %d\", GetGroupID(0), GetGroupID(1), GetGroupID(2), GetGroupID(3))\n\
           Till(function() return GetPlcRelay(\"M112\") and GetPlcRelay(\"M212\") end)\n\
           Print(\"done %d %d at %d %d %d %d\", GetPlcReg(\"D4062\"), GetPlcReg(\"D4063\"), ps(0), ps(1), ps(2), ps(3))\n";
    expect_lines(&run_lua("f147-two", &source), &["groups 14 14 15 15", "done 1 1 at 800 -600 -300 400"]);
}

/// FUN147 error table: SR+0 other than 0xA55C gives ERR and 34 in D4060, kept until it
/// is written 0; WR+1 B13.
#[test]
fn a_bad_table_gives_err_and_34() {
    let source = prelude(ONE_STEP)
        + "SetPlcReg(\"R2000\", 0x1234)\n\
           SetPlcRelay(\"M100\", true)\n\
           Till(function() return GetPlcRelay(\"M111\") end)\n\
           Print(\"ERR D4060 %d B13 %s ACT %s\", GetPlcReg(\"D4060\"), tostring(GetPlcReg(\"D1\") & 0x2000 ~= 0), tostring(GetPlcRelay(\"M110\")))\n\
           local ok, e = pcall(MHSPOText, \"R2000\")\n\
           Print(\"text: %s\", tostring(e))\n";
    expect_lines(
        &run_lua("f147-bad", &source),
        &["ERR D4060 34 B13 true ACT false", "MHSPOText: 34: illegal positioning program"],
    );
}

/// Hostile calls get clear errors and the core goes on: operands that do not exist, text
/// errors, a box on axes an HMPL group holds (ERR, 90), HMPL commands on a box's group,
/// MHSPO twice (the second replaces the first).
#[test]
fn hostile_calls_give_clear_errors() {
    let source = "for a = 0, 3 do Enable(a) end\n\
        Till(function() return IsEnabled(0) and IsEnabled(1) and IsEnabled(2) and IsEnabled(3) end)\n\
        Print(\"SR R9000 0x%X\", MHSPO(0, \"R9000\", \"D0\", \"M100\", \"M101\", \"M102\", \"M110\", \"M111\", \"M112\"))\n\
        Print(\"Gp 2 0x%X\", MHSPO(2, \"R2000\", \"D0\", \"M100\", \"M101\", \"M102\", \"M110\", \"M111\", \"M112\"))\n\
        Print(\"DN Q1 0x%X\", MHSPO(0, \"R2000\", \"D0\", \"M100\", \"M101\", \"M102\", \"M110\", \"M111\", \"Q1\"))\n\
        Print(\"WR D3995 0x%X\", MHSPO(0, \"R2000\", \"D3995\", \"M100\", \"M101\", \"M102\", \"M110\", \"M111\", \"M112\"))\n\
        Print(\"free 5 0x%X\", MHSPOFree(5))\n\
        Print(\"D4000: %s\", select(2, pcall(GetPlcReg, \"D4000\")))\n\
        Print(\"70000: %s\", select(2, pcall(SetPlcReg, \"R0\", 70000)))\n\
        Print(\"M2002: %s\", select(2, pcall(SetPlcRelay, \"M2002\", true)))\n\
        Print(\"text: %s\", select(2, pcall(MHSPOLoad, \"R2000\", \"001 SPD 5000\\n LIN ADR,1,2\")))\n\
        assert(SetupGroup(0, 0, 1) == 0)\n\
        MHSPOLoad(\"R2000\", \"001 SPD 5000\\n LIN ADR,100,100,,,Ps\")\n\
        assert(MHSPO(0, \"R2000\", \"D0\", \"M100\", \"M101\", \"M102\", \"M110\", \"M111\", \"M112\") == 0)\n\
        Print(\"EnableGroup(14) 0x%X\", EnableGroup(14))\n\
        SetPlcRelay(\"M100\", true)\n\
        Till(function() return GetPlcRelay(\"M111\") end)\n\
        Print(\"grouped elsewhere: D4060 %d Ready %s\", GetPlcReg(\"D4060\"), tostring(GetPlcRelay(\"M1992\")))\n\
        SetPlcRelay(\"M100\", false)\n\
        assert(UngrpAllAxes(0) == 0)\n\
        Print(\"DN of the failed box: %s\", tostring(GetPlcReg(\"D1\") & 0x4000 ~= 0))\n\
        SetPlcReg(\"D4060\", 0)\n\
        assert(MHSPO(0, \"R2000\", \"D0\", \"M200\", \"M201\", \"M202\", \"M210\", \"M211\", \"M212\") == 0)\n\
        SetPlcRelay(\"M200\", true)\n\
        Till(function() return GetPlcRelay(\"M212\") end)\n\
        Print(\"replaced: DN %s at %d %d, ERR %s\", tostring(GetPlcRelay(\"M212\")), GetPlcReg(\"DD4088\"), GetPlcReg(\"DD4090\"), tostring(GetPlcRelay(\"M211\")))\n\
        Print(\"MHSPOFree 0x%X, EnableGroup(14) 0x%X\", MHSPOFree(0), (function() Sleep(5) return EnableGroup(14) end)())\n";
    let lines = run_lua("f147-hostile", source);
    expect_lines(
        &lines,
        &[
            "SR R9000 0x138F",
            "Gp 2 0x138F",
            "DN Q1 0x138F",
            "WR D3995 0x138F",
            "free 5 0x138F",
            "D4000: ",
            "70000: ",
            "M2002: ",
            "text: ",
            "EnableGroup(14) 0x820E006E",
            "grouped elsewhere: D4060 90 Ready true",
            "DN of the failed box: false",
            "replaced: DN true at 100 100, ERR false",
            "MHSPOFree 0x0, EnableGroup(14) 0x820E0032",
        ],
    );
    let text = lines.iter().find(|l| l.starts_with("text: ")).unwrap();
    assert!(text.contains("line 2"), "{text}");
    for (key, what) in [("D4000: ", "D4000"), ("70000: ", "70000"), ("M2002: ", "M2002")] {
        let line = lines.iter().find(|l| l.starts_with(key)).unwrap();
        assert!(line.contains(what) && line.len() > key.len() + what.len(), "{line}");
    }
}

/// docs/fun147.md, "Modbus": pymodbus copies a table into R2000, sets EN's relay, and
/// reads WR+0, DN (WR+1 B14), D4062 and the positions back; D4000 and past S999 are
/// exception 02.
#[test]
fn a_modbus_client_loads_and_starts_a_table() {
    let dir = tempfile::tempdir().unwrap();
    let program = program(
        dir.path(),
        "box.lua",
        "for a = 0, 3 do Enable(a) end\n\
         Till(function() return IsEnabled(0) and IsEnabled(1) end)\n\
         MHSPOLoad(\"R1000\", \"001 SPD 4000\\n LIN ADR,1500,-700,,,Ps\")\n\
         MHSPO(0, \"R2000\", \"D0\", \"M100\", \"M101\", \"M102\", \"M110\", \"M111\", \"M112\")\n\
         while true do Sleep(100) end\n",
    );
    let machine = dir.path().join("machine.toml");
    std::fs::write(
        &machine,
        format!(
            "[[axes]]\n[[axes]]\n[[axes]]\n[[axes]]\n[[tasks]]\nid = 0\nprogram = {:?}\nautorun = true\n",
            program.display().to_string()
        ),
    )
    .unwrap();
    let server = serve(&unique_ns("f147-modbus"), dir.path(), &["--config", machine.to_str().unwrap()]);
    // The client waits for the table at R1000; the box sees EN's rising edge whenever it
    // is declared.
    let output = Command::new(pymodbus_python())
        .arg(repo_path("tests/python/fun147_client.py"))
        .arg(server.port.to_string())
        .output()
        .expect("run the Modbus client");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(output.status.success(), "{stdout}\n{}\n{}", String::from_utf8_lossy(&output.stderr), server.stderr());
    assert!(stdout.contains("WR+0 1 DN 1 D4062 1 Ps0 1500 Ps1 -700"), "{stdout}");
    assert!(stdout.contains("0x5AA0 exception 2") && stdout.contains("0x5BDF exception 2"), "{stdout}");
}

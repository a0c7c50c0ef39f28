//! End to end: the position trigger of HMPL ch. 12 on a running controller. A program
//! moves an axis over a trapezoid it can compute with PT enabled both ways; the trace
//! (`--trace`, its `.pulses.csv` and the `gpo` column) must show a pulse at every point,
//! at the time the feedback crossed it, on the GPO of `[axes.pt]`.

mod common;

use std::collections::HashMap;
use std::path::Path;

use common::*;

/// The profile of the program below: mm/s and mm/s².
const VEL: f64 = 50.0;
const ACC: f64 = 500.0;
const CYCLE_MS: f64 = 1.0;
/// The GPO the trigger is wired to.
const OUTPUT: u32 = 3;

fn read_csv(path: &Path) -> Vec<HashMap<String, f64>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines.map(|l| header.iter().zip(l.split(',')).map(|(h, v)| (h.to_string(), v.parse().unwrap())).collect()).collect()
}

/// Runs `main` as task 0 on one axis `x` with the machine-file lines `axis` (its `[axes.pt]`
/// among them), traced to `trace.csv` in the returned folder.
fn run_on_axis(tag: &str, axis: &str, main: &str) -> (Finished, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let program = program(dir.path(), "main.lua", main);
    let toml = format!(
        "[[axes]]\nname = \"x\"\n{axis}\n\n[[tasks]]\nid = 0\nprogram = {:?}\nautorun = true\n",
        program.display().to_string()
    );
    let config = dir.path().join("machine.toml");
    std::fs::write(&config, toml).unwrap();
    let trace = dir.path().join("trace.csv");
    let out = run(&unique_ns(tag), &["--config", config.to_str().unwrap(), "--trace", trace.to_str().unwrap()]);
    (out, dir)
}

/// Time (ms) a trapezoid from `from` to `to` (|to - from| long enough to cruise) needs to
/// cover the distance to `p`.
fn trapezoid_time(from: f64, to: f64, p: f64) -> f64 {
    let (d, total) = ((p - from).abs(), (to - from).abs());
    let ramp = VEL * VEL / (2.0 * ACC);
    let ramp_s = VEL / ACC;
    let s = if d <= ramp {
        (2.0 * d / ACC).sqrt()
    } else if d <= total - ramp {
        ramp_s + (d - ramp) / VEL
    } else {
        let cruise_end = ramp_s + (total - 2.0 * ramp) / VEL;
        let left = total - d;
        cruise_end + ramp_s - (2.0 * left / ACC).sqrt()
    };
    s * 1000.0
}

#[test]
fn pulses_at_the_crossings_of_a_trapezoid_both_ways_on_the_gpo_and_in_the_trace() {
    let main = r#"
        local a = 0
        Print("not homed: 0x%X", EnablePT(a))
        Enable(a) Till(function() return IsEnabled(a) end)
        SetHomedStatus(a, 1)
        SetPT_PulseWidth(a, 20000)
        SetPT_StartPos(a, 1) SetPT_Interval(a, 1) SetPT_EndPos(a, 29)
        Print("enable %d running %s", EnablePT(a), tostring(IsPTEnabled(a)))
        MoveAbs(a, 30) Till(function() return IsInPos(a) end)
        Print("forward %d missed %d running %s", GetPTPulseNum(a), GetPTMissedNum(a), tostring(IsPTEnabled(a)))
        SetPT_StartPos(a, 29) SetPT_EndPos(a, 1)
        EnablePT(a)
        MoveAbs(a, 0) Till(function() return IsInPos(a) end)
        Print("backward %d missed %d", GetPTPulseNum(a), GetPTMissedNum(a))
        local rc, pos, t = GetPTPulse(a, 28)
        Print("last %d at %g; beyond: 0x%X", rc, pos, GetPTPulse(a, 29))
        -- DisablePT ends a pass: no pulse after it.
        SetPT_StartPos(a, 1) SetPT_EndPos(a, 29) EnablePT(a) DisablePT(a)
        MoveAbs(a, 5) Till(function() return IsInPos(a) end)
        Print("disabled %d running %s", GetPTPulseNum(a), tostring(IsPTEnabled(a)))
    "#;
    let axis = format!("vel = {VEL}\nacc = {ACC}\ndec = {ACC}\n[axes.pt]\noutput = {OUTPUT}");
    let (out, dir) = run_on_axis("pt", &axis, main);
    let trace = dir.path().join("trace.csv");
    assert_eq!(
        out.lines_of_task(0),
        vec![
            "not homed: 0x83000064",
            "enable 0 running true",
            "forward 29 missed 0 running false",
            "backward 29 missed 0",
            "last 0 at 1; beyond: 0x8300012C",
            "disabled 0 running false",
        ],
        "{}\n{}",
        out.stdout,
        out.stderr
    );

    let rows = read_csv(&trace);
    let pulses = read_csv(&trace.with_extension("pulses.csv"));
    let row = |cycle: f64| rows.iter().find(|r| r["cycle"] == cycle).expect("a trace row for each cycle");
    assert_eq!(pulses.len(), 58);
    // The points in order: 1..29 forward, 29..1 backward.
    let expected: Vec<f64> = (1..=29).chain((1..=29).rev()).map(f64::from).collect();
    assert_eq!(pulses.iter().map(|p| p["position"]).collect::<Vec<_>>(), expected);

    // Each pulse lies in the cycle whose feedback passed its point, at the time the
    // feedback, linear between the two samples, crossed it.
    for p in &pulses {
        let (c, pos, t) = (p["cycle"], p["position"], p["time_ms"]);
        let (before, after) = (row(c - 1.0)["a0_pos_fb"], row(c)["a0_pos_fb"]);
        assert!((before - pos) * (after - pos) <= 0.0 && before != pos, "{p:?}: {before} -> {after}");
        let crossing = (c - 1.0 + (pos - before) / (after - before)) * CYCLE_MS;
        assert!((t - crossing).abs() < 1e-6, "{p:?}: crossed at {crossing} ms");
    }

    // Against the trapezoid: the reference starts in the cycle after the last at rest, and
    // the feedback follows it one cycle later (the drive takes the target of the frame
    // before). The points in the ramps (1, 2, 28, 29) test the profile's shape, too.
    for (pass, (from, to)) in [(0.0, 30.0), (30.0, 0.0)].into_iter().enumerate() {
        let first_pulse = pulses[pass * 29]["cycle"];
        let start = rows.iter().rev().find(|r| r["cycle"] < first_pulse && r["a0_ref_pos"] == from).unwrap()["cycle"];
        for p in &pulses[pass * 29..(pass + 1) * 29] {
            let model = start * CYCLE_MS + trapezoid_time(from, to, p["position"]) + CYCLE_MS;
            assert!((p["time_ms"] - model).abs() < 0.2 * CYCLE_MS, "{p:?}: the trapezoid crosses at {model} ms");
        }
    }

    // GPO 3 is high in exactly the cycles with a pulse.
    let bit = 1 << (OUTPUT - 1);
    for r in &rows {
        let high = r["gpo"] as u32 & bit != 0;
        assert_eq!(high, r["a0_pt_pulses"] > 0.0, "cycle {}", r["cycle"]);
    }
    assert_eq!(rows.iter().map(|r| r["a0_pt_pulses"]).sum::<f64>(), 58.0);
}

/// HMPL 12.1.1: velocity < interval x 16 kHz. Above it two points fall in one drive sample
/// and the second gives no pulse; below it none is missed.
#[test]
fn faster_than_interval_times_sampling_frequency_misses_pulses() {
    let main = r#"
        local a = 0
        Enable(a) Till(function() return IsEnabled(a) end)
        SetHomedStatus(a, 1)
        SetVel(a, 100) SetAcc(a, 5000) SetDec(a, 5000)
        -- 100 mm/s moves 0.00625 mm a drive sample: over 0.005 mm points, not over 0.01.
        for _, interval in ipairs({0.005, 0.01}) do
          MoveAbs(a, 0) Till(function() return IsInPos(a) end)
          SetPT_StartPos(a, 5) SetPT_Interval(a, interval) SetPT_EndPos(a, 6)
          EnablePT(a)
          MoveAbs(a, 10) Till(function() return IsInPos(a) end)
          Print("interval %g: %d pulses, %d missed", interval, GetPTPulseNum(a), GetPTMissedNum(a))
        end
    "#;
    let (out, _dir) = run_on_axis("ptfast", "[axes.pt]\noutput = 1", main);
    let lines = out.lines_of_task(0);
    let counts: Vec<(u32, u32)> = lines
        .iter()
        .map(|l| {
            let words: Vec<&str> = l.split_whitespace().collect();
            (words[2].parse().unwrap(), words[4].parse().unwrap())
        })
        .collect();
    assert_eq!(counts.len(), 2, "{}\n{}", out.stdout, out.stderr);
    let (pulses, missed) = counts[0];
    assert_eq!(pulses + missed, 201, "{lines:?}");
    // 1 mm at 0.00625 mm a sample spans 160 samples: one pulse in each, give or take the ends.
    assert!((159..=161).contains(&pulses), "{lines:?}");
    assert_eq!(counts[1], (101, 0), "{lines:?}");
}

/// Hostile arguments on an axis that has a trigger (tests/hostile_input.rs meets only the
/// 0x1451 of axes without one): every PT function answers, with 0 or a code, and the
/// trigger works afterwards; a homing ends its pass.
#[test]
fn hostile_arguments_on_an_axis_with_a_trigger() {
    let main = r#"
        local a = 0
        Enable(a) Till(function() return IsEnabled(a) end)
        SetHomedStatus(a, 1)
        local ints = {-1, 256, 0x7FFFFFFF, 0x100000000, math.mininteger, math.maxinteger}
        local doubles = {0/0, math.huge, -math.huge, 1e308, -1e308, -1, 0}
        local bad = {}
        local function try(name, ...)
          local ok, rc = pcall(_ENV[name], ...)
          -- 0x83II012C invalid parameter, 0x83II0136 position out of range, 0x138F.
          if ok and rc ~= 0 and rc & 0xFFFF ~= 0x012C and rc & 0xFFFF ~= 0x0136 and rc ~= 0x138F then bad[#bad + 1] = string.format("%s(%s)=0x%X", name, tostring(select(2, ...)), rc) end
        end
        for _, v in ipairs(ints) do
          for _, f in ipairs({"SetPT_PulseWidth", "SetPT_StartIndex", "SetPT_EndIndex", "GetPTPulse"}) do try(f, a, v) end
          try("SetPT_PosArray", a, v, 1.5) try("SetPT_StateArray", a, v, 1) try("SetPT_StateArray", a, 0, v)
          for _, f in ipairs({"EnablePT", "DisablePT", "IsPTEnabled", "GetPTPulseNum", "GetPTMissedNum"}) do pcall(_ENV[f], v) end
        end
        for _, v in ipairs(doubles) do
          for _, f in ipairs({"SetPT_StartPos", "SetPT_EndPos", "SetPT_Interval"}) do try(f, a, v) end
          try("SetPT_PosArray", a, 0, v)
          -- A span of 1e308 over the smallest interval has too many points to count.
          SetPT_StartPos(a, -1e9) SetPT_EndPos(a, 1e9) SetPT_Interval(a, 1e-9) try("EnablePT", a)
        end
        Print("unexpected codes: %d %s", #bad, table.concat(bad, " "))
        SetPT_StateArray(a, 0, -1) SetPT_PosArray(a, 0, 1) SetPT_PosArray(a, 1, 2)
        SetPT_StartIndex(a, 0) SetPT_EndIndex(a, 1)
        Print("enable %d", EnablePT(a))
        MoveAbs(a, 3) Till(function() return IsInPos(a) end)
        Print("pulses %d", GetPTPulseNum(a))
        -- A homing redefines the drive's position: it ends a pass (points 1 and 2 wait
        -- behind the axis at 3).
        EnablePT(a)
        Print("before homing %s", tostring(IsPTEnabled(a)))
        SetHomeMethod(a, 37) MoveHome(a)
        Print("after homing %s", tostring(IsPTEnabled(a)))
    "#;
    let (out, _dir) = run_on_axis("pthostile", "[axes.pt]\noutput = 8", main);
    assert!(!out.stderr.contains("panicked"), "{}", out.stderr);
    assert_eq!(
        out.lines_of_task(0),
        vec!["unexpected codes: 0 ", "enable 0", "pulses 2", "before homing true", "after homing false"],
        "{}\n{}",
        out.stdout,
        out.stderr
    );
}

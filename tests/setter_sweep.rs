//! Issue 11, defect 5: no number a script passes can poison an axis. The sweep comes from
//! the registry: every command with a number of a physical quantity (`double` or
//! `double*`), called with extreme finite values in that argument, must return a refusal
//! code; after each call the axis reads finite, and at the end it enables and moves into
//! position. The values just inside the edges (-0.0, subnormals) may be taken or refused,
//! but must leave the axis as sane.

mod common;

use api::registry::{self, ArgType, Kind, Quantity};
use common::*;

/// 2^31 counts of the default machine's axes: one count past what the drive can carry.
fn past_the_counts() -> f64 {
    2_147_483_648.0 / rt_core::MachineConfig::default().axes[0].counts_per_unit
}

fn lua_number(x: f64) -> String {
    format!("{x:e}")
}

/// A valid value for argument `j` of a call on axis 0 (axis 1 as the other axis).
fn valid(ty: ArgType, quantity: Option<Quantity>, first_axis: bool) -> String {
    match (ty, quantity) {
        (ArgType::Int, Some(Quantity::Axis)) => (if first_axis { "1" } else { "0" }).to_string(),
        (ArgType::Int, _) => "2".to_string(),
        (ArgType::Doubles, Some(Quantity::PvtTime)) => "{0, 100}".to_string(),
        (ArgType::Doubles, Some(Quantity::Target)) => "{GetPosFb(0), GetPosFb(0)}".to_string(),
        (ArgType::Doubles, _) => "{0, 0}".to_string(),
        _ => "1".to_string(),
    }
}

/// The calls of the sweep: Lua expressions, and whether each must be refused.
fn sweep() -> Vec<(String, bool)> {
    let past = past_the_counts();
    let out = [1e308, -1e308, 1e30, -1e30, f64::MAX, -f64::MAX, past, -past];
    let edges = [-0.0, 5e-324, -5e-324, f64::MIN_POSITIVE];
    let mut calls = Vec::new();
    for spec in registry::all().filter(|f| f.kind() == Kind::Command) {
        let axes: Vec<usize> =
            spec.args.iter().enumerate().filter(|(_, a)| a.quantity == Some(Quantity::Axis)).map(|(i, _)| i).collect();
        // The axis under test is the one the numbers belong to: the last axis argument.
        let last_axis = axes.last().copied();
        for (i, arg) in spec.args.iter().enumerate() {
            if !matches!(arg.ty, ArgType::Double | ArgType::Doubles) || arg.quantity.is_none() {
                continue;
            }
            // A group's numbers are not bound to the drive's counts (HMPL ch. 8: mm and deg
            // of the path): the values one count past them may be in range there.
            let group_bound = arg.quantity.is_some_and(|q| q.is_group_bound());
            let out = out.iter().filter(|v| !group_bound || v.abs() != past);
            for (value, refused) in out.map(|&v| (v, true)).chain(edges.iter().map(|&v| (v, false))) {
                let args: Vec<String> = spec
                    .args
                    .iter()
                    .enumerate()
                    .map(|(j, a)| match () {
                        _ if j == i && a.ty == ArgType::Double => lua_number(value),
                        // The extreme value as a table's second number.
                        _ if j == i => {
                            let first = if a.quantity == Some(Quantity::Target) { "GetPosFb(0)" } else { "0" };
                            format!("{{{first}, {}}}", lua_number(value))
                        }
                        _ => valid(a.ty, a.quantity, axes.len() > 1 && Some(j) != last_axis),
                    })
                    .collect();
                calls.push((format!("{}({})", spec.name, args.join(", ")), refused));
            }
        }
    }
    calls
}

fn program_text(calls: &[(String, bool)]) -> String {
    let mut lua = String::from(
        "local bad = 0\n\
         local function finite(x) return x == x and math.abs(x) < math.huge end\n\
         local function sane(what)\n\
           for _, f in ipairs({GetPosFb, GetPosErr, GetRefPos, GetPosOut, GetVel, GetAcc, GetDec}) do\n\
             if not finite(f(0)) then bad = bad + 1 Print('not finite after %s', what) return end\n\
           end\n\
         end\n\
         local function try(what, must_refuse, f)\n\
           local ok, rc = pcall(f)\n\
           if not ok then bad = bad + 1 Print('error from %s: %s', what, tostring(rc))\n\
           elseif must_refuse and rc == 0 then bad = bad + 1 Print('taken: %s', what) end\n\
           sane(what)\n\
         end\n\
         assert(Enable(0) == 0 and Enable(1) == 0)\n\
         Till(function() return IsEnabled(0) and IsEnabled(1) end)\n",
    );
    for (call, refused) in calls {
        lua += &format!("try([[{call}]], {refused}, function() return {call} end)\n");
    }
    lua += &format!("Print('calls %d, bad %d', {}, bad)\n", calls.len());
    // Undo what an edge value may have set, then the axis must move into position.
    lua += "Stop(0) Stop(1)\n\
            Till(function() return not IsMoving(0) end)\n\
            Reset(0) ClearAxisLastErr(0) SetVelScale(0, 100) SetVel(0, 100) SetAcc(0, 1000) SetDec(0, 1000)\n\
            SetSMTime(0, 0) SetPosWindow(0, 0.005) SetPosWindowTime(0, 5) SetSWRL(0, 1e5) SetSWLL(0, -1e5)\n\
            Disable(0) Till(function() return not IsEnabled(0) end)\n\
            assert(Enable(0) == 0, string.format('Enable: 0x%08X', GetAxisLastErr(0)))\n\
            Till(function() return IsEnabled(0) end)\n\
            local target = GetPosFb(0) + 5\n\
            assert(MoveAbs(0, target) == 0, string.format('MoveAbs: 0x%08X', GetAxisLastErr(0)))\n\
            local deadline = system_timeInMs + 3000\n\
            Till(function() return IsInPos(0) or system_timeInMs > deadline end)\n\
            assert(IsInPos(0) and math.abs(GetPosFb(0) - target) < 0.01,\n\
              string.format('axis 0 at %f, not %f: 0x%08X', GetPosFb(0), target, GetAxisLastErr(0)))\n\
            Print('moved')\n";
    lua
}

#[test]
fn every_setter_refuses_extreme_values_and_the_axis_still_moves() {
    let calls = sweep();
    assert!(calls.iter().any(|(c, _)| c.starts_with("SetPos(")), "the sweep comes from the registry");
    let dir = tempfile::tempdir().unwrap();
    let path = program(dir.path(), "sweep.lua", &program_text(&calls));
    let out = finish(start_run(&unique_ns("sweep"), &[path.to_str().unwrap()]), std::time::Duration::from_secs(120));
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(
        out.lines_of_task(0),
        vec![format!("calls {}, bad 0", calls.len()), "moved".to_string()],
        "{}",
        out.stderr
    );
}

/// The report: `SetPos(0, 1e308)` is refused with 0x83000136, and after Reset and Enable
/// the axis is finite and a move goes where it is sent.
#[test]
fn set_pos_1e308_is_refused_and_the_axis_moves() {
    let dir = tempfile::tempdir().unwrap();
    let source = "assert(Enable(0) == 0) Till(function() return IsEnabled(0) end)\n\
                  Print('%08x', SetPos(0, 1e308))\n\
                  Reset(0) Disable(0) Till(function() return not IsEnabled(0) end)\n\
                  Enable(0) Till(function() return IsEnabled(0) end)\n\
                  Print(string.format('%s %s %s', GetPosFb(0) == GetPosFb(0), GetPosErr(0) == GetPosErr(0),\n\
                    math.abs(GetRefPos(0)) < 1))\n\
                  assert(MoveAbs(0, 12) == 0)\n\
                  Till(function() return IsInPos(0) end)\n\
                  Print('%.2f', GetPosFb(0))\n";
    let path = program(dir.path(), "setpos.lua", source);
    let out = finish(start_run(&unique_ns("setpos"), &[path.to_str().unwrap()]), std::time::Duration::from_secs(60));
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(out.lines_of_task(0), ["83000136", "true true true", "12.00"], "{}", out.stderr);
}

//! Bad input loses nothing: every function of the registry (commands, queries and the
//! ones that run in the script process, but those `SKIPPED` names), called with values
//! out of every range (NaN, infinities, huge and negative numbers, ids that do not exist,
//! empty and oversized tables and strings), one argument at a time. Each call must come
//! back (a return code or a Lua error); the core must go on cycling, answer commands and
//! move an axis afterwards, and shut down cleanly. A call with more values than its
//! function takes is refused with the registry's words (issue 36.4); then random values
//! in random counts from a fixed seed, the end-to-end smoke of script-host's fuzz of the
//! call decoding (`bindings::call_tests`): each call comes back or raises an error that
//! names its function.

mod common;

use api::registry::{self, ArgType};
use common::*;

/// Functions left out: `Enable` would power axes and let `MoveHome` block for a homing;
/// `EStop` and `StopAllTask` end the run; `BindEMO(1)` would make the next `SimSetGPI(1, -1)`
/// an E-stop; `Sleep` and `DELAY` would wait for days on a huge number; `MutexLock` taken
/// twice ends the task, as HMPL 2.22 says; `Print` and `my_print` write the lines the test
/// reads; a failed `expect_*` fails the program by design (their bad input:
/// tests/test_runner.rs).
const SKIPPED: &[&str] = &[
    "Enable",
    "MoveHome",
    "EStop",
    "StopAllTask",
    "BindEMO",
    "Sleep",
    "DELAY",
    "MutexLock",
    "Print",
    "my_print",
    "expect_eq",
    "expect_near",
    "expect_true",
];

fn valid(ty: ArgType) -> &'static str {
    match ty {
        ArgType::Int => "1",
        ArgType::Double => "1.5",
        ArgType::Str => "'x'",
        ArgType::Bytes => "{1, 2}",
        ArgType::Doubles => "{0, 1}",
        ArgType::Func => "function() return true end",
        ArgType::Rest | ArgType::Any => "1",
        ArgType::Bool => "true",
        ArgType::Timer => "TimerInit()",
        ArgType::Memory => "{1, 2}",
    }
}

fn hostile(ty: ArgType) -> &'static [&'static str] {
    match ty {
        ArgType::Int => &["-1", "99", "0x7FFFFFFF", "math.mininteger", "math.maxinteger", "1.5", "0/0"],
        ArgType::Double => &["0/0", "math.huge", "-math.huge", "1e308", "-1e308", "-1", "0"],
        ArgType::Str => &["''", "string.rep('y', 100000)"],
        ArgType::Bytes => &["{}", "{300, -1}", "big_bytes"],
        ArgType::Doubles => &["{}", "{0/0, math.huge}", "big_doubles"],
        ArgType::Bool => &["{}", "'x'"],
        ArgType::Timer => &["{}", "1"],
        ArgType::Memory => &["{}", "{1.5, 'x'}", "{math.maxinteger}", "big_bytes", "'x'"],
        ArgType::Any => &["{}", "nil", "string.rep('y', 100000)"],
        ArgType::Func | ArgType::Rest => &[],
    }
}

fn barrage() -> (String, usize) {
    let mut lua = String::from(
        "local big_bytes, big_doubles = {}, {}\n\
         for i = 1, 5000 do big_bytes[i] = i % 256 big_doubles[i] = i end\n\
         local calls, wrong = 0, 0\n\
         local function try(f, ...) calls = calls + 1 pcall(f, ...) end\n\
         local function refused(f, want, ...)\n\
           calls = calls + 1\n\
           local ok, e = pcall(f, ...)\n\
           if ok or not tostring(e):find(want, 1, true) then wrong = wrong + 1 Print('not refused: %s', tostring(e)) end\n\
         end\n",
    );
    let mut calls = 0;
    for spec in registry::all().filter(|f| !SKIPPED.contains(&f.name)) {
        let args: Vec<ArgType> = spec.args.iter().map(|a| a.ty).collect();
        for (i, &ty) in args.iter().enumerate() {
            for bad in hostile(ty) {
                let list: Vec<&str> =
                    args.iter().enumerate().map(|(j, &t)| if i == j { *bad } else { valid(t) }).collect();
                lua += &format!("try({}, {})\n", spec.name, list.join(", "));
                calls += 1;
            }
        }
        // Too few and too many arguments.
        lua += &format!("try({})\n", spec.name);
        calls += 1;
        if let Some(max) = spec.max_args() {
            let want = spec.too_many_args(max + 3);
            lua += &format!("refused({}, {want:?}, {})\n", spec.name, vec!["1"; max + 3].join(", "));
            calls += 1;
        }
    }
    let (random, smoked) = random_calls();
    lua += &random;
    calls += smoked;
    lua += "Print('calls %d, wrong %d', calls, wrong)\n";
    // The core still answers and moves an axis.
    lua += "local start = system_fclk\n\
            Sleep(20)\n\
            assert(system_fclk >= start + 20, 'the core cycles')\n\
            Disable(2) Till(function() return not IsEnabled(2) end)\n\
            Reset(2) ClearAxisLastErr(2) SetRollover(2, 0) SetOpMode(2, 8)\n\
            SetVel(2, 100) SetAcc(2, 1000) SetDec(2, 1000) SetSMTime(2, 0) SetVelScale(2, 100)\n\
            SetSWLL(2, -1e9) SetSWRL(2, 1e9) IgnoreSWL(2, 0) SetBufferMode(2, 0)\n\
            for i = 0, 3 do ReleasePDO(2, 0x6040, 0) ReleasePDO(2, 0x607A, 0) ReleasePDO(2, 0x6060, 0) end\n\
            assert(Enable(2) == 0, string.format('Enable: 0x%08X', GetAxisLastErr(2)))\n\
            local deadline = system_timeInMs + 2000\n\
            Till(function() return IsEnabled(2) or system_timeInMs > deadline end)\n\
            assert(IsEnabled(2), 'axis 2 enables')\n\
            local from = GetPosFb(2)\n\
            assert(MoveRel(2, 5) == 0, string.format('MoveRel: 0x%08X', GetAxisLastErr(2)))\n\
            deadline = system_timeInMs + 3000\n\
            Till(function() return IsInPos(2) or system_timeInMs > deadline end)\n\
            assert(math.abs(GetPosFb(2) - from - 5) < 0.01, 'axis 2 moved 5 mm')\n\
            Print('the core survived')\n";
    (lua, calls)
}

/// Functions the random calls leave out besides `SKIPPED`: the task functions would stop or
/// start this program or others (`StopTask(0)`), `ScanNetwork` restarts the network.
const NOT_RANDOM: &[&str] = &["StartTask", "StartTaskFunc", "StopTask", "ScanNetwork", "SetupGroup", "Till"];

/// Lua that calls every function `ROUNDS` times with values of random types in random
/// counts (a fixed seed: the same calls each run), each error checked to name its function.
fn random_calls() -> (String, usize) {
    const ROUNDS: usize = 5;
    let mut lua = format!("local ROUNDS = {ROUNDS}\n");
    lua.push_str(
        "math.randomseed(36)\n\
         local pool = {nil, true, false, 0, 1, 2, -1, 255, 256, math.maxinteger, math.mininteger, 0.5, -0.0,\n\
           0/0, math.huge, -math.huge, 1e308, '', 'R0', '%d%s%n', '\\0\\255', string.rep('y', 70000),\n\
           {}, {1, 2, 3}, {0/0, 'x'}, big_bytes, function() return true end}\n\
         local function values(n) local t = {} for i = 1, n do t[i] = pool[math.random(1, 27)] end return t end\n\
         local function random(name, f, most)\n\
           for _ = 1, ROUNDS do\n\
             local n = math.random(0, most)\n\
             local ok, e = pcall(f, table.unpack(values(n), 1, n))\n\
             calls = calls + 1\n\
             if not ok and not tostring(e):find(name, 1, true) then wrong = wrong + 1 Print('%s: %s', name, tostring(e)) end\n\
           end\n\
         end\n",
    );
    let mut calls = 0;
    for spec in registry::all().filter(|f| !SKIPPED.contains(&f.name) && !NOT_RANDOM.contains(&f.name)) {
        let most = spec.max_args().unwrap_or(spec.args.len() + 2) + 2;
        let short = spec.name.rsplit('.').next().unwrap_or(spec.name);
        lua += &format!("random({short:?}, {}, {most})\n", spec.name);
        calls += ROUNDS;
    }
    (lua, calls)
}

#[test]
fn every_function_survives_hostile_arguments() {
    let dir = tempfile::tempdir().unwrap();
    let (source, calls) = barrage();
    let path = program(dir.path(), "hostile.lua", &source);
    let out = finish(start_run(&unique_ns("hostile"), &[path.to_str().unwrap()]), std::time::Duration::from_secs(120));
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert!(!out.stderr.contains("panicked"), "{}", out.stderr);
    assert_eq!(
        out.lines_of_task(0),
        vec![format!("calls {calls}, wrong 0"), "the core survived".to_string()],
        "{}",
        out.stderr
    );
}

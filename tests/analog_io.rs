//! End to end: a Lua program uses every function of HMPL ch. 10 on an analog I/O terminal
//! declared in `[[slaves]]` (outputs wired back to inputs), through the running controller:
//! conversion types, raw and converted words in the process data, the manual's error
//! cases, and an output bound to axis 0's velocity feedback that follows it during a move.

mod common;

use common::*;

const MACHINE: &str = "[[axes]]\nname = \"x\"\n\n\
    [[slaves]]\ndevice = \"analog_io\"\ninputs = 3\noutputs = 2\nloopback = true\n\n";

fn run_program(tag: &str, main: &str) -> Vec<String> {
    let dir = tempfile::tempdir().unwrap();
    let program = program(dir.path(), "main.lua", main);
    let toml = format!("{MACHINE}[[tasks]]\nid = 0\nprogram = {:?}\nautorun = true\n", program.display().to_string());
    let config = dir.path().join("machine.toml");
    std::fs::write(&config, toml).unwrap();
    let out = run(&unique_ns(tag), &["--config", config.to_str().unwrap()]);
    let lines = out.lines_of_task(0);
    assert!(lines.last().is_some_and(|l| l == "done"), "{}\n{}", out.stdout, out.stderr);
    lines
}

/// Every setter and getter, the conversion rows of HMPL table 10.1.1 through process data
/// and the loopback, and the codes of docs/decisions.md ("Slave analog I/O").
#[test]
fn a_program_converts_raw_and_engineering_values() {
    let main = r#"
        local A = 1   -- the terminal: slave 0 is axis 0's drive
        -- HMPL 10.1.1 example 1: a raw word, read back as the master sent it and, one frame
        -- later, on the input it is wired to.
        Print("raw %d %d", SetSlvAORaw(A, 1, 0xFFFF), GetSlvAORaw(A, 1))
        Sleep(5)
        Print("looped raw %d type %d", GetSlvAIRaw(A, 1), GetSlvAIType(A, 1))
        -- Example 3: both ends -10..10; 5 V is 49152 (table 10.1.1).
        Print("types %d %d -> %d %d", SetSlvAOType(A, 1, HMPL_DAC_N10_P10), SetSlvAIType(A, 1, HMPL_DAC_N10_P10),
            GetSlvAOType(A, 1), GetSlvAIType(A, 1))
        Print("ao %d %.4f raw %d", SetSlvAO(A, 1, 5), GetSlvAO(A, 1), GetSlvAORaw(A, 1))
        Sleep(5)
        Print("ai %.4f raw %d", GetSlvAI(A, 1), GetSlvAIRaw(A, 1))
        Print("top %d raw %d %.5f", SetSlvAO(A, 1, 10), GetSlvAORaw(A, 1), GetSlvAO(A, 1))
        -- Signed: -16384 is -5 V; the simulator drives input 3, which no output is wired to.
        local signed = HMPL_DAC_SIGNED | HMPL_DAC_N10_P10
        Print("signed %d %d", SetSlvAIType(A, 3, signed), SimSetSlvAIRaw(A, 3, -16384))
        Sleep(5)
        Print("ai3 %d %.4f type %d", GetSlvAIRaw(A, 3), GetSlvAI(A, 3), GetSlvAIType(A, 3))
        Print("4-20 %d %d", SetSlvAIType(A, 3, HMPL_DAC_P4_P20), SimSetSlvAIRaw(A, 3, 32768))
        Sleep(5)
        Print("ai3 %d %.4f", GetSlvAIRaw(A, 3), GetSlvAI(A, 3))
        -- Refusals: out of range, no such type, channel, slave or slot; no conversion type.
        Print("bad %d %d %d %d %d %d %d", SetSlvAO(A, 1, 10.5), SetSlvAOType(A, 1, 8), SetSlvAORaw(A, 3, 0),
            SetSlvAIType(A, 0, 1), SetSlvAORaw(0, 1, 0), SetSlvAORaw(A | HMPL_SLOT_1, 1, 0), SetSlvAORaw(A, 1, 65536))
        Print("no type %d %d %d", SetSlvAO(A, 2, 1), SetSlvAOMonitor(A, 2, HMPL_AXIS_0 | HMPL_VEL_FB), SimSetSlvAIRaw(A, 1, 0))
        local function err(f, ...) local ok, e = pcall(f, ...) return ok and "ok" or e:match("0x0000%x+") end
        Print("get %s %s %s %s", err(GetSlvAI, A, 2), err(GetSlvAO, A, 2), err(GetSlvAIRaw, A, 4), err(GetSlvAIType, 7, 1))
        Print("channels %d %d", GetSlvChNum(A, 3), GetSlvChNum(A, 4))
        -- The manual's reset.
        Print("reset %d %d %d", SetSlvAO(A, 1, 0), SetSlvAOType(A, 1, HMPL_DAC_NONE), SetSlvAIType(A, 1, HMPL_DAC_NONE))
        Print("done")
    "#;
    assert_eq!(
        run_program("aio", main),
        vec![
            "raw 0 65535",
            "looped raw 65535 type 0",
            "types 0 0 -> 1 1",
            "ao 0 5.0000 raw 49152",
            "ai 5.0000 raw 49152",
            "top 0 raw 65535 9.99969",
            "signed 0 0",
            "ai3 -16384 -5.0000 type 257",
            "4-20 0 0",
            "ai3 32768 12.0000",
            "bad 5007 5000 5007 5007 5007 5007 5007",
            "no type 5004 5004 5007",
            "get 0x0000138C 0x0000138C 0x0000138F 0x0000138F",
            "channels 3 2",
            "reset 0 0 0",
            "done",
        ]
    );
}

/// HMPL 10.4: output 2 bound to axis 0's velocity feedback follows it every cycle during a
/// move (AO = vel * scale + offset within one step of the converter); bound, it refuses
/// other writers but a forced PDO value; freed, it keeps its last word and takes writes again.
#[test]
fn a_bound_output_follows_the_velocity_during_a_move() {
    let main = r#"
        local A, axis = 1, 0
        local scale, offset = 0.0125, 0.625
        Print("types %d %d monitor %d param %d", SetSlvAOType(A, 2, HMPL_DAC_N10_P10), SetSlvAIType(A, 2, HMPL_DAC_N10_P10),
            SetSlvAOMonitor(A, 2, HMPL_AXIS_0 | HMPL_VEL_FB), SetSlvAOParam(A, 2, 1, scale, offset))
        Print("bound %d scale %.4f offset %.3f", IsSlvAOBound(A, 2), GetSlvAOScale(A, 2), GetSlvAOOffset(A, 2))
        Print("refused while bound %d %d %d", SetSlvAO(A, 2, 1), SetSlvAORaw(A, 2, 0), SetSlvAOType(A, 2, HMPL_DAC_NONE))
        -- A forced PDO value (HMPL 17.2.8) wins over the binding until released.
        local forced = ForceWritePDO(A, 0x6411, 2, 1234)
        Sleep(5)
        Print("forced %d raw %d released %d", forced, GetSlvAORaw(A, 2), ReleasePDO(A, 0x6411, 2))
        Sleep(5)
        Print("at rest %.4f", GetSlvAO(A, 2))
        Enable(axis) Till(function() return IsEnabled(axis) end)
        SetVel(axis, 200)
        MoveRel(axis, 100)
        -- A sample counts when the velocity read before and after the output is the same
        -- (both from one snapshot, or the velocity did not change between them).
        local samples, worst, peak, looped = 0, 0, 0, 0
        while IsMoving(axis) do
            local v = GetVelFb(axis)
            local ao = GetSlvAO(A, 2)
            if GetVelFb(axis) == v then
                samples = samples + 1
                worst = math.max(worst, math.abs(ao - (v * scale + offset)))
                peak = math.max(peak, ao)
            end
            if math.abs(GetSlvAI(A, 2) - (200 * scale + offset)) < 0.01 then looped = looped + 1 end
        end
        -- Each fact prints its number when it does not hold.
        Print("samples %s, worst %s, peak %.1f, input 2 %s", samples > 100 and "over 100" or samples,
            worst <= 20 / 65536 and "within a step" or string.format("%.6f", worst), peak,
            looped > 10 and "looped back" or looped)
        Till(function() return IsInPos(axis) end)
        Sleep(5)
        Print("stopped %.4f", GetSlvAO(A, 2))
        Print("freed %d bound %d write %d %.4f", SetSlvAOParam(A, 2, 0, 2, 1), IsSlvAOBound(A, 2), SetSlvAO(A, 2, -2.5), GetSlvAO(A, 2))
        Print("kept scale %.1f offset %.1f; bind again %d", GetSlvAOScale(A, 2), GetSlvAOOffset(A, 2), SetSlvAOParam(A, 2, 1, 1, 0))
        Print("bad %d %d %d", SetSlvAOMonitor(A, 2, HMPL_AXIS_1 | HMPL_REF_POS), SetSlvAOMonitor(A, 2, 0x800),
            SetSlvAOParam(A, 2, 2, 1, 0))
        Print("done")
    "#;
    assert_eq!(
        run_program("aiomon", main),
        vec![
            "types 0 0 monitor 0 param 0",
            "bound 1 scale 0.0125 offset 0.625",
            "refused while bound 5004 5004 5004",
            "forced 0 raw 1234 released 0",
            "at rest 0.6250",
            "samples over 100, worst within a step, peak 3.1, input 2 looped back",
            "stopped 0.6250",
            "freed 0 bound 0 write 0 -2.5000",
            "kept scale 2.0 offset 1.0; bind again 0",
            "bad 5007 5000 5007",
            "done",
        ]
    );
}

/// Hostile arguments on a machine that has the terminal, so that they reach ch. 10's own
/// checks rather than stopping at "no such slave": NaN, infinities, huge and negative
/// numbers in every argument of every function (as `tests/hostile_input.rs` does for the
/// whole registry). Each call comes back; afterwards the terminal still converts, and an
/// output bound with a huge offset saturates at the range's top.
#[test]
fn hostile_arguments_reach_the_terminal_and_are_refused() {
    use api::registry::{self, ArgType};
    let mut lua = String::from("local A = 1\nlocal calls, accepted = 0, {}\n");
    lua += "local function try(call, f, ...) calls = calls + 1 local ok, rc = pcall(f, ...) ";
    lua += "if ok and rc == 0 then accepted[#accepted + 1] = call end end\n";
    let chapter_10 = registry::all().filter(|f| f.manual.starts_with("HMPL 10.") || f.name == "SimSetSlvAIRaw");
    let mut functions = 0;
    for spec in chapter_10 {
        functions += 1;
        // Valid: the terminal, channel 1, HMPL_DAC_N10_P10, and numbers that fit it.
        let valid = |i: usize| if i == 0 { "A" } else { "1" };
        for (i, arg) in spec.args.iter().enumerate() {
            let bad: &[&str] = match arg.ty {
                ArgType::Int => &["-1", "99", "0x7FFFFFFF", "math.mininteger", "math.maxinteger", "1.5", "0/0"],
                ArgType::Double => &["0/0", "math.huge", "-math.huge", "1e308", "-1e308"],
                other => panic!("{}: a {other:?} argument", spec.name),
            };
            for bad in bad {
                let args: Vec<&str> = (0..spec.args.len()).map(|j| if i == j { *bad } else { valid(j) }).collect();
                let call = format!("{}({})", spec.name, args.join(", "));
                lua += &format!("try({call:?}, {}, {})\n", spec.name, args.join(", "));
            }
        }
    }
    lua += r#"
        Print("functions %d, calls %d, accepted: %s", FUNCTIONS, calls, table.concat(accepted, " "))
        Print("still %d %d %.4f", SetSlvAOType(A, 1, HMPL_DAC_N10_P10), SetSlvAO(A, 1, 5), GetSlvAO(A, 1))
        Print("saturated %d %d %.5f", SetSlvAOMonitor(A, 1, HMPL_AXIS_0 | HMPL_REF_POS), SetSlvAOParam(A, 1, 1, 1e308, 1e308),
            (function() Sleep(5) return GetSlvAO(A, 1) end)())
        Print("done")
    "#;
    let lua = lua.replace("FUNCTIONS", &functions.to_string());
    assert_eq!(
        run_program("aiohostile", &lua),
        vec![
            // -1 (0xFFFF given signed) and 99 are words an output takes; the simulator cannot
            // drive input 1, which is wired to output 1.
            "functions 16, calls 281, accepted: SetSlvAORaw(A, 1, -1) SetSlvAORaw(A, 1, 99)",
            "still 0 0 5.0000",
            "saturated 0 0 9.99969",
            "done",
        ]
    );
}

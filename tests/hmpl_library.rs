//! End to end: the HMPL library a program calls for itself (HMPL ch. 2, 3, 4, 17.3, 19)
//! beyond what the reference scripts print: the runtime errors that end a task as the
//! system's last error, the controller variables by HCV id, the pins as expressions, and
//! the strings' and memory's limits.

mod common;

use std::path::{Path, PathBuf};

use common::*;

/// A machine file in `dir`: three axes, task 0 runs `main`, tasks 1.. run `others`.
fn machine(dir: &Path, main: &str, others: &[&str]) -> PathBuf {
    let mut toml = String::from("[[axes]]\n[[axes]]\n[[axes]]\n");
    for (id, source) in std::iter::once(&main).chain(others).enumerate() {
        let path = program(dir, &format!("task{id}.lua"), source);
        toml += &format!("[[tasks]]\nid = {id}\nprogram = {:?}\nautorun = {}\n", path.display().to_string(), id == 0);
    }
    toml += "[identity]\nmodel = \"HIMC-A-E00\"\nserial = \"SN 0042\"\n";
    let path = dir.join("machine.toml");
    std::fs::write(&path, toml).unwrap();
    path
}

fn run_main(main: &str, others: &[&str]) -> Finished {
    let dir = tempfile::tempdir().unwrap();
    let config = machine(dir.path(), main, others);
    run(&unique_ns("lib"), &["--config", config.to_str().unwrap()])
}

/// HMPL 18.2 with 2.22: a runtime error ends the task and is the system's last error,
/// whichever kind it is: a mutex locked twice (0x13EC), an endless recursion (0x138A
/// stack overflow), any other Lua error (0x1770 execution failed).
#[test]
fn a_runtime_error_that_ends_a_task_is_the_systems_last_error() {
    let main = r#"
        for task = 1, 3 do
          assert(StartTask(task) == 0)
          Till(function() return IsTaskStop(task) end)
          Print("task %d ended: 0x%04X", task, GetSystemLastErr())
        end
    "#;
    let twice = "MutexLock(3)\nMutexLock(3)\nPrint('never printed')\n";
    let recursion = "local function f(n) return 1 + f(n + 1) end\nf(1)\n";
    let lua_error = "error('a plain Lua error')\n";
    let out = run_main(main, &[twice, recursion, lua_error]);
    assert_eq!(
        out.lines_of_task(0),
        vec!["task 1 ended: 0x13EC", "task 2 ended: 0x138A", "task 3 ended: 0x1770"],
        "{}\n{}",
        out.stdout,
        out.stderr
    );
    assert!(!out.stdout.contains("never printed"));
}

/// HMPL 17.3: the manual's examples (axis 2's and axis 0's software right limit), the
/// system variables, group variables, and the manual's codes for what luamotion lacks.
#[test]
fn controller_variables_by_hcv_id() {
    let main = r#"
        SetSWRL(2, 123.5)
        local SW_RL, result = GetConfigVar(0x83020065)
        Print("axis 2 SW_RL = %f, result %d", SW_RL, result)
        Print("SetConfigVar(0x83000065, 0.0) = %d", SetConfigVar(0x83000065, 0.0))
        Print("SW_RL = %f", GetConfigVar(0x83000065))
        Print("signed id: %f", GetConfigVar(0x83000065 - (1 << 32)))
        system_dtest3 = 2.5
        set = SetConfigVar(0x2331, 7)
        Print("dtest3 %g, ltest9 after set %d: %d", GetConfigVar(0x235D), set, system_ltest9)
        Print("ltest0 = 1.5: 0x%04X", SetConfigVar(0x2328, 1.5))
        Print("fclk counts: %s", tostring(GetConfigVar(0x012C) > 0))
        Print("fclk is read-only: 0x%04X", SetConfigVar(0x012C, 1))
        Print("last_err is read-only: 0x%04X", SetConfigVar(0x83000263, 0))
        Print("user table: 0x%04X, value %g result %d", SetConfigVar(0x07D0, 1), GetConfigVar(0x07D0))
        Print("axis 9: result %d", select(2, GetConfigVar(0x83090065)))
        Print("vel_scale 150: 0x%08X", SetConfigVar(0x830000DB, 150))
        local set = SetConfigVar(0x820000DD, 250)
        Print("group 0 vel %g after %d", GetConfigVar(0x820000DD), set)
        Print("group 0 buffer mode 2.5: 0x%04X", SetConfigVar(0x820000F2, 2.5))
        set = SetConfigVar(0x830100A0, 1)
        Print("homed %g after %d", GetConfigVar(0x830100A0), set)
    "#;
    let out = run_main(main, &[]);
    assert_eq!(
        out.lines_of_task(0),
        vec![
            "axis 2 SW_RL = 123.500000, result 0",
            "SetConfigVar(0x83000065, 0.0) = 0",
            "SW_RL = 0.000000",
            "signed id: 0.000000",
            "dtest3 2.5, ltest9 after set 0: 7",
            "ltest0 = 1.5: 0x0004",
            "fclk counts: true",
            "fclk is read-only: 0x0003",
            "last_err is read-only: 0x0003",
            "user table: 0x0001, value 0 result -1",
            "axis 9: result -1",
            "vel_scale 150: 0x8300017C",
            "group 0 vel 250 after 0",
            "group 0 buffer mode 2.5: 0x0004",
            "homed 1 after 0",
        ],
        "{}\n{}",
        out.stdout,
        out.stderr
    );
}

/// HMPL 19.4, 19.5: the pins as expressions, `HIMC_GPO(1) = HIMC_GPI(4) && HIMC_GPI(6)`.
#[test]
fn pins_as_expressions() {
    let main = r#"
        SimSetGPI(4, 1) SimSetGPI(6, 0)
        Sleep(5)
        HIMC_GPO[1] = HIMC_GPI(4) and HIMC_GPI(6)
        Print("in 4 %s, in 6 %s: out 1 %s", tostring(HIMC_GPI[4]), tostring(HIMC_GPI[6]), tostring(HIMC_GPO[1]))
        SimSetGPI(6, 1)
        Sleep(5)
        HIMC_GPO[1] = HIMC_GPI(4) and HIMC_GPI(6)
        Print("both on: out 1 %s, GetGPO(1) %d", tostring(HIMC_GPO(1)), GetGPO(1))
        HIMC_GPO[2] = 1
        HIMC_GPO[2] = 0
        Print("out 2 set by numbers: %s", tostring(HIMC_GPO[2]))
        Print("%s", select(2, pcall(function() return HIMC_GPI[9] end)))
        Print("%s", select(2, pcall(function() HIMC_GPI[1] = true end)))
        Print("%s", select(2, pcall(function() HIMC_GPO[0] = true end)))
    "#;
    let out = run_main(main, &[]);
    let lines = out.lines_of_task(0);
    let context = format!("{}\n{}", out.stdout, out.stderr);
    assert_eq!(
        lines[..3],
        ["in 4 true, in 6 false: out 1 false", "both on: out 1 true, GetGPO(1) 1", "out 2 set by numbers: false"],
        "{context}"
    );
    assert!(lines[3].ends_with("HIMC_GPI[9]: the pins are 1..8 (0x138F)"), "{context}");
    assert!(lines[4].ends_with("HIMC_GPI is read-only: inputs are set by what is wired to them"), "{context}");
    assert!(lines[5].ends_with("HIMC_GPO[0]: the pins are 1..8 (0x138F)"), "{context}");
}

/// HMPL 3.1, 3.14-3.16, 2.14, 2.15: the 512-character limit on every function that makes a
/// string, C's view of a string (up to its first NUL), the memory functions' bounds and
/// element types, and the machine file's identity.
#[test]
fn strings_memory_and_identity_keep_their_limits() {
    let main = r#"
        local long = string.rep("a", 512)
        Print("copy 512: %d %d", StringCopy(long), StringLen(select(2, StringCopy(long))))
        Print("copy 513: 0x%04X", StringCopy(long .. "b"))
        Print("cat: 0x%04X, ex: 0x%04X", StringCat(long, "b"), StringCatEx(long, "xb", 1, 1))
        Print("print: %d", StringPrint("%s!", long))
        Print("copyex past the end: 0x%04X, length past it: %s", StringCopyEx("abc", 4, 1), select(2, StringCopyEx("abc", 1, 99)))
        Print("NUL ends a string: %d %s", StringLen("ab\0cd"), tostring(IsStringEqual("ab\0x", "ab")))
        Print("strchr of NUL: %d, of 104: %d", StrFindChar("hello", 0), StrFindChar("hello", 104))
        local rc, d = MemorySet({1.5, 2.5}, 0xFF, 8)
        Print("doubles: rc %d, %s, NaN %s, %g", rc, math.type(d[1]), tostring(d[1] ~= d[1]), d[2])
        rc, d = MemoryCopy({0, 0}, {1.0}, 8)
        Print("a double into two ints: %d %d (0x%08X)", rc, d[1], d[2])
        rc, d = MemoryCopy({0, 0}, {1, 2, 3}, 12)
        Print("past the destination: 0x%04X, kept %d %d", rc, d[1], d[2])
        Print("negative count: 0x%04X", (MemorySet({1}, 0, -1)))
        Print("equal past the end: %s", tostring(IsMemoryEqual({1}, {1}, 8)))
        Print("%s", select(2, pcall(MemorySet, {1 << 40}, 0, 4)))
        Print("model %s, serial %s", select(2, GetModelNum()), select(2, GetSerialNum()))
    "#;
    let out = run_main(main, &[]);
    let lines = out.lines_of_task(0);
    let context = format!("{}\n{}", out.stdout, out.stderr);
    let want = [
        "copy 512: 0 512",
        "copy 513: 0x138D",
        "cat: 0x138D, ex: 0x138D",
        "print: -1",
        "copyex past the end: 0x138F, length past it: bc",
        "NUL ends a string: 2 true",
        "strchr of NUL: 5, of 104: 0",
        "doubles: rc 0, float, NaN true, 2.5",
        "a double into two ints: 0 0 (0x3FF00000)",
        "past the destination: 0x138B, kept 0 0",
        "negative count: 0x138F",
        "equal past the end: false",
    ];
    assert_eq!(lines[..want.len()], want, "{context}");
    assert!(lines[want.len()].contains("1099511627776 does not fit a C int"), "{context}");
    assert_eq!(lines[want.len() + 1], "model HIMC-A-E00, serial SN 0042", "{context}");
}

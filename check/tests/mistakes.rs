//! Typical mistakes in luamotion programs, one row each: the program, the code the check
//! gives it, and the line and column it points at. Each row's program has that one
//! mistake; the rest of it is right.

use check::{Checker, Options};

/// (what, program, code, line, column)
const MISTAKES: &[(&str, &str, &str, usize, usize)] = &[
    // Unknown API names and constants, with the registry's nearest.
    ("a long name for MoveAbs", "MoveAbsolute(0, 10)", "E101", 1, 1),
    ("a misspelled constant", "local mode = BM_LOOKAHAED", "E101", 1, 14),
    ("the wrong case", "enable(0)", "E101", 1, 1),
    ("swapped letters", "Enabel(0)", "E101", 1, 1),
    ("a DXMC name of another controller", "MC_MoveAbsolute(0, 10)", "E101", 1, 1),
    ("a misspelled error id", "if GetAxisLastErr(0) & 0xFFFF == eERR_AXIS_CMD_INVALID_PAROM then end", "E101", 1, 34),
    ("a misspelled home method", "SetHomeMethod(0, HOME_METHOD_35)", "E101", 1, 18),
    ("a FreePort member that does not exist", "FreePort.Eth.Send(1, 'x')", "E101", 1, 14),
    ("an unknown call inside a function", "local function go()\n  MoveAbsolut(0, 1)\nend", "E101", 2, 3),
    ("an unknown call in a Till condition", "Till(function() return IsInPosition(0) end)", "E101", 1, 24),
    // Argument counts.
    ("a position left out", "MoveAbs(0)", "E102", 1, 8),
    ("a velocity too many", "MoveAbs(0, 10, 50)", "E102", 1, 8),
    ("no axis at all", "Enable()", "E102", 1, 7),
    ("an axis where none is taken", "TimerInit(0)", "E102", 1, 10),
    ("SDO without its length", "ReadSDO(1, 0x6041, 0)", "E102", 1, 8),
    ("Sleep without a time", "Sleep()", "E102", 1, 6),
    ("a count error on the second line", "Enable(0)\nMoveRel(0)", "E102", 2, 8),
    ("a count error in an argument", "Print('%f', GetPosFb())", "E102", 1, 21),
    // Literal types.
    ("a string for a position", "MoveAbs(0, 'ten')", "E103", 1, 12),
    ("a float axis id", "Enable(0.5)", "E103", 1, 8),
    ("a boolean axis id", "Enable(true)", "E103", 1, 8),
    ("nil for a velocity", "MoveVel(0, nil)", "E103", 1, 12),
    ("a table for an axis", "Enable({0})", "E103", 1, 8),
    ("a string for an SDO index", "ReadSDO(1, '0x6041', 0, 2)", "E103", 1, 12),
    ("a function for a task's function name", "StartTaskFunc(1, function() end)", "E103", 1, 18),
    ("a string for a GPO", "SetGPO('1', 1)", "E103", 1, 8),
    ("a number for a timer", "TON(1, true, 100)", "E103", 1, 5),
    ("a string for the user table's data", "SetUserTable(0, 1, 'data')", "E103", 1, 20),
    // Callbacks.
    ("Till given the value of its condition", "Till(IsInPos(0))", "E104", 1, 6),
    ("Till given a boolean", "Till(true)", "E104", 1, 6),
    ("Till given a number", "Till(1)", "E104", 1, 6),
    ("Till given a string", "Till('IsInPos(0)')", "E104", 1, 6),
    ("the ASCII agent given a table", "START_ASCII_AGENT({})", "E104", 1, 19),
    // The sandbox.
    ("io", "local f = io.open('log.txt', 'w')", "E105", 1, 11),
    ("os.time", "local t0 = os.time()", "E105", 1, 12),
    ("os.exit", "os.exit(1)", "E105", 1, 1),
    ("dofile", "dofile('other.lua')", "E105", 1, 1),
    ("a module that is not in the project", "local util = require('no_such_module')", "E105", 1, 22),
    ("a module name with a path", "local util = require('../util')", "E105", 1, 22),
    ("bytecode", "local chunk = ...\nlocal f = load(chunk, 'x', 'b')", "E105", 2, 28),
    ("the debug library", "debug.sethook()", "E105", 1, 1),
    // Return codes compared with booleans.
    ("a code compared with true", "if MoveAbs(0, 10) == true then end", "W201", 1, 22),
    ("a code compared with false", "if Enable(0) ~= false then end", "W201", 1, 17),
    ("false first", "if false == Disable(0) then end", "W201", 1, 4),
    // Read-only names of the API.
    ("an assignment to the cycle counter", "system_fclk = 0", "E106", 1, 1),
    ("an API function overwritten", "MoveAbs = nil", "E106", 1, 1),
    ("an API function defined again", "function Enable(axis) end", "E106", 1, 10),
    ("a constant overwritten", "PI = 3", "E106", 1, 1),
    ("an error id overwritten", "eERR_AXIS_CMD_INVALID_PARAMETER = 0", "E106", 1, 1),
    // Globals never set.
    ("a global read before any is set", "Print('%d', counter)", "W202", 1, 13),
    // Not Lua.
    ("a C-style comment", "// move\nMoveAbs(0, 1)", "E100", 1, 1),
    ("a backtick, which Lua has no use for", "local s = `text`", "E100", 1, 1),
    ("a missing end", "if IsEnabled(0) then\n  MoveAbs(0, 1)\n", "E100", 3, 1),
];

#[test]
fn each_mistake_is_caught_where_it_is() {
    let checker = Checker::new(Options::default());
    let folder = tempfile::tempdir().unwrap();
    let mut wrong = Vec::new();
    let mut rows = 0;
    for (what, program, code, line, column) in MISTAKES {
        rows += 1;
        let found = checker.check_source("t.lua", program, Some(folder.path()));
        let got: Vec<(&str, usize, usize)> = found.iter().map(|d| (d.code, d.line, d.column)).collect();
        if got != [(*code, *line, *column)] {
            let shown: String = found.iter().map(|d| d.render(program)).collect();
            wrong.push(format!("{what}: {program:?}\n  expected {code} at {line}:{column}, got {got:?}\n{shown}"));
        }
    }
    assert!(rows >= 40, "the table has {rows} rows");
    assert!(wrong.is_empty(), "{} of {rows} rows wrong:\n{}", wrong.len(), wrong.join("\n"));
}

//! Input no program has: nesting deeper than Lua allows, chains its parser recurses on,
//! and any text at all. The check answers each with findings, never a crash.

use check::{Checker, Options};
use proptest::prelude::*;

fn codes(source: &str) -> Vec<&'static str> {
    Checker::new(Options::default()).check_source("t.lua", source, None).iter().map(|d| d.code).collect()
}

/// Each row: a program past Lua's 200 levels (lua5.4 says "C stack overflow" to each),
/// and one just inside that the check takes as Lua.
#[test]
fn nesting_past_lua_s_levels_is_a_syntax_error_not_a_crash() {
    let deep = |open: &str, close: &str, n: usize| format!("local x = {}1{}", open.repeat(n), close.repeat(n));
    for (what, program, expected) in [
        ("100 000 parentheses", deep("(", ")", 100_000), vec!["E100"]),
        ("300 nested tables", deep("{", "}", 300), vec!["E100"]),
        ("a chain of 50 000 concatenations", format!("local x = 1{}", " .. 1".repeat(50_000)), vec!["E100"]),
        ("100 000 nots", format!("local x = {}true", "not ".repeat(100_000)), vec!["E100"]),
        ("blocks 10 000 deep", format!("{}{}", "do ".repeat(10_000), "end ".repeat(10_000)), vec!["E100"]),
        ("150 nested ifs", format!("{}{}", "if true then ".repeat(150), "end ".repeat(150)), vec![]),
        ("50 nested parentheses", deep("(", ")", 50), vec![]),
    ] {
        assert_eq!(codes(&program), expected, "{what}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Any text: findings, no panic.
    #[test]
    fn any_text_is_answered(source in "\\PC{0,200}") {
        let _ = codes(&source);
    }

    /// Text made of Lua's own pieces, closer to a program being typed.
    #[test]
    fn lua_pieces_are_answered(pieces in proptest::collection::vec(
        prop::sample::select(vec!["MoveAbs", "(", ")", "0", ",", "10", "local", "x", "=", "function", "end",
            "Till", "IsInPos", "if", "then", "..", "\"s\"", "{", "}", "[", "]", "not", "return", "io", ".", ":"]),
        0..60,
    )) {
        let _ = codes(&pieces.join(" "));
    }
}

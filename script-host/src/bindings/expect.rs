//! The expectations of `luamotion test` programs (`expect_eq`, `expect_near`,
//! `expect_true`). As gtest's EXPECT_*, a failed one is said where it failed and the
//! program goes on, so one run shows every failure of a file; the program fails when it
//! ends (docs/decisions.md, "luamotion test").

use std::borrow::Cow;
use std::cell::Cell;

use api::{FunctionSpec, LocalCall};
use mlua::{IntoLuaMulti, Lua, MultiValue, Value};

use super::{Host, LuaArg, write_output};

/// The expectations a program checked, and how many of them failed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    pub checked: u32,
    pub failed: u32,
}

/// Counts one expectation; a failed one prints `file:line: <function> failed: <why>[ (<message>)]`,
/// the line `luamotion test` reports.
fn record(
    lua: &Lua,
    tally: &Cell<Tally>,
    spec: &FunctionSpec,
    held: bool,
    why: impl FnOnce() -> String,
    message: Option<String>,
) -> bool {
    let mut t = tally.get();
    t.checked += 1;
    if !held {
        t.failed += 1;
        let message = message.map(|m| format!(" ({m})")).unwrap_or_default();
        let line = format!("{}{} failed: {}{message}", crate::sandbox::raised_at(lua), spec.name, why());
        write_output(&[line.as_bytes()]);
    }
    tally.set(t);
    held
}

/// The optional message as text.
fn message(message: Option<Cow<[u8]>>) -> Option<String> {
    message.map(|m| String::from_utf8_lossy(&m).into_owned())
}

/// A value as a failure shows it: strings quoted, floats with their point (`100.0`).
fn shown(v: &Value) -> String {
    match v {
        Value::Nil => "nil".into(),
        Value::Boolean(b) => b.to_string(),
        Value::Integer(n) => n.to_string(),
        Value::Number(n) => format!("{n:?}"),
        Value::String(s) => format!("{:?}", s.to_string_lossy()),
        other => other.type_name().to_string(),
    }
}

/// The functions of `Local` that belong here.
pub fn call(lua: &Lua, host: &Host, call: LocalCall<'_, LuaArg>) -> mlua::Result<MultiValue> {
    let spec = call.func().spec();
    host.beat();
    match call {
        LocalCall::expect_eq { actual, expected, message: text } => {
            let (actual, expected) = (actual.value, expected.value);
            let held = actual.equals(&expected)?;
            let why = || format!("got {}, expected {}", shown(&actual), shown(&expected));
            record(lua, &host.tally, spec, held, why, message(text)).into_lua_multi(lua)
        }
        LocalCall::expect_near { actual, expected, tolerance, message: text } => {
            // Written so that a NaN anywhere fails.
            let held = (actual - expected).abs() <= tolerance;
            let why =
                || format!("got {actual:?}, expected {expected:?} ± {tolerance:?} (off by {:?})", actual - expected);
            record(lua, &host.tally, spec, held, why, message(text)).into_lua_multi(lua)
        }
        LocalCall::expect_true { value, message: text } => {
            let held = super::is_true(&value.value);
            let why = || format!("got {}", shown(&value.value));
            record(lua, &host.tally, spec, held, why, message(text)).into_lua_multi(lua)
        }
        other => unreachable!("{} is no expectation", other.func().spec().name),
    }
}

/// After the program: an error naming how many expectations failed, if any did.
pub fn verdict(host: &Host, program: &str) -> mlua::Result<()> {
    let Tally { checked, failed } = host.tally.get();
    if failed == 0 {
        return Ok(());
    }
    let plural = if checked == 1 { "" } else { "s" };
    Err(mlua::Error::runtime(format!("{program}: {failed} of {checked} expectation{plural} failed")))
}

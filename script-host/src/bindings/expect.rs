//! The expectations of `luamotion test` programs (`expect_eq`, `expect_near`,
//! `expect_true`). As gtest's EXPECT_*, a failed one is said where it failed and the
//! program goes on, so one run shows every failure of a file; the program fails when it
//! ends (docs/decisions.md, "luamotion test").

use std::cell::Cell;
use std::rc::Rc;

use api::{FunctionSpec, Local};
use mlua::{Function, Lua, MultiValue, Value};

use super::{Host, binding, double_arg, lua_string_arg, write_output};

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

/// The optional message, argument `i`.
fn message_arg(lua: &Lua, spec: &FunctionSpec, args: &MultiValue, i: usize) -> mlua::Result<Option<String>> {
    match args.get(i) {
        None | Some(Value::Nil) => Ok(None),
        Some(_) => Ok(Some(lua_string_arg(lua, spec, args, i)?.to_string_lossy())),
    }
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

pub fn local(lua: &Lua, host: Rc<Host>, local: Local) -> mlua::Result<Function> {
    let spec = local.spec();
    match local {
        Local::expect_eq => binding(lua, spec, move |lua, args| {
            host.beat();
            let actual = args.front().cloned().unwrap_or(Value::Nil);
            let expected = args.get(1).cloned().unwrap_or(Value::Nil);
            let message = message_arg(lua, spec, &args, 2)?;
            let held = actual.equals(&expected)?;
            let why = || format!("got {}, expected {}", shown(&actual), shown(&expected));
            Ok(record(lua, &host.tally, spec, held, why, message))
        }),
        Local::expect_near => binding(lua, spec, move |lua, args| {
            host.beat();
            let actual = double_arg(lua, spec, &args, 0)?;
            let expected = double_arg(lua, spec, &args, 1)?;
            let tolerance = double_arg(lua, spec, &args, 2)?;
            let message = message_arg(lua, spec, &args, 3)?;
            // Written so that a NaN anywhere fails.
            let held = (actual - expected).abs() <= tolerance;
            let why =
                || format!("got {actual:?}, expected {expected:?} ± {tolerance:?} (off by {:?})", actual - expected);
            Ok(record(lua, &host.tally, spec, held, why, message))
        }),
        Local::expect_true => binding(lua, spec, move |lua, args| {
            host.beat();
            let value = args.front().cloned().unwrap_or(Value::Nil);
            let message = message_arg(lua, spec, &args, 1)?;
            let held = super::locals::is_true(&value);
            Ok(record(lua, &host.tally, spec, held, || format!("got {}", shown(&value)), message))
        }),
        other => unreachable!("{} is no expectation", other.spec().name),
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

//! The Lua VM a user program runs in: Lua 5.4 with base, table, string, math, coroutine
//! and utf8 only (no io, os, package, debug), text chunks only, and a memory limit. The
//! script process adds a `require` that reads modules from the program's own folder only
//! (`crate::require`).
//!
//! Errors read as Lua's own interpreter writes them: every uncaught error says where it was
//! raised (`file:line: message`, also for `error({})` and `error()`), and an API
//! function's error caught by `pcall` is its message, not an mlua error object whose text
//! carries a whole traceback.

use mlua::{Function, Lua, LuaOptions, MultiValue, StdLib, Value};

/// The chunk name of the sandbox's own Lua functions; positions in them are no program's.
const INTERNAL: &str = "=[luamotion]";

/// Where `call_program` finds the VM's own `xpcall` and message handler.
const RUNNER: &str = "luamotion.runner";

/// A VM with the sandbox's libraries and `load`, its memory limited to
/// `memory_limit_bytes`; the API is bound into it later.
pub fn new_vm(memory_limit_bytes: usize) -> mlua::Result<Lua> {
    let libs = StdLib::TABLE | StdLib::STRING | StdLib::MATH | StdLib::COROUTINE | StdLib::UTF8;
    let lua = Lua::new_with(libs, LuaOptions::new())?;
    lua.set_memory_limit(memory_limit_bytes)?;
    let globals = lua.globals();
    // The base library can read files; a program reaches nothing outside its VM.
    for name in ["dofile", "loadfile"] {
        globals.raw_set(name, Value::Nil)?;
    }
    // Precompiled chunks can crash the VM: `load` takes source text only. Lua 5.4 gives the
    // chunk the `env` argument as `_ENV` if there is one (even nil), else the globals.
    let load: Function = globals.get("load")?;
    let text_only = lua.create_function(move |_, args: MultiValue| {
        let mut args = args.into_iter();
        let (chunk, name) = (args.next().unwrap_or(Value::Nil), args.next().unwrap_or(Value::Nil));
        match args.nth(1) {
            Some(env) => load.call::<MultiValue>((chunk, name, "t", env)),
            None => load.call::<MultiValue>((chunk, name, "t")),
        }
    })?;
    globals.raw_set("load", text_only)?;
    // The VM's own, whatever a program assigns to the global.
    let tostring: Function = globals.get("tostring")?;
    let runner: Function = lua
        .load("local handler, xpcall = ..., xpcall return function(f) return xpcall(f, handler) end")
        .set_name(INTERNAL)
        .call(lua.create_function(move |lua, error| on_uncaught_error(lua, &tostring, error))?)?;
    lua.set_named_registry_value(RUNNER, runner)?;
    crate::arming::track_coroutines(&lua)?;
    plain_caught_errors(&lua)?;
    Ok(lua)
}

/// Runs a program's function (its main chunk, its entry) to its end. An error comes back
/// with the position it was raised at and a traceback (`message\nstack traceback:...`).
pub fn call_program(lua: &Lua, function: &Function) -> mlua::Result<()> {
    let runner: Function = lua.named_registry_value(RUNNER)?;
    match runner.call::<(bool, Value)>(function)? {
        (true, _) => Ok(()),
        (false, Value::Error(error)) => Err(*error),
        // The handler did not run: Lua raises memory errors without it.
        (false, Value::String(s)) if s == "not enough memory" => Err(mlua::Error::MemoryError(s.to_string_lossy())),
        (false, other) => Err(mlua::Error::runtime(other.to_string()?)),
    }
}

/// What an error says, without mlua's wrappers and the traceback.
pub fn message(error: &mlua::Error) -> String {
    match root_cause(error) {
        mlua::Error::RuntimeError(text) => text.split("\nstack traceback:").next().unwrap_or_default().to_string(),
        other => other.to_string(),
    }
}

/// The error an error really is, below mlua's wrappers.
pub fn root_cause(error: &mlua::Error) -> &mlua::Error {
    match error {
        mlua::Error::CallbackError { cause, .. } => root_cause(cause),
        mlua::Error::WithContext { cause, .. } => root_cause(cause),
        other => other,
    }
}

/// The message handler of a program's uncaught errors (as `msghandler` in Lua's `lua.c`):
/// a value that is no string becomes one, with the position of the function that raised
/// it; the traceback is added. Errors of Rust functions (mlua error objects) stay whole.
fn on_uncaught_error(lua: &Lua, tostring: &Function, error: Value) -> mlua::Result<Value> {
    let message = match error {
        Value::Error(_) => return Ok(error),
        Value::String(s) => s.to_string_lossy(),
        other => format!("{}{}", raised_at(lua), error_object_text(tostring, &other)),
    };
    let traceback = lua.traceback(None, 1).map(|t| t.to_string_lossy()).unwrap_or_default();
    Ok(Value::Error(Box::new(mlua::Error::RuntimeError(format!("{message}\n{traceback}")))))
}

/// `file:line: ` of the innermost program function on the stack that called the running
/// one (`error`, `pcall` and the API functions are C functions and have no line; the
/// sandbox's own wrappers are skipped).
pub fn raised_at(lua: &Lua) -> String {
    (1..)
        .map_while(|level| {
            lua.inspect_stack(level, |d| {
                let line = d.current_line()?;
                let file = d.source().short_src.filter(|f| *f != INTERNAL[1..])?;
                Some(format!("{file}:{line}: "))
            })
        })
        .flatten()
        .next()
        .unwrap_or_default()
}

/// An error value that is no string, as text: its `__tostring` if it has one that works.
fn error_object_text(tostring: &Function, value: &Value) -> String {
    let has_tostring = match value {
        Value::Table(t) => t.metatable().is_some_and(|m| m.raw_get::<Value>("__tostring").is_ok_and(|f| !f.is_nil())),
        Value::Integer(_) | Value::Number(_) => true,
        _ => false,
    };
    let kind = value.type_name();
    if !has_tostring {
        return format!("(error object is a {kind} value)");
    }
    match tostring.call::<mlua::LuaString>(value) {
        Ok(text) => text.to_string_lossy(),
        Err(e) => format!("(error object is a {kind} value whose __tostring failed: {})", message(&e)),
    }
}

/// `pcall`, `xpcall`, `coroutine.resume` and `coroutine.close` hand a program an API
/// function's error as its message, the string `file:line: ...` a Lua error would be.
/// Lua functions wrap Lua's own, so that a coroutine can still yield inside `pcall`.
fn plain_caught_errors(lua: &Lua) -> mlua::Result<()> {
    let plain = lua.create_function(|lua, error: Value| {
        Ok(match error {
            Value::Error(error) => match root_cause(&error) {
                // The controller being gone ends the program: kept whole for `describe`.
                mlua::Error::ExternalError(_) | mlua::Error::MemoryError(_) => Value::Error(error),
                _ => Value::String(lua.create_string(message(&error))?),
            },
            other => other,
        })
    })?;
    lua.load(
        r#"
        local plain = ...
        local raw_pcall, raw_xpcall, raw_resume, raw_close = pcall, xpcall, coroutine.resume, coroutine.close
        local function caught(ok, ...)
            if ok then return true, ... end
            return false, plain((...))
        end
        pcall = function(f, ...) return caught(raw_pcall(f, ...)) end
        xpcall = function(f, handler, ...)
            if type(handler) ~= "function" then return raw_xpcall(f, handler, ...) end
            return raw_xpcall(f, function(e) return handler(plain(e)) end, ...)
        end
        coroutine.resume = function(co, ...) return caught(raw_resume(co, ...)) end
        coroutine.close = function(co) return caught(raw_close(co)) end
        "#,
    )
    .set_name(INTERNAL)
    .call(plain)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_safe_libraries_are_there() {
        let lua = new_vm(16 << 20).unwrap();
        for absent in ["io", "os", "package", "debug", "require", "dofile", "loadfile"] {
            let v: Value = lua.globals().get(absent).unwrap();
            assert!(v.is_nil(), "{absent} must not exist");
        }
        for present in ["string", "table", "math", "coroutine", "utf8", "pcall", "load"] {
            let v: Value = lua.globals().get(present).unwrap();
            assert!(!v.is_nil(), "{present} must exist");
        }
    }

    #[test]
    fn binary_chunks_are_refused() {
        let lua = new_vm(16 << 20).unwrap();
        let refused: bool = lua.load(r#"return load(string.dump(function() return 1 end)) == nil"#).eval().unwrap();
        assert!(refused);
        let ok: i64 = lua.load("return load('return 41 + 1')()").eval().unwrap();
        assert_eq!(ok, 42);
    }

    #[test]
    fn the_memory_limit_stops_a_memory_bomb() {
        let lua = new_vm(8 << 20).unwrap();
        let err = lua.load("local s = string.rep('x', 64 * 1024 * 1024)").exec().unwrap_err();
        assert!(matches!(err, mlua::Error::MemoryError(_)), "{err:?}");
    }
}

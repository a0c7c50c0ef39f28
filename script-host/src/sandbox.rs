//! The Lua VM a user program runs in: Lua 5.4 with base, table, string, math, coroutine
//! and utf8 only (no io, os, package, debug), text chunks only, and a memory limit. The
//! script process adds a `require` that reads modules from the program's own folder only
//! (`crate::require`).

use mlua::{Function, Lua, LuaOptions, MultiValue, StdLib, Value};

pub fn new_vm(memory_limit_bytes: usize) -> mlua::Result<Lua> {
    let libs = StdLib::TABLE | StdLib::STRING | StdLib::MATH | StdLib::COROUTINE | StdLib::UTF8;
    let lua = Lua::new_with(libs, LuaOptions::new())?;
    lua.set_memory_limit(memory_limit_bytes)?;
    let globals = lua.globals();
    // The base library can read files; a program reaches nothing outside its VM.
    for name in ["dofile", "loadfile"] {
        globals.raw_set(name, Value::Nil)?;
    }
    // Precompiled chunks can crash the VM: `load` takes source text only.
    let load: Function = globals.get("load")?;
    let text_only = lua.create_function(move |_, (chunk, name, _mode, env): (Value, Value, Value, Value)| {
        load.call::<MultiValue>((chunk, name, "t", env))
    })?;
    globals.raw_set("load", text_only)?;
    Ok(lua)
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

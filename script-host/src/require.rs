//! `require` for a DRL project (DXMC manual A.3): a project is a folder holding `main.lua`
//! and its modules, and a program can load modules from its own folder only. The sandbox
//! has no `package` library; this `require` reads `<folder>/<a>/<b>.lua` for the name
//! `a.b`, refuses any file whose real path (symbolic links resolved) lies outside the
//! folder, runs each module once and keeps what it returned, as Lua's `require` does.

use std::cell::RefCell;
use std::collections::HashSet;
use std::path::{Path, PathBuf};

use mlua::chunk::ChunkMode;
use mlua::{Lua, Table, Value};

use crate::bindings::error_here;

/// Why a module could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum RequireError {
    #[error("require: bad module name {0:?} (names are like util or motion.pallet)")]
    BadName(String),
    #[error("require: no module '{name}' in {folder}")]
    NotFound { name: String, folder: String },
    #[error("require: module '{name}' is outside {folder}")]
    Outside { name: String, folder: String },
    #[error("require: module '{0}' requires itself (directly or through other modules)")]
    Loop(String),
    #[error("require: cannot read {path}: {source}")]
    Read { path: String, source: std::io::Error },
}

/// The modules of one program's folder.
struct Modules {
    /// As the program's path names it: chunk names and messages show this.
    folder: PathBuf,
    /// Resolved once: a module's real path must lie under it.
    real_folder: PathBuf,
    /// Module name to the value its chunk returned.
    loaded: Table,
    /// Modules whose chunk is running: requiring one of them again is a loop.
    loading: RefCell<HashSet<String>>,
}

/// Installs `require(name)`, loading modules from `program`'s folder.
pub fn install(lua: &Lua, program: &Path) -> mlua::Result<()> {
    let folder = match program.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let real_folder = folder
        .canonicalize()
        .map_err(|e| mlua::Error::external(RequireError::Read { path: folder.display().to_string(), source: e }))?;
    let modules = Modules { folder, real_folder, loaded: lua.create_table()?, loading: RefCell::default() };
    let require = lua.create_function(move |lua, name: String| modules.require(lua, &name))?;
    lua.globals().raw_set("require", require)
}

impl Modules {
    fn require(&self, lua: &Lua, name: &str) -> mlua::Result<Value> {
        let cached: Value = self.loaded.raw_get(name)?;
        if !cached.is_nil() {
            return Ok(cached);
        }
        let (path, source) = self.find(name).map_err(|e| error_here(lua, e))?;
        if !self.loading.borrow_mut().insert(name.to_string()) {
            return Err(error_here(lua, RequireError::Loop(name.to_string())));
        }
        let result = self.run(lua, name, &path, &source);
        self.loading.borrow_mut().remove(name);
        let value = match result? {
            Value::Nil => Value::Boolean(true),
            value => value,
        };
        self.loaded.raw_set(name, &value)?;
        Ok(value)
    }

    /// The module's file (as the program's folder names it) and its text.
    fn find(&self, name: &str) -> Result<(PathBuf, String), RequireError> {
        if !is_module_name(name) {
            return Err(RequireError::BadName(name.to_string()));
        }
        let relative = format!("{}.lua", name.replace('.', "/"));
        let path = self.folder.join(&relative);
        let folder = || self.folder.display().to_string();
        let real = self.real_folder.join(&relative).canonicalize().map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => RequireError::NotFound { name: name.to_string(), folder: folder() },
            _ => RequireError::Read { path: path.display().to_string(), source: e },
        })?;
        if !real.starts_with(&self.real_folder) {
            return Err(RequireError::Outside { name: name.to_string(), folder: folder() });
        }
        let source = std::fs::read_to_string(&real)
            .map_err(|source| RequireError::Read { path: path.display().to_string(), source })?;
        Ok((path, source))
    }

    /// Runs the module's chunk as Lua's `require` does: with the name and the file as
    /// arguments; named `@<file>` so that its errors give file and line.
    fn run(&self, lua: &Lua, name: &str, path: &Path, source: &str) -> mlua::Result<Value> {
        let file = path.display().to_string();
        let chunk = lua.load(source).set_name(format!("@{file}")).set_mode(ChunkMode::Text).into_function()?;
        chunk.call((name, file))
    }
}

/// `^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*$`: no path separators, no `..`.
fn is_module_name(name: &str) -> bool {
    name.split('.').all(|part| {
        let mut chars = part.chars();
        chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sandbox;

    /// A project folder with `files` (path, text) and a VM whose program is its `main.lua`.
    fn project(files: &[(&str, &str)]) -> (tempfile::TempDir, Lua) {
        let folder = tempfile::tempdir().unwrap();
        for (path, text) in files {
            let path = folder.path().join(path);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, text).unwrap();
        }
        let lua = sandbox::new_vm(16 << 20).unwrap();
        install(&lua, &folder.path().join("main.lua")).unwrap();
        (folder, lua)
    }

    /// Runs `code` as the folder's main chunk.
    fn run<T: mlua::FromLuaMulti>(folder: &tempfile::TempDir, lua: &Lua, code: &str) -> mlua::Result<T> {
        lua.load(code).set_name(format!("@{}/main.lua", folder.path().display())).call(())
    }

    #[test]
    fn a_module_of_the_folder_is_loaded_once() {
        let util = "loads = (loads or 0) + 1\nreturn { answer = 42 }\n";
        let (folder, lua) = project(&[("util.lua", util)]);
        let (answer, same, loads): (i64, bool, i64) =
            run(&folder, &lua, "local a = require('util')\nreturn a.answer, a == require('util'), loads").unwrap();
        assert_eq!((answer, same, loads), (42, true, 1));
    }

    #[test]
    fn a_dotted_name_is_a_path_in_the_folder() {
        let (folder, lua) = project(&[("motion/pallet.lua", "return { ... }")]);
        let (name, file): (String, String) =
            run(&folder, &lua, "local args = require('motion.pallet')\nreturn args[1], args[2]").unwrap();
        assert_eq!(name, "motion.pallet", "the chunk gets the name, as in Lua");
        assert_eq!(file, folder.path().join("motion/pallet.lua").display().to_string());
    }

    #[test]
    fn a_module_that_returns_nothing_reads_true() {
        let (folder, lua) = project(&[("setup.lua", "configured = true")]);
        let value: mlua::Value = run(&folder, &lua, "return require('setup')").unwrap();
        assert_eq!(value, mlua::Value::Boolean(true));
    }

    #[test]
    fn names_that_could_leave_the_folder_are_refused() {
        let (folder, lua) = project(&[("util.lua", "return 1")]);
        for name in ["..", "../util", "a/b", "a..b", ".util", "util.", "", "1util", "/etc/passwd"] {
            let err = run::<()>(&folder, &lua, &format!("require({name:?})")).unwrap_err().to_string();
            assert!(err.contains("main.lua:1: require: bad module name"), "{name:?}: {err}");
        }
    }

    #[test]
    fn a_missing_module_is_a_clear_error() {
        let (folder, lua) = project(&[]);
        let err = run::<()>(&folder, &lua, "\nrequire('nope')").unwrap_err().to_string();
        let expected = format!("main.lua:2: require: no module 'nope' in {}", folder.path().display());
        assert!(err.contains(&expected), "{err}");
    }

    #[test]
    fn a_symbolic_link_out_of_the_folder_is_refused() {
        let outside = tempfile::tempdir().unwrap();
        std::fs::write(outside.path().join("secret.lua"), "return 'secret'").unwrap();
        let (folder, lua) = project(&[]);
        std::os::unix::fs::symlink(outside.path().join("secret.lua"), folder.path().join("secret.lua")).unwrap();
        std::os::unix::fs::symlink(outside.path(), folder.path().join("lib")).unwrap();
        for name in ["secret", "lib.secret"] {
            let err = run::<()>(&folder, &lua, &format!("require('{name}')")).unwrap_err().to_string();
            assert!(err.contains(&format!("require: module '{name}' is outside")), "{err}");
        }
    }

    #[test]
    fn an_error_in_a_module_gives_its_file_and_line() {
        let (folder, lua) = project(&[("broken.lua", "local x = 1\nerror('boom')\n")]);
        let err = run::<()>(&folder, &lua, "require('broken')").unwrap_err().to_string();
        assert!(err.contains("broken.lua:2: boom"), "{err}");
    }

    #[test]
    fn modules_that_require_each_other_are_an_error_not_a_stack_overflow() {
        let (folder, lua) = project(&[("a.lua", "return require('b')"), ("b.lua", "return require('a')")]);
        let err = run::<()>(&folder, &lua, "require('a')").unwrap_err().to_string();
        assert!(err.contains("b.lua:1: require: module 'a' requires itself"), "{err}");
        let err = run::<()>(&folder, &lua, "require('a')").unwrap_err().to_string();
        assert!(err.contains("requires itself"), "a failed load is not cached: {err}");
    }
}

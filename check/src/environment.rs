//! The globals a program starts with, all from the registry (`api::registry`,
//! `api::constants`, `api::system_vars`) but Lua's own libraries, which are the sandbox's
//! (script-host's `sandbox.rs`: base, table, string, math, coroutine, utf8, and its
//! `require`). A test holds this list to the globals of a real script VM.

use std::collections::HashMap;

use api::FunctionSpec;
use api::constants::{CONSTANTS, Constant};
use api::system_vars::SystemVar;

/// Lua 5.4's base library as the sandbox leaves it (without `dofile` and `loadfile`),
/// its libraries, and the project's `require`.
pub const LUA_GLOBALS: &[&str] = &[
    "_G",
    "_VERSION",
    "assert",
    "collectgarbage",
    "error",
    "getmetatable",
    "ipairs",
    "load",
    "next",
    "pairs",
    "pcall",
    "print",
    "rawequal",
    "rawget",
    "rawlen",
    "rawset",
    "select",
    "setmetatable",
    "tonumber",
    "tostring",
    "type",
    "warn",
    "xpcall",
    "table",
    "string",
    "math",
    "coroutine",
    "utf8",
    "require",
];

/// What the sandbox leaves out, in its words (script-host `sandbox.rs`).
pub const REFUSED: &[(&str, &str)] = &[
    ("io", "the sandbox has no io library: a program reaches nothing outside its VM"),
    ("os", "the sandbox has no os library: a program reaches nothing outside its VM (its time: system_timeInMs)"),
    ("package", "the sandbox has no package library: `require` loads modules from the program's own folder"),
    ("debug", "the sandbox has no debug library"),
    ("dofile", "the sandbox has no dofile: the base library could read files; use `require` for the program's modules"),
    (
        "loadfile",
        "the sandbox has no loadfile: the base library could read files; use `require` for the program's modules",
    ),
];

/// What a name the program did not make is.
#[derive(Clone, Copy, Debug)]
pub enum Known {
    /// A function of the registry.
    Function(&'static FunctionSpec),
    /// A table holding registry functions by dotted name (`FreePort`).
    ApiTable,
    /// A constant (`BM_LOOKAHEAD`, `PI`, an error id, `HOME_METHOD_1`).
    Constant,
    /// A system variable (`system_fclk`); `writable` for the test variables.
    SystemVariable {
        /// `system_ltest0 = 5` is a write to shared memory, not a mistake.
        writable: bool,
    },
    /// Lua's own.
    Lua,
}

/// Every global name a program starts with.
pub struct Environment {
    names: HashMap<String, Known>,
    /// Registry functions by their full dotted name (`FreePort.Eth.Tx`).
    dotted: HashMap<&'static str, &'static FunctionSpec>,
    /// What the registry says of each constant and variable.
    notes: HashMap<String, Note>,
}

/// What the registry says of a constant or a variable, for an editor.
#[derive(Clone, Debug, Default)]
pub struct Note {
    /// Its value (`BM_LOOKAHEAD = 6`) or type (`system_fclk: integer`).
    pub detail: String,
    /// Where it comes from and what it is.
    pub doc: String,
}

impl Environment {
    /// The environment of every script VM, from the registry.
    pub fn new() -> Self {
        let mut names = HashMap::new();
        let mut dotted = HashMap::new();
        for spec in api::registry::all() {
            match spec.name.split_once('.') {
                Some((root, _)) => {
                    names.insert(root.to_string(), Known::ApiTable);
                    dotted.insert(spec.name, spec);
                }
                None => {
                    names.insert(spec.name.to_string(), Known::Function(spec));
                }
            }
        }
        let mut notes = HashMap::new();
        let mut note = |name: String, known: Known, detail: String, doc: String| {
            names.insert(name.clone(), known);
            notes.insert(name, Note { detail, doc });
        };
        for (name, value, source) in CONSTANTS {
            let value = match value {
                Constant::Int(i) => i.to_string(),
                Constant::Double(d) => d.to_string(),
                Constant::Str(s) => format!("{s:?}"),
            };
            note(name.to_string(), Known::Constant, format!("{name} = {value}"), source.to_string());
        }
        for (name, id) in api::constants::error_ids() {
            note(name.to_string(), Known::Constant, format!("{name} = 0x{id:04X}"), "error id (HMPL ch. 18)".into());
        }
        for (name, value) in api::constants::numbered() {
            note(name.clone(), Known::Constant, format!("{name} = {value}"), String::new());
        }
        let tests = (0..api::system_vars::TEST_VARS).flat_map(|i| ["ltest", "dtest"].map(|k| format!("system_{k}{i}")));
        let described = |name: &str| SystemVar::ALL.iter().find(|d| d.name == name);
        let variables = SystemVar::ALL.iter().map(|d| d.name.to_string()).chain(tests);
        for name in variables {
            let var = SystemVar::parse(&name);
            let writable = matches!(var, Some(SystemVar::LTest(_) | SystemVar::DTest(_)));
            // The reference describes the first test variable of each kind for all ten.
            let first = match var {
                Some(SystemVar::LTest(_)) => "system_ltest0",
                Some(SystemVar::DTest(_)) => "system_dtest0",
                _ => name.as_str(),
            };
            let (detail, doc) = described(first)
                .map(|d| (format!("{name}: {}", d.lua_type), format!("{} ({})", d.doc, d.source)))
                .unwrap_or_default();
            note(name.clone(), Known::SystemVariable { writable }, detail, doc);
        }
        for name in LUA_GLOBALS {
            names.insert(name.to_string(), Known::Lua);
        }
        Environment { names, dotted, notes }
    }

    /// What `name` is, if the program starts with it.
    pub fn get(&self, name: &str) -> Option<Known> {
        self.names.get(name).copied()
    }

    /// Every global name and what it is.
    pub fn globals(&self) -> impl Iterator<Item = (&str, Known)> {
        self.names.iter().map(|(name, known)| (name.as_str(), *known))
    }

    /// What the registry says of a constant or variable.
    pub fn note(&self, name: &str) -> Option<&Note> {
        self.notes.get(name)
    }

    /// Every dotted registry function (`FreePort.Eth.Tx`).
    pub fn dotted_functions(&self) -> impl Iterator<Item = &'static FunctionSpec> + '_ {
        self.dotted.values().copied()
    }

    /// The registry function of a dotted name (`FreePort.Eth.Tx`).
    pub fn dotted(&self, path: &str) -> Option<&'static FunctionSpec> {
        self.dotted.get(path).copied()
    }

    /// Whether `path` is a dotted function's name or the start of one (`FreePort.Eth`).
    pub fn is_dotted_prefix(&self, path: &str) -> bool {
        self.dotted
            .keys()
            .any(|full| full.strip_prefix(path).is_some_and(|rest| rest.is_empty() || rest.starts_with('.')))
    }

    /// Every name a suggestion may be: globals and dotted functions.
    pub fn candidates(&self) -> impl Iterator<Item = &str> {
        self.names.keys().map(String::as_str).chain(self.dotted.keys().copied())
    }

    /// Why the sandbox refuses `name`, if it does.
    pub fn refused(name: &str) -> Option<&'static str> {
        REFUSED.iter().find(|(n, _)| *n == name).map(|(_, why)| *why)
    }
}

impl Default for Environment {
    fn default() -> Self {
        Environment::new()
    }
}

//! The API reference (`docs/api.md`) and the lua-language-server annotations
//! (`scripts/luamotion.d.lua`), generated from the registry. Tests keep the committed
//! files equal to what this generates.

use std::fmt::Write;

use crate::catalogue::Offered;
use crate::constants::{CONSTANTS, Constant, error_ids, numbered};
use crate::registry::{ArgType, FunctionSpec, Kind, ValueType, all};
use crate::system_vars::SystemVar;

fn lua_type(v: ValueType) -> &'static str {
    match v {
        ValueType::Int => "integer",
        ValueType::Double => "number",
        ValueType::Bool => "boolean",
        ValueType::Str => "string",
        ValueType::Bytes => "integer[]",
        ValueType::Doubles => "number[]",
        ValueType::Timer => "Timer",
        ValueType::Any => "any",
        ValueType::Memory => "integer[]|number[]",
    }
}

fn lua_returns(f: &FunctionSpec) -> String {
    if f.returns.is_empty() {
        "nothing".to_string()
    } else {
        f.returns.iter().map(|&r| lua_type(r)).collect::<Vec<_>>().join(", ")
    }
}

fn kind_name(k: Kind) -> &'static str {
    match k {
        Kind::Command => "command (round trip to the core)",
        Kind::Query => "query (local snapshot)",
        Kind::Local => "script process",
    }
}

/// `docs/api.md`.
pub fn markdown() -> String {
    let mut out = String::new();
    out.push_str("# API reference\n\n");
    out.push_str("Generated from the registry (`api/src/functions.rs`) by `luamotion api markdown`; do not edit.\n\n");
    out.push_str("Commands return 0 or an HMPL error code (`0x83IIEEEE` for an axis, as an unsigned number). ");
    out.push_str("`Is*` queries return Lua booleans. Errors in arguments (a string where a number belongs, ");
    out.push_str("an axis that does not exist in a query) raise a Lua error at the calling line.\n\n");
    out.push_str("| function | C signature (manual) | returns in Lua | runs as | manual | ASCII |\n");
    out.push_str("|---|---|---|---|---|---|\n");
    for f in all() {
        let _ = writeln!(
            out,
            "| `{}` | `{}` | {} | {} | {} | {} |",
            f.name,
            f.signature(),
            lua_returns(f),
            kind_name(f.kind()),
            f.manual,
            if f.ascii { "yes" } else { "no" }
        );
    }
    out.push_str("\n## Functions\n");
    for f in all() {
        let _ = write!(out, "\n### {}\n\n`{}` ({})\n\n", f.name, f.signature(), f.manual);
        for line in f.doc {
            let _ = writeln!(out, "{}", line.trim());
        }
    }
    out.push_str("\n## Constants\n\n| name | value | source |\n|---|---|---|\n");
    for (name, value, source) in CONSTANTS {
        let value = match value {
            Constant::Int(i) => i.to_string(),
            Constant::Double(d) => d.to_string(),
            Constant::Str(s) => format!("{s:?}"),
        };
        let _ = writeln!(out, "| `{name}` | `{value}` | {source} |");
    }
    out.push_str("\n`HOME_METHOD_n` (HMPL 20.1) and `HMPL_AXIS_n` (0..15) are constants too.\n");
    out.push_str("\n## Variables\n\n| name | Lua type | source | what |\n|---|---|---|---|\n");
    for v in SystemVar::ALL {
        let _ = writeln!(out, "| `{}` | `{}` | {} | {} |", v.name, v.lua_type, v.source, v.doc);
    }
    out.push_str("\n## Controller variables (HCV ids, HMPL 17.1)\n\n");
    out.push_str("The ids `GetConfigVar` and `SetConfigVar` know; an axis or group variable is `0x83II` or `0x82II` ");
    out.push_str("(`II` the axis or group) before its `VVVV`, read by its getter and written by its setter.\n\n");
    out.push_str("| id | name | what |\n|---|---|---|\n");
    for (id, name, doc) in crate::hcv::SYSTEM_VARS {
        let _ = writeln!(out, "| `0x{id:08X}` | `{name}` | {doc} |");
    }
    for (class, vars) in [("83II", crate::hcv::AXIS_VARS), ("82II", crate::hcv::GROUP_VARS)] {
        for v in vars {
            let set = v.set.map_or_else(|| "read-only".to_string(), |c| format!("`{}`", c.spec().name));
            let _ = writeln!(out, "| `0x{class}{:04X}` | `{}` | `{}`, {set} |", v.vvvv, v.name, v.get.spec().name);
        }
    }
    out.push_str("\nEvery error name of HMPL ch. 18 is also a constant holding its error id (`EEEE`), ");
    out.push_str("e.g. `GetAxisLastErr(0) & 0xFFFF == eERR_AXIS_CMD_INVALID_DISABLED`.\n");
    catalogue(&mut out);
    out
}

/// The manual's 340 catalogue entries, how a script reaches each, and how the simulator
/// differs where it does.
fn catalogue(out: &mut String) {
    out.push_str("\n## The HMPL catalogue\n\n");
    let _ = write!(
        out,
        "All {} entries of the HMPL manual's catalogue (ch. 2 to 22), in its order. The last column says what \
         a program sees differently on this simulator than on a controller with a machine; an empty cell \
         means the entry behaves as the manual says.\n\n",
        crate::catalogue::ENTRIES.len()
    );
    out.push_str("| HMPL | entry | in luamotion | in simulation |\n|---|---|---|---|\n");
    for (section, name) in crate::catalogue::ENTRIES {
        let how = match crate::catalogue::offered(name) {
            Some(Offered::Function(f)) => kind_name(f.kind()).to_string(),
            Some(Offered::Variable(_)) => "system variable (see Variables)".to_string(),
            Some(Offered::Construct(how)) => how.to_string(),
            None => "**missing**".to_string(),
        };
        let sim = crate::catalogue::SIMULATION.iter().find(|(n, _)| *n == name).map_or("", |(_, note)| note);
        let _ = writeln!(out, "| {section} | `{name}` | {how} | {sim} |");
    }
}

/// `scripts/luamotion.d.lua`, for completion and checks in editors.
pub fn lua_meta() -> String {
    let mut out = String::new();
    out.push_str("---@meta luamotion\n");
    out.push_str("-- Generated from the registry by `luamotion api lua`; do not edit.\n");
    out.push_str("\n---A timer for TON and TOF (HMPL 2.24).\n---@class Timer\n---@field Q boolean\n---@field ET integer\n---@field IN boolean\n");
    let mut tables = std::collections::BTreeSet::new();
    for f in all() {
        out.push('\n');
        // A dotted name lives in nested tables, each declared before its first function.
        let mut prefix = f.name;
        let mut new = Vec::new();
        while let Some((table, _)) = prefix.rsplit_once('.') {
            if tables.insert(table) {
                new.push(table);
            }
            prefix = table;
        }
        for table in new.iter().rev() {
            let _ = writeln!(out, "{table} = {{}}");
        }
        for line in f.doc {
            let _ = writeln!(out, "---{}", line.trim_end());
        }
        let _ = writeln!(out, "---{} ({})", f.manual, kind_name(f.kind()));
        let mut params = Vec::new();
        for a in f.args {
            let (name, ty) = match a.ty {
                ArgType::Int => (a.name, "integer"),
                ArgType::Double => (a.name, "number"),
                ArgType::Str => (a.name, "string"),
                ArgType::Func => (a.name, "fun(): any"),
                ArgType::Bytes => (a.name, "integer[]|string"),
                ArgType::Doubles => (a.name, "number[]"),
                ArgType::Rest => ("...", "any"),
                ArgType::Bool => (a.name, "boolean|number"),
                ArgType::Timer => (a.name, "Timer"),
                ArgType::Any => (a.name, "any"),
                ArgType::Memory => (a.name, "integer[]|number[]"),
            };
            let _ = writeln!(out, "---@param {name} {ty}");
            params.push(name);
        }
        for &r in f.returns {
            let _ = writeln!(out, "---@return {}", lua_type(r));
        }
        let _ = writeln!(out, "function {}({}) end", f.name, params.join(", "));
    }
    out.push('\n');
    for (name, value, source) in CONSTANTS {
        let value = match value {
            Constant::Int(i) => i.to_string(),
            Constant::Double(d) => format!("{d:?}"),
            Constant::Str(s) => format!("{s:?}"),
        };
        let _ = writeln!(out, "{name} = {value} -- {source}");
    }
    for (name, value) in numbered() {
        let _ = writeln!(out, "{name} = {value}");
    }
    for (name, id) in error_ids() {
        let _ = writeln!(out, "{name} = 0x{id:04X}");
    }
    for v in SystemVar::ALL {
        let _ = writeln!(out, "---@type {}\n{} = nil -- {} ({})", v.lua_type, v.name, v.doc, v.source);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;
    use std::path::Path;

    fn repo_file(relative: &str) -> String {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(relative);
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }

    #[test]
    fn committed_reference_matches_the_registry() {
        assert!(repo_file("docs/api.md") == markdown(), "run `cargo run -- api markdown > docs/api.md`");
        assert!(
            repo_file("scripts/luamotion.d.lua") == lua_meta(),
            "run `cargo run -- api lua > scripts/luamotion.d.lua`"
        );
    }

    #[test]
    fn names_are_unique_and_every_function_is_documented() {
        let mut names = HashSet::new();
        for f in all() {
            assert!(names.insert(f.name), "{} declared twice", f.name);
            assert!(!f.doc.is_empty(), "{} has no doc", f.name);
            let source = ["HMPL ", "DXMC ", "Fatek ", "luamotion "].iter().any(|p| f.manual.starts_with(p));
            assert!(source, "{}: {}", f.name, f.manual);
            assert_eq!(crate::registry::find(f.name).map(|g| g.name), Some(f.name));
        }
    }
}

//! A `.luacheckrc` for luacheck users (`luamotion api luacheckrc`): the environment's
//! globals, read-only where the API's are, and the libraries the sandbox leaves out as
//! globals that do not exist.

use crate::environment::{Environment, Known, REFUSED};

/// The file's text.
pub fn generate(environment: &Environment) -> String {
    let mut read_only: Vec<&str> = Vec::new();
    let mut writable: Vec<&str> = Vec::new();
    for (name, known) in environment.globals() {
        match known {
            Known::Lua => {}
            Known::SystemVariable { writable: true } => writable.push(name),
            _ => read_only.push(name),
        }
    }
    read_only.sort_unstable();
    writable.sort_unstable();
    // The tables among the variables (the user table, task_vars, HIMC_GPO) take writes to
    // their fields; the name itself stays the API's.
    let list = |names: &[&str]| {
        names
            .iter()
            .map(|n| match environment.get(n) {
                Some(Known::SystemVariable { writable: false }) => {
                    format!("  {n} = {{ other_fields = true, read_only = false }},\n")
                }
                _ => format!("  {n:?},\n"),
            })
            .collect::<String>()
    };
    let refused: Vec<&str> = REFUSED.iter().map(|(name, _)| *name).collect();
    format!(
        "-- Generated from the registry by `luamotion api luacheckrc`; do not edit.\n\
         -- The globals of a luamotion script VM: Lua 5.4's libraries but io, os, package\n\
         -- and debug (the sandbox), and the API's functions, constants and variables.\n\
         std = \"lua54\"\n\
         -- A program's own globals, set at its top level: entries for StartTaskFunc.\n\
         allow_defined_top = true\n\
         not_globals = {{\n{}}}\n\
         read_globals = {{\n{}}}\n\
         globals = {{\n{}}}\n",
        list(&refused),
        list(&read_only),
        list(&writable),
    )
}

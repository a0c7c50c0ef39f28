//! The variables every program sees (HMPL 1.1, 19.1, 23.2), declared once: the bindings
//! resolve names with `SystemVar::parse`, the reference and the editor annotations list
//! `SystemVar::ALL`.

/// HMPL 23.2: `system_ltest0..9` and `system_dtest0..9`.
pub const TEST_VARS: usize = 10;

/// A variable every program sees, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SystemVar {
    /// `system_fclk`: controller cycles since start (read-only).
    Fclk,
    /// `system_timeInMs`: controller time in ms (read-only).
    TimeInMs,
    /// `system_user_table[0..511999]`: the user table (HMPL ch. 11).
    UserTable,
    /// `system_ltest0..9`: integers shared by all tasks.
    LTest(usize),
    /// `system_dtest0..9`: numbers shared by all tasks.
    DTest(usize),
    /// `system_mtest[0..9]`: numbers shared by all tasks.
    MTest,
    /// `_TASKID_`: the task's own id (HMPL 19.1).
    TaskId,
    /// `task_vars.name`: this task's variables that keep their values across restarts.
    TaskVars,
    /// `HIMC_GPI[i]` / `HIMC_GPI(i)`: controller input i as a boolean (HMPL 19.4).
    HimcGpi,
    /// `HIMC_GPO[i]` / `HIMC_GPO(i)`: controller output i; `HIMC_GPO[i] = on` sets it (HMPL 19.5).
    HimcGpo,
}

/// One line of the reference: name, Lua type, where it comes from, what it is.
pub struct Described {
    /// The global's name, e.g. `system_fclk`.
    pub name: &'static str,
    /// Its Lua type for the editor annotations.
    pub lua_type: &'static str,
    /// The manual section it comes from.
    pub source: &'static str,
    /// What it is.
    pub doc: &'static str,
}

impl SystemVar {
    /// Every variable, for the reference and the editor annotations.
    pub const ALL: &'static [Described] = &[
        Described {
            name: "system_fclk",
            lua_type: "integer",
            source: "HMPL 23.2",
            doc: "controller cycles since start (read-only)",
        },
        Described {
            name: "system_timeInMs",
            lua_type: "integer",
            source: "HMPL 23.2",
            doc: "controller time, ms (read-only)",
        },
        Described {
            name: "system_user_table",
            lua_type: "number[]",
            source: "HMPL 11, 23.2",
            doc: "the user table, indices 0..511999, shared by all tasks",
        },
        Described {
            name: "system_ltest0",
            lua_type: "integer",
            source: "HMPL 23.2",
            doc: "system_ltest0 .. system_ltest9: integers shared by all tasks",
        },
        Described {
            name: "system_dtest0",
            lua_type: "number",
            source: "HMPL 23.2",
            doc: "system_dtest0 .. system_dtest9: numbers shared by all tasks",
        },
        Described {
            name: "system_mtest",
            lua_type: "number[]",
            source: "HMPL 23.2",
            doc: "10 numbers shared by all tasks, indices 0..9",
        },
        Described { name: "_TASKID_", lua_type: "integer", source: "HMPL 19.1", doc: "this task's id" },
        Described {
            name: "task_vars",
            lua_type: "table<string, number|boolean|string>",
            source: "HMPL 1.5 (luamotion)",
            doc: "this task's variables: they keep their values when the task is stopped and started again (64 per task, names up to 31 bytes, strings up to 64)",
        },
        Described {
            name: "HIMC_GPI",
            lua_type: "table<integer, boolean>",
            source: "HMPL 19.4",
            doc: "controller input i (1..8) as a boolean: `HIMC_GPI[4]` or `HIMC_GPI(4)` (read-only; a Lua error for no such input)",
        },
        Described {
            name: "HIMC_GPO",
            lua_type: "table<integer, boolean>",
            source: "HMPL 19.5",
            doc: "controller output i (1..8): read as `HIMC_GPO[1]` or `HIMC_GPO(1)`, set with `HIMC_GPO[1] = HIMC_GPI[4] and HIMC_GPI[6]` (true, false or a number, 0 is off)",
        },
    ];

    /// The variable a global name stands for; `None` for any other name.
    pub fn parse(name: &str) -> Option<Self> {
        let numbered = |prefix: &str| {
            name.strip_prefix(prefix)
                .and_then(|n| n.parse::<usize>().ok())
                .filter(|&i| i < TEST_VARS && name.len() == prefix.len() + 1)
        };
        Some(match name {
            "system_fclk" => SystemVar::Fclk,
            "system_timeInMs" => SystemVar::TimeInMs,
            "system_user_table" => SystemVar::UserTable,
            "system_mtest" => SystemVar::MTest,
            "_TASKID_" => SystemVar::TaskId,
            "task_vars" => SystemVar::TaskVars,
            "HIMC_GPI" => SystemVar::HimcGpi,
            "HIMC_GPO" => SystemVar::HimcGpo,
            _ => {
                if let Some(i) = numbered("system_ltest") {
                    SystemVar::LTest(i)
                } else {
                    SystemVar::DTest(numbered("system_dtest")?)
                }
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names() {
        for d in SystemVar::ALL {
            assert!(SystemVar::parse(d.name).is_some(), "{}", d.name);
        }
        assert_eq!(SystemVar::parse("system_ltest9"), Some(SystemVar::LTest(9)));
        assert_eq!(SystemVar::parse("system_dtest0"), Some(SystemVar::DTest(0)));
        for absent in ["system_ltest10", "system_dtest", "system_ltest01", "fclk"] {
            assert_eq!(SystemVar::parse(absent), None, "{absent}");
        }
    }
}

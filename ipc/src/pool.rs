//! A pooled script process' assignment: the one line the supervisor writes on its stdin
//! when it hands the process a task (`rt-core/src/pool.rs`).

use std::path::PathBuf;

/// Node name of a pooled process before it has a task.
pub const POOL_NODE_NAME: &str = "luamotion-script-pool";

/// The task a pooled process is to run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Assignment {
    /// The task slot.
    pub task: u8,
    /// The memory limit of its VM, MiB.
    pub memory_limit_mib: u32,
    /// `StartTaskFunc`: the function to run after the program's top level.
    pub entry: Option<String>,
    /// The Lua program.
    pub program: PathBuf,
}

impl Assignment {
    /// `<task> <memory limit> <entry or -> <program>\n`: the program last, since a path may
    /// hold spaces; `-` is no Lua name, so it stands for "no entry".
    pub fn encode(&self) -> String {
        let entry = self.entry.as_deref().unwrap_or("-");
        format!("{} {} {entry} {}\n", self.task, self.memory_limit_mib, self.program.display())
    }

    /// The assignment of one line `encode` wrote; `None` for anything else.
    pub fn decode(line: &str) -> Option<Self> {
        let mut fields = line.strip_suffix('\n')?.splitn(4, ' ');
        let task = fields.next()?.parse().ok()?;
        let memory_limit_mib = fields.next()?.parse().ok()?;
        let entry = Some(fields.next()?).filter(|e| *e != "-").map(str::to_string);
        let program = PathBuf::from(fields.next().filter(|p| !p.is_empty())?);
        Some(Assignment { task, memory_limit_mib, entry, program })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_assignment_survives_its_line() {
        for (entry, program) in [(None, "/tmp/a b/main.lua"), (Some("go".to_string()), "x.lua")] {
            let assignment = Assignment { task: 63, memory_limit_mib: 64, entry, program: program.into() };
            assert_eq!(Assignment::decode(&assignment.encode()), Some(assignment));
        }
        assert_eq!(Assignment::decode("1 64 -\n"), None);
        assert_eq!(Assignment::decode("1 64 - x.lua"), None, "a line cut short");
    }
}

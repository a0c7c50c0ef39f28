//! `[[tasks]]`: the HMPL tasks (ch. 16) the controller runs, and what their motion does
//! when they fail.

use std::collections::HashSet;
use std::path::PathBuf;

use schema::MAX_TASKS;
use serde::Deserialize;

use crate::error::{ConfigError, invalid};

/// `[[tasks]]`: one task slot and the program its script process runs.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaskConfig {
    /// The HMPL task id, 0..63 (ch. 16), each used once.
    pub id: u8,
    /// The Lua program, relative to the machine file; it must exist at load.
    pub program: PathBuf,
    /// Started with the controller; otherwise only when another task starts it
    /// (`StartTask`).
    #[serde(default)]
    pub autorun: bool,
    /// A task that runs Lua this long (ms, default 500) without calling the API is
    /// stopped as hung.
    #[serde(default = "TaskConfig::default_watchdog_ms")]
    pub watchdog_ms: u32,
    /// The Lua VM's memory limit, 1..4096 MiB (default 64); over it the task ends.
    #[serde(default = "TaskConfig::default_memory_limit_mib")]
    pub memory_limit_mib: u32,
    /// What the axes this task set moving do when it fails or is stopped.
    #[serde(default)]
    pub fault_reaction: FaultReaction,
    /// The controller starts no process for this task: a program started by the user
    /// (a benchmark, a tool) attaches to it and runs without a watchdog.
    #[serde(default)]
    pub external: bool,
    /// An external slot that carries a front end's calls (the Native ASCII agent, which
    /// the web view shares), not a program: no stop command stops it (HMPL 16.4, 16.5).
    /// Set by `with_ascii_task`, never by a machine file.
    #[serde(skip)]
    pub front_end: bool,
}

/// What happens to the active motion a task commanded when the task fails (watchdog,
/// crash, error) or is stopped (DXMC parameter 8-1; docs/decisions.md, "Fault reaction").
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum FaultReaction {
    /// The motion carries on.
    None,
    /// The axis stops with its kill deceleration and stays enabled.
    #[default]
    Decelerate,
    /// The drive's quick stop (CiA 402): it stops with 0x6085, then the axis is disabled.
    QuickStop,
    /// The axis is disabled at once.
    Disable,
}

impl TaskConfig {
    pub(crate) fn default_watchdog_ms() -> u32 {
        500
    }

    pub(crate) fn default_memory_limit_mib() -> u32 {
        64
    }

    /// A task running `program`, started with the controller.
    pub fn autorun(id: u8, program: PathBuf) -> Self {
        TaskConfig {
            id,
            program,
            autorun: true,
            watchdog_ms: Self::default_watchdog_ms(),
            memory_limit_mib: Self::default_memory_limit_mib(),
            fault_reaction: FaultReaction::default(),
            external: false,
            front_end: false,
        }
    }
}

/// The `[[tasks]]` entries: each id once, in range, with its program's file there.
pub(crate) fn validate_tasks(tasks: &[TaskConfig]) -> Result<(), ConfigError> {
    let mut ids = HashSet::new();
    for (i, task) in tasks.iter().enumerate() {
        let key = format!("tasks[{i}]");
        if task.id as usize >= MAX_TASKS {
            return Err(invalid(format!("{key}.id"), format!("task ids are 0..{} (HMPL ch. 16)", MAX_TASKS - 1)));
        }
        if !ids.insert(task.id) {
            return Err(invalid(format!("{key}.id"), format!("task {} is configured twice", task.id)));
        }
        if task.watchdog_ms == 0 {
            return Err(invalid(format!("{key}.watchdog_ms"), "must be at least 1 ms"));
        }
        if !(1..=4096).contains(&task.memory_limit_mib) {
            return Err(invalid(format!("{key}.memory_limit_mib"), "must be 1..4096"));
        }
        if !task.program.is_file() {
            return Err(invalid(format!("{key}.program"), format!("{} is not a file", task.program.display())));
        }
    }
    Ok(())
}

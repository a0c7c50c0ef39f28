//! `[drl]`: DRL projects and their program control (DXMC manual A.3).

use std::path::PathBuf;

use serde::Deserialize;

use crate::error::{ConfigError, invalid};
use crate::task::{FaultReaction, TaskConfig};

/// `[drl]`: where DRL projects live and how the one being run is supervised. The running
/// project is a task like the others, in its own slot.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DrlConfig {
    /// The HMPL task slot the DRL project runs in; no `[[tasks]]` entry may use it.
    pub task: u8,
    /// Folder of the projects, one folder per DRL id holding `main.lua` (the DXMC's FTP
    /// area); relative to the machine file. Default: `<data dir>/projects`.
    pub projects: Option<PathBuf>,
    /// Folder projects are exported to and imported from (the DXMC's USB stick).
    /// Default: `<data dir>/export`.
    pub export: Option<PathBuf>,
    /// The project's watchdog, ms, as a `[[tasks]]` entry's `watchdog_ms`.
    pub watchdog_ms: u32,
    /// The project's Lua memory limit, MiB, as a `[[tasks]]` entry's `memory_limit_mib`.
    pub memory_limit_mib: u32,
    /// What the project's motion does when it fails or is stopped (DXMC parameter 8-1).
    pub fault_reaction: FaultReaction,
}

impl Default for DrlConfig {
    fn default() -> Self {
        DrlConfig {
            task: (schema::MAX_TASKS - 1) as u8,
            projects: None,
            export: None,
            watchdog_ms: TaskConfig::default_watchdog_ms(),
            memory_limit_mib: TaskConfig::default_memory_limit_mib(),
            fault_reaction: FaultReaction::default(),
        }
    }
}

impl DrlConfig {
    /// The task slot's configuration; its program is set when a project is opened.
    pub fn task_config(&self) -> TaskConfig {
        TaskConfig {
            id: self.task,
            program: PathBuf::new(),
            autorun: false,
            watchdog_ms: self.watchdog_ms,
            memory_limit_mib: self.memory_limit_mib,
            fault_reaction: self.fault_reaction,
            external: false,
            front_end: false,
        }
    }

    pub(crate) fn validate(&self) -> Result<(), ConfigError> {
        if self.task as usize >= schema::MAX_TASKS {
            return Err(invalid("drl.task", format!("task ids are 0..63, not {}", self.task)));
        }
        if self.watchdog_ms == 0 || !(1..=4096).contains(&self.memory_limit_mib) {
            return Err(invalid("drl", "watchdog_ms must be at least 1 ms and memory_limit_mib 1..4096"));
        }
        Ok(())
    }
}

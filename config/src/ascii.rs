//! `[ascii]`: the Native and User ASCII servers (HMPL 22.1).

use serde::Deserialize;

use crate::error::{ConfigError, bind_address, invalid};

/// `[ascii]`: the ASCII servers of HMPL 22.1. The Native server (port 3999) runs in
/// `luamotion serve` and carries its clients' commands out as task `agent_task`, an
/// external slot; the User server (port 4000) is opened by the task that calls
/// `START_ASCII_AGENT`, in its own process.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AsciiConfig {
    /// The address both servers listen on. Default 127.0.0.1, as `[modbus]`.
    pub bind: String,
    /// The Native ASCII server's port (HMPL 22.1: 3999); 0 asks the OS for a free one.
    pub native_port: u16,
    /// The User ASCII server's port (HMPL 22.1: 4000); 0 asks the OS for a free one.
    pub user_port: u16,
    /// The task slot the Native server's commands run as; no `[[tasks]]` entry may use it.
    pub agent_task: u8,
    /// Connections the Native server serves at once; more get an error line and are
    /// closed. (The User agent, in a task's process, serves 32.)
    pub max_connections: u32,
    /// A Native connection that sends no whole line for this long is closed, ms. (The
    /// User agent's: 60 s.)
    pub idle_timeout_ms: u64,
}

impl Default for AsciiConfig {
    fn default() -> Self {
        AsciiConfig {
            bind: "127.0.0.1".into(),
            native_port: 3999,
            user_port: 4000,
            agent_task: (schema::MAX_TASKS - 2) as u8,
            max_connections: 32,
            idle_timeout_ms: 60_000,
        }
    }
}

impl AsciiConfig {
    pub(crate) fn validate(&self) -> Result<(), ConfigError> {
        if !(1..=4096).contains(&self.max_connections) {
            return Err(invalid("ascii.max_connections", "must be 1..4096"));
        }
        if self.idle_timeout_ms == 0 {
            return Err(invalid("ascii.idle_timeout_ms", "must be at least 1 ms"));
        }
        bind_address("ascii.bind", &self.bind)?;
        Ok(())
    }
}

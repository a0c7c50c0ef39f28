//! `[modbus]`: the Modbus TCP server of `luamotion serve` (DXMC manual 8.2).

use serde::Deserialize;

use crate::error::{ConfigError, bind_address, invalid};

/// `[modbus]`: the Modbus TCP server (DXMC manual 8.2: TCP port 502, station 1).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ModbusConfig {
    /// The address to listen on. Default 127.0.0.1: serving other hosts is a choice
    /// made here or with `luamotion serve --bind`.
    pub bind: String,
    /// 0 asks the OS for a free port (tests).
    pub port: u16,
    /// DXMC parameter 0-0, 1..247.
    pub station: u8,
    /// Connections served at once; more are closed as soon as they are accepted.
    pub max_connections: u32,
    /// A connection that sends no whole request for this long is closed, ms.
    pub idle_timeout_ms: u64,
}

impl Default for ModbusConfig {
    fn default() -> Self {
        ModbusConfig { bind: "127.0.0.1".into(), port: 502, station: 1, max_connections: 32, idle_timeout_ms: 60_000 }
    }
}

impl ModbusConfig {
    pub(crate) fn validate(&self) -> Result<(), ConfigError> {
        if !(1..=247).contains(&self.station) {
            return Err(invalid("modbus.station", "Modbus station numbers are 1..247 (DXMC parameter 0-0)"));
        }
        if !(1..=4096).contains(&self.max_connections) {
            return Err(invalid("modbus.max_connections", "must be 1..4096"));
        }
        if self.idle_timeout_ms == 0 {
            return Err(invalid("modbus.idle_timeout_ms", "must be at least 1 ms"));
        }
        bind_address("modbus.bind", &self.bind)?;
        Ok(())
    }
}

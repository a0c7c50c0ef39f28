//! `[serial]`: serial port 1, a pseudo-terminal (DXMC manual 8.2, 8.3).

use std::path::PathBuf;

use serde::Deserialize;

use crate::error::{ConfigError, invalid};

/// `[serial]`: serial port 1, a pseudo-terminal any serial program can open. Its Modbus
/// station is `[modbus] station`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SerialConfig {
    /// Whether the controller opens the port (default true); without it scripts'
    /// `FreePort.Serial` calls return 10.
    pub enabled: bool,
    /// A symlink to the pseudo-terminal (`/dev/pts/N`), made at start (replacing one
    /// there) and removed at the end; relative to the machine file.
    pub link: Option<PathBuf>,
    /// DXMC parameter 5-1, 0x00..0x1D: the character frame and Modbus ASCII, Modbus RTU
    /// or FreePort. Default 0x16, 8,N,1 Modbus RTU.
    pub protocol: u8,
    /// DXMC parameter 5-4: 0 4800, 1 9600, 2 19200, 3 38400 (default), 4 57600, 5 115200 baud.
    pub baud: u8,
    /// What is sent comes back, as with 485+ and 485- shorted (FreePort only).
    pub loopback: bool,
}

impl Default for SerialConfig {
    fn default() -> Self {
        SerialConfig { enabled: true, link: None, protocol: 0x16, baud: 3, loopback: false }
    }
}

impl SerialConfig {
    pub(crate) fn validate(&self) -> Result<(), ConfigError> {
        if self.protocol > 0x1D {
            return Err(invalid("serial.protocol", "DXMC parameter 5-1 is 0x00..0x1D"));
        }
        if self.baud > 5 {
            return Err(invalid("serial.baud", "DXMC parameter 5-4 is 0..5 (4800, 9600, 19200, 38400, 57600, 115200)"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `[serial]`: port 1 on by default as 8,N,1 Modbus RTU at 38400; parameters 5-1 and
    /// 5-4 outside their tables are refused by key.
    #[test]
    fn serial_port_settings() {
        let default = SerialConfig::default();
        assert_eq!((default.enabled, default.protocol, default.baud, default.loopback), (true, 0x16, 3, false));
        assert!(toml::from_str::<SerialConfig>("protocol = 0x17\n").unwrap().validate().is_ok());
        for (text, key) in [("protocol = 0x1E\n", "serial.protocol"), ("baud = 6\n", "serial.baud")] {
            let serial: SerialConfig = toml::from_str(text).unwrap();
            assert!(matches!(serial.validate(), Err(ConfigError::Invalid { key: k, .. }) if k == key), "{text}");
        }
    }
}

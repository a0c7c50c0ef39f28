//! What loading a machine file can refuse, and the checks every section shares.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    #[error("cannot read {path}: {source}")]
    Read { path: PathBuf, source: std::io::Error },
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    #[error("{key}: {message}")]
    Invalid { key: String, message: String },
}

pub(crate) fn invalid(key: impl Into<String>, message: impl Into<String>) -> ConfigError {
    ConfigError::Invalid { key: key.into(), message: message.into() }
}

pub(crate) fn positive(key: &str, value: f64) -> Result<(), ConfigError> {
    if value.is_finite() && value > 0.0 { Ok(()) } else { Err(invalid(key, format!("must be > 0, not {value}"))) }
}

/// A bind address of the machine file: an IP address, so that a typo is told at load
/// time rather than when the server starts (or, for `0.0.0.0` meant as `127.0.0.1`, never).
pub(crate) fn bind_address(key: &str, value: &str) -> Result<std::net::IpAddr, ConfigError> {
    value
        .parse()
        .map_err(|_| invalid(key, format!("{value:?} is not an IP address (such as 127.0.0.1, 0.0.0.0 or ::1)")))
}

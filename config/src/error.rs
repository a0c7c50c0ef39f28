//! What loading a machine file can refuse, and the checks every section shares.

use std::path::PathBuf;

/// Why a machine file was refused; nothing starts on one.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The machine file.
        path: PathBuf,
        /// What reading it failed with.
        source: std::io::Error,
    },
    /// Not TOML, or a key or type the types do not have (serde's message names the line).
    #[error("{path}: {message}")]
    Parse {
        /// The machine file.
        path: PathBuf,
        /// toml's message: the key, the line and what was wrong.
        message: String,
    },
    /// A value out of its range, or sections that contradict each other.
    #[error("{key}: {message}")]
    Invalid {
        /// The key refused, as a path into the file (`axes[0].max_vel`).
        key: String,
        /// What the key must be.
        message: String,
    },
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

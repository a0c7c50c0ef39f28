//! `[web]`: the web view of `--http` (docs/decisions.md, "Web view security").

use serde::Deserialize;

use crate::error::{ConfigError, bind_address, invalid};

/// `[web]`: the web view of `--http PORT` (docs/decisions.md, "Web view security").
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WebConfig {
    /// The address it listens on. Default 127.0.0.1; `luamotion serve --bind` overrides it.
    pub bind: String,
    /// Host names, besides the bound address (and `localhost` on a loopback bind), that a
    /// request's `Host` may name: the names the operator's browser reaches the controller
    /// by. Any other name is refused, so that a rebinding DNS name cannot reach the view.
    pub allowed_hosts: Vec<String>,
    /// When set, the page asks for it before it takes commands. Without it, a bind other
    /// than loopback serves read-only.
    pub password: Option<String>,
    /// Connections served at once (each open page holds one); more are closed.
    pub max_connections: u32,
    /// A connection that sends no whole request head for this long is closed, ms.
    pub header_timeout_ms: u64,
}

impl Default for WebConfig {
    fn default() -> Self {
        WebConfig {
            bind: "127.0.0.1".into(),
            allowed_hosts: Vec::new(),
            password: None,
            max_connections: 32,
            header_timeout_ms: 10_000,
        }
    }
}

impl WebConfig {
    pub(crate) fn validate(&self) -> Result<(), ConfigError> {
        bind_address("web.bind", &self.bind)?;
        for (i, name) in self.allowed_hosts.iter().enumerate() {
            let host_name = |c: char| c.is_ascii_alphanumeric() || c == '-' || c == '.';
            if name.is_empty() || !name.chars().all(host_name) {
                let message = format!("{name:?} is not a host name (letters, digits, '-' and '.'; no port)");
                return Err(invalid(format!("web.allowed_hosts[{i}]"), message));
            }
        }
        if self.password.as_ref().is_some_and(|p| p.is_empty()) {
            return Err(invalid("web.password", "must not be empty (leave it out for no password)"));
        }
        if !(1..=4096).contains(&self.max_connections) {
            return Err(invalid("web.max_connections", "must be 1..4096"));
        }
        if self.header_timeout_ms == 0 {
            return Err(invalid("web.header_timeout_ms", "must be at least 1 ms"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `[web]`: a host name without a port, a password that is not empty, limits in range.
    #[test]
    fn the_web_section_is_checked() {
        let key = |text: &str| match toml::from_str::<WebConfig>(text).unwrap().validate() {
            Err(ConfigError::Invalid { key, .. }) => key,
            other => panic!("{text}: {other:?}"),
        };
        assert_eq!(key("allowed_hosts = [\"cell-7.local\", \"cell-7:8080\"]"), "web.allowed_hosts[1]");
        assert_eq!(key("allowed_hosts = [\"\"]"), "web.allowed_hosts[0]");
        assert_eq!(key("password = \"\""), "web.password");
        assert_eq!(key("max_connections = 0"), "web.max_connections");
        assert_eq!(key("header_timeout_ms = 0"), "web.header_timeout_ms");
        let web: WebConfig = toml::from_str("allowed_hosts = [\"cell-7.local\"]\npassword = \"s3cret\"\n").unwrap();
        assert!(web.validate().is_ok());
    }
}

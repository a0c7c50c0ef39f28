//! `[identity]`: what `GetModelNum` and `GetSerialNum` report (HMPL 2.14, 2.15).

use serde::Deserialize;

use crate::error::{ConfigError, invalid};

/// `[identity]`: the controller's product model and serial number (HMPL 2.14, 2.15).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct IdentityConfig {
    /// At most 64 bytes.
    pub model: String,
    /// At most 64 bytes.
    pub serial: String,
}

impl Default for IdentityConfig {
    fn default() -> Self {
        IdentityConfig { model: "luamotion-sim".into(), serial: "LM00000000".into() }
    }
}

impl IdentityConfig {
    pub(crate) fn validate(&self) -> Result<(), ConfigError> {
        for (key, text) in [("identity.model", &self.model), ("identity.serial", &self.serial)] {
            if text.len() > 64 || text.contains('\0') {
                return Err(invalid(key, "at most 64 bytes, no NUL"));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// HMPL 2.14, 2.15: `[identity]` has defaults; what does not fit 64 bytes is refused.
    #[test]
    fn identity_of_the_controller() {
        let identity: IdentityConfig = toml::from_str("").unwrap();
        assert_eq!((identity.model.as_str(), identity.serial.as_str()), ("luamotion-sim", "LM00000000"));
        let identity: IdentityConfig = toml::from_str("serial = \"SN 7\"\n").unwrap();
        assert_eq!((identity.model.as_str(), identity.serial.as_str()), ("luamotion-sim", "SN 7"));
        assert!(identity.validate().is_ok());
        let long = "m".repeat(65);
        let identity: IdentityConfig = toml::from_str(&format!("model = \"{long}\"\n")).unwrap();
        assert!(matches!(identity.validate(), Err(ConfigError::Invalid { key, .. }) if key == "identity.model"));
    }
}

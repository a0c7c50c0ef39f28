//! `[freeport]`: the programs' `FreePort.Eth` servers (DXMC 8.3).

use serde::Deserialize;

use crate::error::bind_address;

/// `[freeport]`: where `FreePort.Eth.OpenAsServer` listens (DXMC 8.3 names only the port).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FreePortConfig {
    /// The address programs' servers listen on. Default 127.0.0.1: serving other hosts
    /// is a choice made here, as for `[modbus]` and `[ascii]`.
    #[serde(deserialize_with = "freeport_bind")]
    pub bind: std::net::IpAddr,
}

/// `[freeport] bind`, refused with the same words as the other bind addresses.
fn freeport_bind<'de, D: serde::Deserializer<'de>>(deserializer: D) -> Result<std::net::IpAddr, D::Error> {
    let value = String::deserialize(deserializer)?;
    bind_address("freeport.bind", &value).map_err(serde::de::Error::custom)
}

impl Default for FreePortConfig {
    fn default() -> Self {
        FreePortConfig { bind: std::net::IpAddr::from([127, 0, 0, 1]) }
    }
}

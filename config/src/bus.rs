//! `[bus]`: where the EtherCAT segment is.

use serde::Deserialize;

use crate::error::{ConfigError, invalid};

/// `[bus]`: without `interface` the segment is the simulated one in the controller's
/// memory; with it, the core is an EtherCAT MainDevice on that network interface and the
/// axes' drives and `[[slaves]]` are what it must find there, in ring order.
#[derive(Clone, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(deny_unknown_fields, default)]
pub struct BusConfig {
    /// The network interface of the segment (`eth1`, an end of a veth pair); the core
    /// needs CAP_NET_RAW on it.
    pub interface: Option<String>,
}

impl BusConfig {
    pub(crate) fn validate(&self) -> Result<(), ConfigError> {
        match &self.interface {
            // Linux interface names: 1 to 15 bytes, no '/', no white space (IFNAMSIZ).
            Some(name) if name.is_empty() || name.len() > 15 || name.contains(['/', ' ', '\t']) => {
                Err(invalid("bus.interface", format!("{name:?} is not a network interface name")))
            }
            _ => Ok(()),
        }
    }
}

//! The per-controller namespace: every service and shared-memory region of one
//! controller lives under it, so that controllers (and parallel tests) run side by side.

use iceoryx2::config::Config;
use iceoryx2::prelude::*;
use iceoryx2_bb_container::semantic_string::SemanticString;
use iceoryx2_bb_system_types::file_name::FileName;
use iceoryx2_bb_system_types::path::Path;

use crate::error::IpcError;

const MAX_LEN: usize = 40;

/// iceoryx2's root folder (its `nodes` and `services` folders), in memory rather than
/// iceoryx2's default `/tmp/iceoryx2`: every node and every service a process opens writes
/// a file there and fsyncs it, and on a disk each fsync waits for the disk (5-20 ms while
/// builds write), which was most of a task's start (`rt-core/src/pool.rs`).
const ICEORYX2_ROOT: &str = "/dev/shm/iceoryx2/";

/// iceoryx2's defaults with luamotion's root folder.
pub(crate) fn base_config() -> Config {
    let mut config = Config::default();
    config.global.set_root_path(&Path::new(ICEORYX2_ROOT.as_bytes()).expect("a valid absolute path"));
    config
}

#[derive(Clone, Debug, PartialEq, Eq)]
/// A controller's namespace (`--ns`): every service and file of one controller carries it.
pub struct Namespace(String);

impl Namespace {
    /// A namespace is 1 to 40 characters of `A-Z a-z 0-9 _ -`.
    pub fn new(name: &str) -> Result<Self, IpcError> {
        let valid = !name.is_empty()
            && name.len() <= MAX_LEN
            && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-');
        if valid { Ok(Namespace(name.to_string())) } else { Err(IpcError::Namespace(name.to_string())) }
    }

    /// The name as given.
    pub fn as_str(&self) -> &str {
        &self.0
    }

    /// Prefix of every file iceoryx2 creates for this controller.
    pub fn prefix(&self) -> String {
        format!("lm.{}.", self.0)
    }

    /// The iceoryx2 configuration of this namespace: its own file prefix, no config file
    /// read from disk, and dead nodes cleaned when services are opened.
    pub fn config(&self) -> Config {
        let mut config = base_config();
        config.global.prefix =
            FileName::new(self.prefix().as_bytes()).expect("a validated namespace is a valid file name");
        config.global.node.cleanup_dead_nodes_on_creation = true;
        config.global.service.cleanup_dead_nodes_on_open = true;
        config
    }

    /// The iceoryx2 service name of `path` within this namespace.
    pub fn service_name(&self, path: &str) -> Result<ServiceName, IpcError> {
        let name = format!("luamotion/{}/{path}", self.0);
        ServiceName::new(&name).map_err(|e| IpcError::Service { what: name, source: e.into() })
    }
}

impl std::fmt::Display for Namespace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn namespaces_are_short_file_safe_names() {
        assert!(Namespace::new("luamotion").is_ok());
        assert!(Namespace::new("test-42_a").is_ok());
        assert!(Namespace::new("").is_err());
        assert!(Namespace::new("a/b").is_err());
        assert!(Namespace::new(&"x".repeat(41)).is_err());
    }
}

//! A tool's view of a running controller (`luamotion tasks`): its newest snapshot and its
//! task table, read without taking part in the cycle.

use iceoryx2::prelude::*;
use iceoryx2::sample::Sample;

use crate::messages::Snapshot;
use crate::services::{self, Ipc, Open, StateSubscriber, failed};
use crate::shm::Region;
use crate::task_table::TaskTable;
use crate::{IpcError, Namespace};

/// A tool's read-only view of a running controller: its snapshot and its task table.
pub struct Monitor {
    state: StateSubscriber,
    latest: Option<Sample<Ipc, Snapshot, ()>>,
    table: Region<TaskTable>,
    _node: Node<Ipc>,
}

/// How long `open` waits for a controller that is still creating its services.
const OPEN_PATIENCE: std::time::Duration = std::time::Duration::from_secs(2);

impl Monitor {
    /// Opens the controller's state and task table, waiting briefly for a controller that
    /// is still starting.
    pub fn open(ns: &Namespace) -> Result<Self, IpcError> {
        let deadline = std::time::Instant::now() + OPEN_PATIENCE;
        loop {
            match Self::try_open(ns) {
                Ok(monitor) => return Ok(monitor),
                Err(e) if std::time::Instant::now() > deadline => return Err(e),
                Err(_) => std::thread::sleep(std::time::Duration::from_millis(10)),
            }
        }
    }

    fn try_open(ns: &Namespace) -> Result<Self, IpcError> {
        let node = services::node(ns, &format!("luamotion-monitor-{}", std::process::id()))?;
        let state = services::state(&node, ns, Open::Existing)?
            .subscriber_builder()
            .create()
            .map_err(|e| failed("state subscriber", e))?;
        let table = Region::<TaskTable>::open(ns, "tasks")?;
        Ok(Monitor { state, latest: None, table, _node: node })
    }

    /// The newest snapshot, waiting up to a second for the first one.
    pub fn snapshot(&mut self) -> Result<&Snapshot, IpcError> {
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(1);
        loop {
            self.refresh();
            if self.latest.is_some() || std::time::Instant::now() > deadline {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        self.latest.as_deref().ok_or_else(|| IpcError::Service("no snapshot from the controller".into()))
    }

    /// Takes the snapshots published since the last look, without waiting.
    pub fn refresh(&mut self) {
        while let Ok(Some(sample)) = self.state.receive() {
            self.latest = Some(sample);
        }
    }

    /// The newest snapshot taken by `refresh` or `snapshot`.
    pub fn latest(&self) -> Option<&Snapshot> {
        self.latest.as_deref()
    }

    /// The controller's task table.
    pub fn table(&self) -> &TaskTable {
        &self.table
    }
}

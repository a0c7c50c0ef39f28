//! A tool's view of a running controller (`luamotion tasks`): its newest snapshot and its
//! task table, read without taking part in the cycle.

use schema::Snapshot;

use crate::error::IpcError;
use crate::namespace::Namespace;
use crate::shm::Region;
use crate::snapshot_board::{BoardReader, SnapshotBoard};
use crate::task_table::TaskTable;

/// A tool's read-only view of a running controller: its snapshot and its task table.
pub struct Monitor {
    state: BoardReader<Snapshot>,
    table: Region<TaskTable>,
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
        let state = BoardReader::tool(SnapshotBoard::open(ns)?)?;
        let table = Region::<TaskTable>::open(ns, "tasks")?;
        Ok(Monitor { state, table })
    }

    /// The newest snapshot, waiting up to a second for the first one.
    pub fn snapshot(&mut self) -> Result<&Snapshot, IpcError> {
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(1);
        while self.state.latest().is_none() && std::time::Instant::now() < deadline {
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        self.state.latest().ok_or(IpcError::NoSnapshot)
    }

    /// Takes the newest snapshot, without waiting.
    pub fn refresh(&mut self) {
        self.state.refresh();
    }

    /// The newest snapshot taken by `refresh` or `snapshot`.
    pub fn latest(&self) -> Option<&Snapshot> {
        self.state.pinned()
    }

    /// The controller's task table.
    pub fn table(&self) -> &TaskTable {
        &self.table
    }
}

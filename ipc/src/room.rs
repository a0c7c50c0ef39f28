//! The room one controller takes in `/dev/shm` with every task and tool attached, checked
//! before anything is created, and the advice when a service or region finds it used up.

use schema::shared::SharedData;
use schema::{MAX_TASKS, Snapshot};

use crate::advice::failed;
use crate::error::{IpcError, Refusal, Shortage};
use crate::event_record::EventRecord;
use crate::files;
use crate::limits::{EVENT_BORROWED, EVENT_BUFFER, EVENT_HISTORY, MAX_EVENT_READERS, MAX_NODES, MAX_TOOLS};
use crate::snapshot_board::SnapshotBoard;
use crate::task_table::TaskTable;

/// A service or port the controller creates, sized for every task and tool, failed:
/// says what it was sized for and what the OS has.
pub(crate) fn too_big(what: &str, e: impl Into<Refusal>) -> IpcError {
    match failed(what, e) {
        IpcError::Service { what, source } => {
            IpcError::Capacity { what, shortage: Shortage::Refused(source), advice: room_advice() }
        }
        other => other,
    }
}

/// A region the controller creates failed for want of room: says what it was sized for.
pub(crate) fn region_too_big(what: &str, e: IpcError) -> IpcError {
    match e {
        IpcError::Shm { what: region, source } => IpcError::Capacity {
            what: what.to_string(),
            shortage: Shortage::Region { what: region, source },
            advice: room_advice(),
        },
        other => other,
    }
}

/// Shared memory one controller takes when every task and tool is attached, bytes:
/// iceoryx2 gives each publisher a data segment of `subscribers * (buffer + borrowed) +
/// history + loaned` samples, each with a header; plus the snapshot board, the task table
/// (the tasks' call mailboxes in it) and shared data.
pub fn planned_shm_bytes() -> usize {
    const LOANED: usize = 2;
    // iceoryx2's sample header and alignment, as measured in 0.10 (52 bytes).
    const SAMPLE_OVERHEAD: usize = 64;
    let segment = |subscribers: usize, buffer: usize, borrowed: usize, history: usize, sample: usize| {
        (subscribers * (buffer + borrowed) + history + LOANED) * (sample + SAMPLE_OVERHEAD)
    };
    // One writer per task, the supervisor and the DRL console.
    let events = (MAX_TASKS + 2)
        * segment(MAX_EVENT_READERS, EVENT_BUFFER, EVENT_BORROWED, EVENT_HISTORY, size_of::<EventRecord>());
    events + size_of::<SnapshotBoard<Snapshot>>() + size_of::<TaskTable>() + size_of::<SharedData>()
}

/// Refuses to start a controller where `/dev/shm` has no room for `planned_shm_bytes`,
/// rather than failing the 40th task when it attaches.
pub fn check_room() -> Result<(), IpcError> {
    match files::shm_free_bytes() {
        Some(free) if free < planned_shm_bytes() => Err(IpcError::Capacity {
            what: "shared memory".into(),
            shortage: Shortage::Room { free_mib: free >> 20 },
            advice: room_advice(),
        }),
        _ => Ok(()),
    }
}

fn room_advice() -> String {
    let free = files::shm_free_bytes().map_or("unknown".to_string(), |b| format!("{} MiB", b >> 20));
    format!(
        "the services are sized for {MAX_TASKS} tasks and {MAX_TOOLS} attached tools ({MAX_NODES} nodes) and need \
         about {} MiB of shared memory; {free} free in /dev/shm. Give /dev/shm more room (a container: \
         `--shm-size=256m`) and, where luamotion may lock memory, raise `ulimit -l`",
        planned_shm_bytes().div_ceil(1 << 20)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every task and tool at once must fit a container's default `/dev/shm` (64 MiB)
    /// with room to spare (measured: 39.8 MiB with 64 tasks and 96 axes; the snapshot, held
    /// by every reader, is most of it).
    #[test]
    fn the_services_of_64_tasks_fit_a_small_dev_shm() {
        let mib = planned_shm_bytes() as f64 / (1 << 20) as f64;
        println!("planned shared memory: {mib:.1} MiB");
        assert!(mib < 40.0, "{mib:.1} MiB");
    }
}

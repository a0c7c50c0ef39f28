//! A task in the snapshot (HMPL ch. 16).

use num_enum::{FromPrimitive, IntoPrimitive};

/// A task as the core sees it (HMPL ch. 16): `IsTaskStop` is true unless it is starting
/// or running. An unknown word reads as `Empty`, the state of a zeroed snapshot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, FromPrimitive, IntoPrimitive)]
#[repr(u32)]
pub enum TaskState {
    /// No program configured for this id (`StartTask` gives 0x010A).
    #[default]
    Empty = 0,
    /// Has a program, not running.
    Stopped = 1,
    /// Its process is being started; `StartTask` returns once it runs.
    Starting = 2,
    /// Its program runs.
    Running = 3,
    /// Stopped by `StopTask`, `StopAllTask` or an E-stop; its process is being ended.
    Stopping = 4,
    /// Ended by a fault (watchdog, crash, runtime error): see its alarm.
    Error = 5,
}

impl TaskState {
    /// HMPL 16.6: `IsTaskStop`.
    pub fn is_stopped(self) -> bool {
        !matches!(self, TaskState::Starting | TaskState::Running)
    }

    /// The state's name for the tools.
    pub fn name(self) -> &'static str {
        match self {
            TaskState::Empty => "empty",
            TaskState::Stopped => "stopped",
            TaskState::Starting => "starting",
            TaskState::Running => "running",
            TaskState::Stopping => "stopping",
            TaskState::Error => "error",
        }
    }
}

/// One task slot in the snapshot.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
pub struct TaskSnapshot {
    /// `TaskState` as a number.
    pub state: u32,
    /// The last alarm raised for this task (DXMC format, 0: none).
    pub alarm: u32,
    /// The script process, 0 when none.
    pub pid: u32,
    /// Its watchdog time, ms (0: none).
    pub watchdog_ms: u32,
    /// Its run speed, % of the programmed velocity (DXMC A.3, 0x6B03; 100 but for a
    /// DRL project).
    pub run_speed_pct: u32,
}

#[cfg(test)]
mod tests {
    use super::TaskState;

    /// The task states as the snapshot carries them; an unknown word reads as `Empty`.
    #[test]
    fn task_state_words() {
        let rows = [
            (TaskState::Empty, 0u32),
            (TaskState::Stopped, 1),
            (TaskState::Starting, 2),
            (TaskState::Running, 3),
            (TaskState::Stopping, 4),
            (TaskState::Error, 5),
        ];
        for (state, word) in rows {
            assert_eq!(u32::from(state), word, "{state:?}");
            assert_eq!(TaskState::from(word), state, "word {word}");
        }
        for word in [6, 0x100, u32::MAX] {
            assert_eq!(TaskState::from(word), TaskState::Empty, "word {word}");
        }
    }
}

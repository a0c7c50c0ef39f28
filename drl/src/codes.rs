//! The codes of the DRL registers, DXMC manual appendix A.3 ("程序流程"): execution state
//! (0x6B01), control commands (0x6B05) and status (0x6B06). An unknown code of any of
//! them is an error (`TryFromPrimitive`): the caller answers it as the manual says.

use num_enum::{IntoPrimitive, TryFromPrimitive};

/// DXMC A.3, register 0x6B01: the current DRL execution state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, TryFromPrimitive, IntoPrimitive)]
#[repr(u16)]
pub enum ExecState {
    /// No project opened.
    Close = 0,
    /// The project's program runs.
    Running = 1,
    /// The program stopped at a breakpoint (0x6B02 shows the line).
    BreakPoint = 2,
    /// The program is paused by Pause, a step or Block Run.
    Pause = 3,
    /// Opened, waiting for a run command.
    PreRun = 4,
}

impl ExecState {
    /// The program runs (or is stopped inside its run by the debugger).
    pub fn is_running(self) -> bool {
        matches!(self, ExecState::Running | ExecState::BreakPoint | ExecState::Pause)
    }

    /// The manual's name (DXMC A.3).
    pub fn name(self) -> &'static str {
        match self {
            ExecState::Close => "Close",
            ExecState::Running => "Running",
            ExecState::BreakPoint => "Break Point",
            ExecState::Pause => "Pause",
            ExecState::PreRun => "Pre-Run",
        }
    }
}

/// DXMC A.3, register 0x6B05: the DRL control commands, by code; any other code is
/// alarm 0x7000.
#[derive(Clone, Copy, Debug, PartialEq, Eq, TryFromPrimitive, IntoPrimitive)]
#[repr(u16)]
pub enum Control {
    /// Checks and opens the project selected in 0x6B04.
    Open = 1,
    /// Runs the opened project, breakpoints ignored.
    ReleaseRun = 2,
    /// Stops the program and closes the project.
    Stop = 3,
    /// Pauses the program at its next line of `main.lua`.
    Pause = 4,
    /// Open, then Release Run.
    OpenAndReleaseRun = 6,
    /// Debug: one line, into a called function.
    StepInto = 11,
    /// Debug: one line, over calls.
    StepOver = 12,
    /// Debug: on to the caller's next line.
    StepOut = 13,
    /// A Debug Run that stops before the first line (docs/decisions.md: the manual does
    /// not describe it).
    BlockRun = 21,
    /// Open, then Block Run.
    OpenAndBlockRun = 22,
    /// Runs the opened project, stopping at its breakpoints.
    DebugRun = 44,
    /// Open, then Debug Run.
    OpenAndDebugRun = 45,
    /// FTP area -> USB.
    ExportProject = 31,
    /// USB -> FTP area.
    ImportProject = 32,
    /// Before a run: the breakpoints 0x6B07..0x6B0E name (at most 8).
    SetBp = 41,
    /// One breakpoint more, at the line in 0x6B07 (during a run it reaches the debugger
    /// at
    /// once).
    AddBp = 42,
    /// Removes the breakpoint at the line in 0x6B07.
    DeleteBp = 43,
}

/// DXMC A.3, register 0x6B06: the DRL status display. Each command family has a
/// "cannot", an "in progress" and a "done" code.
#[derive(Clone, Copy, Debug, PartialEq, Eq, TryFromPrimitive, IntoPrimitive)]
#[repr(u16)]
pub enum Status {
    /// BUSY: a command is on its way (a start not yet seen, a pause waiting for a line).
    Busy = 0,
    /// CHECKING: Open checks the project's `main.lua`.
    Checking = 1,
    /// FAILED: the program ended with an error, or an import was refused.
    Failed = 2,
    /// CANNOT_OPEN: no such project, or it does not compile.
    CannotOpen = 10,
    /// OPENING: Open under way.
    Opening = 11,
    /// OPENED: the project is open (state Pre-Run).
    Opened = 12,
    /// CANNOT_RUN: no project open, or the core refused the start.
    CannotRun = 20,
    /// RUNNING: the run command is done.
    Running = 21,
    /// CANNOT_STOP: nothing to stop.
    CannotStop = 30,
    /// STOPPING: Stop under way.
    Stopping = 31,
    /// STOPPED: the program ended, or was stopped.
    Stopped = 32,
    /// CANNOT_PAUSE: the program does not run.
    CannotPause = 40,
    /// PAUSED: the program stands at a line.
    Paused = 41,
    /// CANNOT_STEP: the program is not at a breakpoint or paused.
    CannotStep = 50,
    /// STEPPED: the step is done.
    Stepped = 51,
    /// PASSWORD_ERROR (export and import); never sent here, no password is asked.
    PasswordError = 60,
    /// FTP_ID_ERROR: export of a project the FTP area does not hold.
    FtpIdError = 61,
    /// USB_MOUNT_ERROR: the export folder could not be written.
    UsbMountError = 62,
    /// EXPORTING: export under way.
    Exporting = 63,
    /// USB_UNMOUNT_ERROR; never sent here, the export folder is not unmounted.
    UsbUnmountError = 64,
    /// EXPORT_DONE: the project is in the export folder.
    ExportDone = 65,
    /// USB_ID_CHECKING: import under way, checking the exported project.
    UsbIdChecking = 66,
    /// USB_ID_ERROR: import of a project the export folder does not hold.
    UsbIdError = 67,
    /// IMPORTING: import under way.
    Importing = 68,
    /// IMPORT_DONE: the project is back in the FTP area.
    ImportDone = 69,
    /// CANNOT_SETBP: Set BP during a run, or a line past the end of `main.lua`.
    CannotSetBp = 70,
    /// BP_SETTING: Set BP under way.
    BpSetting = 71,
    /// BP_SET: the breakpoints are set for the next run.
    BpSet = 72,
    /// CANNOT_ADDBP: no line, a line already set, 8 set before a run, or one the debugger
    /// refuses.
    CannotAddBp = 73,
    /// BP_ADDED: the breakpoint is added.
    BpAdded = 74,
    /// CANNOT_DELETEBP: no breakpoint at that line.
    CannotDeleteBp = 75,
    /// BP_DELETED: the breakpoint is gone.
    BpDeleted = 76,
}

/// Every status with the manual's name (DXMC A.3), in code order.
const STATUS_NAMES: [(Status, &str); 32] = [
    (Status::Busy, "BUSY"),
    (Status::Checking, "CHECKING"),
    (Status::Failed, "FAILED"),
    (Status::CannotOpen, "CANNOT_OPEN"),
    (Status::Opening, "OPENING"),
    (Status::Opened, "OPENED"),
    (Status::CannotRun, "CANNOT_RUN"),
    (Status::Running, "RUNNING"),
    (Status::CannotStop, "CANNOT_STOP"),
    (Status::Stopping, "STOPPING"),
    (Status::Stopped, "STOPPED"),
    (Status::CannotPause, "CANNOT_PAUSE"),
    (Status::Paused, "PAUSED"),
    (Status::CannotStep, "CANNOT_STEP"),
    (Status::Stepped, "STEPPED"),
    (Status::PasswordError, "PASSWORD_ERROR"),
    (Status::FtpIdError, "FTP_ID_ERROR"),
    (Status::UsbMountError, "USB_MOUNT_ERROR"),
    (Status::Exporting, "EXPORTING"),
    (Status::UsbUnmountError, "USB_UNMOUNT_ERROR"),
    (Status::ExportDone, "EXPORT_DONE"),
    (Status::UsbIdChecking, "USB_ID_CHECKING"),
    (Status::UsbIdError, "USB_ID_ERROR"),
    (Status::Importing, "IMPORTING"),
    (Status::ImportDone, "IMPORT_DONE"),
    (Status::CannotSetBp, "CANNOT_SETBP"),
    (Status::BpSetting, "BP_SETTING"),
    (Status::BpSet, "BP_SET"),
    (Status::CannotAddBp, "CANNOT_ADDBP"),
    (Status::BpAdded, "BP_ADDED"),
    (Status::CannotDeleteBp, "CANNOT_DELETEBP"),
    (Status::BpDeleted, "BP_DELETED"),
];

impl Status {
    /// The manual's name (DXMC A.3), e.g. `CANNOT_OPEN`.
    pub fn name(self) -> &'static str {
        STATUS_NAMES.iter().find(|(s, _)| *s == self).map_or("", |(_, name)| name)
    }

    /// The command was not carried out: FAILED, the CANNOT_x codes and the
    /// export/import errors (DXMC A.3).
    pub fn is_failure(self) -> bool {
        use Status::*;
        matches!(
            self,
            Failed
                | CannotOpen
                | CannotRun
                | CannotStop
                | CannotPause
                | CannotStep
                | PasswordError
                | FtpIdError
                | UsbMountError
                | UsbUnmountError
                | UsbIdError
                | CannotSetBp
                | CannotAddBp
                | CannotDeleteBp
        )
    }

    /// The statuses that still change by themselves (DXMC A.3): BUSY, CHECKING, OPENING,
    /// STOPPING, EXPORTING, USB_ID_CHECKING, IMPORTING, BP_SETTING.
    pub fn in_progress(code: u16) -> bool {
        use Status::*;
        Status::try_from(code).is_ok_and(|s| {
            matches!(s, Busy | Checking | Opening | Stopping | Exporting | UsbIdChecking | Importing | BpSetting)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// DXMC A.3, 0x6B01.
    #[test]
    fn execution_states() {
        let rows = [
            (ExecState::Close, 0),
            (ExecState::Running, 1),
            (ExecState::BreakPoint, 2),
            (ExecState::Pause, 3),
            (ExecState::PreRun, 4),
        ];
        for (state, code) in rows {
            assert_eq!(state as u16, code, "{state:?}");
            assert_eq!(ExecState::try_from(code).ok(), Some(state));
        }
        assert_eq!(ExecState::PreRun.name(), "Pre-Run");
        assert_eq!(ExecState::try_from(5).ok(), None);
    }

    /// DXMC A.3, 0x6B05; codes not in the table are alarm 0x7000 (DXMC 9).
    #[test]
    fn control_codes() {
        let rows = [
            (1, Control::Open),
            (2, Control::ReleaseRun),
            (3, Control::Stop),
            (4, Control::Pause),
            (6, Control::OpenAndReleaseRun),
            (11, Control::StepInto),
            (12, Control::StepOver),
            (13, Control::StepOut),
            (21, Control::BlockRun),
            (22, Control::OpenAndBlockRun),
            (44, Control::DebugRun),
            (45, Control::OpenAndDebugRun),
            (31, Control::ExportProject),
            (32, Control::ImportProject),
            (41, Control::SetBp),
            (42, Control::AddBp),
            (43, Control::DeleteBp),
        ];
        for (code, control) in rows {
            assert_eq!(Control::try_from(code).ok(), Some(control), "code {code}");
        }
        let valid: Vec<u16> = rows.iter().map(|r| r.0).collect();
        for code in (0..=100).filter(|c| !valid.contains(c)) {
            assert_eq!(Control::try_from(code).ok(), None, "code {code} is not a DRL control command");
        }
    }

    /// DXMC A.3, 0x6B06.
    #[test]
    fn status_codes() {
        use Status::*;
        let rows = [
            (Busy, 0),
            (Checking, 1),
            (Failed, 2),
            (CannotOpen, 10),
            (Opening, 11),
            (Opened, 12),
            (CannotRun, 20),
            (Running, 21),
            (CannotStop, 30),
            (Stopping, 31),
            (Stopped, 32),
            (CannotPause, 40),
            (Paused, 41),
            (CannotStep, 50),
            (Stepped, 51),
            (PasswordError, 60),
            (FtpIdError, 61),
            (UsbMountError, 62),
            (Exporting, 63),
            (UsbUnmountError, 64),
            (ExportDone, 65),
            (UsbIdChecking, 66),
            (UsbIdError, 67),
            (Importing, 68),
            (ImportDone, 69),
            (CannotSetBp, 70),
            (BpSetting, 71),
            (BpSet, 72),
            (CannotAddBp, 73),
            (BpAdded, 74),
            (CannotDeleteBp, 75),
            (BpDeleted, 76),
        ];
        for (status, code) in rows {
            assert_eq!(status as u16, code, "{status:?}");
            assert_eq!(Status::try_from(code).ok(), Some(status));
            let name = status.name();
            assert!(!name.is_empty() && name.chars().all(|c| c.is_ascii_uppercase() || c == '_'), "{name}");
            assert_eq!(status.is_failure(), name.contains("CANNOT") || name.contains("ERROR") || name == "FAILED");
        }
        assert_eq!(Status::CannotOpen.name(), "CANNOT_OPEN");
        assert_eq!(Status::try_from(3).ok(), None);
        let settling = [0, 1, 11, 31, 63, 66, 68, 71];
        for code in 0..=80 {
            assert_eq!(Status::in_progress(code), settling.contains(&code), "status {code}");
        }
    }
}

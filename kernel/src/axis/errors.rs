//! An axis' error state: ErrorStop (HMPL 5.2.3), the fault bits of `fault_status`
//! (table 5.1.1.4), its last error (18.3), the drive's error code, and the E-stop's
//! refusal of motion (2.9).

use schema::fault_status;

/// What went wrong on an axis, and what it refuses until it is reset or enabled again.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct ErrorState {
    /// HMPL 5.2.3: ErrorStop, left by `Reset`.
    error_stop: bool,
    /// fault_status bits other than ErrorStop.
    faults: u32,
    /// HMPL 18.3: the code `GetAxisLastErr` answers, 0 for none: an axis error
    /// (`0x83IIEEEE`), or the alarm of another task's stop that cut this axis' motion short.
    last_err: u32,
    /// The drive's error code (0x603F) of its last fault.
    drive_err: u16,
    /// Stopped by an E-stop: motion is refused with 0x0064 until the axis is enabled again.
    emergency_stopped: bool,
}

impl ErrorState {
    pub(super) fn is_error_stop(&self) -> bool {
        self.error_stop
    }

    /// `fault_status` bits but ErrorStop (HMPL table 5.1.1.4).
    pub(super) fn faults(&self) -> u32 {
        self.faults
    }

    pub(super) fn last_err(&self) -> u32 {
        self.last_err
    }

    pub(super) fn drive_err(&self) -> u16 {
        self.drive_err
    }

    pub(super) fn is_emergency_stopped(&self) -> bool {
        self.emergency_stopped
    }

    /// HMPL 18.3: `code` becomes the last error; 0 clears it.
    pub(super) fn record(&mut self, code: u32) {
        self.last_err = code;
    }

    /// Into ErrorStop, with the fault bits `faults` set.
    pub(super) fn enter_error_stop(&mut self, faults: u32) {
        self.error_stop = true;
        self.faults |= faults;
    }

    /// The drive faulted with its error code `drive_err`.
    pub(super) fn drive_fault(&mut self, drive_err: u16) {
        self.enter_error_stop(fault_status::DRIVE_FAULT);
        self.drive_err = drive_err;
    }

    /// A hardware limit switch's bit follows the switch.
    pub(super) fn set_limit_switch(&mut self, bit: u32, active: bool) {
        if active { self.faults |= bit } else { self.faults &= !bit }
    }

    /// Leaves ErrorStop (HMPL 5.2.3): the other faults clear, the limit switches' bits
    /// stay, since the switches still say where they are.
    pub(super) fn reset(&mut self) {
        self.error_stop = false;
        self.faults &= fault_status::HW_LEFT_LIMIT | fault_status::HW_RIGHT_LIMIT;
    }

    pub(super) fn set_emergency_stopped(&mut self, stopped: bool) {
        self.emergency_stopped = stopped;
    }
}

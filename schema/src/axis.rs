//! One axis in the snapshot (HMPL ch. 5): its status bits and the variables the status
//! and `Get*` functions read.

/// HMPL table 5.1.1.5: the bits of an axis' `motion_status`.
pub mod motion_status {
    /// Bit 0: the axis is enabled.
    pub const ENABLED: u32 = 1 << 0;
    /// Bit 1: the axis is moving.
    pub const MOVING: u32 = 1 << 1;
    /// Bit 2: in position.
    pub const IN_POSITION: u32 = 1 << 2;
    /// Bit 3: in a synchronous motion (gear, cam).
    pub const SYNCHRONOUS: u32 = 1 << 3;
    /// Bit 4: a member of a group.
    pub const GROUP: u32 = 1 << 4;
    /// Bit 5: a member of a gantry pair.
    pub const GANTRY: u32 = 1 << 5;
    /// Bit 6: input shaping on.
    pub const INPUT_SHAPE: u32 = 1 << 6;
    /// Bit 7: VSF on.
    pub const VSF: u32 = 1 << 7;
    /// Bit 8: geared to a master.
    pub const GEAR: u32 = 1 << 8;
    /// Bit 9: following a cam.
    pub const CAM: u32 = 1 << 9;
    /// Bit 10: accelerating.
    pub const ACCELERATING: u32 = 1 << 10;
    /// Bit 11: homed.
    pub const HOMED: u32 = 1 << 11;
    /// Bit 12: homing.
    pub const HOMING: u32 = 1 << 12;
    /// Bit 13: the home switch is on.
    pub const HOME_SWITCH: u32 = 1 << 13;
}

/// HMPL table 5.1.1.4: the bits of an axis' `fault_status`.
pub mod fault_status {
    /// Bit 0: stopped by an error.
    pub const ERROR_STOP: u32 = 1 << 0;
    /// Bit 1: the drive is in fault.
    pub const DRIVE_FAULT: u32 = 1 << 1;
    /// Bit 2: following error too large.
    pub const POSITION_ERROR: u32 = 1 << 2;
    /// Bit 3: the right (positive) hardware limit.
    pub const HW_RIGHT_LIMIT: u32 = 1 << 3;
    /// Bit 4: the left (negative) hardware limit.
    pub const HW_LEFT_LIMIT: u32 = 1 << 4;
    /// Bit 5: the right (positive) software limit.
    pub const SW_RIGHT_LIMIT: u32 = 1 << 5;
    /// Bit 6: the left (negative) software limit.
    pub const SW_LEFT_LIMIT: u32 = 1 << 6;
}

/// One axis as the kernel saw it at the end of a cycle (HMPL tables 5.1.1.1 to 5.1.1.6):
/// the variables and settings the status and `Get*` functions read.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
pub struct AxisSnapshot {
    /// `motion_status` bits (HMPL table 5.1.1.5).
    pub motion_status: u32,
    /// `fault_status` bits (HMPL table 5.1.1.4).
    pub fault_status: u32,
    /// The axis' last HMPL error code (HMPL 18.3).
    pub last_err: u32,
    /// The drive's own error code, 0x603F (HMPL 18.7).
    pub drive_err: u32,
    /// The controlword last sent (0x6040).
    pub coe_controlword: u16,
    /// The statusword last received (0x6041).
    pub coe_statusword: u16,
    /// Commands waiting in the queue (HMPL 5.3.44).
    pub cmd_num: u32,
    /// The buffer mode for the next command (1: buffered).
    pub buffer_mode: u32,
    /// Whole turns of a rollover axis.
    pub rollover_turns: i32,
    /// -1 when not in a gantry pair.
    pub gantry_pair_id: i32,
    /// The axis' group (HMPL 8.3.5), -1 when in none.
    pub group_id: i32,
    /// The gear master's axis id.
    pub gear_master: u32,
    /// 1 while geared.
    pub in_gear: u32,
    /// 8 csp, 9 csv, 10 cst.
    pub op_mode: u32,
    /// Reference position, counts.
    pub ref_pos: f64,
    /// Reference velocity, counts/s.
    pub ref_vel: f64,
    /// Reference acceleration, counts/s².
    pub ref_acc: f64,
    /// Position sent to the drive, counts.
    pub pos_out: f64,
    /// Velocity sent to the drive, counts/s.
    pub vel_out: f64,
    /// Acceleration sent to the drive, counts/s².
    pub acc_out: f64,
    /// The origin's shift by `SetPos` (HMPL 5.3.19), counts.
    pub pos_offset: f64,
    /// Position feedback, counts.
    pub pos_fb: f64,
    /// Velocity feedback, counts/s.
    pub vel_fb: f64,
    /// Position error, counts.
    pub pos_err: f64,
    /// Velocity error, counts/s.
    pub vel_err: f64,
    /// Current feedback, A (HMPL 5.3.26, from 0x6077).
    pub curr_fb: f64,
    /// Profile velocity setting, counts/s.
    pub vel: f64,
    /// Acceleration setting, counts/s².
    pub acc: f64,
    /// Deceleration setting, counts/s².
    pub dec: f64,
    /// Kill deceleration setting, counts/s².
    pub kill_dec: f64,
    /// Smooth time, ms.
    pub sm_time: f64,
    /// Right (positive) software limit, counts.
    pub swrl: f64,
    /// Left (negative) software limit, counts.
    pub swll: f64,
    /// ms.
    pub move_time: f64,
    /// Time from the end of the profile to in position, ms.
    pub settling_time: f64,
    /// Percent.
    pub vel_scale: f64,
    /// In-position window, counts.
    pub pos_window: f64,
    /// Time the position must stay in the window, ms.
    pub pos_window_time: f64,
    /// Gear ratio to the master.
    pub gear_ratio: f64,
    /// Touch probes 1 and 2 (HMPL ch. 13), bit 0 probe 1, bit 1 probe 2: enabled by the
    /// master (HMPL 13.6, 13.7).
    pub tp_enabled: u32,
    /// Latched on the selected edge since enabled (HMPL 13.8, 13.9).
    pub tp_triggered: u32,
    /// The probe's objects are in the process data.
    pub tp_mapped: u32,
    /// The selected edge's latched position of each probe, units (HMPL 13.10, 13.11).
    pub tp_pos: [f64; 2],
    // HMPL ch. 14: dynamic error compensation.
    /// The compensation added to the reference (`comp_pos_set`), mm or deg.
    pub comp_pos: f64,
    /// The feedback as the drive reports it, the compensation in it (HMPL 5.3.21).
    pub pos_fb_comp: f64,
    /// 1 while compensation is active (HMPL 5.4.14).
    pub comp_active: u32,
}

#[cfg(test)]
mod tests {
    use super::{fault_status, motion_status};

    /// HMPL table 5.1.1.5: one row per `motion_status` bit.
    #[test]
    fn motion_status_bits() {
        let table: [(&str, u32, u32); 14] = [
            ("Enabled", motion_status::ENABLED, 0x0001),
            ("Moving", motion_status::MOVING, 0x0002),
            ("InPos", motion_status::IN_POSITION, 0x0004),
            ("Sync", motion_status::SYNCHRONOUS, 0x0008),
            ("Group", motion_status::GROUP, 0x0010),
            ("Gantry", motion_status::GANTRY, 0x0020),
            ("InputShape", motion_status::INPUT_SHAPE, 0x0040),
            ("VSF", motion_status::VSF, 0x0080),
            ("Gear", motion_status::GEAR, 0x0100),
            ("Cam", motion_status::CAM, 0x0200),
            ("Acc", motion_status::ACCELERATING, 0x0400),
            ("Homed", motion_status::HOMED, 0x0800),
            ("Homing", motion_status::HOMING, 0x1000),
            ("HomeSwitch", motion_status::HOME_SWITCH, 0x2000),
        ];
        for (name, bit, literal) in table {
            assert_eq!(bit, literal, "motion_status {name}");
        }
    }

    /// HMPL table 5.1.1.4: one row per `fault_status` bit.
    #[test]
    fn fault_status_bits() {
        let table: [(&str, u32, u32); 7] = [
            ("ErrorStop", fault_status::ERROR_STOP, 0x01),
            ("DriveFault", fault_status::DRIVE_FAULT, 0x02),
            ("PosErr", fault_status::POSITION_ERROR, 0x04),
            ("HWRL", fault_status::HW_RIGHT_LIMIT, 0x08),
            ("HWLL", fault_status::HW_LEFT_LIMIT, 0x10),
            ("SWRL", fault_status::SW_RIGHT_LIMIT, 0x20),
            ("SWLL", fault_status::SW_LEFT_LIMIT, 0x40),
        ];
        for (name, bit, literal) in table {
            assert_eq!(bit, literal, "fault_status {name}");
        }
    }
}

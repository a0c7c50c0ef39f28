//! One group in the snapshot (HMPL ch. 8): its status bits and its path.

/// HMPL table 8.1.1.5: the bits of a group's `grp_motion_status`.
pub mod group_motion_status {
    /// Bit 0: the group is enabled.
    pub const ENABLED: u32 = 1 << 0;
    /// Bit 1: the group's path generator still outputs positions.
    pub const MOVING: u32 = 1 << 1;
    /// Bit 2: every axis of the group is in position.
    pub const IN_POSITION: u32 = 1 << 2;
    /// Bit 3: the group's input-shaping filter is on.
    pub const INPUT_SHAPE: u32 = 1 << 3;
}

/// HMPL table 8.1.1.4: the bits of a group's `grp_fault_status`.
pub mod group_fault_status {
    /// Bit 0: Group Error Stop.
    pub const ERROR_STOP: u32 = 1 << 0;
    /// Bit 1: an axis of the group faulted (disabled); the group left sync.
    pub const AXIS_FAULT: u32 = 1 << 1;
    /// Bit 2: an axis of the group hit a software limit; the group left sync.
    pub const SOFTWARE_LIMIT: u32 = 1 << 2;
}

/// Axes a group holds at most (HMPL 8.3.1).
pub const MAX_GROUP_AXES: usize = 9;

/// One group as the kernel saw it at the end of a cycle (HMPL tables 8.1.1.1 to 8.1.1.5).
/// Poses are in MCS: X, Y, Z in mm, A, B, C in deg.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
pub struct GroupSnapshot {
    /// `grp_motion_status` bits (table 8.1.1.5).
    pub motion_status: u32,
    /// `grp_fault_status` bits (table 8.1.1.4).
    pub fault_status: u32,
    /// Axes in the group, the first `axis_count` of `axes` in the order added.
    pub axis_count: u32,
    /// Kinematics id (table 8.1.3.1).
    pub kin: u32,
    /// The coordinate system flags of later targets (table 8.1.2.1).
    pub coord_sys: u32,
    /// The buffer mode of later commands (table 8.1.4.1).
    pub buffer_mode: u32,
    /// The transition mode of later junctions (table 8.1.5.1).
    pub trans_mode: u32,
    /// Commands in the buffer, the one under way included (HMPL 8.3.27).
    pub cmd_num: u32,
    /// The buffer's size (HMPL 8.3.35).
    pub queue_size: u32,
    /// The axes, in the order added.
    pub axes: [u8; MAX_GROUP_AXES],
    /// `grp_lin_vel`, `grp_lin_acc`, `grp_lin_dec` (mm/s, mm/s²), `grp_lin_sf` (ms).
    pub lin_profile: [f64; 4],
    /// `grp_ang_vel`, `grp_ang_acc`, `grp_ang_dec` (deg/s, deg/s²), `grp_ang_sf` (ms).
    pub ang_profile: [f64; 4],
    /// The velocity override, %.
    pub vel_scale: f64,
    /// `carte_pose_cmd`.
    pub carte_pose_cmd: [f64; 6],
    /// `carte_vel_cmd`.
    pub carte_vel_cmd: [f64; 6],
    /// `carte_pose_fb`.
    pub carte_pose_fb: [f64; 6],
    /// `grp_pg_pos`, `grp_pg_vel`, `grp_pg_acc`: the path generator along the path.
    pub grp_pg: [f64; 3],
}

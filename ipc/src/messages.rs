//! Every message that crosses a process boundary. All are `#[repr(C)]`, fixed-size and
//! free of pointers, so that iceoryx2 can hand them between processes without copying.

use iceoryx2::prelude::ZeroCopySend;
use num_enum::{FromPrimitive, IntoPrimitive, TryFromPrimitive};

/// 32 drives + 64 virtual axes (DXMC), more than HMPL's 16.
pub const MAX_AXES: usize = 96;
/// Group ids HMPL addresses (0x00..0x0f).
pub const MAX_GROUPS: usize = 16;
/// HMPL task ids 0..63 (HMPL ch. 16).
pub const MAX_TASKS: usize = 64;
/// Scalar arguments of one call; no HMPL function has more.
pub const MAX_ARGS: usize = 12;
/// Bytes for string and array arguments (`MovePVT` sends 3 x 50 doubles).
pub const BLOB_SIZE: usize = 1536;

/// One API call that needs the core (`api::Kind::Command`).
///
/// Arguments are 64-bit words whose meaning the registry gives: an `Int` argument is an
/// `i64`, a `Double` the bits of an `f64`.
#[derive(Debug, Clone, Copy, ZeroCopySend)]
#[repr(C)]
pub struct Request {
    /// Per-task sequence number, echoed by the reply: lost or duplicated replies show.
    pub seq: u64,
    /// CLOCK_MONOTONIC when the script sent it.
    pub sent_ns: u64,
    /// `api::Command::id()`.
    pub func: u16,
    /// Arguments used in `args`.
    pub argc: u16,
    /// Bytes used in `blob`.
    pub blob_len: u32,
    /// The argument words.
    pub args: [u64; MAX_ARGS],
    /// Bytes that do not fit in words (a string, a PVT table).
    pub blob: [u8; BLOB_SIZE],
}

impl Request {
    /// An empty request for function id `func`.
    pub fn new(func: u16) -> Self {
        Request { seq: 0, sent_ns: 0, func, argc: 0, blob_len: 0, args: [0; MAX_ARGS], blob: [0; BLOB_SIZE] }
    }

    /// Appends an `Int` argument.
    pub fn push_int(&mut self, v: i64) {
        self.push_word(v as u64);
    }

    /// Appends a `Double` argument.
    pub fn push_double(&mut self, v: f64) {
        self.push_word(v.to_bits());
    }

    fn push_word(&mut self, w: u64) {
        self.args[self.argc as usize] = w;
        self.argc += 1;
    }

    /// Argument `i` as an `Int`.
    pub fn int(&self, i: usize) -> i64 {
        self.args[i] as i64
    }

    /// The blob's used bytes.
    pub fn blob(&self) -> &[u8] {
        &self.blob[..self.blob_len as usize]
    }

    /// Sets the blob; bytes past `BLOB_SIZE` are cut.
    pub fn set_blob(&mut self, bytes: &[u8]) {
        let n = bytes.len().min(BLOB_SIZE);
        self.blob[..n].copy_from_slice(&bytes[..n]);
        self.blob_len = n as u32;
    }

    /// Appends bytes after what the blob holds; false when they do not fit.
    pub fn append_blob(&mut self, bytes: &[u8]) -> bool {
        let start = self.blob_len as usize;
        let Some(end) = start.checked_add(bytes.len()).filter(|&e| e <= BLOB_SIZE) else { return false };
        self.blob[start..end].copy_from_slice(bytes);
        self.blob_len = end as u32;
        true
    }
}

/// The core's answer to one `Request`.
#[derive(Debug, Clone, Copy, ZeroCopySend)]
#[repr(C)]
pub struct Reply {
    /// The request's sequence number.
    pub seq: u64,
    /// The request's `sent_ns`, echoed for the round trip.
    pub request_sent_ns: u64,
    /// CLOCK_MONOTONIC when the core took the request.
    pub received_ns: u64,
    /// CLOCK_MONOTONIC when the core sent this reply.
    pub sent_ns: u64,
    /// The cycle in which the command was applied; the snapshot of that cycle shows it.
    pub cycle: u64,
    /// 0 on success, otherwise why it failed: the HMPL error code (`0x83IIEEEE`, ...),
    /// or for SDO services the CiA 301 abort code.
    pub rc: u32,
    /// Values used in `values`.
    pub valuec: u16,
    /// Bytes used in `blob`.
    pub blob_len: u16,
    /// Returned values as words, typed by the registry's `returns`.
    pub values: [u64; MAX_ARGS],
    /// A returned out-pointer buffer.
    pub blob: [u8; BLOB_SIZE],
}

impl Reply {
    /// Appends a returned value (the C return value first, then out-pointers).
    pub fn push_int(&mut self, v: i64) {
        self.values[self.valuec as usize] = v as u64;
        self.valuec += 1;
    }

    /// Appends a returned `double` (an element of an out-pointer array).
    pub fn push_double(&mut self, v: f64) {
        self.values[self.valuec as usize] = v.to_bits();
        self.valuec += 1;
    }

    /// Sets the blob; bytes past `BLOB_SIZE` are cut.
    pub fn set_blob(&mut self, bytes: &[u8]) {
        let n = bytes.len().min(BLOB_SIZE);
        self.blob[..n].copy_from_slice(&bytes[..n]);
        self.blob_len = n as u16;
    }

    /// The blob's used bytes.
    pub fn blob(&self) -> &[u8] {
        &self.blob[..self.blob_len as usize]
    }

    /// An empty successful reply to `request`.
    pub fn to(request: &Request) -> Self {
        Reply {
            seq: request.seq,
            request_sent_ns: request.sent_ns,
            received_ns: 0,
            sent_ns: 0,
            cycle: 0,
            rc: 0,
            valuec: 0,
            blob_len: 0,
            values: [0; MAX_ARGS],
            blob: [0; BLOB_SIZE],
        }
    }
}

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
#[derive(Debug, Clone, Copy, Default, ZeroCopySend)]
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

/// One axis as the kernel saw it at the end of a cycle (HMPL tables 5.1.1.1 to 5.1.1.6):
/// the variables and settings the status and `Get*` functions read.
#[derive(Debug, Clone, Copy, Default, ZeroCopySend)]
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

/// PDOs a slave may assign per direction (0x1600/0x1601 and 0x1A00/0x1A01).
pub const PDOS_PER_DIRECTION: usize = 2;
/// Mapped entries of one direction: each PDO holds at most 7 (CoE manual 2.4).
pub const MAX_PDO_ENTRIES: usize = 7 * PDOS_PER_DIRECTION;
/// Bytes of one direction's process data: each PDO carries at most 20 (CoE manual 2.4).
pub const MAX_PDO_BYTES: usize = 20 * PDOS_PER_DIRECTION;
/// One drive per axis.
pub const MAX_SLAVES: usize = MAX_AXES;

/// Where a slave's digital channels sit in its process data (HMPL 9.3, 9.5): an object
/// and the bit of channel 1; channel n is the bit n - 1 above it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DigitalWord {
    /// Object index.
    pub index: u16,
    /// Object sub-index.
    pub sub: u8,
    /// The bit of channel 1.
    pub first_bit: u8,
}

/// Digital inputs, the first object mapped wins: a digital I/O terminal's word, then a
/// CiA 402 drive's 0x60FD (bit 0 negative limit, 1 positive limit, 2 home switch).
pub const SLAVE_DIGITAL_INPUTS: [DigitalWord; 2] =
    [DigitalWord { index: 0x6000, sub: 1, first_bit: 0 }, DigitalWord { index: 0x60FD, sub: 0, first_bit: 0 }];
/// Digital outputs: a terminal's word, then a drive's 0x60FE:01, whose O1 is bit 17
/// (CoE manual tables 4-19 to 4-21; bit 16 is the brake).
pub const SLAVE_DIGITAL_OUTPUTS: [DigitalWord; 2] =
    [DigitalWord { index: 0x7000, sub: 1, first_bit: 0 }, DigitalWord { index: 0x60FE, sub: 1, first_bit: 17 }];

/// The bits of `n` channels from bit 0.
pub fn channel_mask(n: u8) -> u32 {
    if n >= 32 { u32::MAX } else { (1 << n) - 1 }
}

/// Analog channels an analog terminal has at most each way (HMPL ch. 10): one PDO of
/// 16-bit words.
pub const MAX_ANALOG_CHANNELS: usize = 4;
/// Slaves with analog channels a machine may have: their settings are in every snapshot,
/// and every snapshot is in shared memory some 250 times.
pub const MAX_ANALOG_TERMINALS: usize = 8;
/// CiA 401 "Read analogue input 16-bit": channel n is sub-index n (INT16, TxPDO).
pub const ANALOG_INPUTS: u16 = 0x6401;
/// CiA 401 "Write analogue output 16-bit": channel n is sub-index n (INT16, RxPDO).
pub const ANALOG_OUTPUTS: u16 = 0x6411;

/// An analog output's settings the controller keeps (HMPL 10.2.2, 10.4).
#[derive(Debug, Clone, Copy, ZeroCopySend)]
#[repr(C)]
pub struct AnalogOutputSnapshot {
    /// `ao_scale` of `SetSlvAOParam`.
    pub scale: f64,
    /// `ao_offset` of `SetSlvAOParam`.
    pub offset: f64,
    /// The `var_id` of `SetSlvAOMonitor`, -1 before one is chosen.
    pub var_id: i32,
    /// The conversion type's code (`HMPL_DAC_*`).
    pub range_type: u16,
    /// 1 while the output follows its variable.
    pub bound: u8,
}

impl Default for AnalogOutputSnapshot {
    fn default() -> Self {
        AnalogOutputSnapshot { scale: 1.0, offset: 0.0, var_id: -1, range_type: 0, bound: 0 }
    }
}

/// A slave's analog channels: how many, and their settings (HMPL ch. 10, 21.1).
#[derive(Debug, Clone, Copy, Default, ZeroCopySend)]
#[repr(C)]
pub struct AnalogSnapshot {
    /// The slave's position on the bus; only an entry with channels names one.
    pub slave: u16,
    /// The outputs' settings, channel n at n - 1.
    pub outputs: [AnalogOutputSnapshot; MAX_ANALOG_CHANNELS],
    /// The inputs' conversion types, channel n at n - 1.
    pub input_types: [u16; MAX_ANALOG_CHANNELS],
    /// Analog input channels.
    pub input_count: u8,
    /// Analog output channels.
    pub output_count: u8,
}

/// One mapped object of a PDO and its byte offset in the slave's process data.
#[derive(Debug, Clone, Copy, Default, ZeroCopySend)]
#[repr(C)]
pub struct PdoEntrySnapshot {
    /// Object index.
    pub index: u16,
    /// Object sub-index.
    pub sub: u8,
    /// Bit length.
    pub bits: u8,
    /// Byte offset in the process data.
    pub offset: u8,
    /// The object's type is signed (sign-extend when reading).
    pub signed: u8,
}

/// One slave as the master sees it: its AL state, its mapping and its process data.
#[derive(Debug, Clone, Copy, ZeroCopySend)]
#[repr(C)]
pub struct SlaveSnapshot {
    /// 1 Init, 2 PreOp, 4 SafeOp, 8 Op.
    pub al_state: u8,
    /// Entries of the RxPDOs used in `rx` (the first PDO's, then the second's).
    pub rx_count: u8,
    /// Entries of the TxPDOs used in `tx`.
    pub tx_count: u8,
    /// Digital inputs and outputs of the slave (HMPL ch. 21).
    pub digital_inputs: u8,
    /// See `digital_inputs`.
    pub digital_outputs: u8,
    /// AL status code of the last refused state change (0: none).
    pub al_status_code: u16,
    /// The RxPDO mapping (master to slave).
    pub rx: [PdoEntrySnapshot; MAX_PDO_ENTRIES],
    /// The TxPDO mapping (slave to master).
    pub tx: [PdoEntrySnapshot; MAX_PDO_ENTRIES],
    /// RxPDO as the master last sent it, TxPDO as the slave last returned it.
    pub outputs: [u8; MAX_PDO_BYTES],
    /// See `outputs`.
    pub inputs: [u8; MAX_PDO_BYTES],
}

impl Default for SlaveSnapshot {
    fn default() -> Self {
        SlaveSnapshot {
            al_state: 0,
            rx_count: 0,
            tx_count: 0,
            digital_inputs: 0,
            digital_outputs: 0,
            al_status_code: 0,
            rx: [PdoEntrySnapshot::default(); MAX_PDO_ENTRIES],
            tx: [PdoEntrySnapshot::default(); MAX_PDO_ENTRIES],
            outputs: [0; MAX_PDO_BYTES],
            inputs: [0; MAX_PDO_BYTES],
        }
    }
}

/// Bytes of text an event carries: `SendMsgEvent`'s 128 characters and an alarm's line.
pub const EVENT_TEXT_BYTES: usize = 160;
/// The `task` of an event the controller raised.
pub const CONTROLLER: u32 = 0xFF;

/// What an event record is. An unknown kind is an error: the tools skip the record.
#[derive(Debug, Clone, Copy, PartialEq, Eq, TryFromPrimitive, IntoPrimitive)]
#[repr(u32)]
pub enum EventKind {
    /// `SendEvent(id)` (HMPL 2.19).
    Event = 1,
    /// `SendMsgEvent(...)` (HMPL 2.20).
    Message = 2,
    /// An alarm in the DXMC format (DXMC 9, `0xXYZUABCD`).
    Alarm = 3,
}

/// One record of the `events` stream the tools follow.
#[derive(Debug, Clone, Copy, ZeroCopySend)]
#[repr(C)]
pub struct EventRecord {
    /// The cycle it was raised in.
    pub cycle: u64,
    /// `EventKind` as a number.
    pub kind: u32,
    /// The task that sent or caused it; `CONTROLLER` for the controller.
    pub task: u32,
    /// The event id or the alarm code.
    pub code: u32,
    /// Bytes used in `text`.
    pub len: u32,
    /// UTF-8 text, cut at a character boundary.
    pub text: [u8; EVENT_TEXT_BYTES],
}

impl EventRecord {
    /// A record; `text` is cut to `EVENT_TEXT_BYTES` at a character boundary.
    pub fn new(kind: EventKind, task: u32, cycle: u64, code: u32, text: &str) -> Self {
        let mut record = EventRecord { cycle, kind: kind.into(), task, code, len: 0, text: [0; EVENT_TEXT_BYTES] };
        let mut n = text.len().min(EVENT_TEXT_BYTES);
        while !text.is_char_boundary(n) {
            n -= 1;
        }
        record.text[..n].copy_from_slice(&text.as_bytes()[..n]);
        record.len = n as u32;
        record
    }

    /// The record's kind; `None` for a number no kind has.
    pub fn kind(&self) -> Option<EventKind> {
        EventKind::try_from(self.kind).ok()
    }

    /// The text (invalid UTF-8 replaced).
    pub fn text(&self) -> String {
        String::from_utf8_lossy(&self.text[..(self.len as usize).min(EVENT_TEXT_BYTES)]).into_owned()
    }
}

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
#[derive(Debug, Clone, Copy, Default, ZeroCopySend)]
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

/// HMPL 9.1: the controller has 8 inputs and 8 outputs, pins 1..8.
pub const GPIO_PINS: i64 = 8;

/// The controller's own digital I/O (HMPL ch. 9): bit i is pin i + 1.
#[derive(Debug, Clone, Copy, Default, ZeroCopySend)]
#[repr(C)]
pub struct GpioSnapshot {
    /// Inputs as programs read them (after inversion).
    pub gpi: u32,
    /// Outputs as the controller drives them.
    pub gpo: u32,
    /// The inversion mask of the inputs (HMPL 9.5).
    pub gpi_invert: u32,
    /// The inversion mask of the outputs (HMPL 9.5).
    pub gpo_invert: u32,
    /// The input bound to the E-stop (1-based; 0: none).
    pub emo_input: u32,
}

/// The machine at the end of one cycle, published every cycle (latest value wins).
#[derive(Debug, Clone, Copy, ZeroCopySend)]
#[repr(C)]
pub struct Snapshot {
    /// `system_fclk`: cycles since start.
    pub cycle: u64,
    /// The cycle period, ns.
    pub period_ns: u64,
    /// `system_timeInMs`: controller time, derived from the cycle count.
    pub time_in_ms: u64,
    /// CLOCK_MONOTONIC at publication, for the age of a snapshot when read.
    pub published_ns: u64,
    /// Axes in use (of `MAX_AXES`).
    pub axis_count: u32,
    /// EtherCAT master state: 1 Init, 2 PreOp, 4 SafeOp, 8 Op (HMPL 2.5).
    pub ecat_state: u32,
    /// The system is in error (HMPL 2.4): EtherCAT start-up stopped short of Op.
    pub system_error: u32,
    /// The last system error code (HMPL 18.2).
    pub system_last_err: u32,
    /// Slaves on the segment (of `MAX_SLAVES`).
    pub slave_count: u32,
    /// Each group's last error (HMPL 18.5).
    pub group_last_err: [u32; MAX_GROUPS],
    /// Every group (HMPL ch. 8).
    pub groups: [GroupSnapshot; MAX_GROUPS],
    /// Cycles whose work ran past the next deadline, since start.
    pub overruns: u64,
    /// DXMC 3.6, register 0x6A80: 0 Initial, 1 Fail, 2 Edit, 4 Run, 5 Diagnosis.
    pub controller_state: u32,
    /// The controller's digital I/O.
    pub gpio: GpioSnapshot,
    /// Every task's slot.
    pub tasks: [TaskSnapshot; MAX_TASKS],
    /// Every axis, the first `axis_count` in use.
    pub axes: [AxisSnapshot; MAX_AXES],
    /// Every slave, the first `slave_count` present.
    pub slaves: [SlaveSnapshot; MAX_SLAVES],
    /// The slaves with analog channels, in bus order; an entry without channels is free.
    pub analog: [AnalogSnapshot; MAX_ANALOG_TERMINALS],
    /// Every axis' position trigger (HMPL ch. 12).
    pub position_triggers: [PtSnapshot; MAX_AXES],
}

/// An axis' position trigger (HMPL ch. 12), its last pass.
#[derive(Debug, Clone, Copy, Default, ZeroCopySend)]
#[repr(C)]
pub struct PtSnapshot {
    /// 1 while a pass runs (HMPL 12.4).
    pub enabled: u32,
    /// Pulses given in the pass.
    pub pulses: u32,
    /// Points reached in the same drive sample as the pulse before: no pulse for them.
    pub missed: u32,
}

impl Default for Snapshot {
    fn default() -> Self {
        Snapshot {
            cycle: 0,
            period_ns: 0,
            time_in_ms: 0,
            published_ns: 0,
            axis_count: 0,
            ecat_state: 0,
            system_error: 0,
            system_last_err: 0,
            slave_count: 0,
            group_last_err: [0; MAX_GROUPS],
            groups: [GroupSnapshot::default(); MAX_GROUPS],
            overruns: 0,
            controller_state: 0,
            gpio: GpioSnapshot::default(),
            tasks: [TaskSnapshot::default(); MAX_TASKS],
            axes: [AxisSnapshot::default(); MAX_AXES],
            slaves: [SlaveSnapshot::default(); MAX_SLAVES],
            position_triggers: [PtSnapshot::default(); MAX_AXES],
            analog: [AnalogSnapshot::default(); MAX_ANALOG_TERMINALS],
        }
    }
}

impl Snapshot {
    /// Slave `slave`'s analog channels, if it has any (HMPL ch. 10).
    pub fn analog_of(&self, slave: usize) -> Option<&AnalogSnapshot> {
        self.analog.iter().find(|a| a.slave as usize == slave && a.input_count + a.output_count > 0)
    }
}

#[cfg(test)]
mod tests {
    use super::{EventKind, EventRecord, TaskState, fault_status, motion_status};

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

    /// The kinds of the `events` stream; a record of an unknown kind has none.
    #[test]
    fn event_kind_words() {
        let rows = [(EventKind::Event, 1u32), (EventKind::Message, 2), (EventKind::Alarm, 3)];
        for (kind, word) in rows {
            let record = EventRecord::new(kind, 0, 0, 0, "");
            assert_eq!(record.kind, word, "{kind:?}");
            assert_eq!(record.kind(), Some(kind));
        }
        for word in [0, 4, u32::MAX] {
            let record = EventRecord { kind: word, ..EventRecord::new(EventKind::Event, 0, 0, 0, "") };
            assert_eq!(record.kind(), None, "word {word}");
        }
    }

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

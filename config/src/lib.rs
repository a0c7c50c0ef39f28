//! The machine configuration (TOML): cycle, RT thread, axes and their drives, tasks, the
//! DRL and Modbus sections of `luamotion serve`.
//!
//! Unknown keys and wrong types are refused by serde with the key's name and line;
//! `validate` checks ranges and names the key it refuses. Nothing starts on an error.
//! The controller (`rt-core`) builds its drives from these types; this crate knows
//! nothing of the controller, so the drive can import its model from here.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use serde::Deserialize;

/// DC cycle times the drives accept (CoE manual table 2-1), in µs.
pub const DC_CYCLES_US: [u32; 5] = [250, 500, 1000, 2000, 4000];
/// HMPL task ids 0..63.
pub const MAX_TASKS: usize = ipc::messages::MAX_TASKS;
pub const MAX_AXES: usize = ipc::messages::MAX_AXES;

/// Drive families of the HIWIN CoE manual, with their product codes (CoE table 4-2).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
pub enum DriveModel {
    #[serde(rename = "D1-N")]
    D1N,
    D1,
    D2,
    #[serde(rename = "abily")]
    Abily,
}

impl DriveModel {
    pub fn product_code(self) -> u32 {
        match self {
            DriveModel::D1N => 1,
            DriveModel::D1 => 2,
            DriveModel::D2 => 3,
            DriveModel::Abily => 4,
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    #[error("cannot read {path}: {source}")]
    Read { path: PathBuf, source: std::io::Error },
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    #[error("{key}: {message}")]
    Invalid { key: String, message: String },
}

fn invalid(key: impl Into<String>, message: impl Into<String>) -> ConfigError {
    ConfigError::Invalid { key: key.into(), message: message.into() }
}

/// The mapping the master writes unless the machine file gives one: the objects the HMPL
/// functions use, within 7 entries and 20 bytes per PDO (CoE manual 2.4). Out:
/// controlword, target position, mode, target velocity, target torque (13 bytes). In:
/// statusword, position actual, following error, digital inputs, mode display, error
/// code, torque actual (19 bytes).
pub const BUILT_IN_RX_PDO: [u32; 5] = [0x6040_0010, 0x607A_0020, 0x6060_0008, 0x60FF_0020, 0x6071_0010];
pub const BUILT_IN_TX_PDO: [u32; 7] =
    [0x6041_0010, 0x6064_0020, 0x60F4_0020, 0x60FD_0020, 0x6061_0008, 0x603F_0010, 0x6077_0010];

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MachineConfig {
    /// Controller cycle in µs: one of 250, 500, 1000, 2000, 4000.
    pub cycle_us: u32,
    pub rt: RtConfig,
    pub axes: Vec<AxisConfig>,
    /// Devices on the bus that drive no axis, after the axes' drives in file order.
    pub slaves: Vec<SlaveConfig>,
    pub tasks: Vec<TaskConfig>,
    /// DRL projects and their program control (DXMC manual A.3).
    pub drl: DrlConfig,
    /// The Modbus TCP server of `luamotion serve` (DXMC manual 8.2).
    pub modbus: ModbusConfig,
    /// The Native and User ASCII servers (HMPL 22.1).
    pub ascii: AsciiConfig,
    /// What `GetModelNum` and `GetSerialNum` report (HMPL 2.14, 2.15).
    pub identity: IdentityConfig,
    /// Serial port 1, a pseudo-terminal (DXMC manual 8.2, 8.3).
    pub serial: SerialConfig,
    /// The programs' `FreePort.Eth` servers (DXMC 8.3).
    pub freeport: FreePortConfig,
    /// The web view of `--http`.
    pub web: WebConfig,
}

/// `[identity]`: the controller's product model and serial number (HMPL 2.14, 2.15).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct IdentityConfig {
    /// At most 64 bytes.
    pub model: String,
    /// At most 64 bytes.
    pub serial: String,
}

impl Default for IdentityConfig {
    fn default() -> Self {
        IdentityConfig { model: "luamotion-sim".into(), serial: "LM00000000".into() }
    }
}

/// `[drl]`: where DRL projects live and how the one being run is supervised. The running
/// project is a task like the others, in its own slot.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DrlConfig {
    /// The HMPL task slot the DRL project runs in; no `[[tasks]]` entry may use it.
    pub task: u8,
    /// Folder of the projects, one folder per DRL id holding `main.lua` (the DXMC's FTP
    /// area); relative to the machine file. Default: `<data dir>/projects`.
    pub projects: Option<PathBuf>,
    /// Folder projects are exported to and imported from (the DXMC's USB stick).
    /// Default: `<data dir>/export`.
    pub export: Option<PathBuf>,
    pub watchdog_ms: u32,
    pub memory_limit_mib: u32,
    pub fault_reaction: FaultReaction,
}

impl Default for DrlConfig {
    fn default() -> Self {
        DrlConfig {
            task: (MAX_TASKS - 1) as u8,
            projects: None,
            export: None,
            watchdog_ms: TaskConfig::default_watchdog_ms(),
            memory_limit_mib: TaskConfig::default_memory_limit_mib(),
            fault_reaction: FaultReaction::default(),
        }
    }
}

impl DrlConfig {
    /// The task slot's configuration; its program is set when a project is opened.
    pub fn task_config(&self) -> TaskConfig {
        TaskConfig {
            id: self.task,
            program: PathBuf::new(),
            autorun: false,
            watchdog_ms: self.watchdog_ms,
            memory_limit_mib: self.memory_limit_mib,
            fault_reaction: self.fault_reaction,
            external: false,
            front_end: false,
        }
    }
}

/// `[modbus]`: the Modbus TCP server (DXMC manual 8.2: TCP port 502, station 1).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ModbusConfig {
    /// The address to listen on. Default 127.0.0.1: serving other hosts is a choice
    /// made here or with `luamotion serve --bind`.
    pub bind: String,
    /// 0 asks the OS for a free port (tests).
    pub port: u16,
    /// DXMC parameter 0-0, 1..247.
    pub station: u8,
    /// Connections served at once; more are closed as soon as they are accepted.
    pub max_connections: u32,
    /// A connection that sends no whole request for this long is closed, ms.
    pub idle_timeout_ms: u64,
}

impl Default for ModbusConfig {
    fn default() -> Self {
        ModbusConfig { bind: "127.0.0.1".into(), port: 502, station: 1, max_connections: 32, idle_timeout_ms: 60_000 }
    }
}

/// `[ascii]`: the ASCII servers of HMPL 22.1. The Native server (port 3999) runs in
/// `luamotion serve` and carries its clients' commands out as task `agent_task`, an
/// external slot; the User server (port 4000) is opened by the task that calls
/// `START_ASCII_AGENT`, in its own process.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AsciiConfig {
    /// The address both servers listen on. Default 127.0.0.1, as `[modbus]`.
    pub bind: String,
    /// The Native ASCII server's port (HMPL 22.1: 3999); 0 asks the OS for a free one.
    pub native_port: u16,
    /// The User ASCII server's port (HMPL 22.1: 4000); 0 asks the OS for a free one.
    pub user_port: u16,
    /// The task slot the Native server's commands run as; no `[[tasks]]` entry may use it.
    pub agent_task: u8,
    /// Connections the Native server serves at once; more get an error line and are
    /// closed. (The User agent, in a task's process, serves 32.)
    pub max_connections: u32,
    /// A Native connection that sends no whole line for this long is closed, ms. (The
    /// User agent's: 60 s.)
    pub idle_timeout_ms: u64,
}

impl Default for AsciiConfig {
    fn default() -> Self {
        AsciiConfig {
            bind: "127.0.0.1".into(),
            native_port: 3999,
            user_port: 4000,
            agent_task: (MAX_TASKS - 2) as u8,
            max_connections: 32,
            idle_timeout_ms: 60_000,
        }
    }
}

/// `[freeport]`: where `FreePort.Eth.OpenAsServer` listens (DXMC 8.3 names only the port).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FreePortConfig {
    /// The address programs' servers listen on. Default 127.0.0.1: serving other hosts
    /// is a choice made here, as for `[modbus]` and `[ascii]`.
    #[serde(deserialize_with = "freeport_bind")]
    pub bind: std::net::IpAddr,
}

/// `[freeport] bind`, refused with the same words as the other bind addresses.
fn freeport_bind<'de, D: serde::Deserializer<'de>>(deserializer: D) -> Result<std::net::IpAddr, D::Error> {
    let value = String::deserialize(deserializer)?;
    bind_address("freeport.bind", &value).map_err(serde::de::Error::custom)
}

impl Default for FreePortConfig {
    fn default() -> Self {
        FreePortConfig { bind: std::net::IpAddr::from([127, 0, 0, 1]) }
    }
}

/// `[web]`: the web view of `--http PORT` (docs/decisions.md, "Web view security").
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WebConfig {
    /// The address it listens on. Default 127.0.0.1; `luamotion serve --bind` overrides it.
    pub bind: String,
    /// Host names, besides the bound address (and `localhost` on a loopback bind), that a
    /// request's `Host` may name: the names the operator's browser reaches the controller
    /// by. Any other name is refused, so that a rebinding DNS name cannot reach the view.
    pub allowed_hosts: Vec<String>,
    /// When set, the page asks for it before it takes commands. Without it, a bind other
    /// than loopback serves read-only.
    pub password: Option<String>,
    /// Connections served at once (each open page holds one); more are closed.
    pub max_connections: u32,
    /// A connection that sends no whole request head for this long is closed, ms.
    pub header_timeout_ms: u64,
}

impl Default for WebConfig {
    fn default() -> Self {
        WebConfig {
            bind: "127.0.0.1".into(),
            allowed_hosts: Vec::new(),
            password: None,
            max_connections: 32,
            header_timeout_ms: 10_000,
        }
    }
}

/// A bind address of the machine file: an IP address, so that a typo is told at load
/// time rather than when the server starts (or, for `0.0.0.0` meant as `127.0.0.1`, never).
fn bind_address(key: &str, value: &str) -> Result<std::net::IpAddr, ConfigError> {
    value
        .parse()
        .map_err(|_| invalid(key, format!("{value:?} is not an IP address (such as 127.0.0.1, 0.0.0.0 or ::1)")))
}

/// `[serial]`: serial port 1, a pseudo-terminal any serial program can open. Its Modbus
/// station is `[modbus] station`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SerialConfig {
    pub enabled: bool,
    /// A symlink to the pseudo-terminal (`/dev/pts/N`), made at start (replacing one
    /// there) and removed at the end; relative to the machine file.
    pub link: Option<PathBuf>,
    /// DXMC parameter 5-1, 0x00..0x1D: the character frame and Modbus ASCII, Modbus RTU
    /// or FreePort. Default 0x16, 8,N,1 Modbus RTU.
    pub protocol: u8,
    /// DXMC parameter 5-4: 0 4800, 1 9600, 2 19200, 3 38400 (default), 4 57600, 5 115200 baud.
    pub baud: u8,
    /// What is sent comes back, as with 485+ and 485- shorted (FreePort only).
    pub loopback: bool,
}

impl Default for SerialConfig {
    fn default() -> Self {
        SerialConfig { enabled: true, link: None, protocol: 0x16, baud: 3, loopback: false }
    }
}

/// `[[slaves]]`: a device on the bus beside the axes' drives.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlaveConfig {
    pub device: SlaveDevice,
    /// Input channels: 0..=32 of a `digital_io` terminal, 0..=4 of an `analog_io` one.
    #[serde(default)]
    pub inputs: u8,
    /// Output channels, as many as `inputs` may be.
    #[serde(default)]
    pub outputs: u8,
    /// An `analog_io` terminal's output n wired to its input n (docs/decisions.md,
    /// "Slave analog I/O"); a `digital_io` terminal has no such wiring.
    #[serde(default)]
    pub loopback: bool,
}

/// Channels a `digital_io` terminal may have: one 32-bit process-data word each way.
pub const MAX_TERMINAL_CHANNELS: u8 = 32;

/// The kinds of device a `[[slaves]]` entry may name; any other is refused with the name
/// it gave (docs/decisions.md, "`[[slaves]]`").
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SlaveDevice {
    /// A digital I/O terminal (HMPL 9.3, 9.5): `inputs` and `outputs` channels.
    DigitalIo,
    /// An analog I/O terminal (HMPL ch. 10): `inputs` and `outputs` 16-bit channels.
    AnalogIo,
}

impl SlaveDevice {
    /// The channels the kind may have each way.
    pub fn max_channels(self) -> u8 {
        match self {
            SlaveDevice::DigitalIo => MAX_TERMINAL_CHANNELS,
            SlaveDevice::AnalogIo => ipc::messages::MAX_ANALOG_CHANNELS as u8,
        }
    }
}

/// How the RT thread asks the OS for real-time service. Each is tried and, where the OS
/// refuses, logged and skipped.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RtConfig {
    /// SCHED_FIFO priority 1..99; 0 runs a plain thread.
    pub priority: u8,
    /// CPU to pin the RT thread to; none for no pinning.
    pub cpu: Option<usize>,
    /// mlockall(MCL_CURRENT | MCL_FUTURE) so that the cycle never page-faults.
    pub lock_memory: bool,
    /// Script processes kept started and waiting, so that a `StartTask` runs its program
    /// without a process start; 0 starts a process per task start.
    pub script_pool: usize,
    /// While the controller runs, idle CPUs poll instead of halting (a Linux PM QoS CPU
    /// latency limit of 0 us, `/dev/cpu_dma_latency`, as cyclictest holds), so a wake-up
    /// (the cycle's timer, a task's reply) finds its CPU awake; false leaves the idle
    /// states to the OS.
    pub idle_poll: bool,
    /// Which CPUs the script processes the controller starts may run on.
    pub script_cpus: ScriptCpus,
    /// Before its first cycle the RT thread has the controller's private memory rebuilt in
    /// 2 MiB pages (transparent huge pages, `MADV_COLLAPSE`): fewer pages for the cycle to
    /// touch, each a possible stall on a virtual machine; false leaves 4 KiB pages.
    pub huge_pages: bool,
}

/// Where the script processes run beside the RT thread (`[rt] script_cpus`). Sharing the
/// RT thread's CPU costs the cycle its caches and delays its wake-ups while a script holds
/// that CPU (docs/decisions.md, "Script CPUs"); keeping off it leaves the scripts a CPU
/// fewer.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ScriptCpus {
    /// `Others` when at least two CPUs are left besides the RT thread's, else `All`.
    #[default]
    Auto,
    /// Every CPU the controller may use, the RT thread's included.
    All,
    /// Every CPU the controller may use but the RT thread's.
    Others,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Unit {
    Mm,
    Deg,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AxisConfig {
    pub name: String,
    pub drive: DriveModel,
    pub unit: Unit,
    /// Drive counts per mm (or per degree).
    pub counts_per_unit: f64,
    /// Highest profile velocity `SetVel` accepts (units/s).
    pub max_vel: f64,
    /// Highest acceleration or deceleration `SetAcc`/`SetDec` accept (units/s²).
    pub max_acc: f64,
    /// Profile at start-up.
    pub vel: f64,
    pub acc: f64,
    pub dec: f64,
    pub plant: PlantConfig,
    pub travel: TravelConfig,
    pub drive_settings: DriveSettings,
    /// PDO mapping entries (`0xIIIISSLL`) the master writes in PreOp; by default the
    /// built-in mapping. `None` leaves the drive's defaults (CoE manual table 4-3).
    pub rx_pdo: Option<Vec<u32>>,
    pub tx_pdo: Option<Vec<u32>>,
    /// HMPL ch. 12: the drive has the position trigger (an E1-series drive with a digital
    /// encoder) and its PT output is wired to a controller GPO. None: no position trigger.
    pub pt: Option<PtConfig>,
    /// The master maps the touch probe (HMPL ch. 13) into the second PDOs: 0x60B8 into
    /// 0x1601 and `touch_probe_tx_pdo`'s objects into 0x1A01 (docs/decisions.md, "Touch probe").
    pub touch_probe_pdo: bool,
}

/// `[axes.pt]`: where the drive's position-trigger output is seen (docs/decisions.md,
/// "Position trigger").
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PtConfig {
    /// The controller GPO (1..8) that pulses.
    pub output: i64,
}

/// Which touch probe the drive has (docs/decisions.md, "Touch probe").
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum TouchProbeKind {
    /// CoE manual 3.9: touch probe 1 on the encoder index only; 0x60BC/0x60BD do not exist.
    #[default]
    Index,
    /// The CiA 402 touch probe: probes 1 and 2, each on its own probe input or the index
    /// (0x60B8 bits 2-3 and 10-11), with 0x60BC/0x60BD.
    Cia402,
}

/// 0x1601: the touch probe function.
pub const TOUCH_PROBE_RX_PDO: [u32; 1] = [0x60B8_0010];

impl AxisConfig {
    /// 0x1A01 for the drive's touch probe: its status and the edge positions it has.
    pub fn touch_probe_tx_pdo(&self) -> &'static [u32] {
        match self.drive_settings.touch_probe {
            TouchProbeKind::Index => &[0x60B9_0010, 0x60BA_0020, 0x60BB_0020],
            TouchProbeKind::Cia402 => &[0x60B9_0010, 0x60BA_0020, 0x60BB_0020, 0x60BC_0020, 0x60BD_0020],
        }
    }
}

/// Switches, index and hard stops along the travel, in units (mm or deg) of the machine's
/// own coordinates. Absent ones do not exist.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TravelConfig {
    pub negative_limit: Option<f64>,
    pub positive_limit: Option<f64>,
    /// The home switch is active over `[L, R]`.
    pub home_switch: Option<[f64; 2]>,
    /// Distance between encoder index pulses (one motor turn); none: no index.
    pub index_pitch: Option<f64>,
    pub index_offset: f64,
    pub negative_hard_stop: Option<f64>,
    pub positive_hard_stop: Option<f64>,
    /// Where the motor stands at power-up.
    pub start_position: f64,
    /// The drive's touch probe inputs 1 and 2 (a `cia402` touch probe only): a sensor
    /// active over `[L, R]`, like the home switch.
    pub probe_input_1: Option<[f64; 2]>,
    pub probe_input_2: Option<[f64; 2]>,
}

/// Drive parameters set with HIWIN's Lightening tool rather than through objects.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DriveSettings {
    /// Hard-stop homing (methods -1, -2, -4, -5): the current that means "at the stop",
    /// in % of rated current, held for `end_stop_time_ms`.
    pub end_stop_current_pct: f64,
    pub end_stop_time_ms: f64,
    /// Methods -4/-5: distance from the hard stop to home, counts.
    pub end_stop_offset: i64,
    /// A multi-turn absolute encoder (method -3).
    pub multi_turn_absolute: bool,
    /// Motor rated current, A, and force (torque) constant, N/A (N·m/A): torque modes.
    pub rated_current_a: f64,
    pub force_constant: f64,
    /// Outputs O1..O5 configured as general purpose ("PDL usage"), bit 0 = O1.
    pub general_purpose_outputs: u8,
    /// The drive's touch probe: the CoE manual's (index) or the CiA 402 one.
    pub touch_probe: TouchProbeKind,
}

impl Default for DriveSettings {
    fn default() -> Self {
        DriveSettings {
            end_stop_current_pct: 80.0,
            end_stop_time_ms: 20.0,
            end_stop_offset: 1000,
            multi_turn_absolute: false,
            rated_current_a: 2.0,
            force_constant: 10.0,
            general_purpose_outputs: 0b1_1111,
            touch_probe: TouchProbeKind::Index,
        }
    }
}

impl TravelConfig {
    /// The built-in machine: limit switches at ±1000 mm, hard stops 10 mm beyond them, a
    /// home switch at [-10, -5] mm and an index every 10 mm (a 10 mm screw).
    pub fn built_in() -> Self {
        TravelConfig {
            negative_limit: Some(-1000.0),
            positive_limit: Some(1000.0),
            home_switch: Some([-10.0, -5.0]),
            index_pitch: Some(10.0),
            index_offset: 0.0,
            negative_hard_stop: Some(-1010.0),
            positive_hard_stop: Some(1010.0),
            start_position: 0.0,
            probe_input_1: None,
            probe_input_2: None,
        }
    }
}

/// The highest natural frequency of a flexible load: the servo loops run at 16 kHz, and
/// their integration of a spring needs many steps per period.
pub const MAX_LOAD_FREQUENCY_HZ: f64 = 1000.0;

/// The motor and load behind a drive (see rt-core's `drive::plant`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PlantConfig {
    /// Bandwidth of the drive's velocity loop, Hz.
    pub bandwidth_hz: f64,
    /// Load inertia over the inertia the drive is tuned for; 1 is a perfect tuning.
    pub inertia_ratio: f64,
    /// Coulomb friction as a fraction of rated force.
    pub friction: f64,
    /// Acceleration of the tuned load at rated force, units/s².
    pub rated_acc: f64,
    /// Peak force over rated force.
    pub peak_ratio: f64,
    /// A flexible load: a second mass on a spring and damper behind the motor, ringing at
    /// this natural frequency (Hz) when the motor stands still; 0 (the default) is a rigid
    /// load. HMPL 15.1's cantilever, for the VSF and input shaping of ch. 15.
    pub load_frequency_hz: f64,
    /// The flexible load's damping ratio, 0..1.
    pub load_damping: f64,
    /// The flexible load's mass over the motor's (its inertia, `inertia_ratio`), > 0..10.
    pub load_mass_ratio: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaskConfig {
    pub id: u8,
    pub program: PathBuf,
    #[serde(default)]
    pub autorun: bool,
    #[serde(default = "TaskConfig::default_watchdog_ms")]
    pub watchdog_ms: u32,
    #[serde(default = "TaskConfig::default_memory_limit_mib")]
    pub memory_limit_mib: u32,
    /// What the axes this task set moving do when it fails or is stopped.
    #[serde(default)]
    pub fault_reaction: FaultReaction,
    /// The controller starts no process for this task: a program started by the user
    /// (a benchmark, a tool) attaches to it and runs without a watchdog.
    #[serde(default)]
    pub external: bool,
    /// An external slot that carries a front end's calls (the Native ASCII agent, which
    /// the web view shares), not a program: no stop command stops it (HMPL 16.4, 16.5).
    /// Set by `with_ascii_task`, never by a machine file.
    #[serde(skip)]
    pub front_end: bool,
}

/// What happens to the active motion a task commanded when the task fails (watchdog,
/// crash, error) or is stopped (DXMC parameter 8-1; docs/decisions.md, "Fault reaction").
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum FaultReaction {
    /// The motion carries on.
    None,
    /// The axis stops with its kill deceleration and stays enabled.
    #[default]
    Decelerate,
    /// The drive's quick stop (CiA 402): it stops with 0x6085, then the axis is disabled.
    QuickStop,
    /// The axis is disabled at once.
    Disable,
}

impl TaskConfig {
    fn default_watchdog_ms() -> u32 {
        500
    }

    fn default_memory_limit_mib() -> u32 {
        64
    }

    /// A task running `program`, started with the controller.
    pub fn autorun(id: u8, program: PathBuf) -> Self {
        TaskConfig {
            id,
            program,
            autorun: true,
            watchdog_ms: Self::default_watchdog_ms(),
            memory_limit_mib: Self::default_memory_limit_mib(),
            fault_reaction: FaultReaction::default(),
            external: false,
            front_end: false,
        }
    }
}

impl Default for MachineConfig {
    /// The built-in machine: 4 axes on simulated HIWIN D1 drives, mm, 1 ms cycle.
    fn default() -> Self {
        MachineConfig {
            cycle_us: 1000,
            rt: RtConfig::default(),
            axes: (0..4)
                .map(|i| AxisConfig {
                    name: format!("axis{i}"),
                    travel: TravelConfig::built_in(),
                    ..AxisConfig::default()
                })
                .collect(),
            slaves: Vec::new(),
            tasks: Vec::new(),
            drl: DrlConfig::default(),
            modbus: ModbusConfig::default(),
            ascii: AsciiConfig::default(),
            identity: IdentityConfig::default(),
            serial: SerialConfig::default(),
            freeport: FreePortConfig::default(),
            web: WebConfig::default(),
        }
    }
}

impl Default for RtConfig {
    fn default() -> Self {
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
        RtConfig {
            priority: 80,
            cpu: (cpus > 1).then(|| cpus - 1),
            lock_memory: true,
            script_pool: 2,
            idle_poll: true,
            script_cpus: ScriptCpus::Auto,
            huge_pages: true,
        }
    }
}

impl Default for AxisConfig {
    fn default() -> Self {
        AxisConfig {
            name: String::new(),
            drive: DriveModel::D1,
            unit: Unit::Mm,
            counts_per_unit: 10_000.0,
            max_vel: 2_000.0,
            max_acc: 50_000.0,
            vel: 100.0,
            acc: 1_000.0,
            dec: 1_000.0,
            plant: PlantConfig::default(),
            travel: TravelConfig::default(),
            drive_settings: DriveSettings::default(),
            rx_pdo: Some(BUILT_IN_RX_PDO.to_vec()),
            tx_pdo: Some(BUILT_IN_TX_PDO.to_vec()),
            pt: None,
            touch_probe_pdo: true,
        }
    }
}

impl Default for PlantConfig {
    fn default() -> Self {
        PlantConfig {
            bandwidth_hz: 100.0,
            inertia_ratio: 1.0,
            friction: 0.02,
            rated_acc: 20_000.0,
            peak_ratio: 3.0,
            load_frequency_hz: 0.0,
            load_damping: 0.02,
            load_mass_ratio: 0.1,
        }
    }
}

impl MachineConfig {
    /// Reads and validates a machine file. Task programs are relative to the file.
    pub fn load(path: &Path) -> Result<Self, ConfigError> {
        let text =
            std::fs::read_to_string(path).map_err(|source| ConfigError::Read { path: path.to_path_buf(), source })?;
        let mut config: MachineConfig = toml::from_str(&text)
            .map_err(|e| ConfigError::Parse { path: path.to_path_buf(), message: e.to_string() })?;
        let base = path.parent().unwrap_or(Path::new("."));
        for task in &mut config.tasks {
            if task.program.is_relative() {
                task.program = base.join(&task.program);
            }
        }
        for dir in [&mut config.drl.projects, &mut config.drl.export, &mut config.serial.link].into_iter().flatten() {
            if dir.is_relative() {
                *dir = base.join(&*dir);
            }
        }
        config.validate()?;
        Ok(config)
    }

    /// Adds the DRL project's task slot (`luamotion serve`).
    pub fn with_drl_task(mut self) -> Result<Self, ConfigError> {
        if self.tasks.iter().any(|t| t.id == self.drl.task) {
            return Err(invalid(
                "drl.task",
                format!("task {} runs the DRL project; no [[tasks]] entry may use it", self.drl.task),
            ));
        }
        self.tasks.push(self.drl.task_config());
        Ok(self)
    }

    /// Adds the Native ASCII server's agent slot (`[ascii] agent_task`), an external task
    /// without a watchdog; after `with_drl_task`, so that the two slots are told apart.
    pub fn with_ascii_task(mut self) -> Result<Self, ConfigError> {
        let id = self.ascii.agent_task;
        if id as usize >= MAX_TASKS {
            return Err(invalid("ascii.agent_task", format!("task ids are 0..63, not {id}")));
        }
        if self.tasks.iter().any(|t| t.id == id) {
            return Err(invalid(
                "ascii.agent_task",
                format!(
                    "task {id} carries out the Native ASCII server's commands; no other task (nor drl.task) may use it"
                ),
            ));
        }
        self.tasks.push(TaskConfig {
            id,
            program: PathBuf::new(),
            autorun: false,
            watchdog_ms: TaskConfig::default_watchdog_ms(),
            memory_limit_mib: TaskConfig::default_memory_limit_mib(),
            // A client that vanishes leaves its motion as a script's stop would.
            fault_reaction: FaultReaction::default(),
            external: true,
            front_end: true,
        });
        Ok(self)
    }

    pub fn period_ns(&self) -> u64 {
        self.cycle_us as u64 * 1000
    }

    pub fn validate(&self) -> Result<(), ConfigError> {
        if !DC_CYCLES_US.contains(&self.cycle_us) {
            return Err(invalid(
                "cycle_us",
                format!(
                    "{} is not a DC cycle the drives accept; use one of 250, 500, 1000, 2000, 4000 (CoE manual table 2-1)",
                    self.cycle_us
                ),
            ));
        }
        if self.rt.priority > 99 {
            return Err(invalid("rt.priority", "SCHED_FIFO priorities are 1..99 (0: plain thread)"));
        }
        // Each waiting process is a node of the namespace's services, sized for this many.
        if self.rt.script_pool > ipc::services::MAX_POOL {
            let max = ipc::services::MAX_POOL;
            return Err(invalid("rt.script_pool", format!("at most {max} waiting script processes (0: none)")));
        }
        // The snapshot has a fixed room for slaves: drives and terminals share it.
        if self.axes.len() + self.slaves.len() > ipc::messages::MAX_SLAVES {
            let max = ipc::messages::MAX_SLAVES;
            return Err(invalid("slaves", format!("a bus holds at most {max} slaves, the axes' drives included")));
        }
        for (i, slave) in self.slaves.iter().enumerate() {
            let max = slave.device.max_channels();
            for (key, count) in [("inputs", slave.inputs), ("outputs", slave.outputs)] {
                if count > max {
                    let kind = format!("a {:?} terminal has 0..{max} channels", slave.device);
                    return Err(invalid(format!("slaves[{i}].{key}"), kind));
                }
            }
            let analog = self.slaves[..=i].iter().filter(|s| s.device == SlaveDevice::AnalogIo).count();
            if analog > ipc::messages::MAX_ANALOG_TERMINALS {
                let room = format!("at most {} analog_io terminals", ipc::messages::MAX_ANALOG_TERMINALS);
                return Err(invalid(format!("slaves[{i}]"), room));
            }
            if slave.loopback && slave.device != SlaveDevice::AnalogIo {
                return Err(invalid(format!("slaves[{i}].loopback"), "only an analog_io terminal has a loopback"));
            }
        }
        if self.axes.is_empty() || self.axes.len() > MAX_AXES {
            return Err(invalid("axes", format!("a machine has 1 to {MAX_AXES} axes, not {}", self.axes.len())));
        }
        for (i, axis) in self.axes.iter().enumerate() {
            axis.validate(&format!("axes[{i}]"))?;
        }
        let mut ids = HashSet::new();
        for (i, task) in self.tasks.iter().enumerate() {
            let key = format!("tasks[{i}]");
            if task.id as usize >= MAX_TASKS {
                return Err(invalid(format!("{key}.id"), format!("task ids are 0..{} (HMPL ch. 16)", MAX_TASKS - 1)));
            }
            if !ids.insert(task.id) {
                return Err(invalid(format!("{key}.id"), format!("task {} is configured twice", task.id)));
            }
            if task.watchdog_ms == 0 {
                return Err(invalid(format!("{key}.watchdog_ms"), "must be at least 1 ms"));
            }
            if !(1..=4096).contains(&task.memory_limit_mib) {
                return Err(invalid(format!("{key}.memory_limit_mib"), "must be 1..4096"));
            }
            if !task.program.is_file() {
                return Err(invalid(format!("{key}.program"), format!("{} is not a file", task.program.display())));
            }
        }
        let drl = &self.drl;
        if drl.task as usize >= MAX_TASKS {
            return Err(invalid("drl.task", format!("task ids are 0..63, not {}", drl.task)));
        }
        if drl.watchdog_ms == 0 || !(1..=4096).contains(&drl.memory_limit_mib) {
            return Err(invalid("drl", "watchdog_ms must be at least 1 ms and memory_limit_mib 1..4096"));
        }
        if !(1..=247).contains(&self.modbus.station) {
            return Err(invalid("modbus.station", "Modbus station numbers are 1..247 (DXMC parameter 0-0)"));
        }
        if !(1..=4096).contains(&self.modbus.max_connections) {
            return Err(invalid("modbus.max_connections", "must be 1..4096"));
        }
        if self.serial.protocol > 0x1D {
            return Err(invalid("serial.protocol", "DXMC parameter 5-1 is 0x00..0x1D"));
        }
        if self.serial.baud > 5 {
            return Err(invalid("serial.baud", "DXMC parameter 5-4 is 0..5 (4800, 9600, 19200, 38400, 57600, 115200)"));
        }
        if self.modbus.idle_timeout_ms == 0 {
            return Err(invalid("modbus.idle_timeout_ms", "must be at least 1 ms"));
        }
        if !(1..=4096).contains(&self.ascii.max_connections) {
            return Err(invalid("ascii.max_connections", "must be 1..4096"));
        }
        if self.ascii.idle_timeout_ms == 0 {
            return Err(invalid("ascii.idle_timeout_ms", "must be at least 1 ms"));
        }
        for (key, value) in
            [("modbus.bind", &self.modbus.bind), ("ascii.bind", &self.ascii.bind), ("web.bind", &self.web.bind)]
        {
            bind_address(key, value)?;
        }
        self.web.validate()?;
        for (key, text) in [("identity.model", &self.identity.model), ("identity.serial", &self.identity.serial)] {
            if text.len() > 64 || text.contains('\0') {
                return Err(invalid(key, "at most 64 bytes, no NUL"));
            }
        }
        Ok(())
    }
}

impl WebConfig {
    fn validate(&self) -> Result<(), ConfigError> {
        for (i, name) in self.allowed_hosts.iter().enumerate() {
            let host_name = |c: char| c.is_ascii_alphanumeric() || c == '-' || c == '.';
            if name.is_empty() || !name.chars().all(host_name) {
                let message = format!("{name:?} is not a host name (letters, digits, '-' and '.'; no port)");
                return Err(invalid(format!("web.allowed_hosts[{i}]"), message));
            }
        }
        if self.password.as_ref().is_some_and(|p| p.is_empty()) {
            return Err(invalid("web.password", "must not be empty (leave it out for no password)"));
        }
        if !(1..=4096).contains(&self.max_connections) {
            return Err(invalid("web.max_connections", "must be 1..4096"));
        }
        if self.header_timeout_ms == 0 {
            return Err(invalid("web.header_timeout_ms", "must be at least 1 ms"));
        }
        Ok(())
    }
}

fn positive(key: &str, value: f64) -> Result<(), ConfigError> {
    if value.is_finite() && value > 0.0 { Ok(()) } else { Err(invalid(key, format!("must be > 0, not {value}"))) }
}

impl AxisConfig {
    fn validate(&self, key: &str) -> Result<(), ConfigError> {
        positive(&format!("{key}.counts_per_unit"), self.counts_per_unit)?;
        if let Some(pt) = &self.pt
            && !(1..=ipc::messages::GPIO_PINS).contains(&pt.output)
        {
            return Err(invalid(format!("{key}.pt.output"), "a controller GPO, 1..8"));
        }
        positive(&format!("{key}.max_vel"), self.max_vel)?;
        positive(&format!("{key}.max_acc"), self.max_acc)?;
        for (name, value, max) in
            [("vel", self.vel, self.max_vel), ("acc", self.acc, self.max_acc), ("dec", self.dec, self.max_acc)]
        {
            positive(&format!("{key}.{name}"), value)?;
            if value > max {
                return Err(invalid(format!("{key}.{name}"), format!("{value} is above the axis limit {max}")));
            }
        }
        // A drive position is an INT32 count: keep one full turn of travel representable.
        if self.max_vel * self.counts_per_unit > i32::MAX as f64 {
            return Err(invalid(format!("{key}.max_vel"), "max_vel x counts_per_unit exceeds the drive's INT32 range"));
        }
        let p = &self.plant;
        positive(&format!("{key}.plant.bandwidth_hz"), p.bandwidth_hz)?;
        if p.bandwidth_hz > 1000.0 {
            return Err(invalid(
                format!("{key}.plant.bandwidth_hz"),
                "a servo velocity loop above 1000 Hz is not simulated",
            ));
        }
        positive(&format!("{key}.plant.inertia_ratio"), p.inertia_ratio)?;
        positive(&format!("{key}.plant.rated_acc"), p.rated_acc)?;
        if !(0.0..1.0).contains(&p.friction) {
            return Err(invalid(format!("{key}.plant.friction"), "a fraction of rated force in 0..1"));
        }
        if !(p.peak_ratio >= 1.0 && p.peak_ratio.is_finite()) {
            return Err(invalid(format!("{key}.plant.peak_ratio"), "peak force is at least the rated force (>= 1)"));
        }
        if !(0.0..=MAX_LOAD_FREQUENCY_HZ).contains(&p.load_frequency_hz) {
            return Err(invalid(
                format!("{key}.plant.load_frequency_hz"),
                "0 (a rigid load) or a frequency up to 1000 Hz",
            ));
        }
        if !(0.0..1.0).contains(&p.load_damping) {
            return Err(invalid(format!("{key}.plant.load_damping"), "a damping ratio in 0..1"));
        }
        if !(p.load_mass_ratio > 0.0 && p.load_mass_ratio <= 10.0) {
            return Err(invalid(format!("{key}.plant.load_mass_ratio"), "a mass ratio in > 0..10"));
        }
        let t = &self.travel;
        if let (Some(n), Some(p)) = (t.negative_limit, t.positive_limit)
            && n >= p
        {
            return Err(invalid(format!("{key}.travel"), "negative_limit must be below positive_limit"));
        }
        if let Some([l, r]) = t.home_switch
            && l > r
        {
            return Err(invalid(format!("{key}.travel.home_switch"), "[L, R] with L <= R"));
        }
        for (name, input) in [("probe_input_1", t.probe_input_1), ("probe_input_2", t.probe_input_2)] {
            let Some([l, r]) = input else { continue };
            if !l.is_finite() || !r.is_finite() || l > r {
                return Err(invalid(format!("{key}.travel.{name}"), "[L, R] with L <= R"));
            }
            if self.drive_settings.touch_probe != TouchProbeKind::Cia402 {
                return Err(invalid(
                    format!("{key}.travel.{name}"),
                    "the drive's touch probe uses the index only (CoE manual 3.9); set drive_settings.touch_probe = \"cia402\"",
                ));
            }
        }
        if let Some(pitch) = t.index_pitch {
            positive(&format!("{key}.travel.index_pitch"), pitch)?;
        }
        if let (Some(n), Some(p)) = (t.negative_hard_stop, t.positive_hard_stop)
            && n >= p
        {
            return Err(invalid(format!("{key}.travel"), "negative_hard_stop must be below positive_hard_stop"));
        }
        let inside = t.negative_hard_stop.is_none_or(|n| t.start_position > n)
            && t.positive_hard_stop.is_none_or(|p| t.start_position < p);
        if !inside {
            return Err(invalid(format!("{key}.travel.start_position"), "must lie between the hard stops"));
        }
        let d = &self.drive_settings;
        positive(&format!("{key}.drive_settings.rated_current_a"), d.rated_current_a)?;
        positive(&format!("{key}.drive_settings.force_constant"), d.force_constant)?;
        positive(&format!("{key}.drive_settings.end_stop_current_pct"), d.end_stop_current_pct)?;
        positive(&format!("{key}.drive_settings.end_stop_time_ms"), d.end_stop_time_ms)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> MachineConfig {
        toml::from_str(text).unwrap()
    }

    /// The drive model is read by its CoE manual name (table 4-2) and carries its product code.
    #[test]
    fn drive_models_by_their_manual_names() {
        for (name, model, code) in [
            ("D1-N", DriveModel::D1N, 1),
            ("D1", DriveModel::D1, 2),
            ("D2", DriveModel::D2, 3),
            ("abily", DriveModel::Abily, 4),
        ] {
            let config = parse(&format!("[[axes]]\nname = \"x\"\ndrive = \"{name}\"\n"));
            assert_eq!(config.axes[0].drive, model, "{name}");
            assert_eq!(model.product_code(), code, "{name}");
        }
        assert!(toml::from_str::<MachineConfig>("[[axes]]\ndrive = \"D3\"\n").is_err(), "no D3 in table 4-2");
    }

    /// A value out of range is refused with the key that holds it.
    #[test]
    fn an_invalid_value_names_its_key() {
        let config = parse("cycle_us = 300\n[[axes]]\nname = \"x\"\n");
        match config.validate() {
            Err(ConfigError::Invalid { key, message }) => {
                assert_eq!(key, "cycle_us");
                assert!(message.contains("CoE manual table 2-1"), "{message}");
            }
            other => panic!("expected an invalid cycle, got {other:?}"),
        }
        let config = parse("[[axes]]\nname = \"x\"\nvel = 5000.0\n");
        assert!(matches!(config.validate(), Err(ConfigError::Invalid { key, .. }) if key == "axes[0].vel"));
    }

    /// Every bind address of the machine file is checked when the file is loaded, and the
    /// error names the key and the value: a host name, an address with a port, a typo.
    #[test]
    fn every_bind_address_is_checked_at_load() {
        let dir = tempfile::tempdir().unwrap();
        let load = |text: &str| {
            let path = dir.path().join("machine.toml");
            std::fs::write(&path, format!("{text}\n[[axes]]\n")).unwrap();
            MachineConfig::load(&path).map(|_| ()).map_err(|e| e.to_string())
        };
        for section in ["modbus", "ascii", "web", "freeport"] {
            for value in ["localhost", "127.0.0.1:502", "127.0.0.256", "", "0.0.0.0 "] {
                let error = load(&format!("[{section}]\nbind = {value:?}")).expect_err(value);
                assert!(error.contains(&format!("{section}.bind: {value:?} is not an IP address")), "{error}");
            }
            for value in ["127.0.0.1", "0.0.0.0", "::1", "::"] {
                assert_eq!(load(&format!("[{section}]\nbind = {value:?}")), Ok(()), "{section}.bind = {value}");
            }
        }
    }

    /// `[web]`: a host name without a port, a password that is not empty, limits in range.
    #[test]
    fn the_web_section_is_checked() {
        let key = |text: &str| match parse(&format!("{text}\n[[axes]]\n")).validate() {
            Err(ConfigError::Invalid { key, .. }) => key,
            other => panic!("{text}: {other:?}"),
        };
        assert_eq!(key("[web]\nallowed_hosts = [\"cell-7.local\", \"cell-7:8080\"]"), "web.allowed_hosts[1]");
        assert_eq!(key("[web]\nallowed_hosts = [\"\"]"), "web.allowed_hosts[0]");
        assert_eq!(key("[web]\npassword = \"\""), "web.password");
        assert_eq!(key("[web]\nmax_connections = 0"), "web.max_connections");
        assert_eq!(key("[web]\nheader_timeout_ms = 0"), "web.header_timeout_ms");
        let web = parse("[web]\nallowed_hosts = [\"cell-7.local\"]\npassword = \"s3cret\"\n[[axes]]\n");
        assert!(web.validate().is_ok());
    }

    /// A probe input needs the CiA 402 touch probe (the CoE manual's drive latches the
    /// index only) and a window `[L, R]` with L <= R.
    #[test]
    fn probe_inputs_need_a_cia402_touch_probe() {
        let key = |text: &str| match parse(text).validate() {
            Err(ConfigError::Invalid { key, .. }) => key,
            other => panic!("{text}: {other:?}"),
        };
        let index_only = "[[axes]]\ntravel = { probe_input_1 = [1.0, 2.0] }\n";
        assert_eq!(key(index_only), "axes[0].travel.probe_input_1");
        let reversed =
            "[[axes]]\ntravel = { probe_input_2 = [2.0, 1.0] }\ndrive_settings = { touch_probe = \"cia402\" }\n";
        assert_eq!(key(reversed), "axes[0].travel.probe_input_2");
        let good = "[[axes]]\ntravel = { probe_input_2 = [1.0, 2.0] }\ndrive_settings = { touch_probe = \"cia402\" }\n";
        assert!(parse(good).validate().is_ok());
        assert_eq!(parse(good).axes[0].touch_probe_tx_pdo().len(), 5, "0x60B9, 0x60BA..0x60BD");
    }

    /// `[ascii]`: HMPL 22.1's ports by default; the agent slot is an external task that no
    /// other task nor the DRL project may use.
    #[test]
    fn the_ascii_agent_has_a_slot_of_its_own() {
        let ascii = MachineConfig::default().ascii;
        assert_eq!(
            (ascii.bind.as_str(), ascii.native_port, ascii.user_port, ascii.agent_task),
            ("127.0.0.1", 3999, 4000, 62)
        );
        let config = MachineConfig::default().with_drl_task().unwrap().with_ascii_task().unwrap();
        let slot = config.tasks.iter().find(|t| t.id == 62).expect("the agent slot");
        assert!(slot.external && slot.front_end && !slot.autorun);
        let taken = parse("[drl]\ntask = 5\n[ascii]\nagent_task = 5\n").with_drl_task().unwrap().with_ascii_task();
        assert!(matches!(taken, Err(ConfigError::Invalid { key, .. }) if key == "ascii.agent_task"));
        let outside = parse("[ascii]\nagent_task = 64\n").with_ascii_task();
        assert!(matches!(outside, Err(ConfigError::Invalid { key, .. }) if key == "ascii.agent_task"));
        let config = parse("[ascii]\nmax_connections = 0\n");
        assert!(matches!(config.validate(), Err(ConfigError::Invalid { key, .. }) if key == "ascii.max_connections"));
    }

    /// HMPL 2.14, 2.15: `[identity]` has defaults; what does not fit 64 bytes is refused.
    #[test]
    fn identity_of_the_controller() {
        let config = parse("[[axes]]\nname = \"x\"\n");
        assert_eq!((config.identity.model.as_str(), config.identity.serial.as_str()), ("luamotion-sim", "LM00000000"));
        let config = parse("[[axes]]\nname = \"x\"\n[identity]\nserial = \"SN 7\"\n");
        assert_eq!((config.identity.model.as_str(), config.identity.serial.as_str()), ("luamotion-sim", "SN 7"));
        assert!(config.validate().is_ok());
        let long = "m".repeat(65);
        let config = parse(&format!("[[axes]]\nname = \"x\"\n[identity]\nmodel = \"{long}\"\n"));
        assert!(matches!(config.validate(), Err(ConfigError::Invalid { key, .. }) if key == "identity.model"));
    }

    /// `[serial]`: port 1 on by default as 8,N,1 Modbus RTU at 38400; its link is relative to
    /// the machine file; parameters 5-1 and 5-4 outside their tables are refused by key.
    #[test]
    fn serial_port_settings() {
        let default = MachineConfig::default().serial;
        assert_eq!((default.enabled, default.protocol, default.baud, default.loopback), (true, 0x16, 3, false));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("machine.toml");
        std::fs::write(&path, "[serial]\nlink = \"ttyS1\"\nprotocol = 0x17\n").unwrap();
        assert_eq!(MachineConfig::load(&path).unwrap().serial.link, Some(dir.path().join("ttyS1")));
        for (text, key) in [("[serial]\nprotocol = 0x1E\n", "serial.protocol"), ("[serial]\nbaud = 6\n", "serial.baud")]
        {
            assert!(matches!(parse(text).validate(), Err(ConfigError::Invalid { key: k, .. }) if k == key), "{text}");
        }
    }

    /// `[rt] script_cpus`: "auto" by default, the three words read, any other refused by
    /// name.
    #[test]
    fn the_script_cpus_are_read_by_name() {
        assert_eq!(MachineConfig::default().rt.script_cpus, ScriptCpus::Auto);
        for (word, cpus) in [("auto", ScriptCpus::Auto), ("all", ScriptCpus::All), ("others", ScriptCpus::Others)] {
            assert_eq!(parse(&format!("[rt]\nscript_cpus = \"{word}\"\n")).rt.script_cpus, cpus, "{word}");
        }
        let refused = toml::from_str::<MachineConfig>("[rt]\nscript_cpus = \"rt\"\n").unwrap_err().to_string();
        assert!(refused.contains("unknown variant `rt`, expected one of `auto`, `all`, `others`"), "{refused}");
    }

    /// `[rt] huge_pages`: on by default, off when asked.
    #[test]
    fn huge_pages_are_on_unless_turned_off() {
        assert!(MachineConfig::default().rt.huge_pages);
        assert!(!parse("[rt]\nhuge_pages = false\n").rt.huge_pages);
    }

    /// `[rt] script_pool`: 2 waiting processes by default, 0 allowed, more than the
    /// services are sized for refused.
    #[test]
    fn the_script_pool_is_bounded_by_the_services() {
        assert_eq!(MachineConfig::default().rt.script_pool, 2);
        assert!(MachineConfig::default().rt.idle_poll, "idle CPUs poll by default");
        assert!(!parse("[rt]\nidle_poll = false\n").rt.idle_poll);
        assert!(parse("[rt]\nscript_pool = 0\n").validate().is_ok());
        let too_many = format!("[rt]\nscript_pool = {}\n", ipc::services::MAX_POOL + 1);
        assert!(
            matches!(parse(&too_many).validate(), Err(ConfigError::Invalid { key, .. }) if key == "rt.script_pool")
        );
    }

    /// `[axes.plant]`'s flexible load: rigid by default; a frequency, damping or mass ratio
    /// outside its range is refused by key.
    #[test]
    fn a_flexible_load_is_off_by_default_and_checked() {
        let plant = &parse("[[axes]]\nname = \"x\"\n").axes[0].plant;
        assert_eq!(plant.load_frequency_hz, 0.0, "rigid");
        let text = "[[axes]]\nname = \"x\"\n[axes.plant]\nload_frequency_hz = 8.0\nload_damping = 0.05\n";
        let config = parse(text);
        assert!(config.validate().is_ok());
        assert_eq!((config.axes[0].plant.load_frequency_hz, config.axes[0].plant.load_damping), (8.0, 0.05));
        for (line, key) in [
            ("load_frequency_hz = -1.0", "axes[0].plant.load_frequency_hz"),
            ("load_frequency_hz = 1001.0", "axes[0].plant.load_frequency_hz"),
            ("load_damping = 1.0", "axes[0].plant.load_damping"),
            ("load_mass_ratio = 0.0", "axes[0].plant.load_mass_ratio"),
            ("load_mass_ratio = 11.0", "axes[0].plant.load_mass_ratio"),
        ] {
            let config = parse(&format!("[[axes]]\nname = \"x\"\n[axes.plant]\n{line}\n"));
            assert!(matches!(config.validate(), Err(ConfigError::Invalid { key: k, .. }) if k == key), "{line}");
        }
    }

    /// `[[slaves]]`: none by default; a kind the bus cannot hold is refused by name.
    #[test]
    fn slaves_beside_the_axes() {
        assert!(MachineConfig::default().slaves.is_empty());
        assert!(parse("[[axes]]\nname = \"x\"\n").slaves.is_empty(), "a file without [[slaves]]");
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("machine.toml");
        std::fs::write(&path, "[[axes]]\nname = \"x\"\n\n[[slaves]]\ndevice = \"stepper\"\n").unwrap();
        match MachineConfig::load(&path) {
            Err(ConfigError::Parse { path: at, message }) => {
                assert_eq!(at, path);
                assert!(message.contains("unknown variant `stepper`"), "{message}");
                assert!(message.contains("line 5"), "the line of the entry: {message}");
            }
            other => panic!("expected the kind refused, got {other:?}"),
        }
    }

    /// A `digital_io` terminal: its channel counts, at most 32 each way.
    #[test]
    fn digital_io_terminals() {
        let config = parse("[[axes]]\nname = \"x\"\n\n[[slaves]]\ndevice = \"digital_io\"\ninputs = 16\noutputs = 8\n");
        let slave = &config.slaves[0];
        assert_eq!((slave.device, slave.inputs, slave.outputs), (SlaveDevice::DigitalIo, 16, 8));
        assert!(config.validate().is_ok());
        let config = parse("[[axes]]\nname = \"x\"\n\n[[slaves]]\ndevice = \"digital_io\"\noutputs = 33\n");
        assert!(
            matches!(config.validate(), Err(ConfigError::Invalid { key, .. }) if key == "slaves[0].outputs"),
            "33 outputs"
        );
        let mut full = MachineConfig::default();
        full.axes = vec![full.axes[0].clone(); MAX_AXES];
        full.slaves = parse("[[slaves]]\ndevice = \"digital_io\"\n").slaves;
        assert!(
            matches!(full.validate(), Err(ConfigError::Invalid { key, .. }) if key == "slaves"),
            "96 drives and a terminal: more slaves than the snapshot holds"
        );
    }

    /// An `analog_io` terminal: at most 4 channels each way; only it has a loopback.
    #[test]
    fn analog_io_terminals() {
        let slave = "[[axes]]\nname = \"x\"\n\n[[slaves]]\n";
        let config = parse(&format!("{slave}device = \"analog_io\"\ninputs = 2\noutputs = 4\nloopback = true\n"));
        let s = &config.slaves[0];
        assert_eq!((s.device, s.inputs, s.outputs, s.loopback), (SlaveDevice::AnalogIo, 2, 4, true));
        assert!(config.validate().is_ok());
        let config = parse(&format!("{slave}device = \"analog_io\"\ninputs = 5\n"));
        assert!(matches!(config.validate(), Err(ConfigError::Invalid { key, .. }) if key == "slaves[0].inputs"));
        let config = parse(&format!("{slave}device = \"digital_io\"\nloopback = true\n"));
        assert!(matches!(config.validate(), Err(ConfigError::Invalid { key, .. }) if key == "slaves[0].loopback"));
        let nine = format!("[[axes]]\nname = \"x\"\n{}", "[[slaves]]\ndevice = \"analog_io\"\n".repeat(9));
        assert!(
            matches!(parse(&nine).validate(), Err(ConfigError::Invalid { key, .. }) if key == "slaves[8]"),
            "9 terminals"
        );
    }
}

//! The machine configuration (TOML): cycle, RT thread, axes and their drives, tasks, the
//! DRL and Modbus sections of `luamotion serve`. One module per section of the machine
//! file; this file holds the whole file's type, its loading and the checks that span
//! sections.
//!
//! Unknown keys and wrong types are refused by serde with the key's name and line;
//! `validate` checks ranges and names the key it refuses. Nothing starts on an error.
//! The controller (`rt-core`) builds its drives from these types; this crate knows
//! nothing of the controller, so the drive can import its model from here.

mod ascii;
mod axis;
mod bus;
mod drl;
mod error;
mod freeport;
mod identity;
mod modbus;
mod rt;
mod serial;
mod slave;
mod task;
mod web;

use std::path::{Path, PathBuf};

use schema::{MAX_AXES, MAX_TASKS};
use serde::Deserialize;

pub use ascii::AsciiConfig;
pub use axis::{
    AxisConfig, BUILT_IN_RX_PDO, BUILT_IN_TX_PDO, DriveModel, DriveSettings, MAX_LOAD_FREQUENCY_HZ, PlantConfig,
    PtConfig, TOUCH_PROBE_RX_PDO, TouchProbeKind, TravelConfig, Unit,
};
pub use bus::BusConfig;
pub use drl::DrlConfig;
pub use error::ConfigError;
pub use freeport::FreePortConfig;
pub use identity::IdentityConfig;
pub use modbus::ModbusConfig;
pub use rt::{RtConfig, ScriptCpus};
pub use serial::SerialConfig;
pub use slave::{MAX_TERMINAL_CHANNELS, SlaveConfig, SlaveDevice};
pub use task::{FaultReaction, TaskConfig};
pub use web::WebConfig;

use error::invalid;

/// DC cycle times the drives accept (CoE manual table 2-1), in µs.
pub const DC_CYCLES_US: [u32; 5] = [250, 500, 1000, 2000, 4000];

/// The whole machine file; a section the file leaves out is the built-in machine's.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MachineConfig {
    /// Controller cycle in µs: one of 250, 500, 1000, 2000, 4000.
    pub cycle_us: u32,
    /// `[rt]`: how the RT thread asks the OS for real-time service, and the script pool.
    pub rt: RtConfig,
    /// `[[axes]]`: 1 to `MAX_AXES` axes, each on its own drive, in API order.
    pub axes: Vec<AxisConfig>,
    /// Devices on the bus that drive no axis, after the axes' drives in file order.
    pub slaves: Vec<SlaveConfig>,
    /// `[[tasks]]`: the programs the controller runs, one HMPL task slot each.
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
    /// `[bus]`: the EtherCAT segment in memory, or on a network interface.
    pub bus: BusConfig,
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
            bus: BusConfig::default(),
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

    /// The controller cycle in ns.
    pub fn period_ns(&self) -> u64 {
        self.cycle_us as u64 * 1000
    }

    /// Checks every section's ranges and the checks that span sections (`load` calls it;
    /// a config built in code calls it itself). The first error found is returned.
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
        self.rt.validate()?;
        // The snapshot has a fixed room for slaves: drives and terminals share it.
        if self.axes.len() + self.slaves.len() > schema::MAX_SLAVES {
            let max = schema::MAX_SLAVES;
            return Err(invalid("slaves", format!("a bus holds at most {max} slaves, the axes' drives included")));
        }
        slave::validate_slaves(&self.slaves)?;
        if self.axes.is_empty() || self.axes.len() > MAX_AXES {
            return Err(invalid("axes", format!("a machine has 1 to {MAX_AXES} axes, not {}", self.axes.len())));
        }
        for (i, axis) in self.axes.iter().enumerate() {
            axis.validate(&format!("axes[{i}]"))?;
        }
        task::validate_tasks(&self.tasks)?;
        self.drl.validate()?;
        self.modbus.validate()?;
        self.serial.validate()?;
        self.ascii.validate()?;
        self.web.validate()?;
        self.bus.validate()?;
        self.identity.validate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> MachineConfig {
        toml::from_str(text).unwrap()
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

    /// Every section's table is checked under its own key: one value out of range in each.
    #[test]
    fn each_section_is_checked_under_its_key() {
        for (text, key) in [
            ("[rt]\nscript_pool = 99", "rt.script_pool"),
            ("[[axes]]\n[axes.plant]\nload_damping = 1.0", "axes[0].plant.load_damping"),
            ("[[axes]]\n[axes.travel]\nprobe_input_1 = [1.0, 2.0]", "axes[0].travel.probe_input_1"),
            ("[[axes]]\n[axes.drive_settings]\nforce_constant = 0.0", "axes[0].drive_settings.force_constant"),
            ("[[axes]]\n[[slaves]]\ndevice = \"digital_io\"\noutputs = 33", "slaves[0].outputs"),
            ("[drl]\nwatchdog_ms = 0", "drl"),
            ("[modbus]\nstation = 0", "modbus.station"),
            ("[serial]\nbaud = 6", "serial.baud"),
            ("[ascii]\nidle_timeout_ms = 0", "ascii.idle_timeout_ms"),
            ("[web]\npassword = \"\"", "web.password"),
            ("[identity]\nserial = \"a\\u0000b\"", "identity.serial"),
        ] {
            let text = if text.contains("[[axes]]") { text.to_string() } else { format!("{text}\n[[axes]]\n") };
            let refused = parse(&text).validate();
            assert!(matches!(&refused, Err(ConfigError::Invalid { key: k, .. }) if k == key), "{text}: {refused:?}");
        }
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

    /// `[serial] link` is relative to the machine file.
    #[test]
    fn the_serial_link_is_relative_to_the_machine_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("machine.toml");
        std::fs::write(&path, "[serial]\nlink = \"ttyS1\"\nprotocol = 0x17\n").unwrap();
        assert_eq!(MachineConfig::load(&path).unwrap().serial.link, Some(dir.path().join("ttyS1")));
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

    /// The drives and the terminals share the snapshot's room for slaves.
    #[test]
    fn the_bus_holds_the_drives_and_the_terminals() {
        let mut full = MachineConfig::default();
        full.axes = vec![full.axes[0].clone(); MAX_AXES];
        full.slaves = parse("[[slaves]]\ndevice = \"digital_io\"\n").slaves;
        assert!(
            matches!(full.validate(), Err(ConfigError::Invalid { key, .. }) if key == "slaves"),
            "96 drives and a terminal: more slaves than the snapshot holds"
        );
    }
}

//! The master's side of one drive: its process-data fields, its power sequence, the mode
//! of operation it is asked for, and its feedback and commands converted to axis units.

use api::AxisError;

use crate::power::{Power, PowerEvent};
use config::AxisConfig;
use devices::cia402::{State, controlword};
use devices::ecat::{Field, Network};

/// Modes of operation the kernel uses (CoE manual table 4-17).
pub const MODE_HOMING: i64 = 6;
pub const MODE_CSP: i64 = 8;
pub const MODE_CSV: i64 = 9;
pub const MODE_CST: i64 = 10;

/// The fields of the drive's PDOs the kernel uses; absent ones are not mapped.
#[derive(Clone, Copy, Debug, Default)]
struct Io {
    controlword: Option<Field>,
    target_position: Option<Field>,
    target_velocity: Option<Field>,
    target_torque: Option<Field>,
    mode: Option<Field>,
    statusword: Option<Field>,
    position_actual: Option<Field>,
    mode_display: Option<Field>,
    digital_inputs: Option<Field>,
    error_code: Option<Field>,
    torque_actual: Option<Field>,
}

/// What the axis sends the drive this cycle, in axis units. The target position is always
/// written, so that a return to csp starts where the motor stands; velocity and torque
/// matter in csv and cst.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Output {
    pub position: f64,
    pub velocity: f64,
    /// Per mille of rated torque.
    pub torque: f64,
}

/// What the drive reported this cycle.
#[derive(Clone, Copy, Debug, Default)]
pub struct Feedback {
    /// Position actual, axis units (before the axis' own offset).
    pub position: f64,
    pub statusword: u16,
    /// 0x60FD, when mapped.
    pub digital_inputs: Option<u32>,
    /// 0x603F, when mapped.
    pub error_code: Option<u16>,
    /// 0x6061, when mapped.
    pub mode_display: Option<i64>,
    /// 0x6077, per mille of rated torque, when mapped.
    pub torque: Option<f64>,
}

pub struct DriveLink {
    slave: usize,
    counts_per_unit: f64,
    io: Io,
    power: Power,
    controlword: u16,
    /// Controlword bits a homing run adds (bit 4: start).
    extra_bits: u16,
    /// The mode of operation the kernel asks for; written by PDO, or by SDO when unmapped.
    mode: i64,
    mode_written: i64,
    /// Torque per mille per N·m (HMPL 5.2.7: force constant x rated current).
    pub per_mille_per_nm: f64,
    pub rated_current_a: f64,
}

impl DriveLink {
    pub fn new(slave: usize, config: &AxisConfig, network: &Network) -> Self {
        let out = |i| network.output_field(slave, i, 0);
        let inp = |i| network.input_field(slave, i, 0);
        let io = Io {
            controlword: out(0x6040),
            target_position: out(0x607A),
            target_velocity: out(0x60FF),
            target_torque: out(0x6071),
            mode: out(0x6060),
            statusword: inp(0x6041),
            position_actual: inp(0x6064),
            mode_display: inp(0x6061),
            digital_inputs: inp(0x60FD),
            error_code: inp(0x603F),
            torque_actual: inp(0x6077),
        };
        let settings = &config.drive_settings;
        DriveLink {
            slave,
            counts_per_unit: config.counts_per_unit,
            io,
            power: Power::Disabled,
            controlword: 0,
            extra_bits: 0,
            mode: MODE_CSP,
            mode_written: MODE_CSP,
            per_mille_per_nm: 1000.0 / (settings.force_constant * settings.rated_current_a),
            rated_current_a: settings.rated_current_a,
        }
    }

    pub fn slave(&self) -> usize {
        self.slave
    }

    /// HMPL 5.2.1: enabling needs the controlword, statusword, target and actual position mapped.
    pub fn can_enable(&self) -> bool {
        self.io.controlword.is_some()
            && self.io.statusword.is_some()
            && self.io.target_position.is_some()
            && self.io.position_actual.is_some()
    }

    /// HMPL 20.2: homing needs 0x6060 and 0x6061 mapped.
    pub fn can_home(&self) -> bool {
        self.io.mode.is_some() && self.io.mode_display.is_some()
    }

    pub fn can_run(&self, mode: i64) -> Result<(), AxisError> {
        let mapped = match mode {
            MODE_CSV => self.io.target_velocity.is_some(),
            MODE_CST => self.io.target_torque.is_some(),
            _ => true,
        };
        if mapped { Ok(()) } else { Err(AxisError::CmdInvalidNoSpecificPdo) }
    }

    pub fn is_enabled(&self) -> bool {
        self.power.is_enabled()
    }

    /// What `IsEnabled` reports (HMPL 5.4.1): the drive is in Operation enabled, which it
    /// still is while the disable sequence runs.
    pub fn drive_enabled(&self) -> bool {
        matches!(self.power, Power::Enabled | Power::Disabling { .. })
    }

    pub fn is_disabled(&self) -> bool {
        self.power == Power::Disabled
    }

    pub fn enable(&mut self, cycle: u64) {
        if matches!(self.power, Power::Disabled | Power::Disabling { .. }) {
            self.power = Power::Enabling { since: cycle };
        }
    }

    pub fn disable(&mut self, cycle: u64) {
        if matches!(self.power, Power::Enabled | Power::Enabling { .. }) {
            self.power = Power::Disabling { since: cycle };
        }
    }

    /// The drive's quick stop; the axis ends disabled.
    pub fn quick_stop(&mut self, cycle: u64) {
        if matches!(self.power, Power::Enabled | Power::Enabling { .. }) {
            self.power = Power::QuickStopping { since: cycle };
        }
    }

    /// Starts clearing a drive fault (fault reset edge).
    pub fn reset_fault(&mut self, cycle: u64) {
        self.power = Power::Resetting { since: cycle, edge_sent: false };
    }

    pub fn set_mode(&mut self, mode: i64) {
        self.mode = mode;
    }

    pub fn set_extra_bits(&mut self, bits: u16) {
        self.extra_bits = bits;
    }

    pub fn controlword(&self) -> u16 {
        self.controlword
    }

    /// Reads this cycle's inputs.
    pub fn read(&self, inputs: &[u8]) -> Feedback {
        let read = |f: Option<Field>| f.map(|f| f.read(inputs));
        Feedback {
            position: read(self.io.position_actual).unwrap_or(0) as f64 / self.counts_per_unit,
            statusword: read(self.io.statusword).unwrap_or(0) as u16,
            digital_inputs: read(self.io.digital_inputs).map(|v| v as u32),
            error_code: read(self.io.error_code).map(|v| v as u16),
            mode_display: read(self.io.mode_display),
            torque: read(self.io.torque_actual).map(|v| v as f64),
        }
    }

    /// One step of the power sequence against the drive's statusword.
    pub fn sequence(&mut self, statusword: Option<u16>, cycle: u64, timeout_cycles: u64, at_rest: bool) -> PowerEvent {
        let drive = statusword.and_then(State::from_statusword);
        let (cw, event) = self.power.step(drive, cycle, timeout_cycles, at_rest);
        self.controlword = cw;
        event
    }

    /// Writes this cycle's outputs: controlword, mode, and the target of the mode.
    pub fn write(&mut self, network: &mut Network, output: Output) {
        if self.io.mode.is_none() && self.mode != self.mode_written {
            // Not in the PDO: the master sets the mode by SDO.
            let _ = network.sdo_write(self.slave, 0x6060, 0, &[self.mode as u8]);
        }
        self.mode_written = self.mode;
        let (_, outputs) = network.images_mut();
        let mut put = |f: Option<Field>, v: i64| {
            if let Some(f) = f {
                f.write(outputs, v);
            }
        };
        let cw = if self.controlword == controlword::ENABLE_OPERATION_CMD {
            self.controlword | self.extra_bits
        } else {
            self.controlword
        };
        put(self.io.controlword, cw as i64);
        put(self.io.mode, self.mode);
        put(self.io.target_position, (output.position * self.counts_per_unit).round() as i64);
        put(self.io.target_velocity, (output.velocity * self.counts_per_unit).round() as i64);
        put(self.io.target_torque, output.torque.round().clamp(-1000.0, 1000.0) as i64);
    }

    /// A position in axis units as drive counts.
    pub fn counts(&self, units: f64) -> f64 {
        units * self.counts_per_unit
    }

    /// Drive counts in axis units.
    pub fn units(&self, counts: f64) -> f64 {
        counts / self.counts_per_unit
    }
}

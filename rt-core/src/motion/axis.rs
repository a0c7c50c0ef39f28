//! One axis of the motion kernel (HMPL ch. 5): its settings, power sequence, profile
//! generator and status, reaching its drive only through process data.

use api::AxisError;
use ipc::messages::{AxisSnapshot, fault_status, motion_status};

use crate::cia402::State;
use crate::config::AxisConfig;
use crate::ecat::{Field, Network};
use crate::motion::power::{Power, PowerEvent};
use crate::profile::{Kinematics, Limits, Trapezoid};

/// The process-data fields the axis uses. HMPL 5.2.1: enabling needs 0x6040/0x6041 mapped.
#[derive(Clone, Copy, Debug)]
pub struct AxisIo {
    controlword: Option<Field>,
    target_position: Option<Field>,
    statusword: Option<Field>,
    position_actual: Option<Field>,
}

impl AxisIo {
    pub fn resolve(network: &Network, slave: usize) -> Self {
        AxisIo {
            controlword: network.output_field(slave, 0x6040, 0),
            target_position: network.output_field(slave, 0x607A, 0),
            statusword: network.input_field(slave, 0x6041, 0),
            position_actual: network.input_field(slave, 0x6064, 0),
        }
    }

    fn complete(&self) -> bool {
        self.controlword.is_some()
            && self.target_position.is_some()
            && self.statusword.is_some()
            && self.position_actual.is_some()
    }
}

/// The profile and monitoring settings of HMPL 5.3, in mm (or deg), s and ms.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    pub vel: f64,
    pub acc: f64,
    pub dec: f64,
    /// In-position window (mm) and the time (ms) the feedback must stay in it (HMPL 5.1).
    pub pos_window: f64,
    pub pos_window_time_ms: f64,
    /// `HCV_ID_en_delay`: how long the drive may take to enable or disable.
    pub enable_timeout_ms: f64,
}

/// What the profile generator is doing. The plan lives inline: the RT thread does not allocate.
#[derive(Clone, Copy, Debug)]
#[allow(clippy::large_enum_variant)]
enum Motion {
    Idle,
    Profile { plan: Trapezoid, elapsed: f64 },
}

pub struct Axis {
    id: u8,
    io: AxisIo,
    counts_per_unit: f64,
    max_vel: f64,
    max_acc: f64,
    settings: Settings,
    power: Power,
    motion: Motion,
    reference: Kinematics,
    pos_fb: f64,
    vel_fb: f64,
    controlword: u16,
    statusword: u16,
    error_stop: bool,
    fault_status: u32,
    in_window_cycles: u32,
    last_err: Option<AxisError>,
    cycle: u64,
    period_s: f64,
}

impl Axis {
    pub fn new(id: u8, config: &AxisConfig, io: AxisIo, period_s: f64) -> Self {
        Axis {
            id,
            io,
            counts_per_unit: config.counts_per_unit,
            max_vel: config.max_vel,
            max_acc: config.max_acc,
            settings: Settings {
                vel: config.vel,
                acc: config.acc,
                dec: config.dec,
                pos_window: 0.005,
                pos_window_time_ms: 5.0,
                enable_timeout_ms: 1000.0,
            },
            power: Power::Disabled,
            motion: Motion::Idle,
            reference: Kinematics::default(),
            pos_fb: 0.0,
            vel_fb: 0.0,
            controlword: 0,
            statusword: 0,
            error_stop: false,
            fault_status: 0,
            in_window_cycles: 0,
            last_err: None,
            cycle: 0,
            period_s,
        }
    }

    pub fn id(&self) -> u8 {
        self.id
    }

    pub fn is_enabled(&self) -> bool {
        self.power.is_enabled()
    }

    /// The drive is out of Operation enabled and nothing is asked of it.
    pub fn is_disabled(&self) -> bool {
        self.power == Power::Disabled
    }

    pub fn is_moving(&self) -> bool {
        matches!(self.motion, Motion::Profile { .. })
    }

    pub fn reference(&self) -> Kinematics {
        self.reference
    }

    pub fn pos_fb(&self) -> f64 {
        self.pos_fb
    }

    /// Records a rejection or a fault as the axis' last error (HMPL 18.3) and returns it.
    pub fn fail(&mut self, error: AxisError) -> AxisError {
        self.last_err = Some(error);
        error
    }

    fn cycles(&self, ms: f64) -> u64 {
        (ms / 1000.0 / self.period_s).ceil() as u64
    }

    // --- commands (HMPL 5.2, 5.3) ---

    pub fn enable(&mut self) -> Result<(), AxisError> {
        if !self.io.complete() {
            return Err(self.fail(AxisError::CmdInvalidNoSpecificPdo));
        }
        if self.error_stop {
            return Err(self.fail(AxisError::CmdInvalidErrorState));
        }
        if matches!(self.power, Power::Disabled | Power::Disabling { .. }) {
            self.power = Power::Enabling { since: self.cycle };
        }
        Ok(())
    }

    pub fn disable(&mut self) -> Result<(), AxisError> {
        self.motion = Motion::Idle;
        if matches!(self.power, Power::Enabled | Power::Enabling { .. }) {
            self.power = Power::Disabling { since: self.cycle };
        }
        Ok(())
    }

    pub fn move_abs(&mut self, pos: f64) -> Result<(), AxisError> {
        self.check_can_move()?;
        if !pos.is_finite() || (pos * self.counts_per_unit).abs() > i32::MAX as f64 {
            return Err(self.fail(AxisError::CmdInvalidPos));
        }
        let limits = Limits { vel: self.settings.vel, acc: self.settings.acc, dec: self.settings.dec };
        let plan = Trapezoid::plan(self.reference.pos, self.reference.vel, pos, limits);
        self.motion = Motion::Profile { plan, elapsed: 0.0 };
        Ok(())
    }

    /// Relative to the target of the move under way, else to the reference position, so
    /// that two quick `MoveRel(a, 10)` add up to 20.
    pub fn move_rel(&mut self, distance: f64) -> Result<(), AxisError> {
        let base = match self.motion {
            Motion::Profile { plan, .. } => plan.target(),
            Motion::Idle => self.reference.pos,
        };
        self.move_abs(base + distance)
    }

    fn check_can_move(&mut self) -> Result<(), AxisError> {
        if self.error_stop {
            return Err(self.fail(AxisError::CmdInvalidErrorState));
        }
        if !self.power.is_enabled() {
            return Err(self.fail(AxisError::CmdInvalidDisabled));
        }
        Ok(())
    }

    /// HMPL 5.3.2: velocity > 0, and at most the axis' configured `max_vel`.
    pub fn set_vel(&mut self, vel: f64) -> Result<(), AxisError> {
        if !(vel > 0.0 && vel <= self.max_vel) {
            return Err(self.fail(AxisError::CmdInvalidVel));
        }
        self.settings.vel = vel;
        Ok(())
    }

    pub fn set_acc(&mut self, acc: f64) -> Result<(), AxisError> {
        if !(acc > 0.0 && acc <= self.max_acc) {
            return Err(self.fail(AxisError::CmdInvalidAcc));
        }
        self.settings.acc = acc;
        Ok(())
    }

    pub fn set_dec(&mut self, dec: f64) -> Result<(), AxisError> {
        if !(dec > 0.0 && dec <= self.max_acc) {
            return Err(self.fail(AxisError::CmdInvalidDec));
        }
        self.settings.dec = dec;
        Ok(())
    }

    // --- the cycle ---

    /// One cycle: read the drive, sequence power, advance the profile, write the drive.
    pub fn step(&mut self, cycle: u64, inputs: &[u8], outputs: &mut [u8]) {
        self.cycle = cycle;
        let read = |field: Option<Field>| field.map_or(0, |f| f.read(inputs));
        self.statusword = read(self.io.statusword) as u16;
        let pos_fb = read(self.io.position_actual) as f64 / self.counts_per_unit;
        self.vel_fb = (pos_fb - self.pos_fb) / self.period_s;
        self.pos_fb = pos_fb;

        let timeout = self.cycles(self.settings.enable_timeout_ms);
        let drive = State::from_statusword(self.statusword);
        let (controlword, event) = self.power.step(drive, cycle, timeout);
        self.controlword = controlword;
        self.on_power_event(event);

        if self.power.is_enabled() {
            self.advance_profile();
        } else {
            // A disabled axis' reference follows the motor, so enabling never jumps.
            self.motion = Motion::Idle;
            self.reference = Kinematics { pos: self.pos_fb, vel: 0.0, acc: 0.0 };
        }

        let in_window = (self.reference.pos - self.pos_fb).abs() <= self.settings.pos_window;
        self.in_window_cycles =
            if in_window && !self.is_moving() { self.in_window_cycles.saturating_add(1) } else { 0 };

        if let Some(f) = self.io.controlword {
            f.write(outputs, self.controlword as i64);
        }
        if let Some(f) = self.io.target_position {
            f.write(outputs, (self.reference.pos * self.counts_per_unit).round() as i64);
        }
    }

    fn on_power_event(&mut self, event: PowerEvent) {
        match event {
            PowerEvent::None | PowerEvent::Disabled => {}
            PowerEvent::Enabled => {
                self.reference = Kinematics { pos: self.pos_fb, vel: 0.0, acc: 0.0 };
                self.motion = Motion::Idle;
            }
            PowerEvent::Timeout => {
                let error = if self.statusword_says_enabled() {
                    AxisError::DriveDisableTout
                } else {
                    AxisError::DriveEnableTout
                };
                self.fail(error);
            }
            PowerEvent::DriveFault => {
                self.error_stop = true;
                self.fault_status |= fault_status::DRIVE_FAULT;
                self.fail(AxisError::DriveFault);
            }
            PowerEvent::AbnormalDisable => {
                self.error_stop = true;
                self.fail(AxisError::DriveAbnormalDisable);
            }
        }
    }

    fn statusword_says_enabled(&self) -> bool {
        State::from_statusword(self.statusword) == Some(State::OperationEnabled)
    }

    fn advance_profile(&mut self) {
        if let Motion::Profile { plan, elapsed } = &mut self.motion {
            *elapsed += self.period_s;
            self.reference = plan.at(*elapsed);
            if *elapsed >= plan.duration() {
                self.motion = Motion::Idle;
            }
        }
    }

    /// The axis as `motion_status` and `fault_status` show it (HMPL tables 5.1.1.4, 5.1.1.5).
    pub fn snapshot(&self) -> AxisSnapshot {
        let mut motion = 0;
        if self.power.is_enabled() {
            motion |= motion_status::ENABLED;
            let window = self.cycles(self.settings.pos_window_time_ms).max(1);
            if self.in_window_cycles as u64 >= window {
                motion |= motion_status::IN_POSITION;
            }
        }
        if self.is_moving() {
            motion |= motion_status::MOVING;
        }
        if self.reference.acc * self.reference.vel > 0.0 {
            motion |= motion_status::ACCELERATING;
        }
        let mut fault = self.fault_status;
        if self.error_stop {
            fault |= fault_status::ERROR_STOP;
        }
        AxisSnapshot {
            motion_status: motion,
            fault_status: fault,
            last_err: self.last_err.map_or(0, |e| api::ErrorCode::axis(self.id, e).code()),
            coe_controlword: self.controlword,
            coe_statusword: self.statusword,
            ref_pos: self.reference.pos,
            ref_vel: self.reference.vel,
            ref_acc: self.reference.acc,
            pos_out: self.reference.pos,
            pos_fb: self.pos_fb,
            vel_fb: self.vel_fb,
            pos_err: self.reference.pos - self.pos_fb,
            vel: self.settings.vel,
            acc: self.settings.acc,
            dec: self.settings.dec,
        }
    }
}

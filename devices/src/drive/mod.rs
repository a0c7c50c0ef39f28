//! A simulated HIWIN CoE drive: the CiA 402 application of one EtherCAT slave.
//!
//! The drive sees only its object dictionary: the master writes the controlword, the mode
//! and the targets (by PDO or SDO); each cycle the drive runs its state machine and its
//! mode of operation, moves the motor through its servo loops, watches the limits, and
//! writes the statusword and the feedback objects back.

pub mod faults;
pub mod fsa;
pub(crate) mod limits;
pub(crate) mod modes;
pub(crate) mod od;
pub(crate) mod plant;
pub(crate) mod touch_probe;
pub(crate) mod travel;

pub use config::DriveModel;

use crate::cia402::{State, statusword};
use crate::coe::ObjectStore;
use crate::ecat::SdoAbort;
use crate::ecat::device::Device;
use crate::profile::{Kinematics, ramp_velocity};
use config::{AxisConfig, DriveSettings, TouchProbeKind};
use fsa::Fsa;
use limits::{FollowingError, HardwareLimits, clamp_to_software_limits};
use modes::homing::{Homing, HomingEvent};
use modes::profile_position::ProfilePosition;
use modes::profile_torque::ProfileTorque;
use modes::profile_velocity::ProfileVelocity;
use modes::{ModeInput, ModeOfOperation, Setpoint, cyclic};
use plant::{Demand, Plant, SERVO_PERIOD_S};
use touch_probe::TouchProbe;
use travel::{Edges, Travel};

/// The "save" signature of 0x1010:01 (CiA 301; the manual's fig. 4-1 is missing).
pub const SAVE_SIGNATURE: u32 = 0x6576_6173;

/// The running mode and its state.
#[derive(Clone, Debug)]
enum ActiveMode {
    /// Holds still. After an interrupted homing it keeps showing the homing status, as it
    /// has no bits 10, 12, 13 of its own (CoE manual 3.2, A4).
    NoMode {
        shown: u16,
    },
    ProfilePosition(ProfilePosition),
    ProfileVelocity(ProfileVelocity),
    ProfileTorque(ProfileTorque),
    Homing(Homing),
    Cyclic(ModeOfOperation),
}

impl ActiveMode {
    fn operation(&self) -> ModeOfOperation {
        match self {
            ActiveMode::NoMode { .. } => ModeOfOperation::NoMode,
            ActiveMode::ProfilePosition(_) => ModeOfOperation::ProfilePosition,
            ActiveMode::ProfileVelocity(_) => ModeOfOperation::ProfileVelocity,
            ActiveMode::ProfileTorque(_) => ModeOfOperation::ProfileTorque,
            ActiveMode::Homing(_) => ModeOfOperation::Homing,
            ActiveMode::Cyclic(m) => *m,
        }
    }
}

/// The drive on the bus: the slave reaches it through its dictionary and these.
impl Device for Drive {
    fn od(&self) -> &ObjectStore {
        &self.od
    }

    fn od_mut(&mut self) -> &mut ObjectStore {
        &mut self.od
    }

    fn step(&mut self, period_s: f64) {
        Drive::step(self, period_s);
    }

    fn sdo_download(&mut self, index: u16, _sub: u8, value: i64) -> Result<bool, SdoAbort> {
        match index {
            0x1010 if !self.store_parameters(value as u32) => Err(SdoAbort::DeviceState),
            0x1010 => Ok(true),
            _ => Ok(false),
        }
    }

    /// Digital inputs and outputs a model has (CoE manual fig. 4-2, table 4-19).
    fn digital_channels(&self) -> (u8, u8) {
        match self.model {
            // I1..I10, O1..O5.
            DriveModel::D1N | DriveModel::D1 | DriveModel::D2 => (10, 5),
            // The manual documents no inputs for abily.
            DriveModel::Abily => (0, 5),
        }
    }

    /// The master's frames stopped: CoE manual table 4-16, error 23 (0x7580, EtherCAT
    /// interface not detected; drive error events 2 bit 30), and the fault reaction.
    fn process_data_lost(&mut self) {
        if let Some(fault) = faults::find(ETHERCAT_LOST) {
            self.raise(fault);
            self.fsa.fault();
        }
    }
}

/// CoE manual table 4-16, error 23: every model reports it.
const ETHERCAT_LOST: u16 = 0x7580;

/// Why the simulation could not inject a drive fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum FaultInjectionError {
    /// A code table 4-16 does not list.
    #[error("0x{0:04X} is not an error code of CoE manual table 4-16")]
    UnknownCode(u16),
    /// A code the model does not report (an X in table 4-16).
    #[error("the {1:?} drive does not report 0x{0:04X} (CoE manual table 4-16)")]
    NotOnThisModel(u16, DriveModel),
    /// The slave at this position holds no drive.
    #[error("slave {0} is not a drive")]
    NotADrive(usize),
    /// The drives are on a wire: a real drive's faults are its own.
    #[error("slave {0} is on a wire, not simulated here")]
    NotSimulated(usize),
}

/// A simulated HIWIN CoE drive and the motor behind it: the device of an axis' slave.
pub struct Drive {
    model: DriveModel,
    settings: DriveSettings,
    od: ObjectStore,
    fsa: Fsa,
    plant: Plant,
    travel: Travel,
    mode: ActiveMode,
    /// Position demand (drive coordinates) at the end of the last cycle.
    demand: Kinematics,
    /// Drive coordinates = raw encoder counts + shift (homing moves the origin).
    shift: f64,
    limits: HardwareLimits,
    internal_limit: bool,
    following: FollowingError,
    touch_probe: TouchProbe,
    /// Edges the motor crossed in the last cycle (raw counts).
    edges: Edges,
    outputs: u32,
}

impl Drive {
    /// The drive of `axis` at power-up: Not ready to switch on, its dictionary at the
    /// defaults of the model, the motor at the travel's start position.
    pub fn new(axis: &AxisConfig) -> Self {
        let travel = Travel::from_config(&axis.travel, axis.counts_per_unit);
        let start = axis.travel.start_position * axis.counts_per_unit;
        let plant = Plant::new(
            &axis.plant,
            axis.counts_per_unit,
            start,
            (travel.negative_hard_stop, travel.positive_hard_stop),
        );
        let mut od = od::store(axis.drive, axis.drive_settings.touch_probe);
        od.set(od::MOTOR_RATED_CURRENT, (axis.drive_settings.rated_current_a * 1000.0) as i64);
        let mut drive = Drive {
            model: axis.drive,
            settings: axis.drive_settings.clone(),
            od,
            fsa: Fsa::default(),
            plant,
            travel,
            mode: ActiveMode::Cyclic(ModeOfOperation::CyclicSyncPosition),
            demand: Kinematics { pos: start.round(), vel: 0.0, acc: 0.0 },
            shift: 0.0,
            limits: HardwareLimits::at_power_up(&travel, start),
            internal_limit: false,
            following: FollowingError::default(),
            touch_probe: TouchProbe::new(axis.drive_settings.touch_probe),
            edges: Edges::default(),
            outputs: 0,
        };
        drive.update_feedback();
        drive
    }

    /// The CiA 402 state the statusword shows.
    pub fn state(&self) -> State {
        self.fsa.state()
    }

    /// The motor's position in raw encoder counts (the machine's own coordinates).
    pub fn raw_position(&self) -> f64 {
        self.plant.position
    }

    /// Simulation only: where a flexible load is, in drive coordinates (counts, as the
    /// position actual value); `None` for a rigid load. No object carries it: a drive
    /// measures only its motor.
    pub fn load_position(&self) -> Option<f64> {
        self.plant.load_position().map(|p| p + self.shift)
    }

    /// The state of the brake (bit 16, 1 = released) and outputs O1..O5 (bits 17..21).
    pub fn outputs(&self) -> u32 {
        self.outputs
    }

    /// A fault of table 4-16: 0x603F, its error-events bit, then Fault reaction active.
    pub fn inject_fault(&mut self, code: u16) -> Result<(), FaultInjectionError> {
        let fault = faults::find(code).ok_or(FaultInjectionError::UnknownCode(code))?;
        if !fault.supported_on(self.model) {
            return Err(FaultInjectionError::NotOnThisModel(code, self.model));
        }
        self.raise(fault);
        self.fsa.fault();
        Ok(())
    }

    fn raise(&mut self, fault: &faults::FaultDef) {
        self.od.set(od::ERROR_CODE, fault.code as i64);
        let (events, bit) = fault.events_bit(self.model);
        let object = if events == faults::Events::One { od::ERROR_EVENTS_1 } else { od::ERROR_EVENTS_2 };
        self.od.set(object, self.od.get(object) | 1 << bit);
        self.od.set(od::ERROR_REGISTER, 1);
    }

    fn clear_faults(&mut self) {
        for object in [od::ERROR_CODE, od::ERROR_EVENTS_1, od::ERROR_EVENTS_2, od::ERROR_REGISTER] {
            self.od.set(object, 0);
        }
        self.following.reset();
    }

    /// 0x1010:01 written: with the "save" signature in Switch on disabled the parameters
    /// are stored and the object reads back 1 (CoE manual table 4-1). Returns false when
    /// the drive's state forbids it.
    pub fn store_parameters(&mut self, value: u32) -> bool {
        if value != SAVE_SIGNATURE {
            return true;
        }
        if self.fsa.state() != State::SwitchOnDisabled {
            return false;
        }
        self.od.set(od::SAVE_ALL_PARAMETERS, 1);
        true
    }

    /// One bus cycle of `period_s` seconds.
    pub fn step(&mut self, period_s: f64) {
        let cw = self.od.get(od::CONTROLWORD) as u16;
        let before = self.fsa.state();
        if self.fsa.step(cw, self.demand.vel == 0.0) == Some(15) {
            self.clear_faults();
        }
        let state = self.fsa.state();
        if before == State::OperationEnabled
            && state != State::OperationEnabled
            && let ActiveMode::Homing(homing) = &mut self.mode
        {
            homing.interrupt();
        }
        self.switch_mode(cw, period_s);

        let mut setpoint = match state {
            State::OperationEnabled => self.run_mode(cw, period_s),
            State::QuickStopActive | State::FaultReactionActive => self.ramp_down(period_s),
            _ => Setpoint::Hold,
        };
        self.internal_limit = false;
        let operation = self.mode.operation();
        if operation.software_limits_apply() && self.od.get(od::SOFTWARE_LIMIT_ENABLE) & 1 != 0 {
            self.internal_limit |= clamp_to_software_limits(&mut setpoint, self.software_limits());
        }
        let protect = self.od.get(od::HARDWARE_LIMIT_ENABLE) & 1 != 0;
        if protect && operation != ModeOfOperation::Homing {
            self.internal_limit |= self.limits.guard(&mut setpoint, self.demand.pos);
        }
        let commanded = limits::direction(&setpoint, self.demand.pos);

        self.move_motor(setpoint, state.is_energised(), period_s);

        let raw = self.plant.position;
        if protect {
            let reached = self.limits.update(&self.edges, commanded);
            if reached && operation != ModeOfOperation::Homing {
                self.stop_mode();
            }
        } else {
            self.limits.negative = self.travel.negative_limit_active(raw);
            self.limits.positive = self.travel.positive_limit_active(raw);
        }
        self.touch_probe.update(self.od.get(od::TOUCH_PROBE_FUNCTION) as u16, &self.edges, self.shift);

        if operation.following_error_applies() && state == State::OperationEnabled {
            let error = self.demand.pos - (raw + self.shift);
            let window = self.od.get(od::FOLLOWING_ERROR_WINDOW) as u32;
            let timeout = self.od.get(od::FOLLOWING_ERROR_TIMEOUT) as u16;
            if self.following.check(error, window, timeout, period_s) {
                self.raise(faults::find(faults::POSITION_ERROR_TOO_BIG).expect("in table 4-16"));
                self.fsa.fault();
            }
        } else {
            self.following.reset();
        }
        self.update_outputs(state);
        self.update_feedback();
    }

    /// What a mode reads of the drive this cycle.
    fn input(&self, cw: u16, period_s: f64) -> ModeInput<'_> {
        ModeInput {
            od: &self.od,
            controlword: cw,
            demand: self.demand,
            actual: self.plant.position + self.shift,
            actual_velocity: self.plant.velocity,
            force: self.plant.force,
            period_s,
            edges: &self.edges,
            shift: self.shift,
            travel: &self.travel,
        }
    }

    fn software_limits(&self) -> (f64, f64) {
        (self.od.get(od::MIN_SOFTWARE_LIMIT) as f64, self.od.get(od::MAX_SOFTWARE_LIMIT) as f64)
    }

    /// Applies 0x6060: a supported value becomes the mode (0x6061 follows); others are
    /// ignored. Homing under way is stopped first (CoE manual 3.2, A4 and B4).
    fn switch_mode(&mut self, cw: u16, period_s: f64) {
        let raw = self.od.get(od::MODES_OF_OPERATION);
        let Some(requested) = i8::try_from(raw).ok().and_then(|v| ModeOfOperation::try_from(v).ok()) else { return };
        if requested == self.mode.operation() {
            return;
        }
        let mut shown = 0;
        if let ActiveMode::Homing(homing) = &self.mode {
            if homing.in_progress() {
                let mut homing = homing.clone();
                let event = homing.leave(requested == ModeOfOperation::NoMode, &self.input(cw, period_s));
                self.mode = ActiveMode::Homing(homing);
                if event == Some(HomingEvent::Error) {
                    self.raise(faults::find(faults::HOMING_ERROR).expect("in table 4-16"));
                }
                return;
            }
            shown = homing.status_bits();
            // Leaving homing clears the limit flags of 0x60FD (note b).
            self.limits.clear();
        }
        self.mode = match requested {
            ModeOfOperation::NoMode => ActiveMode::NoMode { shown },
            ModeOfOperation::ProfilePosition => ActiveMode::ProfilePosition(ProfilePosition::default()),
            ModeOfOperation::ProfileVelocity => {
                ActiveMode::ProfileVelocity(ProfileVelocity::starting_at(self.demand.vel))
            }
            ModeOfOperation::ProfileTorque => ActiveMode::ProfileTorque(ProfileTorque::default()),
            ModeOfOperation::Homing => ActiveMode::Homing(Homing::new(self.model, self.settings.clone())),
            cyclic => ActiveMode::Cyclic(cyclic),
        };
    }

    fn run_mode(&mut self, cw: u16, period_s: f64) -> Setpoint {
        let software_limits = (self.od.get(od::SOFTWARE_LIMIT_ENABLE) & 1 != 0).then(|| self.software_limits());
        // The mode is taken out while it runs, so that it can read the rest of the drive.
        let mut mode = std::mem::replace(&mut self.mode, ActiveMode::NoMode { shown: 0 });
        let input = self.input(cw, period_s);
        let (setpoint, event) = match &mut mode {
            ActiveMode::NoMode { .. } => (Setpoint::Hold, None),
            ActiveMode::ProfilePosition(pp) => {
                pp.set_software_limits(software_limits);
                (pp.step(&input), None)
            }
            ActiveMode::ProfileVelocity(pv) => (pv.step(&input), None),
            ActiveMode::ProfileTorque(tq) => (tq.step(&input), None),
            ActiveMode::Homing(homing) => homing.step(&input),
            ActiveMode::Cyclic(m) => (cyclic::step(*m, &input), None),
        };
        self.mode = mode;
        match event {
            None => setpoint,
            Some(HomingEvent::Started) => {
                if self.od.get(od::ERROR_CODE) == faults::HOMING_ERROR as i64 {
                    self.clear_faults();
                }
                setpoint
            }
            Some(HomingEvent::Error) => {
                self.raise(faults::find(faults::HOMING_ERROR).expect("in table 4-16"));
                setpoint
            }
            Some(HomingEvent::Home { raw }) => {
                // The home point now reads as the home offset (CoE manual 3.2.3).
                let new_shift = self.od.get(od::HOME_OFFSET) as f64 - raw;
                let moved = new_shift - self.shift;
                self.shift = new_shift;
                self.demand.pos += moved;
                match setpoint {
                    Setpoint::Position { pos, vel } => Setpoint::Position { pos: pos + moved, vel },
                    other => other,
                }
            }
        }
    }

    /// A limit switch reached: the profile modes drop what they were doing.
    fn stop_mode(&mut self) {
        match &mut self.mode {
            ActiveMode::ProfilePosition(pp) => pp.abort(),
            ActiveMode::ProfileVelocity(pv) => pv.stop(),
            ActiveMode::ProfileTorque(tq) => tq.stop(),
            _ => {}
        }
        self.demand.vel = 0.0;
    }

    /// Quick stop and fault reaction: the demand decelerates with 0x6085 to rest (a
    /// deceleration of 0, the default, stops at once).
    fn ramp_down(&mut self, period_s: f64) -> Setpoint {
        let dec = self.od.get(od::QUICK_STOP_DECELERATION) as f64;
        let v = self.demand.vel;
        let next = if dec > 0.0 { ramp_velocity(v, 0.0, dec, dec, period_s) } else { 0.0 };
        Setpoint::Position { pos: self.demand.pos + (v + next) / 2.0 * period_s, vel: next }
    }

    /// Runs the servo loops through one cycle, interpolating the set-point, and collects
    /// the edges the motor crosses.
    fn move_motor(&mut self, setpoint: Setpoint, energised: bool, period_s: f64) {
        let start = self.demand;
        let substeps = (period_s / SERVO_PERIOD_S).round().max(1.0) as usize;
        self.edges.clear();
        let mut edges = Edges::default();
        for k in 1..=substeps {
            let f = k as f64 / substeps as f64;
            let demand = match (energised, setpoint) {
                (false, _) => Demand::Off,
                (true, Setpoint::Hold) => {
                    Demand::Position { position: start.pos - self.shift, velocity: 0.0, acceleration: 0.0 }
                }
                (true, Setpoint::Position { pos, vel }) => Demand::Position {
                    position: start.pos + (pos - start.pos) * f - self.shift,
                    velocity: (pos - start.pos) / period_s,
                    acceleration: (vel - start.vel) / period_s,
                },
                (true, Setpoint::Velocity { vel }) => Demand::Velocity {
                    velocity: start.vel + (vel - start.vel) * f,
                    acceleration: (vel - start.vel) / period_s,
                },
                (true, Setpoint::Force(force)) => Demand::Force(force),
            };
            let before = self.plant.position;
            self.plant.step(demand);
            edges.clear();
            self.travel.edges(before, self.plant.position, &mut edges);
            self.edges.extend(&edges);
        }
        let actual = self.plant.position + self.shift;
        self.demand = match (energised, setpoint) {
            (true, Setpoint::Hold) => Kinematics { pos: start.pos, vel: 0.0, acc: 0.0 },
            (true, Setpoint::Position { pos, vel }) => Kinematics { pos, vel, acc: (vel - start.vel) / period_s },
            (true, Setpoint::Velocity { vel }) => Kinematics { pos: actual, vel, acc: 0.0 },
            // Not energised, or torque: the demand follows the motor, so nothing jumps later.
            _ => Kinematics { pos: actual, vel: 0.0, acc: 0.0 },
        };
    }

    /// The brake (bit 16) and O1..O5 (bits 17..21) of 0x60FE (tables 4-19 to 4-21).
    fn update_outputs(&mut self, state: State) {
        let commanded = self.od.get(od::PHYSICAL_OUTPUTS) as u32;
        let mask = self.od.get(od::OUTPUT_MASK) as u32;
        let mut outputs = 0;
        for k in 0..5 {
            let bit = 1 << (17 + k);
            if self.settings.general_purpose_outputs & (1 << k) != 0 && mask & bit != 0 {
                outputs |= commanded & bit;
            }
        }
        let brake = 1 << 16;
        // Energised, the brake must be released; otherwise the host may unlock it.
        if state.is_energised() || (mask & brake != 0 && commanded & brake != 0) {
            outputs |= brake;
        }
        self.outputs = outputs;
    }

    fn update_feedback(&mut self) {
        let raw = self.plant.position;
        let actual = (raw + self.shift).round() as i64;
        let state = self.fsa.state();
        self.od.set(od::POSITION_ACTUAL, actual);
        self.od.set(od::POSITION_ACTUAL_INTERNAL, actual);
        self.od.set(od::VELOCITY_ACTUAL, self.plant.velocity.round() as i64);
        self.od.set(od::TORQUE_ACTUAL, (self.plant.force * 1000.0).round() as i64);
        self.od.set_f32(od::MOTOR_ACTUAL_CURRENT, (self.plant.force.abs() * self.settings.rated_current_a) as f32);
        self.od.set(od::POSITION_DEMAND_INTERNAL, self.demand.pos.round() as i64);
        self.od.set(od::FOLLOWING_ERROR_ACTUAL, self.demand.pos.round() as i64 - actual);
        self.od.set(od::MODES_OF_OPERATION_DISPLAY, i8::from(self.mode.operation()).into());
        self.od.set(od::INDEX_SIGNAL, self.travel.index_active(raw) as i64);
        if let Some(at) = self.edges.iter().find_map(|e| match e {
            travel::Edge::Index { at } => Some(at),
            _ => None,
        }) {
            self.od.set(od::LATCHED_INDEX_POSITION, (at + self.shift).round() as i64);
        }
        let inputs = self.limits.negative as i64
            | (self.limits.positive as i64) << 1
            | (self.travel.home_switch_active(raw) as i64) << 2;
        self.od.set(od::DIGITAL_INPUTS, inputs);
        self.od.set(od::TOUCH_PROBE_STATUS, self.touch_probe.status() as i64);
        let (positive, negative) = self.touch_probe.edges(0);
        self.od.set(od::TOUCH_PROBE_1_POSITIVE, positive);
        self.od.set(od::TOUCH_PROBE_1_NEGATIVE, negative);
        if self.settings.touch_probe == TouchProbeKind::Cia402 {
            let (positive, negative) = self.touch_probe.edges(1);
            self.od.set(od::TOUCH_PROBE_2_POSITIVE, positive);
            self.od.set(od::TOUCH_PROBE_2_NEGATIVE, negative);
        }
        self.od.set(od::STATUSWORD, self.statusword(state) as i64);
    }

    /// Statusword 0x6041 (CoE manual tables 3-4, 3-5 and the mode tables).
    fn statusword(&self, state: State) -> u16 {
        let mut sw = state.statusword_bits() | statusword::REMOTE;
        if state.voltage_enabled() {
            sw |= statusword::VOLTAGE_ENABLED;
        }
        if self.internal_limit {
            sw |= statusword::INTERNAL_LIMIT_ACTIVE;
        }
        let input = self.input(self.od.get(od::CONTROLWORD) as u16, 0.0);
        let enabled = state == State::OperationEnabled;
        sw |= match &self.mode {
            ActiveMode::Homing(homing) => homing.status_bits(),
            ActiveMode::NoMode { shown } => *shown,
            _ if !enabled => 0,
            ActiveMode::ProfilePosition(pp) => pp.status_bits(&input),
            ActiveMode::ProfileVelocity(pv) => pv.status_bits(&input),
            ActiveMode::ProfileTorque(tq) => tq.status_bits(&input),
            ActiveMode::Cyclic(_) => statusword::OMS_12,
        };
        if self.following.active && self.mode.operation().following_error_applies() {
            sw |= statusword::OMS_13;
        }
        sw
    }
}

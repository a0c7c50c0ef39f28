//! One HMPL axis (ch. 5, 18, 20): its settings, power, profile generator, limits and
//! status, following the manual's pipeline (fig. 5.1.1): command -> profile generator ->
//! filter chain (HMPL 15.1) -> reference position + compensation -> position output +
//! offset -> counts to the drive. Which source gives the reference is the axis' one
//! `ReferenceSource` (`source.rs`), changed only through its transitions. Gear and
//! gantry couplings are the kernel's (`lib.rs`); the axis takes their results
//! through `follow` and `set_drive_position`. Limits live in `limits.rs`, what the axis
//! shows and its settle statistics in `status.rs`, homing in `homing.rs`, what it senses
//! of its drive in `sensed.rs`, its error state in `errors.rs`. Who commanded its motion,
//! and at what run speed, is the kernel's claim (`Kernel::claim`).

mod errors;
mod homing;
mod limits;
mod ranges;
mod sensed;
mod status;
mod vibration;

pub use homing::HomeState;
pub use vibration::VibrationFilter;

use api::AxisError;
use api::alarms::Alarm;

use crate::drive_link::{DriveLink, MODE_CSP, MODE_CST, MODE_CSV, Output};
use crate::filter::FilterChain;
use crate::generator::{Generator, Move};
use crate::power::PowerEvent;
use crate::pvt::{Pvt, PvtError, PvtPoint};
use crate::settings::{MAX_SMOOTH_TIME_MS, Settings, rate_from_time};
use crate::shaping::AXIS_MIN_SHAPER_HZ;
use crate::source::{Engagement, ReferenceSource};
use crate::touch_probe::TouchProbes;
use config::AxisConfig;
use devices::cia402::State;
use devices::ecat::Network;
use devices::profile::Kinematics;
use errors::ErrorState;
use sensed::Sensed;
use status::Settle;

/// Below this fraction of the axis' velocity limit the motor counts as standing.
const STANDSTILL: f64 = 1e-3;

/// One axis and its drive, stepped by the kernel in the stages of `Kernel::step`.
pub struct Axis {
    id: u8,
    link: DriveLink,
    settings: Settings,
    /// What gives the reference this cycle.
    source: ReferenceSource,
    generator: Generator,
    /// Between the generator and the reference: smoothing first.
    filters: FilterChain,
    period_s: f64,
    cycle: u64,
    /// The reference (the source's, after the filter chain), axis coordinates.
    reference: Kinematics,
    /// HMPL 5.3.19: `SetPos` moves the origin; drive position = axis position + offset.
    pos_offset: f64,
    /// HMPL 14.1: this cycle's compensation (`comp_pos_set`), added to the reference.
    compensation: f64,
    sensed: Sensed,
    /// csp or csv: how a position reference reaches the drive (cst is the torque source).
    cyclic_mode: i64,
    errors: ErrorState,
    home_state: HomeState,
    /// A Stop (not a Halt) is decelerating: other motion is refused (0x83II008C).
    stopping: bool,
    enabled_pending: bool,
    settle: Settle,
    /// HMPL ch. 13.
    touch_probes: TouchProbes,
}

impl Axis {
    pub(crate) fn new(id: u8, config: &AxisConfig, network: &Network, period_s: f64) -> Self {
        let settings = Settings::new(config);
        let max_samples = (MAX_SMOOTH_TIME_MS / 1000.0 / period_s).round() as usize + 1;
        let mut axis = Axis {
            id,
            link: DriveLink::new(id as usize, config, network),
            source: ReferenceSource::Profile,
            generator: Generator::new(period_s, settings.profile()),
            filters: FilterChain::for_axis(max_samples, AXIS_MIN_SHAPER_HZ, period_s),
            settings,
            period_s,
            cycle: 0,
            reference: Kinematics::default(),
            pos_offset: 0.0,
            compensation: 0.0,
            sensed: Sensed::default(),
            cyclic_mode: MODE_CSP,
            errors: ErrorState::default(),
            home_state: HomeState::default(),
            stopping: false,
            enabled_pending: false,
            settle: Settle::default(),
            touch_probes: TouchProbes::new(id as usize, config, network),
        };
        axis.rest_profile_at(0.0);
        axis
    }

    /// The axis id scripts use: its place in the machine file, from 0.
    pub fn id(&self) -> u8 {
        self.id
    }

    /// HMPL ch. 13: the axis' touch probes.
    pub fn touch_probes_mut(&mut self) -> &mut TouchProbes {
        &mut self.touch_probes
    }

    pub(crate) fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The power sequence reached Operation enabled: the axis takes motion commands.
    pub fn is_enabled(&self) -> bool {
        self.link.is_enabled()
    }

    /// The power sequence is at Disabled: not enabled, nor on its way in or out.
    pub fn is_disabled(&self) -> bool {
        self.link.is_disabled()
    }

    /// IsMoving (HMPL 5.4.2): a coupled axis while its reference moves, else while the
    /// profile generator plans or the filter chain has not settled.
    pub fn is_moving(&self) -> bool {
        if self.source.engagement().is_some() || self.source.is_group_synced() {
            self.reference.vel != 0.0
        } else {
            self.profile_moving()
        }
    }

    /// The profile generator plans, or the filter chain after it has not settled.
    fn profile_moving(&self) -> bool {
        self.generator.is_running() || !self.filters.settled()
    }

    /// The profile generator and its filter chain at rest at `pos`, nothing planned.
    fn rest_profile_at(&mut self, pos: f64) {
        self.generator.reset(pos);
        self.filters.reset(pos);
    }

    pub(crate) fn source(&self) -> &ReferenceSource {
        &self.source
    }

    /// IsErrorStop (HMPL 5.4.4): a fault or a limit stopped the axis, until Reset.
    pub fn is_error_stop(&self) -> bool {
        self.errors.is_error_stop()
    }

    /// IsGearSlave (HMPL 6.9): EnableGear linked it to a master, engaged or not.
    pub fn is_gear_slave(&self) -> bool {
        self.source.gear_master().is_some()
    }

    /// GetRefPos, GetRefVel, GetRefAcc (HMPL 5.3.27 to 5.3.29): the reference after the
    /// filter chain, before compensation, axis units.
    pub fn reference(&self) -> Kinematics {
        self.reference
    }

    /// GetPosFb (HMPL 5.3.20): the feedback position, axis units, after the axis' offset.
    pub fn pos_fb(&self) -> f64 {
        self.sensed.pos_fb
    }

    /// Simulation only: where the drive's flexible load is, axis coordinates (the motor's
    /// feedback plus the load's deflection); `None` for a rigid load.
    pub fn load_position(&self, network: &Network) -> Option<f64> {
        network.load_position(self.link.slave()).map(|counts| self.link.units(counts) - self.pos_offset)
    }

    /// HMPL 5.3.21: the feedback with the compensation it holds, as the drive reports it.
    pub fn pos_fb_comp(&self) -> f64 {
        self.sensed.pos_fb_comp()
    }

    /// The drive's position before the axis' offset (the gantry transform works on it).
    pub fn drive_position(&self) -> f64 {
        self.sensed.drive_position
    }

    /// Records a rejection or a fault as the axis' last error (HMPL 18.3) and returns it.
    pub fn fail(&mut self, error: AxisError) -> AxisError {
        self.errors.record(api::ErrorCode::axis(self.id, error).code());
        error
    }

    /// Records an alarm as the axis' last error (`Kernel::record_interruption`).
    pub(crate) fn record_alarm(&mut self, alarm: Alarm) {
        self.errors.record(alarm.0);
    }

    fn check<T>(&mut self, result: Result<T, AxisError>) -> Result<T, AxisError> {
        result.map_err(|e| self.fail(e))
    }

    /// ClearAxisLastErr (HMPL 18.4).
    pub fn clear_last_err(&mut self) {
        self.errors.record(0);
    }

    fn cycles(&self, ms: f64) -> u64 {
        cycles(ms, self.period_s)
    }

    // --- power (HMPL 5.2.1 to 5.2.3) ---

    /// Enable (HMPL 5.2.1): starts the power sequence; refused without the PDOs it needs
    /// or in ErrorStop. Clears an E-stop.
    pub fn enable(&mut self) -> Result<(), AxisError> {
        if !self.link.can_enable() {
            return Err(self.fail(AxisError::CmdInvalidNoSpecificPdo));
        }
        if self.errors.is_error_stop() {
            return Err(self.fail(AxisError::CmdInvalidErrorState));
        }
        self.errors.set_emergency_stopped(false);
        self.link.enable(self.cycle);
        Ok(())
    }

    /// HMPL 2.9, 9.1: the E-stop disables the axis and refuses motion until `Enable`.
    pub fn emergency_stop(&mut self) {
        let _ = self.disable();
        self.errors.set_emergency_stopped(true);
    }

    /// An E-stop disabled the axis and no Enable followed yet (HMPL 2.9).
    pub fn is_emergency_stopped(&self) -> bool {
        self.errors.is_emergency_stopped()
    }

    /// Whether the axis' own motion lasts (planned, halted, queued, settling, homing, an
    /// engaged gear, a torque) on an enabled axis out of error stop: while it does, the
    /// task that set it going owns it (`Kernel::axis_owner`, docs/decisions.md, "Axis
    /// ownership").
    pub fn motion_lasts(&self) -> bool {
        let lasts = self.generator.is_busy()
            || self.is_moving()
            || self.source.is_homing()
            || self.source.is_torque()
            || self.source.engagement().is_some();
        lasts && self.link.is_enabled() && !self.errors.is_error_stop()
    }

    /// DXMC A.3, 0x6B03: the commanding program's run speed (a factor, the kernel's
    /// claim) scales the velocity of its motion, on top of `SetVelScale` (HMPL 5.3.37),
    /// the move under way included.
    pub(crate) fn set_run_speed(&mut self, run_speed: f64) {
        self.generator.set_scale(self.settings.vel_scale / 100.0 * run_speed);
    }

    /// The drive's quick stop (CiA 402); the axis ends disabled.
    pub fn quick_stop(&mut self) {
        self.rest_profile_at(self.reference.pos);
        self.abort_homing();
        self.stopping = false;
        self.link.quick_stop(self.cycle);
    }

    /// Disables and clears the path planning (HMPL 5.2.2).
    pub fn disable(&mut self) -> Result<(), AxisError> {
        self.rest_profile_at(self.reference.pos);
        self.abort_homing();
        self.stopping = false;
        self.link.disable(self.cycle);
        Ok(())
    }

    /// Leaves ErrorStop (HMPL 5.2.3); a drive fault is reset too. The axis stays disabled.
    pub fn reset(&mut self) -> Result<(), AxisError> {
        if self.errors.is_error_stop() {
            if matches!(
                State::from_statusword(self.sensed.feedback.statusword),
                Some(State::Fault | State::FaultReactionActive)
            ) {
                self.link.reset_fault(self.cycle);
            }
            self.errors.reset();
        }
        Ok(())
    }

    // --- motion (HMPL 5.2) ---

    fn check_can_move(&mut self) -> Result<(), AxisError> {
        let refused = if self.errors.is_error_stop() {
            Some(AxisError::CmdInvalidErrorState)
        } else if !self.link.is_enabled() {
            Some(AxisError::CmdInvalidDisabled)
        } else if let Some(e) = self.source.refuses_motion() {
            Some(e)
        } else if self.stopping {
            Some(AxisError::CmdInvalidStopping)
        } else {
            None
        };
        match refused {
            Some(e) => Err(self.fail(e)),
            None => Ok(()),
        }
    }

    fn command(&mut self, m: Move) -> Result<(), AxisError> {
        let buffered = self.settings.buffer_mode == 1;
        self.generator.command(m, buffered).map_err(|_| self.fail(AxisError::CmdQueueFull))?;
        self.settle.start(self.cycle);
        Ok(())
    }

    /// MoveAbs (HMPL 5.2.4), axis units; with rollover the shortest way within a turn.
    pub fn move_abs(&mut self, pos: f64) -> Result<(), AxisError> {
        self.check_can_move()?;
        let target = if self.settings.rollover > 0.0 { self.shortest_way_to(pos) } else { pos };
        self.command(Move::Absolute(target))
    }

    /// Rollover (HMPL 5.3.39): an absolute target within a turn, reached the shortest way.
    fn shortest_way_to(&self, pos: f64) -> f64 {
        let r = self.settings.rollover;
        let from = self.generator.target().unwrap_or(self.reference.pos);
        let mut delta = pos.rem_euclid(r) - from.rem_euclid(r);
        if delta > r / 2.0 {
            delta -= r;
        } else if delta < -r / 2.0 {
            delta += r;
        }
        from + delta
    }

    /// Relative to the target under way, else to the reference, so that two quick
    /// `MoveRel(a, 10)` add up to 20.
    pub fn move_rel(&mut self, distance: f64) -> Result<(), AxisError> {
        self.check_can_move()?;
        self.command(Move::Relative(distance))
    }

    /// HMPL 5.2.6: a velocity move, sign for direction.
    pub fn move_vel(&mut self, vel: f64) -> Result<(), AxisError> {
        self.check_can_move()?;
        self.command(Move::Velocity(vel))
    }

    /// HMPL 5.2.8: PVT points (times in ms from 0), starting where the axis stands.
    pub fn move_pvt(&mut self, points: &[PvtPoint]) -> Result<(), AxisError> {
        self.check_can_move()?;
        let pvt = Pvt::new(points, self.settings.max_vel, self.settings.max_acc).map_err(|e| {
            self.fail(match e {
                PvtError::InvalidTime => AxisError::PvtMotionInvalidTime,
                PvtError::VelocityLimit => AxisError::PvtMotionVelLimit,
                PvtError::AccelerationLimit => AxisError::PvtMotionAccLimit,
                PvtError::Points => AxisError::CmdInvalidParameter,
            })
        })?;
        let start = self.generator.target().filter(|_| self.settings.buffer_mode == 1).unwrap_or(self.reference.pos);
        if (pvt.first().pos - start).abs() > self.settings.pos_window {
            return Err(self.fail(AxisError::CmdInvalidPos));
        }
        self.command(Move::Pvt(pvt))
    }

    /// HMPL 5.2.7: a constant torque (N·m), in cst (`SetOpMode(a, 10)`), with 0x6071 mapped;
    /// clamped to the rated (continuous) torque.
    pub fn move_trq(&mut self, torque: f64) -> Result<(), AxisError> {
        if self.errors.is_error_stop() {
            return Err(self.fail(AxisError::CmdInvalidErrorState));
        }
        if !self.link.is_enabled() {
            return Err(self.fail(AxisError::CmdInvalidDisabled));
        }
        if !self.source.is_torque() {
            return Err(self.fail(AxisError::CmdInvalidControlMode));
        }
        let per_mille = self.link.per_mille_per_nm;
        if !(per_mille.is_finite() && per_mille > 0.0) {
            return Err(self.fail(AxisError::CmdInvalidForceconstTrqmode));
        }
        let result = self.source.command_torque((torque * per_mille).clamp(-1000.0, 1000.0));
        self.check(result)
    }

    /// HMPL 5.2.9: decelerate and clear the path planning.
    pub fn stop(&mut self) -> Result<(), AxisError> {
        self.stop_with(self.settings.dec);
        Ok(())
    }

    /// StopAll, errors: stop with the kill deceleration (HMPL 2.8, 5.3.10). A homing run
    /// is ended: the drive leaves homing mode and holds.
    pub fn kill_stop(&mut self) {
        self.abort_homing();
        self.stop_with(self.settings.kill_dec);
    }

    fn stop_with(&mut self, dec: f64) {
        self.source.stop_torque();
        if self.profile_moving() {
            self.generator.stop_with(dec);
            self.stopping = true;
        }
    }

    /// Halt (HMPL 5.2.10): decelerates to rest keeping the target, for Resume.
    pub fn halt(&mut self) -> Result<(), AxisError> {
        if self.errors.is_error_stop() {
            return Err(self.fail(AxisError::CmdInvalidErrorState));
        }
        self.generator.halt();
        Ok(())
    }

    /// Resume (HMPL 5.2.11): on to the target a Halt kept.
    pub fn resume(&mut self) -> Result<(), AxisError> {
        if self.errors.is_error_stop() {
            return Err(self.fail(AxisError::CmdInvalidErrorState));
        }
        self.generator.resume();
        Ok(())
    }

    // --- settings (HMPL 5.3) ---

    // The ranges of the arguments are checked before (`ranges.rs`); the setters check
    // what depends on the axis' state.

    /// SetVel (HMPL 5.3.2), axis units/s; the move under way is re-planned.
    pub fn set_vel(&mut self, vel: f64) -> Result<(), AxisError> {
        self.settings.vel = vel;
        self.generator.set_profile(self.settings.profile());
        Ok(())
    }

    /// SetAcc (HMPL 5.3.4), axis units/s²; the move under way is re-planned.
    pub fn set_acc(&mut self, acc: f64) -> Result<(), AxisError> {
        self.settings.acc = acc;
        self.generator.set_profile(self.settings.profile());
        Ok(())
    }

    /// SetDec (HMPL 5.3.7), axis units/s²; the move under way is re-planned.
    pub fn set_dec(&mut self, dec: f64) -> Result<(), AxisError> {
        self.settings.dec = dec;
        self.generator.set_profile(self.settings.profile());
        Ok(())
    }

    /// HMPL 5.3.5: acceleration from a time: acc = vel / time.
    pub fn set_acc_time(&mut self, ms: f64) -> Result<(), AxisError> {
        let acc = self.check(rate_from_time(self.settings.vel, ms, self.settings.max_acc, AxisError::CmdInvalidAcc))?;
        self.set_acc(acc)
    }

    /// HMPL 5.3.8: deceleration from a time: dec = vel / time.
    pub fn set_dec_time(&mut self, ms: f64) -> Result<(), AxisError> {
        let dec = self.check(rate_from_time(self.settings.vel, ms, self.settings.max_acc, AxisError::CmdInvalidDec))?;
        self.set_dec(dec)
    }

    /// SetKillDec (HMPL 5.3.10): the deceleration of StopAll, limits and fault reactions.
    pub fn set_kill_dec(&mut self, kill_dec: f64) -> Result<(), AxisError> {
        self.settings.kill_dec = kill_dec;
        Ok(())
    }

    /// SetSWRL (HMPL 5.3.12): the right software limit, above the left one.
    pub fn set_swrl(&mut self, pos: f64) -> Result<(), AxisError> {
        if pos <= self.settings.swll {
            return Err(self.fail(AxisError::CmdInvalidPos));
        }
        self.settings.swrl = pos;
        Ok(())
    }

    /// SetSWLL (HMPL 5.3.14): the left software limit, below the right one.
    pub fn set_swll(&mut self, pos: f64) -> Result<(), AxisError> {
        if pos >= self.settings.swrl {
            return Err(self.fail(AxisError::CmdInvalidPos));
        }
        self.settings.swll = pos;
        Ok(())
    }

    /// HMPL 5.3.16: not while moving.
    pub fn set_sm_time(&mut self, ms: f64) -> Result<(), AxisError> {
        if self.is_moving() {
            return Err(self.fail(AxisError::CmdInvalidMoving));
        }
        self.settings.sm_time_ms = ms;
        self.filters.set_smoothing(self.smooth_samples(), self.generator.raw().pos);
        Ok(())
    }

    fn smooth_samples(&self) -> usize {
        (self.settings.sm_time_ms / 1000.0 / self.period_s).round().max(1.0) as usize
    }

    /// HMPL 5.3.19: the present position becomes `pos` by moving the origin (`pos_offset`).
    /// The kernel refuses it on a gantry axis first (`Kernel::set_pos`).
    pub(crate) fn set_pos(&mut self, pos: f64) -> Result<(), AxisError> {
        let refused = if self.is_gear_slave() {
            Some(AxisError::CmdInvalidInSync)
        } else if self.source.group().is_some() {
            Some(AxisError::CmdInvalidGrouped)
        } else if self.errors.is_error_stop() {
            Some(AxisError::CmdInvalidErrorState)
        } else if self.is_moving() {
            Some(AxisError::CmdInvalidMoving)
        } else {
            None
        };
        if let Some(e) = refused {
            return Err(self.fail(e));
        }
        let shift = self.reference.pos - pos;
        self.pos_offset += shift;
        self.sensed.pos_fb -= shift;
        self.reference.pos = pos;
        self.rest_profile_at(pos);
        Ok(())
    }

    /// IgnoreHWL, IgnoreSWL, IgnorePE (HMPL 5.3.33 to 5.3.35).
    pub fn set_ignore(&mut self, which: Ignore, on: bool) -> Result<(), AxisError> {
        match which {
            Ignore::HardwareLimits => self.settings.ignore_hwl = on,
            Ignore::SoftwareLimits => self.settings.ignore_swl = on,
            Ignore::PositionError => self.settings.ignore_pe = on,
        }
        Ok(())
    }

    /// HMPL 5.3.37: applied to the move under way, with the commanding program's run
    /// speed (`Kernel::set_vel_scale`).
    pub(crate) fn set_vel_scale(&mut self, percent: f64, run_speed: f64) {
        self.settings.vel_scale = percent;
        self.set_run_speed(run_speed);
    }

    /// HMPL 5.3.39: rollover length (0 switches it off), only while disabled.
    pub fn set_rollover(&mut self, value: f64) -> Result<(), AxisError> {
        if !self.link.is_disabled() {
            return Err(self.fail(AxisError::CmdInvalidEnabled));
        }
        self.settings.rollover = value;
        Ok(())
    }

    /// HMPL 5.3.41: 8 csp, 9 csv, 10 cst; the target of the mode must be mapped.
    pub fn set_op_mode(&mut self, mode: i64) -> Result<(), AxisError> {
        if !matches!(mode, MODE_CSP | MODE_CSV | MODE_CST) {
            return Err(self.fail(AxisError::CmdInvalidOpMode));
        }
        if self.is_moving() {
            return Err(self.fail(AxisError::CmdInvalidMoving));
        }
        let mapped = self.link.can_run(mode);
        self.check(mapped)?;
        let switched = self.source.set_torque_mode(mode == MODE_CST);
        self.check(switched)?;
        if mode != MODE_CST {
            self.cyclic_mode = mode;
        }
        self.link.set_mode(mode);
        Ok(())
    }

    /// HMPL 5.3.42: 0 immediate, 1 buffered; not while commands wait.
    pub fn set_buffer_mode(&mut self, mode: i64) -> Result<(), AxisError> {
        if !matches!(mode, 0 | 1) {
            return Err(self.fail(AxisError::CmdInvalidBufferMode));
        }
        if self.generator.cmd_num() > 0 {
            return Err(self.fail(AxisError::CmdInvalidSetbuffermode));
        }
        self.settings.buffer_mode = mode;
        Ok(())
    }

    /// SetPosWindow (HMPL 5.3.45): how near the target counts as in position, axis units.
    pub fn set_pos_window(&mut self, window: f64) -> Result<(), AxisError> {
        self.settings.pos_window = window;
        Ok(())
    }

    /// SetPosWindowTime (HMPL 5.3.47): how long the axis stays in the window before it is
    /// in position, ms.
    pub fn set_pos_window_time(&mut self, ms: f64) -> Result<(), AxisError> {
        self.settings.pos_window_time_ms = ms;
        Ok(())
    }

    // --- the cycle ---

    /// 1. Reads the drive and steps the power sequence.
    pub fn sense(&mut self, network: &mut Network, cycle: u64) {
        self.cycle = cycle;
        let (inputs, _) = network.images_mut();
        self.sensed.feedback = self.link.read(inputs);
        self.touch_probes.read(inputs);
        self.sensed.drive_position = self.sensed.feedback.position;
        let timeout = self.cycles(self.settings.enable_timeout_ms);
        let at_rest = self.sensed.vel_fb.abs() < STANDSTILL * self.settings.max_vel;
        // A statusword the bus did not bring this cycle says nothing: an enabled axis whose
        // drive is out of reach counts as disabled without a command (0x83II03FC).
        let statusword = network.inputs_valid().then_some(self.sensed.feedback.statusword);
        let event = self.link.sequence(statusword, cycle, timeout, at_rest);
        self.on_power_event(event, network);
    }

    /// The kernel's gantry transform replaces the drive position with a pair's.
    pub(crate) fn set_drive_position(&mut self, position: f64) {
        self.sensed.drive_position = position;
    }

    fn on_power_event(&mut self, event: PowerEvent, network: &mut Network) {
        match event {
            PowerEvent::None | PowerEvent::Disabled | PowerEvent::FaultCleared => {}
            PowerEvent::Enabled => self.enabled_pending = true,
            PowerEvent::Timeout => {
                let enabling = !State::from_statusword(self.sensed.feedback.statusword)
                    .is_some_and(|s| s == State::OperationEnabled);
                self.fail(if enabling { AxisError::DriveEnableTout } else { AxisError::DriveDisableTout });
            }
            PowerEvent::DriveFault => {
                let drive_err = match self.sensed.feedback.error_code {
                    Some(code) => code,
                    None => network.sdo_read(self.link.slave(), 0x603F, 0).map_or(0, |(v, _)| v as u16),
                };
                self.errors.drive_fault(drive_err);
                self.abort_homing();
                self.fail(AxisError::DriveFault);
            }
            PowerEvent::AbnormalDisable => {
                self.errors.enter_error_stop(0);
                self.fail(AxisError::DriveAbnormalDisable);
            }
        }
    }

    /// 2. The reference from the axis' source.
    ///
    /// The profile generator's through the filter chain, or the feedback (disabled,
    /// homing, torque); an engaged gear slave's comes from the kernel (`follow`).
    pub fn plan(&mut self) {
        self.sensed.locate(self.pos_offset, self.compensation, self.period_s);
        if std::mem::take(&mut self.enabled_pending) {
            self.rest_profile_at(self.sensed.pos_fb);
        }
        self.step_homing();
        match self.source {
            _ if !self.link.is_enabled() => self.follow_feedback(),
            ReferenceSource::Homing(_) | ReferenceSource::Torque { .. } => self.follow_feedback(),
            ReferenceSource::Gear { engaged: Some(_), .. } | ReferenceSource::Group { synced: true, .. } => {}
            // A disengaged gear slave, and an axis out of its group's sync, come to rest
            // through the generator.
            ReferenceSource::Profile
            | ReferenceSource::Gear { engaged: None, .. }
            | ReferenceSource::Group { synced: false, .. } => {
                self.guard_software_limits();
                self.reference = self.filters.push(self.generator.step());
            }
        }
        if self.stopping && !self.profile_moving() {
            self.stopping = false;
        }
        if self.filters.is_smoothing_suspended() && !self.profile_moving() {
            self.filters.resume_smoothing(self.smooth_samples(), self.generator.raw().pos);
        }
    }

    /// The reference stands where the motor is; the generator waits there.
    fn follow_feedback(&mut self) {
        let pos = self.sensed.pos_fb;
        self.rest_profile_at(pos);
        self.reference = Kinematics { pos, vel: 0.0, acc: 0.0 };
    }

    // --- gear (HMPL ch. 6): the kernel's gear commands move the source ---

    /// `EnableGear`: the kernel has checked the pair of axes.
    pub(crate) fn link_gear(&mut self, master: u8) -> Result<(), AxisError> {
        let result = self.source.link_gear(master);
        self.check(result)
    }

    /// `DisableGear`: the master it was linked to; an engaged slave comes to rest first.
    pub(crate) fn unlink_gear(&mut self) -> Result<u8, AxisError> {
        let result = self.source.unlink_gear();
        let (master, engaged) = self.check(result)?;
        if engaged.is_some() {
            self.come_to_rest(self.settings.dec);
        }
        Ok(master)
    }

    /// `GearIn`: the kernel has checked both axes are enabled.
    pub(crate) fn engage(&mut self, master: u8, engagement: Engagement) -> Result<(), AxisError> {
        let result = self.source.engage(master, engagement);
        self.check(result)
    }

    /// `GearOut`: the slave comes to rest from where the gear left it.
    pub(crate) fn gear_out(&mut self) -> Result<(), AxisError> {
        let result = self.source.disengage();
        self.check(result)?;
        self.come_to_rest(self.settings.dec);
        Ok(())
    }

    /// A gear slave's reference from its master's (HMPL 6.1). A slave the master would take
    /// past a limit (its software limits, or the ends of its drive's counts) is disengaged
    /// and stopped with its kill deceleration, as a move would be.
    pub(crate) fn follow(&mut self, master: Kinematics) {
        if let Some(e) = self.source.engagement() {
            let next = e.follow(master);
            if let Some((bit, error)) = self.passes_limit(next) {
                // Engaged, so the source takes it.
                let _ = self.source.disengage();
                self.come_to_rest(self.settings.kill_dec);
                self.errors.enter_error_stop(bit);
                self.fail(error);
                return;
            }
            self.reference = next;
        }
    }

    // --- groups (HMPL ch. 8): the kernel's group commands move the source ---

    /// `AddAxisToGrp`: the kernel has checked the group.
    pub(crate) fn join_group(&mut self, group: u8) -> Result<(), AxisError> {
        let result = self.source.join_group(group);
        self.check(result)
    }

    /// `RemoveAxisFromGrp`, `UngrpAllAxes`: the group is disabled, the axis at rest.
    pub(crate) fn leave_group(&mut self) {
        self.source.leave_group();
    }

    /// `EnableGroup`, `ResetGroup`: the group's interpolator takes the reference from where
    /// the axis stands.
    pub(crate) fn sync_group(&mut self) {
        self.source.set_group_sync(true);
    }

    /// `DisableGroup`, Group Error Stop: the generator takes over the motion the group left
    /// and brings it to rest with `dec` (HMPL table 8.1.1.4: "group leaves sync"). A group
    /// that stands (`group_at_rest`: its move over, or stopped at once) leaves the axis
    /// standing where it is, not braking from the last cycle's step.
    pub(crate) fn leave_group_sync(&mut self, dec: f64, group_at_rest: bool) {
        if self.source.is_group_synced() {
            self.source.set_group_sync(false);
            if group_at_rest {
                self.reference = Kinematics { pos: self.reference.pos, vel: 0.0, acc: 0.0 };
            }
            self.come_to_rest(dec);
        }
    }

    /// A synced group axis' reference from its group's interpolator. A reference that would
    /// pass a limit stops the axis with its kill deceleration in error stop, as a move would;
    /// the group sees it in its next cycle and leaves sync (HMPL table 8.1.1.4).
    pub(crate) fn follow_group(&mut self, next: Kinematics) {
        if !self.source.is_group_synced() || !self.link.is_enabled() {
            return;
        }
        if let Some((bit, error)) = self.passes_limit(next) {
            self.leave_group_sync(self.settings.kill_dec, false);
            self.errors.enter_error_stop(bit);
            self.fail(error);
            return;
        }
        self.reference = next;
    }

    /// The generator takes over the motion the gear left, unsmoothed until at rest.
    fn come_to_rest(&mut self, dec: f64) {
        self.generator.take_over(self.reference);
        self.filters.suspend_smoothing(self.reference.pos);
        self.generator.stop_with(dec);
    }

    /// HMPL 5.1.1, 14.1: position output = reference + compensation.
    pub fn pos_out(&self) -> f64 {
        self.reference.pos + self.compensation
    }

    /// HMPL 5.1.1: the position error, output minus the feedback as the drive reports it.
    pub fn pos_err(&self) -> f64 {
        self.pos_out() - self.pos_fb_comp()
    }

    /// HMPL 14.1: this cycle's compensation (`Kernel::compensate`).
    pub(crate) fn set_compensation(&mut self, value: f64) {
        self.compensation = value;
    }

    /// HMPL 14.1: the compensation passed its limit (0x83II0802): the axis' own motion
    /// stops with the kill deceleration in ErrorStop, as at a software limit
    /// (docs/decisions.md, "Compensation").
    pub(crate) fn compensation_limit(&mut self) {
        self.kill_stop();
        self.errors.enter_error_stop(0);
        self.fail(AxisError::CompLimit);
    }

    /// HMPL 14.3: without compensation the reference is where the (disabled) axis stands.
    pub(crate) fn end_compensation(&mut self) {
        self.compensation = 0.0;
        self.sensed.drop_compensation(self.pos_offset);
        self.follow_feedback();
    }

    /// The drive's position command before the gantry transform: output + offset.
    pub fn drive_command(&self) -> f64 {
        self.pos_out() + self.pos_offset
    }

    /// 4. Writes the drive: `position` is the drive command (after any gantry transform).
    pub fn actuate(&mut self, network: &mut Network, position: f64) {
        self.configure_homing(network);
        let velocity = if self.op_mode() == MODE_CSV { self.reference.vel } else { 0.0 };
        let torque = match self.source {
            ReferenceSource::Torque { per_mille } if self.link.is_enabled() => per_mille,
            _ => 0.0,
        };
        self.link.write(network, Output { position, velocity, torque });
        self.touch_probes.write(network.images_mut().1);
    }

    /// HMPL 5.3.41: the mode the axis runs in (8 csp, 9 csv, 10 cst).
    pub fn op_mode(&self) -> i64 {
        if self.source.is_torque() { MODE_CST } else { self.cyclic_mode }
    }
}

/// `ms` in whole cycles of `period_s`, rounded up.
fn cycles(ms: f64, period_s: f64) -> u64 {
    (ms / 1000.0 / period_s).ceil() as u64
}

/// The three notifications a user may switch off (HMPL 5.3.33 to 5.3.35).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ignore {
    /// IgnoreHWL (HMPL 5.3.33): the drive's limit switches.
    HardwareLimits,
    /// IgnoreSWL (HMPL 5.3.34): the software limits.
    SoftwareLimits,
    /// IgnorePE (HMPL 5.3.35): the position error limit (`HCV_ID_max_pos_err`).
    PositionError,
}

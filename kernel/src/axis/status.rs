//! What an axis shows (HMPL 5.1.1, 5.3.17/18, 5.4): in position, move and settling
//! times, and the snapshot with `motion_status` and `fault_status` (tables 5.1.1.4/5).

use schema::{AxisSnapshot, fault_status, motion_status};

use super::Axis;
use crate::touch_probe::TouchProbes;
use devices::cia402::State;

/// The settle statistics: how long the axis has stood in its position window (HMPL
/// 5.3.45-48), and the last move's move and settling times (HMPL 5.3.17/18).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Settle {
    /// Cycles in a row within the window, at rest and enabled.
    in_window_cycles: u64,
    /// The cycle the present motion began in.
    moving_since: Option<u64>,
    /// The cycle the last move ended in, until the axis is in position.
    settled_at: Option<u64>,
    move_time_ms: f64,
    settling_time_ms: f64,
}

impl Settle {
    /// A command set the axis going in `cycle`: its move time counts from the first.
    pub(super) fn start(&mut self, cycle: u64) {
        self.moving_since.get_or_insert(cycle);
    }

    /// One cycle: whether the axis moves, whether it stands in its window (at rest and
    /// enabled), and how many such cycles in a row are in position.
    fn track(&mut self, moving: bool, in_window: bool, cycle: u64, period_s: f64, window_cycles: u64) {
        self.in_window_cycles = if in_window { self.in_window_cycles + 1 } else { 0 };
        if moving {
            self.moving_since.get_or_insert(cycle);
            self.settled_at = None;
        } else if let Some(since) = self.moving_since.take() {
            self.move_time_ms = (cycle - since) as f64 * period_s * 1000.0;
            self.settled_at = Some(cycle);
        }
        if self.in_position(window_cycles)
            && let Some(stopped) = self.settled_at.take()
        {
            self.settling_time_ms = (cycle - stopped) as f64 * period_s * 1000.0;
        }
    }

    fn in_position(&self, window_cycles: u64) -> bool {
        self.in_window_cycles >= window_cycles
    }
}

impl Axis {
    /// In position: within the window, at rest, for the window time (HMPL 5.3.45-48).
    pub(super) fn track_in_position(&mut self) {
        let moving = self.is_moving();
        let in_window = self.pos_err().abs() <= self.settings.pos_window && !moving && self.link.is_enabled();
        let window_cycles = self.window_cycles();
        self.settle.track(moving, in_window, self.cycle, self.period_s, window_cycles);
    }

    pub(crate) fn is_in_position(&self) -> bool {
        self.in_position()
    }

    /// `fault_status` bits but ErrorStop (HMPL table 5.1.1.4).
    pub(crate) fn fault_status(&self) -> u32 {
        self.errors.faults()
    }

    pub(super) fn in_position(&self) -> bool {
        self.settle.in_position(self.window_cycles())
    }

    /// The position window time (HMPL 5.3.45-48) in whole cycles, at least one.
    fn window_cycles(&self) -> u64 {
        self.cycles(self.settings.pos_window_time_ms).max(1)
    }

    /// Bit p for touch probe p + 1.
    fn probe_bits(&self, f: impl Fn(&TouchProbes, usize) -> bool) -> u32 {
        (0..2).filter(|&p| f(&self.touch_probes, p)).fold(0, |bits, p| bits | 1 << p)
    }

    fn wrap(&self, pos: f64) -> f64 {
        if self.settings.rollover > 0.0 { pos.rem_euclid(self.settings.rollover) } else { pos }
    }

    /// The axis as the scope and the status functions see it (HMPL tables 5.1.1.1 to
    /// 5.1.1.6), but for its couplings, which the kernel adds (`Kernel::axis_snapshot`).
    pub(crate) fn snapshot(&self) -> AxisSnapshot {
        let mut motion = 0;
        if self.link.drive_enabled() {
            motion |= motion_status::ENABLED;
            if self.in_position() {
                motion |= motion_status::IN_POSITION;
            }
        }
        if self.is_moving() {
            motion |= motion_status::MOVING;
        }
        if self.reference.acc * self.reference.vel > 0.0 {
            motion |= motion_status::ACCELERATING;
        }
        if self.is_gear_slave() {
            motion |= motion_status::SYNCHRONOUS | motion_status::GEAR;
        }
        motion |= self.vibration_status();
        if self.home_state.is_homed() {
            motion |= motion_status::HOMED;
        }
        if self.source.is_homing() {
            motion |= motion_status::HOMING;
        }
        if self.sensed.feedback.digital_inputs.is_some_and(|i| i & 0b100 != 0) {
            motion |= motion_status::HOME_SWITCH;
        }
        let mut fault = self.errors.faults();
        if self.errors.is_error_stop() {
            fault |= fault_status::ERROR_STOP;
        }
        let feedback = &self.sensed.feedback;
        if matches!(State::from_statusword(feedback.statusword), Some(State::Fault | State::FaultReactionActive)) {
            fault |= fault_status::DRIVE_FAULT;
        }
        let s = &self.settings;
        let rollover_turns = if s.rollover > 0.0 { (self.sensed.pos_fb / s.rollover).floor() as i32 } else { 0 };
        AxisSnapshot {
            motion_status: motion,
            fault_status: fault,
            last_err: self.errors.last_err(),
            drive_err: self.errors.drive_err() as u32,
            coe_controlword: self.link.controlword(),
            coe_statusword: feedback.statusword,
            cmd_num: self.generator.cmd_num() as u32,
            buffer_mode: s.buffer_mode as u32,
            rollover_turns,
            gantry_pair_id: -1,
            group_id: -1,
            gear_master: 0,
            in_gear: self.source.engagement().is_some() as u32,
            op_mode: self.op_mode() as u32,
            ref_pos: self.wrap(self.reference.pos),
            ref_vel: self.reference.vel,
            ref_acc: self.reference.acc,
            pos_out: self.wrap(self.pos_out()),
            vel_out: self.reference.vel,
            acc_out: self.reference.acc,
            pos_offset: self.pos_offset,
            pos_fb: self.wrap(self.sensed.pos_fb),
            vel_fb: self.sensed.vel_fb,
            pos_err: self.pos_err(),
            vel_err: self.reference.vel - self.sensed.vel_fb,
            curr_fb: feedback.torque.map_or(0.0, |t| t / 1000.0 * self.link.rated_current_a),
            vel: s.vel,
            acc: s.acc,
            dec: s.dec,
            kill_dec: s.kill_dec,
            sm_time: s.sm_time_ms,
            swrl: s.swrl,
            swll: s.swll,
            move_time: self.settle.move_time_ms,
            settling_time: self.settle.settling_time_ms,
            vel_scale: s.vel_scale,
            pos_window: s.pos_window,
            pos_window_time: s.pos_window_time_ms,
            gear_ratio: self.source.engagement().map_or(0.0, |e| e.ratio),
            tp_enabled: self.probe_bits(|tp, p| tp.enabled(p)),
            tp_triggered: self.probe_bits(|tp, p| tp.triggered(p)),
            tp_mapped: self.probe_bits(|tp, p| tp.mapped(p)),
            // In the axis' coordinates, as the feedback (HMPL 13.10).
            tp_pos: [0, 1].map(|p| self.wrap(self.link.units(self.touch_probes.latched(p) as f64) - self.pos_offset)),
            comp_pos: self.compensation,
            pos_fb_comp: self.wrap(self.pos_fb_comp()),
            comp_active: 0,
        }
    }
}

//! Profile position mode (pp, 0x6060 = 1; CoE manual 3.3, tables 3-9 and 3-10).
//!
//! A set-point is taken on the rising edge of controlword bit 4: bit 5 "change set
//! immediately", bit 6 "relative" (to the previous target). HIWIN keeps two set-points,
//! one executing and one buffered (fig. 3-12): a third one is discarded unless bit 5 is
//! set, which drops both and runs the new one at once. Statusword bit 12 acknowledges a
//! set-point and stays high while the buffer is full; bit 10 is "target reached", or with
//! halt "velocity 0".

use crate::cia402::controlword::{CHANGE_SET_IMMEDIATELY, NEW_SET_POINT, RELATIVE};
use crate::cia402::statusword::{OMS_12, TARGET_REACHED};
use crate::drive::modes::{ModeInput, Setpoint, capped};
use crate::drive::od;
use crate::profile::{Limits, Trapezoid};

#[derive(Clone, Copy, Debug)]
struct Running {
    plan: Trapezoid,
    elapsed: f64,
}

#[derive(Clone, Debug, Default)]
pub struct ProfilePosition {
    /// The executing set-point's target and its plan (none once reached).
    executing: Option<f64>,
    running: Option<Running>,
    buffered: Option<f64>,
    /// Base of relative set-points: the last target accepted.
    last_target: Option<f64>,
    new_set_point_bit: bool,
    /// Bit 4 is still high after the edge that was accepted.
    acknowledged_edge: bool,
    halted: bool,
    /// Software limits, drive coordinates, when 0x2041 enables them.
    limits: Option<(f64, f64)>,
}

impl ProfilePosition {
    fn limits(input: &ModeInput) -> Limits {
        Limits {
            vel: capped(input.od, od::PROFILE_VELOCITY, od::MAX_PROFILE_VELOCITY),
            acc: capped(input.od, od::PROFILE_ACCELERATION, od::MAX_ACCELERATION),
            dec: capped(input.od, od::PROFILE_DECELERATION, od::MAX_DECELERATION),
        }
    }

    /// Clamps a target into the software limits (CoE manual 3: pp stops at the limit).
    pub fn set_software_limits(&mut self, limits: Option<(f64, f64)>) {
        self.limits = limits;
    }

    fn plan_to(&mut self, target: f64, input: &ModeInput) {
        let limits = Self::limits(input);
        self.executing = Some(target);
        self.running = (limits.vel > 0.0 && limits.acc > 0.0 && limits.dec > 0.0).then(|| Running {
            plan: Trapezoid::plan(input.demand.pos, input.demand.vel, target, limits),
            elapsed: 0.0,
        });
    }

    /// Drops the set-points (a limit stopped the motion, or the mode was left).
    pub fn abort(&mut self) {
        self.executing = None;
        self.running = None;
        self.buffered = None;
    }

    pub fn step(&mut self, input: &ModeInput) -> Setpoint {
        let cw = input.controlword;
        let bit4 = cw & NEW_SET_POINT != 0;
        if bit4 && !self.new_set_point_bit {
            self.accept(cw, input);
        }
        if !bit4 {
            self.acknowledged_edge = false;
        }
        self.new_set_point_bit = bit4;

        if input.halt() {
            if !self.halted {
                self.halted = true;
                let dec = Self::limits(input).dec;
                self.running = (dec > 0.0 && input.demand.vel != 0.0)
                    .then(|| Running { plan: Trapezoid::stop(input.demand.pos, input.demand.vel, dec), elapsed: 0.0 });
            }
        } else if self.halted {
            // Halt released: carry on to the executing target.
            self.halted = false;
            if let Some(target) = self.executing {
                self.plan_to(target, input);
            }
        }

        let Some(running) = &mut self.running else { return Setpoint::Hold };
        running.elapsed += input.period_s;
        let k = running.plan.at(running.elapsed);
        if running.elapsed >= running.plan.duration() {
            self.running = None;
            if !self.halted {
                self.executing = None;
                if let Some(next) = self.buffered.take() {
                    self.plan_to(next, input);
                }
            }
        }
        Setpoint::Position { pos: k.pos, vel: k.vel }
    }

    fn accept(&mut self, cw: u16, input: &ModeInput) {
        let value = input.od.get(od::TARGET_POSITION) as f64;
        let base = self.buffered.or(self.executing).or(self.last_target).unwrap_or(input.demand.pos);
        let mut target = if cw & RELATIVE != 0 { base + value } else { value };
        if let Some((low, high)) = self.limits {
            target = target.clamp(low, high);
        }
        if cw & CHANGE_SET_IMMEDIATELY != 0 {
            self.buffered = None;
            self.plan_to(target, input);
        } else if self.executing.is_none() {
            self.plan_to(target, input);
        } else if self.buffered.is_none() {
            self.buffered = Some(target);
        } else {
            // Buffer full: the set-point is discarded (fig. 3-12, 3 and 4).
            return;
        }
        self.last_target = Some(target);
        self.acknowledged_edge = true;
    }

    /// Statusword bits 10 and 12 (table 3-10); bit 13 comes from the following-error monitor.
    pub fn status_bits(&self, input: &ModeInput) -> u16 {
        let mut bits = 0;
        if self.buffered.is_some() || self.acknowledged_edge {
            bits |= OMS_12;
        }
        let reached = if self.halted {
            self.running.is_none() && input.demand.vel == 0.0
        } else {
            self.executing.is_none() && self.buffered.is_none()
        };
        if reached {
            bits |= TARGET_REACHED;
        }
        bits
    }
}

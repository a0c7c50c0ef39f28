//! Travel protection (CoE manual 3, "Limit functions by mode"; 0x60FD notes a and b):
//! hardware limits (0x2042, all modes), software limits (0x2041 with 0x607D, pp and csp),
//! and the following-error monitor (0x6065/0x6066, pp and csp; 3.3.2).

use crate::drive::modes::Setpoint;
use crate::drive::travel::{Edge, Edges, Travel};

/// The direction a set-point commands, from where the demand is: -1, 0 or 1.
pub fn direction(setpoint: &Setpoint, from: f64) -> f64 {
    let d = match *setpoint {
        Setpoint::Position { pos, .. } => pos - from,
        Setpoint::Velocity { vel } => vel,
        Setpoint::Force(f) => f,
        Setpoint::Hold => 0.0,
    };
    if d == 0.0 { 0.0 } else { d.signum() }
}

/// The latched limit flags of 0x60FD bits 0 and 1: set when the motor reaches a limit
/// switch with protection on, cleared once it moves the other way (note a) or homing mode
/// is left (note b).
#[derive(Clone, Copy, Debug, Default)]
pub struct HardwareLimits {
    pub negative: bool,
    pub positive: bool,
}

impl HardwareLimits {
    /// A drive that powers up on a limit switch has it latched.
    pub fn at_power_up(travel: &Travel, raw: f64) -> Self {
        HardwareLimits { negative: travel.negative_limit_active(raw), positive: travel.positive_limit_active(raw) }
    }

    /// Updates the latches from this cycle's edges and the direction of the commanded
    /// motion (the set-point's, not the settling motor's). Returns true when a limit was
    /// newly reached (the motion must stop).
    pub fn update(&mut self, edges: &Edges, commanded: f64) -> bool {
        let mut reached = false;
        for edge in edges.iter() {
            match edge {
                Edge::NegativeLimit { rising: true, .. } if !self.negative => {
                    self.negative = true;
                    reached = true;
                }
                Edge::PositiveLimit { rising: true, .. } if !self.positive => {
                    self.positive = true;
                    reached = true;
                }
                _ => {}
            }
        }
        if reached {
            return true;
        }
        if self.negative && commanded > 0.0 {
            self.negative = false;
        }
        if self.positive && commanded < 0.0 {
            self.positive = false;
        }
        false
    }

    pub fn clear(&mut self) {
        *self = HardwareLimits::default();
    }

    /// Holds any set-point that would move toward a latched limit; only the opposite
    /// direction is accepted. Returns whether it held one.
    pub fn guard(&self, setpoint: &mut Setpoint, from: f64) -> bool {
        let d = direction(setpoint, from);
        let held = (self.positive && d > 0.0) || (self.negative && d < 0.0);
        if held {
            *setpoint = Setpoint::Hold;
        }
        held
    }
}

/// Software limits: a position set-point is clamped to [min, max]. Returns whether it was.
pub fn clamp_to_software_limits(setpoint: &mut Setpoint, limits: (f64, f64)) -> bool {
    if let Setpoint::Position { pos, vel } = setpoint {
        let clamped = pos.clamp(limits.0, limits.1);
        if clamped != *pos {
            *pos = clamped;
            *vel = 0.0;
            return true;
        }
    }
    false
}

/// |demand - actual| > window for longer than the timeout: statusword bit 13, then Fault
/// with 0x8611. A window of 0 (the default) switches the monitor off (docs/drive.md).
#[derive(Clone, Copy, Debug, Default)]
pub struct FollowingError {
    /// Time outside the window, in µs (integer, so that 10 cycles of 1 ms are exactly 10 ms).
    outside_us: u64,
    pub active: bool,
}

impl FollowingError {
    /// One cycle. Returns true when the error has lasted past the timeout.
    pub fn check(&mut self, error: f64, window: u32, timeout_ms: u16, period_s: f64) -> bool {
        if window == 0 || error.abs() <= window as f64 {
            *self = FollowingError::default();
            return false;
        }
        self.outside_us += (period_s * 1e6).round() as u64;
        self.active = self.outside_us > timeout_ms as u64 * 1000;
        self.active
    }

    pub fn reset(&mut self) {
        *self = FollowingError::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CoE manual 3.3.2: a persistent error over the window for longer than the timeout
    /// trips; a shorter one does not (CoE 3.3.2).
    #[test]
    fn following_error_needs_the_whole_timeout() {
        let mut fe = FollowingError::default();
        for _ in 0..10 {
            assert!(!fe.check(150.0, 100, 10, 0.001), "10 ms is not longer than 10 ms");
        }
        assert!(fe.check(150.0, 100, 10, 0.001));
        fe.reset();
        for _ in 0..9 {
            fe.check(150.0, 100, 10, 0.001);
        }
        assert!(!fe.check(50.0, 100, 10, 0.001), "back inside the window restarts the count");
        assert!(!fe.check(1e9, 0, 0, 0.001), "window 0: off");
    }

    #[test]
    fn a_latched_limit_only_lets_the_motor_back() {
        let limits = HardwareLimits { negative: false, positive: true };
        let mut toward = Setpoint::Position { pos: 10.0, vel: 5.0 };
        assert!(limits.guard(&mut toward, 0.0));
        assert_eq!(toward, Setpoint::Hold);
        let mut away = Setpoint::Velocity { vel: -5.0 };
        assert!(!limits.guard(&mut away, 0.0));
    }
}

//! Profile velocity mode (pv, 0x6060 = 3; CoE manual 3.4, tables 3-11 and 3-12).
//!
//! The demand ramps to the target velocity 0x60FF with the profile acceleration 0x6083
//! (deceleration 0x6084 when slowing down); halt ramps it to 0. Statusword bit 10 is
//! "target velocity reached" (with halt: "velocity 0"); bit 12 is "speed = 0", as table
//! 3-12 and CiA 402 have it (the manual's text says the opposite; docs/drive.md).

use crate::cia402::statusword::{OMS_12, TARGET_REACHED};
use crate::drive::modes::{ModeInput, Setpoint, capped};
use crate::drive::od;
use crate::profile::ramp_velocity;

/// Below this actual speed (counts/s) the motor counts as standing.
pub const ZERO_SPEED: f64 = 100.0;

#[derive(Clone, Debug, Default)]
pub struct ProfileVelocity {
    velocity: f64,
    target: f64,
}

impl ProfileVelocity {
    /// Starts from the motor's present demand velocity, so a mode change does not jump.
    pub fn starting_at(velocity: f64) -> Self {
        ProfileVelocity { velocity, target: velocity }
    }

    pub fn step(&mut self, input: &ModeInput) -> Setpoint {
        self.target = if input.halt() { 0.0 } else { input.od.get(od::TARGET_VELOCITY) as f64 };
        let acc = capped(input.od, od::PROFILE_ACCELERATION, od::MAX_ACCELERATION);
        let dec = capped(input.od, od::PROFILE_DECELERATION, od::MAX_DECELERATION);
        self.velocity = ramp_velocity(self.velocity, self.target, acc, dec, input.period_s);
        Setpoint::Velocity { vel: self.velocity }
    }

    /// Stops at once (a limit switch): the velocity demand drops to 0.
    pub fn stop(&mut self) {
        self.velocity = 0.0;
    }

    pub fn status_bits(&self, input: &ModeInput) -> u16 {
        let mut bits = 0;
        if self.velocity == self.target {
            bits |= TARGET_REACHED;
        }
        if input.actual_velocity.abs() < ZERO_SPEED {
            bits |= OMS_12;
        }
        bits
    }
}

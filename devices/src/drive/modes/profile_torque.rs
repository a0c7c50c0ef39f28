//! Profile torque mode (tq, 0x6060 = 4; CoE manual 3.5, table 3-13).
//!
//! The current command ramps toward the target torque 0x6071 (0.1 % of rated) by the
//! torque slope 0x6087 (0.1 % per second; 0 is a step); halt ramps it to 0. Output force
//! = force constant x rated current x 0x6071 / 1000. Statusword bit 10: the command has
//! reached the target (with halt: velocity 0).

use crate::cia402::statusword::TARGET_REACHED;
use crate::drive::modes::profile_velocity::ZERO_SPEED;
use crate::drive::modes::{ModeInput, Setpoint};
use crate::drive::od;
use crate::profile::ramp_velocity;

#[derive(Clone, Debug, Default)]
pub struct ProfileTorque {
    /// Torque command, 0.1 % of rated.
    command: f64,
    target: f64,
}

impl ProfileTorque {
    pub fn step(&mut self, input: &ModeInput) -> Setpoint {
        self.target = if input.halt() { 0.0 } else { input.od.get(od::TARGET_TORQUE) as f64 };
        let slope = input.od.get(od::TORQUE_SLOPE) as f64;
        self.command = ramp_velocity(self.command, self.target, slope, slope, input.period_s);
        Setpoint::Force(self.command / 1000.0)
    }

    pub fn stop(&mut self) {
        self.command = 0.0;
    }

    pub fn status_bits(&self, input: &ModeInput) -> u16 {
        let reached = if input.halt() { input.actual_velocity.abs() < ZERO_SPEED } else { self.command == self.target };
        if reached { TARGET_REACHED } else { 0 }
    }
}

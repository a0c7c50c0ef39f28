//! The motor and load behind a drive, and the drive's servo loops that move them.
//!
//! The drive runs a position loop (P, with velocity and acceleration feed-forward) and a
//! velocity loop (PI) at 16 kHz, tuned for the nominal inertia. The load's real inertia
//! may differ (`inertia_ratio`), Coulomb friction opposes motion, the force is limited to
//! the peak force, and hard stops end the travel. So following error, overshoot, settling
//! and the torque feedback look like those of a real servo. Everything is in encoder counts.

use crate::config::PlantConfig;

/// The servo loops' rate.
pub const SERVO_PERIOD_S: f64 = 62.5e-6;

/// What the drive asks of the loops during one servo period.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Demand {
    /// Motor not energised: no force, the load coasts against friction.
    Off,
    /// Follow a position, with velocity and acceleration feed-forward.
    Position { position: f64, velocity: f64, acceleration: f64 },
    /// Follow a velocity (velocity loop only).
    Velocity { velocity: f64, acceleration: f64 },
    /// Produce a force, as a fraction of rated force (current loop only).
    Force(f64),
}

#[derive(Clone, Debug)]
pub struct Plant {
    /// Position, counts (the encoder reads it rounded).
    pub position: f64,
    /// Velocity, counts/s.
    pub velocity: f64,
    /// Force, as a fraction of rated force (1.0 = rated).
    pub force: f64,
    /// Acceleration the tuned load gets at rated force, counts/s².
    rated_acc: f64,
    inertia_ratio: f64,
    friction: f64,
    peak: f64,
    kp: f64,
    kv: f64,
    ki: f64,
    integral: f64,
    hard_stops: (f64, f64),
}

impl Plant {
    pub fn new(config: &PlantConfig, counts_per_unit: f64, start: f64, hard_stops: (Option<f64>, Option<f64>)) -> Self {
        let omega = 2.0 * std::f64::consts::PI * config.bandwidth_hz;
        Plant {
            position: start,
            velocity: 0.0,
            force: 0.0,
            rated_acc: config.rated_acc * counts_per_unit,
            inertia_ratio: config.inertia_ratio,
            friction: config.friction,
            peak: config.peak_ratio,
            kp: omega / 4.0,
            kv: omega,
            ki: omega * omega / 8.0,
            integral: 0.0,
            hard_stops: (hard_stops.0.unwrap_or(f64::NEG_INFINITY), hard_stops.1.unwrap_or(f64::INFINITY)),
        }
    }

    /// Peak force, as a fraction of rated force.
    pub fn peak(&self) -> f64 {
        self.peak
    }

    /// Advances the motor by one servo period.
    pub fn step(&mut self, demand: Demand) {
        let dt = SERVO_PERIOD_S;
        let velocity_loop = |this: &mut Plant, velocity_ref: f64, acceleration: f64| {
            let error = velocity_ref - this.velocity;
            let force = (this.kv * error + this.integral + acceleration) / this.rated_acc;
            if force.abs() < this.peak {
                // Anti-windup: integrate only while the force is not saturated.
                this.integral += this.ki * error * dt;
            }
            force
        };
        let commanded = match demand {
            Demand::Off => {
                self.integral = 0.0;
                0.0
            }
            Demand::Position { position, velocity, acceleration } => {
                let velocity_ref = velocity + self.kp * (position - self.position);
                velocity_loop(self, velocity_ref, acceleration)
            }
            Demand::Velocity { velocity, acceleration } => velocity_loop(self, velocity, acceleration),
            Demand::Force(force) => {
                self.integral = 0.0;
                force
            }
        }
        .clamp(-self.peak, self.peak);
        self.force = commanded;
        let accel = self.rated_acc / self.inertia_ratio;
        let moving = self.velocity.abs() > 1e-9;
        let net = if moving {
            commanded - self.friction * self.velocity.signum()
        } else if commanded.abs() > self.friction {
            commanded - self.friction * commanded.signum()
        } else {
            0.0
        };
        let new_velocity = self.velocity + net * accel * dt;
        // Friction stops a coasting load; it does not reverse it.
        self.velocity = if moving && demand == Demand::Off && new_velocity.signum() != self.velocity.signum() {
            0.0
        } else {
            new_velocity
        };
        self.position += self.velocity * dt;
        let (low, high) = self.hard_stops;
        if self.position <= low || self.position >= high {
            // A hard stop: the load stops dead against it.
            self.position = self.position.clamp(low, high);
            self.velocity = 0.0;
        }
    }

    /// Position the encoder reports.
    pub fn encoder(&self) -> i64 {
        self.position.round() as i64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plant() -> Plant {
        Plant::new(&PlantConfig::default(), 10_000.0, 0.0, (None, Some(5_000.0)))
    }

    #[test]
    fn follows_a_step_and_settles_without_error() {
        let mut p = plant();
        let demand = Demand::Position { position: 1000.0, velocity: 0.0, acceleration: 0.0 };
        for _ in 0..(0.2 / SERVO_PERIOD_S) as usize {
            p.step(demand);
        }
        assert!((p.position - 1000.0).abs() < 1.0, "settled at {}", p.position);
        assert!(p.velocity.abs() < 10.0);
    }

    #[test]
    fn a_de_energised_motor_coasts_to_rest_against_friction() {
        let mut p = plant();
        p.velocity = -50_000.0;
        for _ in 0..(1.0 / SERVO_PERIOD_S) as usize {
            p.step(Demand::Off);
        }
        assert_eq!(p.velocity, 0.0);
        assert!(p.position < 0.0);
    }

    #[test]
    fn a_hard_stop_stops_the_load_and_the_force_saturates() {
        let mut p = plant();
        for _ in 0..(0.5 / SERVO_PERIOD_S) as usize {
            p.step(Demand::Velocity { velocity: 100_000.0, acceleration: 0.0 });
        }
        assert_eq!(p.position, 5_000.0);
        assert_eq!(p.force, p.peak(), "pushing against the stop at peak force");
    }
}

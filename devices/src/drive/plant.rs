//! The motor and load behind a drive, and the drive's servo loops that move them.
//!
//! The drive runs a position loop (P, with velocity and acceleration feed-forward) and a
//! velocity loop (PI) at 16 kHz, tuned for the nominal inertia. The load's real inertia
//! may differ (`inertia_ratio`), Coulomb friction opposes motion, the force is limited to
//! the peak force, and hard stops end the travel. So following error, overshoot, settling
//! and the torque feedback look like those of a real servo. Everything is in encoder counts.
//!
//! A flexible load (`load_frequency_hz` > 0) is a second mass m2 = `load_mass_ratio` · m1
//! coupled to the motor by a spring and a damper: with q = x2 - x1 the deflection, the load
//! accelerates by -(ω²·q + 2ζω·q') and the motor by its force plus m2/m1 · (ω²·q + 2ζω·q'),
//! ω and ζ the load's natural frequency and damping ratio with the motor held. The
//! loops know only the motor: the load rings after a move, as a cantilever does (HMPL 15.1).

use config::PlantConfig;

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
    load: Option<FlexibleLoad>,
}

/// The second mass of a flexible load, relative to the motor.
#[derive(Clone, Debug)]
struct FlexibleLoad {
    omega: f64,
    zeta: f64,
    mass_ratio: f64,
    /// q = load position - motor position, counts, and its rate, counts/s.
    deflection: f64,
    deflection_rate: f64,
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
            load: (config.load_frequency_hz > 0.0).then_some(FlexibleLoad {
                omega: 2.0 * std::f64::consts::PI * config.load_frequency_hz,
                zeta: config.load_damping,
                mass_ratio: config.load_mass_ratio,
                deflection: 0.0,
                deflection_rate: 0.0,
            }),
        }
    }

    /// Where the flexible load is, counts; `None` for a rigid load.
    pub fn load_position(&self) -> Option<f64> {
        self.load.as_ref().map(|l| self.position + l.deflection)
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
        // The spring and damper pull the motor towards the load (as a force in the units of
        // `commanded`) and the load towards the motor.
        let spring_acc =
            self.load.as_ref().map_or(0.0, |l| l.omega * (l.omega * l.deflection + 2.0 * l.zeta * l.deflection_rate));
        let applied = commanded + self.load.as_ref().map_or(0.0, |l| l.mass_ratio * spring_acc / accel);
        let moving = self.velocity.abs() > 1e-9;
        let net = if moving {
            applied - self.friction * self.velocity.signum()
        } else if applied.abs() > self.friction {
            applied - self.friction * applied.signum()
        } else {
            0.0
        };
        let new_velocity = self.velocity + net * accel * dt;
        // Friction stops a coasting load; it does not reverse it.
        let velocity = if moving && demand == Demand::Off && new_velocity.signum() != self.velocity.signum() {
            0.0
        } else {
            new_velocity
        };
        let motor_acc = (velocity - self.velocity) / dt;
        self.velocity = velocity;
        self.position += self.velocity * dt;
        let (low, high) = self.hard_stops;
        if self.position <= low || self.position >= high {
            // A hard stop: the motor stops dead against it (the load swings on).
            self.position = self.position.clamp(low, high);
            self.velocity = 0.0;
        }
        if let Some(l) = &mut self.load {
            // Semi-implicit Euler, as the motor: the rate first, then the deflection.
            l.deflection_rate += (-spring_acc - motor_acc) * dt;
            l.deflection += l.deflection_rate * dt;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plant() -> Plant {
        Plant::new(&PlantConfig::default(), 10_000.0, 0.0, (None, Some(5_000.0)))
    }

    /// Zero crossings of the load's deflection over `seconds` while the loops hold the motor.
    fn ring(p: &mut Plant, seconds: f64) -> (Vec<f64>, f64) {
        let hold = Demand::Position { position: 0.0, velocity: 0.0, acceleration: 0.0 };
        let (mut crossings, mut peak, mut last) = (Vec::new(), 0.0f64, p.load_position().unwrap() - p.position);
        for i in 0..(seconds / SERVO_PERIOD_S) as usize {
            p.step(hold);
            let q = p.load_position().unwrap() - p.position;
            if q.signum() != last.signum() {
                crossings.push(i as f64 * SERVO_PERIOD_S);
            }
            peak = peak.max(q.abs());
            last = q;
        }
        (crossings, peak)
    }

    #[test]
    fn a_rigid_load_has_no_position_of_its_own() {
        assert_eq!(plant().load_position(), None);
    }

    /// A light load on a spring, released from a deflection while the loops hold the motor,
    /// rings at its natural frequency (half a period between zero crossings) and decays.
    #[test]
    fn a_flexible_load_rings_at_its_frequency() {
        let config = PlantConfig {
            load_frequency_hz: 12.0,
            load_damping: 0.01,
            load_mass_ratio: 0.01,
            ..PlantConfig::default()
        };
        let mut p = Plant::new(&config, 10_000.0, 0.0, (None, None));
        p.load.as_mut().unwrap().deflection = 100.0;
        let (crossings, _) = ring(&mut p, 1.0);
        let half_periods = (crossings[crossings.len() - 1] - crossings[1]) / (crossings.len() - 2) as f64;
        let f = 1.0 / (2.0 * half_periods);
        assert!((f - 12.0).abs() < 0.12, "rings at {f} Hz");
        // After 1 s the envelope is exp(-ζω · 1 s) = 0.47 of the release.
        let (_, peak) = ring(&mut p, 0.5);
        let envelope = 100.0 * (-0.01 * 2.0 * std::f64::consts::PI * 12.0).exp();
        assert!(
            peak < 1.05 * envelope && peak > 0.9 * envelope * (-0.01 * std::f64::consts::PI * 12.0).exp(),
            "decays: {peak}"
        );
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
        assert_eq!(p.force, p.peak, "pushing against the stop at peak force");
    }
}

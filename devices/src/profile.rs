//! A time-optimal trapezoidal velocity profile from any position and velocity to a target
//! at rest, under a velocity limit and separate acceleration and deceleration limits: the
//! T-curve of HMPL 5.1 (fig. 5.1.2) for the kernel's axes, and the planner of the drives'
//! profile modes (CoE manual 3.3).
//!
//! The plan is a list of constant-acceleration segments, sampled analytically, so that a
//! sampled profile never exceeds its limits and ends exactly on its target.

/// Profile limits, all > 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Highest velocity, units/s.
    pub vel: f64,
    /// Highest acceleration, units/s².
    pub acc: f64,
    /// Highest deceleration, units/s² (positive).
    pub dec: f64,
}

/// A sample of a profile.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Kinematics {
    /// Position, in the profile's unit (counts in a drive, the axis' unit in the kernel).
    pub pos: f64,
    /// Velocity, units/s.
    pub vel: f64,
    /// Acceleration, units/s² (negative when braking forward).
    pub acc: f64,
}

#[derive(Clone, Copy, Debug, Default)]
struct Segment {
    start: f64,
    pos: f64,
    vel: f64,
    acc: f64,
    duration: f64,
}

impl Segment {
    fn at(&self, t: f64) -> Kinematics {
        let dt = t - self.start;
        Kinematics {
            pos: self.pos + self.vel * dt + 0.5 * self.acc * dt * dt,
            vel: self.vel + self.acc * dt,
            acc: self.acc,
        }
    }

    fn end(&self) -> f64 {
        self.start + self.duration
    }
}

/// At most: brake to rest, decelerate to the limit, accelerate, cruise, decelerate.
const MAX_SEGMENTS: usize = 5;

/// A planned move. Fixed size, so that planning in the RT cycle does not allocate.
#[derive(Clone, Copy, Debug)]
pub struct Trapezoid {
    segments: [Segment; MAX_SEGMENTS],
    count: usize,
    target: f64,
}

impl Trapezoid {
    /// Plans from `(pos, vel)` to `target` at rest.
    pub fn plan(pos: f64, vel: f64, target: f64, limits: Limits) -> Self {
        let mut plan = Trapezoid { segments: [Segment::default(); MAX_SEGMENTS], count: 0, target };
        let (mut p, mut v) = (pos, vel);
        let Limits { vel: vmax, acc, dec } = limits;

        // Moving away from the target, or too fast to stop before it: brake to rest first.
        let toward = (target - p).signum();
        let stop_distance = v * v / (2.0 * dec);
        if v != 0.0 && (v.signum() != toward || stop_distance > (target - p).abs()) {
            let duration = v.abs() / dec;
            plan.push(p, v, -v.signum() * dec, duration);
            p += v * duration / 2.0;
            v = 0.0;
        }

        let distance = (target - p).abs();
        let s = (target - p).signum();
        let mut u = v.abs();
        if distance == 0.0 && u == 0.0 {
            return plan;
        }
        // Faster than the limit (it was lowered): come down to it with the deceleration.
        let mut covered = 0.0;
        if u > vmax {
            let duration = (u - vmax) / dec;
            plan.push(p, s * u, -s * dec, duration);
            covered += (u + vmax) / 2.0 * duration;
            u = vmax;
        }
        let remaining = (distance - covered).max(0.0);
        let peak = ((2.0 * acc * dec * remaining + dec * u * u) / (acc + dec)).sqrt().min(vmax).max(u);
        let accel_time = (peak - u) / acc;
        let accel_distance = (peak * peak - u * u) / (2.0 * acc);
        let decel_time = peak / dec;
        let decel_distance = peak * peak / (2.0 * dec);
        let cruise_time = ((remaining - accel_distance - decel_distance) / peak).max(0.0);
        let p_accel = p + s * covered;
        plan.push(p_accel, s * u, s * acc, accel_time);
        plan.push(p_accel + s * accel_distance, s * peak, 0.0, cruise_time);
        // The last segment is anchored on the target so that the move ends exactly there.
        let decel_start = target - s * decel_distance;
        plan.push(decel_start, s * peak, -s * dec, decel_time);
        plan
    }

    /// Decelerates to rest from `(pos, vel)` with `dec`, where the stop naturally falls.
    pub fn stop(pos: f64, vel: f64, dec: f64) -> Self {
        let target = pos + vel * vel.abs() / (2.0 * dec);
        Trapezoid::plan(pos, vel, target, Limits { vel: vel.abs().max(f64::MIN_POSITIVE), acc: dec, dec })
    }

    fn push(&mut self, pos: f64, vel: f64, acc: f64, duration: f64) {
        if duration <= 0.0 {
            return;
        }
        let start = self.duration();
        self.segments[self.count] = Segment { start, pos, vel, acc, duration };
        self.count += 1;
    }

    /// Total duration, s.
    pub fn duration(&self) -> f64 {
        self.count.checked_sub(1).map_or(0.0, |i| self.segments[i].end())
    }

    /// Where the move ends, at rest.
    pub fn target(&self) -> f64 {
        self.target
    }

    /// The profile at time `t` (s) since the plan started; at rest on the target after it ends.
    pub fn at(&self, t: f64) -> Kinematics {
        if t >= self.duration() {
            return Kinematics { pos: self.target, vel: 0.0, acc: 0.0 };
        }
        let segment = self.segments[..self.count].iter().find(|s| t < s.end()).expect("t is within the plan");
        segment.at(t)
    }
}

/// One step of a velocity ramp toward `target`: `acc` while speeding up, `dec` while
/// slowing down (and through zero). A rate of 0 means a step.
pub fn ramp_velocity(v: f64, target: f64, acc: f64, dec: f64, dt: f64) -> f64 {
    let speeding_up = target.abs() > v.abs() && (v == 0.0 || v.signum() == target.signum());
    let rate = if speeding_up { acc } else { dec };
    if rate <= 0.0 {
        return target;
    }
    let dv = rate * dt;
    if (target - v).abs() <= dv { target } else { v + dv * (target - v).signum() }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: Limits = Limits { vel: 100.0, acc: 1000.0, dec: 500.0 };

    fn check(pos: f64, vel: f64, target: f64, limits: Limits) -> Trapezoid {
        let plan = Trapezoid::plan(pos, vel, target, limits);
        let dt = 1e-3;
        let steps = (plan.duration() / dt).ceil() as usize + 2;
        let mut previous = plan.at(0.0);
        assert_eq!((previous.pos, previous.vel), (pos, vel), "starts where it was planned from");
        // The trapezoid rule is exact within a segment; across a change of acceleration
        // it is off by at most |da| dt² / 8.
        let tolerance = (limits.acc + limits.dec) * dt * dt / 8.0 + 1e-9;
        for k in 1..=steps {
            let now = plan.at(k as f64 * dt);
            assert!(now.vel.abs() <= limits.vel.max(vel.abs()) * (1.0 + 1e-9), "vel {now:?} at step {k}");
            assert!(now.acc.abs() <= limits.acc.max(limits.dec) * (1.0 + 1e-9), "acc {now:?}");
            let mean = (previous.vel + now.vel) / 2.0;
            assert!((now.pos - previous.pos - mean * dt).abs() <= tolerance, "pos jump at step {k}");
            previous = now;
        }
        assert_eq!(plan.at(plan.duration()).pos, target, "ends exactly on the target");
        plan
    }

    #[test]
    fn a_long_move_reaches_cruise_velocity() {
        let plan = check(0.0, 0.0, 100.0, LIMITS);
        let t = 0.1 + 0.5 * 100.0 / 1000.0;
        assert_eq!(plan.at(t).vel, 100.0);
        // accel 0.1 s (5 mm), decel 0.2 s (10 mm), cruise 85 mm at 100 mm/s.
        assert!((plan.duration() - (0.1 + 0.85 + 0.2)).abs() < 1e-12);
    }

    #[test]
    fn a_short_move_is_a_triangle() {
        let plan = check(0.0, 0.0, 1.0, LIMITS);
        let peak = (0..1000).map(|k| plan.at(k as f64 * 1e-4).vel).fold(0.0, f64::max);
        assert!(peak < 100.0);
    }

    #[test]
    fn retargets_behind_brake_then_return() {
        check(50.0, 100.0, 0.0, LIMITS);
    }

    #[test]
    fn retargets_too_close_to_stop_overshoot_and_return() {
        check(0.0, 100.0, 1.0, LIMITS);
    }

    #[test]
    fn a_lowered_limit_decelerates_to_it() {
        let plan = check(0.0, 100.0, 1000.0, Limits { vel: 20.0, ..LIMITS });
        assert_eq!(plan.at(plan.duration() / 2.0).vel, 20.0);
    }

    #[test]
    fn negative_moves_mirror_positive_ones() {
        let plus = Trapezoid::plan(0.0, 0.0, 42.0, LIMITS);
        let minus = Trapezoid::plan(0.0, 0.0, -42.0, LIMITS);
        assert!((plus.duration() - minus.duration()).abs() < 1e-12);
        assert!((plus.at(0.1).pos + minus.at(0.1).pos).abs() < 1e-12);
        check(10.0, -30.0, -500.0, LIMITS);
    }

    #[test]
    fn a_stop_is_one_deceleration() {
        let plan = check(0.0, 100.0, 5.0, LIMITS);
        let stop = Trapezoid::stop(0.0, 100.0, 500.0);
        assert!((stop.duration() - 0.2).abs() < 1e-12);
        assert_eq!(stop.target(), 10.0);
        assert!(plan.duration() > stop.duration());
    }

    #[test]
    fn velocity_ramps_use_acc_up_and_dec_down() {
        assert_eq!(ramp_velocity(0.0, 10.0, 100.0, 50.0, 0.01), 1.0);
        assert_eq!(ramp_velocity(10.0, 0.0, 100.0, 50.0, 0.01), 9.5);
        assert_eq!(ramp_velocity(1.0, -10.0, 100.0, 50.0, 0.01), 0.5, "through zero with dec");
        assert_eq!(ramp_velocity(3.0, 7.0, 0.0, 0.0, 0.01), 7.0, "a rate of 0 is a step");
    }

    #[test]
    fn no_move_is_an_empty_plan() {
        let plan = Trapezoid::plan(5.0, 0.0, 5.0, LIMITS);
        assert_eq!(plan.duration(), 0.0);
        assert_eq!(plan.at(0.0).pos, 5.0);
    }
}

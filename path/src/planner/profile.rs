//! The velocity profile along one segment: from the current velocity to a cruise velocity,
//! then to an exit velocity at the segment's end (a trapezoid, HMPL 8.1 "S-curve profile
//! like axes" before the group's smoothing). It is planned again every cycle from where the
//! path is, so a new cruise (velocity scale, halt) or a new exit (a push) takes effect at
//! once while acceleration and deceleration stay within their limits.

/// A trapezoid over a distance: phase 1 from `v0` to `vm`, phase 2 at `vm`, phase 3 to `ve`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Trapezoid {
    v0: f64,
    vm: f64,
    ve: f64,
    a1: f64,
    a3: f64,
    t1: f64,
    t2: f64,
    t3: f64,
    d1: f64,
    d2: f64,
    dist: f64,
}

/// The distance to go from `a` to `b` with acceleration `acc` (up) or `dec` (down).
fn ramp(a: f64, b: f64, acc: f64, dec: f64) -> f64 {
    if b >= a { (b * b - a * a) / (2.0 * acc) } else { (a * a - b * b) / (2.0 * dec) }
}

/// The lowest velocity `v0` can be braked to within `dist`.
pub(crate) fn brake_to(v0: f64, dist: f64, dec: f64) -> f64 {
    (v0 * v0 - 2.0 * dec * dist).max(0.0).sqrt()
}

impl Trapezoid {
    /// From `v0` over `dist` with at most `cruise` between, ending as near to `exit` as
    /// `acc` and `dec` allow (an exit out of reach becomes the nearest reachable one).
    pub(crate) fn plan(v0: f64, dist: f64, cruise: f64, exit: f64, acc: f64, dec: f64) -> Trapezoid {
        let dist = dist.max(0.0);
        let (mut acc, mut dec) = (acc, dec);
        // The state is planned again every cycle, so a segment's end is approached from a
        // rounded distance; an exit missed by rounding is met by braking or accelerating a
        // hair (1e-9) harder, instead of a velocity step at the junction. The rounding of the
        // position (1e-12 mm, `s` up to metres) counts absolutely: over the last micrometres
        // before a stop it is far more than 1e-9 of the distance, and missing a stop by
        // d leaves a step of sqrt(2 dec d) (path/tests/planner_constraints.rs).
        let slack = |rate: f64| 2.0 * rate * (dist * (1.0 + 1e-9) + 1e-12) + 1e-12;
        let (down, up) = (v0 * v0 - exit * exit, exit * exit - v0 * v0);
        if down > 2.0 * dec * dist && down <= slack(dec) && dist > 0.0 {
            dec = down / (2.0 * dist);
        } else if up > 2.0 * acc * dist && up <= slack(acc) && dist > 0.0 {
            acc = up / (2.0 * dist);
        }
        let lo = brake_to(v0, dist, dec);
        let hi = (v0 * v0 + 2.0 * acc * dist).sqrt();
        let ve =
            if down > 0.0 && down <= slack(dec) || up > 0.0 && up <= slack(acc) { exit } else { exit.max(lo).min(hi) };
        let mut vm = cruise.max(0.0);
        if ramp(v0, vm, acc, dec) + ramp(vm, ve, acc, dec) > dist {
            // No room to reach the cruise velocity: a peak below it or a valley above it.
            vm = if vm > v0.max(ve) {
                ((2.0 * acc * dec * dist + dec * v0 * v0 + acc * ve * ve) / (acc + dec)).sqrt().max(v0.max(ve))
            } else if vm < v0.min(ve) {
                ((acc * v0 * v0 + dec * ve * ve - 2.0 * acc * dec * dist) / (acc + dec)).max(0.0).sqrt().min(v0.min(ve))
            } else {
                // Monotone from v0 to ve (only rounding gets here): no cruise.
                ve
            };
        }
        let d1 = ramp(v0, vm, acc, dec);
        let d3 = ramp(vm, ve, acc, dec);
        let d2 = (dist - d1 - d3).max(0.0);
        let (a1, t1) = if vm >= v0 { (acc, (vm - v0) / acc) } else { (-dec, (v0 - vm) / dec) };
        let (a3, t3) = if ve >= vm { (acc, (ve - vm) / acc) } else { (-dec, (vm - ve) / dec) };
        let t2 = if vm > 0.0 {
            d2 / vm
        } else if d2 > 1e-12 {
            f64::INFINITY // halted short of the end: it stays
        } else {
            0.0
        };
        Trapezoid { v0, vm, ve, a1, a3, t1, t2, t3, d1, d2, dist }
    }

    /// How long the whole profile takes (infinite when it stops short of its end).
    pub(crate) fn duration(&self) -> f64 {
        self.t1 + self.t2 + self.t3
    }

    pub(crate) fn exit(&self) -> f64 {
        self.ve
    }

    /// Distance, velocity and acceleration at time `t` after the start.
    pub(crate) fn at(&self, t: f64) -> (f64, f64, f64) {
        if t < self.t1 {
            (self.v0 * t + 0.5 * self.a1 * t * t, self.v0 + self.a1 * t, self.a1)
        } else if t < self.t1 + self.t2 {
            (self.d1 + self.vm * (t - self.t1), self.vm, 0.0)
        } else if t < self.duration() {
            let tau = t - self.t1 - self.t2;
            (self.d1 + self.d2 + self.vm * tau + 0.5 * self.a3 * tau * tau, self.vm + self.a3 * tau, self.a3)
        } else {
            (self.dist, self.ve, 0.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_trapezoid_ends_at_its_distance_and_exit() {
        let p = Trapezoid::plan(0.0, 100.0, 100.0, 0.0, 5000.0, 2500.0);
        assert!((p.duration() - (1.0 + 0.01 + 0.02)).abs() < 1e-12);
        let (s, v, _) = p.at(p.duration());
        assert_eq!((s, v), (100.0, 0.0));
        let (s, v, a) = p.at(0.5);
        assert!((v - 100.0).abs() < 1e-12 && a == 0.0 && (s - (1.0 + 100.0 * 0.48)).abs() < 1e-9);
    }

    #[test]
    fn an_unreachable_exit_becomes_the_nearest_reachable_one() {
        // 1 mm is too short to brake from 100 mm/s at 1000 mm/s^2 (needs 5 mm).
        let p = Trapezoid::plan(100.0, 1.0, 100.0, 0.0, 1000.0, 1000.0);
        assert!((p.exit() - (100.0f64 * 100.0 - 2000.0).sqrt()).abs() < 1e-9);
        // And a raised exit above what acceleration allows.
        let p = Trapezoid::plan(0.0, 1.0, 1000.0, 1000.0, 1000.0, 1000.0);
        assert!((p.exit() - 2000f64.sqrt()).abs() < 1e-9);
    }

    #[test]
    fn a_stop_missed_by_the_rounding_of_the_position_is_met() {
        // Found by the checker: 0.0175 mm/s at 6012.5 mm/s² needs 2.5e-8 mm to stop; a
        // distance short of it by 1e-15 mm (the rounding of a position of some mm) must
        // still end at rest, not 3.5e-6 mm/s above it.
        let (v0, dec) = (0.0175, 6012.5);
        let p = Trapezoid::plan(v0, v0 * v0 / (2.0 * dec) - 1e-15, 100.0, 0.0, 5000.0, dec);
        assert_eq!(p.exit(), 0.0);
        // And an exit to accelerate to, out of reach by as little.
        let (ve, acc) = (0.0123, 4321.0);
        let p = Trapezoid::plan(0.0, ve * ve / (2.0 * acc) - 1e-15, 100.0, ve, acc, 5000.0);
        assert_eq!(p.exit(), ve);
    }

    #[test]
    fn halted_it_stops_short_and_stays() {
        let p = Trapezoid::plan(100.0, 100.0, 0.0, 0.0, 1000.0, 1000.0);
        assert_eq!(p.duration(), f64::INFINITY);
        let (s, v, _) = p.at(10.0);
        assert!((s - 5.0).abs() < 1e-12 && v == 0.0);
    }
}

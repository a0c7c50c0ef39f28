//! PVT motion (HMPL 5.2.8): through points of time (ms, from 0), position and velocity,
//! with cubic Hermite segments; at most 50 points.

use devices::profile::Kinematics;

/// The most points one MovePVT table holds (HMPL 5.2.8).
pub const MAX_POINTS: usize = 50;

/// One point of a PVT table: the axis passes `pos` at `t` with velocity `vel`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PvtPoint {
    /// Seconds from the start.
    pub t: f64,
    /// Axis position, axis units, absolute: the first point is where the axis stands.
    pub pos: f64,
    /// Axis velocity, axis units/s.
    pub vel: f64,
}

/// Why a PVT table is refused (HMPL table 18.1.2.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PvtError {
    /// 0x08B6: times must start at 0 and increase.
    InvalidTime,
    /// 0x08A2: a point's velocity, or a segment's, above the limit.
    VelocityLimit,
    /// 0x08AC: a segment's acceleration above the limit.
    AccelerationLimit,
    /// More than 50 points, fewer than 2, or a value that is not a finite number.
    Points,
}

/// A checked PVT table (`Pvt::new`), held inline so that queueing it never allocates.
#[derive(Clone, Copy, Debug)]
pub struct Pvt {
    points: [PvtPoint; MAX_POINTS],
    count: usize,
}

impl Pvt {
    /// Checks a table against the axis' velocity and acceleration limits.
    pub fn new(points: &[PvtPoint], max_vel: f64, max_acc: f64) -> Result<Self, PvtError> {
        if !(2..=MAX_POINTS).contains(&points.len()) {
            return Err(PvtError::Points);
        }
        if points.iter().any(|p| !(p.t.is_finite() && p.pos.is_finite() && p.vel.is_finite())) {
            return Err(PvtError::Points);
        }
        if points[0].t != 0.0 || points.windows(2).any(|w| w[1].t <= w[0].t) {
            return Err(PvtError::InvalidTime);
        }
        let mut table = [PvtPoint::default(); MAX_POINTS];
        table[..points.len()].copy_from_slice(points);
        let pvt = Pvt { points: table, count: points.len() };
        // A cubic's acceleration is linear, so its extremes are at the ends; its velocity is
        // quadratic, so check the ends and the vertex.
        for w in pvt.points[..pvt.count].windows(2) {
            let (a0, a1) = (Self::acc(w, 0.0), Self::acc(w, 1.0));
            if a0.abs().max(a1.abs()) > max_acc * (1.0 + 1e-9) {
                return Err(PvtError::AccelerationLimit);
            }
            let h = w[1].t - w[0].t;
            let mut peak = w[0].vel.abs().max(w[1].vel.abs());
            if a0 != a1 {
                let s = a0 / (a0 - a1);
                if (0.0..=1.0).contains(&s) {
                    peak = peak.max(Self::sample(w, s * h).vel.abs());
                }
            }
            if peak > max_vel * (1.0 + 1e-9) {
                return Err(PvtError::VelocityLimit);
            }
        }
        Ok(pvt)
    }

    pub(crate) fn first(&self) -> PvtPoint {
        self.points[0]
    }

    pub(crate) fn last(&self) -> PvtPoint {
        self.points[self.count - 1]
    }

    pub(crate) fn duration(&self) -> f64 {
        self.last().t
    }

    /// Acceleration at fraction `s` of a segment.
    fn acc(w: &[PvtPoint], s: f64) -> f64 {
        let h = w[1].t - w[0].t;
        let (p0, p1, v0, v1) = (w[0].pos, w[1].pos, w[0].vel * h, w[1].vel * h);
        ((6.0 - 12.0 * s) * p0 + (6.0 * s - 4.0) * v0 + (12.0 * s - 6.0) * p1 + (6.0 * s - 2.0) * v1) / (h * h)
    }

    /// A segment at time `dt` after its start.
    fn sample(w: &[PvtPoint], dt: f64) -> Kinematics {
        let h = w[1].t - w[0].t;
        let s = dt / h;
        let (p0, p1, v0, v1) = (w[0].pos, w[1].pos, w[0].vel * h, w[1].vel * h);
        let (s2, s3) = (s * s, s * s * s);
        let pos =
            (2.0 * s3 - 3.0 * s2 + 1.0) * p0 + (s3 - 2.0 * s2 + s) * v0 + (-2.0 * s3 + 3.0 * s2) * p1 + (s3 - s2) * v1;
        let vel = ((6.0 * s2 - 6.0 * s) * p0
            + (3.0 * s2 - 4.0 * s + 1.0) * v0
            + (-6.0 * s2 + 6.0 * s) * p1
            + (3.0 * s2 - 2.0 * s) * v1)
            / h;
        Kinematics { pos, vel, acc: Self::acc(w, s) }
    }

    /// The motion at time `t` from the start; at the last point afterwards.
    pub fn at(&self, t: f64) -> Kinematics {
        let points = &self.points[..self.count];
        if t >= self.duration() {
            let last = self.last();
            return Kinematics { pos: last.pos, vel: last.vel, acc: 0.0 };
        }
        let i = points.windows(2).position(|w| t < w[1].t).unwrap_or(0);
        Self::sample(&points[i..i + 2], t - points[i].t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn points(rows: &[(f64, f64, f64)]) -> Vec<PvtPoint> {
        rows.iter().map(|&(ms, pos, vel)| PvtPoint { t: ms / 1000.0, pos, vel }).collect()
    }

    /// HMPL 5.2.8: the manual's example passes through its points.
    #[test]
    fn the_manual_example_passes_its_points() {
        let p = points(&[
            (0.0, 0.0, 0.0),
            (2000.0, 153.333, 1000.0),
            (3000.0, 42.123, 800.0),
            (4000.0, 161.21, 1660.0),
            (6000.0, 177.0, 450.0),
            (11000.0, 83.333, 0.0),
        ]);
        let pvt = Pvt::new(&p, 1e6, 1e6).unwrap();
        for point in &p {
            let k = pvt.at(point.t);
            assert!((k.pos - point.pos).abs() < 1e-9 && (k.vel - point.vel).abs() < 1e-9, "{point:?}");
        }
        assert_eq!(pvt.at(20.0).pos, 83.333);
    }

    #[test]
    fn bad_tables_are_refused() {
        let ok = [(0.0, 0.0, 0.0), (1000.0, 10.0, 0.0)];
        assert!(Pvt::new(&points(&ok), 100.0, 100.0).is_ok());
        assert_eq!(
            Pvt::new(&points(&[(5.0, 0.0, 0.0), (1000.0, 1.0, 0.0)]), 100.0, 100.0).err(),
            Some(PvtError::InvalidTime)
        );
        assert_eq!(
            Pvt::new(&points(&[(0.0, 0.0, 0.0), (0.0, 1.0, 0.0)]), 100.0, 100.0).err(),
            Some(PvtError::InvalidTime)
        );
        assert_eq!(Pvt::new(&points(&ok), 10.0, 100.0).err(), Some(PvtError::VelocityLimit), "peak 15 mm/s");
        assert_eq!(
            Pvt::new(&points(&ok), 100.0, 50.0).err(),
            Some(PvtError::AccelerationLimit),
            "60 mm/s² at the ends"
        );
        let many: Vec<(f64, f64, f64)> = (0..51).map(|i| (i as f64, 0.0, 0.0)).collect();
        assert_eq!(Pvt::new(&points(&many), 100.0, 100.0).err(), Some(PvtError::Points), "51 points");
        let nan = [(0.0, 0.0, 0.0), (1000.0, f64::NAN, 0.0)];
        assert_eq!(Pvt::new(&points(&nan), 100.0, 100.0).err(), Some(PvtError::Points), "a position not a number");
    }
}

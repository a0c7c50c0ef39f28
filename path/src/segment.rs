//! One segment of a group's path (HMPL 8.1: "each command is one segment"): where it
//! starts and ends, how long it is, and the pose at any fraction of it.
//!
//! A pose is X, Y, Z in mm and A, B, C in degrees (HMPL 8.1.2). Translation and rotation
//! both move in proportion to the fraction `u` in [0, 1] of the segment, so they start and
//! end together; the planner turns time into `u`.

/// X, Y, Z (mm), A, B, C (deg), HMPL 8.1.2.
pub type Pose = [f64; 6];

/// A unit vector of the translation's direction (all zero where the segment only rotates).
pub type Direction = [f64; 3];

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    Line(Line),
}

/// A straight line in X, Y, Z with A, B, C moving linearly beside it (HMPL 8.2.9, 8.5.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    pub start: Pose,
    pub end: Pose,
}

impl Segment {
    pub fn start(&self) -> Pose {
        match self {
            Segment::Line(l) => l.start,
        }
    }

    pub fn end(&self) -> Pose {
        match self {
            Segment::Line(l) => l.end,
        }
    }

    /// The length of the translation along the path, mm.
    pub fn length(&self) -> f64 {
        match self {
            Segment::Line(l) => norm3(sub3(&l.end, &l.start)),
        }
    }

    /// How far A, B, C turn, deg (the Euclidean length of their change).
    pub fn angular_length(&self) -> f64 {
        let (s, e) = (self.start(), self.end());
        ((e[3] - s[3]).powi(2) + (e[4] - s[4]).powi(2) + (e[5] - s[5]).powi(2)).sqrt()
    }

    /// The pose at fraction `u` (0 start, 1 end) of the segment.
    pub fn pose_at(&self, u: f64) -> Pose {
        match self {
            Segment::Line(l) => lerp(&l.start, &l.end, u),
        }
    }

    /// The unit direction of the translation at fraction `u`.
    pub fn direction_at(&self, _u: f64) -> Direction {
        match self {
            Segment::Line(l) => unit3(sub3(&l.end, &l.start)),
        }
    }

    /// The radius of curvature of the translation at fraction `u`; `None` where straight.
    pub fn radius_at(&self, _u: f64) -> Option<f64> {
        match self {
            Segment::Line(_) => None,
        }
    }
}

/// The pose a fraction `u` of the way from `a` to `b`.
pub fn lerp(a: &Pose, b: &Pose, u: f64) -> Pose {
    std::array::from_fn(|i| a[i] + (b[i] - a[i]) * u)
}

/// The translation from `a` to `b`.
pub fn sub3(b: &Pose, a: &Pose) -> [f64; 3] {
    [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
}

pub fn norm3(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// `v` scaled to length 1; zero stays zero.
pub fn unit3(v: [f64; 3]) -> Direction {
    let n = norm3(v);
    if n > 0.0 { [v[0] / n, v[1] / n, v[2] / n] } else { [0.0; 3] }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_is_straight_and_proportional() {
        let l =
            Segment::Line(Line { start: [100.0, 200.0, 0.0, 0.0, 0.0, 0.0], end: [200.0, 300.0, 0.0, 0.0, 0.0, 90.0] });
        assert!((l.length() - 100.0 * 2f64.sqrt()).abs() < 1e-12);
        assert_eq!(l.angular_length(), 90.0);
        assert_eq!(l.pose_at(0.5), [150.0, 250.0, 0.0, 0.0, 0.0, 45.0]);
        let d = l.direction_at(0.3);
        assert!((d[0] - 0.5f64.sqrt()).abs() < 1e-15 && (d[1] - 0.5f64.sqrt()).abs() < 1e-15 && d[2] == 0.0);
        assert_eq!(l.radius_at(0.5), None);
    }
}

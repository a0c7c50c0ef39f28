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

/// The geometry of one segment, by the command that made it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    /// LineAbs / LineRel (HMPL 8.2.9-8.2.12).
    Line(Line),
    /// The arcs, circles and helices (HMPL 8.2.13-8.2.17).
    Arc(Arc),
    /// A corner transition the planner inserted between two segments (HMPL 8.1.5).
    Blend(Blend),
}

/// A straight line in X, Y, Z with A, B, C moving linearly beside it (HMPL 8.2.9, 8.5.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    /// The pose the line starts at, in MCS.
    pub start: Pose,
    /// The commanded end, in MCS.
    pub end: Pose,
}

/// An arc, a full circle or a helix (HMPL 8.2.13-8.2.17, 8.5.3): the start turns by
/// `sweep` about the axis through `center` along `normal` (right-hand rule: a positive
/// sweep turns counter-clockwise seen from the normal's tip) while it rises by `rise`
/// along the normal. A, B, C move linearly beside it.
///
/// `radius_change` is the end radius minus the start radius: a commanded end off the
/// circle by less than the tolerance of `commands` makes the radius drift linearly with
/// the angle, so the path meets the commanded end exactly. Only then is the arc length
/// not closed-form (see [`Arc::tau`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arc {
    /// The pose the arc starts at, in MCS.
    pub start: Pose,
    /// The commanded end, returned as it is at `u = 1`.
    pub end: Pose,
    /// The center in the start's plane (perpendicular to `normal`).
    pub center: [f64; 3],
    /// Unit vector.
    pub normal: [f64; 3],
    /// Radius at the start, mm (> 0).
    pub radius: f64,
    /// End radius minus start radius, mm; 0 for a true circle (see above).
    pub radius_change: f64,
    /// Signed turning angle, rad; its magnitude may exceed 2π (several turns).
    pub sweep: f64,
    /// Translation along `normal` from start to end, mm (a helix where non-zero).
    pub rise: f64,
}

/// Panels of a blend's length table (8-point Gauss-Legendre each): with the turning
/// angle of a blended corner at most [`Blend::MAX_TURN_DEG`] the speed along `u`
/// stays within 1e-7 of uniform (measured by `path/tests/speed.rs`: 4e-8 at worst over
/// random blends, 1e-10 at a 170° corner).
const BLEND_PANELS: usize = 16;

/// A corner blend (HMPL 8.1.5): the Bézier curve with control points `ctrl`, tangent to the
/// trimmed segments at both ends. Between two lines it is the quadratic Bézier through the
/// corner as control point (written as a cubic), whose deviation from the corner,
/// ½·d·cos(β/2) for a trim d and corner angle β, is the bound of HMPL table 8.3.26.1.
///
/// Its arc length has no closed form: `table` holds the length at the ends of
/// `BLEND_PANELS` equal parameter panels (8-point Gauss-Legendre), and `pose_at` inverts
/// it by Newton's method inside the panel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blend {
    /// Where it leaves the first segment, the trim d before the corner.
    pub start: Pose,
    /// Where it joins the second segment, d after the corner.
    pub end: Pose,
    /// The cubic Bézier's control points in X, Y, Z, mm; A, B, C move linearly.
    pub ctrl: [[f64; 3]; 4],
    table: [f64; BLEND_PANELS + 1],
}

impl Segment {
    /// The pose at `u = 0`.
    pub fn start(&self) -> Pose {
        match self {
            Segment::Line(l) => l.start,
            Segment::Arc(a) => a.start,
            Segment::Blend(b) => b.start,
        }
    }

    /// The pose at `u = 1`, the commanded end.
    pub fn end(&self) -> Pose {
        match self {
            Segment::Line(l) => l.end,
            Segment::Arc(a) => a.end,
            Segment::Blend(b) => b.end,
        }
    }

    /// The length of the translation along the path, mm.
    pub fn length(&self) -> f64 {
        match self {
            Segment::Line(l) => norm3(sub3(&l.end, &l.start)),
            Segment::Arc(a) => a.length(),
            Segment::Blend(b) => b.table[BLEND_PANELS],
        }
    }

    /// How far A, B, C turn, deg (the Euclidean length of their change).
    pub fn angular_length(&self) -> f64 {
        let (s, e) = (self.start(), self.end());
        ((e[3] - s[3]).powi(2) + (e[4] - s[4]).powi(2) + (e[5] - s[5]).powi(2)).sqrt()
    }

    /// The pose at fraction `u` (0 start, 1 end) of the segment; exactly `end()` at 1.
    pub fn pose_at(&self, u: f64) -> Pose {
        if u >= 1.0 {
            return self.end();
        }
        if u <= 0.0 {
            return self.start();
        }
        match self {
            Segment::Line(l) => lerp(&l.start, &l.end, u),
            Segment::Arc(a) => with_xyz(lerp(&a.start, &a.end, u), a.point(a.tau(u))),
            Segment::Blend(b) => with_xyz(lerp(&b.start, &b.end, u), b.point(b.tau(u))),
        }
    }

    /// The unit direction of the translation at fraction `u`.
    pub fn direction_at(&self, u: f64) -> Direction {
        let u = u.clamp(0.0, 1.0);
        match self {
            Segment::Line(l) => unit3(sub3(&l.end, &l.start)),
            Segment::Arc(a) => unit3(a.derivatives(a.tau(u)).0),
            Segment::Blend(b) => unit3(b.derivatives(b.tau(u)).0),
        }
    }

    /// The radius of curvature of the translation at fraction `u`; `None` where straight.
    /// A helix reports its true radius of curvature, (r² + p²)/r for the pitch p = rise/sweep.
    pub fn radius_at(&self, u: f64) -> Option<f64> {
        let u = u.clamp(0.0, 1.0);
        let (d1, d2) = match self {
            Segment::Line(_) => return None,
            Segment::Arc(a) => a.derivatives(a.tau(u)),
            Segment::Blend(b) => b.derivatives(b.tau(u)),
        };
        let speed = norm3(d1);
        let cross = norm3(cross3(d1, d2));
        (cross > 1e-12 * speed.powi(3) && speed > 0.0).then(|| speed.powi(3) / cross)
    }

    /// The part of the segment between fractions `u0 < u1`, as a segment of the same kind
    /// (a corner blend trims its neighbours with it; a stop may cut the path short).
    pub fn sub(&self, u0: f64, u1: f64) -> Segment {
        let (s, e) = (self.pose_at(u0), self.pose_at(u1));
        match self {
            Segment::Line(_) => Segment::Line(Line { start: s, end: e }),
            Segment::Arc(a) => {
                let (t0, t1) = (a.tau(u0), a.tau(u1));
                Segment::Arc(Arc {
                    start: s,
                    end: e,
                    center: add3(a.center, scale3(a.normal, a.rise * t0)),
                    normal: a.normal,
                    radius: a.radius + a.radius_change * t0,
                    radius_change: a.radius_change * (t1 - t0),
                    sweep: a.sweep * (t1 - t0),
                    rise: a.rise * (t1 - t0),
                })
            }
            Segment::Blend(b) => {
                // The cubic on [t0, t1] is the cubic with the same ends and end tangents
                // scaled to the shorter parameter range.
                let (t0, t1) = (b.tau(u0), b.tau(u1));
                let (d0, d1) = (b.derivatives(t0).0, b.derivatives(t1).0);
                let k = (t1 - t0) / 3.0;
                Segment::Blend(Blend::new(s, e, [add3(xyz(&s), scale3(d0, k)), diff3(xyz(&e), scale3(d1, k))]))
            }
        }
    }
}

impl Arc {
    /// The start's unit radial vector and the one a quarter turn ahead about the normal.
    fn basis(&self) -> ([f64; 3], [f64; 3]) {
        let e1 = unit3(diff3(xyz(&self.start), self.center));
        (e1, cross3(self.normal, e1))
    }

    /// The point at angle fraction `tau` (the angle is `tau · sweep`).
    fn point(&self, tau: f64) -> [f64; 3] {
        let (e1, e2) = self.basis();
        let (s, c) = (self.sweep * tau).sin_cos();
        let r = self.radius + self.radius_change * tau;
        std::array::from_fn(|i| self.center[i] + self.normal[i] * self.rise * tau + r * (c * e1[i] + s * e2[i]))
    }

    /// First and second derivative of the point with respect to `tau`.
    fn derivatives(&self, tau: f64) -> ([f64; 3], [f64; 3]) {
        let (e1, e2) = self.basis();
        let (s, c) = (self.sweep * tau).sin_cos();
        let (r, dr, w) = (self.radius + self.radius_change * tau, self.radius_change, self.sweep);
        let radial: [f64; 3] = std::array::from_fn(|i| c * e1[i] + s * e2[i]);
        let tangential: [f64; 3] = std::array::from_fn(|i| -s * e1[i] + c * e2[i]);
        let d1 = std::array::from_fn(|i| self.normal[i] * self.rise + dr * radial[i] + r * w * tangential[i]);
        let d2 = std::array::from_fn(|i| 2.0 * dr * w * tangential[i] - r * w * w * radial[i]);
        (d1, d2)
    }

    /// |d point / d tau|.
    fn speed(&self, tau: f64) -> f64 {
        let r = self.radius + self.radius_change * tau;
        (self.radius_change.powi(2) + (r * self.sweep).powi(2) + self.rise.powi(2)).sqrt()
    }

    fn length(&self) -> f64 {
        if self.radius_change == 0.0 { self.speed(0.0) } else { gauss_legendre(|t| self.speed(t), 0.0, 1.0) }
    }

    /// The angle fraction at arc-length fraction `u`: `u` itself on a circle or helix; on
    /// a drifting radius (at most 1e-3 of it, `commands`) the speed varies by less than
    /// that, and Newton's method on the Gauss-Legendre length (exact to rounding for so
    /// smooth an integrand) converges in three steps.
    fn tau(&self, u: f64) -> f64 {
        if self.radius_change == 0.0 {
            return u;
        }
        let target = u * self.length();
        let mut t = u;
        for _ in 0..8 {
            let step = (gauss_legendre(|x| self.speed(x), 0.0, t) - target) / self.speed(t);
            t -= step;
            if step.abs() < 1e-15 {
                break;
            }
        }
        t.clamp(0.0, 1.0)
    }
}

impl Blend {
    /// The largest corner turn a blend is built for, deg: near a reversal it would be a
    /// hairpin of tiny radius, and its length table loses accuracy (`BLEND_PANELS`).
    pub const MAX_TURN_DEG: f64 = 170.0;

    /// The blend from `start` to `end` (poses; their X, Y, Z are `ctrl[0]` and `ctrl[3]`).
    pub fn new(start: Pose, end: Pose, inner: [[f64; 3]; 2]) -> Blend {
        let ctrl = [[start[0], start[1], start[2]], inner[0], inner[1], [end[0], end[1], end[2]]];
        let mut blend = Blend { start, end, ctrl, table: [0.0; BLEND_PANELS + 1] };
        for k in 0..BLEND_PANELS {
            let (a, b) = (k as f64 / BLEND_PANELS as f64, (k + 1) as f64 / BLEND_PANELS as f64);
            blend.table[k + 1] = blend.table[k] + gauss_legendre(|t| blend.speed(t), a, b);
        }
        blend
    }

    pub(crate) fn point(&self, t: f64) -> [f64; 3] {
        let [p0, p1, p2, p3] = self.ctrl;
        let s = 1.0 - t;
        let w = [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t];
        std::array::from_fn(|i| w[0] * p0[i] + w[1] * p1[i] + w[2] * p2[i] + w[3] * p3[i])
    }

    pub(crate) fn derivatives(&self, t: f64) -> ([f64; 3], [f64; 3]) {
        let [p0, p1, p2, p3] = self.ctrl;
        let s = 1.0 - t;
        let d1 = std::array::from_fn(|i| {
            3.0 * (s * s * (p1[i] - p0[i]) + 2.0 * s * t * (p2[i] - p1[i]) + t * t * (p3[i] - p2[i]))
        });
        let d2 = std::array::from_fn(|i| 6.0 * (s * (p2[i] - 2.0 * p1[i] + p0[i]) + t * (p3[i] - 2.0 * p2[i] + p1[i])));
        (d1, d2)
    }

    fn speed(&self, t: f64) -> f64 {
        norm3(self.derivatives(t).0)
    }

    /// The curve parameter at arc-length fraction `u`.
    fn tau(&self, u: f64) -> f64 {
        let target = u * self.table[BLEND_PANELS];
        let k = self.table.partition_point(|&s| s <= target).clamp(1, BLEND_PANELS) - 1;
        let a = k as f64 / BLEND_PANELS as f64;
        let mut t = a + (target - self.table[k]) / (self.table[k + 1] - self.table[k]) / BLEND_PANELS as f64;
        for _ in 0..12 {
            let step = (self.table[k] + gauss_legendre(|x| self.speed(x), a, t) - target) / self.speed(t);
            t -= step;
            if step.abs() < 1e-15 {
                break;
            }
        }
        t.clamp(0.0, 1.0)
    }
}

/// ∫ f over [a, b] by 8-point Gauss-Legendre.
fn gauss_legendre(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    const X: [f64; 4] =
        [0.183_434_642_495_649_8, 0.525_532_409_916_329, 0.796_666_477_413_626_7, 0.960_289_856_497_536_3];
    const W: [f64; 4] =
        [0.362_683_783_378_362, 0.313_706_645_877_887_3, 0.222_381_034_453_374_5, 0.101_228_536_290_376_3];
    let (m, h) = ((a + b) / 2.0, (b - a) / 2.0);
    h * X.iter().zip(W).map(|(x, w)| w * (f(m - h * x) + f(m + h * x))).sum::<f64>()
}

/// `pose` with its X, Y, Z replaced by `p`.
fn with_xyz(mut pose: Pose, p: [f64; 3]) -> Pose {
    pose[..3].copy_from_slice(&p);
    pose
}

/// The pose a fraction `u` of the way from `a` to `b`.
pub fn lerp(a: &Pose, b: &Pose, u: f64) -> Pose {
    std::array::from_fn(|i| a[i] + (b[i] - a[i]) * u)
}

/// The translation from `a` to `b`.
pub fn sub3(b: &Pose, a: &Pose) -> [f64; 3] {
    [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
}

/// The Euclidean length of `v`.
pub fn norm3(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The X, Y, Z of a pose.
pub fn xyz(p: &Pose) -> [f64; 3] {
    [p[0], p[1], p[2]]
}

/// `a − b`.
pub fn diff3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn add3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(crate) fn scale3(a: [f64; 3], k: f64) -> [f64; 3] {
    [a[0] * k, a[1] * k, a[2] * k]
}

/// The scalar product `a · b`.
pub fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The vector product `a × b`, right-handed.
pub fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
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

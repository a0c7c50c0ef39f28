//! One constructor per geometry command of HMPL 8.2 and 8.5: each takes the pose where the
//! queued path ends (`start`) and the command's points already in MCS (`frames::Frame`
//! maps them), and returns the segment or the manual's error (table 18.1.3.1).
//!
//! A 2-D command keeps Z, A, B, C of the start in its coordinate system: the caller lifts
//! its points with [`crate::frames::Frame::point_2d`] and passes the system's Z axis in MCS
//! as the circle's normal ([`crate::frames::Frame::z_axis`]; `[0, 0, 1]` in MCS).

use std::f64::consts::TAU;

use api::GroupError;

use crate::segment::{Arc, Line, Pose, Segment, add3, cross3, diff3, dot3, norm3, scale3, unit3, xyz};

/// A center closer than this to the start or the end point is refused
/// (`CmdCircInvalidCenter`), mm.
pub const MIN_RADIUS: f64 = 1e-6;

/// A smaller turning angle is refused (`CmdCircAngleSmall`), rad.
pub const MIN_SWEEP: f64 = 1e-9;

/// How far the end may lie off the start's circle, mm: 1 µm, or 0.1 % of radii under
/// 1 mm. Within it the radius drifts to the end (`Arc::radius_change`), beyond it
/// `CmdCircInvalidRadius`; also the distance below which start and end coincide.
pub fn radius_tolerance(radius: f64) -> f64 {
    1e-3 * radius.min(1.0)
}

/// LineAbs2D (HMPL 8.2.9): `end` is the target in MCS at the start's height in its system.
pub fn line_abs_2d(start: &Pose, end: [f64; 3]) -> Result<Segment, GroupError> {
    line_to(start, end)
}

/// LineAbs3D (HMPL 8.2.10).
pub fn line_abs_3d(start: &Pose, end: [f64; 3]) -> Result<Segment, GroupError> {
    line_to(start, end)
}

/// LineRel2D (HMPL 8.2.11): `delta` is the displacement in MCS (the 2-D one rotated by
/// [`crate::frames::Frame::vector_to_mcs`]).
pub fn line_rel_2d(start: &Pose, delta: [f64; 3]) -> Result<Segment, GroupError> {
    line_to(start, add3(xyz(start), delta))
}

/// LineRel3D (HMPL 8.2.12).
pub fn line_rel_3d(start: &Pose, delta: [f64; 3]) -> Result<Segment, GroupError> {
    line_to(start, add3(xyz(start), delta))
}

/// LineAbs (HMPL 8.5.1): a 6-DOF target in MCS.
pub fn line_abs(start: &Pose, target: &Pose) -> Result<Segment, GroupError> {
    if !target.iter().all(|v| v.is_finite()) {
        return Err(GroupError::CmdInvalidPos);
    }
    Ok(Segment::Line(Line { start: *start, end: *target }))
}

/// LineRel (HMPL 8.5.2) in MCS: every coordinate of `delta` added to the start. In
/// another system the caller computes the target there
/// ([`crate::frames::Frame::relative_target`]) and calls [`line_abs`].
pub fn line_rel(start: &Pose, delta: &Pose) -> Result<Segment, GroupError> {
    line_abs(start, &std::array::from_fn(|i| start[i] + delta[i]))
}

fn line_to(start: &Pose, end: [f64; 3]) -> Result<Segment, GroupError> {
    line_abs(start, &with_point(start, end))
}

/// Arc2D (HMPL 8.2.13): from the start through `border` to `end`, turning less than 2π.
/// Three points on a line, or two of them equal, make no arc (`CmdCircInvalidParam`).
pub fn arc_2d(start: &Pose, border: [f64; 3], end: [f64; 3]) -> Result<Segment, GroupError> {
    finite(&[border, end])?;
    let p0 = xyz(start);
    let (a, b) = (diff3(border, p0), diff3(end, p0));
    let n = cross3(a, b);
    if norm3(n) <= 1e-9 * norm3(a) * norm3(b) || norm3(diff3(end, border)) < MIN_RADIUS {
        return Err(GroupError::CmdCircInvalidParam);
    }
    // The circumcenter; seen from n = a × b, start, border and end run counter-clockwise.
    let k = cross3(diff3(scale3(b, dot3(a, a)), scale3(a, dot3(b, b))), n);
    let center = add3(p0, scale3(k, 0.5 / dot3(n, n)));
    match arc(start, center, unit3(n), with_point(start, end), Sweep::Ccw)? {
        // An end within the tolerance of the start would close the circle.
        Segment::Arc(a) if a.sweep >= TAU => Err(GroupError::CmdCircInvalidParam),
        segment => Ok(segment),
    }
}

/// ArcCW2D (HMPL 8.2.14): clockwise about `center` (seen from `normal`) to `end`; the end
/// on the start makes a full circle.
pub fn arc_cw_2d(start: &Pose, center: [f64; 3], end: [f64; 3], normal: [f64; 3]) -> Result<Segment, GroupError> {
    arc(start, center, normal, with_point(start, end), Sweep::Cw)
}

/// ArcCCW2D (HMPL 8.2.15): counter-clockwise, as [`arc_cw_2d`].
pub fn arc_ccw_2d(start: &Pose, center: [f64; 3], end: [f64; 3], normal: [f64; 3]) -> Result<Segment, GroupError> {
    arc(start, center, normal, with_point(start, end), Sweep::Ccw)
}

/// ArcAngle2D (HMPL 8.2.16): about `center` by `angle_deg`, > 0 counter-clockwise; any
/// magnitude (several turns) is allowed.
pub fn arc_angle_2d(start: &Pose, center: [f64; 3], normal: [f64; 3], angle_deg: f64) -> Result<Segment, GroupError> {
    if !angle_deg.is_finite() {
        return Err(GroupError::CmdCircInvalidParam);
    }
    let sweep = angle_deg.to_radians();
    let n = normal_of(normal)?;
    finite(&[center])?;
    let p0 = xyz(start);
    let c = add3(center, scale3(n, dot3(diff3(p0, center), n)));
    let v0 = diff3(p0, c);
    let (s, co) = sweep.sin_cos();
    let end = add3(c, add3(scale3(v0, co), scale3(cross3(n, v0), s)));
    arc(start, c, n, with_point(start, end), Sweep::Angle(sweep))
}

/// Circle2D (HMPL 8.2.17): about `center` to `end` with the turns rule (see [`turns_sweep`]).
pub fn circle_2d(
    start: &Pose,
    center: [f64; 3],
    end: [f64; 3],
    normal: [f64; 3],
    turns: i64,
) -> Result<Segment, GroupError> {
    arc(start, center, normal, with_point(start, end), Sweep::Turns(turns))
}

/// CircleAbs (HMPL 8.5.3): about the axis through `center` along `normal` to the 6-DOF
/// `target`, turns as Circle2D. A target off the start's plane makes a helix; a start off
/// the center's plane turns about the same axis in its own plane.
pub fn circle_abs(
    start: &Pose,
    center: [f64; 3],
    normal: [f64; 3],
    turns: i64,
    target: &Pose,
) -> Result<Segment, GroupError> {
    arc(start, center, normal, *target, Sweep::Turns(turns))
}

/// CircleRel (HMPL 8.5.4): as [`circle_abs`] to the start plus `delta` (in MCS; the
/// center stays absolute). In another system the caller computes the target there
/// ([`crate::frames::Frame::relative_target`]) and calls [`circle_abs`].
pub fn circle_rel(
    start: &Pose,
    center: [f64; 3],
    normal: [f64; 3],
    turns: i64,
    delta: &Pose,
) -> Result<Segment, GroupError> {
    circle_abs(start, center, normal, turns, &std::array::from_fn(|i| start[i] + delta[i]))
}

/// The signed turning angle (rad) of Circle2D's rule (HMPL 8.2.17) from the
/// counter-clockwise angle `ccw` and the clockwise angle `cw` (both in (0, 2π]) from start
/// to end: turns ≥ 1 give ccw + (turns − 1)·2π, turns 0 is turns 1, turns < 0 give
/// −cw + (turns + 1)·2π. With θ = 210°: −2 → −510°, −1 → −150°, 0 and 1 → 210°, 2 → 570°.
pub fn turns_sweep(ccw: f64, cw: f64, turns: i64) -> f64 {
    if turns >= 0 { ccw + (turns.max(1) - 1) as f64 * TAU } else { -cw + (turns + 1) as f64 * TAU }
}

#[derive(Clone, Copy)]
enum Sweep {
    Ccw,
    Cw,
    Angle(f64),
    Turns(i64),
}

/// The arc from `start` about the axis (`center`, `normal`) to `end`.
fn arc(start: &Pose, center: [f64; 3], normal: [f64; 3], end: Pose, sweep: Sweep) -> Result<Segment, GroupError> {
    finite(&[center])?;
    if !end.iter().all(|v| v.is_finite()) {
        return Err(GroupError::CmdCircInvalidParam);
    }
    let n = normal_of(normal)?;
    let (p0, p1) = (xyz(start), xyz(&end));
    let c = add3(center, scale3(n, dot3(diff3(p0, center), n)));
    let rise = dot3(diff3(p1, p0), n);
    let (v0, v1) = (diff3(p0, c), diff3(diff3(p1, c), scale3(n, rise)));
    let (r0, r1) = (norm3(v0), norm3(v1));
    if r0 < MIN_RADIUS || r1 < MIN_RADIUS {
        return Err(GroupError::CmdCircInvalidCenter);
    }
    if (r1 - r0).abs() > radius_tolerance(r0) {
        return Err(GroupError::CmdCircInvalidRadius);
    }
    // The angle from start to end about n in (-π, π]; an end on the start is a full
    // turn either way (HMPL 8.1.6 example 4), so the counter-clockwise and clockwise angles
    // are both in (0, 2π].
    let theta = dot3(cross3(v0, v1), n).atan2(dot3(v0, v1));
    let (ccw, cw) = if norm3(diff3(v1, v0)) <= radius_tolerance(r0) {
        (TAU + theta, TAU - theta)
    } else if theta > 0.0 {
        (theta, TAU - theta)
    } else {
        (TAU + theta, -theta)
    };
    let sweep = match sweep {
        Sweep::Ccw => ccw,
        Sweep::Cw => -cw,
        Sweep::Angle(a) => a,
        Sweep::Turns(t) => turns_sweep(ccw, cw, t),
    };
    if sweep.abs() < MIN_SWEEP {
        return Err(GroupError::CmdCircAngleSmall);
    }
    // A difference of rounding is no drift: keep the closed-form arc length.
    let drift = r1 - r0;
    let radius_change = if drift.abs() <= 1e-12 * r0.max(1.0) { 0.0 } else { drift };
    Ok(Segment::Arc(Arc { start: *start, end, center: c, normal: n, radius: r0, radius_change, sweep, rise }))
}

fn normal_of(normal: [f64; 3]) -> Result<[f64; 3], GroupError> {
    finite(&[normal])?;
    if norm3(normal) < 1e-12 {
        return Err(GroupError::CmdCircInvalidParam);
    }
    Ok(unit3(normal))
}

fn finite(points: &[[f64; 3]]) -> Result<(), GroupError> {
    match points.iter().flatten().all(|v| v.is_finite()) {
        true => Ok(()),
        false => Err(GroupError::CmdCircInvalidParam),
    }
}

/// `start` moved to the point `p`, A, B, C kept.
fn with_point(start: &Pose, p: [f64; 3]) -> Pose {
    [p[0], p[1], p[2], start[3], start[4], start[5]]
}

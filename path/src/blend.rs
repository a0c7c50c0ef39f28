//! Corner transitions between two queued segments (HMPL 8.1.5, parameters 8.3.26): the
//! corner is cut by a blend curve that leaves the first segment a trim distance d before
//! the corner and joins the second d after it, tangent to both (see [`Blend`]).
//!
//! - TM_CONST_VEL and TM_CORNER_DIST (identical, HMPL 8.1.5 note 3): d = trans_dis.
//!   (trans_vel, the speed on the blend, is the planner's.)
//! - TM_MAX_CORNER_DEV: the largest d ≤ trans_dis whose blend passes the corner within
//!   trans_dev.
//! - TM_MAX_CORNER_CURV: the smallest d whose blend bends no more than trans_curv.
//!
//! Where d reaches the length of either segment the junction is not blended (HMPL 8.1.5
//! note 1), nor where there is no corner (the directions agree) or a near reversal.

use api::GroupError;

use crate::segment::{Blend, Segment, add3, cross3, diff3, dot3, norm3, scale3, xyz};

/// TM_NONE 0, TM_CONST_VEL 1, TM_CORNER_DIST 2, TM_MAX_CORNER_DEV 3, TM_MAX_CORNER_CURV 4
/// (HMPL table 8.1.5.1, "0 ~ 4"; TM_START_VEL is not available).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TransitionMode {
    /// TM_NONE: no blend; the junction is what the buffer mode makes of it.
    #[default]
    None,
    /// TM_CONST_VEL: trim trans_dis, and the blend is run at trans_vel.
    ConstVel,
    /// TM_CORNER_DIST: trim trans_dis; the same corner as TM_CONST_VEL (HMPL 8.1.5 note 3).
    CornerDist,
    /// TM_MAX_CORNER_DEV: the longest trim up to trans_dis whose blend passes the corner
    /// within trans_dev.
    MaxCornerDev,
    /// TM_MAX_CORNER_CURV: the shortest trim whose blend bends no more than trans_curv.
    MaxCornerCurv,
}

impl TryFrom<i64> for TransitionMode {
    type Error = GroupError;

    fn try_from(value: i64) -> Result<Self, GroupError> {
        Ok(match value {
            0 => TransitionMode::None,
            1 => TransitionMode::ConstVel,
            2 => TransitionMode::CornerDist,
            3 => TransitionMode::MaxCornerDev,
            4 => TransitionMode::MaxCornerCurv,
            _ => return Err(GroupError::CmdTransModeUnknown),
        })
    }
}

impl From<TransitionMode> for i64 {
    fn from(mode: TransitionMode) -> i64 {
        mode as i64
    }
}

/// {trans_vel mm/s, trans_dis mm, trans_dev mm, trans_curv 1/mm} (HMPL 8.3.26, 8.5).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TransitionParams {
    /// The path velocity on the blend with TM_CONST_VEL and TM_CORNER_DIST, mm/s, in (0, 5000).
    pub trans_vel: f64,
    /// The trim distance d from the corner, mm (> 0): the longest with TM_MAX_CORNER_DEV.
    pub trans_dis: f64,
    /// The largest distance of the blend from the corner with TM_MAX_CORNER_DEV, mm; 0 unused.
    pub trans_dev: f64,
    /// The largest curvature of the blend with TM_MAX_CORNER_CURV, 1/mm; 0 unused.
    pub trans_curv: f64,
}

/// trans_vel < 5000 mm/s (HMPL table 8.3.26.1).
const MAX_TRANS_VEL: f64 = 5000.0;
/// trans_curv < 1e7 1/mm (HMPL table 8.3.26.1).
const MAX_TRANS_CURV: f64 = 1e7;

/// A junction turning less than this has no corner, rad.
pub const MIN_TURN: f64 = 1e-9;

impl TransitionParams {
    /// The ranges of HMPL table 8.3.26.1 that hold whatever the segments (SetGrpTransPrm):
    /// trans_vel in (0, 5000) else `CmdInvalidTransVel`, trans_dis > 0 else
    /// `CmdInvalidTransDis`; trans_dev ≥ 0 and trans_curv in [0, 1e7), 0 meaning unused as
    /// in the manual's SetGrpTransPrm(gid, 50, 20, 0, 0) (HMPL 8.1.6 example 3-2).
    pub fn validate(&self) -> Result<(), GroupError> {
        if !(self.trans_vel > 0.0 && self.trans_vel < MAX_TRANS_VEL) {
            return Err(GroupError::CmdInvalidTransVel);
        }
        if !(self.trans_dis > 0.0 && self.trans_dis.is_finite()) {
            return Err(GroupError::CmdInvalidTransDis);
        }
        if !(self.trans_dev >= 0.0 && self.trans_dev.is_finite()) {
            return Err(GroupError::CmdInvalidTransDev);
        }
        if !(self.trans_curv >= 0.0 && self.trans_curv < MAX_TRANS_CURV) {
            return Err(GroupError::CmdInvalidTransCurve);
        }
        Ok(())
    }

    /// The parameters a mode uses, before a command with it is queued: nothing for
    /// TM_NONE (the examples pass zeros, HMPL 8.1.6 example 2); else [`Self::validate`],
    /// and trans_dev > 0 for TM_MAX_CORNER_DEV, trans_curv > 0 for TM_MAX_CORNER_CURV.
    pub fn validate_for(&self, mode: TransitionMode) -> Result<(), GroupError> {
        match mode {
            TransitionMode::None => return Ok(()),
            TransitionMode::MaxCornerDev if self.trans_dev <= 0.0 => return Err(GroupError::CmdInvalidTransDev),
            TransitionMode::MaxCornerCurv if self.trans_curv <= 0.0 => return Err(GroupError::CmdInvalidTransCurve),
            _ => {}
        }
        self.validate()
    }
}

/// The corner between `prev` and `next` blended: (`prev` trimmed, the blend, `next`
/// trimmed), the blend tangent to both at its ends. `None` where the junction is not
/// blended: TM_NONE, no corner, a turn over [`Blend::MAX_TURN_DEG`], a segment that is itself a
/// blend or only rotates, segments that do not meet, or a trim that reaches the length of
/// either segment.
pub fn corner(
    prev: &Segment,
    next: &Segment,
    mode: TransitionMode,
    params: &TransitionParams,
) -> Option<(Segment, Segment, Segment)> {
    if mode == TransitionMode::None || matches!(prev, Segment::Blend(_)) || matches!(next, Segment::Blend(_)) {
        return None;
    }
    let joint = xyz(&prev.end());
    if norm3(diff3(joint, xyz(&next.start()))) > 1e-9 {
        return None;
    }
    let (t1, t2) = (prev.direction_at(1.0), next.direction_at(0.0));
    let turn = dot3(t1, t2).clamp(-1.0, 1.0).acos();
    if norm3(t1) == 0.0 || norm3(t2) == 0.0 || turn < MIN_TURN || turn > Blend::MAX_TURN_DEG.to_radians() {
        return None;
    }
    let len_min = prev.length().min(next.length());
    // The first trim is exact between two lines (the quadratic Bézier: deviation
    // ½·d·sin(turn/2), peak curvature 4·sin(turn) / (d·(2 + 2·cos(turn))^1.5) at its middle);
    // next to an arc the measured value corrects it.
    let (mut d, limit, measure): (f64, f64, Measure) = match mode {
        TransitionMode::None => return None,
        TransitionMode::ConstVel | TransitionMode::CornerDist => (params.trans_dis, f64::INFINITY, |_, _| 0.0),
        TransitionMode::MaxCornerDev => {
            (params.trans_dis.min(2.0 * params.trans_dev / (turn / 2.0).sin()), params.trans_dev, deviation)
        }
        TransitionMode::MaxCornerCurv => {
            let d = 4.0 * turn.sin() / (params.trans_curv * (2.0 + 2.0 * turn.cos()).powf(1.5));
            (d, params.trans_curv, |b, _| max_curvature(b))
        }
    };
    for _ in 0..32 {
        if !(d > 0.0 && d < len_min) {
            return None;
        }
        let (a, blend, b) = build(prev, next, d);
        let value = measure(&blend, joint);
        if value <= limit * (1.0 + 1e-9) {
            return Some((a, Segment::Blend(blend), b));
        }
        // Both measures go with d (deviation) or against it (curvature) about linearly.
        d *= match mode {
            TransitionMode::MaxCornerDev => limit / value * (1.0 - 1e-9),
            _ => value / limit * (1.0 + 1e-9),
        };
    }
    None
}

/// What a mode bounds, of a blend and the corner it cuts.
type Measure = fn(&Blend, [f64; 3]) -> f64;

/// The blend for trim `d`: control points d·⅔ along the tangents from both ends, which
/// between two lines is the quadratic Bézier with the corner as control point.
fn build(prev: &Segment, next: &Segment, d: f64) -> (Segment, Blend, Segment) {
    let a = prev.sub(0.0, 1.0 - d / prev.length());
    let b = next.sub(d / next.length(), 1.0);
    let (p0, p3) = (a.end(), b.start());
    let inner = [
        add3(xyz(&p0), scale3(a.direction_at(1.0), 2.0 / 3.0 * d)),
        diff3(xyz(&p3), scale3(b.direction_at(0.0), 2.0 / 3.0 * d)),
    ];
    (a, Blend::new(p0, p3, inner), b)
}

/// Sample count of the measures, refined by golden-section search around the best sample.
const SAMPLES: usize = 64;

/// The distance from `corner` to the nearest point of the blend.
fn deviation(blend: &Blend, corner: [f64; 3]) -> f64 {
    extremum(|t| -norm3(diff3(blend.point(t), corner))).abs()
}

/// The largest curvature of the blend, 1/mm.
pub(crate) fn max_curvature(blend: &Blend) -> f64 {
    extremum(|t| {
        let (d1, d2) = blend.derivatives(t);
        norm3(cross3(d1, d2)) / norm3(d1).powi(3)
    })
}

/// The maximum of `f` on [0, 1]: the best of `SAMPLES` + 1 samples, refined.
fn extremum(f: impl Fn(f64) -> f64) -> f64 {
    let step = 1.0 / SAMPLES as f64;
    let best = (0..=SAMPLES).map(|i| i as f64 * step).max_by(|&a, &b| f(a).total_cmp(&f(b))).unwrap_or(0.0);
    let (mut lo, mut hi) = ((best - step).max(0.0), (best + step).min(1.0));
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..60 {
        let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if f(x1) < f(x2) { lo = x1 } else { hi = x2 }
    }
    f(best).max(f((lo + hi) / 2.0))
}

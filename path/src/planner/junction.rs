//! What one segment may do and how fast two segments may join: the feed rule of HMPL 8.1,
//! the machine's limits per MCS coordinate, the buffer modes of table 8.1.4.1 and the
//! look-ahead speeds of table 8.1.4.2.
//!
//! Velocities here are along the path parameter `s`: mm of translation, or deg of rotation
//! for a segment that only rotates. `g` is the pose's rate along `s` (dPose/ds): the unit
//! direction for X, Y, Z and the rotation per mm for A, B, C.

use super::{BufferMode, Limits, LookAhead, Motion, Profile};
use crate::segment::Segment;

/// Below this a length or a rate of change counts as zero.
pub(crate) const EPS: f64 = 1e-12;

/// A queued segment with what the planner derived from it once, at push.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Entry {
    pub segment: Segment,
    pub motion: Motion,
    pub limits: Limits,
    /// Length of the whole segment along `s`.
    pub full: f64,
    /// Where along `s` it ends: `full`, or less after a stop cut it short.
    pub end: f64,
    /// Feed (HMPL 8.1), within the machine's limits, along `s`.
    pub vel: f64,
    pub acc: f64,
    pub dec: f64,
    /// The machine's speed limit on this segment (max_vel per coordinate, curvature): no
    /// junction rule may exceed it.
    pub vcap: f64,
    pub g_start: [f64; 6],
    pub g_end: [f64; 6],
    /// Per coordinate, the most acceleration the profile alone can cause on this segment.
    pub cont_acc: [f64; 6],
    /// Per coordinate, the largest |g| over the segment.
    g_max: [f64; 6],
    /// The radius of curvature where smallest, on an arc or a blend.
    radius: Option<f64>,
    /// The speed cap from the segment's own geometry and the machine's limits.
    own_vcap: f64,
    /// The highest velocity that may enter this segment (its entry junction's bound).
    pub v_in: f64,
    /// The junction to the next segment: its bound from the rules (unscaled), and the
    /// velocity planned there after the backward pass.
    pub exit_cap: f64,
    pub exit_plan: f64,
    /// It ends at rest and holds for the smooth time (BM_BUFF, BM_ABORT, a stop).
    pub stop_after: bool,
    /// The group's smooth time Ts for this segment (the longer of the two profiles'), s.
    pub smooth: f64,
}

/// Rest-to-rest time of a trapezoid over `d`.
fn move_time(d: f64, p: &Profile) -> f64 {
    if d <= EPS {
        return 0.0;
    }
    if p.vel <= 0.0 {
        return f64::INFINITY;
    }
    let ramps = p.vel * p.vel / (2.0 * p.acc) + p.vel * p.vel / (2.0 * p.dec);
    if ramps <= d {
        d / p.vel + p.vel / (2.0 * p.acc) + p.vel / (2.0 * p.dec)
    } else {
        let vp = (2.0 * d * p.acc * p.dec / (p.acc + p.dec)).sqrt();
        vp / p.acc + vp / p.dec
    }
}

/// The radius of curvature where smallest: an arc's or helix's at an end (one radius, or
/// one drifting linearly); a corner blend's from a search along it, since next to an arc
/// its tightest point lies anywhere, not in its middle (path/tests/planner_constraints.rs).
fn min_radius(segment: &Segment) -> Option<f64> {
    match segment {
        Segment::Line(_) => None,
        Segment::Arc(_) => [0.0, 1.0].iter().filter_map(|&u| segment.radius_at(u)).reduce(f64::min),
        Segment::Blend(b) => Some(1.0 / crate::blend::max_curvature(b)).filter(|r| r.is_finite()),
    }
}

impl Entry {
    pub(crate) fn new(segment: Segment, motion: Motion, limits: &Limits, look_ahead: &LookAhead, period: f64) -> Entry {
        let (len, ang) = (segment.length(), segment.angular_length());
        let (s0, s1) = (segment.start(), segment.end());
        // HMPL 8.1: each part's move time with its own profile; the longer one sets the feed,
        // the other follows in proportion. `s` runs along the translation unless there is none.
        let (full, profile) = if len > EPS {
            let lin_time = move_time(len, &motion.lin);
            if ang > EPS && move_time(ang, &motion.ang) > lin_time {
                let k = len / ang;
                (
                    len,
                    Profile { vel: motion.ang.vel * k, acc: motion.ang.acc * k, dec: motion.ang.dec * k, ..motion.ang },
                )
            } else {
                (len, motion.lin)
            }
        } else {
            (ang, motion.ang)
        };
        let g_at = |u: f64| -> [f64; 6] {
            let d = segment.direction_at(u);
            let t = if full > EPS { len / full } else { 0.0 };
            std::array::from_fn(|i| {
                if i < 3 {
                    d[i] * t
                } else if full > EPS {
                    (s1[i] - s0[i]) / full
                } else {
                    0.0
                }
            })
        };
        let (g_start, g_end, g_mid) = (g_at(0.0), g_at(1.0), g_at(0.5));
        let radius = min_radius(&segment);
        // The largest |g| per coordinate over the segment: on a curve a moving coordinate's
        // direction may turn fully onto it, so 1.
        let g_max: [f64; 6] = std::array::from_fn(|i| {
            let m = g_start[i].abs().max(g_end[i].abs()).max(g_mid[i].abs());
            if i < 3 && radius.is_some() && m > EPS { 1.0 } else { m }
        });
        let (mut vel, mut acc, mut dec) = (profile.vel, profile.acc, profile.dec);
        let mut vcap = f64::INFINITY;
        for (i, &g) in g_max.iter().enumerate() {
            if g <= EPS {
                continue;
            }
            vcap = vcap.min(limits.max_vel[i] / g);
            // On a curve half of a coordinate's acceleration is left to the centripetal part.
            let share = if i < 3 && radius.is_some() { 0.5 } else { 1.0 };
            acc = acc.min(limits.max_acc[i] * share / g);
            dec = dec.min(limits.max_acc[i] * share / g);
            if let (true, Some(r)) = (i < 3, radius) {
                vcap = vcap.min((limits.max_acc[i] * 0.5 * r).sqrt());
            }
        }
        if motion.buffer == BufferMode::LookAhead
            && let Some(r) = radius
        {
            vel = vel.min(arc_speed(look_ahead, r, period));
        }
        vel = vel.min(vcap);
        let mut entry = Entry {
            segment,
            motion,
            limits: *limits,
            full,
            end: full,
            vel,
            acc,
            dec,
            vcap,
            g_start,
            g_end,
            cont_acc: [0.0; 6],
            g_max,
            radius,
            own_vcap: vcap,
            v_in: 0.0,
            exit_cap: 0.0,
            exit_plan: 0.0,
            stop_after: matches!(motion.buffer, BufferMode::Buff | BufferMode::Abort),
            smooth: motion.lin.smooth_ms.max(motion.ang.smooth_ms) / 1000.0,
        };
        entry.count_acc();
        entry
    }

    fn count_acc(&mut self) {
        self.cont_acc = std::array::from_fn(|i| {
            let centripetal = match self.radius {
                Some(r) if i < 3 && self.g_max[i] > EPS => self.vcap * self.vcap / r,
                _ => 0.0,
            };
            self.acc.max(self.dec) * self.g_max[i] + centripetal
        });
    }

    /// An arc or a corner blend: its speed limit comes from its curvature.
    pub(crate) fn is_curved(&self) -> bool {
        self.radius.is_some()
    }

    /// Whether `next` joins this segment with a step in the pose's rate (a corner).
    pub(crate) fn turns_into(&self, next: &Entry) -> bool {
        (0..6).any(|i| (next.g_start[i] - self.g_end[i]).abs() > EPS)
    }

    /// This curve with its speed cap lowered for a corner within `reach` of it along the
    /// path: the smoothing averages a corner per coordinate with the tangents the legs have
    /// at the corner (`crate::smoothing`), which on a curve turn by up to reach / radius
    /// within the window (and a unit tangent changes by 2 at most), so the speed leaves that
    /// much room.
    pub(crate) fn near_corner(&self, reach: f64) -> Entry {
        let mut curve = *self;
        if let Some(r) = self.radius {
            curve.vcap = curve.vcap.min(self.own_vcap / (1.0 + (reach / r).min(2.0)));
            curve.vel = curve.vel.min(curve.vcap);
        }
        curve
    }

    /// The group's smoothing averages the path speed over its window along the path
    /// (`crate::smoothing`), so a segment within one window of a curve moves within the
    /// curve's limits: its speed cap and its acceleration, which leave room for the
    /// centripetal part. Segments that only rotate have no curve to keep.
    pub(crate) fn keep_within(&mut self, curve: &Entry) {
        if self.segment.length() <= EPS {
            return;
        }
        self.vcap = self.vcap.min(curve.vcap);
        self.vel = self.vel.min(self.vcap);
        self.acc = self.acc.min(curve.acc);
        self.dec = self.dec.min(curve.dec);
        self.count_acc();
    }

    /// How fast the translation (mm) and the rotation (deg) run per unit of `s`.
    fn rates(&self) -> [f64; 2] {
        let norm = |r: std::ops::Range<usize>| r.map(|i| self.g_start[i] * self.g_start[i]).sum::<f64>().sqrt();
        [norm(0..3), norm(3..6)]
    }
}

/// Look-ahead's bound on a curve of radius `r`: HMPL table 8.1.4.2 (c) the arc velocity
/// sqrt(A_arc r) and (d) the chord-error velocity 2 r acos(1 - e/r) / cycle.
pub(crate) fn arc_speed(look_ahead: &LookAhead, r: f64, period: f64) -> f64 {
    let arc = (look_ahead.arc_acc * r).sqrt();
    let e = look_ahead.chord_error;
    if e > 0.0 && e < r { arc.min(2.0 * r * (1.0 - e / r).acos() / period) } else { arc }
}

/// The velocity bound at the junction of `prev` into `next`. `prev`'s buffer mode governs
/// (HMPL 8.1.6 example 2: the junction speed is planned "at the end position of each path").
pub(crate) fn junction_cap(prev: &Entry, next: &Entry, look_ahead: &LookAhead, period: f64) -> f64 {
    let by_mode = match prev.motion.buffer {
        BufferMode::Buff | BufferMode::Abort => return 0.0,
        BufferMode::Low | BufferMode::LookAhead => prev.vel.min(next.vel),
        BufferMode::Prev => prev.vel,
        BufferMode::Next => next.vel,
        BufferMode::High => prev.vel.max(next.vel),
    };
    let mut cap = by_mode.min(prev.vcap).min(next.vcap);
    // The feed a mode carries over is one segment's; on the other the same velocity along
    // `s` may translate or rotate faster (another ratio of rotation to translation, or `s`
    // in deg against mm). Neither part may run faster than the faster of the two feeds in
    // that part, on either side of the junction.
    let (rates_prev, rates_next) = (prev.rates(), next.rates());
    for part in 0..2 {
        let fastest = (prev.vel * rates_prev[part]).max(next.vel * rates_next[part]);
        for rate in [rates_prev[part], rates_next[part]] {
            if rate > EPS {
                cap = cap.min(fastest / rate);
            }
        }
    }
    if cap <= 0.0 {
        return 0.0;
    }
    // The group's moving average spreads a corner's velocity step over Ts (at least a cycle).
    let window = prev.smooth.max(next.smooth).max(period);
    let dg: [f64; 6] = std::array::from_fn(|i| (next.g_start[i] - prev.g_end[i]).abs());
    // Per coordinate, within max_acc after smoothing: the steps of the corners inside any
    // window of Ts plus what the profile accelerates there must stay within max_acc * Ts.
    // Each corner gets at most half the shorter neighbour's time (and half of Ts), so the
    // corners inside one window never add up to more than Ts; `fastest` bounds the speed
    // on each neighbour, hence its time from below.
    let fastest_prev = prev.vel.max(prev.v_in).max(by_mode);
    let fastest_next = next.vel.max((by_mode * by_mode + 2.0 * next.acc * next.full).sqrt());
    let spread = window.min(prev.full / fastest_prev).min(next.full / fastest_next) / 2.0;
    for (i, &d) in dg.iter().enumerate() {
        let max_acc = prev.limits.max_acc[i].min(next.limits.max_acc[i]);
        if d > EPS && max_acc.is_finite() {
            let room = (max_acc - prev.cont_acc[i].max(next.cont_acc[i])).max(0.0) * spread;
            cap = cap.min(room / d);
        }
    }
    // And within the path's own acceleration (docs/decisions.md), for the translation
    // and the rotation; look-ahead also within its corner acceleration (table 8.1.4.2 (b)).
    let norm = |r: std::ops::Range<usize>| r.map(|i| dg[i] * dg[i]).sum::<f64>().sqrt();
    let (dt, dr) = (norm(0..3), norm(3..6));
    let mut lin_acc = prev.motion.lin.acc.min(next.motion.lin.acc);
    if prev.motion.buffer == BufferMode::LookAhead {
        lin_acc = lin_acc.min(look_ahead.corner_acc);
    }
    if dt > EPS {
        cap = cap.min(lin_acc * window / dt);
    }
    if dr > EPS {
        cap = cap.min(prev.motion.ang.acc.min(next.motion.ang.acc) * window / dr);
    }
    cap.max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_ahead_caps_curves_by_arc_acceleration_and_chord_error() {
        // HMPL 8.1.4 defaults: A_arc 100 mm/s^2, chord error off: r = 25 mm -> 50 mm/s.
        let la = LookAhead::default();
        assert!((arc_speed(&la, 25.0, 0.001) - 50.0).abs() < 1e-12);
        assert!((arc_speed(&la, 100.0, 0.001) - 100.0).abs() < 1e-12);
        // Chord error 0.001 mm on r = 10 000 mm at 1 ms: 2 r acos(1 - e/r) / dT = 8944 mm/s
        // (below the arc velocity 10 000 mm/s).
        let la = LookAhead { arc_acc: 10_000.0, chord_error: 0.001, ..la };
        let expected = 2.0 * 10_000.0 * (1.0 - 0.001f64 / 10_000.0).acos() / 0.001;
        assert!((arc_speed(&la, 10_000.0, 0.001) - expected).abs() < 1e-9 && expected < 10_000.0);
        // A chord error at or above the radius leaves the arc velocity.
        let la = LookAhead { chord_error: 20.0, ..LookAhead::default() };
        assert_eq!(arc_speed(&la, 4.0, 0.001), 20.0);
    }

    #[test]
    fn the_longer_move_time_sets_the_feed() {
        // HMPL 8.1: 10 mm with 180 deg; the rotation (0.7 s at 360 deg/s, 1800 deg/s^2) takes
        // longer than the translation (0.12 s), so it sets the feed: 360 deg/s is 20 mm/s.
        let lin = Profile { vel: 100.0, acc: 5000.0, dec: 5000.0, smooth_ms: 0.0 };
        let ang = Profile { vel: 360.0, acc: 1800.0, dec: 1800.0, smooth_ms: 0.0 };
        let seg = Segment::Line(crate::segment::Line { start: [0.0; 6], end: [10.0, 0.0, 0.0, 0.0, 0.0, 180.0] });
        let e =
            Entry::new(seg, Motion { lin, ang, buffer: BufferMode::Buff }, &Limits::NONE, &LookAhead::default(), 0.001);
        assert!((e.vel - 20.0).abs() < 1e-12 && (e.acc - 100.0).abs() < 1e-12 && e.full == 10.0);
        assert!((move_time(10.0, &lin) - 0.12).abs() < 1e-12 && (move_time(180.0, &ang) - 0.7).abs() < 1e-12);
    }
}

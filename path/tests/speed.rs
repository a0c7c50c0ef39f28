//! Property: every segment moves at uniform speed in `u` (|d xyz/du| = length, A, B, C
//! linear), so the planner's path position maps onto the path without distortion.

use path::Pose;
use path::blend::{TransitionMode, TransitionParams, corner};
use path::commands::*;
use path::segment::Segment;

/// xorshift64*: deterministic, no dependency.
struct Rng(u64);

impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    fn point(&mut self, scale: f64) -> [f64; 3] {
        [self.range(-scale, scale), self.range(-scale, scale), self.range(-scale, scale)]
    }

    fn pose(&mut self) -> Pose {
        let p = self.point(200.0);
        [p[0], p[1], p[2], self.range(-90.0, 90.0), self.range(-90.0, 90.0), self.range(-180.0, 180.0)]
    }
}

/// The largest relative deviation of |d xyz/du| from the length, and of the A, B, C rate.
fn speed_error(s: &Segment) -> f64 {
    let (len, h) = (s.length(), 1e-5);
    let (start, end) = (s.start(), s.end());
    let mut worst = 0.0f64;
    for k in 1..200 {
        let u = k as f64 / 200.0;
        // Central differences with Richardson's extrapolation (error O(h⁴)).
        let diff = |h: f64| {
            let (a, b) = (s.pose_at(u - h), s.pose_at(u + h));
            std::array::from_fn::<f64, 6, _>(|i| (b[i] - a[i]) / (2.0 * h))
        };
        let (d1, d2) = (diff(h), diff(h / 2.0));
        let d: [f64; 6] = std::array::from_fn(|i| (4.0 * d2[i] - d1[i]) / 3.0);
        let v = ((0..3).map(|i| d[i] * d[i]).sum::<f64>()).sqrt();
        worst = worst.max((v - len).abs() / len);
        for i in 3..6 {
            let rate = d[i];
            assert!(
                (rate - (end[i] - start[i])).abs() < 1e-6 * (1.0 + (end[i] - start[i]).abs()),
                "A, B, C move linearly"
            );
        }
    }
    worst
}

#[test]
fn every_variant_moves_at_uniform_speed() {
    let mut rng = Rng(0x0123_4567_89ab_cdef);
    let mut worst = [0.0f64; 4];
    let mut blends = 0;
    for _ in 0..300 {
        let start = rng.pose();
        let line = line_abs(&start, &rng.pose()).unwrap();
        worst[0] = worst[0].max(speed_error(&line));

        // An arc or helix about a random axis turning by a random angle, sometimes ending
        // off the circle within the tolerance, sometimes rising along the axis.
        let angle = rng.range(-700.0, 700.0);
        let Ok(Segment::Arc(a)) = arc_angle_2d(&start, rng.point(100.0), rng.point(1.0), angle) else { continue };
        let mut end = a.end;
        let drift = if rng.unit() < 0.5 { 0.0 } else { rng.range(-1.0, 1.0) * radius_tolerance(a.radius) * 0.99 };
        let radial: [f64; 3] = std::array::from_fn(|i| end[i] - a.center[i]);
        let r = (radial.iter().map(|x| x * x).sum::<f64>()).sqrt();
        let rise = if rng.unit() < 0.3 { 0.0 } else { rng.range(-100.0, 100.0) };
        for i in 0..3 {
            end[i] += radial[i] / r * drift + a.normal[i] * rise;
        }
        end[5] += 45.0;
        let turns = if angle > 0.0 { 1 + (angle / 360.0) as i64 } else { -1 + (angle / 360.0) as i64 };
        let helix = circle_abs(&start, a.center, a.normal, turns, &end).unwrap();
        let e = speed_error(&helix);
        let kind = if drift != 0.0 { 2 } else { 1 };
        worst[kind] = worst[kind].max(e);
        let p = helix.pose_at(1.0 - f64::EPSILON);
        assert!((0..3).all(|i| (p[i] - end[i]).abs() < 1e-9), "the formula meets the end: {p:?} {end:?}");

        // A blend between the line and the arc, in any mode.
        let next = arc_angle_2d(&line.end(), rng.point(100.0), rng.point(1.0), rng.range(-300.0, 300.0));
        let Ok(next) = next else { continue };
        let params = TransitionParams {
            trans_vel: 100.0,
            trans_dis: rng.range(0.1, 80.0),
            trans_dev: rng.range(0.01, 5.0),
            trans_curv: rng.range(0.01, 1.0),
        };
        let mode =
            [TransitionMode::CornerDist, TransitionMode::MaxCornerDev, TransitionMode::MaxCornerCurv][blends % 3];
        if let Some((_, blend, _)) = corner(&line, &next, mode, &params) {
            worst[3] = worst[3].max(speed_error(&blend));
            blends += 1;
        }
    }
    println!(
        "worst relative speed error: line {:.1e}, arc/helix {:.1e}, drifting arc {:.1e}, blend {:.1e} ({blends} blends)",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(blends > 50, "{blends}");
    assert!(worst.iter().all(|&w| w < 1e-6), "{worst:?}");
}

#[test]
fn sharpest_blended_corner_keeps_uniform_speed() {
    // The worst case of the blend's arc length: the largest turn still blended.
    let turn = path::segment::Blend::MAX_TURN_DEG.to_radians() - 1e-9;
    let prev = line_abs_2d(&[0.0; 6], [100.0, 0.0, 0.0]).unwrap();
    let next = line_rel_2d(&prev.end(), [100.0 * turn.cos(), 100.0 * turn.sin(), 0.0]).unwrap();
    let params = TransitionParams { trans_vel: 100.0, trans_dis: 50.0, trans_dev: 0.0, trans_curv: 0.0 };
    let (_, blend, _) = corner(&prev, &next, TransitionMode::CornerDist, &params).expect("blended");
    let e = speed_error(&blend);
    println!("relative speed error at a {:.0}° turn: {e:.1e}", turn.to_degrees());
    assert!(e < 1e-6, "{e}");
}

//! Corner transitions (HMPL 8.1.5, 8.3.26, example 3 of 8.1.6).

use std::f64::consts::SQRT_2;

use api::GroupError;
use path::Pose;
use path::blend::*;
use path::commands::*;
use path::segment::Segment;

const Z: [f64; 3] = [0.0, 0.0, 1.0];

fn at(x: f64, y: f64, z: f64) -> Pose {
    [x, y, z, 0.0, 0.0, 0.0]
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

fn dist(a: &Pose, b: &Pose) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn params(trans_dis: f64, trans_dev: f64, trans_curv: f64) -> TransitionParams {
    TransitionParams { trans_vel: 50.0, trans_dis, trans_dev, trans_curv }
}

/// The three pieces join in position and direction (G1), and the blend's pieces are the
/// original segments trimmed by `d` of arc length.
fn assert_g1(prev: &Segment, next: &Segment, (a, b, c): &(Segment, Segment, Segment), d: f64) {
    assert_eq!(a.start(), prev.start());
    assert_eq!(c.end(), next.end());
    assert!((prev.length() - a.length() - d).abs() < 1e-9, "prev trimmed by {}", prev.length() - a.length());
    assert!((next.length() - c.length() - d).abs() < 1e-9, "next trimmed by {}", next.length() - c.length());
    assert_eq!(a.end(), b.start());
    assert_eq!(b.end(), c.start());
    assert!(
        close(&a.direction_at(1.0), &b.direction_at(0.0), 1e-9),
        "{:?} {:?}",
        a.direction_at(1.0),
        b.direction_at(0.0)
    );
    assert!(
        close(&b.direction_at(1.0), &c.direction_at(0.0), 1e-9),
        "{:?} {:?}",
        b.direction_at(1.0),
        c.direction_at(0.0)
    );
    // direction_at is continuous along the blend: no step larger than the curvature allows.
    let n = 2000;
    let r_min = (0..=n).filter_map(|k| b.radius_at(k as f64 / n as f64)).fold(f64::INFINITY, f64::min);
    let step = b.length() / n as f64;
    for k in 0..n {
        let (d0, d1) = (b.direction_at(k as f64 / n as f64), b.direction_at((k + 1) as f64 / n as f64));
        let turn = (d0[0] * d1[0] + d0[1] * d1[1] + d0[2] * d1[2]).clamp(-1.0, 1.0).acos();
        assert!(turn <= step / r_min * 1.01 + 1e-12, "direction jumps by {turn} at {k}");
    }
}

#[test]
fn corner_dist_on_a_square() {
    // HMPL 8.1.6 example 3-2: trans_dis 20 on a 100 × 100 square: the path leaves each line
    // 20 mm before the corner and joins the next 20 mm after it.
    let corners = [at(0.0, 0.0, 0.0), at(100.0, 0.0, 0.0), at(100.0, 100.0, 0.0), at(0.0, 100.0, 0.0)];
    for mode in [TransitionMode::CornerDist, TransitionMode::ConstVel] {
        for i in 0..4 {
            let (p0, p1, p2) = (corners[i], corners[(i + 1) % 4], corners[(i + 2) % 4]);
            let prev = line_abs_2d(&p0, [p1[0], p1[1], 0.0]).unwrap();
            let next = line_abs_2d(&p1, [p2[0], p2[1], 0.0]).unwrap();
            let pieces = corner(&prev, &next, mode, &params(20.0, 0.0, 0.0)).expect("blended");
            assert_g1(&prev, &next, &pieces, 20.0);
            let (a, b, c) = pieces;
            assert!((dist(&a.end(), &p1) - 20.0).abs() < 1e-12 && (dist(&c.start(), &p1) - 20.0).abs() < 1e-12);
            assert!(close(&b.direction_at(0.0), &prev.direction_at(1.0), 1e-12));
            assert!(close(&b.direction_at(1.0), &next.direction_at(0.0), 1e-12));
            // The quadratic Bézier's deviation: ½·d·cos(β/2) for the corner angle β = 90°.
            assert!((dist(&b.pose_at(0.5), &p1) - 10.0 * 0.5f64.sqrt()).abs() < 1e-9);
            // Peak curvature 4·sin θ / (d·(2 + 2·cos θ)^1.5) at the middle.
            assert!((b.radius_at(0.5).unwrap() - 20.0 * 2f64.powf(1.5) / 4.0).abs() < 1e-9);
        }
    }
}

#[test]
fn junctions_that_are_not_blended() {
    let a = line_abs_2d(&at(0.0, 0.0, 0.0), [50.0, 0.0, 0.0]).unwrap();
    let b = line_abs_2d(&at(50.0, 0.0, 0.0), [50.0, 100.0, 0.0]).unwrap();
    let p = params(20.0, 0.0, 0.0);
    assert!(corner(&a, &b, TransitionMode::CornerDist, &p).is_some());
    // The trim reaches the length of a segment (HMPL 8.1.5 note 1).
    assert!(corner(&a, &b, TransitionMode::CornerDist, &params(50.0, 0.0, 0.0)).is_none());
    assert!(corner(&b, &line_abs_2d(&b.end(), [60.0, 100.0, 0.0]).unwrap(), TransitionMode::CornerDist, &p).is_none());
    assert!(corner(&a, &b, TransitionMode::None, &p).is_none());
    // No corner: collinear, or into a tangent arc; a reversal; segments that do not meet.
    let straight = line_abs_2d(&a.end(), [150.0, 0.0, 0.0]).unwrap();
    assert!(corner(&a, &straight, TransitionMode::CornerDist, &p).is_none());
    let tangent = arc_angle_2d(&a.end(), [50.0, 50.0, 0.0], Z, 90.0).unwrap();
    assert!(corner(&a, &tangent, TransitionMode::CornerDist, &p).is_none());
    let back = line_abs_2d(&a.end(), [0.0, 1.0, 0.0]).unwrap();
    assert!(corner(&a, &back, TransitionMode::CornerDist, &p).is_none());
    let apart = line_abs_2d(&at(50.0, 1.0, 0.0), [50.0, 100.0, 0.0]).unwrap();
    assert!(corner(&a, &apart, TransitionMode::CornerDist, &p).is_none());
    // A zero-length line (the manual's first LineAbs2D) has no direction.
    let zero = line_abs_2d(&at(0.0, 0.0, 0.0), [0.0, 0.0, 0.0]).unwrap();
    assert!(corner(&zero, &a, TransitionMode::CornerDist, &p).is_none());
    // A blend is not blended again.
    let (_, blend, _) = corner(&a, &b, TransitionMode::CornerDist, &p).unwrap();
    assert!(corner(&blend, &b, TransitionMode::CornerDist, &p).is_none());
}

#[test]
fn max_corner_deviation() {
    // The trim shrinks until the blend passes the corner within trans_dev.
    for (turn_deg, dev) in [(90.0f64, 2.0), (30.0, 0.5), (150.0, 3.0)] {
        let t = turn_deg.to_radians();
        let prev = line_abs_2d(&at(0.0, 0.0, 0.0), [100.0, 0.0, 0.0]).unwrap();
        let next = line_rel_2d(&prev.end(), [100.0 * t.cos(), 100.0 * t.sin(), 0.0]).unwrap();
        let pieces = corner(&prev, &next, TransitionMode::MaxCornerDev, &params(40.0, dev, 0.0)).expect("blended");
        let d = 2.0 * dev / (t / 2.0).sin();
        assert_g1(&prev, &next, &pieces, d.min(40.0));
        let deviation =
            (0..=10000).map(|k| dist(&pieces.1.pose_at(k as f64 / 10000.0), &prev.end())).fold(f64::INFINITY, f64::min);
        assert!(deviation <= dev * (1.0 + 1e-9) && (d > 40.0 || deviation > dev * 0.9999), "{turn_deg}: {deviation}");
    }
    // Next to an arc the first estimate is corrected by the measured deviation.
    let line = line_abs_2d(&at(0.0, 0.0, 0.0), [100.0, 0.0, 0.0]).unwrap();
    for (center, angle) in [([120.0, -20.0, 0.0], -200.0), ([130.0, 0.0, 0.0], 150.0), ([120.0, -20.0, 0.0], 200.0)] {
        let arc = arc_angle_2d(&line.end(), center, Z, angle).unwrap();
        let pieces = corner(&line, &arc, TransitionMode::MaxCornerDev, &params(40.0, 1.5, 0.0)).expect("blended");
        let d = line.length() - pieces.0.length();
        assert_g1(&line, &arc, &pieces, d);
        let deviation =
            (0..=10000).map(|k| dist(&pieces.1.pose_at(k as f64 / 10000.0), &line.end())).fold(f64::INFINITY, f64::min);
        assert!(deviation <= 1.5 * (1.0 + 1e-6) && deviation > 1.5 * 0.999, "{center:?}: {deviation}");
    }
    // A deviation larger than trans_dis allows: the trim stays trans_dis.
    let prev = line_abs_2d(&at(0.0, 0.0, 0.0), [100.0, 0.0, 0.0]).unwrap();
    let next = line_abs_2d(&prev.end(), [100.0, 100.0, 0.0]).unwrap();
    assert_g1(
        &prev,
        &next,
        &corner(&prev, &next, TransitionMode::MaxCornerDev, &params(20.0, 50.0, 0.0)).unwrap(),
        20.0,
    );
}

#[test]
fn max_corner_curvature() {
    let prev = line_abs_2d(&at(0.0, 0.0, 0.0), [100.0, 0.0, 0.0]).unwrap();
    let next = line_abs_2d(&prev.end(), [100.0, 100.0, 0.0]).unwrap();
    let pieces = corner(&prev, &next, TransitionMode::MaxCornerCurv, &params(1.0, 0.0, 0.1)).expect("blended");
    let d = 4.0 / (0.1 * 2f64.powf(1.5));
    assert_g1(&prev, &next, &pieces, d);
    let r_min = (0..=1000).filter_map(|k| pieces.1.radius_at(k as f64 / 1000.0)).fold(f64::INFINITY, f64::min);
    assert!((r_min - 10.0).abs() < 1e-6, "{r_min}");
    // Too little curvature for the segments: not blended.
    assert!(corner(&prev, &next, TransitionMode::MaxCornerCurv, &params(1.0, 0.0, 0.01)).is_none());
    // Next to an arc the measured curvature decides.
    let arc = arc_angle_2d(&prev.end(), [150.0, 0.0, 0.0], Z, 90.0).unwrap();
    let (_, b, _) = corner(&prev, &arc, TransitionMode::MaxCornerCurv, &params(1.0, 0.0, 0.2)).expect("blended");
    let r_min = (0..=1000).filter_map(|k| b.radius_at(k as f64 / 1000.0)).fold(f64::INFINITY, f64::min);
    assert!(r_min >= 5.0 * (1.0 - 1e-6), "{r_min}");
}

#[test]
fn line_arc_arc_line_arc_arc_and_3d() {
    // HMPL 8.1.6 example 3-3: arcs and lines blended with trans_dis 20.
    let p = params(20.0, 0.0, 0.0);
    let l1 = line_abs_2d(&at(0.0, 0.0, 0.0), [100.0, 0.0, 0.0]).unwrap();
    // Up over (150, 50) to (200, 0), a quarter clockwise about (200, -50), then along X.
    let a1 = circle_2d(&l1.end(), [150.0, 0.0, 0.0], [200.0, 0.0, 0.0], Z, -1).unwrap();
    let a2 = circle_2d(&a1.end(), [200.0, -50.0, 0.0], [250.0, -50.0, 0.0], Z, -1).unwrap();
    let l2 = line_abs_2d(&a2.end(), [350.0, -50.0, 0.0]).unwrap();
    for (prev, next) in [(&l1, &a1), (&a1, &a2), (&a2, &l2)] {
        let pieces = corner(prev, next, TransitionMode::CornerDist, &p).expect("blended");
        assert_g1(prev, next, &pieces, 20.0);
        // The trimmed arcs keep their circle.
        for s in [&pieces.0, &pieces.2] {
            if let Segment::Arc(a) = s {
                let m = s.pose_at(0.5);
                assert!(((m[0] - a.center[0]).hypot(m[1] - a.center[1]) - 50.0).abs() < 1e-9);
            }
        }
    }
    // 3-D: a helix into a line leaving the plane, orientation moving beside.
    let helix = circle_abs(&at(0.0, 0.0, 0.0), [0.0, 50.0, 0.0], Z, 1, &[0.0, 0.0, 30.0, 0.0, 0.0, 90.0]).unwrap();
    let up = line_abs(&helix.end(), &[0.0, 0.0, 130.0, 0.0, 45.0, 90.0]).unwrap();
    let pieces = corner(&helix, &up, TransitionMode::CornerDist, &p).expect("blended");
    assert_g1(&helix, &up, &pieces, 20.0);
    assert!((pieces.1.start()[5] - helix.pose_at(1.0 - 20.0 / helix.length())[5]).abs() < 1e-12);
    assert!((pieces.1.end()[4] - 45.0 * 0.2).abs() < 1e-12);
    let skew = line_abs_3d(&l1.end(), [100.0, 60.0, 80.0]).unwrap();
    assert_g1(&l1, &skew, &corner(&l1, &skew, TransitionMode::CornerDist, &p).unwrap(), 20.0);
}

#[test]
fn parameters_and_modes() {
    // HMPL table 8.1.5.1 numbers ("0 ~ 4"); TM_START_VEL (5) is not available.
    for (n, m) in [
        (0, TransitionMode::None),
        (1, TransitionMode::ConstVel),
        (2, TransitionMode::CornerDist),
        (3, TransitionMode::MaxCornerDev),
        (4, TransitionMode::MaxCornerCurv),
    ] {
        assert_eq!(TransitionMode::try_from(n), Ok(m));
        assert_eq!(i64::from(m), n);
    }
    for n in [-1, 5, 6] {
        assert_eq!(TransitionMode::try_from(n), Err(GroupError::CmdTransModeUnknown));
    }
    // HMPL table 8.3.26.1.
    let ok = TransitionParams { trans_vel: 50.0, trans_dis: 20.0, trans_dev: 0.0, trans_curv: 0.0 };
    assert_eq!(ok.validate(), Ok(()));
    let cases = [
        (TransitionParams { trans_vel: 5000.0, ..ok }, GroupError::CmdInvalidTransVel),
        (TransitionParams { trans_vel: 0.0, ..ok }, GroupError::CmdInvalidTransVel),
        (TransitionParams { trans_vel: f64::NAN, ..ok }, GroupError::CmdInvalidTransVel),
        (TransitionParams { trans_dis: 0.0, ..ok }, GroupError::CmdInvalidTransDis),
        (TransitionParams { trans_dis: -1.0, ..ok }, GroupError::CmdInvalidTransDis),
        (TransitionParams { trans_dev: -1.0, ..ok }, GroupError::CmdInvalidTransDev),
        (TransitionParams { trans_curv: 1e7, ..ok }, GroupError::CmdInvalidTransCurve),
        (TransitionParams { trans_curv: -1.0, ..ok }, GroupError::CmdInvalidTransCurve),
    ];
    for (p, e) in cases {
        assert_eq!(p.validate(), Err(e), "{p:?}");
    }
    assert_eq!(ok.validate_for(TransitionMode::CornerDist), Ok(()));
    assert_eq!(ok.validate_for(TransitionMode::MaxCornerDev), Err(GroupError::CmdInvalidTransDev));
    assert_eq!(ok.validate_for(TransitionMode::MaxCornerCurv), Err(GroupError::CmdInvalidTransCurve));
    assert_eq!(TransitionParams::default().validate_for(TransitionMode::None), Ok(()));
    assert_eq!(
        TransitionParams::default().validate_for(TransitionMode::CornerDist),
        Err(GroupError::CmdInvalidTransVel)
    );
    let _ = SQRT_2;
}

#[test]
fn a_blend_cut_short_keeps_its_curve() {
    // Segment::sub on a blend (a stop inside a rounded corner): the same points, fractions rescaled.
    let a = line_abs_2d(&at(0.0, 0.0, 0.0), [100.0, 0.0, 0.0]).unwrap();
    let b = line_abs_3d(&a.end(), [130.0, 80.0, 40.0]).unwrap();
    let (_, blend, _) = corner(&a, &b, TransitionMode::CornerDist, &params(30.0, 0.0, 0.0)).unwrap();
    let (u0, u1) = (0.2, 0.7);
    let part = blend.sub(u0, u1);
    assert!(matches!(part, Segment::Blend(_)));
    assert_eq!((part.start(), part.end()), (blend.pose_at(u0), blend.pose_at(u1)));
    assert!((part.length() - (u1 - u0) * blend.length()).abs() < 1e-9);
    for k in 0..=50 {
        let v = k as f64 / 50.0;
        let (p, q) = (part.pose_at(v), blend.pose_at(u0 + v * (u1 - u0)));
        assert!(close(&p, &q, 1e-9), "{v}: {p:?} {q:?}");
        assert!(close(&part.direction_at(v), &blend.direction_at(u0 + v * (u1 - u0)), 1e-9));
    }
}

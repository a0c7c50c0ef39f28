//! Conformance of the geometry commands (HMPL 8.2.9-8.2.17, 8.5, example 4 of 8.1.6).

use std::f64::consts::{PI, SQRT_2};

use api::GroupError;
use path::Pose;
use path::commands::*;
use path::segment::Segment;

const Z: [f64; 3] = [0.0, 0.0, 1.0];

fn at(x: f64, y: f64, z: f64) -> Pose {
    [x, y, z, 0.0, 0.0, 0.0]
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

fn arc(s: &Segment) -> path::segment::Arc {
    match s {
        Segment::Arc(a) => *a,
        other => panic!("not an arc: {other:?}"),
    }
}

/// The distance of a point from the arc's axis (its radius where the radius is constant).
fn axis_distance(a: &path::segment::Arc, p: &Pose) -> f64 {
    let v: [f64; 3] = std::array::from_fn(|i| p[i] - a.center[i]);
    let along: f64 = (0..3).map(|i| v[i] * a.normal[i]).sum();
    (0..3).map(|i| (v[i] - along * a.normal[i]).powi(2)).sum::<f64>().sqrt()
}

/// The point the arc formula reaches just before the stored end.
fn formula_end(s: &Segment) -> Pose {
    s.pose_at(1.0 - f64::EPSILON)
}

#[test]
fn lines_absolute_relative_and_zero_length() {
    // HMPL 8.2.11: from (100, 200) LineRel2D(100, 100) ends at (200, 300).
    let l = line_rel_2d(&at(100.0, 200.0, 0.0), [100.0, 100.0, 0.0]).unwrap();
    assert_eq!(l.end(), at(200.0, 300.0, 0.0));
    // HMPL 8.2.10, 8.2.12, 8.5.1, 8.5.2.
    assert_eq!(line_abs_3d(&at(1.0, 2.0, 3.0), [4.0, 5.0, 6.0]).unwrap().end(), at(4.0, 5.0, 6.0));
    assert_eq!(line_rel_3d(&at(1.0, 2.0, 3.0), [4.0, 5.0, 6.0]).unwrap().end(), at(5.0, 7.0, 9.0));
    let start = [1.0, 2.0, 3.0, 10.0, 20.0, 30.0];
    assert_eq!(line_abs(&start, &[0.0, 0.0, 0.0, 0.0, 0.0, 90.0]).unwrap().end(), [0.0, 0.0, 0.0, 0.0, 0.0, 90.0]);
    assert_eq!(line_rel(&start, &[1.0, 1.0, 1.0, 1.0, 1.0, 1.0]).unwrap().end(), [2.0, 3.0, 4.0, 11.0, 21.0, 31.0]);
    // The manual's examples start with a line to where the group stands (8.1.6 ex. 4).
    let zero = line_abs_2d(&at(0.0, 0.0, 0.0), [0.0, 0.0, 0.0]).unwrap();
    assert_eq!((zero.length(), zero.end()), (0.0, at(0.0, 0.0, 0.0)));
    assert_eq!(line_abs(&start, &[f64::NAN; 6]), Err(GroupError::CmdInvalidPos));
    // Sampled points of a line lie on it.
    let l = line_abs_3d(&at(-3.0, 7.0, 1.0), [120.0, -45.5, 33.0]).unwrap();
    for k in 0..=100 {
        let p = l.pose_at(k as f64 / 100.0);
        let (s, e) = (l.start(), l.end());
        let t = k as f64 / 100.0;
        assert!(close(&p[..3], &[s[0] + t * (e[0] - s[0]), s[1] + t * (e[1] - s[1]), s[2] + t * (e[2] - s[2])], 1e-9));
    }
}

#[test]
fn arc_2d_through_three_points() {
    // HMPL 8.2.13: from (0, 0) through (100, 100) to (200, 0): center (100, 0), radius 100.
    let s = arc_2d(&at(0.0, 0.0, 0.0), [100.0, 100.0, 0.0], [200.0, 0.0, 0.0]).unwrap();
    let a = arc(&s);
    assert!(close(&a.center, &[100.0, 0.0, 0.0], 1e-9), "{:?}", a.center);
    assert!((a.radius - 100.0).abs() < 1e-9 && (a.sweep.abs() - PI).abs() < 1e-12);
    assert!(close(&s.pose_at(0.5), &at(100.0, 100.0, 0.0), 1e-9), "{:?}", s.pose_at(0.5));
    assert!(close(&formula_end(&s), &at(200.0, 0.0, 0.0), 1e-9));
    assert!((s.length() - 100.0 * PI).abs() < 1e-9);
    for k in 0..=64 {
        assert!((axis_distance(&a, &s.pose_at(k as f64 / 64.0)) - 100.0).abs() < 1e-9);
        assert_eq!(s.radius_at(k as f64 / 64.0).map(|r| (r - 100.0).abs() < 1e-9), Some(true));
    }
    // The border point may lie anywhere on the arc: an arc of 270°.
    let s = arc_2d(&at(100.0, 0.0, 0.0), [0.0, 100.0, 0.0], [0.0, -100.0, 0.0]).unwrap();
    assert!((arc(&s).sweep - 1.5 * PI).abs() < 1e-12);
    assert!(close(&s.pose_at(1.0 / 3.0), &at(0.0, 100.0, 0.0), 1e-9));
    // Collinear or coincident points make no arc.
    for (b, e) in [
        ([50.0, 50.0, 0.0], [100.0, 100.0, 0.0]),
        ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
        ([10.0, 0.0, 0.0], [10.0, 0.0, 0.0]),
        ([10.0, 5.0, 0.0], [0.0, 0.0, 0.0]),
    ] {
        assert_eq!(arc_2d(&at(0.0, 0.0, 0.0), b, e), Err(GroupError::CmdCircInvalidParam), "{b:?} {e:?}");
    }
}

#[test]
fn arc_angle_2d_direction_and_end() {
    // HMPL 8.2.16: from (0, 0) about (10, 10) by 45° counter-clockwise ends at (10, 10 − 10√2).
    let s = arc_angle_2d(&at(0.0, 0.0, 0.0), [10.0, 10.0, 0.0], Z, 45.0).unwrap();
    assert!(close(&s.end(), &at(10.0, 10.0 - 10.0 * SQRT_2, 0.0), 1e-9), "{:?}", s.end());
    assert!(close(&formula_end(&s), &s.end(), 1e-9));
    let d = s.direction_at(0.0);
    assert!(close(&d, &[0.5f64.sqrt(), -(0.5f64.sqrt()), 0.0], 1e-12), "{d:?}");
    // Negative: clockwise, to (10 − 10√2, 10).
    let s = arc_angle_2d(&at(0.0, 0.0, 0.0), [10.0, 10.0, 0.0], Z, -45.0).unwrap();
    assert!(close(&s.end(), &at(10.0 - 10.0 * SQRT_2, 10.0, 0.0), 1e-9), "{:?}", s.end());
    assert!(close(&s.direction_at(0.0), &[-(0.5f64.sqrt()), 0.5f64.sqrt(), 0.0], 1e-12));
    // Several turns are one command.
    let s = arc_angle_2d(&at(0.0, 0.0, 0.0), [10.0, 0.0, 0.0], Z, 720.0 + 90.0).unwrap();
    assert!(close(&s.end(), &at(10.0, -10.0, 0.0), 1e-9) && (s.length() - 10.0 * 4.5 * PI).abs() < 1e-9);
    assert_eq!(arc_angle_2d(&at(0.0, 0.0, 0.0), [10.0, 10.0, 0.0], Z, 0.0), Err(GroupError::CmdCircAngleSmall));
    assert_eq!(arc_angle_2d(&at(5.0, 5.0, 0.0), [5.0, 5.0, 0.0], Z, 10.0), Err(GroupError::CmdCircInvalidCenter));
    assert_eq!(arc_angle_2d(&at(0.0, 0.0, 0.0), [5.0, 5.0, 0.0], [0.0; 3], 10.0), Err(GroupError::CmdCircInvalidParam));
}

#[test]
fn circle_2d_turns_rule() {
    // HMPL 8.2.17, the table for θ = 210°.
    let (ccw, cw) = (210f64.to_radians(), 150f64.to_radians());
    for (turns, deg) in [(-2, -510.0), (-1, -150.0), (0, 210.0), (1, 210.0), (2, 570.0)] {
        assert!((turns_sweep(ccw, cw, turns).to_degrees() - deg).abs() < 1e-9, "turns {turns}");
        // The same through the command: start at 0°, end at 210° on a circle of radius 10.
        let end = [10.0 * 210f64.to_radians().cos(), 10.0 * 210f64.to_radians().sin(), 0.0];
        let s = circle_2d(&at(10.0, 0.0, 0.0), [0.0; 3], end, Z, turns).unwrap();
        assert!((arc(&s).sweep.to_degrees() - deg).abs() < 1e-9, "turns {turns}: {}", arc(&s).sweep.to_degrees());
        assert!(close(&formula_end(&s), &s.end(), 1e-9));
    }
    // HMPL 8.2.17 example: from (0, 0) about (100, 0) to (200, 0), turns 1: half a circle CCW.
    let s = circle_2d(&at(0.0, 0.0, 0.0), [100.0, 0.0, 0.0], [200.0, 0.0, 0.0], Z, 1).unwrap();
    assert!((arc(&s).sweep - PI).abs() < 1e-12);
    assert!(close(&s.pose_at(0.5), &at(100.0, -100.0, 0.0), 1e-9), "{:?}", s.pose_at(0.5));
    assert!(close(&formula_end(&s), &at(200.0, 0.0, 0.0), 1e-9));
    // End on the start: whole turns (HMPL 8.1.6 example 4), both ways.
    for (turns, revolutions) in [(0, 1.0), (1, 1.0), (5, 5.0), (-1, -1.0), (-3, -3.0)] {
        let s = circle_2d(&at(0.0, 0.0, 0.0), [0.0, 50.0, 0.0], [0.0, 0.0, 0.0], Z, turns).unwrap();
        assert!((arc(&s).sweep - revolutions * 2.0 * PI).abs() < 1e-12, "turns {turns}");
    }
    assert_eq!(
        circle_2d(&at(0.0, 0.0, 0.0), [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], Z, 1),
        Err(GroupError::CmdCircInvalidCenter)
    );
    assert_eq!(
        circle_2d(&at(0.0, 0.0, 0.0), [1.0, 0.0, 0.0], [1.0, 0.0, 0.0], Z, 1),
        Err(GroupError::CmdCircInvalidCenter)
    );
}

#[test]
fn arc_cw_ccw_2d_radii() {
    let start = at(10.0, 0.0, 0.0);
    // HMPL 8.2.14/8.2.15: a quarter circle either way round.
    let ccw = arc_ccw_2d(&start, [0.0; 3], [0.0, 10.0, 0.0], Z).unwrap();
    let cw = arc_cw_2d(&start, [0.0; 3], [0.0, 10.0, 0.0], Z).unwrap();
    assert!((arc(&ccw).sweep - PI / 2.0).abs() < 1e-12 && (arc(&cw).sweep + 1.5 * PI).abs() < 1e-12);
    assert!(close(&ccw.pose_at(0.5), &at(10.0 * 0.5f64.sqrt(), 10.0 * 0.5f64.sqrt(), 0.0), 1e-9));
    assert!(close(&cw.pose_at(1.0 / 3.0), &at(0.0, -10.0, 0.0), 1e-9));
    // Radii differing beyond the tolerance: 0x0280; the center on an end point: 0x026C.
    assert_eq!(arc_cw_2d(&start, [0.0; 3], [0.0, 10.01, 0.0], Z), Err(GroupError::CmdCircInvalidRadius));
    assert_eq!(arc_ccw_2d(&start, [0.0; 3], [0.0, 9.998, 0.0], Z), Err(GroupError::CmdCircInvalidRadius));
    assert_eq!(arc_cw_2d(&start, [10.0, 0.0, 0.0], [0.0, 10.0, 0.0], Z), Err(GroupError::CmdCircInvalidCenter));
    assert_eq!(arc_cw_2d(&start, [0.0, 10.0, 0.0], [0.0, 10.0, 0.0], Z), Err(GroupError::CmdCircInvalidCenter));
    // Within the tolerance (an end typed to 4 decimals) the radius drifts onto the end.
    let end = [7.0711, 7.0711, 0.0];
    let s = arc_ccw_2d(&start, [0.0; 3], end, Z).unwrap();
    let a = arc(&s);
    assert!(a.radius_change != 0.0);
    assert!(close(&formula_end(&s), &s.end(), 1e-9), "{:?}", formula_end(&s));
    let r1 = (end[0] * end[0] + end[1] * end[1]).sqrt();
    for k in 0..=32 {
        let r = axis_distance(&a, &s.pose_at(k as f64 / 32.0));
        assert!(r >= 10.0f64.min(r1) - 1e-12 && r <= 10.0f64.max(r1) + 1e-12);
    }
}

#[test]
fn example_4_circles_in_three_planes_and_a_helix() {
    // HMPL 8.1.6 example 4, from (0, 0, 0): the direction follows the normal by the right-hand rule.
    let o = at(0.0, 0.0, 0.0);
    let (c1, c2) = ([0.0, 50.0, 0.0], [0.0, 0.0, 50.0]);
    let cases = [
        (c1, [0.0, 0.0, 1.0], [1.0, 0.0, 0.0], at(50.0, 50.0, 0.0), at(0.0, 100.0, 0.0)),
        (c2, [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], at(-50.0, 0.0, 50.0), at(0.0, 0.0, 100.0)),
        (c2, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], at(0.0, 50.0, 50.0), at(0.0, 0.0, 100.0)),
    ];
    for (center, normal, first, quarter, half) in cases {
        let s = circle_abs(&o, center, normal, 1, &o).unwrap();
        assert!((s.length() - 100.0 * PI).abs() < 1e-9);
        assert!(close(&s.direction_at(0.0), &first, 1e-12), "{normal:?}: {:?}", s.direction_at(0.0));
        assert!(close(&s.pose_at(0.25), &quarter, 1e-9) && close(&s.pose_at(0.5), &half, 1e-9), "{normal:?}");
        assert!(close(&formula_end(&s), &o, 1e-9));
    }
    // The helix: five revolutions about (0, 50) while Z rises linearly to 100.
    let end = at(0.0, 0.0, 100.0);
    let s = circle_abs(&o, c1, [0.0, 0.0, 1.0], 5, &end).unwrap();
    let a = arc(&s);
    assert!((a.sweep - 10.0 * PI).abs() < 1e-12 && (a.rise - 100.0).abs() < 1e-12);
    for k in 0..=500 {
        let u = k as f64 / 500.0;
        let p = s.pose_at(u);
        assert!((p[2] - 100.0 * u).abs() < 1e-9, "z at {u}");
        assert!((axis_distance(&a, &p) - 50.0).abs() < 1e-9);
    }
    for k in 0..=5 {
        assert!(close(&s.pose_at(k as f64 / 5.0), &at(0.0, 0.0, 20.0 * k as f64), 1e-9), "turn {k}");
    }
    assert!(close(&formula_end(&s), &end, 1e-9));
    let pitch = 100.0 / (10.0 * PI);
    let expected = (50.0f64.powi(2) + pitch * pitch) / 50.0;
    assert!((s.radius_at(0.3).unwrap() - expected).abs() < 1e-9, "{:?} vs {expected}", s.radius_at(0.3));
    assert!((s.length() - ((100.0 * 5.0 * PI).powi(2) + 100.0f64.powi(2)).sqrt()).abs() < 1e-9);
    // CircleRel: the same helix by its displacement; the orientation moves beside it.
    let r = circle_rel(&o, c1, [0.0, 0.0, 1.0], 5, &[0.0, 0.0, 100.0, 0.0, 0.0, 90.0]).unwrap();
    assert_eq!(r.end(), [0.0, 0.0, 100.0, 0.0, 0.0, 90.0]);
    assert!((r.pose_at(0.5)[5] - 45.0).abs() < 1e-12 && (r.angular_length() - 90.0).abs() < 1e-12);
}

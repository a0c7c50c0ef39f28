//! A 200-segment polygon of short segments, run with BM_LOOKAHEAD and with BM_BUFF, beside
//! the time-optimal bound for the same limits (shared by the test and the benchmark).

use path::segment::Line;
use path::{BufferMode, Limits, LookAhead, Motion, Planner, Pose, Profile, Segment};

pub const PERIOD: f64 = 0.001;
const FEED: f64 = 200.0;
const ACC: f64 = 2000.0;
const SMOOTH_MS: f64 = 20.0;

/// 200 segments of 1 mm whose heading swings like a sine, with a right angle every 50.
pub fn polygon() -> Vec<Pose> {
    let mut pts = vec![[0.0; 6]];
    let mut heading = 0.0f64;
    for j in 0..200 {
        heading += 0.05 * (j as f64 / 8.0).sin() + if j % 50 == 49 { std::f64::consts::FRAC_PI_2 } else { 0.0 };
        let p = *pts.last().unwrap();
        pts.push([p[0] + heading.cos(), p[1] + heading.sin(), 0.0, 0.0, 0.0, 0.0]);
    }
    pts
}

fn motion(buffer: BufferMode) -> Motion {
    Motion {
        lin: Profile { vel: FEED, acc: ACC, dec: ACC, smooth_ms: SMOOTH_MS },
        ang: Profile { vel: 360.0, acc: 1800.0, dec: 1800.0, smooth_ms: SMOOTH_MS },
        buffer,
    }
}

/// The planner's path time over the polygon, s.
pub fn planner_time(buffer: BufferMode) -> f64 {
    let pts = polygon();
    let mut p = Planner::new(PERIOD);
    for w in pts.windows(2) {
        p.push(Segment::Line(Line { start: w[0], end: w[1] }), motion(buffer), &Limits::NONE).unwrap();
    }
    let mut cycles = 0;
    while p.step().moving {
        cycles += 1;
    }
    assert_eq!(p.end_pose(), *pts.last().unwrap());
    cycles as f64 * PERIOD
}

/// The time-optimal path time for the same limits: feed, acceleration and deceleration along
/// the path, and at each corner the corner velocity min(A_corner, acc) * Ts / |d2 - d1|
/// (HMPL table 8.1.4.2 (b), the group's corner rule), from rest to rest; the exact forward
/// and backward passes on a 1 µm grid.
pub fn bound_time() -> f64 {
    let pts = polygon();
    let ds = 1e-3;
    let window = (SMOOTH_MS / 1000.0).max(PERIOD);
    let corner_acc = LookAhead::default().corner_acc.min(ACC);
    let dir = |a: &Pose, b: &Pose| {
        let (x, y) = (b[0] - a[0], b[1] - a[1]);
        let n = (x * x + y * y).sqrt();
        (x / n, y / n, n)
    };
    let mut limit = Vec::new();
    for k in 0..pts.len() - 1 {
        let (_, _, len) = dir(&pts[k], &pts[k + 1]);
        let steps = (len / ds).round() as usize;
        let mut cap = vec![FEED; steps];
        if k > 0 {
            let (x1, y1, _) = dir(&pts[k - 1], &pts[k]);
            let (x2, y2, _) = dir(&pts[k], &pts[k + 1]);
            let turn = ((x2 - x1).powi(2) + (y2 - y1).powi(2)).sqrt();
            if turn > 1e-12 {
                cap[0] = cap[0].min(corner_acc * window / turn);
            }
        }
        limit.extend(cap);
    }
    limit.push(0.0);
    limit[0] = 0.0;
    let mut v = limit.clone();
    for i in (0..v.len() - 1).rev() {
        v[i] = v[i].min((v[i + 1] * v[i + 1] + 2.0 * ACC * ds).sqrt());
    }
    for i in 1..v.len() {
        v[i] = v[i].min((v[i - 1] * v[i - 1] + 2.0 * ACC * ds).sqrt());
    }
    v.windows(2).map(|w| 2.0 * ds / (w[0] + w[1])).sum()
}

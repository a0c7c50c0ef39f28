//! The planner's fixes the constraint checker (`planner_constraints.rs`) led to, each with
//! the case it was found by and a second one the fix was not written for.

use path::blend::{TransitionMode, TransitionParams};
use path::commands::{arc_ccw_2d, circle_2d, line_abs, line_abs_2d};
use path::{BufferMode, Limits, Motion, Planner, Pose, Profile, Sample, Segment};

const PERIOD: f64 = 0.001;
const Z: [f64; 3] = [0.0, 0.0, 1.0];

fn xy(x: f64, y: f64) -> Pose {
    [x, y, 0.0, 0.0, 0.0, 0.0]
}

fn motion(vel: f64, buffer: BufferMode) -> Motion {
    Motion {
        lin: Profile { vel, acc: 5000.0, dec: 5000.0, smooth_ms: 0.0 },
        ang: Profile { vel: 360.0, acc: 1800.0, dec: 1800.0, smooth_ms: 0.0 },
        buffer,
    }
}

fn trans(trans_vel: f64, trans_dis: f64) -> TransitionParams {
    TransitionParams { trans_vel, trans_dis, trans_dev: 0.0, trans_curv: 0.0 }
}

/// Steps until the planner stops emitting, with the command count after each cycle.
fn run(p: &mut Planner) -> Vec<(Sample, usize)> {
    let mut out = Vec::new();
    loop {
        let s = p.step();
        out.push((s, p.commands()));
        if !s.moving {
            return out;
        }
    }
}

/// The smallest radius of curvature of a segment, from 20 000 samples.
fn tightest(segment: &Segment) -> f64 {
    (0..=20_000).filter_map(|k| segment.radius_at(k as f64 / 20_000.0)).fold(f64::INFINITY, f64::min)
}

/// A corner between `prev` and `next` blended (TM_CORNER_DIST) at a feed far above what
/// the axes allow on the blend: the path on it stays within sqrt(max_acc / 2 · r) at its
/// tightest point r (half of max_acc is the centripetal share, HMPL 8.1 "within each
/// axis' limits"), also where that point is not the blend's middle.
fn assert_blend_within_centripetal_cap(prev: Segment, next: Segment, trans_dis: f64) {
    let max_acc = 2000.0;
    let limits = Limits { max_vel: [f64::INFINITY; 6], max_acc: [max_acc, max_acc, max_acc, 1e9, 1e9, 1e9] };
    let mut p = Planner::new(PERIOD);
    let m = motion(2000.0, BufferMode::Low);
    let params = trans(4000.0, trans_dis);
    p.push_with_transition(prev, m, TransitionMode::CornerDist, &params, &limits).unwrap();
    let q = p.push_with_transition(next, m, TransitionMode::CornerDist, &params, &limits).unwrap();
    let (blend, _) = q.blend.expect("the corner is blended");
    let r = tightest(&blend);
    let quarters = [0.0, 0.25, 0.5, 0.75, 1.0].iter().filter_map(|&u| blend.radius_at(u)).fold(f64::INFINITY, f64::min);
    assert!(r < 0.95 * quarters, "the tightest point ({r} mm) lies between the quarters ({quarters} mm)");
    let cap = (max_acc / 2.0 * r).sqrt();
    let on_blend: Vec<f64> = run(&mut p).iter().filter(|(_, n)| *n == 2).map(|(s, _)| s.path_vel).collect();
    assert!(on_blend.len() > 3, "the path ran on the blend");
    for v in on_blend {
        assert!(v <= cap * (1.0 + 1e-9), "{v} mm/s on the blend, above {cap}");
    }
}

#[test]
fn a_blend_into_an_arc_slows_for_its_tightest_point() {
    // Found by the checker: a line into a tight arc; the blend bends hardest near the arc.
    let line = line_abs_2d(&xy(0.0, 0.0), [20.0, 0.0, 0.0]).unwrap();
    // An arc of 1.4 mm about (21, 1) leaves (20, 0) at 45° to the line.
    let arc = arc_ccw_2d(&xy(20.0, 0.0), [21.0, 1.0, 0.0], [21.0 + 2f64.sqrt(), 1.0, 0.0], Z).unwrap();
    assert_blend_within_centripetal_cap(line, arc, 3.0);
}

#[test]
fn a_blend_between_two_arcs_slows_for_its_tightest_point() {
    // A quarter circle of 10 mm into a tight circle of 2.8 mm, 135° apart.
    let wide = circle_2d(&xy(0.0, 0.0), [0.0, 10.0, 0.0], [10.0, 10.0, 0.0], Z, 1).unwrap();
    let tight = circle_2d(&xy(10.0, 10.0), [12.0, 8.0, 0.0], [14.0, 10.0, 0.0], Z, 1).unwrap();
    assert_blend_within_centripetal_cap(wide, tight, 1.5);
}

/// The translation and rotation speeds of the raw path, per cycle.
fn speeds(samples: &[(Sample, usize)], start: Pose) -> Vec<(f64, f64)> {
    let mut last = start;
    samples
        .iter()
        .map(|(s, _)| {
            let d = |r: std::ops::Range<usize>| r.map(|i| (s.pose[i] - last[i]).powi(2)).sum::<f64>().sqrt() / PERIOD;
            let v = (d(0..3), d(3..6));
            last = s.pose;
            v
        })
        .collect()
}

/// Long smoothing and a stiff rotation, so the corner rule does not hide the feed rule.
fn stiff(lin_vel: f64, buffer: BufferMode) -> Motion {
    Motion {
        lin: Profile { vel: lin_vel, acc: 5000.0, dec: 5000.0, smooth_ms: 100.0 },
        ang: Profile { vel: 360.0, acc: 100_000.0, dec: 100_000.0, smooth_ms: 100.0 },
        buffer,
    }
}

#[test]
fn bm_high_carries_the_higher_feed_without_rotating_faster_than_either() {
    // Found by the checker: 10 mm turning C by 10° at 100 mm/s (100°/s), then BM_HIGH into
    // 2 mm turning 40° at 10 mm/s (200°/s). The higher feed along the path, 100 mm/s, would
    // turn C at 2000°/s on the second segment; it may turn at most 200°/s, the faster of
    // the two feeds' rotations (HMPL table 8.1.4.1 with the feed rule of 8.1).
    let a: Pose = [0.0; 6];
    let b: Pose = [10.0, 0.0, 0.0, 0.0, 0.0, 10.0];
    let c: Pose = [12.0, 0.0, 0.0, 0.0, 0.0, 50.0];
    let mut p = Planner::new(PERIOD);
    p.push(line_abs(&a, &b).unwrap(), stiff(100.0, BufferMode::High), &Limits::NONE).unwrap();
    p.push(line_abs(&b, &c).unwrap(), stiff(10.0, BufferMode::High), &Limits::NONE).unwrap();
    let samples = run(&mut p);
    let speeds = speeds(&samples, a);
    let top = speeds.iter().fold((0.0f64, 0.0f64), |m, s| (m.0.max(s.0), m.1.max(s.1)));
    assert!(top.0 <= 100.0 + 1e-6 && top.1 <= 200.0 + 1e-6, "peaks {top:?}");
    assert!(top.1 > 199.0, "the second segment runs at its feed: {top:?}");
    assert_eq!(samples.last().unwrap().0.pose, c);
}

#[test]
fn bm_high_from_a_rotation_into_a_line_keeps_the_line_within_its_feed() {
    // The same rule where the path parameter changes unit: C turns 90° at 360°/s (`s` in
    // deg), then BM_HIGH into a 10 mm line at 20 mm/s. 360 "per second" carried into the
    // line would be 360 mm/s; it may translate at most 20 mm/s.
    let a: Pose = [0.0; 6];
    let b: Pose = [0.0, 0.0, 0.0, 0.0, 0.0, 90.0];
    let c: Pose = [10.0, 0.0, 0.0, 0.0, 0.0, 90.0];
    let mut p = Planner::new(PERIOD);
    p.push(line_abs(&a, &b).unwrap(), stiff(100.0, BufferMode::High), &Limits::NONE).unwrap();
    p.push(line_abs(&b, &c).unwrap(), stiff(20.0, BufferMode::High), &Limits::NONE).unwrap();
    let samples = run(&mut p);
    for (i, (trans, rot)) in speeds(&samples, a).into_iter().enumerate() {
        assert!(trans <= 20.0 + 1e-6 && rot <= 360.0 + 1e-6, "cycle {i}: {trans} mm/s, {rot} deg/s");
    }
    assert_eq!(samples.last().unwrap().0.pose, c);
}

/// Runs until the path has gone `distance`, then queues `segment` as the group does and
/// runs to the end: the path velocity never steps by more than the deceleration allows.
fn assert_late_corner_keeps_the_deceleration(
    p: &mut Planner,
    distance: f64,
    segment: Segment,
    params: TransitionParams,
) {
    let mut samples = Vec::new();
    while samples.last().is_none_or(|s: &Sample| s.path_pos < distance) {
        samples.push(p.step());
    }
    let m = motion(200.0, BufferMode::Buff);
    p.push_with_transition(segment, m, TransitionMode::ConstVel, &params, &Limits::NONE).unwrap();
    samples.extend(run(p).into_iter().map(|(s, _)| s));
    for w in samples.windows(2) {
        let dv = (w[1].path_vel - w[0].path_vel).abs();
        assert!(dv <= 5000.0 * PERIOD * (1.0 + 1e-9) + 1e-9, "velocity step {dv} at {}", w[1].path_pos);
    }
    assert_eq!(samples.last().unwrap().pose, segment.end());
}

#[test]
fn a_corner_is_not_blended_into_a_tail_the_path_cannot_stop_on_in_time() {
    // Found by the checker: a BM_BUFF line at 200 mm/s (4 mm to stop at 5000 mm/s²), 6 mm
    // from its end; a corner of 5 mm would make it end 1 mm closer than the path can stop.
    let mut p = Planner::new(PERIOD);
    p.push(line_abs_2d(&xy(0.0, 0.0), [100.0, 0.0, 0.0]).unwrap(), motion(200.0, BufferMode::Buff), &Limits::NONE)
        .unwrap();
    let next = line_abs_2d(&xy(100.0, 0.0), [100.0, 50.0, 0.0]).unwrap();
    assert_late_corner_keeps_the_deceleration(&mut p, 94.0, next, trans(100.0, 5.0));
}

#[test]
fn a_corner_is_not_blended_into_a_queued_tail_the_path_cannot_slow_down_for() {
    // The tail is not running: 200 mm/s on a first line, 1.5 mm before a 4 mm tail the
    // path is to stop at the end of (it begins braking at the tail's start). A corner with
    // trans_vel 1 mm/s trimming the tail by 2 mm would leave 3.5 mm to slow to 1 mm/s.
    let mut p = Planner::new(PERIOD);
    let low = motion(200.0, BufferMode::Low);
    p.push(line_abs_2d(&xy(0.0, 0.0), [100.0, 0.0, 0.0]).unwrap(), low, &Limits::NONE).unwrap();
    p.push(line_abs_2d(&xy(100.0, 0.0), [104.0, 0.0, 0.0]).unwrap(), low, &Limits::NONE).unwrap();
    let next = line_abs_2d(&xy(104.0, 0.0), [104.0, 50.0, 0.0]).unwrap();
    assert_late_corner_keeps_the_deceleration(&mut p, 98.5, next, trans(1.0, 2.0));
}

/// HMPL 8.1: a full queue refuses a command with nothing lost. A corner needs two places
/// (the blend and the segment): with one left the segment is queued unblended; with none,
/// the command is refused and the queue, its tail included, stays as it was.
#[test]
fn a_corner_is_blended_only_where_the_queue_has_room_for_it() {
    let mut p = Planner::new(PERIOD);
    p.set_queue_size(4).unwrap();
    let m = motion(100.0, BufferMode::Low);
    let params = trans(50.0, 5.0);
    let square = [xy(100.0, 0.0), xy(100.0, 100.0), xy(0.0, 100.0), xy(0.0, 0.0)];
    let mut start = xy(0.0, 0.0);
    let mut blends = Vec::new();
    for (i, &end) in square.iter().enumerate() {
        let segment = line_abs(&start, &end).unwrap();
        let result = p.push_with_transition(segment, m, TransitionMode::CornerDist, &params, &Limits::NONE);
        if i < 3 {
            blends.push(result.expect("room").blend.is_some());
        } else {
            assert_eq!(result, Err(api::GroupError::CmdQueueFull), "the fifth place does not exist");
        }
        start = end;
    }
    assert_eq!(blends, [false, true, false], "first line: no corner; second: blended; third: one place left");
    assert_eq!(p.commands(), 4);
    assert_eq!(p.end_pose(), xy(0.0, 100.0), "the refused command left the tail whole");
}

//! The group planner against the manual's rows (HMPL ch. 8), one test per behaviour.

use api::GroupError;
use path::segment::Line;
use path::{BufferMode, Limits, Motion, Planner, Pose, Profile, Sample, Segment};

const PERIOD: f64 = 0.001;

fn line(start: Pose, end: Pose) -> Segment {
    Segment::Line(Line { start, end })
}

fn xy(x: f64, y: f64) -> Pose {
    [x, y, 0.0, 0.0, 0.0, 0.0]
}

/// HMPL 8.3.6/8.3.7 defaults with the smooth time `smooth_ms`, and a buffer mode.
fn motion(vel: f64, buffer: BufferMode) -> Motion {
    Motion {
        lin: Profile { vel, acc: 5000.0, dec: 5000.0, smooth_ms: 50.0 },
        ang: Profile { vel: 360.0, acc: 1800.0, dec: 1800.0, smooth_ms: 50.0 },
        buffer,
    }
}

/// Steps until the planner stops emitting (or `max` cycles), with the command count after
/// each cycle.
fn run(p: &mut Planner, max: usize) -> Vec<(Sample, usize)> {
    let mut out = Vec::new();
    for _ in 0..max {
        let s = p.step();
        out.push((s, p.commands()));
        if !s.moving {
            break;
        }
    }
    out
}

/// Velocity right after each junction: the first sample after the command count fell.
fn junction_speeds(samples: &[(Sample, usize)]) -> Vec<f64> {
    samples.windows(2).filter(|w| w[1].1 < w[0].1 && w[1].1 > 0).map(|w| w[1].0.path_vel).collect()
}

fn assert_accelerations_within(samples: &[(Sample, usize)], limit: f64) {
    for w in samples.windows(2) {
        let dv = (w[1].0.path_vel - w[0].0.path_vel).abs();
        assert!(dv <= limit * PERIOD * (1.0 + 1e-9) + 1e-9, "velocity step {dv}");
    }
}

#[test]
fn line_abs_2d_moves_both_coordinates_together_within_the_feed() {
    // HMPL 8.2.9 and 8.1 (example 1 of 8.1.6): LineAbs2D(g, 100, 100) from (0, 0).
    let mut p = Planner::new(PERIOD);
    p.push(line(xy(0.0, 0.0), xy(100.0, 100.0)), motion(100.0, BufferMode::Buff), &Limits::NONE).unwrap();
    let samples = run(&mut p, 10_000);
    let last = samples.last().unwrap().0;
    assert_eq!(last.pose, xy(100.0, 100.0), "the end is reached exactly");
    assert!(!last.moving && p.commands() == 0);
    for (s, _) in &samples {
        assert!(s.path_vel <= 100.0 + 1e-9, "path speed {} above the feed", s.path_vel);
        // Both start and stop together: on the diagonal at every cycle.
        assert!((s.pose[0] - s.pose[1]).abs() < 1e-9);
    }
    assert!(samples.iter().any(|(s, _)| (s.path_vel - 100.0).abs() < 1e-9), "it reaches the feed");
    assert!((last.path_pos - 100.0 * 2f64.sqrt()).abs() < 1e-9);
    assert_accelerations_within(&samples, 5000.0);
}

#[test]
fn the_queue_holds_512_and_refuses_the_513th_losing_nothing() {
    // HMPL 8.1: "up to 512 motion commands"; beyond, eERR_CRD_CMD_QUEUE_FULL (0x0078).
    let mut p = Planner::new(PERIOD);
    let m = motion(100.0, BufferMode::Low);
    for i in 0..512 {
        p.push(line(xy(i as f64, 0.0), xy(i as f64 + 1.0, 0.0)), m, &Limits::NONE).unwrap();
    }
    p.step();
    assert_eq!(p.commands(), 512, "the first is still running");
    let end = p.end_pose();
    assert_eq!(p.push(line(end, xy(600.0, 0.0)), m, &Limits::NONE), Err(GroupError::CmdQueueFull));
    assert_eq!((p.commands(), p.end_pose()), (512, end), "nothing lost, nothing added");
    // HMPL 8.3.35: the size changes only while the queue is empty.
    assert_eq!(p.set_queue_size(8), Err(GroupError::CmdQueueIsNotEmpty));
    assert_eq!(p.set_queue_size(2048), Err(GroupError::CmdInvalidQueueSize));
    run(&mut p, 100_000);
    assert_eq!(p.end_pose(), xy(512.0, 0.0));
    p.set_queue_size(8).unwrap();
    assert_eq!(p.queue_size(), 8);
    for i in 0..8 {
        p.push(line(xy(512.0 + i as f64, 0.0), xy(513.0 + i as f64, 0.0)), m, &Limits::NONE).unwrap();
    }
    assert_eq!(p.push(line(xy(520.0, 0.0), xy(521.0, 0.0)), m, &Limits::NONE), Err(GroupError::CmdQueueFull));
}

#[test]
fn the_command_count_falls_as_segments_finish_and_stop_empties_it() {
    // HMPL 8.3.27 GetGrpCmdNum, 8.2.4 StopGroup.
    let mut p = Planner::new(PERIOD);
    let m = motion(100.0, BufferMode::Buff);
    for i in 0..4 {
        p.push(line(xy(10.0 * i as f64, 0.0), xy(10.0 * (i + 1) as f64, 0.0)), m, &Limits::NONE).unwrap();
    }
    let samples = run(&mut p, 100_000);
    let counts: Vec<usize> = samples.iter().map(|s| s.1).collect();
    assert!(counts.windows(2).all(|w| w[1] <= w[0]));
    for n in [3, 2, 1, 0] {
        assert!(counts.contains(&n), "count {n} seen");
    }
    // Stop while moving: decelerates along the path, then nothing is left.
    for i in 0..4 {
        p.push(
            line(xy(40.0 + 10.0 * i as f64, 0.0), xy(50.0 + 10.0 * i as f64, 0.0)),
            motion(100.0, BufferMode::Low),
            &Limits::NONE,
        )
        .unwrap();
    }
    for _ in 0..150 {
        p.step();
    }
    let stop_at = p.stopping_pose();
    p.stop();
    let samples = run(&mut p, 100_000);
    assert_eq!(p.commands(), 0);
    assert_eq!(samples.last().unwrap().0.pose, stop_at, "it stops where stopping_pose said");
    assert!(stop_at[0] < 80.0 && stop_at[1] == 0.0);
    assert_accelerations_within(&samples, 5000.0);
}

#[test]
fn bm_buff_stops_at_every_junction_and_holds_for_the_smooth_time() {
    // HMPL table 8.1.4.1 BM_BUFF: finish the current path, then start the next.
    let mut p = Planner::new(PERIOD);
    let m = motion(100.0, BufferMode::Buff);
    let pts = [xy(0.0, 0.0), xy(20.0, 0.0), xy(20.0, 20.0), xy(40.0, 20.0)];
    for w in pts.windows(2) {
        p.push(line(w[0], w[1]), m, &Limits::NONE).unwrap();
    }
    let samples = run(&mut p, 100_000);
    let js: Vec<usize> = (1..samples.len()).filter(|&i| samples[i].1 < samples[i - 1].1 && samples[i].1 > 0).collect();
    assert_eq!(js.len(), 2);
    for &i in &js {
        // At rest at the junction, and for Ts (50 cycles) after the cycle it arrived in.
        for (s, _) in &samples[i..=i + 50] {
            assert_eq!(s.path_vel, 0.0);
            assert_eq!(s.pose, samples[i].0.pose);
        }
        assert!(samples[i + 52].0.path_vel > 0.0, "then it goes on");
    }
}

/// Two collinear segments (v1 then v2) joined by `mode`: the velocity right after the junction.
fn straight_junction(v1: f64, v2: f64, mode: BufferMode) -> f64 {
    let mut p = Planner::new(PERIOD);
    p.push(line(xy(0.0, 0.0), xy(100.0, 0.0)), motion(v1, mode), &Limits::NONE).unwrap();
    p.push(line(xy(100.0, 0.0), xy(200.0, 0.0)), motion(v2, BufferMode::Buff), &Limits::NONE).unwrap();
    let samples = run(&mut p, 100_000);
    assert_accelerations_within(&samples, 5000.0);
    assert_eq!(samples.last().unwrap().0.pose, xy(200.0, 0.0));
    let js = junction_speeds(&samples);
    assert_eq!(js.len(), 1);
    js[0]
}

#[test]
fn blending_modes_set_the_junction_velocity_by_table_8_1_4_1() {
    // One cycle after the junction the velocity has changed by at most acc * period = 5 mm/s.
    let near = |v: f64, expected: f64| (v - expected).abs() <= 5.0 + 1e-9;
    // BM_LOW: the lower of the two, never below min(v1, v2).
    let v = straight_junction(150.0, 50.0, BufferMode::Low);
    assert!(near(v, 50.0) && v >= 50.0 - 1e-9, "{v}");
    let v = straight_junction(50.0, 150.0, BufferMode::Low);
    assert!(near(v, 50.0) && v >= 50.0 - 1e-9, "{v}");
    // BM_PREV: the current path's; BM_NEXT: the next one's; BM_HIGH: the higher.
    assert!(near(straight_junction(150.0, 100.0, BufferMode::Prev), 150.0));
    assert!(near(straight_junction(150.0, 50.0, BufferMode::Next), 50.0));
    assert!(near(straight_junction(50.0, 150.0, BufferMode::Next), 150.0));
    assert!(near(straight_junction(50.0, 150.0, BufferMode::High), 150.0));
    assert!(near(straight_junction(150.0, 50.0, BufferMode::High), 150.0));
    // BM_BUFF: at rest.
    assert_eq!(straight_junction(150.0, 50.0, BufferMode::Buff), 0.0);
}

#[test]
fn a_corner_is_slowed_so_the_smoothed_velocity_step_stays_within_max_acc() {
    // The corner rule (docs/decisions.md): a 90 deg corner at BM_HIGH, X and Y limited to
    // 2000 mm/s^2, Ts 50 ms. X's velocity steps from v to 0 and Y's from 0 to v.
    let mut p = Planner::new(PERIOD);
    let limits = Limits {
        max_vel: [f64::INFINITY; 6],
        max_acc: [2000.0, 2000.0, 2000.0, f64::INFINITY, f64::INFINITY, f64::INFINITY],
    };
    p.push(line(xy(0.0, 0.0), xy(100.0, 0.0)), motion(100.0, BufferMode::High), &limits).unwrap();
    p.push(line(xy(100.0, 0.0), xy(100.0, 100.0)), motion(100.0, BufferMode::Buff), &limits).unwrap();
    let samples = run(&mut p, 100_000);
    let v = junction_speeds(&samples)[0];
    // Each coordinate's step is v; the profile takes 2000 of the 2000 mm/s^2 (acc capped to
    // max_acc), so nothing is left: the corner is passed at rest.
    assert!(v <= 2000.0 * PERIOD + 1e-9, "{v}");
    // With room (max_acc 20 000), the step may take (20 000 - 5000) * 25 ms = 375 mm/s,
    // so the feed (100) holds.
    let mut p = Planner::new(PERIOD);
    let limits = Limits { max_acc: [20_000.0; 6], ..limits };
    p.push(line(xy(0.0, 0.0), xy(100.0, 0.0)), motion(100.0, BufferMode::High), &limits).unwrap();
    p.push(line(xy(100.0, 0.0), xy(100.0, 100.0)), motion(100.0, BufferMode::Buff), &limits).unwrap();
    let v = junction_speeds(&run(&mut p, 100_000))[0];
    assert!((v - 100.0).abs() < 1e-9, "{v}");
}

#[test]
fn a_segment_pushed_after_the_group_came_to_rest_starts_from_rest() {
    // HMPL 8.1.4: "if the group has not received the next command before the current path
    // is in position, the buffer mode is ignored" (8.1.6 example 2, path 3 to path 4).
    let mut p = Planner::new(PERIOD);
    p.push(line(xy(0.0, 0.0), xy(50.0, 0.0)), motion(100.0, BufferMode::High), &Limits::NONE).unwrap();
    let first = run(&mut p, 100_000);
    assert_eq!(first.last().unwrap().0.path_vel, 0.0, "the last queued segment ends at rest");
    p.push(line(xy(50.0, 0.0), xy(100.0, 0.0)), motion(100.0, BufferMode::High), &Limits::NONE).unwrap();
    let second = run(&mut p, 100_000);
    let moving: Vec<&Sample> = second.iter().map(|(s, _)| s).filter(|s| s.path_vel > 0.0).collect();
    assert!(moving[0].path_vel <= 5000.0 * PERIOD + 1e-9, "starts from rest: {}", moving[0].path_vel);
    assert_eq!(second.last().unwrap().0.pose, xy(100.0, 0.0));
}

#[test]
fn a_push_while_the_tail_brakes_raises_its_exit_only_as_far_as_reachable() {
    let mut p = Planner::new(PERIOD);
    p.push(line(xy(0.0, 0.0), xy(50.0, 0.0)), motion(100.0, BufferMode::Low), &Limits::NONE).unwrap();
    // Run until it brakes for its end (1 mm before it, at 5000 mm/s^2 from 100 mm/s).
    let mut samples = Vec::new();
    while p.step().path_vel >= 99.0 {}
    for _ in 0..5 {
        samples.push((p.step(), p.commands()));
    }
    let braking = samples.last().unwrap().0.path_vel;
    assert!(braking < 100.0 && braking > 0.0);
    p.push(line(xy(50.0, 0.0), xy(100.0, 0.0)), motion(100.0, BufferMode::Buff), &Limits::NONE).unwrap();
    samples.extend(run(&mut p, 100_000));
    assert_accelerations_within(&samples, 5000.0);
    let js = junction_speeds(&samples);
    // Blended after all: the tail keeps at least the speed it had when the push came.
    assert!(js[0] >= braking, "junction at {}, braking from {braking}", js[0]);
    assert_eq!(samples.last().unwrap().0.pose, xy(100.0, 0.0));
}

#[test]
fn halt_stops_on_the_path_and_resume_reaches_the_same_end() {
    // HMPL 8.2.5 HaltGroup / 8.2.6 ResumeGroup.
    let mut p = Planner::new(PERIOD);
    p.push(line(xy(0.0, 0.0), xy(100.0, 50.0)), motion(100.0, BufferMode::Buff), &Limits::NONE).unwrap();
    let mut samples: Vec<(Sample, usize)> = (0..300).map(|_| (p.step(), 1)).collect();
    p.halt();
    assert!(p.is_halted());
    samples.extend(run(&mut p, 10_000));
    let halted = samples.last().unwrap().0;
    assert!(!halted.moving && halted.path_vel == 0.0 && p.commands() == 1);
    assert!(halted.pose[0] > 0.0 && halted.pose[0] < 100.0);
    assert!((halted.pose[1] - halted.pose[0] / 2.0).abs() < 1e-9, "still on the line");
    for _ in 0..100 {
        assert_eq!(p.step().pose, halted.pose, "halted stays");
    }
    p.resume();
    samples.extend(run(&mut p, 10_000));
    assert_accelerations_within(&samples, 5000.0);
    assert_eq!(samples.last().unwrap().0.pose, xy(100.0, 50.0));
    assert_eq!(p.commands(), 0);
}

#[test]
fn velocity_scale_changes_the_speed_smoothly() {
    // HMPL 8.3.28 SetGrpVelScale 0..100 %.
    let mut p = Planner::new(PERIOD);
    p.push(line(xy(0.0, 0.0), xy(200.0, 0.0)), motion(100.0, BufferMode::Buff), &Limits::NONE).unwrap();
    let mut samples: Vec<(Sample, usize)> = (0..300).map(|_| (p.step(), 1)).collect();
    assert!((samples.last().unwrap().0.path_vel - 100.0).abs() < 1e-9);
    p.set_velocity_scale(40.0);
    samples.extend((0..300).map(|_| (p.step(), 1)));
    assert!((samples.last().unwrap().0.path_vel - 40.0).abs() < 1e-9);
    p.set_velocity_scale(0.0);
    samples.extend((0..300).map(|_| (p.step(), 1)));
    let still = samples.last().unwrap().0;
    assert_eq!(still.path_vel, 0.0);
    p.set_velocity_scale(100.0);
    samples.extend(run(&mut p, 100_000));
    assert_accelerations_within(&samples, 5000.0);
    assert_eq!(samples.last().unwrap().0.pose, xy(200.0, 0.0));
}

#[test]
fn jog_moves_one_coordinate_until_jogged_to_zero_or_halted() {
    // HMPL 8.2.7 JogGroup(g, 0, 10): X at 10 mm/s.
    let mut p = Planner::new(PERIOD);
    p.rest_at(xy(5.0, 7.0));
    let m = motion(100.0, BufferMode::Buff);
    p.jog(0, 10.0, m, &Limits::NONE);
    let mut last = p.step();
    for _ in 0..999 {
        last = p.step();
    }
    // 1 s at 10 mm/s after a 2 ms ramp (10 / 5000 s): 10 - 0.01 mm.
    assert!((last.pose[0] - (5.0 + 10.0 - 0.01)).abs() < 1e-9, "{}", last.pose[0]);
    assert_eq!((last.pose[1], last.path_vel), (7.0, 10.0));
    assert_eq!(p.push(line(last.pose, xy(0.0, 0.0)), m, &Limits::NONE), Err(GroupError::CmdInvalidMoving));
    p.jog(0, -10.0, m, &Limits::NONE);
    for _ in 0..10 {
        last = p.step();
    }
    assert_eq!(last.path_vel, 10.0, "reversed");
    p.jog(0, 0.0, m, &Limits::NONE);
    for _ in 0..10 {
        last = p.step();
    }
    assert!(!last.moving && !p.is_moving());
    let x = last.pose[0];
    assert_eq!(p.step().pose[0], x);
    // Halt ends a jog too; limits cap the velocity.
    let limits = Limits { max_vel: [4.0; 6], ..Limits::NONE };
    p.jog(1, 10.0, m, &limits);
    for _ in 0..100 {
        last = p.step();
    }
    assert_eq!(last.path_vel, 4.0);
    p.halt();
    for _ in 0..10 {
        last = p.step();
    }
    assert!(!last.moving);
}

#[test]
fn bm_abort_stops_along_the_path_and_starts_the_new_segment_there() {
    // HMPL table 8.1.4.1 BM_ABORT: abort the current motion and execute the next at once.
    let mut p = Planner::new(PERIOD);
    let m = motion(100.0, BufferMode::Low);
    p.push(line(xy(0.0, 0.0), xy(100.0, 0.0)), m, &Limits::NONE).unwrap();
    p.push(line(xy(100.0, 0.0), xy(100.0, 100.0)), m, &Limits::NONE).unwrap();
    let mut samples: Vec<(Sample, usize)> = (0..300).map(|_| (p.step(), 2)).collect();
    let at = p.stopping_pose();
    assert!(at[0] > samples.last().unwrap().0.pose[0] && at[1] == 0.0);
    p.push(line(at, xy(at[0], -50.0)), motion(100.0, BufferMode::Abort), &Limits::NONE).unwrap();
    assert_eq!(p.commands(), 2, "the running one, cut, and the new one");
    samples.extend(run(&mut p, 100_000));
    assert_accelerations_within(&samples, 5000.0);
    assert!(samples.iter().any(|(s, _)| s.pose == at && s.path_vel == 0.0), "at rest where it stopped");
    assert!(samples.iter().all(|(s, _)| s.pose[1] <= 0.0), "the dropped segment never ran");
    assert_eq!(samples.last().unwrap().0.pose, xy(at[0], -50.0));
}

#[test]
fn look_ahead_keeps_speed_through_shallow_corners_and_brakes_for_the_end() {
    // HMPL 8.1.4 look-ahead over a polygon of 1 mm segments turning 2 deg each.
    let mut p = Planner::new(PERIOD);
    let m = motion(100.0, BufferMode::LookAhead);
    let mut pose = xy(0.0, 0.0);
    for i in 0..100 {
        let a = (i as f64 * 2.0).to_radians();
        let next = xy(pose[0] + a.cos(), pose[1] + a.sin());
        p.push(line(pose, next), m, &Limits::NONE).unwrap();
        pose = next;
    }
    let samples = run(&mut p, 100_000);
    assert_accelerations_within(&samples, 5000.0);
    let js = junction_speeds(&samples);
    assert_eq!(js.len(), 99);
    // V_corner = 5000 mm/s^2 * 50 ms / |d2 - d1| is far above the feed at 2 deg, so the
    // middle junctions pass at the feed; the last ones brake for the end.
    assert!(js[10..80].iter().all(|&v| (v - 100.0).abs() < 1e-9));
    assert!(js[98] < 100.0);
    assert_eq!(samples.last().unwrap().0.pose, pose);
}

#[test]
fn each_command_s_own_buffer_mode_sets_the_junction_at_its_end() {
    // HMPL 8.1.6 example 2 with the half circle straightened (it leaves p1 tangentially):
    // path 1 at 150 mm/s with BM_PREV, path 2 at 100 with BM_NEXT, path 3 at 50 with BM_PREV,
    // queued at once. The junction speed is planned "at the end position of each path": p1
    // at path 1's 150 (BM_PREV), p2 at path 3's 50 (path 2's BM_NEXT); path 3 ends at rest,
    // as nothing follows it.
    let mut p = Planner::new(PERIOD);
    let profile = |vel: f64, acc: f64| Profile { vel, acc, dec: acc, smooth_ms: 50.0 };
    let with = |lin: Profile, buffer| Motion { lin, ang: profile(360.0, 1800.0), buffer };
    p.push(line(xy(0.0, 0.0), xy(100.0, 0.0)), with(profile(150.0, 1000.0), BufferMode::Prev), &Limits::NONE).unwrap();
    p.push(line(xy(100.0, 0.0), xy(257.0, 0.0)), with(profile(100.0, 5000.0), BufferMode::Next), &Limits::NONE)
        .unwrap();
    p.push(line(xy(257.0, 0.0), xy(357.0, 0.0)), with(profile(50.0, 250.0), BufferMode::Prev), &Limits::NONE).unwrap();
    let samples = run(&mut p, 100_000);
    let js = junction_speeds(&samples);
    assert_eq!(js.len(), 2);
    assert!((js[0] - 150.0).abs() <= 5.0, "p1 at {}", js[0]);
    assert!((js[1] - 50.0).abs() <= 1.0, "p2 at {}", js[1]);
    let end = samples.last().unwrap().0;
    assert_eq!((end.pose, end.path_vel), (xy(357.0, 0.0), 0.0));
}

//! The planner's constraint checker: 10 000 random sequences of segments (lines in 2-D,
//! 3-D and 6-D with rotations, polygons approximating arcs), every buffer mode, random
//! profiles and machine limits, velocity scale changes, halts and late pushes (BM_ABORT
//! among them) while the path runs. Each cycle's raw pose is smoothed with a moving average
//! over Ts as the group does (HMPL 5.1's S-curve), and the checker asserts:
//! - the raw translation and rotation speeds within the feeds (HMPL 8.1) times the scale,
//!   and the path acceleration within the profiles';
//! - every coordinate's smoothed velocity and acceleration (finite differences) within the
//!   machine's max_vel and max_acc;
//! - velocity 0 at every BM_BUFF junction and the raw pose still for Ts there, so the
//!   smoothed path stops too (HMPL table 8.1.4.1);
//! - the end pose exact.
//!
//! Tolerances are for rounding only (relative 1e-9 plus 1e-6 absolute): the smoothed
//! acceleration is (v[k] - v[k-N]) / (N T) with v the mean raw velocity over a cycle, which
//! the planner bounds exactly (its trapezoids are sampled, not integrated).

use path::segment::Line;
use path::{BufferMode, Limits, Motion, Planner, Pose, Profile, Segment};

const PERIOD: f64 = 0.004;
const SEQUENCES: u64 = 10_000;

/// SplitMix64: a small deterministic generator, so a failing sequence can be replayed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn chance(&mut self, p: f64) -> bool {
        self.uniform(0.0, 1.0) < p
    }
}

const MODES: [BufferMode; 6] =
    [BufferMode::Buff, BufferMode::Low, BufferMode::Prev, BufferMode::Next, BufferMode::High, BufferMode::LookAhead];

/// What the checker knows of a pushed segment.
#[derive(Clone, Copy)]
struct Pushed {
    end: Pose,
    motion: Motion,
    lin_len: f64,
    ang_len: f64,
}

impl Pushed {
    /// Bounds of the translation speed, the rotation speed and the path acceleration
    /// (in either unit of the path parameter) that the feed rule allows.
    fn bounds(&self) -> (f64, f64, f64) {
        let (l, a) = (self.motion.lin, self.motion.ang);
        let k = if self.lin_len > 1e-12 && self.ang_len > 1e-12 { self.lin_len / self.ang_len } else { 0.0 };
        let trans = l.vel.max(a.vel * k);
        let rot = a.vel.max(if k > 0.0 { l.vel / k } else { 0.0 });
        let acc = l.acc.max(l.dec).max(a.acc.max(a.dec)).max(a.acc.max(a.dec) * k);
        (trans, rot, acc)
    }
}

struct Sequence {
    planner: Planner,
    limits: Limits,
    smooth_ms: f64,
    dims: usize,
    pushed: Vec<Pushed>,
    rng: Rng,
}

impl Sequence {
    fn random_motion(&mut self) -> Motion {
        let r = &mut self.rng;
        let lin = Profile {
            vel: r.uniform(20.0, 300.0),
            acc: r.uniform(500.0, 20_000.0),
            dec: r.uniform(500.0, 20_000.0),
            smooth_ms: self.smooth_ms,
        };
        let ang = Profile {
            vel: r.uniform(30.0, 720.0),
            acc: r.uniform(300.0, 7200.0),
            dec: r.uniform(300.0, 7200.0),
            smooth_ms: self.smooth_ms,
        };
        Motion { lin, ang, buffer: MODES[r.below(MODES.len() as u64) as usize] }
    }

    fn push(&mut self, start: Pose, end: Pose, motion: Motion) {
        let seg = Segment::Line(Line { start, end });
        self.planner.push(seg, motion, &self.limits).expect("room in the queue");
        self.pushed.push(Pushed { end, motion, lin_len: seg.length(), ang_len: seg.angular_length() });
    }

    /// A line or a polygon approximating an arc, from the queue's end.
    fn push_item(&mut self, abort: bool) {
        let mut motion = self.random_motion();
        let start = if abort { self.planner.stopping_pose() } else { self.planner.end_pose() };
        if abort {
            motion.buffer = BufferMode::Abort;
        }
        if abort || self.rng.chance(0.6) {
            let mut end = start;
            let len = self.rng.uniform(0.5, 20.0);
            let dir: Vec<f64> = (0..self.dims.min(3)).map(|_| self.rng.uniform(-1.0, 1.0)).collect();
            let n = dir.iter().map(|d| d * d).sum::<f64>().sqrt().max(1e-9);
            let pure_rotation = self.dims == 6 && self.rng.chance(0.15);
            for (i, d) in dir.iter().enumerate() {
                if !pure_rotation {
                    end[i] += d / n * len;
                }
            }
            if self.dims == 6 {
                for v in &mut end[3..] {
                    *v += self.rng.uniform(-30.0, 30.0);
                }
            }
            self.push(start, end, motion);
        } else {
            let r = self.rng.uniform(2.0, 40.0);
            let n = 8 + self.rng.below(17);
            let sweep = self.rng.uniform(0.3, 3.0) * if self.rng.chance(0.5) { 1.0 } else { -1.0 };
            let step = sweep / n as f64;
            let chord = 2.0 * r * (step.abs() / 2.0).sin();
            let mut heading = self.rng.uniform(0.0, std::f64::consts::TAU);
            let mut p = start;
            for _ in 0..n {
                let mut q = p;
                q[0] += chord * heading.cos();
                q[1] += chord * heading.sin();
                if self.dims == 6 {
                    q[5] += 2.0;
                }
                self.push(p, q, motion);
                p = q;
                heading += step;
            }
        }
    }
}

/// Runs one random sequence; returns the number of cycles, or the violation.
fn check(seed: u64) -> Result<usize, String> {
    let mut rng = Rng(seed);
    let dims = [2, 3, 6][rng.below(3) as usize];
    let smooth_ms = [0.0, 4.0, 12.0, 24.0, 48.0][rng.below(5) as usize];
    let pick = |rng: &mut Rng, lo: f64, hi: f64| if rng.chance(0.3) { f64::INFINITY } else { rng.uniform(lo, hi) };
    let max_vel =
        std::array::from_fn(|i| if i < 3 { pick(&mut rng, 50.0, 500.0) } else { pick(&mut rng, 90.0, 900.0) });
    let max_acc =
        std::array::from_fn(
            |i| if i < 3 { pick(&mut rng, 2000.0, 30_000.0) } else { pick(&mut rng, 1000.0, 20_000.0) },
        );
    let mut seq = Sequence {
        planner: Planner::new(PERIOD),
        limits: Limits { max_vel, max_acc },
        smooth_ms,
        dims,
        pushed: Vec::new(),
        rng,
    };
    for _ in 0..1 + seq.rng.below(6) {
        seq.push_item(false);
    }
    let rng = &mut seq.rng;
    let halt_at = if rng.chance(0.3) { Some(rng.below(400)) } else { None };
    let resume_after = 1 + rng.below(100);
    let scale_at =
        if rng.chance(0.3) { Some((rng.below(400), rng.uniform(0.0, 100.0), rng.uniform(20.0, 100.0))) } else { None };
    let late_push = if rng.chance(0.4) { Some((rng.below(600), rng.chance(0.3))) } else { None };

    let hold = (smooth_ms / 1000.0 / PERIOD).round() as usize;
    let n = hold.max(1);
    let mut poses: Vec<Pose> = vec![[0.0; 6]; n + 2];
    let mut smoothed_vel = [0.0f64; 6];
    let mut finished = 0usize;
    let mut scale = 1.0f64;
    let mut scale_high = (1.0f64, 0usize); // the highest scale lately, and when it was lowered
    let mut hold_check: Option<(usize, Pose)> = None;
    let tol = |bound: f64| bound * (1.0 + 1e-9) + 1e-6;
    for cycle in 0..200_000usize {
        let c = cycle as u64;
        if halt_at == Some(c) {
            seq.planner.halt();
        }
        if halt_at.map(|h| h + resume_after) == Some(c) {
            seq.planner.resume();
        }
        if let Some((at, low, back)) = scale_at
            && (c == at || c == at + 150)
        {
            let new = if c == at { low } else { back } / 100.0;
            if new < scale {
                scale_high = (scale.max(scale_high.0), cycle);
            }
            scale = new;
            seq.planner.set_velocity_scale(new * 100.0);
        }
        if let Some((at, abort)) = late_push
            && c == at
        {
            seq.push_item(abort);
            if abort {
                // The checker's copy of the queue: what was kept, then the new segment.
                let kept = seq.planner.commands() - 1;
                let new = *seq.pushed.last().unwrap();
                seq.pushed.truncate(finished + kept);
                seq.pushed.push(new);
            }
        }
        let prev_commands = seq.planner.commands();
        let s = seq.planner.step();
        let commands = seq.planner.commands();
        // Segments that finished in this cycle.
        for k in finished..finished + (prev_commands - commands) {
            if seq.pushed[k].motion.buffer == BufferMode::Buff && commands > 0 {
                if s.path_vel != 0.0 {
                    return Err(format!("cycle {cycle}: BM_BUFF junction passed at {}", s.path_vel));
                }
                hold_check = Some((cycle, s.pose));
            }
        }
        let finished_before = finished;
        finished += prev_commands - commands;
        if let Some((at, pose)) = hold_check {
            if cycle <= at + hold {
                if s.pose != pose {
                    return Err(format!("cycle {cycle}: moved during the hold after a BM_BUFF stop"));
                }
            } else {
                hold_check = None;
            }
        }
        // Raw speeds within the feeds of the running segment and its neighbours.
        let recent_scale = if cycle < scale_high.1 + 2000 { scale_high.0.max(scale) } else { scale };
        let last = *poses.last().unwrap();
        let trans = (0..3).map(|i| (s.pose[i] - last[i]).powi(2)).sum::<f64>().sqrt() / PERIOD;
        let rot = (3..6).map(|i| (s.pose[i] - last[i]).powi(2)).sum::<f64>().sqrt() / PERIOD;
        // Every segment this cycle ran on, and the neighbours whose junction rule may have
        // brought their feed into it.
        let lo = finished_before.saturating_sub(1);
        let hi = (finished + 2).min(seq.pushed.len());
        let (mut bt, mut br, mut ba) = (0.0f64, 0.0f64, 0.0f64);
        for p in &seq.pushed[lo..hi.max(lo)] {
            let (t, r, a) = p.bounds();
            (bt, br, ba) = (bt.max(t), br.max(r), ba.max(a));
        }
        if trans > tol(bt * recent_scale) || rot > tol(br * recent_scale) {
            return Err(format!(
                "cycle {cycle}: speed {trans} mm/s, {rot} deg/s above {bt}, {br} x {recent_scale} (finished {finished}, push {late_push:?}, {:?})",
                seq.pushed[lo.saturating_sub(2)..(hi + 2).min(seq.pushed.len())]
                    .iter()
                    .map(|p| (p.motion.buffer, p.bounds().0, p.lin_len))
                    .collect::<Vec<_>>()
            ));
        }
        if s.path_acc.abs() > tol(ba) {
            return Err(format!("cycle {cycle}: path acceleration {} above {ba}", s.path_acc));
        }
        // The group's moving average over N cycles, and its finite differences.
        poses.push(s.pose);
        let k = poses.len() - 1;
        for i in 0..6 {
            let v = (poses[k][i] - poses[k - n][i]) / (n as f64 * PERIOD);
            let a = (v - smoothed_vel[i]) / PERIOD;
            smoothed_vel[i] = v;
            if v.abs() > tol(seq.limits.max_vel[i]) {
                return Err(format!(
                    "cycle {cycle}: coordinate {i} smoothed velocity {v} above {}",
                    seq.limits.max_vel[i]
                ));
            }
            if cycle > 0 && a.abs() > tol(seq.limits.max_acc[i]) {
                return Err(format!(
                    "cycle {cycle}: coordinate {i} smoothed acceleration {a} above {} (n {n}, halt {halt_at:?}, scale {scale_at:?}, push {late_push:?}, finished {finished}, modes {:?})",
                    seq.limits.max_acc[i],
                    seq.pushed.iter().map(|p| p.motion.buffer).collect::<Vec<_>>()
                ));
            }
        }
        let events_done = halt_at.is_none_or(|h| c > h + resume_after)
            && scale_at.is_none_or(|(at, _, _)| c > at + 150)
            && late_push.is_none_or(|(at, _)| c > at);
        if events_done && !s.moving && commands == 0 {
            let end = seq.pushed.last().unwrap().end;
            return if s.pose == end { Ok(cycle) } else { Err(format!("ended at {:?}, not {:?}", s.pose, end)) };
        }
    }
    Err("did not finish in 200 000 cycles".into())
}

#[test]
fn ten_thousand_random_sequences_keep_every_constraint() {
    let mut cycles = 0;
    let mut failures = Vec::new();
    for seed in 0..SEQUENCES {
        match check(seed) {
            Ok(n) => cycles += n,
            Err(e) => failures.push(format!("seed {seed}: {e}")),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {SEQUENCES} sequences violate:\n{}",
        failures.len(),
        failures[..failures.len().min(20)].join("\n")
    );
    println!("{SEQUENCES} sequences, {cycles} cycles of {} ms", PERIOD * 1000.0);
    assert!(cycles > 1_000_000, "the sequences ran ({cycles} cycles)");
}

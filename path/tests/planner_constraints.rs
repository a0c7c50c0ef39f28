//! The planner's constraint checker: 10 000 random sequences of segments built with the
//! group's commands (`path::commands`): lines in 2-D, 3-D and 6-D with rotations, polygons
//! approximating arcs, real arcs (Arc2D, ArcCW2D, ArcCCW2D, ArcAngle2D, Circle2D with
//! turns) and 3-D circles and helices (CircleAbs with any normal, turns and a target off
//! the plane), corner transitions (HMPL 8.1.5) inserted as the group does, every buffer
//! mode, random profiles and machine limits, velocity scale changes, halts and late pushes
//! (BM_ABORT among them) while the path runs. Each cycle's raw pose is smoothed as the
//! group smooths it, a moving average over Ts along the path (HMPL 5.1's S-curve,
//! ceil(Ts / cycle) + 1 samples, `path::smoothing`), and the checker asserts:
//! - the raw translation and rotation speeds within the feeds (HMPL 8.1) times the scale,
//!   and the path acceleration within the profiles';
//! - every coordinate's smoothed velocity and acceleration (finite differences of the
//!   smoothed poses) within the machine's max_vel and max_acc (on curves the centripetal
//!   part counts);
//! - velocity 0 at every BM_BUFF junction and the raw pose still for Ts there, so the
//!   smoothed path stops too (HMPL table 8.1.4.1);
//! - every raw pose on the segment it runs on: on a line, on an arc's or helix's curve
//!   (distance to the axis = radius, height and angle in step), on a blend's curve;
//! - the end pose exact.
//!
//! Tolerances are for rounding only (relative 1e-9 plus 1e-6 absolute for rates, 1e-9 mm
//! for positions).
//!
//! A second checker runs 10 000 random polygons with TM_MAX_CORNER_DEV and the group's
//! default smooth time (50 ms): the smoothed path passes every corner within trans_dev and
//! never leaves the band of trans_dev around the polygon (HMPL 8.1.5, table 8.1.5.1).

use std::f64::consts::TAU;

use path::blend::{TransitionMode, TransitionParams};
use path::commands;
use path::segment::{Line, cross3, diff3, dot3, norm3, unit3, xyz};
use path::smoothing::PathSmoother;
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
    fn sign(&mut self) -> f64 {
        if self.chance(0.5) { 1.0 } else { -1.0 }
    }
    /// A random unit vector.
    fn direction(&mut self) -> [f64; 3] {
        loop {
            let v = [self.uniform(-1.0, 1.0), self.uniform(-1.0, 1.0), self.uniform(-1.0, 1.0)];
            if (0.1..=1.0).contains(&norm3(v)) {
                return unit3(v);
            }
        }
    }
}

const MODES: [BufferMode; 6] =
    [BufferMode::Buff, BufferMode::Low, BufferMode::Prev, BufferMode::Next, BufferMode::High, BufferMode::LookAhead];

const TRANSITIONS: [TransitionMode; 5] = [
    TransitionMode::None,
    TransitionMode::ConstVel,
    TransitionMode::CornerDist,
    TransitionMode::MaxCornerDev,
    TransitionMode::MaxCornerCurv,
];

/// What the checker knows of a queued segment.
#[derive(Clone, Copy)]
struct Pushed {
    segment: Segment,
    motion: Motion,
}

impl Pushed {
    /// Bounds of the translation speed, the rotation speed and the path acceleration
    /// (in either unit of the path parameter) that the feed rule allows.
    fn bounds(&self) -> (f64, f64, f64) {
        let (l, a) = (self.motion.lin, self.motion.ang);
        let (lin_len, ang_len) = (self.segment.length(), self.segment.angular_length());
        let k = if lin_len > 1e-12 && ang_len > 1e-12 { lin_len / ang_len } else { 0.0 };
        let trans = l.vel.max(a.vel * k);
        let rot = a.vel.max(if k > 0.0 { l.vel / k } else { 0.0 });
        let acc = l.acc.max(l.dec).max(a.acc.max(a.dec)).max(a.acc.max(a.dec) * k);
        (trans, rot, acc)
    }
}

/// What a sequence built, to show the checker covered it.
#[derive(Default)]
struct Coverage {
    lines: usize,
    arcs: usize,
    helices: usize,
    blends: [usize; 5],
}

struct Sequence {
    planner: Planner,
    limits: Limits,
    smooth_ms: f64,
    dims: usize,
    transition: TransitionMode,
    trans: TransitionParams,
    pushed: Vec<Pushed>,
    coverage: Coverage,
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

    /// Queues a command's segment as the group does, and keeps the checker's copy.
    fn push(&mut self, segment: Segment, motion: Motion) {
        match segment {
            Segment::Line(_) => self.coverage.lines += 1,
            Segment::Arc(a) if a.rise.abs() >= HELIX => self.coverage.helices += 1,
            _ => self.coverage.arcs += 1,
        }
        let q = self
            .planner
            .push_with_transition(segment, motion, self.transition, &self.trans, &self.limits)
            .expect("room in the queue");
        if let Some(trimmed) = q.trimmed_tail {
            self.pushed.last_mut().expect("the tail is known").segment = trimmed;
        }
        if let Some((segment, motion)) = q.blend {
            self.pushed.push(Pushed { segment, motion });
            self.coverage.blends[self.transition as usize] += 1;
        }
        self.pushed.push(Pushed { segment: q.segment, motion });
    }

    /// A random unit normal of a 2-D command's plane (the coordinate system's Z axis in
    /// MCS): Z in a 2-D sequence, any direction in 3-D.
    fn plane_normal(&mut self) -> [f64; 3] {
        if self.dims == 2 || self.rng.chance(0.4) { [0.0, 0.0, self.rng.sign()] } else { self.rng.direction() }
    }

    /// A command from the queue's end (or, for BM_ABORT, from where the path stops): a line,
    /// a polygon approximating an arc, an arc or a circle of HMPL 8.2, or a helix of 8.5.
    fn push_item(&mut self, abort: bool) {
        let mut motion = self.random_motion();
        let start = if abort { self.planner.stopping_pose() } else { self.planner.end_pose() };
        if abort {
            motion.buffer = BufferMode::Abort;
        }
        if self.rng.chance(0.3) {
            self.transition = TRANSITIONS[self.rng.below(5) as usize];
        }
        match self.rng.below(10) {
            _ if abort => self.push_line(start, motion),
            0..=3 => self.push_line(start, motion),
            4 => self.push_polygon(start, motion),
            5..=7 => self.push_arc_2d(start, motion),
            _ if self.dims == 2 => self.push_arc_2d(start, motion),
            _ => self.push_circle_abs(start, motion),
        }
    }

    fn push_line(&mut self, start: Pose, motion: Motion) {
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
        self.push(commands::line_abs(&start, &end).expect("a finite target"), motion);
    }

    fn push_polygon(&mut self, start: Pose, motion: Motion) {
        let r = self.rng.uniform(2.0, 40.0);
        let n = 8 + self.rng.below(17);
        let sweep = self.rng.uniform(0.3, 3.0) * self.rng.sign();
        let step = sweep / n as f64;
        let chord = 2.0 * r * (step.abs() / 2.0).sin();
        let mut heading = self.rng.uniform(0.0, TAU);
        let mut p = start;
        for _ in 0..n {
            let mut q = p;
            q[0] += chord * heading.cos();
            q[1] += chord * heading.sin();
            if self.dims == 6 {
                q[5] += 2.0;
            }
            self.push(Segment::Line(Line { start: p, end: q }), motion);
            p = q;
            heading += step;
        }
    }

    /// Arc2D, ArcCW2D, ArcCCW2D, ArcAngle2D or Circle2D in a plane through the start.
    fn push_arc_2d(&mut self, start: Pose, motion: Motion) {
        let n = self.plane_normal();
        let r = self.rng.uniform(1.0, 15.0);
        let p0 = xyz(&start);
        // The start's radial direction, in the plane.
        let u0 = unit3(cross3(n, self.rng.direction()));
        let center: [f64; 3] = std::array::from_fn(|i| p0[i] - r * u0[i]);
        let v0 = cross3(n, u0);
        let at = |angle: f64| -> [f64; 3] {
            let (s, c) = angle.sin_cos();
            std::array::from_fn(|i| center[i] + r * (c * u0[i] + s * v0[i]))
        };
        // Short enough that a sequence takes a few seconds at most.
        let most = (25.0 / r).min(2.0 * TAU);
        let segment = match self.rng.below(5) {
            0 => {
                let angle = self.rng.uniform(0.1, (TAU - 0.1).min(most)) * self.rng.sign();
                commands::arc_2d(&start, at(angle / 2.0), at(angle))
            }
            1 => commands::arc_cw_2d(&start, center, at(self.rng.uniform(0.0, TAU)), n),
            2 => commands::arc_ccw_2d(&start, center, at(self.rng.uniform(0.0, TAU)), n),
            3 => commands::arc_angle_2d(&start, center, n, self.rng.uniform(5.0, most.to_degrees()) * self.rng.sign()),
            _ => {
                let turns = self.rng.below(5) as i64 - 2;
                let end = if r < 3.0 { at(self.rng.uniform(0.0, TAU)) } else { p0 };
                commands::circle_2d(&start, center, end, n, turns)
            }
        };
        self.push(segment.expect("a valid arc"), motion);
    }

    /// CircleAbs: about any axis, with turns, to a target off the start's plane (a helix)
    /// that in 6-D also turns A, B, C; the center need not lie in the start's plane.
    fn push_circle_abs(&mut self, start: Pose, motion: Motion) {
        let n = self.rng.direction();
        let r = self.rng.uniform(1.0, 10.0);
        let p0 = xyz(&start);
        let u0 = unit3(cross3(n, self.rng.direction()));
        let lift = self.rng.uniform(-10.0, 10.0);
        let center: [f64; 3] = std::array::from_fn(|i| p0[i] - r * u0[i] + lift * n[i]);
        let (s, c) = self.rng.uniform(0.0, TAU).sin_cos();
        let v0 = cross3(n, u0);
        let rise = if self.rng.chance(0.25) { 0.0 } else { self.rng.uniform(1.0, 10.0) * self.rng.sign() };
        let mut target = start;
        for i in 0..3 {
            target[i] = p0[i] - r * u0[i] + r * (c * u0[i] + s * v0[i]) + rise * n[i];
        }
        if self.dims == 6 {
            for v in &mut target[3..] {
                *v += self.rng.uniform(-45.0, 45.0);
            }
        }
        let turns = if r < 3.0 { self.rng.below(5) as i64 - 2 } else { self.rng.sign() as i64 };
        self.push(commands::circle_abs(&start, center, n, turns, &target).expect("a valid circle"), motion);
    }
}

/// A smaller rise is a flat arc's rounding (the helices here rise 1 mm or more).
const HELIX: f64 = 1e-6;

/// How far `pose` lies off `segment`'s geometry (mm, deg for A, B, C).
fn off_geometry(segment: &Segment, pose: &Pose) -> f64 {
    let (s, e) = (segment.start(), segment.end());
    // A, B, C between their ends.
    let rotation = (3..6).map(|i| (pose[i] - pose[i].clamp(s[i].min(e[i]), s[i].max(e[i]))).abs()).fold(0.0, f64::max);
    let p = xyz(pose);
    let translation = match segment {
        Segment::Line(_) => {
            let d: [f64; 6] = std::array::from_fn(|i| e[i] - s[i]);
            let dd = d.iter().map(|x| x * x).sum::<f64>();
            let u = if dd > 0.0 {
                ((0..6).map(|i| (pose[i] - s[i]) * d[i]).sum::<f64>() / dd).clamp(0.0, 1.0)
            } else {
                0.0
            };
            return (0..6).map(|i| (pose[i] - s[i] - u * d[i]).powi(2)).sum::<f64>().sqrt();
        }
        Segment::Arc(a) => {
            // Height along the axis and distance from it; on a helix the height sets the
            // angle fraction, whose angle the point must have.
            let q = diff3(p, a.center);
            let h = dot3(q, a.normal);
            let w: [f64; 3] = std::array::from_fn(|i| q[i] - h * a.normal[i]);
            let rho = norm3(w);
            let (r0, r1) = (a.radius, a.radius + a.radius_change);
            let off_radius = rho - rho.clamp(r0.min(r1), r0.max(r1));
            if a.rise.abs() < HELIX {
                off_radius.abs().max(h.abs() - a.rise.abs())
            } else {
                let tau = h / a.rise;
                let e1 = unit3(diff3(xyz(&s), a.center));
                let e2 = cross3(a.normal, e1);
                let angle = dot3(w, e2).atan2(dot3(w, e1));
                let miss = (angle - a.sweep * tau).rem_euclid(TAU);
                let ends = (tau - tau.clamp(0.0, 1.0)).abs() * a.rise.abs();
                off_radius.abs().max(rho * miss.min(TAU - miss)).max(ends)
            }
        }
        Segment::Blend(b) => {
            // A blend next to an arc may pass close to itself, even loop: a finer search
            // where the coarse one finds no point of the curve there.
            let coarse = nearest_on_cubic(&b.ctrl, p, 32);
            if coarse > 1e-9 { nearest_on_cubic(&b.ctrl, p, 4096) } else { coarse }
        }
    };
    translation.max(rotation)
}

/// The distance from `p` to the cubic Bézier curve with control points `ctrl`: `n` + 1
/// samples, each local minimum refined by Newton's method on (B(t) - p)·B'(t) = 0.
fn nearest_on_cubic(ctrl: &[[f64; 3]; 4], p: [f64; 3], n: usize) -> f64 {
    let [p0, p1, p2, p3] = *ctrl;
    let point = |t: f64| -> [f64; 3] {
        let u = 1.0 - t;
        let w = [u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t];
        std::array::from_fn(|i| w[0] * p0[i] + w[1] * p1[i] + w[2] * p2[i] + w[3] * p3[i])
    };
    let derivatives = |t: f64| -> ([f64; 3], [f64; 3]) {
        let u = 1.0 - t;
        let d1 = std::array::from_fn(|i| {
            3.0 * (u * u * (p1[i] - p0[i]) + 2.0 * u * t * (p2[i] - p1[i]) + t * t * (p3[i] - p2[i]))
        });
        let d2 = std::array::from_fn(|i| 6.0 * (u * (p2[i] - 2.0 * p1[i] + p0[i]) + t * (p3[i] - 2.0 * p2[i] + p1[i])));
        (d1, d2)
    };
    let dist = |t: f64| norm3(diff3(point(t), p));
    let sample = |k: usize| dist(k as f64 / n as f64);
    let mut best = f64::INFINITY;
    let (mut before, mut here) = (f64::INFINITY, sample(0));
    for k in 0..=n {
        let after = if k < n { sample(k + 1) } else { f64::INFINITY };
        if here <= before && here <= after {
            let (lo, hi) = (k.saturating_sub(1) as f64 / n as f64, (k + 1).min(n) as f64 / n as f64);
            let mut t = k as f64 / n as f64;
            for _ in 0..16 {
                let q = diff3(point(t), p);
                let (d1, d2) = derivatives(t);
                let slope = dot3(d1, d1) + dot3(q, d2);
                if slope <= 0.0 {
                    break;
                }
                t = (t - dot3(q, d1) / slope).clamp(lo, hi);
            }
            best = best.min(here).min(dist(t));
        }
        (before, here) = (here, after);
    }
    best
}

/// Runs one random sequence; returns the number of cycles and what it built, or the violation.
fn check(seed: u64) -> Result<(usize, Coverage), String> {
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
    let trans = TransitionParams {
        trans_vel: rng.uniform(5.0, 400.0),
        trans_dis: rng.uniform(0.1, 6.0),
        trans_dev: rng.uniform(0.005, 0.5),
        trans_curv: rng.uniform(0.02, 2.0),
    };
    let mut seq = Sequence {
        planner: Planner::new(PERIOD),
        limits: Limits { max_vel, max_acc },
        smooth_ms,
        dims,
        transition: TransitionMode::None,
        trans,
        pushed: Vec::new(),
        coverage: Coverage::default(),
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

    // The planner holds a full stop for ceil(Ts / cycle) cycles; the group averages one
    // sample more (rt-core `Group::samples`).
    let hold = (smooth_ms / 1000.0 / PERIOD - 1e-9).ceil().max(0.0) as usize;
    let mut smoother = PathSmoother::new(hold + 1);
    smoother.reset([0.0; 6], 0.0, hold + 1);
    let mut last = [0.0; 6];
    let mut smoothed = [0.0; 6];
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
            let before = seq.pushed.len();
            seq.push_item(abort);
            if abort {
                // The checker's copy of the queue: what was kept, then the new segment.
                let kept = seq.planner.commands() - 1;
                let new = *seq.pushed.last().unwrap();
                assert_eq!(seq.pushed.len(), before + 1, "BM_ABORT is never blended");
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
        // On the running segment's geometry.
        if commands > 0 {
            let running = &seq.pushed[finished].segment;
            let off = off_geometry(running, &s.pose);
            if off > 1e-9 {
                return Err(format!("cycle {cycle}: pose {:?} is {off} off its segment {running:?}", s.pose));
            }
        }
        // Raw speeds within the feeds of the running segment and its neighbours.
        let recent_scale = if cycle < scale_high.1 + 2000 { scale_high.0.max(scale) } else { scale };
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
                    .map(|p| (p.motion.buffer, p.bounds().0, p.segment.length()))
                    .collect::<Vec<_>>()
            ));
        }
        if s.path_acc.abs() > tol(ba) {
            return Err(format!("cycle {cycle}: path acceleration {} above {ba}", s.path_acc));
        }
        last = s.pose;
        // The group's smoothing, and its finite differences.
        let previous = std::mem::replace(&mut smoothed, smoother.push(&s));
        for i in 0..6 {
            let v = (smoothed[i] - previous[i]) / PERIOD;
            let a = (v - smoothed_vel[i]) / PERIOD;
            smoothed_vel[i] = v;
            if v.abs() > tol(seq.limits.max_vel[i]) {
                return Err(format!(
                    "cycle {cycle}: coordinate {i} smoothed velocity {v} above {} (hold {hold}, halt {halt_at:?}, scale {scale_at:?}, push {late_push:?}, finished {finished}, segments {:?})",
                    seq.limits.max_vel[i],
                    seq.pushed
                        .iter()
                        .map(|p| (p.motion.buffer, kind(&p.segment), p.segment.length(), p.motion.lin.vel))
                        .collect::<Vec<_>>()
                ));
            }
            if cycle > 0 && a.abs() > tol(seq.limits.max_acc[i]) {
                return Err(format!(
                    "cycle {cycle}: coordinate {i} smoothed acceleration {a} above {} (hold {hold}, halt {halt_at:?}, scale {scale_at:?}, push {late_push:?}, finished {finished}, segments {:?})",
                    seq.limits.max_acc[i],
                    seq.pushed.iter().map(|p| (p.motion.buffer, kind(&p.segment))).collect::<Vec<_>>()
                ));
            }
        }
        let events_done = halt_at.is_none_or(|h| c > h + resume_after)
            && scale_at.is_none_or(|(at, _, _)| c > at + 150)
            && late_push.is_none_or(|(at, _)| c > at);
        if events_done && !s.moving && commands == 0 {
            let end = seq.pushed.last().unwrap().segment.end();
            return if s.pose == end {
                Ok((cycle, seq.coverage))
            } else {
                Err(format!("ended at {:?}, not {:?}", s.pose, end))
            };
        }
    }
    Err(format!(
        "did not finish in 200 000 cycles: {} commands, halt {halt_at:?} {resume_after} finished {finished} segments {:?}",
        seq.planner.commands(),
        seq.pushed
            .iter()
            .map(|p| (p.motion.buffer, kind(&p.segment), p.segment.length(), p.motion.lin.vel))
            .collect::<Vec<_>>()
    ))
}

fn kind(segment: &Segment) -> &'static str {
    match segment {
        Segment::Line(_) => "line",
        Segment::Arc(a) if a.rise.abs() >= HELIX => "helix",
        Segment::Arc(_) => "arc",
        Segment::Blend(_) => "blend",
    }
}

#[test]
fn ten_thousand_random_sequences_keep_every_constraint() {
    let mut cycles = 0;
    let mut total = Coverage::default();
    let mut failures = Vec::new();
    for seed in 0..SEQUENCES {
        match check(seed) {
            Ok((n, c)) => {
                cycles += n;
                (total.lines, total.arcs, total.helices) =
                    (total.lines + c.lines, total.arcs + c.arcs, total.helices + c.helices);
                for (t, b) in total.blends.iter_mut().zip(c.blends) {
                    *t += b;
                }
            }
            Err(e) => failures.push(format!("seed {seed}: {e}")),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {SEQUENCES} sequences violate:\n{}",
        failures.len(),
        failures[..failures.len().min(20)].join("\n")
    );
    println!(
        "{SEQUENCES} sequences, {cycles} cycles of {} ms: {} lines, {} arcs, {} helices, blends by mode {:?}",
        PERIOD * 1000.0,
        total.lines,
        total.arcs,
        total.helices,
        total.blends
    );
    assert!(cycles > 1_000_000, "the sequences ran ({cycles} cycles)");
    assert!(total.arcs > 5000 && total.helices > 1000, "arcs and helices were checked");
    assert!(total.blends[1..].iter().all(|&b| b > 500), "every transition mode blended corners: {:?}", total.blends);
}

/// The group's cycle and default smooth time (HMPL 8.3.6: 50 ms).
const POLYGON_PERIOD: f64 = 0.001;
const POLYGON_SMOOTH_MS: f64 = 50.0;
const POLYGONS: u64 = 10_000;

/// The distance from `p` to the segment from `a` to `b` (X, Y).
fn to_edge(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (d, w) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
    let dd = d[0] * d[0] + d[1] * d[1];
    let u = if dd > 0.0 { ((w[0] * d[0] + w[1] * d[1]) / dd).clamp(0.0, 1.0) } else { 0.0 };
    ((w[0] - u * d[0]).powi(2) + (w[1] - u * d[1]).powi(2)).sqrt()
}

/// One random open polygon in X, Y with TM_MAX_CORNER_DEV at a blending buffer mode, run
/// through the planner and the group's smoothing at 50 ms. The path the drives follow (the
/// segments between the cycles' smoothed poses) passes each corner within trans_dev and
/// never leaves the band of trans_dev around the polygon. Beyond trans_dev only the chords
/// count: a cycle's chord of a blend of radius r at step h lies h²/(8 r) inside it, for the
/// planner's cycle and then the smoothed one. Returns the largest corner deviation as a
/// fraction of trans_dev.
fn check_polygon(seed: u64) -> Result<f64, String> {
    let mut rng = Rng(seed ^ 0x5EED_0FC0_FFEE);
    let pick = |rng: &mut Rng, lo: f64, hi: f64| if rng.chance(0.3) { f64::INFINITY } else { rng.uniform(lo, hi) };
    let limits = Limits {
        max_vel: std::array::from_fn(|_| pick(&mut rng, 50.0, 500.0)),
        max_acc: std::array::from_fn(|_| pick(&mut rng, 2000.0, 30_000.0)),
    };
    let trans = TransitionParams {
        trans_vel: 50.0,
        trans_dis: rng.uniform(0.5, 4.0),
        trans_dev: rng.uniform(0.01, 2.0),
        trans_curv: 0.0,
    };
    let motion = Motion {
        lin: Profile {
            vel: rng.uniform(20.0, 300.0),
            acc: rng.uniform(1000.0, 20_000.0),
            dec: rng.uniform(1000.0, 20_000.0),
            smooth_ms: POLYGON_SMOOTH_MS,
        },
        ang: Profile { vel: 360.0, acc: 1800.0, dec: 1800.0, smooth_ms: POLYGON_SMOOTH_MS },
        buffer: MODES[1 + rng.below(MODES.len() as u64 - 1) as usize],
    };
    let mut planner = Planner::new(POLYGON_PERIOD);
    // Edges longer than twice the trim, turns within what a blend takes (HMPL 8.1.5 note 1).
    let mut vertices = vec![[0.0f64; 2]];
    let mut heading = rng.uniform(0.0, TAU);
    let mut blends = Vec::new();
    for k in 0..2 + rng.below(6) {
        if k > 0 {
            heading += rng.uniform(10f64, 160.0).to_radians() * rng.sign();
        }
        let len = rng.uniform(2.5 * trans.trans_dis, 40.0);
        let [x, y] = *vertices.last().unwrap();
        let next = [x + len * heading.cos(), y + len * heading.sin()];
        let (start, end) = ([x, y, 0.0, 0.0, 0.0, 0.0], [next[0], next[1], 0.0, 0.0, 0.0, 0.0]);
        let q = planner
            .push_with_transition(
                Segment::Line(Line { start, end }),
                motion,
                TransitionMode::MaxCornerDev,
                &trans,
                &limits,
            )
            .expect("room in the queue");
        if k > 0 {
            blends.push(q.blend.ok_or_else(|| format!("corner {k} not blended"))?.0);
        }
        vertices.push(next);
    }
    let samples = (POLYGON_SMOOTH_MS / 1000.0 / POLYGON_PERIOD).ceil() as usize + 1;
    let mut smoother = PathSmoother::new(samples);
    smoother.reset([0.0; 6], 0.0, samples);
    let mut poses = vec![[0.0f64; 2]];
    let mut raw_step = 0.0f64;
    let mut last_raw = [0.0f64; 2];
    for cycle in 0.. {
        if cycle > 1_000_000 {
            return Err("did not finish".into());
        }
        let s = planner.step();
        raw_step = raw_step.max(((s.pose[0] - last_raw[0]).powi(2) + (s.pose[1] - last_raw[1]).powi(2)).sqrt());
        last_raw = [s.pose[0], s.pose[1]];
        let p = smoother.push(&s);
        poses.push([p[0], p[1]]);
        if !s.moving && smoother.settled() {
            break;
        }
    }
    let radius = blends
        .iter()
        .flat_map(|b| (0..=64).filter_map(move |i| b.radius_at(i as f64 / 64.0)))
        .fold(f64::INFINITY, f64::min);
    let smoothed_step = poses
        .windows(2)
        .map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt())
        .fold(0.0, f64::max);
    let chords = (raw_step.powi(2) + smoothed_step.powi(2)) / (8.0 * radius) + 1e-9;
    let dev = trans.trans_dev;
    let mut worst = 0.0f64;
    for (k, corner) in vertices[1..vertices.len() - 1].iter().enumerate() {
        let nearest = poses.windows(2).map(|w| to_edge(*corner, w[0], w[1])).fold(f64::INFINITY, f64::min);
        if nearest > dev + chords {
            return Err(format!("corner {k} passed {nearest} mm away, trans_dev {dev} (+ chords {chords})"));
        }
        worst = worst.max(nearest / dev);
    }
    for (cycle, p) in poses.iter().enumerate() {
        let off = vertices.windows(2).map(|e| to_edge(*p, e[0], e[1])).fold(f64::INFINITY, f64::min);
        if off > dev + chords {
            return Err(format!("cycle {cycle}: {p:?} is {off} mm off the polygon, trans_dev {dev}"));
        }
    }
    let end = *vertices.last().unwrap();
    if poses.last() != Some(&end) {
        return Err(format!("ended at {:?}, not {end:?}", poses.last()));
    }
    Ok(worst)
}

#[test]
fn ten_thousand_random_polygons_keep_the_corner_deviation_with_smoothing_on() {
    let mut failures = Vec::new();
    let mut worst = 0.0f64;
    for seed in 0..POLYGONS {
        match check_polygon(seed) {
            Ok(w) => worst = worst.max(w),
            Err(e) => failures.push(format!("seed {seed}: {e}")),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {POLYGONS} polygons violate:\n{}",
        failures.len(),
        failures[..failures.len().min(20)].join("\n")
    );
    println!("{POLYGONS} polygons: the nearest pass of a corner is at most {worst} of trans_dev");
    assert!(worst > 0.99, "the blends use their tolerance ({worst})");
}

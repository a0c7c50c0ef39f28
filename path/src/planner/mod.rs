//! The planner of a group's path (HMPL 8.1): the command buffer, the feed rule, the
//! junctions between segments by buffer mode, look-ahead, halt, resume, stop, velocity
//! scale and jog, and the step that turns each cycle into a raw pose along the path.
//!
//! The group smooths the raw pose with a moving average over its smooth time Ts (HMPL 5.1's
//! S-curve), so the planner plans a trapezoid along the path, stands still for Ts at every
//! full stop inside the queue, and keeps each corner's velocity step within what Ts can
//! spread. Planning happens when a command is pushed (a backward pass that stops where
//! nothing changes); each cycle only plans the running segment's trapezoid again from where
//! the path is. Nothing here allocates after `new` or reads a clock.

mod junction;
mod profile;
mod queue;

use api::GroupError;

use crate::blend::{self, TransitionMode, TransitionParams};

use crate::sample::{Corners, Sample};
use crate::segment::Pose;
use junction::{Entry, junction_cap};
use profile::{Trapezoid, brake_to};
pub use queue::MAX_QUEUE_SIZE;
use queue::Ring;

/// The queue size until SetGrpQueueSize (HMPL 8.1: "up to 512 motion commands").
pub const DEFAULT_QUEUE_SIZE: usize = 512;

/// How a segment joins the next (HMPL table 8.1.4.1, in its order).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BufferMode {
    /// Finish the path at rest, then start the next.
    Buff,
    /// The new command discards the queue; the motion under way stops along its path.
    Abort,
    /// Blend at the lower of the two feeds.
    Low,
    /// Blend at this segment's feed.
    Prev,
    /// Blend at the next segment's feed.
    Next,
    /// Blend at the higher of the two feeds.
    High,
    /// The controller decides from look-ahead over the buffer.
    LookAhead,
}

/// The mode's number, as GetGrpBufferMode returns it.
impl From<BufferMode> for i64 {
    fn from(mode: BufferMode) -> i64 {
        mode as i64
    }
}

impl TryFrom<i64> for BufferMode {
    type Error = GroupError;

    fn try_from(value: i64) -> Result<Self, GroupError> {
        Ok(match value {
            0 => BufferMode::Buff,
            1 => BufferMode::Abort,
            2 => BufferMode::Low,
            3 => BufferMode::Prev,
            4 => BufferMode::Next,
            5 => BufferMode::High,
            6 => BufferMode::LookAhead,
            _ => return Err(GroupError::CmdBlendModeUnknown),
        })
    }
}

/// One motion profile (HMPL 8.3.6/8.3.7): mm or deg per s, per s², and the smooth time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    /// The feed: the cruise velocity along the path.
    pub vel: f64,
    /// The acceleration up to the feed.
    pub acc: f64,
    /// The deceleration down from the feed to a stop or a slower junction.
    pub dec: f64,
    /// The group's smooth time Ts, ms (0: no smoothing): the planner holds every full stop
    /// this long and keeps corner velocity steps within what Ts spreads.
    pub smooth_ms: f64,
}

/// What a command moves with: the translation's and the rotation's profile, and how it
/// joins the next command.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// X, Y, Z in mm/s, mm/s².
    pub lin: Profile,
    /// A, B, C in deg/s, deg/s², for the segments that rotate.
    pub ang: Profile,
    /// How this command joins the next.
    pub buffer: BufferMode,
}

/// SetGrpLookAheadPrm (HMPL 8.3.34, table 8.1.4.2): corner and arc acceleration (mm/s²)
/// and the chord error (mm, 0 = off).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LookAhead {
    /// The acceleration a corner's velocity step may cause per coordinate, mm/s².
    pub corner_acc: f64,
    /// The centripetal acceleration on arcs, v²/r, mm/s².
    pub arc_acc: f64,
    /// The largest distance of a cycle's chord from an arc, mm; 0 leaves the speed unbounded by it.
    pub chord_error: f64,
}

impl Default for LookAhead {
    /// HMPL 8.1.4: 5000 mm/s², 100 mm/s², chord error off.
    fn default() -> Self {
        LookAhead { corner_acc: 5000.0, arc_acc: 100.0, chord_error: 0.0 }
    }
}

/// The machine's limits per MCS coordinate (X, Y, Z, A, B, C); `INFINITY` where none.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// The velocity of each coordinate, mm/s or deg/s.
    pub max_vel: [f64; 6],
    /// The acceleration and deceleration of each coordinate, mm/s² or deg/s².
    pub max_acc: [f64; 6],
}

impl Limits {
    /// No limit on any coordinate.
    pub const NONE: Limits = Limits { max_vel: [f64::INFINITY; 6], max_acc: [f64::INFINITY; 6] };
}

/// What one command queued with its corner transition (`push_with_transition`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Queued {
    /// The tail as the blend trimmed it.
    pub trimmed_tail: Option<crate::Segment>,
    /// The blend and its motion.
    pub blend: Option<(crate::Segment, Motion)>,
    /// The command's own segment, trimmed where blended.
    pub segment: crate::Segment,
}

/// JogGroup (HMPL 8.2.7): each MCS coordinate at its own signed velocity.
#[derive(Clone, Copy, Default)]
struct Jog {
    active: bool,
    vel: [f64; 6],
    target: [f64; 6],
    acc: [f64; 6],
    dec: [f64; 6],
}

/// A group's path planner: its command buffer and the motion along it, stepped once per
/// cycle by the group, which smooths its output (`crate::smoothing`).
pub struct Planner {
    period: f64,
    queue: Ring<Entry>,
    queue_size: usize,
    look_ahead: LookAhead,
    /// Where the path is on the running (first) segment, and its velocity and acceleration.
    s: f64,
    v: f64,
    a: f64,
    path_pos: f64,
    /// Where the path stands once the queue is done (and where a jog moves).
    rest_pose: Pose,
    /// Whole cycles still to stand still after a full stop.
    hold: u32,
    halted: bool,
    scale: f64,
    jog: Jog,
    /// The corners passed in the present cycle.
    corners: Corners,
}

impl Planner {
    /// A planner stepping `period_s` seconds a cycle, at rest at the origin.
    pub fn new(period_s: f64) -> Planner {
        Planner {
            period: period_s,
            queue: Ring::new(),
            queue_size: DEFAULT_QUEUE_SIZE,
            look_ahead: LookAhead::default(),
            s: 0.0,
            v: 0.0,
            a: 0.0,
            path_pos: 0.0,
            rest_pose: [0.0; 6],
            hold: 0,
            halted: false,
            scale: 1.0,
            jog: Jog::default(),
            corners: Corners::default(),
        }
    }

    /// SetGrpQueueSize (HMPL 8.3.35); the group checks for a power of two.
    pub fn set_queue_size(&mut self, size: usize) -> Result<(), GroupError> {
        if !(1..=MAX_QUEUE_SIZE).contains(&size) {
            return Err(GroupError::CmdInvalidQueueSize);
        }
        if !self.queue.is_empty() {
            return Err(GroupError::CmdQueueIsNotEmpty);
        }
        self.queue_size = size;
        Ok(())
    }

    /// How many commands the buffer takes: 512 until SetGrpQueueSize (HMPL 8.3.35).
    pub fn queue_size(&self) -> usize {
        self.queue_size
    }

    /// GetGrpCmdNum (HMPL 8.3.27): the segments not finished, the running one included.
    pub fn commands(&self) -> usize {
        self.queue.len()
    }

    /// Forgets everything and stands still at `pose`.
    pub fn rest_at(&mut self, pose: Pose) {
        self.queue.truncate(0);
        self.rest_pose = pose;
        (self.s, self.v, self.a, self.path_pos, self.hold) = (0.0, 0.0, 0.0, 0.0, 0);
        self.halted = false;
        self.jog = Jog::default();
    }

    /// Where the queued path ends: the next segment's start.
    pub fn end_pose(&self) -> Pose {
        self.queue.last().map_or(self.rest_pose, end_of)
    }

    /// Queues a command's segment after the corner transition of HMPL 8.1.5 where there is
    /// one: the tail is trimmed where the path can still slow down for it (`tail`), the
    /// blend follows (at `trans_vel` with TM_CONST_VEL and TM_CORNER_DIST), then the
    /// segment, trimmed. A junction `blend::corner` does not blend, and BM_ABORT, queue the
    /// segment as it is. Room for both is checked first: a full queue refuses with nothing
    /// changed (`CmdQueueFull`).
    pub fn push_with_transition(
        &mut self,
        segment: crate::Segment,
        motion: Motion,
        mode: TransitionMode,
        trans: &TransitionParams,
        limits: &Limits,
    ) -> Result<Queued, GroupError> {
        let room = self.queue_size() - self.commands();
        if room == 0 {
            return Err(GroupError::CmdQueueFull);
        }
        let mut queued = Queued { trimmed_tail: None, blend: None, segment };
        if motion.buffer != BufferMode::Abort
            && room >= 2
            && let Some((prev, travelled)) = self.tail()
            && let Some((trimmed, corner, next)) = blend::corner(&prev, &segment, mode, trans)
            && trimmed.length() > travelled * prev.length()
        {
            self.replace_tail(trimmed);
            let mut blended = motion;
            if matches!(mode, TransitionMode::ConstVel | TransitionMode::CornerDist) {
                blended.lin.vel = trans.trans_vel.min(motion.lin.vel);
            }
            self.push(corner, blended, limits)?;
            (queued.trimmed_tail, queued.blend, queued.segment) = (Some(trimmed), Some((corner, blended)), next);
        }
        self.push(queued.segment, motion, limits)?;
        Ok(queued)
    }

    /// Queues a segment (HMPL 8.1: one command, one segment). With BM_ABORT the motion under
    /// way first stops along its path and the rest of the queue is dropped; the group builds
    /// that segment from `stopping_pose`. A full queue refuses with nothing changed.
    pub fn push(&mut self, segment: crate::Segment, motion: Motion, limits: &Limits) -> Result<(), GroupError> {
        if self.jog.active {
            return Err(GroupError::CmdInvalidMoving);
        }
        let abort = motion.buffer == BufferMode::Abort;
        let kept = if abort { self.stop_point().map_or(0, |(k, _)| k + 1) } else { self.queue.len() };
        if kept + 1 > self.queue_size {
            return Err(GroupError::CmdQueueFull);
        }
        if abort {
            self.cut_at_stop();
        }
        let mut entry = Entry::new(segment, motion, limits, &self.look_ahead, self.period);
        let n = self.queue.len();
        let changed = self.guard_curves(&mut entry, n);
        if let Some(prev) = self.queue.last_mut() {
            let cap = if prev.stop_after { 0.0 } else { junction_cap(prev, &entry, &self.look_ahead, self.period) };
            prev.exit_cap = cap;
            entry.v_in = cap;
        }
        self.queue.push(entry);
        self.plan_backward(changed);
        Ok(())
    }

    /// The limits of the curves within one smoothing window of `entry` (the path it covers
    /// in the group's window at the fastest feed around, `crate::smoothing`) hold on both:
    /// `entry` keeps those of the curves among the `before` entries before it, and if it is
    /// a curve, they keep its. A stop in between (its hold lasts the window) ends the
    /// search. The junctions of the entries changed are planned again; returns the first.
    fn guard_curves(&mut self, entry: &mut Entry, before: usize) -> usize {
        if entry.smooth <= 0.0 {
            return before;
        }
        let window = ((entry.smooth / self.period - 1e-9).ceil() + 1.0) * self.period;
        let (mut fastest, mut between, mut first) = (entry.vel, 0.0, before);
        // A corner between `entry` and the entry looked at (or at either's far end).
        let mut corner = before > 0 && self.queue.get(before - 1).is_some_and(|e| e.turns_into(entry));
        for k in (0..before).rev() {
            let e = *self.queue.get(k).expect("k < before");
            fastest = fastest.max(e.vel);
            let reach = window * fastest;
            if e.stop_after || between >= reach {
                break;
            }
            corner |= k > 0 && self.queue.get(k - 1).is_some_and(|p| p.turns_into(&e));
            let (mut e_curve, mut entry_curve) = (e, *entry);
            if corner {
                (e_curve, entry_curve) = (e.near_corner(reach), entry.near_corner(reach));
                entry.keep_within(&entry_curve);
                self.queue.get_mut(k).expect("k < before").keep_within(&e_curve);
                first = first.min(k);
            }
            if e.is_curved() {
                entry.keep_within(&e_curve);
            }
            if entry.is_curved() {
                self.queue.get_mut(k).expect("k < before").keep_within(&entry_curve);
                first = first.min(k);
            }
            between += e.end;
        }
        for k in first.max(1)..before {
            let next = *self.queue.get(k).expect("k < before");
            let prev = self.queue.get_mut(k - 1).expect("k >= 1");
            let cap = if prev.stop_after { 0.0 } else { junction_cap(prev, &next, &self.look_ahead, self.period) };
            prev.exit_cap = cap;
            self.queue.get_mut(k).expect("k < before").v_in = cap;
        }
        first
    }

    /// The last queued segment and the fraction of it the path passes whatever comes next:
    /// up to where a stop begun now would end, if that is on it (the path could not slow
    /// down for a shorter tail any sooner).
    pub fn tail(&self) -> Option<(crate::Segment, f64)> {
        let e = self.queue.last()?;
        let passed = match self.stop_point() {
            Some((k, s)) if k + 1 == self.queue.len() => s,
            _ => 0.0,
        };
        Some((e.segment, if e.full > 0.0 { passed / e.full } else { 0.0 }))
    }

    /// Replaces the last segment by `segment` (the same start, shortened for a corner blend)
    /// and plans again. The group replaces only a tail whose new end lies beyond what
    /// [`Planner::tail`] says the path passes, and pushes the blend in the same cycle.
    pub fn replace_tail(&mut self, segment: crate::Segment) {
        let Some(old) = self.queue.last().copied() else { return };
        let mut entry = Entry::new(segment, old.motion, &old.limits, &self.look_ahead, self.period);
        entry.stop_after = old.stop_after;
        let n = self.queue.len();
        let changed = self.guard_curves(&mut entry, n - 1);
        if old.end < old.full {
            entry.end = entry.full.min(old.end);
        }
        let n = self.queue.len();
        if n >= 2 {
            let prev = self.queue.get_mut(n - 2).expect("n >= 2");
            let cap = if prev.stop_after { 0.0 } else { junction_cap(prev, &entry, &self.look_ahead, self.period) };
            prev.exit_cap = cap;
            entry.v_in = cap;
        }
        *self.queue.last_mut().expect("tail exists") = entry;
        self.plan_backward(changed);
    }

    /// SetGrpLookAheadPrm (HMPL 8.3.34), for the segments pushed from now on.
    pub fn set_look_ahead(&mut self, look_ahead: LookAhead) {
        self.look_ahead = look_ahead;
    }

    /// HaltGroup (HMPL 8.2.5): velocity to 0 along the path; the plan is kept.
    pub fn halt(&mut self) {
        self.halted = true;
        self.jog.target = [0.0; 6];
    }

    /// ResumeGroup (HMPL 8.2.6): on to the same target.
    pub fn resume(&mut self) {
        self.halted = false;
    }

    /// Whether HaltGroup holds the path, until ResumeGroup or StopGroup.
    pub fn is_halted(&self) -> bool {
        self.halted
    }

    /// StopGroup (HMPL 8.2.4): decelerate along the path, then the queue is empty.
    pub fn stop(&mut self) {
        self.halted = false;
        self.jog.target = [0.0; 6];
        self.cut_at_stop();
    }

    /// Where a stop now would come to rest (BM_ABORT's segment starts there).
    pub fn stopping_pose(&self) -> Pose {
        if self.jog.active {
            return std::array::from_fn(|i| {
                let (v, dec) = (self.jog.vel[i], self.jog.dec[i]);
                if v == 0.0 { self.rest_pose[i] } else { self.rest_pose[i] + v * v.abs() / (2.0 * dec) }
            });
        }
        match self.stop_point() {
            Some((k, s)) => {
                let e = self.queue.get(k).expect("stop point is queued");
                pose_on(e, s)
            }
            None => self.rest_pose,
        }
    }

    /// SetGrpVelScale (HMPL 8.3.28), 0..=100 %: a new cruise velocity the path accelerates
    /// or decelerates to within its limits.
    pub fn set_velocity_scale(&mut self, percent: f64) {
        self.scale = percent.clamp(0.0, 100.0) / 100.0;
    }

    /// JogGroup (HMPL 8.2.7): MCS coordinate `coordinate` (0..=5 X..C) at a signed velocity,
    /// with the translation's or the rotation's profile, until a jog at 0, halt or stop.
    /// Ignored while path segments are queued (the group refuses it with CmdInvalidMoving).
    pub fn jog(&mut self, coordinate: usize, velocity: f64, motion: Motion, limits: &Limits) {
        if coordinate >= 6 || !self.queue.is_empty() || (!self.jog.active && velocity == 0.0) {
            return;
        }
        let p = if coordinate < 3 { motion.lin } else { motion.ang };
        let (max_vel, max_acc) = (limits.max_vel[coordinate], limits.max_acc[coordinate]);
        if !self.jog.active {
            // A stop's hold is for the path; the jog starts from rest at once.
            self.hold = 0;
        }
        self.jog.active = true;
        self.jog.target[coordinate] = velocity.clamp(-max_vel, max_vel);
        self.jog.acc[coordinate] = p.acc.min(max_acc);
        self.jog.dec[coordinate] = p.dec.min(max_acc);
    }

    /// Whether the path generator still emits (IsGrpMoving, HMPL 8.4.2): a jog, velocity
    /// left, or segments queued and not halted.
    pub fn is_moving(&self) -> bool {
        self.jog.active || self.v != 0.0 || (!self.queue.is_empty() && !self.halted)
    }

    /// One cycle.
    pub fn step(&mut self) -> Sample {
        self.corners = Corners::default();
        if self.jog.active {
            return self.step_jog();
        }
        if self.hold > 0 {
            self.hold -= 1;
            return self.sample();
        }
        let mut dt = self.period;
        let sigma = if self.halted { 0.0 } else { self.scale };
        while let Some(head) = self.queue.get(0).copied() {
            let last = self.queue.len() == 1;
            let (target, cap) = if last { (0.0, 0.0) } else { (head.exit_plan * sigma, head.exit_cap) };
            let trap = Trapezoid::plan(self.v, head.end - self.s, head.vel * sigma, target, head.acc, head.dec);
            let duration = trap.duration();
            if duration > dt {
                let (ds, v, a) = trap.at(dt);
                (self.s, self.v, self.a) = (self.s + ds, v, a);
                self.path_pos += ds;
                break;
            }
            // The segment ends within this cycle.
            dt -= duration;
            self.path_pos += (head.end - self.s).max(0.0);
            self.rest_pose = end_of(&head);
            self.queue.pop_front();
            self.s = 0.0;
            if last || head.stop_after {
                // At rest; stand still for Ts so the smoothed path stops too (the rest of
                // this cycle, then whole cycles).
                (self.v, self.a) = (0.0, 0.0);
                self.hold = (head.smooth / self.period - 1e-9).ceil().max(0.0) as u32;
                break;
            }
            self.v = trap.exit().min(cap);
            if let Some(next) = self.queue.get(0) {
                let step: [f64; 6] = std::array::from_fn(|i| next.g_start[i] - head.g_end[i]);
                if step.iter().any(|d| d.abs() > junction::EPS) {
                    self.corners.add(&step, self.path_pos);
                }
            }
        }
        self.sample()
    }

    fn sample(&self) -> Sample {
        let pose = self.queue.get(0).map_or(self.rest_pose, |e| pose_on(e, self.s));
        Sample {
            pose,
            path_pos: self.path_pos,
            path_vel: self.v,
            path_acc: self.a,
            moving: self.is_moving(),
            corners: self.corners,
            jog: false,
        }
    }

    fn step_jog(&mut self) -> Sample {
        let dt = self.period;
        let sigma = if self.halted { 0.0 } else { self.scale };
        let speed = |v: &[f64; 6]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let before = speed(&self.jog.vel);
        for i in 0..6 {
            let target = self.jog.target[i] * sigma;
            let (mut v, mut t, mut dist) = (self.jog.vel[i], dt, 0.0);
            // Towards zero first at the deceleration where the sign changes or the speed
            // falls, then towards the target at the acceleration.
            if v != 0.0 && (target * v < 0.0 || target.abs() < v.abs()) {
                let goal = if target * v < 0.0 { 0.0 } else { target };
                let (nv, d, used) = ramp_toward(v, goal, self.jog.dec[i], t);
                (v, dist, t) = (nv, d, t - used);
            }
            if t > 0.0 {
                let (nv, d, used) = ramp_toward(v, target, self.jog.acc[i], t);
                (v, dist) = (nv, dist + d + nv * (t - used));
            }
            self.jog.vel[i] = v;
            self.rest_pose[i] += dist;
            self.path_pos += dist.abs();
        }
        let after = speed(&self.jog.vel);
        (self.v, self.a) = (0.0, (after - before) / dt);
        if self.jog.vel == [0.0; 6] && (self.jog.target == [0.0; 6] || sigma == 0.0) {
            self.jog = Jog::default();
        }
        Sample {
            pose: self.rest_pose,
            path_pos: self.path_pos,
            path_vel: after,
            path_acc: self.a,
            moving: self.jog.active,
            corners: Corners::default(),
            jog: true,
        }
    }

    /// Where a stop begun now ends: the queue index and the distance on that segment.
    fn stop_point(&self) -> Option<(usize, f64)> {
        let (mut v, mut s) = (self.v, self.s);
        for k in 0..self.queue.len() {
            let e = self.queue.get(k).expect("k < len");
            let rest = (e.end - s).max(0.0);
            let d = v * v / (2.0 * e.dec);
            if d <= rest || k + 1 == self.queue.len() {
                return Some((k, (s + d).min(e.end)));
            }
            v = brake_to(v, rest, e.dec);
            s = 0.0;
        }
        None
    }

    /// Cuts the queue where a stop begun now ends: every junction up to there is passed as
    /// slowly as braking allows, the segment there ends at rest, the rest is dropped.
    fn cut_at_stop(&mut self) {
        let Some((k, s)) = self.stop_point() else { return };
        self.queue.truncate(k + 1);
        for i in 0..=k {
            self.queue.get_mut(i).expect("i <= k").exit_plan = 0.0;
        }
        let e = self.queue.get_mut(k).expect("k is queued");
        (e.end, e.exit_cap, e.stop_after) = (s, 0.0, true);
    }

    /// The backward pass from the tail: each junction's velocity such that everything after
    /// it can still stop by the end of the queue. It stops at the first junction before
    /// entry `changed` that it leaves unchanged, since nothing before that depends on what
    /// follows.
    fn plan_backward(&mut self, changed: usize) {
        let n = self.queue.len();
        let Some(tail) = self.queue.last_mut() else { return };
        tail.exit_plan = 0.0;
        for i in (0..n - 1).rev() {
            let next = self.queue.get(i + 1).expect("i + 1 < n");
            let reach = (next.exit_plan * next.exit_plan + 2.0 * next.dec * next.end).sqrt();
            let e = self.queue.get_mut(i).expect("i < n");
            let planned = e.exit_cap.min(reach);
            if planned == e.exit_plan && i + 2 < n && i < changed {
                break;
            }
            e.exit_plan = planned;
        }
    }
}

/// The pose `s` along an entry.
fn pose_on(e: &Entry, s: f64) -> Pose {
    if s >= e.full {
        e.segment.end()
    } else if e.full > 0.0 {
        e.segment.pose_at(s / e.full)
    } else {
        e.segment.start()
    }
}

/// Where an entry ends (its segment's end, or where a stop cut it).
fn end_of(e: &Entry) -> Pose {
    pose_on(e, e.end)
}

/// From `v` towards `target` at `rate` for at most `t`: the new velocity, the distance and
/// the time the ramp took.
fn ramp_toward(v: f64, target: f64, rate: f64, t: f64) -> (f64, f64, f64) {
    let need = (target - v).abs() / rate;
    let used = need.min(t);
    let nv = if need > t { v + (target - v).signum() * rate * t } else { target };
    (nv, (v + nv) / 2.0 * used, used)
}

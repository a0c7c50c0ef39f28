//! The axis profile generator (HMPL 5.1, fig. 5.1.1 and 5.1.2): T-curve moves, velocity
//! moves and PVT tables, re-planned on the fly (new target, velocity, scale), queued in
//! buffer mode 1 (HMPL 5.3.42), halted and resumed. Its output is the T-curve; the
//! axis' filter chain (`filter.rs`) smooths it into an S-curve. Everything is fixed-size:
//! the RT thread plans without allocating.

use crate::pvt::Pvt;
use devices::profile::{Kinematics, Limits, Trapezoid, ramp_velocity};

/// Commands the axis queue holds in buffer mode 1 (`eERR_AXIS_CMD_QUEUE_FULL` beyond).
pub const QUEUE_CAPACITY: usize = 16;

/// A motion command. A PVT table is held inline: boxing it would allocate in the RT thread.
#[derive(Clone, Copy, Debug)]
#[allow(clippy::large_enum_variant)]
pub enum Move {
    /// To a position, axis units (HMPL 5.2.4).
    Absolute(f64),
    /// By a distance from the target in force, axis units (HMPL 5.2.5).
    Relative(f64),
    /// Signed velocity, run until stopped (HMPL 5.2.6).
    Velocity(f64),
    /// Through a table of points (HMPL 5.2.8).
    Pvt(Pvt),
}

/// The profile of HMPL 5.3: maximum velocity, acceleration, deceleration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    /// Axis units/s.
    pub vel: f64,
    /// Axis units/s².
    pub acc: f64,
    /// Axis units/s², down to a target or a lower velocity.
    pub dec: f64,
}

/// What a halted or paused motion resumes to.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Intent {
    Position(f64),
    Velocity(f64),
}

#[derive(Clone, Copy, Debug)]
#[allow(clippy::large_enum_variant)]
enum Running {
    Position { plan: Trapezoid },
    Velocity { target: f64 },
    Pvt { pvt: Pvt },
    Stopping { plan: Trapezoid },
}

/// Why a command was not taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QueueFull;

/// One axis' profile generator: the T-curve of its present move, and the moves queued behind it.
pub struct Generator {
    period_s: f64,
    profile: Profile,
    /// Velocity override 0..1 (HMPL 5.3.37 in percent).
    scale: f64,
    /// The T-curve's state, where the next cycle plans from.
    raw: Kinematics,
    running: Option<Running>,
    elapsed: f64,
    /// Set by `halt` (resumed by `resume`) or by a scale of 0 (resumed by a scale above 0).
    halted: Option<Intent>,
    paused: Option<Intent>,
    /// Boxed: a queue of inline PVT tables is about 20 KiB, which inline made an axis
    /// span five pages and its hot fields land apart; the cycle touches every axis.
    queue: Box<[Option<Move>; QUEUE_CAPACITY]>,
    queue_head: usize,
    queue_len: usize,
}

impl Generator {
    /// At rest at 0, nothing planned, stepping `period_s` s a cycle.
    pub fn new(period_s: f64, profile: Profile) -> Self {
        Generator {
            period_s,
            profile,
            scale: 1.0,
            raw: Kinematics::default(),
            running: None,
            elapsed: 0.0,
            halted: None,
            paused: None,
            queue: Box::new([None; QUEUE_CAPACITY]),
            queue_head: 0,
            queue_len: 0,
        }
    }

    /// The T-curve's state, where the next cycle plans from.
    pub fn raw(&self) -> Kinematics {
        self.raw
    }

    /// Continues from a motion someone else produced (a gear leaving its slave): the
    /// state becomes `k`, with nothing planned.
    pub fn take_over(&mut self, k: Kinematics) {
        self.running = None;
        self.halted = None;
        self.paused = None;
        self.clear_queue();
        self.raw = k;
    }

    /// A plan runs (the filter chain after it may still be settling).
    pub fn is_running(&self) -> bool {
        self.running.is_some()
    }

    /// A stop (Stop, Halt, a limit) is decelerating the axis.
    pub fn is_stopping(&self) -> bool {
        matches!(self.running, Some(Running::Stopping { .. }))
    }

    /// A Halt (HMPL 5.2.10) or a scale of 0 holds the motion, which a Resume or a scale
    /// above 0 takes up again.
    pub fn is_halted(&self) -> bool {
        self.halted.is_some()
    }

    /// Something runs, is halted or paused, or waits in the queue.
    pub fn is_busy(&self) -> bool {
        self.running.is_some() || self.halted.is_some() || self.paused.is_some() || self.queue_len > 0
    }

    /// The position the running move ends at, if it is a move to a position.
    pub fn target(&self) -> Option<f64> {
        match self.running {
            Some(Running::Position { plan }) => Some(plan.target()),
            Some(Running::Pvt { pvt }) => Some(pvt.last().pos),
            _ => self.halted.or(self.paused).and_then(|i| match i {
                Intent::Position(p) => Some(p),
                Intent::Velocity(_) => None,
            }),
        }
    }

    /// Commands waiting in the queue (HMPL 5.3.44).
    pub fn cmd_num(&self) -> usize {
        self.queue_len
    }

    /// At rest at `pos`: nothing running, nothing queued.
    pub fn reset(&mut self, pos: f64) {
        self.take_over(Kinematics { pos, vel: 0.0, acc: 0.0 });
    }

    fn limits(&self) -> Limits {
        Limits { vel: self.profile.vel * self.scale, acc: self.profile.acc, dec: self.profile.dec }
    }

    /// A motion command: in buffer mode 0 it replaces what runs, in mode 1 it waits its turn.
    pub fn command(&mut self, m: Move, buffered: bool) -> Result<(), QueueFull> {
        if buffered && self.is_busy() {
            if self.queue_len == QUEUE_CAPACITY {
                return Err(QueueFull);
            }
            // A relative move counts from where the moves before it end.
            let resolved = match m {
                Move::Relative(d) => Move::Absolute(self.end_of_queue() + d),
                other => other,
            };
            self.queue[(self.queue_head + self.queue_len) % QUEUE_CAPACITY] = Some(resolved);
            self.queue_len += 1;
            return Ok(());
        }
        self.clear_queue();
        self.halted = None;
        self.paused = None;
        let m = match m {
            Move::Relative(d) => Move::Absolute(self.target().unwrap_or(self.raw.pos) + d),
            other => other,
        };
        self.start(m);
        Ok(())
    }

    /// Where the axis will stand when everything queued has run: what a relative move
    /// counts from (in buffer mode 0 nothing is queued).
    pub fn end_of_queue(&self) -> f64 {
        let mut end = self.target().unwrap_or(self.raw.pos);
        for i in 0..self.queue_len {
            match self.queue[(self.queue_head + i) % QUEUE_CAPACITY] {
                Some(Move::Absolute(p)) => end = p,
                Some(Move::Pvt(pvt)) => end = pvt.last().pos,
                _ => {}
            }
        }
        end
    }

    fn start(&mut self, m: Move) {
        self.elapsed = 0.0;
        let intent = match m {
            Move::Absolute(p) => Intent::Position(p),
            Move::Relative(d) => Intent::Position(self.raw.pos + d),
            Move::Velocity(v) => Intent::Velocity(v),
            Move::Pvt(pvt) => {
                self.running = Some(Running::Pvt { pvt });
                return;
            }
        };
        self.pursue(intent);
    }

    /// Plans toward an intent from the present state, with the present limits.
    fn pursue(&mut self, intent: Intent) {
        self.elapsed = 0.0;
        let limits = self.limits();
        if limits.vel <= 0.0 {
            // A scale of 0 holds the motion where it can stop, to carry on when raised.
            self.paused = Some(intent);
            self.stop_with(self.profile.dec);
            return;
        }
        self.running = Some(match intent {
            Intent::Position(target) => {
                Running::Position { plan: Trapezoid::plan(self.raw.pos, self.raw.vel, target, limits) }
            }
            Intent::Velocity(v) => Running::Velocity { target: v * self.scale },
        });
    }

    fn intent(&self) -> Option<Intent> {
        match self.running {
            Some(Running::Position { plan }) => Some(Intent::Position(plan.target())),
            Some(Running::Velocity { target }) => Some(Intent::Velocity(target / self.scale.max(f64::MIN_POSITIVE))),
            Some(Running::Pvt { pvt }) => Some(Intent::Position(pvt.last().pos)),
            _ => None,
        }
    }

    /// Stop (HMPL 5.2.9): decelerate with `dec`, forget the queue and any halt.
    pub fn stop_with(&mut self, dec: f64) {
        self.clear_queue();
        self.halted = None;
        self.elapsed = 0.0;
        self.running =
            (self.raw.vel != 0.0).then(|| Running::Stopping { plan: Trapezoid::stop(self.raw.pos, self.raw.vel, dec) });
    }

    /// Halt (HMPL 5.2.10): decelerate to rest, keeping the move for `resume`.
    pub fn halt(&mut self) {
        if let Some(intent) = self.intent().or(self.paused) {
            // Counted out, the queue's entries outlive the stop's `clear_queue`.
            let (head, len) = (self.queue_head, std::mem::take(&mut self.queue_len));
            self.stop_with(self.profile.dec);
            (self.queue_head, self.queue_len) = (head, len);
            self.halted = Some(intent);
        }
    }

    /// Resume (HMPL 5.2.11): carry on to the halted move's target.
    pub fn resume(&mut self) {
        if let Some(intent) = self.halted.take() {
            self.pursue(intent);
        }
    }

    /// New limits or scale while moving: the running move is re-planned from where it is.
    pub fn set_profile(&mut self, profile: Profile) {
        self.profile = profile;
        self.replan();
    }

    /// The velocity override as a factor (SetVelScale's percent / 100, times the run
    /// speed): the move under way is re-planned to it; 0 halts it.
    pub fn set_scale(&mut self, scale: f64) {
        let intent = self.intent();
        let velocity_unscaled = intent.and_then(|i| match i {
            Intent::Velocity(v) => Some(v),
            Intent::Position(_) => None,
        });
        self.scale = scale;
        if let Some(v) = velocity_unscaled {
            self.pursue(Intent::Velocity(v));
        } else {
            self.replan();
        }
    }

    fn replan(&mut self) {
        if let Some(intent) = self.paused.take() {
            self.pursue(intent);
        } else if let Some(Running::Position { plan }) = self.running {
            self.pursue(Intent::Position(plan.target()));
        } else if let Some(intent @ Intent::Velocity(_)) = self.intent() {
            self.pursue(intent);
        }
    }

    /// Empties the queue. Only the held entries are cleared (the others are `None`
    /// already): a disabled axis rests every cycle, and a whole queue of inline PVT
    /// tables is about 20 KiB to write.
    fn clear_queue(&mut self) {
        for i in 0..self.queue_len {
            self.queue[(self.queue_head + i) % QUEUE_CAPACITY] = None;
        }
        self.queue_head = 0;
        self.queue_len = 0;
    }

    fn next_queued(&mut self) -> Option<Move> {
        if self.queue_len == 0 {
            return None;
        }
        let m = self.queue[self.queue_head].take();
        self.queue_head = (self.queue_head + 1) % QUEUE_CAPACITY;
        self.queue_len -= 1;
        m
    }

    /// One cycle; returns the T-curve's next sample.
    pub fn step(&mut self) -> Kinematics {
        let dt = self.period_s;
        self.elapsed += dt;
        let (limits, elapsed) = (self.limits(), self.elapsed);
        let mut finished = false;
        self.raw = match self.running {
            None => Kinematics { pos: self.raw.pos, vel: 0.0, acc: 0.0 },
            Some(Running::Position { plan } | Running::Stopping { plan }) => {
                finished = elapsed >= plan.duration();
                plan.at(elapsed)
            }
            Some(Running::Pvt { pvt }) => {
                finished = elapsed >= pvt.duration();
                let k = pvt.at(elapsed);
                if finished { Kinematics { pos: pvt.last().pos, vel: 0.0, acc: 0.0 } } else { k }
            }
            Some(Running::Velocity { target }) => {
                let v = ramp_velocity(self.raw.vel, target, limits.acc, limits.dec, dt);
                Kinematics { pos: self.raw.pos + (self.raw.vel + v) / 2.0 * dt, vel: v, acc: (v - self.raw.vel) / dt }
            }
        };
        if finished {
            self.running = None;
            if self.halted.is_none()
                && self.paused.is_none()
                && let Some(next) = self.next_queued()
            {
                self.start(next);
            }
        }
        self.raw
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Steps until nothing runs; returns where the profile stands.
    fn run_out(g: &mut Generator) -> f64 {
        for _ in 0..100_000 {
            if !g.is_running() {
                break;
            }
            g.step();
        }
        g.raw().pos
    }

    /// HMPL 5.2.10 and 5.2.11 in buffer mode 1: a halt stops short and keeps the moves
    /// queued behind the halted one; resume runs the halted move, then the queue.
    #[test]
    fn a_halt_keeps_the_queue_for_resume() {
        let mut g = Generator::new(1e-3, Profile { vel: 100.0, acc: 1000.0, dec: 1000.0 });
        for m in [Move::Absolute(10.0), Move::Absolute(20.0), Move::Relative(5.0)] {
            g.command(m, true).unwrap();
        }
        for _ in 0..50 {
            g.step();
        }
        assert_eq!((g.cmd_num(), g.end_of_queue()), (2, 25.0), "two moves wait behind the first");
        g.halt();
        assert!(g.is_halted());
        let stopped = run_out(&mut g);
        assert!(stopped < 10.0, "halted short of the first target: {stopped}");
        assert_eq!((g.cmd_num(), g.end_of_queue()), (2, 25.0), "the halt kept the queue");
        g.resume();
        let mut end = run_out(&mut g);
        while g.cmd_num() > 0 || g.is_running() {
            g.step();
            end = run_out(&mut g);
        }
        assert_eq!(end, 25.0, "the halted move, then the two queued ones");
    }
}

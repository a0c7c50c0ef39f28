//! Homing mode (hm, 0x6060 = 6; CoE manual 3.2, tables 3-6 to 3-8).
//!
//! A method is a seek for a reference (a limit switch, an edge of the home switch, a hard
//! stop or the first index pulse) at the fast speed 0x6099:01, then a search for the first
//! index beyond that reference at the slow speed 0x6099:02, with acceleration and
//! deceleration 0x609A. The drive then moves to the index and makes that point read as the
//! home offset 0x607C. Statusword bits 13, 12 and 10 follow table 3-7.

use crate::cia402::controlword::NEW_SET_POINT;
use crate::cia402::statusword::{OMS_12, OMS_13, TARGET_REACHED};
use crate::drive::DriveModel;
use crate::drive::modes::{ModeInput, Setpoint};
use crate::drive::od;
use crate::drive::travel::Edge;
use crate::profile::{Limits, Trapezoid, ramp_velocity};
use config::DriveSettings;

/// A reference a seek looks for.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Goal {
    NegativeLimit,
    PositiveLimit,
    /// The home switch's left (L) or right (R) boundary.
    SwitchEdge {
        left: bool,
    },
    /// The first index mark beyond `after` (raw counts) in the direction of travel.
    Index {
        after: Option<f64>,
    },
    HardStop,
}

/// What follows the first reference.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Then {
    /// The reference is the home.
    Home,
    /// Search the first index beyond the reference in this direction, slowly.
    Index { dir: f64 },
    /// Move this many counts (signed) from the reference; there is home (methods -4, -5).
    Offset(f64),
}

/// How a supported method starts (CoE manual table 3-8).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Plan {
    /// No motion: the present position is home (37, and -3 on drives that support it).
    HereIsHome,
    Seek {
        dir: f64,
        fast: bool,
        goal: Goal,
        then: Then,
    },
}

fn method_plan(method: i64, on_switch: bool, model: DriveModel, settings: &DriveSettings) -> Option<Plan> {
    let seek = |dir: f64, fast: bool, goal: Goal, then: Then| Some(Plan::Seek { dir, fast, goal, then });
    // Methods 7 to 14: the reference edge, the index direction after it, and the start
    // direction off the switch. On the switch, the start is toward the reference edge.
    let switch = |left: bool, index_dir: f64, off_dir: f64| {
        let dir = if on_switch { if left { -1.0 } else { 1.0 } } else { off_dir };
        seek(dir, true, Goal::SwitchEdge { left }, Then::Index { dir: index_dir })
    };
    match method {
        1 => seek(-1.0, true, Goal::NegativeLimit, Then::Index { dir: 1.0 }),
        2 => seek(1.0, true, Goal::PositiveLimit, Then::Index { dir: -1.0 }),
        7 => switch(true, -1.0, 1.0),
        8 => switch(true, 1.0, 1.0),
        9 => switch(false, -1.0, 1.0),
        10 => switch(false, 1.0, 1.0),
        11 => switch(false, 1.0, -1.0),
        // The manual's "slow positive" on the switch contradicts its own "left of R";
        // like CiA 402 and method 7 by symmetry, the search runs negative (docs/drive.md).
        12 => switch(false, -1.0, -1.0),
        13 => switch(true, 1.0, -1.0),
        14 => switch(true, -1.0, -1.0),
        33 => seek(-1.0, false, Goal::Index { after: None }, Then::Home),
        34 => seek(1.0, false, Goal::Index { after: None }, Then::Home),
        37 => Some(Plan::HereIsHome),
        -1 => seek(-1.0, true, Goal::HardStop, Then::Index { dir: 1.0 }),
        -2 => seek(1.0, true, Goal::HardStop, Then::Index { dir: -1.0 }),
        // Absolute position set: multi-turn absolute motors on D1-N and D2 only.
        -3 if settings.multi_turn_absolute && matches!(model, DriveModel::D1N | DriveModel::D2) => {
            Some(Plan::HereIsHome)
        }
        -4 if model == DriveModel::D1N => {
            seek(1.0, true, Goal::HardStop, Then::Offset(-(settings.end_stop_offset as f64)))
        }
        -5 if model == DriveModel::D1N => {
            seek(-1.0, true, Goal::HardStop, Then::Offset(settings.end_stop_offset as f64))
        }
        _ => None,
    }
}

#[derive(Clone, Copy, Debug)]
struct Moving {
    plan: Trapezoid,
    elapsed: f64,
}

impl Moving {
    fn new(plan: Trapezoid) -> Self {
        Moving { plan, elapsed: 0.0 }
    }

    /// Advances; the sample, and whether the move is over.
    fn advance(&mut self, dt: f64) -> (Setpoint, bool) {
        self.elapsed += dt;
        let k = self.plan.at(self.elapsed);
        (Setpoint::Position { pos: k.pos, vel: k.vel }, self.elapsed >= self.plan.duration())
    }
}

#[derive(Clone, Copy, Debug)]
enum Phase {
    /// Moving in `dir` at a homing speed until `goal` shows.
    Seek { dir: f64, fast: bool, goal: Goal, then: Then, velocity: f64, pos: f64, pushing_s: f64 },
    /// Braking after a reference at raw position `at`, before what comes next.
    Brake { motion: Moving, at: f64, then: Then },
    /// Moving to the home point (raw `home`).
    ToHome { motion: Moving, home: f64 },
}

#[derive(Clone, Copy, Debug)]
enum State {
    NotStarted,
    Running(Phase),
    /// Decelerating after an interruption (`error` false) or an error.
    Stopping {
        motion: Option<Moving>,
        error: bool,
    },
    Interrupted,
    Error,
    Attained,
}

/// What the drive must do after a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HomingEvent {
    /// Homing attained: the raw position that reads as the home offset from now on.
    Home { raw: f64 },
    /// A homing error: 0x603F = 0x8613 (CoE manual 3.2, B).
    Error,
    /// A new homing run started: a previous homing error is cleared.
    Started,
}

#[derive(Clone, Debug)]
pub struct Homing {
    state: State,
    start_bit: bool,
    model: DriveModel,
    settings: DriveSettings,
}

impl Homing {
    /// Entering homing mode. Bit 4 already high counts as a start (CoE manual 3.2: switch
    /// the mode away and back with bit 4 held to restart).
    pub fn new(model: DriveModel, settings: DriveSettings) -> Self {
        Homing { state: State::NotStarted, start_bit: false, model, settings }
    }

    /// True while the homing motion or its stop is under way.
    pub fn in_progress(&self) -> bool {
        matches!(self.state, State::Running(_) | State::Stopping { .. })
    }

    /// The drive left Operation enabled: the homing ends without error (CoE manual 3.2, A1).
    pub fn interrupt(&mut self) {
        if self.in_progress() {
            self.state = State::Interrupted;
        }
    }

    /// The mode is being changed: to "no mode" is an interruption (A4), to another
    /// supported mode an error (B4). The drive keeps homing mode until the stop is done.
    pub fn leave(&mut self, to_no_mode: bool, input: &ModeInput) -> Option<HomingEvent> {
        if let State::Running(_) = self.state {
            self.stop(!to_no_mode, input);
            return (!to_no_mode).then_some(HomingEvent::Error);
        }
        None
    }

    fn stop(&mut self, error: bool, input: &ModeInput) {
        let dec = input.od.get(od::HOMING_ACCELERATION) as f64;
        let vel = input.demand.vel;
        let motion = (dec > 0.0 && vel != 0.0).then(|| Moving::new(Trapezoid::stop(input.demand.pos, vel, dec)));
        self.state = State::Stopping { motion, error };
    }

    pub fn step(&mut self, input: &ModeInput) -> (Setpoint, Option<HomingEvent>) {
        let bit4 = input.controlword & NEW_SET_POINT != 0;
        let rising = bit4 && !self.start_bit;
        self.start_bit = bit4;
        let mut event = None;
        if rising {
            event = Some(self.start(input));
        } else if self.in_progress() && matches!(self.state, State::Running(_)) && (!bit4 || input.halt()) {
            // Bit 4 cleared or halt: the homing ends without error (A2, A3).
            self.stop(false, input);
        }
        let (setpoint, found) = match &mut self.state {
            State::Running(phase) => Self::run(phase, input, &self.settings),
            State::Stopping { motion, error } => {
                let done = match motion {
                    Some(m) => {
                        let (setpoint, done) = m.advance(input.period_s);
                        if !done {
                            return (setpoint, event);
                        }
                        done
                    }
                    None => true,
                };
                if done {
                    self.state = if *error { State::Error } else { State::Interrupted };
                }
                (Setpoint::Hold, Outcome::Continue)
            }
            _ => (Setpoint::Hold, Outcome::Continue),
        };
        match found {
            Outcome::Continue => {}
            Outcome::Home(raw) => {
                self.state = State::Attained;
                event = Some(HomingEvent::Home { raw });
            }
            Outcome::Failed => {
                self.stop(true, input);
                event = Some(HomingEvent::Error);
            }
        }
        (setpoint, event)
    }

    fn start(&mut self, input: &ModeInput) -> HomingEvent {
        let method = input.od.get(od::HOMING_METHOD);
        let raw = input.raw(input.actual);
        let on_switch = input.travel.home_switch_active(raw);
        match method_plan(method, on_switch, self.model, &self.settings) {
            None => {
                // An illegal method when bit 4 rises (B2).
                self.state = State::Error;
                HomingEvent::Error
            }
            Some(Plan::HereIsHome) => {
                self.state = State::Attained;
                HomingEvent::Home { raw }
            }
            Some(Plan::Seek { dir, fast, goal, then }) => {
                self.state = State::Running(Phase::Seek {
                    dir,
                    fast,
                    goal,
                    then,
                    velocity: input.demand.vel,
                    pos: input.demand.pos,
                    pushing_s: 0.0,
                });
                HomingEvent::Started
            }
        }
    }

    fn run(phase: &mut Phase, input: &ModeInput, settings: &DriveSettings) -> (Setpoint, Outcome) {
        let acc = input.od.get(od::HOMING_ACCELERATION) as f64;
        let fast = input.od.get(od::HOMING_SPEED_SWITCH) as f64;
        let slow = input.od.get(od::HOMING_SPEED_ZERO) as f64;
        match phase {
            Phase::Seek { dir, fast: is_fast, goal, then, velocity, pos, pushing_s } => {
                match Self::look_for(*goal, *dir, input) {
                    Sighting::Nothing => {}
                    Sighting::Limit if matches!(goal, Goal::SwitchEdge { .. }) => {
                        // A limit switch while looking for the home switch: turn round (CiA 402).
                        *dir = -*dir;
                    }
                    Sighting::Limit => return (Setpoint::Hold, Outcome::Failed),
                    Sighting::Found(at) => {
                        let next = match (*goal, *then) {
                            (Goal::Index { .. }, _) | (_, Then::Home) => Then::Home,
                            (_, then) => then,
                        };
                        let brake = if *velocity != 0.0 && acc > 0.0 {
                            Trapezoid::stop(*pos, *velocity, acc)
                        } else {
                            Trapezoid::plan(*pos, 0.0, *pos, Limits { vel: 1.0, acc: 1.0, dec: 1.0 })
                        };
                        *phase = Phase::Brake { motion: Moving::new(brake), at, then: next };
                        return Self::run(phase, input, settings);
                    }
                }
                if *goal == Goal::HardStop {
                    let threshold = settings.end_stop_current_pct / 100.0;
                    *pushing_s = if input.force * *dir >= threshold { *pushing_s + input.period_s } else { 0.0 };
                    if *pushing_s * 1000.0 >= settings.end_stop_time_ms {
                        // At the stop: the demand restarts from where the motor stands.
                        let at = input.raw(input.actual);
                        let stay =
                            Trapezoid::plan(input.actual, 0.0, input.actual, Limits { vel: 1.0, acc: 1.0, dec: 1.0 });
                        *phase = Phase::Brake { motion: Moving::new(stay), at, then: *then };
                        return Self::run(phase, input, settings);
                    }
                }
                let speed = if *is_fast { fast } else { slow };
                *velocity = ramp_velocity(*velocity, *dir * speed, acc, acc, input.period_s);
                *pos += *velocity * input.period_s;
                (Setpoint::Position { pos: *pos, vel: *velocity }, Outcome::Continue)
            }
            Phase::Brake { motion, at, then } => {
                let (setpoint, done) = motion.advance(input.period_s);
                if !done {
                    return (setpoint, Outcome::Continue);
                }
                let here = motion.plan.target();
                let at = *at;
                *phase = match *then {
                    Then::Home => {
                        Phase::ToHome { motion: Moving::new(Self::to(here, at + input.shift, slow, acc)), home: at }
                    }
                    Then::Offset(distance) => {
                        let home = at + distance;
                        Phase::ToHome { motion: Moving::new(Self::to(here, home + input.shift, slow, acc)), home }
                    }
                    Then::Index { dir } => Phase::Seek {
                        dir,
                        fast: false,
                        goal: Goal::Index { after: Some(at) },
                        then: Then::Home,
                        velocity: 0.0,
                        pos: here,
                        pushing_s: 0.0,
                    },
                };
                (setpoint, Outcome::Continue)
            }
            Phase::ToHome { motion, home } => {
                let (setpoint, done) = motion.advance(input.period_s);
                (setpoint, if done { Outcome::Home(*home) } else { Outcome::Continue })
            }
        }
    }

    /// A plan from `from` to `to` (drive coordinates) at homing speed.
    fn to(from: f64, to: f64, speed: f64, acc: f64) -> Trapezoid {
        let limits = Limits { vel: speed.max(1.0), acc: acc.max(1.0), dec: acc.max(1.0) };
        Trapezoid::plan(from, 0.0, to, limits)
    }

    fn look_for(goal: Goal, dir: f64, input: &ModeInput) -> Sighting {
        let beyond = |at: f64, after: Option<f64>| after.is_none_or(|p| if dir > 0.0 { at > p } else { at < p });
        let limits = input.travel;
        for edge in input.edges.iter() {
            match (goal, edge) {
                (Goal::NegativeLimit, Edge::NegativeLimit { rising: true, at }) => return Sighting::Found(at),
                (Goal::PositiveLimit, Edge::PositiveLimit { rising: true, at }) => return Sighting::Found(at),
                (Goal::SwitchEdge { left }, Edge::HomeSwitch { at, .. }) => {
                    let boundary = limits.home_switch.map(|(l, r)| if left { l } else { r });
                    if boundary == Some(at) {
                        return Sighting::Found(at);
                    }
                }
                (Goal::Index { after }, Edge::Index { at }) if beyond(at, after) => return Sighting::Found(at),
                (Goal::NegativeLimit, _) | (Goal::PositiveLimit, _) => {}
                (_, Edge::NegativeLimit { rising: true, .. }) if dir < 0.0 => return Sighting::Limit,
                (_, Edge::PositiveLimit { rising: true, .. }) if dir > 0.0 => return Sighting::Limit,
                _ => {}
            }
        }
        Sighting::Nothing
    }

    /// Statusword bits 13, 12 and 10 (CoE manual table 3-7).
    pub fn status_bits(&self) -> u16 {
        match self.state {
            State::Running(_) | State::Stopping { error: false, .. } => 0,
            State::NotStarted | State::Interrupted => TARGET_REACHED,
            State::Attained => OMS_12 | TARGET_REACHED,
            State::Stopping { error: true, .. } => OMS_13,
            State::Error => OMS_13 | TARGET_REACHED,
        }
    }
}

enum Sighting {
    Nothing,
    Found(f64),
    /// A limit switch in the direction of travel.
    Limit,
}

enum Outcome {
    Continue,
    Home(f64),
    Failed,
}

//! The FUN147 instruction: one instance (Gp, SR, WR) stepped once per PLC cycle.
//!
//! Per cycle, in this order: ABT, then EN = 0, stop what runs (decelerating when M1991 is
//! ON, FUN147 interface signals); a decelerating stop ends and frees the axes; an EN rising
//! edge starts: the table is checked whole (SR+0 = 0xA55C, N, every step), then the
//! instance waits until the Ready flags of all its axes are ON, takes them (flags OFF) and
//! runs the step after WR+0 (FUN147 expl. 4, WR+0 table); a running move that EXT cuts or
//! that has finished completes its step (DN, D4062/D4063, M1934/M1935 after step N) and
//! the transition (WAIT/EXT) is checked; GOTO starts the next step in the same cycle; PAU
//! pauses or resumes the move; last, WR+1 and the status registers are written.
//!
//! The axes an instance owns are the axes its table names in any step (a travel operand
//! that is not blank). Gp0 may name Ps0-Ps3; Gp1 only Ps2 and Ps3 (FUN147 expl. 2: four
//! axes, or two independent two-axis groups); a Gp1 table naming Ps0 or Ps1 is refused
//! with error 60. The instance holds its axes from the start until it stops, aborts,
//! fails or runs past its last step, WAIT and EXT included.

use thiserror::Error;

use crate::axes::{Axes, AxisSet};
use crate::code::{AXIS_FREQUENCY_MAX, ErrorCode};
use crate::image::{check_goto, check_speed, check_travel, read_header, read_step};
use crate::plc::{Plc, Reg, Relay, ready_flag};
use crate::step::{Condition, Coord, Goto, Mode, Step, Travel, Value16, Value32};

/// Registers of the working area WR+0..WR+8 (FUN147 operand WR).
pub const WR_WORDS: u16 = 9;

/// WR+1 bits (FUN147 WR+1 table); B0-B7 hold N.
pub mod flags {
    /// B0-B7: the number of steps N.
    pub const STEPS: u16 = 0x00FF;
    /// B8: output paused (PAU).
    pub const PAUSE: u16 = 1 << 8;
    /// B9: waiting for the transition condition (WAIT/EXT).
    pub const WAITING: u16 = 1 << 9;
    /// B10: continuous run (LINE).
    pub const LINE: u16 = 1 << 10;
    /// B12: pulse output (ACT).
    pub const ACT: u16 = 1 << 12;
    /// B13: execution error (ERR).
    pub const ERR: u16 = 1 << 13;
    /// B14: a step completed (DN), kept until the user writes WR+1.
    pub const DN: u16 = 1 << 14;
}

/// M1991: stop and pause decelerate (ON) or cut at once (OFF).
pub const M_DECELERATE: Relay = Relay::M(1991);

/// The ladder inputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Inputs {
    /// EN: execution control; its rising edge starts, 0 stops.
    pub en: bool,
    /// PAU: pause output.
    pub pau: bool,
    /// ABT: abort; the next start runs step 1.
    pub abt: bool,
}

/// The ladder outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Outputs {
    /// ACT: a move is under way (paused or decelerating to a stop included).
    pub act: bool,
    /// ERR: the last start or step failed; the code is in D4060/D4061.
    pub err: bool,
    /// DN: WR+1 B14.
    pub dn: bool,
}

/// Operands a FUN147 instance cannot have.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Error)]
pub enum OperandError {
    /// Gp is 0 or 1.
    #[error("Gp must be 0 or 1, not {0}")]
    Group(u8),
    /// SR must be in R0-R3839, R5000-R8071 or D0-D3999.
    #[error("SR {0} is not in R0-R3839, R5000-R8071 or D0-D3999")]
    Table(Reg),
    /// WR+0..WR+8 must lie in one of those areas.
    #[error("WR {0}: WR+0..WR+8 do not lie in R0-R3839, R5000-R8071 or D0-D3999")]
    Work(Reg),
}

fn is_user_register(reg: Reg) -> bool {
    reg.is_valid() && !matches!(reg, Reg::D(n) if n >= 4000)
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum State {
    Idle,
    /// Started; waiting for the Ready flags of these axes.
    WaitAxes(AxisSet),
    /// Step `step` moves.
    Moving,
    /// Step `step`'s pulses are out; waiting for its condition. `need_us`: WAIT TIME.
    Transition {
        elapsed_us: u64,
        need_us: u64,
    },
    /// Decelerating to a stop; the axes go free at rest.
    Stopping,
}

/// One FUN147 instruction.
#[derive(Clone, Debug)]
pub struct Fun147 {
    gp: u8,
    sr: Reg,
    wr: Reg,
    state: State,
    /// The step running or last run.
    step: Option<Step>,
    number: u16,
    steps: u16,
    owned: AxisSet,
    paused: bool,
    error: bool,
    en_before: bool,
    start_pending: bool,
}

impl Fun147 {
    /// An instance for group `gp` (0/1) with its table at `sr` and working area at `wr`.
    pub fn new(gp: u8, sr: Reg, wr: Reg) -> Result<Self, OperandError> {
        if gp > 1 {
            return Err(OperandError::Group(gp));
        }
        if !is_user_register(sr) {
            return Err(OperandError::Table(sr));
        }
        if !is_user_register(wr) || !wr.offset(WR_WORDS - 1).is_some_and(is_user_register) {
            return Err(OperandError::Work(wr));
        }
        Ok(Fun147 {
            gp,
            sr,
            wr,
            state: State::Idle,
            step: None,
            number: 0,
            steps: 0,
            owned: AxisSet::NONE,
            paused: false,
            error: false,
            en_before: false,
            start_pending: false,
        })
    }

    /// Gp.
    pub fn gp(&self) -> u8 {
        self.gp
    }

    /// SR.
    pub fn sr(&self) -> Reg {
        self.sr
    }

    /// WR.
    pub fn wr(&self) -> Reg {
        self.wr
    }

    /// The axes this instance holds now.
    pub fn owned(&self) -> AxisSet {
        self.owned
    }

    fn wr1(&self) -> Reg {
        self.wr.offset(1).expect("checked in new")
    }

    fn group_reg(&self, base: u16) -> Reg {
        Reg::D(base + u16::from(self.gp))
    }

    /// One PLC cycle of `period_s` seconds.
    pub fn step(&mut self, plc: &mut impl Plc, axes: &mut impl Axes, inputs: Inputs, period_s: f64) -> Outputs {
        let shown = self.owned;
        let decelerate = plc.relay(M_DECELERATE);
        let rising = inputs.en && !self.en_before;
        self.en_before = inputs.en;
        if inputs.abt || !inputs.en {
            self.start_pending = false;
            // A stop under way is left to end (the axes are told once).
            if !matches!(self.state, State::Idle | State::Stopping) {
                self.halt(plc, axes, decelerate);
            }
            if inputs.abt {
                // FUN147 expl. 7: the next EN runs step 1, which WR+0 = 0 means.
                plc.set_word(self.wr, 0);
            }
        } else if rising {
            self.start_pending = true;
        }
        if self.state == State::Stopping && axes.is_done(self.owned) {
            self.release(plc);
        }
        if self.start_pending && self.state == State::Idle {
            self.start_pending = false;
            self.error = false;
            match self.check_table(plc) {
                Ok(set) => self.state = State::WaitAxes(set),
                Err(code) => self.fail(plc, axes, code),
            }
        }
        if let State::WaitAxes(set) = self.state
            && set.iter().all(|axis| plc.relay(ready_flag(axis)))
        {
            set.iter().for_each(|axis| plc.set_relay(ready_flag(axis), false));
            self.owned = set;
            let last = plc.word(self.wr);
            let first = if last == 0 || last >= self.steps { 1 } else { last + 1 };
            self.run(plc, axes, first);
        }
        if let Err(code) = self.advance(plc, axes, period_s) {
            self.fail(plc, axes, code);
        }
        if self.state == State::Moving && inputs.pau != self.paused {
            self.paused = inputs.pau;
            if inputs.pau {
                axes.pause(self.owned, decelerate);
            } else {
                axes.resume(self.owned);
            }
        }
        self.show(plc, axes, AxisSet(shown.0 | self.owned.0))
    }

    /// Checks SR+0, N and every step; the axes the table names.
    fn check_table(&mut self, plc: &impl Plc) -> Result<AxisSet, ErrorCode> {
        let steps = read_header(plc, self.sr)?;
        self.steps = steps;
        let mut named = 0;
        for k in 1..=steps {
            named |= read_step(plc, self.sr, k, steps)?.named_axes().0;
        }
        if self.gp == 1 && named & 0b0011 != 0 {
            return Err(ErrorCode::IllegalCommand);
        }
        Ok(AxisSet(named))
    }

    /// Starts step k; a failure goes to ERR.
    fn run(&mut self, plc: &mut impl Plc, axes: &mut impl Axes, k: u16) {
        if let Err(code) = self.try_run(plc, axes, k) {
            self.fail(plc, axes, code);
        }
    }

    fn try_run(&mut self, plc: &mut impl Plc, axes: &mut impl Axes, k: u16) -> Result<(), ErrorCode> {
        plc.set_word(self.wr, k);
        self.number = k;
        plc.set_relay(Relay::M(1934 + u16::from(self.gp)), false);
        let step = read_step(plc, self.sr, k, self.steps)?;
        self.step = Some(step);
        // SPD is read here only: FUN147 has no change of frequency during a move.
        let speed = match step.speed {
            Value32::Const(v) => v,
            Value32::Reg(reg) => check_speed(plc.dword(reg))?,
        };
        let position = axes.position();
        let mut delta = [0i64; 4];
        for (i, travel) in step.motion.travel.iter().enumerate() {
            let Travel::Value(value) = travel else { continue };
            let value = match *value {
                Value32::Const(v) => i64::from(v),
                Value32::Reg(reg) => i64::from(plc.dword(reg)),
            };
            // LINE reads the travels as a ratio, whatever the coordinates.
            let pulses = match (step.motion.mode, step.motion.coord) {
                (Mode::Lin, Coord::Abs) => value - position[i],
                _ => value,
            };
            delta[i] = check_travel(pulses)?;
        }
        let norm = delta.iter().map(|&d| (d as f64).powi(2)).sum::<f64>().sqrt();
        for &d in delta.iter().filter(|&&d| d != 0) {
            let share = f64::from(speed) * d.abs() as f64 / norm;
            if !(1.0..=AXIS_FREQUENCY_MAX).contains(&share) {
                return Err(ErrorCode::Frequency);
            }
        }
        match step.motion.mode {
            Mode::Lin => {
                let targets = std::array::from_fn(|i| (delta[i] != 0).then(|| position[i] + delta[i]));
                if delta != [0; 4] {
                    axes.start_line(targets, f64::from(speed));
                }
            }
            Mode::Line if delta == [0; 4] => return Err(ErrorCode::TravelValue),
            Mode::Line => axes.start_continuous(delta, f64::from(speed)),
        }
        self.paused = false;
        self.state = State::Moving;
        Ok(())
    }

    /// The move and the transition of the running step.
    fn advance(&mut self, plc: &mut impl Plc, axes: &mut impl Axes, period_s: f64) -> Result<(), ErrorCode> {
        let Some(step) = self.step else { return Ok(()) };
        match self.state {
            State::Moving => {
                let cut = matches!(step.condition, Condition::Ext(relay) if plc.relay(relay));
                if cut {
                    // FUN147 EXT: the rest of the move is abandoned and GOTO runs at once.
                    axes.stop(self.owned, false);
                } else if self.paused || !axes.is_done(self.owned) {
                    return Ok(());
                }
                self.complete(plc);
                let need_us = match step.condition {
                    Condition::Time(Value16::Const(t)) => u64::from(t) * 10_000,
                    Condition::Time(Value16::Reg(reg)) => u64::from(plc.word(reg)) * 10_000,
                    _ => 0,
                };
                self.state = State::Transition { elapsed_us: 0, need_us };
                self.transition(plc, axes, step, cut)
            }
            State::Transition { elapsed_us, need_us } => {
                let elapsed_us = elapsed_us + (period_s * 1e6).round() as u64;
                self.state = State::Transition { elapsed_us, need_us };
                self.transition(plc, axes, step, false)
            }
            _ => Ok(()),
        }
    }

    /// DN, the completed step number, and M1934/M1935 after step N (FUN147 expl. 10,
    /// interface signals).
    fn complete(&mut self, plc: &mut impl Plc) {
        let wr1 = self.wr1();
        plc.set_word(wr1, plc.word(wr1) | flags::DN);
        plc.set_word(self.group_reg(4062), self.number);
        if self.number == self.steps {
            plc.set_relay(Relay::M(1934 + u16::from(self.gp)), true);
        }
    }

    fn transition(&mut self, plc: &mut impl Plc, axes: &mut impl Axes, step: Step, cut: bool) -> Result<(), ErrorCode> {
        let State::Transition { elapsed_us, need_us } = self.state else { return Ok(()) };
        let met = cut
            || match step.condition {
                Condition::None => true,
                Condition::Time(_) => elapsed_us >= need_us,
                Condition::Wait(relay) | Condition::Ext(relay) => plc.relay(relay),
            };
        if !met {
            return Ok(());
        }
        let next = match step.goto {
            Goto::Next if self.number == self.steps => None,
            Goto::Next => Some(self.number + 1),
            Goto::Step(k) => Some(check_goto(i64::from(k), self.steps)?),
            Goto::Reg(reg) => Some(check_goto(i64::from(plc.word(reg)), self.steps)?),
        };
        match next {
            Some(k) => self.run(plc, axes, k),
            // GOTO NEXT after step N: the program has run out; the next EN starts step 1.
            None => self.release(plc),
        }
        Ok(())
    }

    /// Stops what runs: at once, or through a deceleration that `Stopping` waits out.
    fn halt(&mut self, plc: &mut impl Plc, axes: &mut impl Axes, decelerate: bool) {
        axes.stop(self.owned, decelerate);
        self.paused = false;
        self.state = State::Stopping;
        if axes.is_done(self.owned) {
            self.release(plc);
        }
    }

    /// The axes failed under the instance (the controller's own error, e.g. an axis
    /// disabled): it stops at once, frees its axes and reports `code` as ERR.
    pub fn fault(&mut self, plc: &mut impl Plc, axes: &mut impl Axes, code: ErrorCode) {
        if self.state != State::Idle {
            self.fail(plc, axes, code);
        } else {
            plc.set_word(self.group_reg(4060), code.code());
            self.error = true;
        }
        self.start_pending = false;
    }

    fn fail(&mut self, plc: &mut impl Plc, axes: &mut impl Axes, code: ErrorCode) {
        axes.stop(self.owned, false);
        // The register keeps the latest code until the user clears it (FUN147 error table).
        plc.set_word(self.group_reg(4060), code.code());
        self.error = true;
        self.release(plc);
    }

    /// Frees the axes (Ready flags ON) and goes idle.
    fn release(&mut self, plc: &mut impl Plc) {
        self.owned.iter().for_each(|axis| plc.set_relay(ready_flag(axis), true));
        self.owned = AxisSet::NONE;
        self.paused = false;
        self.state = State::Idle;
    }

    /// WR+1, the group's vector speed and the status of the axes held this cycle.
    fn show(&self, plc: &mut impl Plc, axes: &impl Axes, shown: AxisSet) -> Outputs {
        let n =
            if plc.word(self.sr) == crate::image::MAGIC { plc.word(self.sr.offset(1).unwrap_or(self.sr)) } else { 0 };
        let act = matches!(self.state, State::Moving | State::Stopping);
        let line = self.state == State::Moving && self.step.is_some_and(|s| s.motion.mode == Mode::Line);
        let wr1 = self.wr1();
        let mut word = plc.word(wr1) & flags::DN;
        word |= if n <= flags::STEPS { n } else { 0 };
        word |= if self.paused { flags::PAUSE } else { 0 };
        word |= if matches!(self.state, State::Transition { .. }) { flags::WAITING } else { 0 };
        word |= if line { flags::LINE } else { 0 };
        word |= if act { flags::ACT } else { 0 };
        word |= if self.error { flags::ERR } else { 0 };
        plc.set_word(wr1, word);
        let (frequency, position, remaining) = (axes.frequency(), axes.position(), axes.remaining());
        let vector = shown.iter().map(|a| frequency[a].powi(2)).sum::<f64>().sqrt();
        plc.set_dword(Reg::D(4068 + 2 * u16::from(self.gp)), vector.round() as i32);
        for a in shown.iter() {
            let a16 = a as u16;
            plc.set_dword(Reg::D(4072 + 2 * a16), remaining[a] as i32);
            plc.set_dword(Reg::D(4080 + 2 * a16), frequency[a].round() as i32);
            plc.set_dword(Reg::D(4088 + 2 * a16), position[a] as i32);
        }
        Outputs { act, err: self.error, dn: word & flags::DN != 0 }
    }
}

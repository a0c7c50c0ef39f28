//! The step table in registers (FUN147 SR format): SR+0 = 0xA55C, SR+1 = N, step k in the
//! 15 words from SR+2+15(k−1); 15N+2 words in all.
//!
//! WinProladder's encoding of a step is not published, so luamotion defines its own; every
//! word and bit not listed must be 0.
//!
//! | word | bits | content |
//! |---|---|---|
//! | 0 | 15-0 | `0x930F`: 0x93 (= 147) and the step length 15 (else error 35) |
//! | 1 | 1-0 | mode: 1 LIN, 2 LINE (else 60) |
//! | 1 | 2 | 0 ADR, 1 ABS |
//! | 1 | 3 | 0 Ut, 1 Ps |
//! | 1 | 5-4 | SPD operand: 0 constant, 1 R, 2 D (3: error 30) |
//! | 1 | 7-6 | 0 |
//! | 1 | 9-8, 11-10, 13-12, 15-14 | travel operand of Ps0 (X), Ps1 (Y), Ps2 (Z), Ps3 (W): 0 blank, 1 constant, 2 R, 3 D |
//! | 2, 3 | | SPD: a constant, low word first; or the register number in word 2 and 0 in word 3 (else 30) |
//! | 4, 5 … 10, 11 | | travel of Ps0 … Ps3 as SPD, signed (a bad register: 32); a blank's words are 0 |
//! | 12 | 3-0 | condition: 0 none, 1 WAIT TIME, 2-5 WAIT X/Y/M/S, 6-9 EXT X/Y/M/S (else 60) |
//! | 12 | 5-4 | TIME operand: 0 constant, 1 R, 2 D (only with WAIT TIME) |
//! | 12 | 9-8 | GOTO: 0 NEXT, 1 step number, 2 R, 3 D |
//! | 13 | | condition operand: the time constant (0.01 s), the register or the relay number (0 with none) |
//! | 14 | | GOTO operand: the step number or the register number (0 with NEXT) |
//!
//! Register numbers are written as the PLC names them (R5000 is 5000). Example: `SPD 5000 /
//! LIN ADR,500,400,300,200,Ut / WAIT TIME,100 / GOTO NEXT` is
//! `930F 5501 1388 0000 01F4 0000 0190 0000 012C 0000 00C8 0000 0001 0064 0000`.
//!
//! Decoding checks the words (codes 30, 32, 35, 60 and the constant ranges 31, 40, 36 for a
//! constant GOTO); what registers hold is checked when a step runs.

use crate::code::{ErrorCode, SPEED_MAX, STEPS_MAX, TRAVEL_MAX};
use crate::plc::{Plc, Reg, Relay};
use crate::step::{Condition, Coord, Goto, Mode, Motion, Step, Travel, Unit, Value16, Value32};

/// SR+0 of a valid program.
pub const MAGIC: u16 = 0xA55C;
/// Words per step.
pub const STEP_WORDS: usize = 15;
/// Word 0 of every step.
pub const STEP_HEADER: u16 = 0x9300 | STEP_WORDS as u16;

/// The words of one step.
pub type StepWords = [u16; STEP_WORDS];

/// Where step k (1-based) starts, as an offset from SR.
pub fn step_offset(k: u16) -> u16 {
    2 + STEP_WORDS as u16 * (k - 1)
}

fn reg_of(kind: u16, number: u16) -> Option<Reg> {
    let reg = match kind {
        1 => Reg::R(number),
        2 => Reg::D(number),
        _ => return None,
    };
    reg.is_valid().then_some(reg)
}

fn reg_kind(reg: Reg) -> u16 {
    match reg {
        Reg::R(_) => 1,
        Reg::D(_) => 2,
    }
}

fn relay_of(kind: u16, number: u16) -> Option<Relay> {
    let relay = match kind {
        0 => Relay::X(number),
        1 => Relay::Y(number),
        2 => Relay::M(number),
        3 => Relay::S(number),
        _ => return None,
    };
    relay.is_condition().then_some(relay)
}

/// Word 12's condition code (`base` + X 0, Y 1, M 2, S 3) and word 13.
fn relay_code(base: u16, relay: Relay) -> (u16, u16) {
    match relay {
        Relay::X(n) => (base, n),
        Relay::Y(n) => (base + 1, n),
        Relay::M(n) => (base + 2, n),
        Relay::S(n) => (base + 3, n),
    }
}

fn encode_value32(value: Value32) -> (u16, [u16; 2]) {
    match value {
        Value32::Const(v) => (0, [v as u16, (v >> 16) as u16]),
        Value32::Reg(reg) => (reg_kind(reg), [reg.number(), 0]),
    }
}

fn decode_value32(kind: u16, words: [u16; 2], bad_reg: ErrorCode) -> Result<Value32, ErrorCode> {
    if kind == 0 {
        return Ok(Value32::Const(((u32::from(words[1]) << 16) | u32::from(words[0])) as i32));
    }
    match reg_of(kind, words[0]) {
        Some(reg) if words[1] == 0 && reg.is_valid_double() => Ok(Value32::Reg(reg)),
        _ => Err(bad_reg),
    }
}

/// The 15 words of a step.
pub fn encode_step(step: &Step) -> StepWords {
    let mut w = [0u16; STEP_WORDS];
    w[0] = STEP_HEADER;
    let m = &step.motion;
    let mut command = match m.mode {
        Mode::Lin => 1,
        Mode::Line => 2,
    };
    command |= u16::from(m.coord == Coord::Abs) << 2 | u16::from(m.unit == Unit::Ps) << 3;
    let (kind, words) = encode_value32(step.speed);
    command |= kind << 4;
    w[2..4].copy_from_slice(&words);
    for (i, travel) in m.travel.iter().enumerate() {
        if let Travel::Value(value) = travel {
            let (kind, words) = encode_value32(*value);
            command |= (kind + 1) << (8 + 2 * i);
            w[4 + 2 * i..6 + 2 * i].copy_from_slice(&words);
        }
    }
    w[1] = command;
    let (condition, operand) = match step.condition {
        Condition::None => (0, 0),
        Condition::Time(Value16::Const(t)) => (1, t),
        Condition::Time(Value16::Reg(reg)) => (1 | reg_kind(reg) << 4, reg.number()),
        Condition::Wait(relay) => relay_code(2, relay),
        Condition::Ext(relay) => relay_code(6, relay),
    };
    let (goto, target) = match step.goto {
        Goto::Next => (0, 0),
        Goto::Step(k) => (1, k),
        Goto::Reg(reg) => (1 + reg_kind(reg), reg.number()),
    };
    w[12] = condition | goto << 8;
    w[13] = operand;
    w[14] = target;
    w
}

/// Decodes the 15 words of a step of a program of `steps` steps.
pub fn decode_step(w: &StepWords, steps: u16) -> Result<Step, ErrorCode> {
    if w[0] != STEP_HEADER {
        return Err(ErrorCode::StepLength);
    }
    let command = w[1];
    let mode = match command & 3 {
        1 => Mode::Lin,
        2 => Mode::Line,
        _ => return Err(ErrorCode::IllegalCommand),
    };
    if command & 0xC0 != 0 {
        return Err(ErrorCode::IllegalCommand);
    }
    let coord = if command & 4 != 0 { Coord::Abs } else { Coord::Adr };
    let unit = if command & 8 != 0 { Unit::Ps } else { Unit::Ut };
    let speed = decode_value32((command >> 4) & 3, [w[2], w[3]], ErrorCode::SpeedVariable)?;
    if let Value32::Const(v) = speed {
        check_speed(v)?;
    }
    let mut travel = [Travel::Blank; 4];
    for (i, slot) in travel.iter_mut().enumerate() {
        let words = [w[4 + 2 * i], w[5 + 2 * i]];
        let kind = (command >> (8 + 2 * i)) & 3;
        if kind == 0 {
            if words != [0, 0] {
                return Err(ErrorCode::IllegalCommand);
            }
            continue;
        }
        let value = decode_value32(kind - 1, words, ErrorCode::TravelVariable)?;
        if let Value32::Const(v) = value {
            check_travel(i64::from(v))?;
        }
        *slot = Travel::Value(value);
    }
    let transition = w[12];
    if transition & 0xFCC0 != 0 {
        return Err(ErrorCode::IllegalCommand);
    }
    let (kind, time_kind, operand) = (transition & 0xF, (transition >> 4) & 3, w[13]);
    if kind != 1 && time_kind != 0 {
        return Err(ErrorCode::IllegalCommand);
    }
    let condition = match kind {
        0 if operand == 0 => Condition::None,
        1 if time_kind == 0 => Condition::Time(Value16::Const(operand)),
        1 => Condition::Time(Value16::Reg(reg_of(time_kind, operand).ok_or(ErrorCode::IllegalCommand)?)),
        2..=5 => Condition::Wait(relay_of(kind - 2, operand).ok_or(ErrorCode::IllegalCommand)?),
        6..=9 => Condition::Ext(relay_of(kind - 6, operand).ok_or(ErrorCode::IllegalCommand)?),
        _ => return Err(ErrorCode::IllegalCommand),
    };
    let target = w[14];
    let goto = match (transition >> 8) & 3 {
        0 if target == 0 => Goto::Next,
        0 => return Err(ErrorCode::IllegalCommand),
        1 => Goto::Step(check_goto(i64::from(target), steps)?),
        kind => Goto::Reg(reg_of(kind - 1, target).ok_or(ErrorCode::IllegalCommand)?),
    };
    Ok(Step { speed, motion: Motion { mode, coord, travel, unit }, condition, goto })
}

/// SPD's range, 1..=1,840,000 (error 31).
pub fn check_speed(value: i32) -> Result<i32, ErrorCode> {
    (1..=SPEED_MAX).contains(&value).then_some(value).ok_or(ErrorCode::SpeedValue)
}

/// One axis' move in one step, at most ±1,999,999 pulses (error 40).
pub fn check_travel(pulses: i64) -> Result<i64, ErrorCode> {
    (-TRAVEL_MAX..=TRAVEL_MAX).contains(&pulses).then_some(pulses).ok_or(ErrorCode::TravelRange)
}

/// A GOTO target, 1..=N (error 36).
pub fn check_goto(target: i64, steps: u16) -> Result<u16, ErrorCode> {
    (1..=i64::from(steps)).contains(&target).then_some(target as u16).ok_or(ErrorCode::StepCount)
}

/// A program: the steps in order, step 1 first.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Program {
    /// The steps.
    pub steps: Vec<Step>,
}

impl Program {
    /// The register image: 0xA55C, N, then 15 words a step.
    pub fn to_words(&self) -> Vec<u16> {
        let mut words = vec![MAGIC, self.steps.len() as u16];
        words.extend(self.steps.iter().flat_map(encode_step));
        words
    }

    /// Decodes an image (at least 15N+2 words; more are ignored).
    pub fn from_words(words: &[u16]) -> Result<Self, ErrorCode> {
        let n = header(words.first().copied(), words.get(1).copied())?;
        if words.len() < 2 + STEP_WORDS * n as usize {
            return Err(ErrorCode::StepLength);
        }
        let steps = words[2..2 + STEP_WORDS * n as usize]
            .chunks_exact(STEP_WORDS)
            .map(|chunk| decode_step(chunk.try_into().expect("15 words"), n))
            .collect::<Result<_, _>>()?;
        Ok(Program { steps })
    }

    /// Writes the image from SR. Fails with 35 when it does not fit in SR's area.
    pub fn write(&self, plc: &mut impl Plc, sr: Reg) -> Result<(), ErrorCode> {
        let words = self.to_words();
        sr.offset(words.len() as u16 - 1).ok_or(ErrorCode::StepLength)?;
        for (i, word) in words.into_iter().enumerate() {
            plc.set_word(sr.offset(i as u16).expect("checked above"), word);
        }
        Ok(())
    }

    /// Reads and decodes the image at SR.
    pub fn read(plc: &impl Plc, sr: Reg) -> Result<Self, ErrorCode> {
        let n = read_header(plc, sr)?;
        let steps = (1..=n).map(|k| read_step(plc, sr, k, n)).collect::<Result<_, _>>()?;
        Ok(Program { steps })
    }
}

fn header(magic: Option<u16>, n: Option<u16>) -> Result<u16, ErrorCode> {
    if magic != Some(MAGIC) {
        return Err(ErrorCode::IllegalProgram);
    }
    match n {
        Some(n) if (1..=STEPS_MAX).contains(&n) => Ok(n),
        _ => Err(ErrorCode::StepCount),
    }
}

/// Checks SR+0 and SR+1 and that the whole table lies in SR's area; returns N.
pub fn read_header(plc: &impl Plc, sr: Reg) -> Result<u16, ErrorCode> {
    let n = header(Some(plc.word(sr)), sr.offset(1).map(|r| plc.word(r)))?;
    sr.offset(step_offset(n) + STEP_WORDS as u16 - 1).ok_or(ErrorCode::StepLength)?;
    Ok(n)
}

/// Reads and decodes step k of a program of N steps whose header `read_header` checked.
pub fn read_step(plc: &impl Plc, sr: Reg, k: u16, n: u16) -> Result<Step, ErrorCode> {
    let mut words = [0u16; STEP_WORDS];
    for (i, word) in words.iter_mut().enumerate() {
        *word = plc.word(sr.offset(step_offset(k) + i as u16).ok_or(ErrorCode::StepLength)?);
    }
    decode_step(&words, n)
}

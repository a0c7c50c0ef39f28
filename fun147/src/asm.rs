//! The text form of a FUN147 program (FUN147 derived command table and program example):
//!
//! ```text
//! 001 SPD 5000                    ; vector speed 5 kHz
//!     LIN ADR,500,400,300,200,Ut
//!     WAIT TIME,100               ; 1 s
//!     GOTO NEXT
//! 002 ...
//!     MEND
//! ```
//!
//! A step starts with its number (001, 002 … in order) and holds SPD and LIN or LINE once
//! each, at most one WAIT or EXT, and at most one GOTO (NEXT when left out). MEND ends the
//! program and may be left out. Case does not matter; `;` starts a comment. The manual's
//! full-width `；` and `，` and its minus sign `−` are read as `;`, `,` and `-`.

use std::fmt::Write as _;

use thiserror::Error;

use crate::code::{ErrorCode, STEPS_MAX};
use crate::image::{Program, check_speed, check_travel};
use crate::plc::{Reg, Relay};
use crate::step::{Condition, Coord, Goto, Mode, Motion, Step, Travel, Unit, Value16, Value32};

/// What is wrong with a program text, and where (1-based line and column, in characters).
#[derive(Clone, Debug, PartialEq, Eq, Error)]
#[error("line {line}, column {column}: {kind}")]
pub struct AsmError {
    /// Line, from 1.
    pub line: usize,
    /// Column, from 1.
    pub column: usize,
    /// What.
    pub kind: AsmErrorKind,
}

/// The kinds of [`AsmError`].
#[derive(Clone, Debug, PartialEq, Eq, Error)]
pub enum AsmErrorKind {
    /// Not SPD, LIN, LINE, WAIT, EXT, GOTO or MEND.
    #[error("unknown command {0:?}")]
    UnknownCommand(String),
    /// A command before the first step number.
    #[error("a command before the first step number (001)")]
    NoStep,
    /// Step numbers must count 1, 2, 3 …
    #[error("step number {found}, expected {expected}")]
    StepNumber {
        /// The next number.
        expected: usize,
        /// The number written.
        found: String,
    },
    /// More than 255 steps.
    #[error("more than 255 steps (FUN147 error 36)")]
    TooManySteps,
    /// The wrong number of operands.
    #[error("{command} takes {expected}")]
    OperandCount {
        /// The command.
        command: &'static str,
        /// What it takes.
        expected: &'static str,
    },
    /// An operand that is none of those the command takes.
    #[error("{command}: {found:?} is not {expected}")]
    Operand {
        /// The command.
        command: &'static str,
        /// The operand written.
        found: String,
        /// What the command takes there.
        expected: &'static str,
    },
    /// A constant outside its range; the code FUN147 would report.
    #[error("FUN147 error {0}")]
    Value(ErrorCode),
    /// A command given twice in one step (SPD, LIN/LINE, WAIT/EXT, GOTO).
    #[error("a second {0} in one step")]
    Twice(&'static str),
    /// A step without SPD or LIN/LINE.
    #[error("step {step} has no {missing}")]
    Missing {
        /// The step number.
        step: usize,
        /// SPD or LIN/LINE.
        missing: &'static str,
    },
    /// Text after MEND.
    #[error("text after MEND")]
    AfterMend,
    /// No step at all.
    #[error("no steps")]
    Empty,
}

/// A step being read: each part once.
#[derive(Default)]
struct Partial {
    number: usize,
    speed: Option<Value32>,
    motion: Option<Motion>,
    condition: Option<Condition>,
    goto: Option<Goto>,
}

impl Partial {
    fn finish(self) -> Result<Step, AsmErrorKind> {
        let missing = |missing| AsmErrorKind::Missing { step: self.number, missing };
        Ok(Step {
            speed: self.speed.ok_or_else(|| missing("SPD"))?,
            motion: self.motion.ok_or_else(|| missing("LIN/LINE"))?,
            condition: self.condition.unwrap_or(Condition::None),
            goto: self.goto.unwrap_or(Goto::Next),
        })
    }
}

/// A piece of a line and the column it starts at.
#[derive(Clone, Copy)]
struct Token<'a> {
    text: &'a str,
    column: usize,
}

impl<'a> Token<'a> {
    fn at(line: &'a str, start: usize, text: &'a str) -> Self {
        // Leading blanks do not count: the column is that of the first character.
        let trimmed = text.trim_start();
        let start = start + (text.len() - trimmed.len());
        Token { text: trimmed.trim_end(), column: line[..start].chars().count() + 1 }
    }

    /// The byte offset of the token in its line.
    fn column_byte(self, line: &str) -> usize {
        line.char_indices().nth(self.column - 1).map_or(line.len(), |(i, _)| i)
    }

    fn error(self, line: usize, kind: AsmErrorKind) -> AsmError {
        AsmError { line, column: self.column, kind }
    }
}

fn normalize(line: &str) -> String {
    line.chars()
        .map(|c| match c {
            '；' => ';',
            '，' => ',',
            '−' => '-',
            c => c,
        })
        .collect()
}

/// The first word of `text` and the rest after it.
fn first_word<'a>(line: &'a str, text: Token<'a>) -> (Token<'a>, Token<'a>) {
    let start = text.column_byte(line);
    let end = text.text.find(char::is_whitespace).unwrap_or(text.text.len());
    (Token::at(line, start, &text.text[..end]), Token::at(line, start + end, &text.text[end..]))
}

/// The comma-separated operands of `rest`.
fn operands<'a>(line: &'a str, rest: Token<'a>) -> Vec<Token<'a>> {
    if rest.text.is_empty() {
        return Vec::new();
    }
    let base = rest.column_byte(line);
    let mut tokens = Vec::new();
    let mut start = 0;
    for piece in rest.text.split(',') {
        tokens.push(Token::at(line, base + start, piece));
        start += piece.len() + 1;
    }
    tokens
}

fn constant(text: &str) -> Option<i64> {
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    if digits.is_empty() || digits.len() > 10 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let value: i64 = digits.parse().ok()?;
    Some(if text.starts_with('-') { -value } else { value })
}

fn register(text: &str) -> Option<Reg> {
    text.parse().ok()
}

/// Reads a program text.
pub fn assemble(text: &str) -> Result<Program, AsmError> {
    let mut steps: Vec<Step> = Vec::new();
    let mut current: Option<Partial> = None;
    let mut ended = false;
    let mut last_line = 0;
    // Constant GOTO targets and where they are written, checked against N at the end.
    let mut gotos: Vec<(u16, usize, usize)> = Vec::new();
    for (index, raw) in text.lines().enumerate() {
        let n = index + 1;
        last_line = n;
        let line = normalize(raw);
        let code = line.split(';').next().unwrap_or("");
        let whole = Token::at(&line, 0, code);
        if whole.text.is_empty() {
            continue;
        }
        if ended {
            return Err(whole.error(n, AsmErrorKind::AfterMend));
        }
        let (mut word, mut rest) = first_word(&line, whole);
        if word.text.bytes().all(|b| b.is_ascii_digit()) {
            let expected = steps.len() + usize::from(current.is_some()) + 1;
            if word.text.parse::<usize>().ok() != Some(expected) {
                let found = word.text.to_owned();
                return Err(word.error(n, AsmErrorKind::StepNumber { expected, found }));
            }
            if expected > usize::from(STEPS_MAX) {
                return Err(word.error(n, AsmErrorKind::TooManySteps));
            }
            if let Some(done) = current.take() {
                steps.push(done.finish().map_err(|kind| word.error(n, kind))?);
            }
            current = Some(Partial { number: expected, ..Partial::default() });
            if rest.text.is_empty() {
                continue;
            }
            (word, rest) = first_word(&line, rest);
        }
        let command = word.text.to_ascii_uppercase();
        if command == "MEND" {
            if !rest.text.is_empty() {
                return Err(rest.error(n, AsmErrorKind::AfterMend));
            }
            ended = true;
            continue;
        }
        let step = current.as_mut().ok_or_else(|| word.error(n, AsmErrorKind::NoStep))?;
        let ops = operands(&line, rest);
        command_into(step, &command, word, &ops).map_err(|(token, kind)| token.error(n, kind))?;
        if let (Some(Goto::Step(k)), "GOTO") = (step.goto, command.as_str()) {
            gotos.push((k, n, ops[0].column));
        }
    }
    if let Some(done) = current.take() {
        steps.push(done.finish().map_err(|kind| AsmError { line: last_line.max(1), column: 1, kind })?);
    }
    if steps.is_empty() {
        return Err(AsmError { line: last_line.max(1), column: 1, kind: AsmErrorKind::Empty });
    }
    if let Some(&(_, line, column)) = gotos.iter().find(|(k, ..)| usize::from(*k) > steps.len()) {
        return Err(AsmError { line, column, kind: AsmErrorKind::Value(ErrorCode::StepCount) });
    }
    Ok(Program { steps })
}

type Failure<'a> = (Token<'a>, AsmErrorKind);

fn set_once<'a, T>(slot: &mut Option<T>, value: T, word: Token<'a>, what: &'static str) -> Result<(), Failure<'a>> {
    if slot.is_some() {
        return Err((word, AsmErrorKind::Twice(what)));
    }
    *slot = Some(value);
    Ok(())
}

fn bad<'a>(command: &'static str, token: Token<'a>, expected: &'static str) -> Failure<'a> {
    (token, AsmErrorKind::Operand { command, found: token.text.to_owned(), expected })
}

fn count<'a>(
    command: &'static str,
    word: Token<'a>,
    ops: &[Token<'a>],
    n: usize,
    expected: &'static str,
) -> Result<(), Failure<'a>> {
    if ops.len() != n {
        return Err((word, AsmErrorKind::OperandCount { command, expected }));
    }
    Ok(())
}

/// A 32-bit operand: a constant or a register pair whose high word exists.
fn value32<'a>(command: &'static str, token: Token<'a>, expected: &'static str) -> Result<Value32, Failure<'a>> {
    if let Some(v) = constant(token.text) {
        return i32::try_from(v).map(Value32::Const).map_err(|_| bad(command, token, expected));
    }
    match register(token.text) {
        Some(reg) if reg.is_valid_double() => Ok(Value32::Reg(reg)),
        _ => Err(bad(command, token, expected)),
    }
}

fn relay<'a>(command: &'static str, token: Token<'a>) -> Result<Relay, Failure<'a>> {
    const EXPECTED: &str = "X0-X255, Y0-Y255, M0-M1911 or S0-S999";
    match token.text.parse::<Relay>() {
        Ok(relay) if relay.is_condition() => Ok(relay),
        _ => Err(bad(command, token, EXPECTED)),
    }
}

fn command_into<'a>(step: &mut Partial, command: &str, word: Token<'a>, ops: &[Token<'a>]) -> Result<(), Failure<'a>> {
    match command {
        "SPD" => {
            count("SPD", word, ops, 1, "one operand: a constant, Rn or Dn")?;
            let speed = value32("SPD", ops[0], "a constant 1..1840000, Rn or Dn")?;
            if let Value32::Const(v) = speed {
                check_speed(v).map_err(|code| (ops[0], AsmErrorKind::Value(code)))?;
            }
            set_once(&mut step.speed, speed, word, "SPD")
        }
        "LIN" | "LINE" => {
            let name = if command == "LIN" { "LIN" } else { "LINE" };
            count(name, word, ops, 6, "six operands: ADR|ABS, X, Y, Z, W, Ut|Ps")?;
            let coord = match ops[0].text.to_ascii_uppercase().as_str() {
                "ADR" => Coord::Adr,
                "ABS" => Coord::Abs,
                _ => return Err(bad(name, ops[0], "ADR or ABS")),
            };
            let unit = match ops[5].text.to_ascii_uppercase().as_str() {
                "UT" => Unit::Ut,
                "PS" => Unit::Ps,
                _ => return Err(bad(name, ops[5], "Ut or Ps")),
            };
            let mut travel = [Travel::Blank; 4];
            for (slot, token) in travel.iter_mut().zip(&ops[1..5]) {
                if token.text.is_empty() {
                    continue;
                }
                let value = value32(name, *token, "blank, a constant, Rn or Dn")?;
                if let Value32::Const(v) = value {
                    check_travel(i64::from(v)).map_err(|code| (*token, AsmErrorKind::Value(code)))?;
                }
                *slot = Travel::Value(value);
            }
            let mode = if command == "LIN" { Mode::Lin } else { Mode::Line };
            set_once(&mut step.motion, Motion { mode, coord, travel, unit }, word, "LIN/LINE")
        }
        "WAIT" => {
            let condition = match ops {
                [kind, time] if kind.text.eq_ignore_ascii_case("TIME") => {
                    let expected = "a constant 0..65535, Rn or Dn";
                    match constant(time.text) {
                        Some(t) => Value16::Const(u16::try_from(t).map_err(|_| bad("WAIT", *time, expected))?),
                        None => Value16::Reg(register(time.text).ok_or_else(|| bad("WAIT", *time, expected))?),
                    }
                }
                [only] => {
                    return set_once(&mut step.condition, Condition::Wait(relay("WAIT", *only)?), word, "WAIT/EXT");
                }
                _ => {
                    return Err((
                        word,
                        AsmErrorKind::OperandCount { command: "WAIT", expected: "TIME,t or one relay" },
                    ));
                }
            };
            set_once(&mut step.condition, Condition::Time(condition), word, "WAIT/EXT")
        }
        "EXT" => {
            count("EXT", word, ops, 1, "one relay")?;
            set_once(&mut step.condition, Condition::Ext(relay("EXT", ops[0])?), word, "WAIT/EXT")
        }
        "GOTO" => {
            count("GOTO", word, ops, 1, "one operand: NEXT, a step number, Rn or Dn")?;
            let token = ops[0];
            let goto = if token.text.eq_ignore_ascii_case("NEXT") {
                Goto::Next
            } else if let Some(k) = constant(token.text) {
                // Whether k names a step is known once the program is read: checked by the image.
                Goto::Step(
                    u16::try_from(k)
                        .ok()
                        .filter(|k| (1..=STEPS_MAX).contains(k))
                        .ok_or((token, AsmErrorKind::Value(ErrorCode::StepCount)))?,
                )
            } else {
                Goto::Reg(register(token.text).ok_or_else(|| bad("GOTO", token, "NEXT, 1..N, Rn or Dn"))?)
            };
            set_once(&mut step.goto, goto, word, "GOTO")
        }
        _ => Err((word, AsmErrorKind::UnknownCommand(word.text.to_owned()))),
    }
}

fn value32_text(value: Value32) -> String {
    match value {
        Value32::Const(v) => v.to_string(),
        Value32::Reg(reg) => reg.to_string(),
    }
}

/// The text of a program, in the form `assemble` reads back to the same program.
pub fn disassemble(program: &Program) -> String {
    let mut text = String::new();
    for (i, step) in program.steps.iter().enumerate() {
        let m = &step.motion;
        let travel: Vec<String> = m
            .travel
            .iter()
            .map(|t| match t {
                Travel::Blank => String::new(),
                Travel::Value(v) => value32_text(*v),
            })
            .collect();
        let _ = writeln!(text, "{:03} SPD {}", i + 1, value32_text(step.speed));
        let _ = writeln!(
            text,
            "    {} {},{},{}",
            if m.mode == Mode::Lin { "LIN" } else { "LINE" },
            if m.coord == Coord::Adr { "ADR" } else { "ABS" },
            travel.join(","),
            if m.unit == Unit::Ut { "Ut" } else { "Ps" }
        );
        match step.condition {
            Condition::None => {}
            Condition::Time(Value16::Const(t)) => _ = writeln!(text, "    WAIT TIME,{t}"),
            Condition::Time(Value16::Reg(reg)) => _ = writeln!(text, "    WAIT TIME,{reg}"),
            Condition::Wait(relay) => _ = writeln!(text, "    WAIT {relay}"),
            Condition::Ext(relay) => _ = writeln!(text, "    EXT {relay}"),
        }
        let _ = match step.goto {
            Goto::Next => writeln!(text, "    GOTO NEXT"),
            Goto::Step(k) => writeln!(text, "    GOTO {k}"),
            Goto::Reg(reg) => writeln!(text, "    GOTO {reg}"),
        };
    }
    text.push_str("    MEND\n");
    text
}

//! One step of a FUN147 program as its derived text commands describe it (FUN147 derived
//! command table): SPD, LIN/LINE, WAIT/EXT, GOTO.

use crate::axes::AxisSet;
use crate::plc::{Reg, Relay};

/// A 32-bit operand: a constant, or the register pair DRn/DDn (low word at n).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Value32 {
    /// A constant.
    Const(i32),
    /// The 32-bit value at the register and the next.
    Reg(Reg),
}

/// A 16-bit operand: a constant, or one register.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Value16 {
    /// A constant.
    Const(u16),
    /// The value in the register.
    Reg(Reg),
}

/// A travel operand: blank (the axis does not output) or a value (FUN147 LIN table).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Travel {
    /// Blank: the axis does not output, in ADR and in ABS.
    Blank,
    /// A value: ADR travel (0 = no output), or ABS target (0 = move to 0).
    Value(Value32),
}

/// LIN (one move) or LINE (continuous in the ratio).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// `LIN`: linear interpolation of one move.
    Lin,
    /// `LINE`: continuous run in the ratio of the travels, until EXT or a stop.
    Line,
}

/// Relative (ADR) or absolute (ABS) coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coord {
    /// `ADR`: travel.
    Adr,
    /// `ABS`: target position.
    Abs,
}

/// The sixth operand: user units (`Ut`) or pulses (`Ps`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    /// `Ut`: one user unit (FUN141 parameters 0, 3); pulses by default.
    Ut,
    /// `Ps`: one pulse.
    Ps,
}

/// The move of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Motion {
    /// LIN or LINE.
    pub mode: Mode,
    /// ADR or ABS.
    pub coord: Coord,
    /// Ps0 (X), Ps1 (Y), Ps2 (Z), Ps3 (W).
    pub travel: [Travel; 4],
    /// Ut or Ps.
    pub unit: Unit,
}

/// The transition condition of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Condition {
    /// No WAIT or EXT: GOTO as soon as the pulses are out.
    None,
    /// `WAIT TIME,t`: t × 0.01 s after the pulses are out.
    Time(Value16),
    /// `WAIT X0`: after the pulses are out, until the relay is ON.
    Wait(Relay),
    /// `EXT X1`: at once when the relay turns ON, abandoning the rest of the move; after
    /// the pulses are out, as WAIT.
    Ext(Relay),
}

/// Where GOTO goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Goto {
    /// `GOTO NEXT`.
    Next,
    /// `GOTO k`, 1..=N.
    Step(u16),
    /// `GOTO Rn`/`GOTO Dn`: the step number in the register.
    Reg(Reg),
}

/// One step: 15 registers in the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Step {
    /// SPD: vector speed or frequency.
    pub speed: Value32,
    /// LIN/LINE.
    pub motion: Motion,
    /// WAIT/EXT.
    pub condition: Condition,
    /// GOTO.
    pub goto: Goto,
}

impl Step {
    /// The axes whose travel operand is not blank.
    pub fn named_axes(&self) -> AxisSet {
        AxisSet((0..4).filter(|&i| self.motion.travel[i] != Travel::Blank).fold(0, |set, i| set | 1 << i))
    }
}

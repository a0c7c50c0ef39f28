//! The error codes FUN147 reports in D4060 (Gp0) / D4061 (Gp1) (FUN147 error-code table,
//! "codes of FUN140 and FUN147"). Only those a FUN147 step table can cause.

use thiserror::Error;

/// A FUN147 error; its number is what goes into the group's error register.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Error)]
pub enum ErrorCode {
    /// 30: the speed operand names a register pair that does not exist.
    #[error("30: speed variable number error")]
    SpeedVariable,
    /// 31: the speed is outside 1..=1,840,000.
    #[error("31: speed setting value error")]
    SpeedValue,
    /// 32: a travel operand names a register pair that does not exist.
    #[error("32: travel variable number error")]
    TravelVariable,
    /// 33: a LINE step whose ratio moves no axis.
    #[error("33: travel setting value error")]
    TravelValue,
    /// 34: SR+0 is not 0xA55C.
    #[error("34: illegal positioning program")]
    IllegalProgram,
    /// 35: a step's header word does not say 15 words, or the table does not fit in SR's area.
    #[error("35: step length error")]
    StepLength,
    /// 36: N outside 1..=255, or a GOTO to a step outside 1..=N.
    #[error("36: exceeds the maximum number of steps")]
    StepCount,
    /// 37: an axis' share of the speed outside 1..=921,600 Hz.
    #[error("37: maximum frequency error")]
    Frequency,
    /// 40: a move of more than 1,999,999 pulses on an axis.
    #[error("40: travel out of range")]
    TravelRange,
    /// 60: any other word of a step that no command encodes.
    #[error("60: illegal interpolation command")]
    IllegalCommand,
    /// 90 (luamotion's, docs/decisions.md "FUN147"): the controller's axes cannot follow:
    /// one is missing, disabled, in error stop or in another group.
    #[error("90: the axes cannot follow")]
    Axes,
}

impl ErrorCode {
    /// The number in the error register.
    pub fn code(self) -> u16 {
        match self {
            ErrorCode::SpeedVariable => 30,
            ErrorCode::SpeedValue => 31,
            ErrorCode::TravelVariable => 32,
            ErrorCode::TravelValue => 33,
            ErrorCode::IllegalProgram => 34,
            ErrorCode::StepLength => 35,
            ErrorCode::StepCount => 36,
            ErrorCode::Frequency => 37,
            ErrorCode::TravelRange => 40,
            ErrorCode::IllegalCommand => 60,
            ErrorCode::Axes => 90,
        }
    }
}

/// SPD range (FUN147 SPD table).
pub const SPEED_MAX: i32 = 1_840_000;
/// Per-axis output frequency range (FUN147 SPD table).
pub const AXIS_FREQUENCY_MAX: f64 = 921_600.0;
/// The largest move of one axis in one step, pulses (FUN147 LIN table).
pub const TRAVEL_MAX: i64 = 1_999_999;
/// The most steps WR+1 B0-B7 can count.
pub const STEPS_MAX: u16 = 255;

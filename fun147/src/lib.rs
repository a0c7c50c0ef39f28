//! The Fatek FBs-PLC FUN147 (MHSPO) instruction: multi-axis linear interpolation from a
//! step table held in registers, free of the controller around it.
//!
//! - `plc`: the register image (R, D, their 32-bit views, X/Y/M/S) as a trait, and an
//!   in-memory one;
//! - `asm`: the text form (SPD, LIN/LINE, WAIT, EXT, GOTO, MEND) to steps and back;
//! - `image`: steps to the registers at SR and back, with the checks of the error codes;
//! - `instr`: the instruction, stepped once per PLC cycle over an [`Axes`];
//! - `axes`: what it needs of the pulse outputs; `sim`: a reference implementation.
//!
//! Manual references are to the FUN147 page of the FBs-PLC positioning manual: its
//! explanation items ("FUN147 expl. 4"), the interface signals, the SR format, the WR+0 and
//! WR+1 tables, the derived command table and the error-code table.

pub mod asm;
pub mod axes;
pub mod code;
pub mod image;
pub mod instr;
pub mod plc;
pub mod sim;
pub mod step;

pub use asm::{AsmError, AsmErrorKind, assemble, disassemble};
pub use axes::{Axes, AxisSet};
pub use code::ErrorCode;
pub use image::Program;
pub use instr::{Fun147, Inputs, OperandError, Outputs};
pub use plc::{MemPlc, Plc, Reg, Relay};
pub use sim::SimAxes;
pub use step::{Condition, Coord, Goto, Mode, Motion, Step, Travel, Unit, Value16, Value32};

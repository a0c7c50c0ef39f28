//! Status queries (`api::Kind::Query`), answered from a snapshot in the reader's own
//! address space: one match over `api::Query`, so that every query of the registry has
//! its answer here.

use api::{ErrorCode, Query, SystemError};

use crate::messages::{AxisSnapshot, Snapshot, motion_status};

/// A query's answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    Int(i64),
    Double(f64),
    Bool(bool),
}

/// Argument words as the registry types them (see `messages::Request`).
#[derive(Clone, Copy)]
pub struct Words<'a>(pub &'a [u64]);

impl Words<'_> {
    pub fn int(&self, i: usize) -> i64 {
        self.0[i] as i64
    }

    pub fn double(&self, i: usize) -> f64 {
        f64::from_bits(self.0[i])
    }
}

pub fn evaluate(query: Query, args: Words, s: &Snapshot) -> Result<Value, ErrorCode> {
    let axis = || axis(s, args.int(0));
    let status = |bit| axis().map(|a| Value::Bool(a.motion_status & bit != 0));
    Ok(match query {
        Query::IsEnabled => status(motion_status::ENABLED)?,
        Query::IsMoving => status(motion_status::MOVING)?,
        Query::IsInPos => status(motion_status::IN_POSITION)?,
        Query::GetPosFb => Value::Double(axis()?.pos_fb),
        Query::GetRefPos => Value::Double(axis()?.ref_pos),
        Query::GetAxisLastErr => Value::Int(axis()?.last_err as i64),
    })
}

/// The axis a query names, or HMPL's "argument out of range".
pub fn axis(s: &Snapshot, id: i64) -> Result<&AxisSnapshot, ErrorCode> {
    usize::try_from(id)
        .ok()
        .filter(|&i| i < s.axis_count as usize)
        .map(|i| &s.axes[i])
        .ok_or(ErrorCode::System(SystemError::HmplArgOutOfRange))
}

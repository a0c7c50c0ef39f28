//! Status queries (`api::Kind::Query`), answered from a snapshot in the reader's own
//! address space: one match over `api::Query`, so that every query of the registry has
//! its answer here.

use api::{ErrorCode, Query, SystemError};

use crate::messages::{AxisSnapshot, PdoEntrySnapshot, Snapshot, motion_status};

/// A query's answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    Int(i64),
    Double(f64),
    Bool(bool),
    /// An out-pointer buffer (at most 8 bytes: the widest drive object).
    Bytes {
        data: [u8; 8],
        len: u8,
    },
}

/// One or two values: the C return value and an out-pointer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Answer(pub Value, pub Option<Value>);

impl From<Value> for Answer {
    fn from(v: Value) -> Self {
        Answer(v, None)
    }
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

/// AL state codes (HMPL 2.5).
const ECAT_PRE_OP: u32 = 2;
const ECAT_OP: u32 = 8;

pub fn evaluate(query: Query, args: Words, s: &Snapshot) -> Result<Answer, ErrorCode> {
    let axis = || axis(s, args.int(0));
    let status = |bit| axis().map(|a| Value::Bool(a.motion_status & bit != 0));
    let slave = |id: i64| usize::try_from(id).ok().filter(|&i| i < s.slave_count as usize).map(|i| &s.slaves[i]);
    Ok(match query {
        Query::IsEnabled => status(motion_status::ENABLED)?.into(),
        Query::IsMoving => status(motion_status::MOVING)?.into(),
        Query::IsInPos => status(motion_status::IN_POSITION)?.into(),
        Query::GetPosFb => Value::Double(axis()?.pos_fb).into(),
        Query::GetRefPos => Value::Double(axis()?.ref_pos).into(),
        Query::GetAxisLastErr => Value::Int(axis()?.last_err as i64).into(),
        Query::ReadPDO => match read_pdo(s, args) {
            Some((value, _)) => Value::Int(value).into(),
            None => Value::Int(-1).into(),
        },
        Query::ReadPDOEx => match read_pdo(s, args) {
            Some((value, len)) => {
                let mut data = [0; 8];
                data[..len].copy_from_slice(&value.to_le_bytes()[..len]);
                Answer(Value::Int(0), Some(Value::Bytes { data, len: len as u8 }))
            }
            None => Answer(Value::Int(-1), Some(Value::Bytes { data: [0; 8], len: 0 })),
        },
        Query::IsSystemInit => Value::Bool(false).into(),
        Query::IsSystemOper => Value::Bool(s.ecat_state == ECAT_OP && s.system_error == 0).into(),
        Query::IsSystemPreOp => Value::Bool(s.ecat_state == ECAT_PRE_OP).into(),
        Query::IsSystemError => Value::Bool(s.system_error != 0).into(),
        Query::GetECATSt => Value::Int(s.ecat_state as i64).into(),
        Query::GetSlvECATSt => Value::Int(slave(args.int(0)).map_or(-1, |sl| sl.al_state as i64)).into(),
        Query::GetSlaveNum => Value::Int(s.slave_count as i64).into(),
        Query::GetSlvChNum => {
            let (id, slot) = api::constants::split_slave_slot(args.int(0));
            let count = match (slave(id), slot, args.int(1)) {
                (Some(sl), 0, 1) => sl.digital_inputs as i64,
                (Some(sl), 0, 2) => sl.digital_outputs as i64,
                (Some(_), 0, 3 | 4) => 0,
                _ => -1,
            };
            Value::Int(count).into()
        }
        Query::GetSlvSlotNum => Value::Int(if slave(args.int(0)).is_some() { 0 } else { -1 }).into(),
    })
}

/// An object in a slave's process data: its value (sign-extended) and length in bytes.
fn read_pdo(s: &Snapshot, args: Words) -> Option<(i64, usize)> {
    let slave = s.slaves.get(usize::try_from(args.int(0)).ok()?).filter(|_| args.int(0) < s.slave_count as i64)?;
    let (index, sub) = (args.int(1), args.int(2));
    let find = |entries: &[PdoEntrySnapshot], image: &[u8]| {
        entries.iter().find(|e| e.index as i64 == index && e.sub as i64 == sub).map(|e| {
            let len = e.bits as usize / 8;
            let mut raw = [0u8; 8];
            raw[..len].copy_from_slice(&image[e.offset as usize..e.offset as usize + len]);
            let value = u64::from_le_bytes(raw);
            let shift = 64 - e.bits as u32;
            let value = if e.signed != 0 { ((value << shift) as i64) >> shift } else { value as i64 };
            (value, len)
        })
    };
    find(&slave.tx[..slave.tx_count as usize], &slave.inputs)
        .or_else(|| find(&slave.rx[..slave.rx_count as usize], &slave.outputs))
}

/// The axis a query names, or HMPL's "argument out of range".
pub fn axis(s: &Snapshot, id: i64) -> Result<&AxisSnapshot, ErrorCode> {
    usize::try_from(id)
        .ok()
        .filter(|&i| i < s.axis_count as usize)
        .map(|i| &s.axes[i])
        .ok_or(ErrorCode::System(SystemError::HmplArgOutOfRange))
}

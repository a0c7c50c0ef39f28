//! A command's reply (`ipc::call::Reply`) as the registry's typed values, and why a
//! reply's nonzero code failed: the one decode and the one explanation every front end
//! (the Lua bindings, the Native ASCII server, the web view through it) shows.

use api::alarms::{Alarm, Event};
use api::{Command, ErrorCode, SdoAbort, ValueType};
use ipc::call::Reply;

/// One returned value, typed by the function's `returns`.
#[derive(Clone, Debug, PartialEq)]
pub enum Value<'r> {
    /// A C `int` (and a `Timer` or `Any`, which no command returns).
    Int(i64),
    /// A C `double`.
    Double(f64),
    /// HMPL's TRUE/FALSE.
    Bool(bool),
    /// An out-pointer buffer: the reply's blob.
    Bytes(&'r [u8]),
    /// An out-pointer array of doubles: every value word after the ones before it.
    Doubles(Vec<f64>),
}

/// The values `reply` returns for `command`, in the declaration's order (the C return
/// value first, then the out-pointers).
pub fn decode(command: Command, reply: &Reply) -> Vec<Value<'_>> {
    let word = |i: usize| reply.values.get(i).copied().unwrap_or(0);
    command
        .spec()
        .returns
        .iter()
        .enumerate()
        .map(|(i, ty)| match ty {
            ValueType::Bytes => Value::Bytes(reply.blob()),
            ValueType::Doubles => {
                let words = reply.values.get(i..reply.valuec as usize).unwrap_or(&[]);
                Value::Doubles(words.iter().map(|&w| f64::from_bits(w)).collect())
            }
            ValueType::Bool => Value::Bool(word(i) != 0),
            ValueType::Double => Value::Double(f64::from_bits(word(i))),
            ValueType::Int | ValueType::Str | ValueType::Timer | ValueType::Any | ValueType::Memory => {
                Value::Int(word(i) as i64)
            }
        })
        .collect()
}

/// A nonzero reply code in words: an HMPL error code (HMPL ch. 18), a CiA 301 SDO abort
/// code, or else a DXMC alarm (DXMC 9) with its event's meaning.
pub fn explain(rc: u32) -> String {
    if let Some(code) = ErrorCode::from_code(rc) {
        return code.to_string();
    }
    if let Ok(abort) = SdoAbort::try_from(rc) {
        return abort.to_string();
    }
    let alarm = Alarm(rc);
    format!("{alarm} alarm: {}", Event::from(alarm.event_code()).meaning())
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::{AxisError, SystemError};

    /// Each returned type from its words: an out-buffer from the blob (HMPL 17.2.2), an
    /// array from the words after the return code (HMPL 8.3.32), doubles from their bits.
    #[test]
    fn values_by_the_registry() {
        let mut reply = Reply::to(&ipc::call::Request::new(0));
        reply.push_int(0);
        reply.push_double(2.5);
        reply.push_double(-1.0);
        assert_eq!(decode(Command::GetPTPulse, &reply), [Value::Int(0), Value::Double(2.5), Value::Double(-1.0)]);
        assert_eq!(decode(Command::GetGrpPoseCmd, &reply), [Value::Int(0), Value::Doubles(vec![2.5, -1.0])]);
        reply.set_blob(&[1, 2]);
        assert_eq!(decode(Command::ReadSDOEx, &reply), [Value::Int(0), Value::Bytes(&[1, 2])]);
    }

    /// Codes of the three kinds, in words.
    #[test]
    fn explanations() {
        assert_eq!(
            explain(ErrorCode::axis(1, AxisError::CmdInvalidPos).code()),
            ErrorCode::axis(1, AxisError::CmdInvalidPos).to_string()
        );
        assert_eq!(
            explain(SystemError::HmplArgOutOfRange.id() as u32),
            ErrorCode::System(SystemError::HmplArgOutOfRange).to_string()
        );
        assert_eq!(explain(0x0609_0011), SdoAbort::try_from(0x0609_0011).expect("CiA 301").to_string());
        assert!(explain(0x1001_001F).starts_with("0x1001001F alarm: command buffer busy"), "{}", explain(0x1001_001F));
    }
}

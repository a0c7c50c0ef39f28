//! HMPL ch. 17: drive objects by SDO and in the process data; these return 0 or -1, the
//! reply's `rc` says why (a CiA 301 abort code or an HMPL code).

use api::{CommandCall, ErrorCode, SdoAbort, SystemError};
use ipc::call::Reply;

use super::{Done, Failure, Outcome, now};
use crate::machine::Machine;
use devices::coe::fits_width;
use devices::ecat::{AlState, Field};

/// HMPL 17.2.1 to 17.2.4, by SDO: at once in memory; on a wire the call waits for the
/// mailbox's answer (`Done::Later`, then `resume` asks again each cycle).
pub(super) fn sdo(m: &mut Machine, call: &CommandCall, reply: &mut Reply) -> Outcome {
    use CommandCall as C;
    let result = match *call {
        C::ReadSDO { slv_id, obj_index, obj_subindex, obj_length } => {
            read_sdo(m, [slv_id, obj_index, obj_subindex, obj_length], reply)
        }
        C::ReadSDOEx { slv_id, obj_index, obj_subindex, obj_length } => {
            read_sdo_ex(m, [slv_id, obj_index, obj_subindex, obj_length], reply)
        }
        C::WriteSDO { slv_id, obj_index, obj_subindex, obj_length, obj_value } => {
            write_sdo(m, [slv_id, obj_index, obj_subindex, obj_length], obj_value)
        }
        C::WriteSDOEx { slv_id, obj_index, obj_subindex, obj_length, ref obj_value } => {
            write_sdo_ex(m, [slv_id, obj_index, obj_subindex, obj_length], obj_value)
        }
        _ => Err(Failure::Code(SystemError::HmplNotSupported.into())),
    };
    match result {
        Err(Failure::Transfer) => Ok(Done::Later),
        other => other,
    }
}

/// HMPL 17.2.1: the object's value (sign-extended).
fn read_sdo(m: &mut Machine, [slave_id, index, subindex, len]: [i64; 4], reply: &mut Reply) -> Outcome {
    let (value, _) = sdo_read(m, slave_id, index, subindex, len)?;
    reply.push_int(value);
    Ok(Done::Now)
}

/// HMPL 17.2.2: 0 and the object's bytes.
fn read_sdo_ex(m: &mut Machine, [slave_id, index, subindex, len]: [i64; 4], reply: &mut Reply) -> Outcome {
    let (value, len) = sdo_read(m, slave_id, index, subindex, len)?;
    reply.push_int(0);
    reply.set_blob(&value.to_le_bytes()[..len]);
    Ok(Done::Now)
}

/// HMPL 17.2.3: writes a value `len` bytes wide.
fn write_sdo(m: &mut Machine, [slave_id, index, subindex, len]: [i64; 4], value: i64) -> Outcome {
    let len = length(len)?;
    let value = fitting(value, len)?.to_le_bytes();
    now(m.network.sdo_write(slave(slave_id)?, object(index)?, sub(subindex)?, &value[..len]))
}

/// HMPL 17.2.4: writes bytes, exactly `len` of them.
fn write_sdo_ex(m: &mut Machine, [slave_id, index, subindex, len]: [i64; 4], data: &[u8]) -> Outcome {
    let len = length(len)?;
    if data.len() != len {
        return Err(Failure::MinusOne(SdoAbort::LengthMismatch.code()));
    }
    now(m.network.sdo_write(slave(slave_id)?, object(index)?, sub(subindex)?, data))
}

/// HMPL 17.2.7: writes a mapped RxPDO object.
pub(super) fn write_pdo(m: &mut Machine, [slave_id, index, subindex]: [i64; 3], value: i64) -> Outcome {
    let field = output_field(m, slave_id, index, subindex)?;
    let value = fitting(value, field.data_type().bytes())?;
    let (_, outputs) = m.network.images_mut();
    field.write(outputs, value);
    Ok(Done::Now)
}

/// HMPL 17.2.8: forces a mapped RxPDO object until it is released.
pub(super) fn force_write_pdo(m: &mut Machine, [slave_id, index, subindex]: [i64; 3], value: i64) -> Outcome {
    let field = output_field(m, slave_id, index, subindex)?;
    let value = fitting(value, field.data_type().bytes())?;
    if m.forces.force(field, value) { Ok(Done::Now) } else { Err(Failure::MinusOne(0)) }
}

/// HMPL 17.2.9: releases a forced object.
pub(super) fn release_pdo(m: &mut Machine, [slave_id, index, subindex]: [i64; 3]) -> Outcome {
    let field = output_field(m, slave_id, index, subindex)?;
    if m.forces.release(field) { Ok(Done::Now) } else { Err(Failure::MinusOne(0)) }
}

/// Simulator only: a drive fault of the CoE manual's table 4-16.
pub(super) fn sim_drive_fault(m: &mut Machine, slave_id: i64, code: i64) -> Outcome {
    let code = u16::try_from(code).map_err(|_| Failure::MinusOne(0))?;
    m.network.inject_fault(slave(slave_id)?, code).map_err(|_| Failure::MinusOne(0))?;
    Ok(Done::Now)
}

pub(super) fn out_of_range() -> Failure {
    Failure::MinusOne(ErrorCode::System(SystemError::HmplArgOutOfRange).code())
}

fn slave(id: i64) -> Result<usize, Failure> {
    usize::try_from(id).map_err(|_| out_of_range())
}

fn object(index: i64) -> Result<u16, Failure> {
    u16::try_from(index).map_err(|_| Failure::MinusOne(SdoAbort::NoObject.code()))
}

fn sub(sub: i64) -> Result<u8, Failure> {
    u8::try_from(sub).map_err(|_| Failure::MinusOne(SdoAbort::NoSubIndex.code()))
}

/// An object is 1 to 8 bytes.
fn length(len: i64) -> Result<usize, Failure> {
    usize::try_from(len).ok().filter(|l| (1..=8).contains(l)).ok_or(Failure::MinusOne(SdoAbort::LengthMismatch.code()))
}

/// A value for an object `len` bytes wide: cut to fit, it would be another value.
fn fitting(value: i64, len: usize) -> Result<i64, Failure> {
    if fits_width(value, len) { Ok(value) } else { Err(Failure::MinusOne(SdoAbort::ValueRange.code())) }
}

/// An SDO read whose length must be the object's.
fn sdo_read(
    m: &mut Machine,
    slave_id: i64,
    index: i64,
    subindex: i64,
    length_arg: i64,
) -> Result<(i64, usize), Failure> {
    let len = length(length_arg)?;
    let (value, size) = m.network.sdo_read(slave(slave_id)?, object(index)?, sub(subindex)?)?;
    if size != len {
        return Err(Failure::MinusOne(SdoAbort::LengthMismatch.code()));
    }
    Ok((value, size))
}

/// An object mapped in the RxPDO of a slave in Op.
fn output_field(m: &Machine, slave_id: i64, index: i64, subindex: i64) -> Result<Field, Failure> {
    if m.network.state() != AlState::Op {
        return Err(Failure::MinusOne(ErrorCode::System(SystemError::HmplNotInOpMode).code()));
    }
    m.network
        .output_field(slave(slave_id)?, object(index)?, sub(subindex)?)
        .ok_or(Failure::MinusOne(SdoAbort::NotMappable.code()))
}

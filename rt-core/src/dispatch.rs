//! Carries out the commands scripts send: one match over `api::Command`, so that the
//! compiler holds every command of the registry to an implementation.

use api::{Command, ErrorCode, FunctionSpec, SdoAbort, SystemError};
use ipc::messages::{Reply, Request};

use crate::cycle::Machine;
use crate::ecat::{AlState, Field, SdoError};
use crate::motion::axis::Axis;

/// How a command failed, in the return convention of its chapter.
enum Failure {
    /// Most functions return the HMPL error code (and record it as a last error).
    Code(ErrorCode),
    /// Ch. 17 returns -1; `rc` carries the reason (a CiA 301 abort code or an HMPL code).
    MinusOne(u32),
}

impl From<ErrorCode> for Failure {
    fn from(e: ErrorCode) -> Self {
        Failure::Code(e)
    }
}

impl From<SdoError> for Failure {
    fn from(e: SdoError) -> Self {
        Failure::MinusOne(match e {
            SdoError::Abort(abort) => abort.code(),
            SdoError::NoMailbox => SdoAbort::DeviceState.code(),
            SdoError::NoSlave(_) => ErrorCode::System(SystemError::HmplArgOutOfRange).code(),
        })
    }
}

/// Applies one request to the machine and fills its reply: the function's return values,
/// and `rc` 0 or the reason it failed.
pub fn execute(machine: &mut Machine, request: &Request, reply: &mut Reply) {
    let result = match Command::from_id(request.func) {
        None => Err(ErrorCode::System(SystemError::HmplNotSupported).into()),
        Some(command) if !arguments_fit(command.spec(), request) => Err(SystemError::HmplInvalidArg.into()),
        Some(command) => run(machine, command, request, reply),
    };
    match result {
        Ok(()) if reply.valuec == 0 => reply.push_int(0),
        Ok(()) => {}
        Err(Failure::Code(code)) => {
            reply.rc = code.code();
            reply.valuec = 0;
            reply.push_int(code.code() as i64);
        }
        Err(Failure::MinusOne(reason)) => {
            reply.rc = reason;
            reply.valuec = 0;
            reply.push_int(-1);
        }
    }
}

impl From<SystemError> for Failure {
    fn from(e: SystemError) -> Self {
        Failure::Code(e.into())
    }
}

fn arguments_fit(spec: &FunctionSpec, request: &Request) -> bool {
    request.argc as usize == spec.args.len() && request.blob_len as usize <= request.blob.len()
}

fn run(m: &mut Machine, command: Command, r: &Request, reply: &mut Reply) -> Result<(), Failure> {
    match command {
        Command::Enable => on_axis(m, r, |a| a.enable()),
        Command::Disable => on_axis(m, r, |a| a.disable()),
        Command::MoveAbs => on_axis(m, r, |a| a.move_abs(r.double(1))),
        Command::MoveRel => on_axis(m, r, |a| a.move_rel(r.double(1))),
        Command::SetVel => on_axis(m, r, |a| a.set_vel(r.double(1))),
        Command::SetAcc => on_axis(m, r, |a| a.set_acc(r.double(1))),
        Command::SetDec => on_axis(m, r, |a| a.set_dec(r.double(1))),
        Command::ReadSDO => {
            let (value, _) = sdo_read(m, r)?;
            reply.push_int(value);
            Ok(())
        }
        Command::ReadSDOEx => {
            let (value, len) = sdo_read(m, r)?;
            reply.push_int(0);
            reply.set_blob(&value.to_le_bytes()[..len]);
            Ok(())
        }
        Command::WriteSDO => {
            let len = length(r.int(3))?;
            let value = r.int(4).to_le_bytes();
            Ok(m.network.sdo_write(slave(r)?, object(r.int(1))?, sub(r.int(2))?, &value[..len])?)
        }
        Command::WriteSDOEx => {
            let len = length(r.int(3))?;
            let data = r.blob();
            if data.len() != len {
                return Err(Failure::MinusOne(SdoAbort::LengthMismatch.code()));
            }
            Ok(m.network.sdo_write(slave(r)?, object(r.int(1))?, sub(r.int(2))?, data)?)
        }
        Command::WritePDO => {
            let field = output_field(m, r)?;
            let (_, outputs) = m.network.images_mut();
            field.write(outputs, r.int(3));
            Ok(())
        }
        Command::ForceWritePDO => {
            let field = output_field(m, r)?;
            if m.forces.force(field, r.int(3)) { Ok(()) } else { Err(Failure::MinusOne(0)) }
        }
        Command::ReleasePDO => {
            let field = output_field(m, r)?;
            if m.forces.release(field) { Ok(()) } else { Err(Failure::MinusOne(0)) }
        }
        Command::SimDriveFault => {
            let code = u16::try_from(r.int(1)).map_err(|_| Failure::MinusOne(0))?;
            m.network.inject_fault(slave(r)?, code).map_err(|_| Failure::MinusOne(0))
        }
    }
}

/// Runs an axis command on the axis named by argument 0. Motion needs EtherCAT in Op
/// (HMPL 2.2; `eERR_HMPL_NOT_IN_OP_MODE`).
fn on_axis(
    m: &mut Machine,
    r: &Request,
    f: impl FnOnce(&mut Axis) -> Result<(), api::AxisError>,
) -> Result<(), Failure> {
    if m.network.state() != AlState::Op {
        return Err(SystemError::HmplNotInOpMode.into());
    }
    let axis = m.kernel.axis_mut(r.int(0))?;
    let id = axis.id();
    f(axis).map_err(|e| Failure::Code(ErrorCode::axis(id, e)))
}

fn out_of_range() -> Failure {
    Failure::MinusOne(ErrorCode::System(SystemError::HmplArgOutOfRange).code())
}

fn slave(r: &Request) -> Result<usize, Failure> {
    usize::try_from(r.int(0)).map_err(|_| out_of_range())
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

/// An SDO read whose length must be the object's.
fn sdo_read(m: &Machine, r: &Request) -> Result<(i64, usize), Failure> {
    let len = length(r.int(3))?;
    let (value, size) = m.network.sdo_read(slave(r)?, object(r.int(1))?, sub(r.int(2))?)?;
    if size != len {
        return Err(Failure::MinusOne(SdoAbort::LengthMismatch.code()));
    }
    Ok((value, size))
}

/// An object mapped in the RxPDO of a slave in Op.
fn output_field(m: &Machine, r: &Request) -> Result<Field, Failure> {
    if m.network.state() != AlState::Op {
        return Err(Failure::MinusOne(ErrorCode::System(SystemError::HmplNotInOpMode).code()));
    }
    m.network
        .output_field(slave(r)?, object(r.int(1))?, sub(r.int(2))?)
        .ok_or(Failure::MinusOne(SdoAbort::NotMappable.code()))
}

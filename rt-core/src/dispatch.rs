//! Carries out the commands scripts send: one match over `api::Command`, so that the
//! compiler holds every command of the registry to an implementation.

use api::{Command, ErrorCode, FunctionSpec, SystemError};
use ipc::messages::{Reply, Request};

use crate::motion::Kernel;
use crate::motion::axis::Axis;

/// Applies one request to the kernel and fills its reply: `rc` 0 or the HMPL error code.
pub fn execute(kernel: &mut Kernel, request: &Request, reply: &mut Reply) {
    let result = match Command::from_id(request.func) {
        None => Err(ErrorCode::System(SystemError::HmplNotSupported)),
        Some(command) if !arguments_fit(command.spec(), request) => Err(SystemError::HmplInvalidArg.into()),
        Some(command) => run(kernel, command, request),
    };
    reply.rc = result.err().map_or(0, ErrorCode::code);
}

fn arguments_fit(spec: &FunctionSpec, request: &Request) -> bool {
    request.argc as usize == spec.args.len() && request.blob_len as usize <= request.blob.len()
}

fn run(kernel: &mut Kernel, command: Command, r: &Request) -> Result<(), ErrorCode> {
    match command {
        Command::Enable => on_axis(kernel, r, |a| a.enable()),
        Command::Disable => on_axis(kernel, r, |a| a.disable()),
        Command::MoveAbs => on_axis(kernel, r, |a| a.move_abs(r.double(1))),
        Command::MoveRel => on_axis(kernel, r, |a| a.move_rel(r.double(1))),
        Command::SetVel => on_axis(kernel, r, |a| a.set_vel(r.double(1))),
        Command::SetAcc => on_axis(kernel, r, |a| a.set_acc(r.double(1))),
        Command::SetDec => on_axis(kernel, r, |a| a.set_dec(r.double(1))),
    }
}

/// Runs an axis command on the axis named by argument 0.
fn on_axis(
    kernel: &mut Kernel,
    r: &Request,
    f: impl FnOnce(&mut Axis) -> Result<(), api::AxisError>,
) -> Result<(), ErrorCode> {
    let axis = kernel.axis_mut(r.int(0))?;
    let id = axis.id();
    f(axis).map_err(|e| ErrorCode::axis(id, e))
}

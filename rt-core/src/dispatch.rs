//! Carries out the commands scripts send: one match over `api::Command`, so that the
//! compiler holds every command of the registry to an implementation.

use api::alarms::{Alarm, Event as AlarmEvent};
use api::registry::ArgType;
use api::{AxisError, Command, ErrorCode, FunctionSpec, SdoAbort, SystemError};
use ipc::Disposition;
use ipc::messages::{Reply, Request};

use crate::drive::od::fits_width;
use crate::ecat::{AlState, Field, SdoError};
use crate::io::NoSuchPin;
use crate::machine::Machine;
use crate::motion::axis::{Axis, Ignore};
use crate::motion::pvt::{MAX_POINTS, PvtPoint};
use crate::motion::settings::HomeSettings;
use crate::tasks::Entry;

/// How a command failed, in the return convention of its chapter.
enum Failure {
    /// Most functions return the HMPL error code (and record it as a last error).
    Code(ErrorCode),
    /// Ch. 9 and 17 return -1; `rc` carries the reason (a CiA 301 abort code or an HMPL code).
    MinusOne(u32),
    /// Refused with an alarm (DXMC format), returned as the code.
    Alarm(Alarm),
}

impl From<ErrorCode> for Failure {
    fn from(e: ErrorCode) -> Self {
        Failure::Code(e)
    }
}

impl From<SystemError> for Failure {
    fn from(e: SystemError) -> Self {
        Failure::Code(e.into())
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

/// What a command did: finished, or started something that answers when it completes.
enum Done {
    Now,
    Later,
}

/// Applies one request of task `caller` to the machine and fills its reply: the function's
/// return values, and `rc` 0 or the reason it failed.
pub fn execute(machine: &mut Machine, caller: u8, request: &Request, reply: &mut Reply) -> Disposition {
    let result = match Command::from_id(request.func) {
        None => Err(SystemError::HmplNotSupported.into()),
        Some(_) if !machine.tasks.accepts_commands(caller) => Err(SystemError::TaskNotRunning.into()),
        Some(command) if !arguments_fit(command.spec(), request) => Err(SystemError::HmplInvalidArg.into()),
        Some(command) => match check_ranges(machine, command.spec(), request) {
            Ok(()) => run(machine, caller, command, request, reply),
            Err(failure) => Err(failure),
        },
    };
    match result {
        Ok(Done::Later) => return Disposition::Defer,
        Ok(Done::Now) => finish(machine, reply, Ok(())),
        Err(failure) => finish(machine, reply, Err(failure)),
    }
    Disposition::Reply
}

/// Completes a deferred call once its operation is over; false while it still runs.
pub fn resume(machine: &mut Machine, request: &Request, reply: &mut Reply) -> bool {
    let result = match Command::from_id(request.func) {
        Some(Command::MoveHome) => {
            let Ok(axis) = machine.kernel.axis_mut(request.int(0)) else { return true };
            let id = axis.id();
            match axis.take_home_result() {
                None => return false,
                Some(result) => result.map_err(|e| Failure::Code(ErrorCode::axis(id, e))),
            }
        }
        Some(Command::StartTask | Command::StartTaskFunc) => {
            let Ok(task) = u8::try_from(request.int(0)) else { return true };
            match machine.tasks.take_start_result(task) {
                None => return false,
                Some(result) => result.map_err(Failure::from),
            }
        }
        // The caller stopped itself (StopTask of itself, StopAllTask, EStop): no answer.
        _ => return false,
    };
    finish(machine, reply, result);
    true
}

fn finish(machine: &mut Machine, reply: &mut Reply, result: Result<(), Failure>) {
    match result {
        Ok(()) if reply.valuec == 0 => reply.push_int(0),
        Ok(()) => {}
        Err(Failure::Code(code)) => {
            if let ErrorCode::System(_) = code {
                machine.kernel.record_system_error(code.code());
            }
            reply.rc = code.code();
            reply.valuec = 0;
            reply.push_int(code.code() as i64);
        }
        Err(Failure::MinusOne(reason)) => {
            reply.rc = reason;
            reply.valuec = 0;
            reply.push_int(-1);
        }
        Err(Failure::Alarm(alarm)) => {
            reply.rc = alarm.0;
            reply.valuec = 0;
            reply.push_int(alarm.0 as i64);
        }
    }
}

fn arguments_fit(spec: &FunctionSpec, request: &Request) -> bool {
    request.argc as usize == spec.args.len() && request.blob_len as usize <= request.blob.len()
}

/// Every argument the registry gives a quantity is checked against its range before the
/// command runs, on the axis named by the axis argument before it. One path for every
/// command: no setter can forget it, and NaN, infinities and numbers no drive could carry
/// never reach the kernel (issue 11).
fn check_ranges(m: &mut Machine, spec: &FunctionSpec, r: &Request) -> Result<(), Failure> {
    for (i, quantity, axis_arg) in spec.quantities() {
        let Some(axis_arg) = axis_arg else {
            // The axis argument itself.
            m.kernel.axis_mut(r.int(i))?;
            continue;
        };
        let axis = m.kernel.axis_mut(r.int(axis_arg))?;
        let id = axis.id();
        let refused = |e: AxisError| Failure::from(ErrorCode::axis(id, e));
        match spec.args[i].ty {
            ArgType::Double => axis.admit(quantity, r.double(i)).map_err(refused)?,
            ArgType::Doubles => {
                for value in doubles(spec, r, i)? {
                    axis.admit(quantity, value).map_err(refused)?;
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// The numbers of `double*` argument `i`: the blob holds the arrays, strings and bytes one
/// after the other, their lengths are in the argument words.
fn doubles<'r>(spec: &FunctionSpec, r: &'r Request, i: usize) -> Result<impl Iterator<Item = f64> + 'r, Failure> {
    let bytes = |j: usize| {
        let len = usize::try_from(r.int(j)).unwrap_or(usize::MAX);
        match spec.args[j].ty {
            ArgType::Doubles => len.saturating_mul(8),
            ArgType::Bytes | ArgType::Str => len,
            _ => 0,
        }
    };
    let start = (0..i).fold(0usize, |sum, j| sum.saturating_add(bytes(j)));
    let array = r.blob().get(start..start.saturating_add(bytes(i))).ok_or(SystemError::HmplInvalidArg)?;
    Ok(array.chunks_exact(8).map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes"))))
}

type Outcome = Result<Done, Failure>;

fn now(result: Result<(), impl Into<Failure>>) -> Outcome {
    result.map(|()| Done::Now).map_err(Into::into)
}

/// The axis a motion command sets going: one task at a time may command it in a cycle,
/// and an E-stop refuses it until the axis is enabled again.
fn moved_axis(command: Command, r: &Request) -> Option<i64> {
    match command {
        Command::MoveAbs
        | Command::MoveRel
        | Command::MoveVel
        | Command::MoveTrq
        | Command::MovePVT
        | Command::Stop
        | Command::Halt
        | Command::Resume
        | Command::MoveHome
        | Command::GearOut => Some(r.int(0)),
        Command::GearIn => Some(r.int(1)),
        _ => None,
    }
}

/// Checks that `caller` may command axis `a` in this cycle.
fn may_command(m: &mut Machine, caller: u8, a: i64) -> Result<u8, Failure> {
    let cycle = m.cycle;
    let axis = m.kernel.axis_mut(a)?;
    let id = axis.id();
    if axis.is_emergency_stopped() {
        return Err(SystemError::EmergencyStop.into());
    }
    if !m.state.allows_motion() {
        return Err(Failure::Alarm(m.tasks.axis_alarm(caller, id, AlarmEvent::WrongMode, cycle)));
    }
    if axis.check_claim(caller, cycle).is_err() {
        return Err(Failure::Alarm(m.tasks.axis_alarm(caller, id, AlarmEvent::CommandBufferBusy, cycle)));
    }
    Ok(id)
}

fn run(m: &mut Machine, caller: u8, command: Command, r: &Request, reply: &mut Reply) -> Outcome {
    let moved = match moved_axis(command, r) {
        Some(a) if m.network.state() == AlState::Op => Some(may_command(m, caller, a)?),
        _ => None,
    };
    let outcome = run_command(m, caller, command, r, reply);
    if let (Some(axis), Ok(_)) = (moved, &outcome) {
        let cycle = m.cycle;
        let run_speed = m.run_speed(caller);
        if let Ok(axis) = m.kernel.axis_mut(axis as i64) {
            axis.claim(caller, cycle, run_speed);
        }
    }
    outcome
}

fn run_command(m: &mut Machine, caller: u8, command: Command, r: &Request, reply: &mut Reply) -> Outcome {
    let (a, x) = (r.int(0), r.double(1));
    match command {
        // HMPL 5.2: motion.
        Command::Enable => motion(m, |m| now(m.kernel.enable(a))),
        Command::Disable => motion(m, |m| now(m.kernel.disable(a))),
        Command::Reset => axis(m, r, |ax| ax.reset()),
        Command::MoveAbs => axis(m, r, |ax| ax.move_abs(x)),
        Command::MoveRel => axis(m, r, |ax| ax.move_rel(x)),
        Command::MoveVel => axis(m, r, |ax| ax.move_vel(x)),
        Command::MoveTrq => axis(m, r, |ax| ax.move_trq(x)),
        Command::MovePVT => {
            let (points, count) = pvt_points(r)?;
            axis(m, r, |ax| ax.move_pvt(&points[..count]))
        }
        Command::Stop => axis(m, r, |ax| ax.stop()),
        Command::Halt => axis(m, r, |ax| ax.halt()),
        Command::Resume => axis(m, r, |ax| ax.resume()),
        // HMPL 5.3: settings.
        Command::SetVel => axis(m, r, |ax| ax.set_vel(x)),
        Command::SetAcc => axis(m, r, |ax| ax.set_acc(x)),
        Command::SetAccTime => axis(m, r, |ax| ax.set_acc_time(x)),
        Command::SetDec => axis(m, r, |ax| ax.set_dec(x)),
        Command::SetDecTime => axis(m, r, |ax| ax.set_dec_time(x)),
        Command::SetKillDec => axis(m, r, |ax| ax.set_kill_dec(x)),
        Command::SetSWRL => axis(m, r, |ax| ax.set_swrl(x)),
        Command::SetSWLL => axis(m, r, |ax| ax.set_swll(x)),
        Command::SetSMTime => axis(m, r, |ax| ax.set_sm_time(x)),
        Command::SetPos => motion(m, |m| now(m.kernel.set_pos(a, x))),
        Command::IgnoreHWL => axis(m, r, |ax| ax.set_ignore(Ignore::HardwareLimits, r.int(1) != 0)),
        Command::IgnoreSWL => axis(m, r, |ax| ax.set_ignore(Ignore::SoftwareLimits, r.int(1) != 0)),
        Command::IgnorePE => axis(m, r, |ax| ax.set_ignore(Ignore::PositionError, r.int(1) != 0)),
        Command::SetVelScale => axis(m, r, |ax| ax.set_vel_scale(x)),
        Command::SetRollover => axis(m, r, |ax| ax.set_rollover(x)),
        Command::SetOpMode => axis(m, r, |ax| ax.set_op_mode(r.int(1))),
        Command::SetBufferMode => axis(m, r, |ax| ax.set_buffer_mode(r.int(1))),
        Command::SetPosWindow => axis(m, r, |ax| ax.set_pos_window(x)),
        Command::SetPosWindowTime => axis(m, r, |ax| ax.set_pos_window_time(x)),
        // HMPL ch. 6 and 7: gear and gantry.
        Command::EnableGear => motion(m, |m| now(m.kernel.enable_gear(a, r.int(1)))),
        Command::DisableGear => motion(m, |m| now(m.kernel.disable_gear(a))),
        Command::GearIn => motion(m, |m| now(m.kernel.gear_in(a, r.int(1), r.double(2)))),
        Command::GearOut => motion(m, |m| now(m.kernel.gear_out(a))),
        Command::EnableGantryPair => motion(m, |m| now(m.kernel.enable_gantry_pair(a, r.int(1)))),
        Command::DisableGantryPair => motion(m, |m| now(m.kernel.disable_gantry_pair(a))),
        // HMPL ch. 20: homing.
        Command::MoveHome => motion(m, |m| {
            let Machine { kernel, network, .. } = m;
            let ax = kernel.axis_mut(a)?;
            let id = ax.id();
            ax.start_homing(network).map_err(|e| ErrorCode::axis(id, e))?;
            Ok(Done::Later)
        }),
        Command::SetHomeMethod => axis(m, r, |ax| ax.set_home(|h| h.set_method(r.int(1)))),
        Command::SetHomeSwitchVel => home_number(m, r, |h| &mut h.switch_vel),
        Command::SetHomeZeroVel => home_number(m, r, |h| &mut h.zero_vel),
        Command::SetHomeAcc => home_number(m, r, |h| &mut h.acc),
        Command::SetHomeOffset => home_number(m, r, |h| &mut h.offset),
        Command::SetHomeTimeout => axis(m, r, |ax| ax.set_home(|h| h.set_timeout(r.int(1)))),
        Command::SetHomedStatus => axis(m, r, |ax| {
            ax.set_homed(r.int(1) != 0);
            Ok(())
        }),
        // HMPL ch. 18: errors.
        Command::ClearAxisLastErr => axis(m, r, |ax| {
            ax.clear_last_err();
            Ok(())
        }),
        Command::ClearGrpLastErr => now(m.kernel.clear_group_last_err(a)),
        // HMPL ch. 17: drive variables.
        Command::ReadSDO => {
            let (value, _) = sdo_read(m, r)?;
            reply.push_int(value);
            Ok(Done::Now)
        }
        Command::ReadSDOEx => {
            let (value, len) = sdo_read(m, r)?;
            reply.push_int(0);
            reply.set_blob(&value.to_le_bytes()[..len]);
            Ok(Done::Now)
        }
        Command::WriteSDO => {
            let len = length(r.int(3))?;
            let value = fitting(r.int(4), len)?.to_le_bytes();
            now(m.network.sdo_write(slave(r)?, object(r.int(1))?, sub(r.int(2))?, &value[..len]))
        }
        Command::WriteSDOEx => {
            let len = length(r.int(3))?;
            let data = r.blob();
            if data.len() != len {
                return Err(Failure::MinusOne(SdoAbort::LengthMismatch.code()));
            }
            now(m.network.sdo_write(slave(r)?, object(r.int(1))?, sub(r.int(2))?, data))
        }
        Command::WritePDO => {
            let field = output_field(m, r)?;
            let value = fitting(r.int(3), field.data_type().bytes())?;
            let (_, outputs) = m.network.images_mut();
            field.write(outputs, value);
            Ok(Done::Now)
        }
        Command::ForceWritePDO => {
            let field = output_field(m, r)?;
            let value = fitting(r.int(3), field.data_type().bytes())?;
            if m.forces.force(field, value) { Ok(Done::Now) } else { Err(Failure::MinusOne(0)) }
        }
        Command::ReleasePDO => {
            let field = output_field(m, r)?;
            if m.forces.release(field) { Ok(Done::Now) } else { Err(Failure::MinusOne(0)) }
        }
        Command::SimDriveFault => {
            let code = u16::try_from(r.int(1)).map_err(|_| Failure::MinusOne(0))?;
            m.network.inject_fault(slave(r)?, code).map_err(|_| Failure::MinusOne(0))?;
            Ok(Done::Now)
        }
        // HMPL ch. 9: controller I/O.
        Command::SimSetGPI => pin(m.io.set_level(a, r.int(1))),
        Command::SetGPO => pin(m.io.set_gpo(a, r.int(1))),
        Command::ToggleGPO => pin(m.io.toggle_gpo(a)),
        Command::SetAllGPO => pin(m.io.set_all_gpo(a)),
        Command::SetGPIInvert => pin(m.io.set_gpi_invert(a, r.int(1))),
        Command::SetGPOInvert => pin(m.io.set_gpo_invert(a, r.int(1))),
        Command::BindEMO => pin(m.io.bind_emo(a)),
        // HMPL ch. 2: system.
        Command::DisableAll => {
            m.kernel.disable_all();
            Ok(Done::Now)
        }
        Command::StopAll => motion(m, |m| {
            m.kernel.stop_all();
            Ok(Done::Now)
        }),
        Command::EStop => {
            m.emergency_stop();
            Ok(Done::Later)
        }
        // HMPL ch. 16: tasks.
        Command::StartTask => {
            let cycle = m.cycle;
            m.tasks.start(a, Entry::TOP_LEVEL, cycle)?;
            Ok(Done::Later)
        }
        Command::StartTaskFunc => {
            let entry = Entry::function(r.blob()).ok_or(SystemError::FuncNotInTask)?;
            let cycle = m.cycle;
            m.tasks.start(a, entry, cycle)?;
            Ok(Done::Later)
        }
        Command::StopTask => {
            let cycle = m.cycle;
            let Machine { tasks, kernel, .. } = m;
            let stopped = tasks.stop(a, cycle, &mut |t, reaction| kernel.react(t, reaction))?;
            Ok(if stopped == caller { Done::Later } else { Done::Now })
        }
        Command::StopAllTask => {
            let cycle = m.cycle;
            let Machine { tasks, kernel, .. } = m;
            tasks.stop_all(cycle, &mut |t, reaction| kernel.react(t, reaction));
            Ok(Done::Later)
        }
    }
}

/// Ch. 9: 0, or -1 for a pin that does not exist.
fn pin(result: Result<(), NoSuchPin>) -> Outcome {
    result.map(|()| Done::Now).map_err(|_| out_of_range())
}

/// A motion command needs EtherCAT in Op (HMPL 2.2; `eERR_HMPL_NOT_IN_OP_MODE`).
fn motion(m: &mut Machine, f: impl FnOnce(&mut Machine) -> Outcome) -> Outcome {
    if m.network.state() != AlState::Op {
        return Err(SystemError::HmplNotInOpMode.into());
    }
    f(m)
}

/// Runs an axis command on the axis named by argument 0.
fn axis(m: &mut Machine, r: &Request, f: impl FnOnce(&mut Axis) -> Result<(), AxisError>) -> Outcome {
    motion(m, |m| {
        let ax = m.kernel.axis_mut(r.int(0))?;
        let id = ax.id();
        now(f(ax).map_err(|e| ErrorCode::axis(id, e)))
    })
}

/// HMPL 20.4 to 20.7: a homing number, its range checked before (`check_ranges`).
fn home_number(m: &mut Machine, r: &Request, field: fn(&mut HomeSettings) -> &mut f64) -> Outcome {
    axis(m, r, |ax| {
        ax.set_home(|h| {
            *field(h) = r.double(1);
            Ok(())
        })
    })
}

/// MovePVT's three arrays follow each other in the blob; argument words 1..3 hold their
/// lengths, word 4 the number of points.
fn pvt_points(r: &Request) -> Result<([PvtPoint; MAX_POINTS + 1], usize), Failure> {
    let count = usize::try_from(r.int(4)).map_err(|_| SystemError::HmplArgOutOfRange)?;
    let lens = [r.int(1), r.int(2), r.int(3)].map(|l| usize::try_from(l).unwrap_or(0));
    if lens.iter().any(|&l| l < count) {
        return Err(SystemError::HmplArgOutOfRange.into());
    }
    let mut points = [PvtPoint::default(); MAX_POINTS + 1];
    // One more than allowed lets the axis refuse a table that is too long.
    let count = count.min(MAX_POINTS + 1);
    let blob = r.blob();
    let number = |array: usize, i: usize| {
        let offset = (lens[..array].iter().sum::<usize>() + i) * 8;
        blob.get(offset..offset + 8).map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
    };
    for (i, point) in points.iter_mut().enumerate().take(count) {
        match (number(0, i), number(1, i), number(2, i)) {
            (Some(ms), Some(pos), Some(vel)) => *point = PvtPoint { t: ms / 1000.0, pos, vel },
            _ => return Err(SystemError::HmplInvalidArg.into()),
        }
    }
    Ok((points, count))
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

/// A value for an object `len` bytes wide: cut to fit, it would be another value.
fn fitting(value: i64, len: usize) -> Result<i64, Failure> {
    if fits_width(value, len) { Ok(value) } else { Err(Failure::MinusOne(SdoAbort::ValueRange.code())) }
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

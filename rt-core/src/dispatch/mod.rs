//! Carries out the commands scripts send: one match over the typed `api::CommandCall`
//! (decoded by `calls::wire`), so that the compiler holds every command of the registry
//! to an implementation. The match is here; what a command does is in the module of its
//! manual chapter: `axis` (HMPL ch. 5, 18, 20), `couplings` (ch. 6, 7), `drive_objects`
//! (ch. 17), `io` (ch. 9), `analog` (ch. 10), `position_trigger` (ch. 12), `touch_probe` (ch. 13),
//! `compensation` (ch. 14), `tasks` (ch. 16); ch. 2's system commands are one-liners here.

mod analog;
mod axis;
mod compensation;
mod couplings;
mod drive_objects;
mod fun147;
mod groups;
mod io;
mod position_trigger;
mod tasks;
mod touch_probe;

use api::alarms::{Alarm, Event as AlarmEvent};
use api::call::{Doubles, Sink};
use api::{ArgSpec, CommandCall, ErrorCode, GroupError, Quantity, Refusal, Role, SdoAbort, SystemError};
use calls::wire::{self, DecodeError};
use ipc::Disposition;
use ipc::call::{Reply, Request};

use crate::machine::Machine;
use crate::ownership::{self, Reach};
use crate::tasks::Entry;
use axis::{axis, home_number, motion};
use devices::ecat::{AlState, SdoError};
use kernel::axis::{Ignore, VibrationFilter as Vibration};
use kernel::group::settings as group_settings;

/// How a command failed, in the return convention of its chapter.
enum Failure {
    /// Most functions return the HMPL error code (and record it as a last error).
    Code(ErrorCode),
    /// Ch. 9 and 17 return -1; `rc` carries the reason (a CiA 301 abort code or an HMPL code).
    MinusOne(u32),
    /// Refused with an alarm (DXMC format), returned as the code.
    Alarm(Alarm),
    /// An SDO transfer on a wire is under way: `drive_objects::sdo` defers the call.
    Transfer,
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
            SdoError::MailboxBusy | SdoError::Pending => return Failure::Transfer,
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
    let result = match wire::decode(request) {
        Err(DecodeError::UnknownFunction(_)) => Err(SystemError::HmplNotSupported.into()),
        Err(_) | Ok(_) if !machine.tasks.accepts_commands(caller) => Err(SystemError::TaskNotRunning.into()),
        Err(_) => Err(SystemError::HmplInvalidArg.into()),
        Ok(call) => match check_ranges(machine, &call) {
            Ok(()) => run(machine, caller, &call, reply),
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

/// A simulated input set from outside (`replay::Input::is_simulated`), applied by the
/// lockstep gate with the code of the command a program would call for it (`SimSetGPI`,
/// `SimSetSlvGPI`, `SimSetSlvAIRaw`); false when the machine has no such input.
pub fn simulate(machine: &mut Machine, input: &crate::replay::Input) -> bool {
    use crate::replay::Input;
    match *input {
        Input::Gpi { pin, on } => machine.io.set_level(pin.into(), on.into()).is_ok(),
        Input::SlvGpi { slave, pin, on } => {
            io::sim_set_slave_input(machine, slave.into(), pin.into(), on.into()).is_ok()
        }
        Input::Ai { slave, channel, raw } => {
            analog::sim_set_input(machine, slave.into(), channel.into(), raw.into()).is_ok()
        }
        Input::Modbus { .. } | Input::Serial(_) | Input::Eth { .. } | Input::Client { .. } => false,
    }
}

/// Completes a deferred call once its operation is over; false while it still runs.
pub fn resume(machine: &mut Machine, request: &Request, reply: &mut Reply) -> bool {
    let result = match wire::decode(request) {
        Ok(CommandCall::MoveHome { axis_id }) => {
            let Ok(axis) = machine.kernel.axis_mut(axis_id) else { return true };
            let id = axis.id();
            match axis.home_state_mut().take_result() {
                None => return false,
                Some(result) => result.map_err(|e| Failure::Code(ErrorCode::axis(id, e))),
            }
        }
        Ok(
            call @ (CommandCall::ReadSDO { .. }
            | CommandCall::ReadSDOEx { .. }
            | CommandCall::WriteSDO { .. }
            | CommandCall::WriteSDOEx { .. }),
        ) => match drive_objects::sdo(machine, &call, reply) {
            Ok(Done::Later) => return false,
            Ok(Done::Now) => Ok(()),
            Err(failure) => Err(failure),
        },
        Ok(CommandCall::EnableComp { axis_id }) => match machine.kernel.take_comp_result(axis_id) {
            None => return false,
            Some(result) => result.map_err(Failure::Code),
        },
        Ok(CommandCall::StartTask { task_id } | CommandCall::StartTaskFunc { task_id, .. }) => {
            let Ok(task) = u8::try_from(task_id) else { return true };
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
        // Only the SDO calls meet a transfer under way, and they wait for it.
        Err(Failure::Transfer) => {
            reply.rc = SdoAbort::DeviceState.code();
            reply.valuec = 0;
            reply.push_int(-1);
        }
    }
}

/// Every argument the registry gives a quantity is checked against its range before the
/// command runs, on the axis or group named by the owner argument before it. One path for
/// every command: no setter can forget it, and NaN, infinities and numbers no drive could
/// carry never reach the kernel (issue 11).
fn check_ranges(m: &mut Machine, call: &CommandCall) -> Result<(), Failure> {
    call.write(&mut RangeCheck { m, args: call.func().spec().args.iter(), axis: None, group: None })
}

/// Walks a call's arguments in order: the first `Axis` or `Group` argument must name one,
/// and every number with a quantity must fit the axis or group named last before it.
struct RangeCheck<'m> {
    m: &'m mut Machine,
    args: std::slice::Iter<'static, ArgSpec>,
    axis: Option<i64>,
    group: Option<i64>,
}

impl RangeCheck<'_> {
    fn admit(&mut self, mut values: impl Iterator<Item = f64>) -> Result<(), Failure> {
        let Some(quantity) = self.args.next().and_then(|a| a.quantity) else { return Ok(()) };
        if let Refusal::System(error) = quantity.error() {
            // A free quantity (`Quantity::Finite`); its own range is the command's.
            return match values.all(f64::is_finite) {
                true => Ok(()),
                false => Err(error.into()),
            };
        }
        if quantity.is_group_bound() {
            let Some(group) = self.group else { return Ok(()) };
            for (i, value) in values.enumerate() {
                if let Err(e) = group_settings::admit(quantity, i, value) {
                    return Err(self.m.kernel.group_refusal(group, e).into());
                }
            }
            return Ok(());
        }
        let Some(axis) = self.axis else { return Ok(()) };
        let axis = self.m.kernel.axis_mut(axis)?;
        let id = axis.id();
        for value in values {
            axis.admit(quantity, value).map_err(|e| Failure::from(ErrorCode::axis(id, e)))?;
        }
        Ok(())
    }
}

impl Sink for RangeCheck<'_> {
    type Error = Failure;

    fn int(&mut self, value: i64) -> Result<(), Failure> {
        match self.args.next().and_then(|a| a.quantity) {
            Some(Quantity::Axis) => {
                // The first axis is checked here; a later one (a gear slave) when a number
                // of its own comes, else by the command itself, which answers as its
                // chapter says.
                if self.axis.is_none() {
                    self.m.kernel.axis_mut(value)?;
                }
                self.axis = Some(value);
            }
            Some(Quantity::Group) => {
                self.m.kernel.group(value)?;
                // A declared FUN147 box's group is the box's alone (docs/decisions.md, "FUN147").
                if self.m.boxes.holds_group(value) {
                    return Err(self.m.kernel.group_refusal(value, GroupError::CmdInvalidState).into());
                }
                self.group = Some(value);
            }
            _ => {}
        }
        Ok(())
    }

    fn double(&mut self, value: f64) -> Result<(), Failure> {
        self.admit(std::iter::once(value))
    }

    fn bool(&mut self, _: bool) -> Result<(), Failure> {
        self.args.next();
        Ok(())
    }

    fn str(&mut self, _: &[u8]) -> Result<(), Failure> {
        self.args.next();
        Ok(())
    }

    fn bytes(&mut self, _: &[u8]) -> Result<(), Failure> {
        self.args.next();
        Ok(())
    }

    fn doubles(&mut self, values: &Doubles) -> Result<(), Failure> {
        self.admit(values.iter())
    }
}

type Outcome = Result<Done, Failure>;

fn now(result: Result<(), impl Into<Failure>>) -> Outcome {
    result.map(|()| Done::Now).map_err(Into::into)
}

/// Checks that `caller` may set axis `a` going: not after an E-stop, nor outside Run or
/// Diagnosis, nor (`owned`) while another task owns its motion.
fn may_command(m: &mut Machine, caller: u8, a: i64, owned: bool) -> Result<u8, Failure> {
    let cycle = m.cycle;
    let axis = m.kernel.axis_mut(a)?;
    let id = axis.id();
    if axis.is_emergency_stopped() {
        return Err(SystemError::EmergencyStop.into());
    }
    if !m.state.allows_motion() {
        return Err(Failure::Alarm(m.tasks.axis_alarm(caller, id, AlarmEvent::WrongMode, cycle)));
    }
    if owned {
        may_change(m, caller, id)?;
    }
    Ok(id)
}

/// DXMC 9, 0x001F (docs/decisions.md, "Axis ownership"): while another task or a FUN147
/// box owns axis `id`'s motion, `caller`'s command on it is refused with the alarm
/// `0x1AAA001F`, which is published as the caller's.
fn may_change(m: &mut Machine, caller: u8, id: u8) -> Result<(), Failure> {
    match ownership::motion_owner(&m.kernel, &m.tasks, id) {
        Some(owner) if owner != caller => {
            Err(Failure::Alarm(m.tasks.axis_alarm(caller, id, AlarmEvent::CommandBufferBusy, m.cycle)))
        }
        _ => Ok(()),
    }
}

/// The axes a stop reaches. A stop is never refused for ownership (a stop button must
/// stop); the owners whose motion it cuts short are told (`ownership::tell_owners`).
fn reach(call: &CommandCall) -> Option<Reach> {
    use CommandCall as C;
    match *call {
        C::Stop { axis_id } | C::Halt { axis_id } => Some(Reach::Axis(axis_id)),
        C::StopGroup { group_id } | C::HaltGroup { group_id } => Some(Reach::Group(group_id)),
        C::StopAll {} | C::DisableAll {} => Some(Reach::All),
        _ => None,
    }
}

fn run(m: &mut Machine, caller: u8, call: &CommandCall, reply: &mut Reply) -> Outcome {
    let reach = reach(call);
    let owned = reach.is_none();
    // The axis a motion command sets going (declared `as Moves` in the registry).
    let moved = match call.arg_with(Role::Moves) {
        Some(a) if m.network.state() == AlState::Op => Some(may_command(m, caller, a, owned)?),
        _ => None,
    };
    // The axis whose motion a command ends or changes (declared `as Changes`).
    if let Some(a) = call.arg_with(Role::Changes) {
        let id = m.kernel.axis_mut(a)?.id();
        may_change(m, caller, id)?;
    }
    // A group motion command moves every axis of the group (HMPL ch. 8).
    let group = match call.arg_with(Role::MovesGroup) {
        Some(g) if m.network.state() == AlState::Op => {
            let (axes, n) = m.kernel.group(g)?.members();
            for &a in &axes[..n] {
                may_command(m, caller, a as i64, owned)?;
            }
            Some((g, axes, n))
        }
        _ => None,
    };
    let cut = reach.map(|reach| ownership::owners_reached(&m.kernel, &m.tasks, &reach, Some(caller)));
    let outcome = run_command(m, caller, call, reply);
    if outcome.is_ok() {
        let run_speed = m.run_speed(caller);
        let group_axes = group.as_ref().map_or(&[][..], |(_, axes, n)| &axes[..*n]);
        for &axis in moved.iter().chain(group_axes) {
            m.kernel.claim(axis, caller, run_speed);
        }
        if let Some((g, _, _)) = group {
            m.kernel.claim_group(g, caller);
        }
        if let Some(owners) = &cut {
            ownership::tell_owners(&mut m.kernel, &mut m.tasks, m.cycle, owners);
        }
    }
    outcome
}

fn run_command(m: &mut Machine, caller: u8, call: &CommandCall, reply: &mut Reply) -> Outcome {
    use CommandCall as C;
    use kernel::group::motion::PathCommand as P;
    use path::planner::Profile;
    match *call {
        // HMPL 5.2: motion.
        C::Enable { axis_id } => motion(m, |m| now(m.kernel.enable(axis_id))),
        C::Disable { axis_id } => motion(m, |m| now(m.kernel.disable(axis_id))),
        C::Reset { axis_id } => axis(m, axis_id, |ax| ax.reset()),
        C::MoveAbs { axis_id, pos } => axis(m, axis_id, |ax| ax.move_abs(pos)),
        C::MoveRel { axis_id, rel_dist } => axis(m, axis_id, |ax| ax.move_rel(rel_dist)),
        C::MoveVel { axis_id, vel } => axis(m, axis_id, |ax| ax.move_vel(vel)),
        C::MoveTrq { axis_id, torque_cmd } => axis(m, axis_id, |ax| ax.move_trq(torque_cmd)),
        C::MovePVT { axis_id, ref time, ref pos, ref vel, num_pt } => {
            axis::move_pvt(m, axis_id, [time, pos, vel], num_pt)
        }
        C::Stop { axis_id } => axis(m, axis_id, |ax| ax.stop()),
        C::Halt { axis_id } => axis(m, axis_id, |ax| ax.halt()),
        C::Resume { axis_id } => axis(m, axis_id, |ax| ax.resume()),
        // HMPL 5.3: settings.
        C::SetVel { axis_id, vel } => axis(m, axis_id, |ax| ax.set_vel(vel)),
        C::SetAcc { axis_id, acc } => axis(m, axis_id, |ax| ax.set_acc(acc)),
        C::SetAccTime { axis_id, acc_time } => axis(m, axis_id, |ax| ax.set_acc_time(acc_time)),
        C::SetDec { axis_id, dec } => axis(m, axis_id, |ax| ax.set_dec(dec)),
        C::SetDecTime { axis_id, dec_time } => axis(m, axis_id, |ax| ax.set_dec_time(dec_time)),
        C::SetKillDec { axis_id, kill_dec } => axis(m, axis_id, |ax| ax.set_kill_dec(kill_dec)),
        C::SetSWRL { axis_id, right_limit_pos } => axis(m, axis_id, |ax| ax.set_swrl(right_limit_pos)),
        C::SetSWLL { axis_id, left_limit_pos } => axis(m, axis_id, |ax| ax.set_swll(left_limit_pos)),
        C::SetSMTime { axis_id, smooth_time } => axis(m, axis_id, |ax| ax.set_sm_time(smooth_time)),
        C::SetPos { axis_id, pos } => motion(m, |m| now(m.kernel.set_pos(axis_id, pos))),
        C::IgnoreHWL { axis_id, cmd } => axis(m, axis_id, |ax| ax.set_ignore(Ignore::HardwareLimits, cmd != 0)),
        C::IgnoreSWL { axis_id, cmd } => axis(m, axis_id, |ax| ax.set_ignore(Ignore::SoftwareLimits, cmd != 0)),
        C::IgnorePE { axis_id, cmd } => axis(m, axis_id, |ax| ax.set_ignore(Ignore::PositionError, cmd != 0)),
        C::SetVelScale { axis_id, vel_scale } => motion(m, |m| now(m.kernel.set_vel_scale(axis_id, vel_scale))),
        C::SetRollover { axis_id, rollover_val } => axis(m, axis_id, |ax| ax.set_rollover(rollover_val)),
        C::SetOpMode { axis_id, op_mode } => axis(m, axis_id, |ax| ax.set_op_mode(op_mode)),
        C::SetBufferMode { axis_id, buf_mode } => axis(m, axis_id, |ax| ax.set_buffer_mode(buf_mode)),
        C::SetPosWindow { axis_id, pos_window } => axis(m, axis_id, |ax| ax.set_pos_window(pos_window)),
        C::SetPosWindowTime { axis_id, pos_window_time } => {
            axis(m, axis_id, |ax| ax.set_pos_window_time(pos_window_time))
        }
        // HMPL ch. 6 and 7: gear and gantry.
        C::EnableGear { axis_master_id, axis_slave_id } => {
            couplings::coupling(m, |k| k.enable_gear(axis_master_id, axis_slave_id))
        }
        C::DisableGear { axis_slave_id } => couplings::coupling(m, |k| k.disable_gear(axis_slave_id)),
        C::GearIn { axis_master_id, axis_slave_id, gear_ratio } => {
            couplings::coupling(m, |k| k.gear_in(axis_master_id, axis_slave_id, gear_ratio))
        }
        C::GearOut { axis_slave_id } => couplings::coupling(m, |k| k.gear_out(axis_slave_id)),
        C::EnableGantryPair { rhs_axis_id, lhs_axis_id } => {
            couplings::coupling(m, |k| k.enable_gantry_pair(rhs_axis_id, lhs_axis_id))
        }
        C::DisableGantryPair { axis_id } => couplings::coupling(m, |k| k.disable_gantry_pair(axis_id)),
        // HMPL 8.2: group motion control.
        C::EnableGroup { group_id } => groups::group(m, |k| k.enable_group(group_id)),
        C::DisableGroup { group_id } => groups::group(m, |k| k.disable_group(group_id)),
        C::ResetGroup { group_id } => groups::group(m, |k| k.reset_group(group_id)),
        C::StopGroup { group_id } => groups::group(m, |k| k.stop_group(group_id)),
        C::HaltGroup { group_id } => groups::group(m, |k| k.halt_group(group_id)),
        C::ResumeGroup { group_id } => groups::group(m, |k| k.resume_group(group_id)),
        C::JogGroup { group_id, carte_dir, jog_vel } => groups::group(m, |k| k.jog_group(group_id, carte_dir, jog_vel)),
        C::JogGroupAxis { group_id, grp_axis, jog_vel } => {
            groups::group(m, |k| k.jog_group_axis(group_id, grp_axis, jog_vel))
        }
        C::LineAbs2D { group_id, end_x, end_y } => groups::path(m, group_id, P::line_abs([end_x, end_y])),
        C::LineAbs3D { group_id, end_x, end_y, end_z } => groups::path(m, group_id, P::line_abs([end_x, end_y, end_z])),
        C::LineRel2D { group_id, distance_x, distance_y } => {
            groups::path(m, group_id, P::line_rel([distance_x, distance_y]))
        }
        C::LineRel3D { group_id, distance_x, distance_y, distance_z } => {
            groups::path(m, group_id, P::line_rel([distance_x, distance_y, distance_z]))
        }
        C::Arc2D { group_id, border_x, border_y, end_x, end_y } => {
            groups::path(m, group_id, P::Arc2D { border: [border_x, border_y], end: [end_x, end_y] })
        }
        C::ArcCW2D { group_id, center_x, center_y, end_x, end_y } => {
            groups::path(m, group_id, P::ArcCenter2D { center: [center_x, center_y], end: [end_x, end_y], ccw: false })
        }
        C::ArcCCW2D { group_id, center_x, center_y, end_x, end_y } => {
            groups::path(m, group_id, P::ArcCenter2D { center: [center_x, center_y], end: [end_x, end_y], ccw: true })
        }
        C::ArcAngle2D { group_id, center_x, center_y, angle } => {
            groups::path(m, group_id, P::ArcAngle2D { center: [center_x, center_y], angle })
        }
        C::Circle2D { group_id, center_x, center_y, end_x, end_y, turns } => {
            groups::path(m, group_id, P::Circle2D { center: [center_x, center_y], end: [end_x, end_y], turns })
        }
        // HMPL 8.3: group settings.
        C::AddAxisToGrp { group_id, axis_id } => groups::group(m, |k| k.add_axis_to_grp(group_id, axis_id)),
        C::RemoveAxisFromGrp { group_id } => groups::group(m, |k| k.remove_axis_from_grp(group_id)),
        C::UngrpAllAxes { group_id } => groups::group(m, |k| k.ungrp_all_axes(group_id)),
        C::SetGrpMotionProfile { group_id, max_velocity, max_acceleration, max_deceleration, smooth_time } => {
            let p = Profile { vel: max_velocity, acc: max_acceleration, dec: max_deceleration, smooth_ms: smooth_time };
            groups::group(m, |k| k.set_group_value(group_id, |s| s.lin = p))
        }
        C::SetGrpAngMotionProfile { group_id, max_velocity, max_acceleration, max_deceleration, smooth_time } => {
            let p = Profile { vel: max_velocity, acc: max_acceleration, dec: max_deceleration, smooth_ms: smooth_time };
            groups::group(m, |k| k.set_group_value(group_id, |s| s.ang = p))
        }
        C::SetGrpKin { group_id, kin_type } => groups::group(m, |k| k.set_grp_kin(group_id, kin_type)),
        C::SetGrpVel { group_id, vel } => groups::group(m, |k| k.set_group_value(group_id, |s| s.lin.vel = vel)),
        C::SetGrpAcc { group_id, acc } => groups::group(m, |k| k.set_group_value(group_id, |s| s.lin.acc = acc)),
        C::SetGrpAccTime { group_id, acc_time } => {
            groups::group(m, |k| k.set_group(group_id, |s| s.set_acc_time(acc_time)))
        }
        C::SetGrpDec { group_id, dec } => groups::group(m, |k| k.set_group_value(group_id, |s| s.lin.dec = dec)),
        C::SetGrpDecTime { group_id, dec_time } => {
            groups::group(m, |k| k.set_group(group_id, |s| s.set_dec_time(dec_time)))
        }
        C::SetGrpSMTime { group_id, smooth_time } => {
            groups::group(m, |k| k.set_group_value(group_id, |s| s.lin.smooth_ms = smooth_time))
        }
        C::SetGrpCoordSys { group_id, coord_sys } => groups::group(m, |k| k.set_grp_coord_sys(group_id, coord_sys)),
        C::SetGrpBufferMode { group_id, buffer_mode } => {
            groups::group(m, |k| k.set_group(group_id, |s| s.set_buffer_mode(buffer_mode)))
        }
        C::SetGrpTransMode { group_id, trans_mode } => groups::group(m, |k| k.set_grp_trans_mode(group_id, trans_mode)),
        C::SetGrpTransPrm { group_id, trans_vel, trans_dis, trans_dev, trans_curv } => {
            groups::group(m, |k| k.set_grp_trans_prm(group_id, [trans_vel, trans_dis, trans_dev, trans_curv]))
        }
        C::SetGrpVelScale { group_id, vel_scale } => {
            groups::group(m, |k| k.set_group_value(group_id, |s| s.vel_scale = vel_scale))
        }
        C::GetGrpCoordTrans { group_id, coord_sys } => {
            groups::six_out(reply, m.kernel.grp_coord_trans(group_id, coord_sys))
        }
        C::SetGrpCoordTrans { group_id, coord_sys, ref trans_param } => {
            groups::group(m, |k| k.set_grp_coord_trans(group_id, coord_sys, trans_param))
        }
        C::GetGrpPoseCmd { group_id, coord_sys } => {
            groups::six_out(reply, m.kernel.grp_pose(group_id, coord_sys, false))
        }
        C::GetGrpPoseFb { group_id, coord_sys } => groups::six_out(reply, m.kernel.grp_pose(group_id, coord_sys, true)),
        C::SetGrpLookAheadPrm { group_id, prm_id, value } => {
            groups::group(m, |k| k.set_group(group_id, |s| s.set_look_ahead(prm_id, value)))
        }
        C::SetGrpQueueSize { group_id, queue_size } => groups::group(m, |k| k.set_grp_queue_size(group_id, queue_size)),
        // HMPL 8.5: advanced group motion.
        C::LineAbs {
            group_id,
            ref target_pos,
            ref motion_profile,
            coord_sys,
            buff_mode,
            trans_mode,
            ref trans_par,
        } => {
            let command = groups::six(target_pos).map(|target| P::LineAbs { target: target.map(Some) });
            groups::advanced(m, group_id, command, motion_profile, [coord_sys, buff_mode, trans_mode], trans_par)
        }
        C::LineRel {
            group_id,
            ref relative_dist,
            ref motion_profile,
            coord_sys,
            buff_mode,
            trans_mode,
            ref trans_par,
        } => {
            let command = groups::six(relative_dist).map(|distance| P::LineRel { distance });
            groups::advanced(m, group_id, command, motion_profile, [coord_sys, buff_mode, trans_mode], trans_par)
        }
        C::CircleAbs {
            group_id,
            ref center_pos,
            ref normal_vector,
            turns,
            ref target_pos,
            ref motion_profile,
            coord_sys,
            buff_mode,
            trans_mode,
            ref trans_par,
        } => {
            let command = groups::circle(center_pos, normal_vector, turns, target_pos, false);
            groups::advanced(m, group_id, command, motion_profile, [coord_sys, buff_mode, trans_mode], trans_par)
        }
        C::CircleRel {
            group_id,
            ref center_pos,
            ref normal_vector,
            turns,
            ref relative_dist,
            ref motion_profile,
            coord_sys,
            buff_mode,
            trans_mode,
            ref trans_par,
        } => {
            let command = groups::circle(center_pos, normal_vector, turns, relative_dist, true);
            groups::advanced(m, group_id, command, motion_profile, [coord_sys, buff_mode, trans_mode], trans_par)
        }
        // HMPL ch. 20: homing.
        C::MoveHome { axis_id } => axis::move_home(m, axis_id),
        C::SetHomeMethod { axis_id, method } => axis(m, axis_id, |ax| ax.set_home(|h| h.set_method(method))),
        C::SetHomeSwitchVel { axis_id, fast_vel } => home_number(m, axis_id, fast_vel, |h| &mut h.switch_vel),
        C::SetHomeZeroVel { axis_id, slow_vel } => home_number(m, axis_id, slow_vel, |h| &mut h.zero_vel),
        C::SetHomeAcc { axis_id, acc } => home_number(m, axis_id, acc, |h| &mut h.acc),
        C::SetHomeOffset { axis_id, offset } => home_number(m, axis_id, offset, |h| &mut h.offset),
        C::SetHomeTimeout { axis_id, timeout } => axis(m, axis_id, |ax| ax.set_home(|h| h.set_timeout(timeout))),
        C::SetHomedStatus { axis_id, is_homed } => axis(m, axis_id, |ax| {
            ax.home_state_mut().set_homed(is_homed != 0);
            Ok(())
        }),
        // HMPL ch. 14: dynamic error compensation.
        C::EnableComp { axis_id } => compensation::enable(m, axis_id),
        C::DisableComp { axis_id } => motion(m, |m| now(m.kernel.disable_comp(axis_id))),
        C::SetupComp { axis_id, start_idx, base_val, interval, num_pt, ref_axis_id } => {
            compensation::setup_1d(m, axis_id, start_idx, base_val, interval, num_pt, ref_axis_id)
        }
        C::SetupComp2D { axis_id, start_idx, ref base_val, ref interval, ref num_pt, ref ref_axis_id } => {
            compensation::setup_nd(m, axis_id, start_idx, [base_val, interval, num_pt, ref_axis_id], 2)
        }
        C::SetupComp3D { axis_id, start_idx, ref base_val, ref interval, ref num_pt, ref ref_axis_id } => {
            compensation::setup_nd(m, axis_id, start_idx, [base_val, interval, num_pt, ref_axis_id], 3)
        }
        C::SetCompAlgType { axis_id, alg_type } => motion(m, |m| now(m.kernel.set_comp_alg_type(axis_id, alg_type))),
        // HMPL ch. 18: errors.
        C::ClearAxisLastErr { axis_id } => axis(m, axis_id, |ax| {
            ax.clear_last_err();
            Ok(())
        }),
        C::ClearGrpLastErr { group_id } => now(m.kernel.clear_group_last_err(group_id)),
        // HMPL ch. 17: drive variables.
        C::ReadSDO { .. } | C::ReadSDOEx { .. } | C::WriteSDO { .. } | C::WriteSDOEx { .. } => {
            drive_objects::sdo(m, call, reply)
        }
        C::WritePDO { slv_id, obj_index, obj_subindex, obj_value } => {
            drive_objects::write_pdo(m, [slv_id, obj_index, obj_subindex], obj_value)
        }
        C::ForceWritePDO { slv_id, obj_index, obj_subindex, obj_value } => {
            drive_objects::force_write_pdo(m, [slv_id, obj_index, obj_subindex], obj_value)
        }
        C::ReleasePDO { slv_id, obj_index, obj_subindex } => {
            drive_objects::release_pdo(m, [slv_id, obj_index, obj_subindex])
        }
        C::SimDriveFault { slv_id, error_code } => drive_objects::sim_drive_fault(m, slv_id, error_code),
        // HMPL ch. 9: controller I/O.
        C::SimSetGPI { gpi_idx, on_off } => io::pin(m.io.set_level(gpi_idx, on_off)),
        C::SetGPO { gpo_idx, on_off } => io::pin(m.io.set_gpo(gpo_idx, on_off)),
        C::ToggleGPO { gpo_idx } => io::pin(m.io.toggle_gpo(gpo_idx)),
        C::SetAllGPO { all_gpo_state } => io::pin(m.io.set_all_gpo(all_gpo_state)),
        C::SetGPIInvert { gpi_idx, invert } => io::pin(m.io.set_gpi_invert(gpi_idx, invert)),
        C::SetGPOInvert { gpo_idx, invert } => io::pin(m.io.set_gpo_invert(gpo_idx, invert)),
        C::BindEMO { gpi_idx } => io::pin(m.io.bind_emo(gpi_idx)),
        // HMPL ch. 15: filters.
        C::EnableAxisVsf { axis_id } => axis(m, axis_id, |ax| ax.switch_vibration_filter(Vibration::Vsf, true)),
        C::DisableAxisVsf { axis_id } => axis(m, axis_id, |ax| ax.switch_vibration_filter(Vibration::Vsf, false)),
        C::SetAxisVsf { axis_id, frequency, damping_ratio } => {
            axis(m, axis_id, |ax| ax.set_vsf(frequency, damping_ratio))
        }
        C::EnableAxisInShape { axis_id } => axis(m, axis_id, |ax| ax.switch_vibration_filter(Vibration::InShape, true)),
        C::DisableAxisInShape { axis_id } => {
            axis(m, axis_id, |ax| ax.switch_vibration_filter(Vibration::InShape, false))
        }
        C::SetAxisInShape { axis_id, frequency, damping_ratio, shaper_type } => {
            axis(m, axis_id, |ax| ax.set_in_shape(frequency, damping_ratio, shaper_type))
        }
        C::EnableGrpInShape { group_id } => groups::group(m, |k| k.switch_group_shaper(group_id, true)),
        C::DisableGrpInShape { group_id } => groups::group(m, |k| k.switch_group_shaper(group_id, false)),
        C::SetGrpInShape { group_id, frequency, damping_ratio, shaper_type } => {
            groups::group(m, |k| k.set_group_shaper(group_id, frequency, damping_ratio, shaper_type))
        }
        // HMPL ch. 13: touch probes.
        C::EnableTouchProbe1 { axis_id } => touch_probe::probes(m, axis_id, |tp| tp.enable(0)),
        C::EnableTouchProbe2 { axis_id } => touch_probe::probes(m, axis_id, |tp| tp.enable(1)),
        C::DisableTouchProbe1 { axis_id } => touch_probe::probes(m, axis_id, |tp| tp.disable(0)),
        C::DisableTouchProbe2 { axis_id } => touch_probe::probes(m, axis_id, |tp| tp.disable(1)),
        C::SetTouchProbe1Func { axis_id, tp_input, cont_trigger, detect_edge } => {
            touch_probe::probes(m, axis_id, |tp| tp.set_function(0, tp_input, cont_trigger, detect_edge))
        }
        C::SetTouchProbe2Func { axis_id, tp_input, cont_trigger, detect_edge } => {
            touch_probe::probes(m, axis_id, |tp| tp.set_function(1, tp_input, cont_trigger, detect_edge))
        }
        C::SimSetSlvGPI { slv_slot_id, gpi_idx, on_off } => io::sim_set_slave_input(m, slv_slot_id, gpi_idx, on_off),
        // HMPL ch. 10: slave analog I/O.
        C::SetSlvAIType { slv_slot_id, ai_idx, range_type } => {
            analog::set_type(m, slv_slot_id, ai_idx, range_type, analog::Way::Input)
        }
        C::SetSlvAOType { slv_slot_id, ao_idx, range_type } => {
            analog::set_type(m, slv_slot_id, ao_idx, range_type, analog::Way::Output)
        }
        C::SetSlvAORaw { slv_slot_id, ao_idx, ao_raw_val } => analog::set_raw(m, slv_slot_id, ao_idx, ao_raw_val),
        C::SetSlvAO { slv_slot_id, ao_idx, ao_val } => analog::set_value(m, slv_slot_id, ao_idx, ao_val),
        C::SetSlvAOMonitor { slv_slot_id, ao_idx, var_id } => analog::set_monitor(m, slv_slot_id, ao_idx, var_id),
        C::SetSlvAOParam { slv_slot_id, ao_idx, ao_en_bind, ao_scale, ao_offset } => {
            analog::set_param(m, slv_slot_id, ao_idx, ao_en_bind, ao_scale, ao_offset)
        }
        C::SimSetSlvAIRaw { slv_slot_id, ai_idx, ai_raw_val } => {
            analog::sim_set_input(m, slv_slot_id, ai_idx, ai_raw_val)
        }
        C::SetSlvGPO { slv_slot_id, gpo_idx, on_off } => io::change_slave_outputs(m, slv_slot_id, |now, mask| {
            let bit = io::channel_bit(gpo_idx, mask)?;
            Ok(if on_off != 0 { now | bit } else { now & !bit })
        }),
        C::ToggleSlvGPO { slv_slot_id, gpo_idx } => {
            io::change_slave_outputs(m, slv_slot_id, |now, mask| Ok(now ^ io::channel_bit(gpo_idx, mask)?))
        }
        C::SetSlvAllGPO { slv_slot_id, all_gpo_state } => {
            io::change_slave_outputs(m, slv_slot_id, |_, mask| io::all_channels(all_gpo_state, mask))
        }
        // HMPL ch. 2: system.
        C::DisableAll {} => {
            m.kernel.disable_all();
            Ok(Done::Now)
        }
        C::StopAll {} => motion(m, |m| {
            m.kernel.stop_all();
            Ok(Done::Now)
        }),
        C::EStop {} => tasks::emergency_stop(m, caller),
        C::ScanNetwork {} => now(m.scan_network()),
        // HMPL ch. 16: tasks.
        C::StartTask { task_id } => tasks::start(m, task_id, Entry::TOP_LEVEL),
        C::StartTaskFunc { task_id, ref func_name } => tasks::start_func(m, task_id, func_name),
        C::StopTask { task_id } => tasks::stop(m, caller, task_id),
        C::StopAllTask {} => tasks::stop_all(m, caller),
        // Fatek FUN147.
        C::MHSPO { gp, ref sr, ref wr, ref en, ref pau, ref abt, ref act, ref err, ref dn } => {
            fun147::declare(m, gp, sr, wr, [en, pau, abt, act, err, dn])
        }
        C::MHSPOFree { gp } => fun147::free(m, gp),
        // HMPL ch. 12: position trigger.
        C::EnablePT { axis_id } => position_trigger::trigger(m, axis_id, |t, a, homed| t.enable(a, homed)),
        C::DisablePT { axis_id } => position_trigger::trigger(m, axis_id, |t, a, _| t.disable(a)),
        C::SetPT_StartPos { axis_id, start_pos } => {
            position_trigger::trigger(m, axis_id, |t, a, _| t.set_start_pos(a, start_pos))
        }
        C::SetPT_EndPos { axis_id, end_pos } => {
            position_trigger::trigger(m, axis_id, |t, a, _| t.set_end_pos(a, end_pos))
        }
        C::SetPT_Interval { axis_id, interval } => {
            position_trigger::trigger(m, axis_id, |t, a, _| t.set_interval(a, interval))
        }
        C::SetPT_PulseWidth { axis_id, width_ns } => {
            position_trigger::trigger(m, axis_id, |t, a, _| t.set_pulse_width(a, width_ns))
        }
        C::SetPT_PosArray { axis_id, index, trigger_pos } => {
            position_trigger::trigger(m, axis_id, |t, a, _| t.set_pos_array(a, index, trigger_pos))
        }
        C::SetPT_StateArray { axis_id, index, state } => {
            position_trigger::trigger(m, axis_id, |t, a, _| t.set_state_array(a, index, state))
        }
        C::SetPT_StartIndex { axis_id, index } => {
            position_trigger::trigger(m, axis_id, |t, a, _| t.set_start_index(a, index))
        }
        C::SetPT_EndIndex { axis_id, index } => {
            position_trigger::trigger(m, axis_id, |t, a, _| t.set_end_index(a, index))
        }
        C::GetPTPulse { axis_id, n } => position_trigger::pulse(m, axis_id, n, reply),
    }
}

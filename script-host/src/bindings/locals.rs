//! The functions that run in the script process (`api::Kind::Local`): waits on controller
//! time, output, the event stream, mutexes, timers and the user table.

use std::rc::Rc;
use std::time::Duration;

use api::FunctionSpec;
use api::{CommandCall, ErrorCode, Local, SystemError};
use calls::user_table;
use ipc::event_record::{EventKind, EventRecord};
use ipc::output::{char_boundary, cut_marker, escape};
use ipc::task_table::RunState;
use mlua::{AnyUserData, BorrowedBytes, Function, Lua, MultiValue, Value};
use schema::shared::{Lock, MUTEXES};

use super::timer::Timer;
use super::{
    Host, binding, bool_arg, double_arg, doubles_arg, error_here, int_arg, lua_string_arg, round_trip, type_name,
    write_output,
};
use crate::printf::{self, Arg, Formatted};

/// HMPL 2.20: the longest message `SendMsgEvent` sends.
const MAX_MESSAGE_CHARS: usize = 128;
/// How long a blocked `MutexLock` sleeps before it checks that the controller lives.
const LIVENESS: Duration = Duration::from_millis(100);

impl Host {
    /// Blocks for `ns` nanoseconds of controller time (at least one cycle if `ns` > 0).
    fn sleep_ns(&self, lua: &Lua, ns: f64) -> mlua::Result<()> {
        if ns <= 0.0 {
            return Ok(());
        }
        let (period, now) = {
            let mut endpoint = self.endpoint.borrow_mut();
            let snapshot = endpoint.snapshot();
            (snapshot.period_ns.max(1), snapshot.cycle)
        };
        let target = now + (ns / period as f64).ceil() as u64;
        // A task running the User ASCII agent serves its clients while it waits.
        let slice = (super::agent::SERVE_PERIOD.as_nanos() as u64 / period).max(1);
        loop {
            let next = if super::agent::active() { target.min(self.cycle() + slice) } else { target };
            self.endpoint.borrow_mut().wait_until_cycle(next).map_err(mlua::Error::external)?;
            if next >= target {
                return Ok(());
            }
            super::agent::serve(lua, self);
        }
    }

    fn cycle(&self) -> u64 {
        self.endpoint.borrow_mut().snapshot().cycle
    }

    fn now_ms(&self) -> u64 {
        self.endpoint.borrow_mut().snapshot().time_in_ms
    }

    /// Waits until the task may send another event.
    fn throttle(&self, lua: &Lua) -> mlua::Result<()> {
        loop {
            let mut throttle = self.throttle.get();
            let taken = throttle.take(self.now_ms());
            self.throttle.set(throttle);
            match taken {
                Ok(()) => return Ok(()),
                Err(ms) => self.sleep_ns(lua, ms as f64 * 1e6)?,
            }
        }
    }

    pub(super) fn send_event(&self, kind: EventKind, code: u32, text: &str) -> i64 {
        let cycle = self.endpoint.borrow_mut().snapshot().cycle;
        let record = EventRecord::new(kind, self.task() as u32, cycle, code, text);
        match self.events.send(&record) {
            Ok(()) => 0,
            Err(_) => system_code(SystemError::HmplExecFailed),
        }
    }

    /// An HMPL runtime error stops the task (HMPL 2.22): no `pcall` can catch it. Says
    /// where and why, records the code for the controller, and ends the process.
    fn stop_with_runtime_error(&self, lua: &Lua, code: SystemError, message: &str) -> ! {
        let error = error_here(lua, format!("{message} (0x{:04X} {})", code.id(), code.name()));
        eprintln!("{error}");
        self.endpoint.borrow().slot().set_end_code(code.id() as u32);
        std::process::exit(1)
    }
}

pub(super) fn system_code(e: SystemError) -> i64 {
    ErrorCode::System(e).code() as i64
}

pub fn local(lua: &Lua, host: Rc<Host>, local: Local) -> mlua::Result<Function> {
    let spec = local.spec();
    match local {
        Local::MHSPOLoad
        | Local::MHSPOText
        | Local::GetPlcReg
        | Local::SetPlcReg
        | Local::GetPlcRelay
        | Local::SetPlcRelay => super::plc::local(lua, host, local),
        Local::EthOpenAsServer
        | Local::EthOpenAsClient
        | Local::EthTx
        | Local::EthRx
        | Local::EthClose
        | Local::EthCloseAll
        | Local::EthBuffClear
        | Local::EthGetSessions
        | Local::EthConnectCheck => super::freeport::local(lua, host, local),
        Local::SerialInit | Local::SerialTx | Local::SerialRx => super::serial::local(lua, host, local),
        Local::ASCII_ClientConnect
        | Local::ASCII_ClientRecv
        | Local::ASCII_ClientSend
        | Local::ASCII_ClientDisconnect
        | Local::Modbus_ClientConnect
        | Local::Modbus_ClientDisconnect
        | Local::Modbus_ClientRead_HoldReg
        | Local::Modbus_ClientRead_InputReg
        | Local::Modbus_ClientRead_Coils
        | Local::Modbus_ClientRead_Inputs
        | Local::Modbus_ClientWrite_HoldReg
        | Local::Modbus_ClientWrite_Coils => super::clients::local(lua, host, local),
        Local::START_ASCII_AGENT | Local::ASCII_ServerBroadcast => super::agent::local(lua, host, local),
        Local::expect_eq | Local::expect_near | Local::expect_true => super::expect::local(lua, host, local),
        Local::GetFirmwareVer
        | Local::GetFirmwareDate
        | Local::GetFirmwareHash
        | Local::GetModelNum
        | Local::GetSerialNum
        | Local::SetHMIScope
        | Local::StringPrint
        | Local::StringLen
        | Local::IsStringEqual
        | Local::StrFindChar
        | Local::StrFindCharEx
        | Local::StrFindStr
        | Local::StringCopy
        | Local::StringCopyEx
        | Local::StringCat
        | Local::StringCatEx
        | Local::StringToDouble
        | Local::MemoryCopy
        | Local::MemorySet
        | Local::IsMemoryEqual
        | Local::sin
        | Local::cos
        | Local::tan
        | Local::asin
        | Local::acos
        | Local::atan
        | Local::atan2
        | Local::abs
        | Local::fabs
        | Local::ceil
        | Local::floor
        | Local::ldexp
        | Local::exp
        | Local::pow
        | Local::log
        | Local::log10
        | Local::sqrt
        | Local::cbrt
        | Local::hypot
        | Local::GetConfigVar
        | Local::SetConfigVar => super::library::local(lua, host, local),
        Local::Sleep => binding(lua, spec, move |lua, args| {
            host.beat();
            let ms = int_arg(lua, spec, &args, 0)?;
            if ms < 0 {
                return Err(error_here(lua, format!("Sleep: ms must be >= 0, not {ms}")));
            }
            host.sleep_ns(lua, ms as f64 * 1e6)
        }),
        Local::DELAY => binding(lua, spec, move |lua, args| {
            host.beat();
            let seconds = double_arg(lua, spec, &args, 0)?;
            if !(seconds >= 0.0 && seconds.is_finite()) {
                return Err(error_here(lua, format!("DELAY: seconds must be >= 0, not {seconds}")));
            }
            host.sleep_ns(lua, seconds * 1e9)
        }),
        Local::Till => binding(lua, spec, move |lua, args| {
            host.beat();
            let condition = match args.front() {
                Some(Value::Function(f)) => f.clone(),
                other => {
                    let got = other.cloned().unwrap_or(Value::Nil);
                    return Err(error_here(
                        lua,
                        format!(
                            "bad argument #1 to 'Till' (function expected, got {}); write Till(function() return IsInPos(0) end)",
                            type_name(&got)
                        ),
                    ));
                }
            };
            loop {
                host.start_watch();
                let value = condition.call::<Value>(());
                let watch = host.take_watch();
                if is_true(&value?) {
                    return Ok(());
                }
                let next = host.cycle() + 1;
                host.endpoint.borrow_mut().wait_watching(next, &watch).map_err(mlua::Error::external)?;
                super::agent::serve(lua, &host);
            }
        }),
        Local::Print => binding(lua, spec, move |lua, args| {
            host.beat();
            match format(lua, spec, &args)? {
                Ok(formatted) => {
                    let marker = if formatted.cut > 0 { cut_marker(formatted.cut) } else { String::new() };
                    write_output(&[&formatted.text, marker.as_bytes()]);
                    Ok(formatted.chars as i64)
                }
                // HMPL 3.2: Print returns -1 on error; the warning says why.
                Err(()) => Ok(-1),
            }
        }),
        Local::my_print => binding(lua, spec, move |lua, args| {
            host.beat();
            write_output(&[&lua_string_arg(lua, spec, &args, 0)?.as_bytes()]);
            Ok(())
        }),
        Local::SendEvent => binding(lua, spec, move |lua, args| {
            host.beat();
            let Ok(id) = u16::try_from(int_arg(lua, spec, &args, 0)?) else {
                return Ok(system_code(SystemError::HmplArgOutOfRange));
            };
            host.throttle(lua)?;
            Ok(host.send_event(EventKind::Event, id as u32, ""))
        }),
        Local::SendMsgEvent => binding(lua, spec, move |lua, args| {
            host.beat();
            let Ok(formatted) = format(lua, spec, &args)? else {
                return Ok(system_code(SystemError::HmplInvalidStrFormat));
            };
            if formatted.chars > MAX_MESSAGE_CHARS {
                return Ok(system_code(SystemError::HmplStrTooLong));
            }
            let text = escape(&formatted.text);
            host.throttle(lua)?;
            Ok(host.send_event(EventKind::Message, 0, &text))
        }),
        Local::RunScheduler => binding(lua, spec, move |_, _| {
            host.beat();
            let mut endpoint = host.endpoint.borrow_mut();
            if endpoint.lockstep() {
                // On the simulation clock the other tasks' turns come first.
                endpoint.yield_turn().map_err(mlua::Error::external)
            } else {
                std::thread::yield_now();
                Ok(())
            }
        }),
        Local::MutexLock => binding(lua, spec, move |lua, args| {
            host.beat();
            let id = mutex_id(lua, spec, &args)?;
            loop {
                match host.shared.try_lock(id, host.task()) {
                    Some(Lock::Acquired) => return Ok(()),
                    Some(Lock::Twice) => host.stop_with_runtime_error(
                        lua,
                        SystemError::HmplMutexLockTwice,
                        &format!("MutexLock({id}): this task holds the mutex already"),
                    ),
                    // On the simulation clock the core grants the next turn once it is free.
                    Some(Lock::HeldBy(_)) if host.endpoint.borrow().lockstep() => {
                        host.endpoint.borrow_mut().wait_for_mutex_turn(id).map_err(mlua::Error::external)?;
                    }
                    Some(Lock::HeldBy(owner)) => {
                        let endpoint = host.endpoint.borrow();
                        endpoint.slot().set_state(RunState::Blocked);
                        ipc::mutex::wait_for_mutex(&host.shared, id, owner, LIVENESS);
                        endpoint.slot().set_state(RunState::Running);
                        endpoint.check_controller().map_err(mlua::Error::external)?;
                    }
                    None => return Err(error_here(lua, format!("MutexLock: no mutex {id}"))),
                }
            }
        }),
        Local::MutexUnlock => binding(lua, spec, move |lua, args| {
            host.beat();
            let id = mutex_id(lua, spec, &args)?;
            ipc::mutex::unlock(&host.shared, id, host.task());
            Ok(())
        }),
        Local::TimerInit => binding(lua, spec, move |_, _| {
            host.beat();
            Ok(Timer::default())
        }),
        Local::TON | Local::TOF => binding(lua, spec, move |lua, args| {
            host.beat();
            let timer = match args.front() {
                Some(Value::UserData(ud)) if ud.is::<Timer>() => ud.clone(),
                other => {
                    let got = other.cloned().unwrap_or(Value::Nil);
                    let what = format!(
                        "bad argument #1 to '{}' (Timer expected, got {}); make one with TimerInit()",
                        spec.name,
                        type_name(&got)
                    );
                    return Err(error_here(lua, what));
                }
            };
            let input = bool_arg(lua, spec, &args, 1)?;
            let preset = int_arg(lua, spec, &args, 2)?.max(0) as u64;
            let now = host.now_ms();
            let mut timer = AnyUserData::borrow_mut::<Timer>(&timer)?;
            Ok(if local == Local::TON {
                timer.on_delay(input, preset, now)
            } else {
                timer.off_delay(input, preset, now)
            })
        }),
        Local::SetupGroup => binding(lua, spec, move |lua, args| {
            // HMPL 8.3.3: AddAxisToGrp for each axis, then EnableGroup; what it added is
            // removed again when a step fails, so a failed setup leaves the group as it was.
            // Every argument is read before the first command: a refused call changes nothing.
            let group_id = int_arg(lua, spec, &args, 0)?;
            let axis_ids = (1..args.len()).map(|i| int_arg(lua, spec, &args, i)).collect::<mlua::Result<Vec<_>>>()?;
            let mut added = 0;
            for axis_id in axis_ids {
                let rc = core_rc(lua, &host, &CommandCall::AddAxisToGrp { group_id, axis_id })?;
                if rc != 0 {
                    return undo_setup(lua, &host, group_id, added, rc);
                }
                added += 1;
            }
            let rc = core_rc(lua, &host, &CommandCall::EnableGroup { group_id })?;
            if rc != 0 {
                return undo_setup(lua, &host, group_id, added, rc);
            }
            Ok(0)
        }),
        Local::SetUserTable => binding(lua, spec, move |lua, args| {
            host.beat();
            let (start, num) = (int_arg(lua, spec, &args, 0)?, int_arg(lua, spec, &args, 1)?);
            let values = doubles_arg(lua, spec, &args, 2)?;
            let Some(range) = host.shared.user_table_range(start, num).filter(|r| r.len() <= values.len()) else {
                return Ok(system_code(SystemError::HmplArgOutOfRange));
            };
            for (i, v) in range.zip(values) {
                host.shared.set_user_table(i, v);
            }
            Ok(0)
        }),
        Local::GetUserTable => binding(lua, spec, move |lua, args| {
            host.beat();
            let (start, num) = (int_arg(lua, spec, &args, 0)?, int_arg(lua, spec, &args, 1)?);
            let Some(range) = host.shared.user_table_range(start, num) else {
                return Ok((system_code(SystemError::HmplArgOutOfRange), lua.create_table()?));
            };
            let values = lua.create_sequence_from(range.map(|i| host.shared.user_table(i).unwrap_or(0.0)))?;
            Ok((0, values))
        }),
        Local::SetTableValue => binding(lua, spec, move |lua, args| {
            host.beat();
            let (index, value) = (int_arg(lua, spec, &args, 0)?, double_arg(lua, spec, &args, 1)?);
            let stored = usize::try_from(index).is_ok_and(|i| host.shared.set_user_table(i, value));
            Ok(if stored { 0 } else { system_code(SystemError::HmplArgOutOfRange) })
        }),
        Local::GetTableValue => binding(lua, spec, move |lua, args| {
            host.beat();
            let index = int_arg(lua, spec, &args, 0)?;
            usize::try_from(index)
                .ok()
                .and_then(|i| host.shared.user_table(i))
                .ok_or_else(|| error_here(lua, format!("GetTableValue: index {index} is outside 0..511999 (0x138F)")))
        }),
        Local::ReadModbusWord => binding(lua, spec, move |lua, args| {
            host.beat();
            let address = int_arg(lua, spec, &args, 0)?;
            calls::user_area::read(&host.shared, address).ok_or_else(|| {
                error_here(
                    lua,
                    format!("ReadModbusWord: 0x{address:X} is outside DV 0x0000..0x2FFF and DH 0x8000..0xAFFF"),
                )
            })
        }),
        Local::WriteModbusWord => binding(lua, spec, move |lua, args| {
            host.beat();
            let (address, value) = (int_arg(lua, spec, &args, 0)?, int_arg(lua, spec, &args, 1)?);
            let stored = u16::try_from(value).is_ok_and(|v| calls::user_area::write(&host.shared, address, v));
            Ok(if stored { 0 } else { system_code(SystemError::HmplArgOutOfRange) })
        }),
        Local::SaveUserTable | Local::LoadUserTable => binding(lua, spec, move |lua, args| {
            host.beat();
            let (start, num) = (int_arg(lua, spec, &args, 0)?, int_arg(lua, spec, &args, 1)?);
            let Some(range) = host.shared.user_table_range(start, num) else {
                return Ok(system_code(SystemError::HmplArgOutOfRange));
            };
            // Waiting on the disk is not a hang.
            let slot_state = |state| host.endpoint.borrow().slot().set_state(state);
            slot_state(RunState::Blocked);
            let result = user_table::save_or_load(local == Local::SaveUserTable, &host.data_dir, &host.shared, range);
            slot_state(RunState::Running);
            Ok(match result {
                Ok(()) => 0,
                Err((code, e)) => {
                    eprintln!("warning: {}: {e}", spec.name);
                    system_code(code)
                }
            })
        }),
    }
}

/// HMPL 2.22: mutex ids 0..7; another id is an error in the program.
fn mutex_id(lua: &Lua, spec: &FunctionSpec, args: &MultiValue) -> mlua::Result<usize> {
    match args.front() {
        Some(Value::Integer(id)) if (0..MUTEXES as i64).contains(id) => Ok(*id as usize),
        Some(Value::Number(id)) if id.fract() == 0.0 && (0.0..MUTEXES as f64).contains(id) => Ok(*id as usize),
        other => {
            let got = other.cloned().unwrap_or(Value::Nil);
            Err(error_here(lua, format!("{}: mutex ids are 0..7, not {} (0x138F)", spec.name, type_name(&got))))
        }
    }
}

/// `Print`'s formatting of a call's arguments. A bad format is a warning on stderr (with
/// the format's start) and `Err`.
pub(super) fn format(lua: &Lua, spec: &FunctionSpec, args: &MultiValue) -> mlua::Result<Result<Formatted, ()>> {
    let fmt = lua_string_arg(lua, spec, args, 0)?;
    let fmt = fmt.as_bytes();
    let strings: Vec<Option<BorrowedBytes>> =
        args.iter().skip(1).map(|v| if let Value::String(s) = v { Some(s.as_bytes()) } else { None }).collect();
    let values: Vec<Arg> = args.iter().skip(1).zip(&strings).map(|(v, s)| printf_arg(v, s.as_deref())).collect();
    Ok(printf::format(&fmt, &values).map_err(|e| {
        let shown = char_boundary(&fmt, 60);
        let more = if shown < fmt.len() { "..." } else { "" };
        eprintln!("warning: {}(\"{}{more}\"): {e}", spec.name, escape(&fmt[..shown]));
    }))
}

/// `Till` keeps waiting while its condition returns false, nil or 0.
pub(super) fn is_true(v: &Value) -> bool {
    match v {
        Value::Nil | Value::Boolean(false) => false,
        Value::Integer(0) => false,
        Value::Number(n) => *n != 0.0,
        _ => true,
    }
}

fn printf_arg<'a>(v: &Value, string: Option<&'a [u8]>) -> Arg<'a> {
    match (v, string) {
        (_, Some(bytes)) => Arg::Str(bytes),
        (Value::Integer(i), _) => Arg::Int(*i),
        (Value::Number(n), _) => Arg::Float(*n),
        (Value::Boolean(b), _) => Arg::Int(*b as i64),
        (other, _) => Arg::Str(other.type_name().as_bytes()),
    }
}

/// A command's return code (its first value).
fn core_rc(lua: &Lua, host: &Host, call: &CommandCall) -> mlua::Result<i64> {
    Ok(round_trip(lua, host, call)?.values[0] as i64)
}

/// SetupGroup failed with `rc` after adding `added` axes: they are removed again.
fn undo_setup(lua: &Lua, host: &Host, group_id: i64, added: usize, rc: i64) -> mlua::Result<i64> {
    for _ in 0..added {
        core_rc(lua, host, &CommandCall::RemoveAxisFromGrp { group_id })?;
    }
    Ok(rc)
}

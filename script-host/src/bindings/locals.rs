//! The functions that run in the script process (`api::Kind::Local`): waits on controller
//! time, output, the event stream, mutexes, timers and the user table.

use std::rc::Rc;
use std::time::Duration;

use api::call::ArgError;
use api::{CommandCall, FunctionSpec, Local, LocalCall, SystemError};
use calls::user_table;
use ipc::event_record::{EventKind, EventRecord};
use ipc::output::{cut_marker, escape};
use ipc::task_table::RunState;
use mlua::{AnyUserData, Function, IntoLuaMulti, Lua, MultiValue, Value};
use schema::shared::{Lock, MUTEXES};

use super::print::format;
use super::timer::Timer;
use super::{Host, LuaArg, binding, error_here, got_name, is_true, local_call, round_trip, system_code, write_output};

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

/// The Lua function of `local`: its typed call, carried out where it belongs.
pub fn local(lua: &Lua, host: Rc<Host>, local: Local) -> mlua::Result<Function> {
    binding(lua, local.spec(), move |lua, args| {
        let call = local_call(lua, local, &args)?;
        match local {
            Local::MHSPOLoad
            | Local::MHSPOText
            | Local::GetPlcReg
            | Local::SetPlcReg
            | Local::GetPlcRelay
            | Local::SetPlcRelay => super::plc::call(lua, &host, call),
            Local::EthOpenAsServer
            | Local::EthOpenAsClient
            | Local::EthTx
            | Local::EthRx
            | Local::EthClose
            | Local::EthCloseAll
            | Local::EthBuffClear
            | Local::EthGetSessions
            | Local::EthConnectCheck => super::freeport::call(lua, &host, call),
            Local::SerialInit | Local::SerialTx | Local::SerialRx => super::serial::call(lua, &host, call),
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
            | Local::Modbus_ClientWrite_Coils => super::clients::call(lua, &host, call),
            Local::START_ASCII_AGENT | Local::ASCII_ServerBroadcast => super::agent::call(lua, &host, call),
            Local::expect_eq | Local::expect_near | Local::expect_true => super::expect::call(lua, &host, call),
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
            | Local::GetConfigVar
            | Local::SetConfigVar => super::library::call(lua, &host, call),
            math if api::libm::is_math(math) => super::library::call(lua, &host, call),
            _ => self::call(lua, &host, call),
        }
    })
}

/// A local's argument error, as every function's (`super::arg_error`); HMPL 2.22: a mutex
/// id that is not an integer is a bad id, as one outside 0..7 is.
pub(super) fn arg_error(lua: &Lua, local: Local, error: ArgError) -> mlua::Error {
    match (local, error) {
        (Local::MutexLock | Local::MutexUnlock, ArgError::Type { got, .. }) => {
            no_mutex(lua, local.spec(), &got_name(got))
        }
        (_, error) => super::arg_error(lua, local.spec(), error),
    }
}

/// The functions of `Local` that belong here: waits, output, events, mutexes, timers, the
/// user table and the DV/DH words.
fn call(lua: &Lua, host: &Host, call: LocalCall<'_, LuaArg>) -> mlua::Result<MultiValue> {
    let spec = call.func().spec();
    match call {
        LocalCall::Sleep { ms } => {
            host.beat();
            if ms < 0 {
                return Err(error_here(lua, format!("Sleep: ms must be >= 0, not {ms}")));
            }
            host.sleep_ns(lua, ms as f64 * 1e6)?.into_lua_multi(lua)
        }
        LocalCall::DELAY { seconds } => {
            host.beat();
            if !(seconds >= 0.0 && seconds.is_finite()) {
                return Err(error_here(lua, format!("DELAY: seconds must be >= 0, not {seconds}")));
            }
            host.sleep_ns(lua, seconds * 1e9)?.into_lua_multi(lua)
        }
        LocalCall::Till { condition } => {
            host.beat();
            let Value::Function(condition) = condition.value else { unreachable!("the source checked it") };
            loop {
                host.start_watch();
                let value = condition.call::<Value>(());
                let watch = host.take_watch();
                if is_true(&value?) {
                    return Ok(MultiValue::new());
                }
                let next = host.cycle() + 1;
                host.endpoint.borrow_mut().wait_watching(next, &watch).map_err(mlua::Error::external)?;
                super::agent::serve(lua, host);
            }
        }
        LocalCall::Print { format: text, args } => {
            host.beat();
            match format(spec, &text, &args) {
                Ok(formatted) => {
                    let marker = if formatted.cut > 0 { cut_marker(formatted.cut) } else { String::new() };
                    write_output(&[&formatted.text, marker.as_bytes()]);
                    (formatted.chars as i64).into_lua_multi(lua)
                }
                // HMPL 3.2: Print returns -1 on error; the warning says why.
                Err(()) => (-1).into_lua_multi(lua),
            }
        }
        LocalCall::my_print { text } => {
            host.beat();
            write_output(&[&text]);
            Ok(MultiValue::new())
        }
        LocalCall::SendEvent { evt_id } => {
            host.beat();
            let Ok(id) = u16::try_from(evt_id) else {
                return system_code(SystemError::HmplArgOutOfRange).into_lua_multi(lua);
            };
            host.throttle(lua)?;
            host.send_event(EventKind::Event, id as u32, "").into_lua_multi(lua)
        }
        LocalCall::SendMsgEvent { format: text, args } => {
            host.beat();
            let Ok(formatted) = format(spec, &text, &args) else {
                return system_code(SystemError::HmplInvalidStrFormat).into_lua_multi(lua);
            };
            if formatted.chars > MAX_MESSAGE_CHARS {
                return system_code(SystemError::HmplStrTooLong).into_lua_multi(lua);
            }
            let text = escape(&formatted.text);
            host.throttle(lua)?;
            host.send_event(EventKind::Message, 0, &text).into_lua_multi(lua)
        }
        LocalCall::RunScheduler {} => {
            host.beat();
            let mut endpoint = host.endpoint.borrow_mut();
            if endpoint.lockstep() {
                // On the simulation clock the other tasks' turns come first.
                endpoint.yield_turn().map_err(mlua::Error::external)?;
            } else {
                std::thread::yield_now();
            }
            Ok(MultiValue::new())
        }
        LocalCall::MutexLock { mutex_id } => {
            host.beat();
            let id = mutex(lua, spec, mutex_id)?;
            loop {
                match host.shared.try_lock(id, host.task()) {
                    Some(Lock::Acquired) => return Ok(MultiValue::new()),
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
        }
        LocalCall::MutexUnlock { mutex_id } => {
            host.beat();
            let id = mutex(lua, spec, mutex_id)?;
            ipc::mutex::unlock(&host.shared, id, host.task());
            Ok(MultiValue::new())
        }
        LocalCall::TimerInit {} => {
            host.beat();
            Timer::default().into_lua_multi(lua)
        }
        LocalCall::TON { timer, IN: input, PT: preset } | LocalCall::TOF { timer, IN: input, PT: preset } => {
            host.beat();
            let Value::UserData(timer) = timer.value else { unreachable!("the source checked it") };
            let preset = preset.max(0) as u64;
            let now = host.now_ms();
            let mut timer = AnyUserData::borrow_mut::<Timer>(&timer)?;
            if spec.func == api::Func::Local(Local::TON) {
                timer.on_delay(input, preset, now)
            } else {
                timer.off_delay(input, preset, now)
            }
            .into_lua_multi(lua)
        }
        LocalCall::SetupGroup { group_id, axis_ids } => {
            // HMPL 8.3.3: AddAxisToGrp for each axis, then EnableGroup; what it added is
            // removed again when a step fails, so a failed setup leaves the group as it was.
            // Every argument is read before the first command: a refused call changes nothing.
            let axis_ids = axis_ids.iter().map(|axis| axis.int(lua, spec)).collect::<mlua::Result<Vec<_>>>()?;
            setup_group(lua, host, group_id, axis_ids)?.into_lua_multi(lua)
        }
        LocalCall::SetUserTable { start_idx, num_data, input } => {
            host.beat();
            let values: Vec<f64> = input.iter().collect();
            let Some(range) = host.shared.user_table_range(start_idx, num_data).filter(|r| r.len() <= values.len())
            else {
                return system_code(SystemError::HmplArgOutOfRange).into_lua_multi(lua);
            };
            for (i, v) in range.zip(values) {
                host.shared.set_user_table(i, v);
            }
            0.into_lua_multi(lua)
        }
        LocalCall::GetUserTable { start_idx, num_data } => {
            host.beat();
            let Some(range) = host.shared.user_table_range(start_idx, num_data) else {
                return (system_code(SystemError::HmplArgOutOfRange), lua.create_table()?).into_lua_multi(lua);
            };
            let values = lua.create_sequence_from(range.map(|i| host.shared.user_table(i).unwrap_or(0.0)))?;
            (0, values).into_lua_multi(lua)
        }
        LocalCall::SetTableValue { index, value } => {
            host.beat();
            let stored = usize::try_from(index).is_ok_and(|i| host.shared.set_user_table(i, value));
            (if stored { 0 } else { system_code(SystemError::HmplArgOutOfRange) }).into_lua_multi(lua)
        }
        LocalCall::GetTableValue { index } => {
            host.beat();
            usize::try_from(index)
                .ok()
                .and_then(|i| host.shared.user_table(i))
                .ok_or_else(|| error_here(lua, format!("GetTableValue: index {index} is outside 0..511999 (0x138F)")))?
                .into_lua_multi(lua)
        }
        LocalCall::ReadModbusWord { address } => {
            host.beat();
            calls::user_area::read(&host.shared, address)
                .ok_or_else(|| {
                    error_here(
                        lua,
                        format!("ReadModbusWord: 0x{address:X} is outside DV 0x0000..0x2FFF and DH 0x8000..0xAFFF"),
                    )
                })?
                .into_lua_multi(lua)
        }
        LocalCall::WriteModbusWord { address, value } => {
            host.beat();
            let stored = u16::try_from(value).is_ok_and(|v| calls::user_area::write(&host.shared, address, v));
            (if stored { 0 } else { system_code(SystemError::HmplArgOutOfRange) }).into_lua_multi(lua)
        }
        LocalCall::SaveUserTable { start_idx, num_data } | LocalCall::LoadUserTable { start_idx, num_data } => {
            host.beat();
            let Some(range) = host.shared.user_table_range(start_idx, num_data) else {
                return system_code(SystemError::HmplArgOutOfRange).into_lua_multi(lua);
            };
            // Waiting on the disk is not a hang.
            let slot_state = |state| host.endpoint.borrow().slot().set_state(state);
            slot_state(RunState::Blocked);
            let save = spec.func == api::Func::Local(Local::SaveUserTable);
            let result = user_table::save_or_load(save, &host.data_dir, &host.shared, range);
            slot_state(RunState::Running);
            match result {
                Ok(()) => 0,
                Err((code, e)) => {
                    eprintln!("warning: {}: {e}", spec.name);
                    system_code(code)
                }
            }
            .into_lua_multi(lua)
        }
        other => unreachable!("{:?} is carried out elsewhere", other.func()),
    }
}

/// HMPL 8.3.3's steps: the code of the first that fails (what was added is removed
/// again), or 0.
fn setup_group(lua: &Lua, host: &Host, group_id: i64, axis_ids: Vec<i64>) -> mlua::Result<i64> {
    let mut added = 0;
    for axis_id in axis_ids {
        let rc = core_rc(lua, host, &CommandCall::AddAxisToGrp { group_id, axis_id })?;
        if rc != 0 {
            return undo_setup(lua, host, group_id, added, rc);
        }
        added += 1;
    }
    let rc = core_rc(lua, host, &CommandCall::EnableGroup { group_id })?;
    if rc != 0 {
        return undo_setup(lua, host, group_id, added, rc);
    }
    Ok(0)
}

/// HMPL 2.22: mutex ids 0..7; another id is an error in the program.
fn mutex(lua: &Lua, spec: &FunctionSpec, id: i64) -> mlua::Result<usize> {
    usize::try_from(id).ok().filter(|&id| id < MUTEXES).ok_or_else(|| no_mutex(lua, spec, &format!("integer {id}")))
}

fn no_mutex(lua: &Lua, spec: &FunctionSpec, got: &str) -> mlua::Error {
    error_here(lua, format!("{}: mutex ids are 0..7, not {got} (0x138F)", spec.name))
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

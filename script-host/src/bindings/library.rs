//! The HMPL library a program calls for itself, in its own process (no round trip): what
//! the controller is (ch. 2), strings and memory (ch. 3), C libm (ch. 4) and the
//! controller variables by HCV id (ch. 17.3). Out-parameters come back after the C return
//! value; arguments are never changed (docs/decisions.md, "Out-parameters").

use std::sync::OnceLock;

use api::call::{self, Value as Neutral};
use api::hcv::{self, Hcv, SystemHcv};
use api::{CommandCall, Local, LocalCall, QueryCall, SystemError, strings};
use calls::query;
use ipc::event_record::EventKind;
use ipc::task_table::RunState;
use mlua::{IntoLuaMulti, Lua, MultiValue, Table, Value};
use schema::shared::{TestValue, TestVar};

use super::{Host, LuaArg, error_here, round_trip, system_code, type_name};

/// HMPL 3.1: `HMPL_STR_MAX_LEN`.
const STR_MAX_LEN: usize = 512;

/// The functions of `Local` that belong here.
pub fn call(lua: &Lua, host: &Host, call: LocalCall<'_, LuaArg>) -> mlua::Result<MultiValue> {
    let spec = call.func().spec();
    match call {
        // HMPL ch. 2.
        LocalCall::GetFirmwareVer {} => text_out(lua, host, Some(env!("CARGO_PKG_VERSION").as_bytes().to_vec())),
        LocalCall::GetFirmwareDate {} => text_out(lua, host, firmware_date().map(String::into_bytes)),
        LocalCall::GetModelNum {} | LocalCall::GetSerialNum {} => {
            let (model, serial) = host.shared.identity();
            let text = if spec.func == api::Func::Local(Local::GetModelNum) { model } else { serial };
            text_out(lua, host, Some(text).filter(|t| !t.is_empty()))
        }
        LocalCall::GetFirmwareHash {} => {
            host.beat();
            match firmware_hash(host) {
                Some(hash) => (0, hash as i64),
                None => (system_code(SystemError::HmplExecFailed), 0),
            }
            .into_lua_multi(lua)
        }
        LocalCall::SetHMIScope { start } => {
            host.beat();
            let (code, open) = match start {
                1 => (0xB2C8, true),
                0 => (0xB2C9, false),
                _ => return system_code(SystemError::HmplArgOutOfRange).into_lua_multi(lua),
            };
            // The scope ring's gate (docs/decisions.md "SetHMIScope"); opened per call,
            // which is rare.
            match ipc::scope::ScopeRing::open(&host.ns) {
                Ok(ring) => ring.set_gate(open),
                Err(_) => return system_code(SystemError::HmplExecFailed).into_lua_multi(lua),
            }
            host.send_event(EventKind::Event, code, "").into_lua_multi(lua)
        }
        // HMPL ch. 3: strings, read as C reads them, up to their first NUL.
        LocalCall::StringPrint { format, args } => {
            let text = match super::print::format(spec, &format, &args) {
                Ok(f) if f.cut == 0 && f.text.len() <= STR_MAX_LEN => f.text,
                Ok(_) => {
                    eprintln!("warning: StringPrint: the text is longer than HMPL_STR_MAX_LEN (512) (0x138D)");
                    return (-1, lua.create_string("")?).into_lua_multi(lua);
                }
                Err(()) => return (-1, lua.create_string("")?).into_lua_multi(lua),
            };
            (text.len() as i64, lua.create_string(&text)?).into_lua_multi(lua)
        }
        LocalCall::StringLen { str } => strings::len(&str).into_lua_multi(lua),
        LocalCall::IsStringEqual { str1, str2 } => strings::equal(&str1, &str2).into_lua_multi(lua),
        LocalCall::StrFindChar { str, character: c } => {
            let s = strings::c_str(&str);
            let c = character(lua, &c)?;
            // As C's strchr: the terminator is found too.
            (if c == 0 { s.len() as i64 } else { strings::offset(s.iter().position(|&b| b == c)) }).into_lua_multi(lua)
        }
        LocalCall::StrFindCharEx { str, char_set, complement_set } => {
            strings::find_char_ex(&str, &char_set, complement_set).into_lua_multi(lua)
        }
        LocalCall::StrFindStr { str1, str2 } => strings::find_str(&str1, &str2).into_lua_multi(lua),
        LocalCall::StringCopy { source } => string_result(lua, Vec::new(), Ok(strings::c_str(&source))),
        LocalCall::StringCopyEx { source, start_pos, copy_len } => {
            string_result(lua, Vec::new(), substring(strings::c_str(&source), start_pos, copy_len))
        }
        LocalCall::StringCat { destination, source } => {
            string_result(lua, strings::c_str(&destination).to_vec(), Ok(strings::c_str(&source)))
        }
        LocalCall::StringCatEx { destination, source, start_pos, copy_len } => {
            let part = substring(strings::c_str(&source), start_pos, copy_len);
            string_result(lua, strings::c_str(&destination).to_vec(), part)
        }
        LocalCall::StringToDouble { str } => strings::to_double(&str).into_lua_multi(lua),
        // HMPL ch. 3: memory, on tables that stand for C arrays.
        LocalCall::MemoryCopy { destination, source, byte_num } => {
            let mut destination = memory(lua, spec.name, &destination)?;
            let source = memory(lua, spec.name, &source)?;
            let rc = match byte_count(byte_num, [destination.bytes.len(), source.bytes.len()]) {
                Ok(n) => {
                    destination.bytes[..n].copy_from_slice(&source.bytes[..n]);
                    0
                }
                Err(code) => code,
            };
            (rc, destination.to_lua(lua)?).into_lua_multi(lua)
        }
        LocalCall::MemorySet { destination, value, byte_num } => {
            let mut destination = memory(lua, spec.name, &destination)?;
            let rc = match byte_count(byte_num, [destination.bytes.len()]) {
                Ok(n) => {
                    // As C's memset: the value is converted to an unsigned char.
                    destination.bytes[..n].fill(value as u8);
                    0
                }
                Err(code) => code,
            };
            (rc, destination.to_lua(lua)?).into_lua_multi(lua)
        }
        LocalCall::IsMemoryEqual { memory_ptr1, memory_ptr2, byte_num } => {
            let (a, b) = (memory(lua, spec.name, &memory_ptr1)?, memory(lua, spec.name, &memory_ptr2)?);
            byte_count(byte_num, [a.bytes.len(), b.bytes.len()])
                .is_ok_and(|n| a.bytes[..n] == b.bytes[..n])
                .into_lua_multi(lua)
        }
        // HMPL ch. 4: the C library's functions (Lua's math library calls the same ones, but
        // takes strings and extra arguments); `abs` takes an integer and must fit one.
        LocalCall::abs { x } => x
            .checked_abs()
            .ok_or_else(|| error_here(lua, format!("abs: |{x}| does not fit an integer")))?
            .into_lua_multi(lua),
        math if api::libm::is_math(math.func()) => {
            api::libm::evaluate(&math).expect("a ch. 4 function").into_lua_multi(lua)
        }
        // HMPL 17.3.
        LocalCall::GetConfigVar { hcv_id } => {
            host.beat();
            match get_config_var(host, hcv_id) {
                Ok(value) => (value, 0),
                Err(why) => {
                    eprintln!("warning: GetConfigVar(0x{:08X}): {why}", hcv_id as u32);
                    (0.0, -1)
                }
            }
            .into_lua_multi(lua)
        }
        LocalCall::SetConfigVar { hcv_id, value } => {
            host.beat();
            set_config_var(lua, host, hcv_id, value)?.into_lua_multi(lua)
        }
        other => unreachable!("{:?} is not a library function", other.func()),
    }
}

/// A ch. 2 function that gives a string: `rc, text`, "N/A" when it cannot be had.
fn text_out(lua: &Lua, host: &Host, text: Option<Vec<u8>>) -> mlua::Result<MultiValue> {
    host.beat();
    match text {
        Some(text) => (0, lua.create_string(&text)?),
        None => (system_code(SystemError::HmplExecFailed), lua.create_string("N/A")?),
    }
    .into_lua_multi(lua)
}

/// HMPL 2.12: the luamotion executable's modification time, UTC.
fn firmware_date() -> Option<String> {
    let modified = std::fs::metadata(std::env::current_exe().ok()?).ok()?.modified().ok()?;
    Some(utc_date(modified.duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs())))
}

/// HMPL 2.13: a hash of the luamotion executable's bytes, read once per process; reading
/// it is waiting on the disk, not a hang.
fn firmware_hash(host: &Host) -> Option<u64> {
    static HASH: OnceLock<Option<u64>> = OnceLock::new();
    *HASH.get_or_init(|| {
        let slot_state = |state| host.endpoint.borrow().slot().set_state(state);
        slot_state(RunState::Blocked);
        let hash = std::env::current_exe().ok().and_then(|p| hash_file(&p).ok());
        slot_state(RunState::Running);
        hash
    })
}

/// std's SipHash (fixed keys) over the file: the same build gives the same hash.
fn hash_file(path: &std::path::Path) -> std::io::Result<u64> {
    use std::hash::Hasher;
    use std::io::Read;
    let mut file = std::fs::File::open(path)?;
    let mut buffer = vec![0u8; 1 << 20];
    let mut hasher = std::hash::DefaultHasher::new();
    loop {
        let n = file.read(&mut buffer)?;
        if n == 0 {
            return Ok(hasher.finish());
        }
        hasher.write(&buffer[..n]);
    }
}

/// `YYYY-MM-DD hh:mm:ss` of seconds since 1970 (UTC), by the civil-from-days algorithm.
fn utc_date(secs: u64) -> String {
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02}", rem / 3600, rem % 3600 / 60, rem % 60)
}

/// `StrFindChar`'s character: a one-character string or a byte code 0..255.
fn character(lua: &Lua, arg: &LuaArg) -> mlua::Result<u8> {
    match &arg.value {
        Value::String(s) if s.as_bytes().len() == 1 => Ok(s.as_bytes()[0]),
        Value::Integer(c) if (0..=255).contains(c) => Ok(*c as u8),
        Value::Number(c) if c.fract() == 0.0 && (0.0..=255.0).contains(c) => Ok(*c as u8),
        other => {
            let what = match other {
                Value::String(_) => "string of another length".to_string(),
                v => type_name(v),
            };
            Err(error_here(
                lua,
                format!(
                    "bad argument #{} to 'StrFindChar' (a one-character string or 0..255 expected, got {what})",
                    arg.at + 1
                ),
            ))
        }
    }
}

/// `copy_len` bytes of `s` from `start` (-1: to the end; past the end: to the end, as
/// `strncpy` stops at the terminator). A start outside the string or a length below -1
/// is 0x138F.
fn substring(s: &[u8], start: i64, len: i64) -> Result<&[u8], i64> {
    let start = usize::try_from(start).ok().filter(|&p| p <= s.len());
    let rest = start.map(|p| &s[p..]).ok_or(system_code(SystemError::HmplArgOutOfRange))?;
    match len {
        -1 => Ok(rest),
        n if n >= 0 => Ok(&rest[..rest.len().min(n as usize)]),
        _ => Err(system_code(SystemError::HmplArgOutOfRange)),
    }
}

/// `rc, destination` of the copy and append functions: `destination` with `tail`
/// appended, or as it was with the code when `tail` failed or the result would be longer
/// than HMPL_STR_MAX_LEN (0x138D).
fn string_result(lua: &Lua, mut destination: Vec<u8>, tail: Result<&[u8], i64>) -> mlua::Result<MultiValue> {
    let rc = match tail {
        Ok(tail) if destination.len() + tail.len() <= STR_MAX_LEN => {
            destination.extend_from_slice(tail);
            0
        }
        Ok(_) => system_code(SystemError::HmplStrTooLong),
        Err(code) => code,
    };
    (rc, lua.create_string(&destination)?).into_lua_multi(lua)
}

/// A table standing for a C array: integers are a C `int[]` (4 bytes each), a table with
/// a float in it a `double[]` (8 bytes each), little-endian as on the controller.
struct Memory {
    doubles: bool,
    bytes: Vec<u8>,
}

impl Memory {
    /// The table the bytes make, of the same element type.
    fn to_lua(&self, lua: &Lua) -> mlua::Result<Table> {
        if self.doubles {
            let values = self.bytes.chunks_exact(8).map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")));
            lua.create_sequence_from(values)
        } else {
            let values = self.bytes.chunks_exact(4).map(|c| i32::from_le_bytes(c.try_into().expect("4 bytes")) as i64);
            lua.create_sequence_from(values)
        }
    }
}

fn memory(lua: &Lua, name: &str, arg: &LuaArg) -> mlua::Result<Memory> {
    let bad = |what: String| {
        error_here(
            lua,
            format!("bad argument #{} to '{name}' (table of integers or numbers expected, {what})", arg.at + 1),
        )
    };
    let Value::Table(table) = &arg.value else {
        return Err(bad(format!("got {}", type_name(&arg.value))));
    };
    let values: Vec<Value> = table.sequence_values::<Value>().collect::<mlua::Result<_>>()?;
    let doubles = values.iter().any(|v| matches!(v, Value::Number(_)));
    let mut bytes = Vec::with_capacity(values.len() * if doubles { 8 } else { 4 });
    for v in &values {
        match (v, doubles) {
            (Value::Integer(n), false) => {
                let n = i32::try_from(*n).map_err(|_| bad(format!("{n} does not fit a C int")))?;
                bytes.extend_from_slice(&n.to_le_bytes());
            }
            (Value::Integer(n), true) => bytes.extend_from_slice(&(*n as f64).to_le_bytes()),
            (Value::Number(x), _) => bytes.extend_from_slice(&x.to_le_bytes()),
            (other, _) => return Err(bad(format!("got a {} in it", type_name(other)))),
        }
    }
    Ok(Memory { doubles, bytes })
}

/// `byte_num` of a memory function: 0x138F below 0, 0x138B past the end of a table (C
/// would write or read outside the array).
fn byte_count(n: i64, lengths: impl IntoIterator<Item = usize>) -> Result<usize, i64> {
    let n = usize::try_from(n).map_err(|_| system_code(SystemError::HmplArgOutOfRange))?;
    if lengths.into_iter().any(|len| n > len) {
        return Err(system_code(SystemError::HmplIllegalMemOp));
    }
    Ok(n)
}

/// HMPL 17.3.1: a system variable from the snapshot or the shared data, an axis or group
/// variable through its query.
fn get_config_var(host: &Host, id: i64) -> Result<f64, String> {
    let not_found = || format!("no such variable in luamotion (0x0001 {})", SystemError::HcvIdNotFound.name());
    match hcv::lookup(id).ok_or_else(not_found)? {
        Hcv::System(var) => Ok(match var {
            SystemHcv::Fclk => host.endpoint.borrow_mut().snapshot().cycle as f64,
            SystemHcv::TimeInMs => host.endpoint.borrow_mut().snapshot().time_in_ms as f64,
            SystemHcv::LTest(i) => test_var(host, TestVar::L(i)),
            SystemHcv::DTest(i) => test_var(host, TestVar::D(i)),
        }),
        Hcv::Member { id: member, var } => {
            let values = [Neutral::Int(member)];
            let call: QueryCall = call::from_values(var.get, &values).map_err(|e| format!("{e:?}"))?;
            let answer = query::evaluate(&call, host.endpoint.borrow_mut().snapshot()).map_err(|e| e.to_string())?;
            Ok(match answer.0 {
                query::Value::Bool(b) => b as i64 as f64,
                query::Value::Int(i) => i as f64,
                query::Value::Double(d) => d,
                query::Value::Bytes { .. } => return Err(not_found()),
            })
        }
    }
}

fn test_var(host: &Host, var: TestVar) -> f64 {
    match host.shared.test_var(var) {
        Some(TestValue::Int(i)) => i as f64,
        Some(TestValue::Double(d)) => d,
        None => 0.0,
    }
}

/// HMPL 17.3.2: a system variable in the shared data, an axis or group variable through
/// its setter (a round trip, refused as the setter refuses).
fn set_config_var(lua: &Lua, host: &Host, id: i64, value: f64) -> mlua::Result<i64> {
    let Some(hcv) = hcv::lookup(id) else { return Ok(system_code(SystemError::HcvIdNotFound)) };
    let integral = value.is_finite() && value.fract() == 0.0 && value.abs() < 9.0e15;
    match hcv {
        Hcv::System(SystemHcv::Fclk | SystemHcv::TimeInMs) => Ok(system_code(SystemError::HcvIsReadOnly)),
        Hcv::System(SystemHcv::LTest(i)) => {
            if !integral {
                return Ok(system_code(SystemError::HcvValueOutOfRange));
            }
            host.shared.set_test_var(TestVar::L(i), value);
            Ok(0)
        }
        Hcv::System(SystemHcv::DTest(i)) => {
            host.shared.set_test_var(TestVar::D(i), value);
            Ok(0)
        }
        Hcv::Member { id: member, var } => {
            let Some(set) = var.set else { return Ok(system_code(SystemError::HcvIsReadOnly)) };
            let values = [Neutral::Int(member), Neutral::Double(value)];
            // An `int` setting takes only an integral value.
            let Ok(call) = call::from_values::<CommandCall>(set, &values) else {
                return Ok(system_code(SystemError::HcvValueOutOfRange));
            };
            Ok(round_trip(lua, host, &call)?.values[0] as i64)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// HMPL 3.10, 3.12: -1 to the end; a length past the end stops there.
    #[test]
    fn substrings() {
        let s = b"hello world";
        assert_eq!(substring(s, 6, 3), Ok(&b"wor"[..]));
        assert_eq!(substring(s, 6, -1), Ok(&b"world"[..]));
        assert_eq!(substring(s, 0, -1), Ok(&s[..]));
        assert_eq!(substring(s, 6, 100), Ok(&b"world"[..]));
        assert_eq!(substring(s, 11, -1), Ok(&b""[..]));
        assert_eq!(substring(s, 12, 1), Err(0x138F));
        assert_eq!(substring(s, -1, 1), Err(0x138F));
        assert_eq!(substring(s, 0, -2), Err(0x138F));
    }

    #[test]
    fn dates_are_utc_calendar_dates() {
        assert_eq!(utc_date(0), "1970-01-01 00:00:00");
        assert_eq!(utc_date(951_782_400), "2000-02-29 00:00:00");
        assert_eq!(utc_date(1_798_761_599), "2026-12-31 23:59:59");
    }
}

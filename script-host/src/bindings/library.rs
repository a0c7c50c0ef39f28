//! The HMPL library a program calls for itself, in its own process (no round trip): what
//! the controller is (ch. 2), strings and memory (ch. 3), C libm (ch. 4) and the
//! controller variables by HCV id (ch. 17.3). Out-parameters come back after the C return
//! value; arguments are never changed (docs/decisions.md, "Out-parameters").

use std::rc::Rc;
use std::sync::OnceLock;

use api::call::{self, Value as Neutral};
use api::hcv::{self, Hcv, SystemHcv};
use api::{CommandCall, ErrorCode, Local, QueryCall, SystemError, strings};
use calls::query;
use ipc::event_record::EventKind;
use ipc::task_table::RunState;
use mlua::{Function, Lua, MultiValue, Table, Value};
use schema::shared::{TestValue, TestVar};

use super::{Host, binding, bool_arg, double_arg, error_here, int_arg, lua_string_arg, round_trip, type_name};

/// HMPL 3.1: `HMPL_STR_MAX_LEN`.
const STR_MAX_LEN: usize = 512;

fn system_code(e: SystemError) -> i64 {
    ErrorCode::System(e).code() as i64
}

pub fn local(lua: &Lua, host: Rc<Host>, local: Local) -> mlua::Result<Function> {
    let spec = local.spec();
    let math1 = |f: fn(f64) -> f64| binding(lua, spec, move |lua, args| Ok(f(number(lua, spec, &args, 0)?)));
    let math2 = |f: fn(f64, f64) -> f64| {
        binding(lua, spec, move |lua, args| Ok(f(number(lua, spec, &args, 0)?, number(lua, spec, &args, 1)?)))
    };
    match local {
        // HMPL ch. 2.
        Local::GetFirmwareVer => text_out(lua, spec, host, || Some(env!("CARGO_PKG_VERSION").as_bytes().to_vec())),
        Local::GetFirmwareDate => text_out(lua, spec, host, || firmware_date().map(String::into_bytes)),
        Local::GetModelNum | Local::GetSerialNum => {
            let shared = host.clone();
            text_out(lua, spec, host, move || {
                let (model, serial) = shared.shared.identity();
                Some(if local == Local::GetModelNum { model } else { serial }).filter(|t| !t.is_empty())
            })
        }
        Local::GetFirmwareHash => binding(lua, spec, move |_, _| {
            host.beat();
            Ok(match firmware_hash(&host) {
                Some(hash) => (0, hash as i64),
                None => (system_code(SystemError::HmplExecFailed), 0),
            })
        }),
        Local::SetHMIScope => binding(lua, spec, move |lua, args| {
            host.beat();
            let (code, open) = match int_arg(lua, spec, &args, 0)? {
                1 => (0xB2C8, true),
                0 => (0xB2C9, false),
                _ => return Ok(system_code(SystemError::HmplArgOutOfRange)),
            };
            // The scope ring's gate (docs/decisions.md "SetHMIScope"); opened per call,
            // which is rare.
            match ipc::scope::ScopeRing::open(&host.ns) {
                Ok(ring) => ring.set_gate(open),
                Err(_) => return Ok(system_code(SystemError::HmplExecFailed)),
            }
            Ok(host.send_event(EventKind::Event, code, ""))
        }),
        // HMPL ch. 3: strings.
        Local::StringPrint => binding(lua, spec, move |lua, args| {
            let formatted = super::locals::format(lua, spec, &args)?;
            let text = match formatted {
                Ok(f) if f.cut == 0 && f.text.len() <= STR_MAX_LEN => f.text,
                Ok(_) => {
                    eprintln!("warning: StringPrint: the text is longer than HMPL_STR_MAX_LEN (512) (0x138D)");
                    return Ok((-1, lua.create_string("")?));
                }
                Err(()) => return Ok((-1, lua.create_string("")?)),
            };
            Ok((text.len() as i64, lua.create_string(&text)?))
        }),
        Local::StringLen => binding(lua, spec, move |lua, args| Ok(strings::len(&c_str(lua, spec, &args, 0)?))),
        Local::IsStringEqual => binding(lua, spec, move |lua, args| {
            Ok(strings::equal(&c_str(lua, spec, &args, 0)?, &c_str(lua, spec, &args, 1)?))
        }),
        Local::StrFindChar => binding(lua, spec, move |lua, args| {
            let s = c_str(lua, spec, &args, 0)?;
            let c = character(lua, &args)?;
            // As C's strchr: the terminator is found too.
            Ok(if c == 0 { s.len() as i64 } else { strings::offset(s.iter().position(|&b| b == c)) })
        }),
        Local::StrFindCharEx => binding(lua, spec, move |lua, args| {
            let s = c_str(lua, spec, &args, 0)?;
            let set = c_str(lua, spec, &args, 1)?;
            let complement = bool_arg(lua, spec, &args, 2)?;
            Ok(strings::find_char_ex(&s, &set, complement))
        }),
        Local::StrFindStr => binding(lua, spec, move |lua, args| {
            let (s, sub) = (c_str(lua, spec, &args, 0)?, c_str(lua, spec, &args, 1)?);
            Ok(strings::find_str(&s, &sub))
        }),
        Local::StringCopy => binding(lua, spec, move |lua, args| {
            let source = c_str(lua, spec, &args, 0)?;
            string_result(lua, Vec::new(), Ok(&source))
        }),
        Local::StringCopyEx => binding(lua, spec, move |lua, args| {
            let source = c_str(lua, spec, &args, 0)?;
            let part = substring(&source, int_arg(lua, spec, &args, 1)?, int_arg(lua, spec, &args, 2)?);
            string_result(lua, Vec::new(), part)
        }),
        Local::StringCat => binding(lua, spec, move |lua, args| {
            let (destination, source) = (c_str(lua, spec, &args, 0)?, c_str(lua, spec, &args, 1)?);
            string_result(lua, destination, Ok(&source))
        }),
        Local::StringCatEx => binding(lua, spec, move |lua, args| {
            let (destination, source) = (c_str(lua, spec, &args, 0)?, c_str(lua, spec, &args, 1)?);
            let part = substring(&source, int_arg(lua, spec, &args, 2)?, int_arg(lua, spec, &args, 3)?);
            string_result(lua, destination, part)
        }),
        Local::StringToDouble => {
            binding(lua, spec, move |lua, args| Ok(strings::to_double(&c_str(lua, spec, &args, 0)?)))
        }
        // HMPL ch. 3: memory, on tables that stand for C arrays.
        Local::MemoryCopy => binding(lua, spec, move |lua, args| {
            let mut destination = memory(lua, spec.name, &args, 0)?;
            let source = memory(lua, spec.name, &args, 1)?;
            let n = int_arg(lua, spec, &args, 2)?;
            let rc = match byte_count(n, [destination.bytes.len(), source.bytes.len()]) {
                Ok(n) => {
                    destination.bytes[..n].copy_from_slice(&source.bytes[..n]);
                    0
                }
                Err(code) => code,
            };
            Ok((rc, destination.to_lua(lua)?))
        }),
        Local::MemorySet => binding(lua, spec, move |lua, args| {
            let mut destination = memory(lua, spec.name, &args, 0)?;
            // As C's memset: the value is converted to an unsigned char.
            let value = int_arg(lua, spec, &args, 1)? as u8;
            let n = int_arg(lua, spec, &args, 2)?;
            let rc = match byte_count(n, [destination.bytes.len()]) {
                Ok(n) => {
                    destination.bytes[..n].fill(value);
                    0
                }
                Err(code) => code,
            };
            Ok((rc, destination.to_lua(lua)?))
        }),
        Local::IsMemoryEqual => binding(lua, spec, move |lua, args| {
            let (a, b) = (memory(lua, spec.name, &args, 0)?, memory(lua, spec.name, &args, 1)?);
            let n = int_arg(lua, spec, &args, 2)?;
            Ok(byte_count(n, [a.bytes.len(), b.bytes.len()]).is_ok_and(|n| a.bytes[..n] == b.bytes[..n]))
        }),
        // HMPL ch. 4: the C library's functions (Lua's math library calls the same ones, but
        // takes strings and extra arguments).
        Local::sin => math1(f64::sin),
        Local::cos => math1(f64::cos),
        Local::tan => math1(f64::tan),
        Local::asin => math1(f64::asin),
        Local::acos => math1(f64::acos),
        Local::sqrt => math1(f64::sqrt),
        Local::atan => math1(f64::atan),
        Local::atan2 => math2(f64::atan2),
        Local::abs => binding(lua, spec, move |lua, args| {
            let x = int_arg(lua, spec, &args, 0)?;
            x.checked_abs().ok_or_else(|| error_here(lua, format!("abs: |{x}| does not fit an integer")))
        }),
        Local::fabs => math1(f64::abs),
        Local::ceil => math1(f64::ceil),
        Local::floor => math1(f64::floor),
        Local::ldexp => binding(lua, spec, move |lua, args| {
            let (x, y) = (double_arg(lua, spec, &args, 0)?, int_arg(lua, spec, &args, 1)?);
            Ok(api::libm::ldexp(x, y))
        }),
        Local::exp => math1(api::libm::exp),
        Local::pow => math2(api::libm::pow),
        Local::log => math1(f64::ln),
        Local::log10 => math1(f64::log10),
        Local::cbrt => math1(f64::cbrt),
        Local::hypot => math2(f64::hypot),
        // HMPL 17.3.
        Local::GetConfigVar => binding(lua, spec, move |lua, args| {
            host.beat();
            let id = int_arg(lua, spec, &args, 0)?;
            Ok(match get_config_var(&host, id) {
                Ok(value) => (value, 0),
                Err(why) => {
                    eprintln!("warning: GetConfigVar(0x{:08X}): {why}", id as u32);
                    (0.0, -1)
                }
            })
        }),
        Local::SetConfigVar => binding(lua, spec, move |lua, args| {
            host.beat();
            let (id, value) = (int_arg(lua, spec, &args, 0)?, double_arg(lua, spec, &args, 1)?);
            set_config_var(lua, &host, id, value)
        }),
        other => unreachable!("{other:?} is not a library function"),
    }
}

/// Argument `i` of a math function: a number as it is (the fast path of a hot loop), else
/// read as every other function's argument, for the same error.
fn number(lua: &Lua, spec: &api::FunctionSpec, args: &MultiValue, i: usize) -> mlua::Result<f64> {
    match args.get(i) {
        Some(Value::Number(x)) => Ok(*x),
        Some(Value::Integer(n)) => Ok(*n as f64),
        _ => double_arg(lua, spec, args, i),
    }
}

/// A ch. 2 function that gives a string: `rc, text`, "N/A" when it cannot be had.
fn text_out(
    lua: &Lua,
    spec: &'static api::FunctionSpec,
    host: Rc<Host>,
    text: impl Fn() -> Option<Vec<u8>> + 'static,
) -> mlua::Result<Function> {
    binding(lua, spec, move |lua, _| {
        host.beat();
        Ok(match text() {
            Some(text) => (0, lua.create_string(&text)?),
            None => (system_code(SystemError::HmplExecFailed), lua.create_string("N/A")?),
        })
    })
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

/// A `char*` argument as C reads it: up to its first NUL.
fn c_str(lua: &Lua, spec: &api::FunctionSpec, args: &MultiValue, i: usize) -> mlua::Result<Vec<u8>> {
    let s = lua_string_arg(lua, spec, args, i)?;
    Ok(strings::c_str(&s.as_bytes()).to_vec())
}

/// `StrFindChar`'s character: a one-character string or a byte code 0..255.
fn character(lua: &Lua, args: &MultiValue) -> mlua::Result<u8> {
    match args.get(1) {
        Some(Value::String(s)) if s.as_bytes().len() == 1 => Ok(s.as_bytes()[0]),
        Some(Value::Integer(c)) if (0..=255).contains(c) => Ok(*c as u8),
        Some(Value::Number(c)) if c.fract() == 0.0 && (0.0..=255.0).contains(c) => Ok(*c as u8),
        other => {
            let got = other.cloned().unwrap_or(Value::Nil);
            let what = match &got {
                Value::String(_) => "string of another length".to_string(),
                v => type_name(v),
            };
            Err(error_here(
                lua,
                format!("bad argument #2 to 'StrFindChar' (a one-character string or 0..255 expected, got {what})"),
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
fn string_result(
    lua: &Lua,
    mut destination: Vec<u8>,
    tail: Result<&[u8], i64>,
) -> mlua::Result<(i64, mlua::LuaString)> {
    let rc = match tail {
        Ok(tail) if destination.len() + tail.len() <= STR_MAX_LEN => {
            destination.extend_from_slice(tail);
            0
        }
        Ok(_) => system_code(SystemError::HmplStrTooLong),
        Err(code) => code,
    };
    Ok((rc, lua.create_string(&destination)?))
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

fn memory(lua: &Lua, name: &str, args: &MultiValue, i: usize) -> mlua::Result<Memory> {
    let bad = |what: String| {
        error_here(lua, format!("bad argument #{} to '{name}' (table of integers or numbers expected, {what})", i + 1))
    };
    let Some(Value::Table(table)) = args.get(i) else {
        return Err(bad(format!("got {}", type_name(args.get(i).unwrap_or(&Value::Nil)))));
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

//! The controller as a TCP client (HMPL 22.2 ASCII, HMPL 22.3 Modbus): the sockets a task
//! opened, kept in the Lua state's app data, and the functions on them.
//!
//! The I/O runs on a current-thread tokio runtime owned by the task (tokio-modbus is
//! asynchronous); every wait is cut into short slices so the task's heartbeat goes on
//! (the watchdog) and is bounded by the call's timeout (a silent peer never hangs it).
//! On the simulation clock each call's outcome is an input, recorded or replayed
//! (`clients_sim`).

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::future::Future;
use std::net::{IpAddr, SocketAddr};
use std::time::{Duration, Instant};

use api::{ErrorCode, Local, LocalCall, SystemError};
use mlua::{IntoLuaMulti, Lua, MultiValue};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio::runtime::Runtime;
use tokio_modbus::client::{Context, Reader, Writer};
use tokio_modbus::prelude::Client;

use super::clients_sim::{Outcome, Sim};
use super::{Host, LuaArg, bytes_table, error_here};

/// How long a connect may take (HMPL 22.2.3, 22.3.1: the manual gives no figure).
const CONNECT_TIMEOUT: Duration = Duration::from_secs(3);
/// How long a send, a receive, a Modbus job or a disconnect may take.
const IO_TIMEOUT: Duration = Duration::from_secs(2);
/// The heartbeat goes on at least this often while a call waits.
const SLICE: Duration = Duration::from_millis(50);
/// Open sockets of a kind per task; one more is "limit reached" (0x17D5, 0x1839).
const MAX_SOCKETS: usize = 8;
/// HMPL 22.2.4, 22.2.5: at most 512 bytes a call.
const MAX_ASCII_LENGTH: i64 = 512;
/// Modbus/TCP's registered port, for an `ip` without `:port` (HMPL 22.3.1 has no port).
const MODBUS_PORT: u16 = 502;
/// The unit id of an `ip` without `/unit` (HMPL 22.3 gives none): 1, the station a
/// server behind a gateway or with a station number of its own expects; a device that
/// is only Modbus TCP ignores it (docs/decisions.md, "Modbus client unit id").
const MODBUS_UNIT: u8 = 1;

/// The task's client sockets; ids count up from 1 for each kind.
struct Clients {
    runtime: Runtime,
    ascii: BTreeMap<i64, TcpStream>,
    modbus: BTreeMap<i64, Context>,
    next_id: i64,
}

impl Clients {
    fn new() -> std::io::Result<Self> {
        let runtime = tokio::runtime::Builder::new_current_thread().enable_io().enable_time().build()?;
        Ok(Self { runtime, ascii: BTreeMap::new(), modbus: BTreeMap::new(), next_id: 1 })
    }

    fn id(&mut self) -> i64 {
        self.next_id += 1;
        self.next_id - 1
    }
}

/// Runs `future` until it ends or `timeout` passes (`None`), beating the heartbeat between
/// slices.
fn wait<F: Future>(host: &Host, runtime: &Runtime, timeout: Duration, future: F) -> Option<F::Output> {
    let deadline = Instant::now() + timeout;
    let mut future = std::pin::pin!(future);
    loop {
        host.beat();
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return None;
        }
        if let Ok(output) = runtime.block_on(async { tokio::time::timeout(left.min(SLICE), &mut future).await }) {
            return Some(output);
        }
    }
}

fn code(e: SystemError) -> i64 {
    ErrorCode::System(e).code() as i64
}

/// Runs `body` with the task's sockets, made on first use.
fn with_clients<R>(lua: &Lua, body: impl FnOnce(&mut Clients) -> R) -> mlua::Result<R> {
    if lua.app_data_ref::<Clients>().is_none() {
        let clients = Clients::new().map_err(|e| error_here(lua, format!("client sockets: {e}")))?;
        lua.set_app_data(clients);
    }
    let mut clients = lua.app_data_mut::<Clients>().expect("installed above");
    Ok(body(&mut clients))
}

thread_local! {
    /// On the simulation clock: the task's client outcomes (made on first use).
    static SIM: RefCell<Option<Sim>> = const { RefCell::new(None) };
}

/// A call's outcome: in real time what `live` did on the sockets; on the simulation clock
/// an input (`live`'s, recorded, or the record's, without sockets) that the program sees
/// in its turn after the cycle the call ended in, so a replay returns it at the same cycle.
fn outcome(
    lua: &Lua,
    host: &Host,
    function: Local,
    live: impl FnOnce(&mut Clients) -> Outcome,
) -> mlua::Result<Outcome> {
    if !host.endpoint.borrow().lockstep() {
        return with_clients(lua, live);
    }
    let replaying = SIM
        .with_borrow_mut(|sim| {
            // Outcomes that cannot be written or read: not recorded or replayed.
            let made =
                || Sim::new(host.task(), &host.freeport_inputs).or_else(|_| Sim::new(host.task(), &Default::default()));
            match sim {
                Some(sim) => Ok(sim.replaying()),
                None => Ok(sim.insert(made()?).replaying()),
            }
        })
        .map_err(|e: std::io::Error| error_here(lua, format!("client record: {e}")))?;
    let (cycle, outcome) = if replaying {
        SIM.with_borrow_mut(|sim| sim.as_mut().expect("made").next(function)).map_err(|e| error_here(lua, e))?
    } else {
        let outcome = with_clients(lua, live)?;
        let cycle = host.endpoint.borrow_mut().snapshot().cycle + 1;
        SIM.with_borrow_mut(|sim| sim.as_mut().expect("made").note(cycle, &outcome));
        (cycle, outcome)
    };
    host.endpoint.borrow_mut().wait_until_cycle(cycle).map_err(mlua::Error::external)?;
    Ok(outcome)
}

/// An outcome of `function` with nothing returned besides `rc`.
fn code_only(function: Local, rc: i64) -> Outcome {
    Outcome { function, rc, value: Vec::new(), socket: 0 }
}

/// `"192.168.0.2"` with `port`, or `"192.168.0.2:1502"`: IP addresses only (no name lookup,
/// which could block without a bound).
fn socket_addr(ip: &str, port: Option<&str>) -> Option<SocketAddr> {
    match port {
        Some(port) => Some(SocketAddr::new(ip.trim().parse::<IpAddr>().ok()?, port.trim().parse().ok()?)),
        None => {
            ip.trim().parse::<SocketAddr>().ok().or_else(|| Some(SocketAddr::new(ip.trim().parse().ok()?, MODBUS_PORT)))
        }
    }
}

/// `Modbus_ClientConnect`'s `ip`: `"192.168.0.2"`, `"192.168.0.2:1502"`, either with
/// `/unit` (`"192.168.0.2:1502/3"`): the server's address and the unit id its requests carry.
fn modbus_server(ip: &str) -> Option<(SocketAddr, u8)> {
    let (address, unit) = match ip.split_once('/') {
        Some((address, unit)) => (address, unit.trim().parse().ok()?),
        None => (ip, MODBUS_UNIT),
    };
    Some((socket_addr(address, None)?, unit))
}

/// The functions of `Local` that belong here.
pub fn call(lua: &Lua, host: &Host, call: LocalCall<'_, LuaArg>) -> mlua::Result<MultiValue> {
    let local = call.func();
    host.beat();
    match call {
        LocalCall::ASCII_ClientConnect { ip, port } => {
            let (ip, port) = (String::from_utf8_lossy(&ip), String::from_utf8_lossy(&port));
            let connected = |rc, socket| Outcome { function: local, rc, value: Vec::new(), socket };
            let o = outcome(lua, host, local, |c| {
                let Some(addr) = socket_addr(&ip, Some(&port)) else {
                    return connected(code(SystemError::AsciiConnectFailed), 0);
                };
                if c.ascii.len() >= MAX_SOCKETS {
                    return connected(code(SystemError::AsciiConnectFailed), 0);
                }
                match wait(host, &c.runtime, CONNECT_TIMEOUT, TcpStream::connect(addr)) {
                    None => connected(code(SystemError::AsciiConnectTimeout), 0),
                    Some(Err(_)) => connected(code(SystemError::AsciiConnectFailed), 0),
                    Some(Ok(stream)) => {
                        let id = c.id();
                        c.ascii.insert(id, stream);
                        connected(0, id)
                    }
                }
            })?;
            (o.rc, o.socket).into_lua_multi(lua)
        }
        LocalCall::ASCII_ClientRecv { socket_id: id, length } => {
            let o = outcome(lua, host, local, |c| {
                let Some(stream) = c.ascii.get_mut(&id).filter(|_| (1..=MAX_ASCII_LENGTH).contains(&length)) else {
                    return code_only(local, code(SystemError::AsciiRecvFail));
                };
                let mut buffer = vec![0; length as usize];
                match wait(host, &c.runtime, IO_TIMEOUT, stream.read(&mut buffer)) {
                    None => code_only(local, code(SystemError::AsciiRecvTimeout)),
                    // 0 bytes: the server closed the connection.
                    Some(Ok(0) | Err(_)) => code_only(local, code(SystemError::AsciiRecvFail)),
                    Some(Ok(n)) => {
                        buffer.truncate(n);
                        Outcome { value: buffer, ..code_only(local, 0) }
                    }
                }
            })?;
            (o.rc, lua.create_string(o.value)?).into_lua_multi(lua)
        }
        LocalCall::ASCII_ClientSend { socket_id: id, length, buffer: bytes } => {
            let o = outcome(lua, host, local, |c| {
                let Some(stream) = c.ascii.get_mut(&id).filter(|_| (0..=MAX_ASCII_LENGTH).contains(&length)) else {
                    return code_only(local, code(SystemError::AsciiSendFail));
                };
                // The first `length` bytes, fewer when the string is shorter (no C buffer to overrun).
                let bytes = &bytes[..bytes.len().min(length as usize)];
                code_only(
                    local,
                    match wait(host, &c.runtime, IO_TIMEOUT, stream.write_all(bytes)) {
                        None => code(SystemError::AsciiSendTimeout),
                        Some(Err(_)) => code(SystemError::AsciiSendFail),
                        Some(Ok(())) => 0,
                    },
                )
            })?;
            o.rc.into_lua_multi(lua)
        }
        LocalCall::ASCII_ClientDisconnect { socket_id: id } => {
            let o = outcome(lua, host, local, |c| {
                code_only(
                    local,
                    match c.ascii.remove(&id) {
                        None => code(SystemError::HmplArgOutOfRange),
                        Some(mut stream) => match wait(host, &c.runtime, IO_TIMEOUT, stream.shutdown()) {
                            None => code(SystemError::AsciiDisconnectTimeout),
                            // A peer that left already is disconnected too.
                            Some(_) => 0,
                        },
                    },
                )
            })?;
            o.rc.into_lua_multi(lua)
        }
        LocalCall::Modbus_ClientConnect { ip } => {
            let ip = String::from_utf8_lossy(&ip);
            let connected = |rc, socket| Outcome { function: local, rc, value: Vec::new(), socket };
            let o = outcome(lua, host, local, |c| {
                let Some((addr, unit)) = modbus_server(&ip) else {
                    return connected(code(SystemError::ModbusConnectFailed), 0);
                };
                if c.modbus.len() >= MAX_SOCKETS {
                    return connected(code(SystemError::ModbusConnectFailed), 0);
                }
                let connect = tokio_modbus::client::tcp::connect_slave(addr, tokio_modbus::Slave(unit));
                match wait(host, &c.runtime, CONNECT_TIMEOUT, connect) {
                    None => connected(code(SystemError::ModbusConnectTimeout), 0),
                    Some(Err(_)) => connected(code(SystemError::ModbusConnectFailed), 0),
                    Some(Ok(context)) => {
                        let id = c.id();
                        c.modbus.insert(id, context);
                        connected(0, id)
                    }
                }
            })?;
            (o.rc, o.socket).into_lua_multi(lua)
        }
        LocalCall::Modbus_ClientDisconnect { socket_id: id } => {
            let o = outcome(lua, host, local, |c| {
                code_only(
                    local,
                    match c.modbus.remove(&id) {
                        None => code(SystemError::HmplArgOutOfRange),
                        Some(mut context) => match wait(host, &c.runtime, IO_TIMEOUT, context.disconnect()) {
                            None => code(SystemError::ModbusDisconnectTimeout),
                            Some(_) => 0,
                        },
                    },
                )
            })?;
            o.rc.into_lua_multi(lua)
        }
        LocalCall::Modbus_ClientRead_HoldReg { socket_id: id, start_addr: start, num_regs: count }
        | LocalCall::Modbus_ClientRead_InputReg { socket_id: id, start_addr: start, num_regs: count }
        | LocalCall::Modbus_ClientRead_Coils { socket_id: id, start_addr: start, num_coils: count }
        | LocalCall::Modbus_ClientRead_Inputs { socket_id: id, start_addr: start, num_inputs: count } => {
            let limit = match local {
                Local::Modbus_ClientRead_HoldReg | Local::Modbus_ClientRead_InputReg => 125,
                _ => 2000,
            };
            let o = outcome(lua, host, local, |c| {
                let Some(request) = request(start, count, limit) else {
                    return code_only(local, code(SystemError::ModbusDatalengthErr));
                };
                let Some(context) = c.modbus.get_mut(&id) else {
                    return code_only(local, code(SystemError::ModbusJobFail));
                };
                let (start, count) = request;
                let job = async {
                    Ok(match local {
                        Local::Modbus_ClientRead_HoldReg => words(context.read_holding_registers(start, count).await??),
                        Local::Modbus_ClientRead_InputReg => words(context.read_input_registers(start, count).await??),
                        Local::Modbus_ClientRead_Coils => bits(context.read_coils(start, count).await??),
                        _ => bits(context.read_discrete_inputs(start, count).await??),
                    })
                };
                job_result(local, wait(host, &c.runtime, IO_TIMEOUT, job))
            })?;
            (o.rc, bytes_table(lua, &o.value)?, o.value.len() as i64).into_lua_multi(lua)
        }
        LocalCall::Modbus_ClientWrite_HoldReg { socket_id: id, start_addr: start, num_regs: count, write_data }
        | LocalCall::Modbus_ClientWrite_Coils { socket_id: id, start_addr: start, num_coils: count, write_data } => {
            {
                let data: Vec<f64> = write_data.iter().collect();
                let registers = local == Local::Modbus_ClientWrite_HoldReg;
                let o = outcome(lua, host, local, |c| {
                    let limit = if registers { 123 } else { 1968 };
                    let Some((start, count)) = request(start, count, limit) else {
                        return code_only(local, code(SystemError::ModbusDatalengthErr));
                    };
                    let Some(words) = words_arg(&data, if registers { count } else { count.div_ceil(16) }) else {
                        return code_only(local, code(SystemError::ModbusDatalengthErr));
                    };
                    let Some(context) = c.modbus.get_mut(&id) else {
                        return code_only(local, code(SystemError::ModbusJobFail));
                    };
                    let job = async {
                        if registers {
                            context.write_multiple_registers(start, &words).await??;
                        } else {
                            // HMPL 22.3.8: coil i is bit i % 16 of word i / 16 (data[0] = 15: four on).
                            let coils: Vec<bool> =
                                (0..usize::from(count)).map(|i| words[i / 16] >> (i % 16) & 1 == 1).collect();
                            context.write_multiple_coils(start, &coils).await??;
                        }
                        // The server's reply to FC 15/16: start address and count, big-endian.
                        Ok([start.to_be_bytes(), count.to_be_bytes()].concat())
                    };
                    job_result(local, wait(host, &c.runtime, IO_TIMEOUT, job))
                })?;
                (o.rc, bytes_table(lua, &o.value)?, o.value.len() as i64).into_lua_multi(lua)
            }
        }
        _ => unreachable!("{} is not a client function", local.spec().name),
    }
}

/// A job's failure: the transport's, or the server's exception reply.
enum JobError {
    Transport,
    Exception,
}

impl From<tokio_modbus::Error> for JobError {
    fn from(_: tokio_modbus::Error) -> Self {
        JobError::Transport
    }
}

impl From<tokio_modbus::ExceptionCode> for JobError {
    fn from(_: tokio_modbus::ExceptionCode) -> Self {
        JobError::Exception
    }
}

fn job_result(function: Local, outcome: Option<Result<Vec<u8>, JobError>>) -> Outcome {
    match outcome {
        None => code_only(function, code(SystemError::ModbusJobTimeout)),
        Some(Err(JobError::Transport | JobError::Exception)) => code_only(function, code(SystemError::ModbusJobFail)),
        Some(Ok(bytes)) => Outcome { value: bytes, ..code_only(function, 0) },
    }
}

/// The start address and a count 1..=`limit` that stays inside the 16-bit address space.
fn request(start: i64, count: i64, limit: i64) -> Option<(u16, u16)> {
    let start = u16::try_from(start).ok()?;
    ((1..=limit).contains(&count) && i64::from(start) + count <= 0x1_0000).then_some((start, count as u16))
}

/// The first `count` values of a `uint16_t*` table, each an integer 0..65535.
fn words_arg(data: &[f64], count: u16) -> Option<Vec<u16>> {
    let data = data.get(..usize::from(count))?;
    data.iter().map(|&v| (v.fract() == 0.0 && (0.0..=65535.0).contains(&v)).then_some(v as u16)).collect()
}

/// Registers as the reply's bytes: high byte first.
fn words(words: Vec<u16>) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_be_bytes()).collect()
}

/// Coils or inputs as the reply's bytes: eight a byte, the first in bit 0.
fn bits(bits: Vec<bool>) -> Vec<u8> {
    bits.chunks(8).map(|c| c.iter().enumerate().fold(0u8, |b, (i, &on)| b | (u8::from(on) << i))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn addresses_are_ip_addresses_with_502_as_the_modbus_default() {
        assert_eq!(socket_addr("127.0.0.1", Some("1234")), Some("127.0.0.1:1234".parse().unwrap()));
        assert_eq!(socket_addr("10.0.0.2", None), Some("10.0.0.2:502".parse().unwrap()));
        assert_eq!(socket_addr("10.0.0.2:1502", None), Some("10.0.0.2:1502".parse().unwrap()));
        for (ip, port) in
            [("localhost", Some("80")), ("127.0.0.1", Some("http")), ("127.0.0.1", Some("65536")), ("", None)]
        {
            assert_eq!(socket_addr(ip, port), None, "{ip} {port:?}");
        }
    }

    /// HMPL 22.3: counts 1..=limit, and the range stays in the 16-bit address space.
    #[test]
    fn requests_stay_within_the_count_limit_and_the_address_space() {
        assert_eq!(request(0, 125, 125), Some((0, 125)));
        assert_eq!(request(65535, 1, 125), Some((65535, 1)));
        for (start, count) in [(0, 0), (0, 126), (65535, 2), (-1, 1), (65536, 1)] {
            assert_eq!(request(start, count, 125), None, "{start} {count}");
        }
    }

    #[test]
    fn write_data_is_words_and_coils_pack_from_bit_0() {
        assert_eq!(words_arg(&[1.0, 65535.0, 9.0], 2), Some(vec![1, 65535]));
        assert_eq!(words_arg(&[1.0], 2), None);
        assert_eq!(words_arg(&[65536.0], 1), None);
        assert_eq!(words_arg(&[1.5], 1), None);
        assert_eq!(words(vec![0x1234, 7]), [0x12, 0x34, 0, 7]);
        let on = |i: usize| i.is_multiple_of(3);
        assert_eq!(bits((0..10).map(on).collect()), [0x49, 0x02]);
    }
}

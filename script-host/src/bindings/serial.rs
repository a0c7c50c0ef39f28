//! DRL `FreePort.Serial` (DXMC 8.3): serial port 1 lives in the controller process
//! (`serial` crate); a task reaches it through the port's socket, one short request and
//! reply a call. The reply comes at once; the wait for it beats the heartbeat and is
//! bounded, so a task polling Rx stays alive and a controller that is gone is a code.

use std::cell::RefCell;
use std::time::Duration;

use api::LocalCall;
use mlua::{Lua, MultiValue, Value};
use serial::format::End;
use serial::link::{Client, Code, MAX_DATA, Op};

use super::freeport::{delimiter, message_bytes};
use super::{Host, LuaArg};

/// The heartbeat goes on at least this often while a call waits.
const SLICE: Duration = Duration::from_millis(50);

thread_local! {
    /// The task's connection to the port, made on first use and again after an error.
    static CLIENT: RefCell<Option<Client>> = const { RefCell::new(None) };
}

fn request(host: &Host, op: &Op) -> (Code, Vec<u8>) {
    CLIENT.with_borrow_mut(|client| {
        if client.is_none() {
            *client = Client::connect(host.ns.as_str()).ok();
        }
        let Some(connected) = client else { return (Code::Unavailable, Vec::new()) };
        match connected.request(op, SLICE, || host.beat()) {
            Ok(reply) => reply,
            Err(_) => {
                *client = None;
                (Code::Unavailable, Vec::new())
            }
        }
    })
}

/// Init's delimiters and protocol as a request, or `None` for one that is not valid.
fn init(start: &LuaArg, end: &LuaArg, protocol: &LuaArg) -> Option<Op> {
    let start = delimiter(&start.value, 1)?.first().copied();
    let end = End::from_bytes(&delimiter(&end.value, 2)?)?;
    let protocol = match &protocol.value {
        Value::Nil => None,
        Value::Integer(n) => Some(u8::try_from(*n).ok()?),
        Value::Number(n) if n.fract() == 0.0 && (0.0..=255.0).contains(n) => Some(*n as u8),
        _ => return None,
    };
    Some(Op::Init { start, end, protocol })
}

/// The functions of `Local` that belong here.
pub fn call(lua: &Lua, host: &Host, call: LocalCall<'_, LuaArg>) -> mlua::Result<MultiValue> {
    // Every call beats, so a task polling Rx in a loop is alive for the watchdog.
    host.beat();
    let mut results = MultiValue::new();
    let status = match call {
        LocalCall::SerialInit { port, SrtByte: start, EndByte: end, Protocol: protocol } => {
            let (status, word) = match init(&start, &end, &protocol) {
                _ if port != 1 => (Code::NoSuchPort, 0),
                None => (Code::BadArgument, 0),
                Some(op) => {
                    let (status, reply) = request(host, &op);
                    (status, reply.try_into().map_or(0, u32::from_le_bytes))
                }
            };
            results.push_back(Value::Integer(word.into()));
            status
        }
        LocalCall::SerialTx { port, Msg: msg } => {
            let msg = msg.value;
            let status = match message_bytes(&msg) {
                _ if port != 1 => Code::NoSuchPort,
                None => Code::BadArgument,
                Some(bytes) if bytes.len() > MAX_DATA => Code::TooLong,
                Some(bytes) => request(host, &Op::Tx(bytes)).0,
            };
            results.push_back(msg);
            status
        }
        LocalCall::SerialRx { port } => {
            let (status, data) = if port == 1 { request(host, &Op::Rx) } else { (Code::NoSuchPort, Vec::new()) };
            results.push_back(Value::String(lua.create_string(&data)?));
            results.push_back(Value::Integer(data.len() as i64));
            status
        }
        other => unreachable!("{:?} is not a FreePort.Serial function", other.func()),
    };
    results.push_front(Value::Integer(status as i64));
    Ok(results)
}

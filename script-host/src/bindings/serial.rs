//! DRL `FreePort.Serial` (DXMC 8.3): serial port 1 lives in the controller process
//! (`serial` crate); a task reaches it through the port's socket, one short request and
//! reply a call. The reply comes at once; the wait for it beats the heartbeat and is
//! bounded, so a task polling Rx stays alive and a controller that is gone is a code.

use std::cell::RefCell;
use std::rc::Rc;
use std::time::Duration;

use api::Local;
use mlua::{Function, Lua, MultiValue, Value};
use serial::format::End;
use serial::link::{Client, Code, MAX_DATA, Op};

use super::freeport::{delimiter, message_bytes};
use super::{Host, binding, int_arg};

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

/// Init's arguments as a request, or `None` for one that is not valid.
fn init(args: &MultiValue) -> Option<Op> {
    let start = delimiter(args.get(1), 1)?.first().copied();
    let end = End::from_bytes(&delimiter(args.get(2), 2)?)?;
    let protocol = match args.get(3).unwrap_or(&Value::Nil) {
        Value::Nil => None,
        Value::Integer(n) => Some(u8::try_from(*n).ok()?),
        Value::Number(n) if n.fract() == 0.0 && (0.0..=255.0).contains(n) => Some(*n as u8),
        _ => return None,
    };
    Some(Op::Init { start, end, protocol })
}

pub fn local(lua: &Lua, host: Rc<Host>, local: Local) -> mlua::Result<Function> {
    let spec = local.spec();
    binding(lua, spec, move |lua, args| {
        // Every call beats, so a task polling Rx in a loop is alive for the watchdog.
        host.beat();
        let port = int_arg(lua, spec, &args, 0)?;
        let mut results = MultiValue::new();
        let status = match local {
            Local::SerialInit => {
                let (status, word) = match init(&args) {
                    _ if port != 1 => (Code::NoSuchPort, 0),
                    None => (Code::BadArgument, 0),
                    Some(op) => {
                        let (status, reply) = request(&host, &op);
                        (status, reply.try_into().map_or(0, u32::from_le_bytes))
                    }
                };
                results.push_back(Value::Integer(word.into()));
                status
            }
            Local::SerialTx => {
                let msg = args.get(1).cloned().unwrap_or(Value::Nil);
                let status = match message_bytes(&msg) {
                    _ if port != 1 => Code::NoSuchPort,
                    None => Code::BadArgument,
                    Some(bytes) if bytes.len() > MAX_DATA => Code::TooLong,
                    Some(bytes) => request(&host, &Op::Tx(bytes)).0,
                };
                results.push_back(msg);
                status
            }
            Local::SerialRx => {
                let (status, data) = if port == 1 { request(&host, &Op::Rx) } else { (Code::NoSuchPort, Vec::new()) };
                results.push_back(Value::String(lua.create_string(&data)?));
                results.push_back(Value::Integer(data.len() as i64));
                status
            }
            other => unreachable!("{other:?} is not a FreePort.Serial function"),
        };
        results.push_front(Value::Integer(status as i64));
        Ok(results)
    })
}

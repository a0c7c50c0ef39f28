//! DRL `FreePort.Eth` (DXMC 8.3 FreePort): TCP sessions of the script process, framed by a
//! start byte and end bytes. The sockets are non-blocking and polled on each call, so no
//! thread is needed; they close with the process, whichever way the task ends, and the
//! listener's port can be bound again at once (std sets SO_REUSEADDR on Unix).

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::io::{ErrorKind, Read, Write};
use std::net::{IpAddr, SocketAddr, TcpListener, TcpStream};
use std::rc::Rc;
use std::time::Duration;

use api::Local;
use mlua::{Function, Lua, MultiValue, Value};
use serial::framing::{Deframer, Framing, Received};

use super::{Host, int_arg, lua_string_arg};

/// DXMC 8.3 FreePort: "0 = success, other = error"; the manual numbers no errors, these
/// are luamotion's (docs/decisions.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(i64)]
enum Code {
    Ok = 0,
    /// A port outside 3000..10000, a start or end byte that is not one, an address that
    /// does not parse, a message that cannot be sent as bytes.
    BadArgument = 1,
    NoSession = 2,
    SessionInUse = 3,
    /// The port is taken, or the peer refused or did not answer in time.
    OpenFailed = 4,
    NotConnected = 5,
    TooLong = 6,
    SendFailed = 7,
    TooManySessions = 8,
}

/// DXMC 8.3 FreePort packet table: at most 1024 bytes of data a frame.
const MAX_DATA: usize = 1024;
/// Bounds the sessions of one task.
const MAX_SESSIONS: usize = 32;
/// DXMC 8.3: OpenAsClient's port range, taken for the server too.
const PORTS: std::ops::RangeInclusive<i64> = 3000..=10000;
/// At most this many connections beyond a server session's peer are closed in one call.
const REFUSED_PER_CALL: usize = 64;
/// At most this much is read from a peer in one call.
const READ_PER_CALL: usize = 64 * 1024;
const CONNECT_TIMEOUT: Duration = Duration::from_secs(1);
const SEND_TIMEOUT: Duration = Duration::from_secs(1);

struct Session {
    listener: Option<TcpListener>,
    peer: Option<TcpStream>,
    received: Deframer,
    /// The peer has sent its last byte (end of stream).
    peer_done: bool,
}

impl Session {
    fn new(listener: Option<TcpListener>, peer: Option<TcpStream>, framing: Framing) -> Self {
        // The frames a task has not read are not bounded here: a peer sends at most
        // `READ_PER_CALL` bytes a call.
        Session { listener, peer, received: Deframer::new(framing, MAX_DATA, usize::MAX), peer_done: false }
    }

    /// Takes a waiting peer (server) and reads it.
    fn poll(&mut self) {
        if self.peer.is_none()
            && let Some(listener) = &self.listener
            && let Ok((stream, _)) = listener.accept()
            && stream.set_nonblocking(true).is_ok()
        {
            self.peer = Some(stream);
        }
        self.read_peer();
        // A session has one peer: later ones are closed at once rather than left waiting
        // in the backlog, bounded per call so that a flood cannot stall the task. The peer
        // is read first, and one that has stopped sending keeps its successor waiting.
        if self.peer.is_some()
            && !self.peer_done
            && let Some(listener) = &self.listener
        {
            for _ in 0..REFUSED_PER_CALL {
                if listener.accept().is_err() {
                    break;
                }
            }
        }
    }

    /// Reads what arrived and cuts it into frames; the unfinished frame of a peer that has
    /// stopped sending is dropped.
    fn read_peer(&mut self) {
        if self.peer_done {
            return;
        }
        let Some(peer) = &mut self.peer else { return };
        let mut buf = [0u8; 4096];
        let mut arrived = Vec::new();
        let gone = loop {
            match peer.read(&mut buf) {
                Ok(0) => break true,
                Ok(n) => arrived.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == ErrorKind::WouldBlock => break false,
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(_) => break true,
            }
            // Bounded: a peer that floods is read on at the next call.
            if arrived.len() >= READ_PER_CALL {
                break false;
            }
        };
        self.received.receive(&arrived);
        if gone {
            self.peer_done = true;
            self.received.drop_unfinished();
        }
    }

    /// Rx: the oldest frame. A peer that has stopped sending stays until Rx finds none of
    /// its frames left, so the answers to its last requests still go out (a half-closed
    /// connection, as `nc -N` leaves it); a peer that has gone altogether fails those sends.
    fn next_frame(&mut self) -> (Code, Vec<u8>) {
        self.poll();
        match self.received.pop() {
            Some(Received::Frame(data)) => (Code::Ok, data),
            // No overrun: the queue is unbounded.
            Some(Received::TooLong | Received::Overrun(_)) => (Code::TooLong, Vec::new()),
            None if self.peer_done => {
                self.peer = None;
                self.peer_done = false;
                (Code::NotConnected, Vec::new())
            }
            None if self.peer.is_none() => (Code::NotConnected, Vec::new()),
            None => (Code::Ok, Vec::new()),
        }
    }

    fn send(&mut self, data: &[u8]) -> Code {
        self.poll();
        let Some(peer) = &mut self.peer else { return Code::NotConnected };
        let packet = self.received.framing().frame(data);
        let sent = peer
            .set_nonblocking(false)
            .and_then(|()| peer.set_write_timeout(Some(SEND_TIMEOUT)))
            .and_then(|()| peer.write_all(&packet))
            .and_then(|()| peer.set_nonblocking(true));
        if sent.is_ok() {
            Code::Ok
        } else {
            self.peer = None;
            self.peer_done = false;
            Code::SendFailed
        }
    }
}

thread_local! {
    /// The task's sessions by id; the Lua state runs on one thread.
    static SESSIONS: RefCell<BTreeMap<i64, Session>> = const { RefCell::new(BTreeMap::new()) };
}

fn with_session<T>(id: i64, f: impl FnOnce(&mut Session) -> T) -> Result<T, Code> {
    SESSIONS.with_borrow_mut(|sessions| sessions.get_mut(&id).map(f).ok_or(Code::NoSession))
}

/// A start byte (at most one: nil, 0..0xFF or a 1-character string) or end bytes (nil, a
/// byte, `CR_LF` or a string of at most 2).
pub(super) fn delimiter(value: Option<&Value>, most: usize) -> Option<Vec<u8>> {
    match value.unwrap_or(&Value::Nil) {
        Value::Nil => Some(Vec::new()),
        Value::Integer(n) => u8::try_from(*n).ok().map(|b| vec![b]),
        Value::Number(n) if n.fract() == 0.0 && (0.0..=255.0).contains(n) => Some(vec![*n as u8]),
        Value::String(s) if !s.as_bytes().is_empty() && s.as_bytes().len() <= most => Some(s.as_bytes().to_vec()),
        _ => None,
    }
}

fn framing(args: &MultiValue, start_at: usize) -> Option<Framing> {
    let start = delimiter(args.get(start_at), 1)?;
    let end = delimiter(args.get(start_at + 1), 2)?;
    Some(Framing { start: start.first().copied(), end })
}

fn port(n: i64) -> Option<u16> {
    PORTS.contains(&n).then_some(n as u16)
}

/// Adds a session made by `open` unless the id is taken or the task has too many.
fn open(id: i64, open: impl FnOnce() -> Result<Session, Code>) -> Code {
    SESSIONS.with_borrow_mut(|sessions| {
        if sessions.contains_key(&id) {
            return Code::SessionInUse;
        }
        if sessions.len() >= MAX_SESSIONS {
            return Code::TooManySessions;
        }
        match open() {
            Ok(session) => {
                sessions.insert(id, session);
                Code::Ok
            }
            Err(code) => code,
        }
    })
}

/// A message as the bytes of its frame, `None` for what has none.
pub(super) fn message_bytes(msg: &Value) -> Option<Vec<u8>> {
    match msg {
        Value::String(s) => Some(s.as_bytes().to_vec()),
        Value::Integer(n) => Some(n.to_string().into_bytes()),
        // Lua's own `tostring` (%.14g), so 3.1415 is sent as "3.1415".
        Value::Number(_) => msg.to_string().ok().map(String::into_bytes),
        Value::Boolean(b) => Some(b.to_string().into_bytes()),
        Value::Table(t) => t
            .sequence_values::<Value>()
            .map(|v| match v {
                Ok(Value::Integer(n)) => u8::try_from(n).ok(),
                _ => None,
            })
            .collect(),
        _ => None,
    }
}

fn code(c: Code) -> i64 {
    c as i64
}

pub fn local(lua: &Lua, host: Rc<Host>, local: Local) -> mlua::Result<Function> {
    let spec = local.spec();
    lua.create_function(move |lua, args: MultiValue| {
        // Every call beats, so a task polling Rx in a loop is alive for the watchdog.
        host.beat();
        let mut results = MultiValue::new();
        let status = match local {
            Local::EthOpenAsServer => {
                let id = int_arg(lua, spec, &args, 0)?;
                let (Some(port), Some(framing)) = (port(int_arg(lua, spec, &args, 1)?), framing(&args, 2)) else {
                    return Ok(MultiValue::from_vec(vec![Value::Integer(code(Code::BadArgument))]));
                };
                open(id, || {
                    let address = SocketAddr::new(host.freeport_bind, port);
                    let listener = TcpListener::bind(address).map_err(|_| Code::OpenFailed)?;
                    listener.set_nonblocking(true).map_err(|_| Code::OpenFailed)?;
                    Ok(Session::new(Some(listener), None, framing))
                })
            }
            Local::EthOpenAsClient => {
                let id = int_arg(lua, spec, &args, 0)?;
                let ip = lua_string_arg(lua, spec, &args, 1)?.to_str().ok().and_then(|s| s.parse::<IpAddr>().ok());
                let (Some(ip), Some(port), Some(framing)) =
                    (ip, port(int_arg(lua, spec, &args, 2)?), framing(&args, 3))
                else {
                    return Ok(MultiValue::from_vec(vec![Value::Integer(code(Code::BadArgument))]));
                };
                open(id, || {
                    let stream = TcpStream::connect_timeout(&SocketAddr::new(ip, port), CONNECT_TIMEOUT)
                        .map_err(|_| Code::OpenFailed)?;
                    stream.set_nonblocking(true).map_err(|_| Code::OpenFailed)?;
                    Ok(Session::new(None, Some(stream), framing))
                })
            }
            Local::EthTx => {
                let id = int_arg(lua, spec, &args, 0)?;
                let msg = args.get(1).cloned().unwrap_or(Value::Nil);
                let status = match message_bytes(&msg) {
                    None => Code::BadArgument,
                    Some(bytes) if bytes.len() > MAX_DATA => Code::TooLong,
                    Some(bytes) => with_session(id, |s| s.send(&bytes)).unwrap_or_else(|c| c),
                };
                results.push_back(msg);
                status
            }
            Local::EthRx => {
                let id = int_arg(lua, spec, &args, 0)?;
                let frame = with_session(id, Session::next_frame);
                let (status, data) = frame.unwrap_or_else(|c| (c, Vec::new()));
                results.push_back(Value::String(lua.create_string(&data)?));
                results.push_back(Value::Integer(data.len() as i64));
                status
            }
            Local::EthClose => {
                let id = int_arg(lua, spec, &args, 0)?;
                SESSIONS.with_borrow_mut(|s| s.remove(&id)).map_or(Code::NoSession, |_| Code::Ok)
            }
            Local::EthCloseAll => {
                SESSIONS.with_borrow_mut(BTreeMap::clear);
                Code::Ok
            }
            Local::EthBuffClear => {
                let id = int_arg(lua, spec, &args, 0)?;
                with_session(id, |s| {
                    s.poll();
                    s.received.clear();
                    Code::Ok
                })
                .unwrap_or_else(|c| c)
            }
            Local::EthGetSessions => {
                let ids: Vec<i64> = SESSIONS.with_borrow(|s| s.keys().copied().collect());
                results.push_back(Value::Table(lua.create_sequence_from(ids)?));
                Code::Ok
            }
            Local::EthConnectCheck => {
                let id = int_arg(lua, spec, &args, 0)?;
                with_session(id, |s| {
                    s.poll();
                    if s.peer.is_some() { Code::Ok } else { Code::NotConnected }
                })
                .unwrap_or_else(|c| c)
            }
            other => unreachable!("{other:?} is not a FreePort function"),
        };
        results.push_front(Value::Integer(code(status)));
        Ok(results)
    })
}

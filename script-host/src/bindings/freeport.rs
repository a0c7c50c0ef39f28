//! DRL `FreePort.Eth` (DXMC 8.3 FreePort): TCP sessions of the script process, framed by a
//! start byte and end bytes. The sockets are non-blocking and polled on each call, so no
//! thread is needed; they close with the process, whichever way the task ends, and the
//! listener's port can be bound again at once (std sets SO_REUSEADDR on Unix).

use std::cell::RefCell;
use std::collections::{BTreeMap, VecDeque};
use std::io::{ErrorKind, Read, Write};
use std::net::{IpAddr, SocketAddr, TcpListener, TcpStream};
use std::time::Duration;

use api::LocalCall;
use mlua::{Lua, MultiValue, Value};
use serial::framing::{Deframer, Framing, Received};

use super::freeport_sim::{Event, Sim};
use super::{Host, LuaArg};

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

/// On the simulation clock: the task's inputs, the cycle of its turn, the session's id.
struct Turn<'a> {
    sim: &'a mut Sim,
    cycle: u64,
    id: i64,
}

impl Turn<'_> {
    /// An input read from the socket now: it takes effect at the next cycle.
    fn stamp(&self, due: &mut VecDeque<(u64, Event)>, event: Event) {
        due.push_back((self.cycle + 1, event));
    }
}

struct Session {
    listener: Option<TcpListener>,
    peer: Option<TcpStream>,
    received: Deframer,
    /// The peer has sent its last byte (end of stream), as the program sees it.
    peer_done: bool,
    /// On the simulation clock: the socket's inputs not yet due, with their cycles.
    due: VecDeque<(u64, Event)>,
    /// On the simulation clock: the program sees a peer (its `Connect` is due).
    connected: bool,
    /// On the simulation clock: the socket's peer has ended its stream (its `End` may not
    /// be due yet).
    socket_done: bool,
}

impl Session {
    fn new(listener: Option<TcpListener>, peer: Option<TcpStream>, framing: Framing) -> Self {
        // The frames a task has not read are not bounded here: a peer sends at most
        // `READ_PER_CALL` bytes a call.
        Session {
            listener,
            peer,
            received: Deframer::new(framing, MAX_DATA, usize::MAX),
            peer_done: false,
            due: VecDeque::new(),
            connected: false,
            socket_done: false,
        }
    }

    /// Whether the program sees a peer.
    fn has_peer(&self, sim: bool) -> bool {
        if sim { self.connected } else { self.peer.is_some() }
    }

    fn forget_peer(&mut self) {
        (self.peer, self.peer_done, self.connected, self.socket_done) = (None, false, false, false);
    }

    /// Takes a waiting peer (server) and reads it; on the simulation clock, stamps what
    /// came and applies what is due by the turn's cycle (a replay's, without sockets).
    fn poll(&mut self, mut turn: Option<&mut Turn>) {
        match turn.as_deref_mut() {
            Some(turn) if turn.sim.replaying() => {
                while let Some(event) = turn.sim.next_due(turn.id, turn.cycle) {
                    self.due.push_back((turn.cycle, event));
                }
            }
            _ => self.poll_socket(turn.as_deref_mut()),
        }
        let Some(turn) = turn else { return };
        // Recorded as the program sees it: what a session closed before it was due is not
        // an input of the run.
        while self.due.front().is_some_and(|(at, _)| *at <= turn.cycle) {
            let (at, event) = self.due.pop_front().expect("front");
            turn.sim.note(at, turn.id, &event);
            match event {
                Event::Connect => self.connected = true,
                Event::Data(bytes) => self.received.receive(&bytes),
                Event::End => {
                    self.peer_done = true;
                    self.received.drop_unfinished();
                }
                Event::Refused => {}
            }
        }
    }

    fn poll_socket(&mut self, mut turn: Option<&mut Turn>) {
        // On the simulation clock the next peer waits until the program has seen the
        // last one's end.
        if self.peer.is_none()
            && !self.socket_done
            && let Some(listener) = &self.listener
            && let Ok((stream, _)) = listener.accept()
            && stream.set_nonblocking(true).is_ok()
        {
            self.peer = Some(stream);
            if let Some(turn) = turn.as_deref_mut() {
                turn.stamp(&mut self.due, Event::Connect);
            }
        }
        self.read_peer(turn);
        // A session has one peer: later ones are closed at once rather than left waiting
        // in the backlog, bounded per call so that a flood cannot stall the task. The peer
        // is read first, and one that has stopped sending keeps its successor waiting.
        if self.peer.is_some()
            && !self.peer_done
            && !self.socket_done
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
    fn read_peer(&mut self, turn: Option<&mut Turn>) {
        if self.peer_done || self.socket_done {
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
        match turn {
            Some(turn) => {
                if !arrived.is_empty() {
                    turn.stamp(&mut self.due, Event::Data(arrived));
                }
                if gone {
                    self.socket_done = true;
                    turn.stamp(&mut self.due, Event::End);
                }
            }
            None => {
                self.received.receive(&arrived);
                if gone {
                    self.peer_done = true;
                    self.received.drop_unfinished();
                }
            }
        }
    }

    /// Rx: the oldest frame. A peer that has stopped sending stays until Rx finds none of
    /// its frames left, so the answers to its last requests still go out (a half-closed
    /// connection, as `nc -N` leaves it); a peer that has gone altogether fails those sends.
    fn next_frame(&mut self, turn: Option<&mut Turn>) -> (Code, Vec<u8>) {
        let sim = turn.is_some();
        self.poll(turn);
        match self.received.pop() {
            Some(Received::Frame(data)) => (Code::Ok, data),
            // No overrun: the queue is unbounded.
            Some(Received::TooLong | Received::Overrun(_)) => (Code::TooLong, Vec::new()),
            None if self.peer_done => {
                self.forget_peer();
                (Code::NotConnected, Vec::new())
            }
            None if !self.has_peer(sim) => (Code::NotConnected, Vec::new()),
            None => (Code::Ok, Vec::new()),
        }
    }

    fn send(&mut self, data: &[u8], turn: Option<&mut Turn>) -> Code {
        let Some(turn) = turn else {
            self.poll(None);
            return self.send_now(data);
        };
        self.poll(Some(&mut *turn));
        if !self.connected {
            return Code::NotConnected;
        }
        // On the simulation clock a send to a peer the program sees is accepted (a
        // replay's is dropped); a socket that refuses it is the peer's end, an input.
        if self.peer.is_some() && !self.write(data) {
            self.peer = None;
            if !std::mem::replace(&mut self.socket_done, true) {
                turn.stamp(&mut self.due, Event::End);
            }
        }
        Code::Ok
    }

    fn send_now(&mut self, data: &[u8]) -> Code {
        if self.peer.is_none() {
            return Code::NotConnected;
        }
        if self.write(data) {
            Code::Ok
        } else {
            self.forget_peer();
            Code::SendFailed
        }
    }

    /// Writes a frame of `data` to the socket's peer; false if it fails.
    fn write(&mut self, data: &[u8]) -> bool {
        let packet = self.received.framing().frame(data);
        let Some(peer) = &mut self.peer else { return false };
        peer.set_nonblocking(false)
            .and_then(|()| peer.set_write_timeout(Some(SEND_TIMEOUT)))
            .and_then(|()| peer.write_all(&packet))
            .and_then(|()| peer.set_nonblocking(true))
            .is_ok()
    }
}

thread_local! {
    /// The task's sessions by id; the Lua state runs on one thread.
    static SESSIONS: RefCell<BTreeMap<i64, Session>> = const { RefCell::new(BTreeMap::new()) };
    /// On the simulation clock: the task's FreePort inputs (made on first use).
    static SIM: RefCell<Option<Sim>> = const { RefCell::new(None) };
}

/// `f` with the turn of session `id` on the simulation clock, `None` in real time.
fn with_turn<T>(host: &Host, id: i64, f: impl FnOnce(Option<&mut Turn>) -> T) -> T {
    let cycle = {
        let mut endpoint = host.endpoint.borrow_mut();
        endpoint.lockstep().then(|| endpoint.snapshot().cycle)
    };
    let Some(cycle) = cycle else { return f(None) };
    SIM.with_borrow_mut(|sim| {
        if sim.is_none() {
            // Inputs that cannot be written or read: stamped, not recorded or replayed.
            let made = Sim::new(host.task(), &host.freeport_inputs);
            *sim = Some(made.unwrap_or_else(|_| Sim::new(host.task(), &Default::default()).expect("live")));
        }
        f(Some(&mut Turn { sim: sim.as_mut().expect("made"), cycle, id }))
    })
}

fn with_session<T>(host: &Host, id: i64, f: impl FnOnce(&mut Session, Option<&mut Turn>) -> T) -> Result<T, Code> {
    with_turn(host, id, |turn| SESSIONS.with_borrow_mut(|sessions| sessions.get_mut(&id).map(|s| f(s, turn))))
        .ok_or(Code::NoSession)
}

fn close(id: i64) -> Code {
    SESSIONS.with_borrow_mut(|s| s.remove(&id)).map_or(Code::NoSession, |_| Code::Ok)
}

/// A start byte (at most one: nil, 0..0xFF or a 1-character string) or end bytes (nil, a
/// byte, `CR_LF` or a string of at most 2).
pub(super) fn delimiter(value: &Value, most: usize) -> Option<Vec<u8>> {
    match value {
        Value::Nil => Some(Vec::new()),
        Value::Integer(n) => u8::try_from(*n).ok().map(|b| vec![b]),
        Value::Number(n) if n.fract() == 0.0 && (0.0..=255.0).contains(n) => Some(vec![*n as u8]),
        Value::String(s) if !s.as_bytes().is_empty() && s.as_bytes().len() <= most => Some(s.as_bytes().to_vec()),
        _ => None,
    }
}

fn framing(start: &LuaArg, end: &LuaArg) -> Option<Framing> {
    let start = delimiter(&start.value, 1)?;
    let end = delimiter(&end.value, 2)?;
    Some(Framing { start: start.first().copied(), end })
}

fn port(n: i64) -> Option<u16> {
    PORTS.contains(&n).then_some(n as u16)
}

/// Adds a session made by `open` (told whether it replays: no socket) unless the id is
/// taken or the task has too many. On the simulation clock whether it opens is an input:
/// recorded, or replayed from the record (`connect` for a client, `refused` for either).
fn open(host: &Host, id: i64, open: impl FnOnce(bool) -> Result<Session, Code>) -> Code {
    with_turn(host, id, |turn| {
        SESSIONS.with_borrow_mut(|sessions| {
            if sessions.contains_key(&id) {
                return Code::SessionInUse;
            }
            if sessions.len() >= MAX_SESSIONS {
                return Code::TooManySessions;
            }
            let opened = match turn {
                None => open(false),
                Some(turn) if turn.sim.replaying() => match open(true) {
                    // A client's open is its `connect`; a server's fails only as recorded.
                    Ok(session) if session.connected => match turn.sim.next_due(id, turn.cycle) {
                        Some(Event::Connect) => Ok(session),
                        _ => Err(Code::OpenFailed),
                    },
                    Ok(_) if turn.sim.refused(id, turn.cycle) => Err(Code::OpenFailed),
                    opened => opened,
                },
                Some(turn) => {
                    let opened = open(false);
                    let event = match &opened {
                        Ok(session) if session.connected => Some(Event::Connect),
                        Ok(_) => None,
                        Err(_) => Some(Event::Refused),
                    };
                    if let Some(event) = event {
                        turn.sim.note(turn.cycle, id, &event);
                    }
                    opened
                }
            };
            match opened {
                Ok(session) => {
                    sessions.insert(id, session);
                    Code::Ok
                }
                Err(code) => code,
            }
        })
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

/// The functions of `Local` that belong here.
pub fn call(lua: &Lua, host: &Host, call: LocalCall<'_, LuaArg>) -> mlua::Result<MultiValue> {
    // Every call beats, so a task polling Rx in a loop is alive for the watchdog.
    host.beat();
    let mut results = MultiValue::new();
    let status = match call {
        LocalCall::EthOpenAsServer { SessionID: id, Port: port_number, SByte: start, EByte: end } => {
            let (Some(port), Some(framing)) = (port(port_number), framing(&start, &end)) else {
                return Ok(MultiValue::from_vec(vec![Value::Integer(code(Code::BadArgument))]));
            };
            open(host, id, |replaying| {
                if replaying {
                    return Ok(Session::new(None, None, framing));
                }
                let address = SocketAddr::new(host.freeport_bind, port);
                let listener = TcpListener::bind(address).map_err(|_| Code::OpenFailed)?;
                listener.set_nonblocking(true).map_err(|_| Code::OpenFailed)?;
                Ok(Session::new(Some(listener), None, framing))
            })
        }
        LocalCall::EthOpenAsClient { SessionID: id, IPAddr: ip, Port: port_number, SByte: start, EByte: end } => {
            let ip = std::str::from_utf8(&ip).ok().and_then(|s| s.parse::<IpAddr>().ok());
            let (Some(ip), Some(port), Some(framing)) = (ip, port(port_number), framing(&start, &end)) else {
                return Ok(MultiValue::from_vec(vec![Value::Integer(code(Code::BadArgument))]));
            };
            open(host, id, |replaying| {
                let mut session = Session::new(None, None, framing);
                // On the simulation clock the program sees the peer at once.
                session.connected = true;
                if !replaying {
                    let stream = TcpStream::connect_timeout(&SocketAddr::new(ip, port), CONNECT_TIMEOUT)
                        .map_err(|_| Code::OpenFailed)?;
                    stream.set_nonblocking(true).map_err(|_| Code::OpenFailed)?;
                    session.peer = Some(stream);
                }
                Ok(session)
            })
        }
        LocalCall::EthTx { SessionID: id, Msg: msg } => {
            let msg = msg.value;
            let status = match message_bytes(&msg) {
                None => Code::BadArgument,
                Some(bytes) if bytes.len() > MAX_DATA => Code::TooLong,
                Some(bytes) => with_session(host, id, |s, turn| s.send(&bytes, turn)).unwrap_or_else(|c| c),
            };
            results.push_back(msg);
            status
        }
        LocalCall::EthRx { SessionID: id } => {
            let frame = with_session(host, id, Session::next_frame);
            let (status, data) = frame.unwrap_or_else(|c| (c, Vec::new()));
            results.push_back(Value::String(lua.create_string(&data)?));
            results.push_back(Value::Integer(data.len() as i64));
            status
        }
        LocalCall::EthClose { SessionID: id } => close(id),
        LocalCall::EthCloseAll {} => {
            for id in SESSIONS.with_borrow(|s| s.keys().copied().collect::<Vec<_>>()) {
                close(id);
            }
            Code::Ok
        }
        LocalCall::EthBuffClear { SessionID: id } => with_session(host, id, |s, turn| {
            s.poll(turn);
            s.received.clear();
            Code::Ok
        })
        .unwrap_or_else(|c| c),
        LocalCall::EthGetSessions {} => {
            let ids: Vec<i64> = SESSIONS.with_borrow(|s| s.keys().copied().collect());
            results.push_back(Value::Table(lua.create_sequence_from(ids)?));
            Code::Ok
        }
        LocalCall::EthConnectCheck { SessionID: id } => with_session(host, id, |s, turn| {
            let sim = turn.is_some();
            s.poll(turn);
            if s.has_peer(sim) { Code::Ok } else { Code::NotConnected }
        })
        .unwrap_or_else(|c| c),
        other => unreachable!("{:?} is not a FreePort function", other.func()),
    };
    results.push_front(Value::Integer(code(status)));
    Ok(results)
}

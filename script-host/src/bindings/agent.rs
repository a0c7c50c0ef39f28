//! HMPL 22.2.1/22.2.2: the User ASCII server. `START_ASCII_AGENT(parser)` claims the one
//! agent of the controller (a word in shared memory; a dead owner gives way) and listens
//! on the User ASCII address in this process. Each line a client sends goes to
//! `parser(command)`, whose string goes back as a line. The task's own thread serves the
//! clients, non-blocking: while the program waits (`serve` from Sleep, Till, DELAY) and,
//! once it has returned, until the task is stopped (`serve_forever`). Broadcasts of any
//! task come through a ring in shared memory.

use std::cell::RefCell;
use std::io::{ErrorKind, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::os::fd::AsRawFd;
use std::time::{Duration, Instant};

use api::{LocalCall, SystemError};
use mlua::{Function, IntoLuaMulti, Lua, MultiValue, Value};
use schema::shared::BROADCAST_BYTES;
use schema::{Snapshot, TaskState};

use super::{Host, LuaArg, error_here, system_code};

/// The address the agent listens on unless the controller says otherwise (HMPL 22.1).
pub const DEFAULT_ADDRESS: &str = "127.0.0.1:4000";
/// The longest line a client may send, without its newline (HMPL 3.1's string length).
const MAX_LINE: usize = 512;
/// Clients served at once; the next one gets an error line and is closed.
const MAX_CLIENTS: usize = 32;
/// A client that sends no whole line for this long gets an error line and is closed.
const IDLE: Duration = Duration::from_secs(60);
/// The longest answer sent, without its line end: HMPL 3.1's string length, as the
/// manual's `char *response`; a longer one is cut there and ends with the cut marker.
const MAX_ANSWER: usize = 512;
/// A client that does not take its answers keeps at most this much; then it is closed.
const MAX_BACKLOG: usize = 64 * 1024;
/// How often a waiting program looks at its clients.
pub const SERVE_PERIOD: Duration = Duration::from_millis(5);
/// The Lua registry key of the parser.
const PARSER: &str = "luamotion.ascii_agent";

struct Client {
    stream: TcpStream,
    line: Vec<u8>,
    overlong: bool,
    out: Vec<u8>,
    last_line: Instant,
    /// The peer has closed or its socket failed: nothing more is sent.
    gone: bool,
}

struct Agent {
    listener: TcpListener,
    clients: Vec<Client>,
    /// The next broadcast to send.
    cursor: u64,
    served_at: Instant,
}

thread_local! {
    /// The task's agent; the Lua state runs on one thread. Taken out while it serves, so
    /// that a parser that waits does not serve from inside itself.
    static AGENT: RefCell<Option<Agent>> = const { RefCell::new(None) };
    /// Whether this process ever started an agent (it keeps serving after `main`).
    static STARTED: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// The functions of `Local` that belong here.
pub fn call(lua: &Lua, host: &Host, call: LocalCall<'_, LuaArg>) -> mlua::Result<MultiValue> {
    host.beat();
    match call {
        LocalCall::START_ASCII_AGENT { parser } => {
            let Value::Function(parser) = parser.value else { unreachable!("the source checked it") };
            let pid = std::process::id();
            let claimed = {
                let mut endpoint = host.endpoint.borrow_mut();
                let snapshot = endpoint.snapshot();
                let stale = |task: u8, owner: u32| !runs(snapshot, task, owner);
                host.shared.claim_ascii_agent(host.task(), pid, stale)
            };
            if claimed.is_err() {
                return system_code(SystemError::HmplAsciiAgentRunning).into_lua_multi(lua);
            }
            lua.set_named_registry_value(PARSER, parser)?;
            if STARTED.get() {
                return 0.into_lua_multi(lua);
            }
            let listener = TcpListener::bind(&host.user_ascii).and_then(|l| l.set_nonblocking(true).map(|()| l));
            let listener = listener.map_err(|e| {
                // Not serving, so not the agent: another task may try.
                host.shared.release_ascii_agent(host.task(), pid);
                error_here(lua, format!("START_ASCII_AGENT: cannot listen on {}: {e}", host.user_ascii))
            })?;
            let address = listener.local_addr().map_err(mlua::Error::external)?;
            // Said once, so that whoever connects knows where (the port may be a free one).
            super::write_output(&[format!("User ASCII on {address}").as_bytes()]);
            let cursor = host.shared.broadcast_cursor();
            AGENT.set(Some(Agent { listener, clients: Vec::new(), cursor, served_at: Instant::now() }));
            STARTED.set(true);
            0.into_lua_multi(lua)
        }
        LocalCall::ASCII_ServerBroadcast { message: bytes, length } => {
            let length = match length {
                None => bytes.len(),
                Some(n) => {
                    usize::try_from(n).map_err(|_| error_here(lua, format!("ASCII_ServerBroadcast: length {n} < 0")))?
                }
            };
            let message = &bytes[..length.min(bytes.len())];
            if message.len() > BROADCAST_BYTES {
                return system_code(SystemError::HmplStrTooLong).into_lua_multi(lua);
            }
            let agent_runs = host
                .shared
                .ascii_agent()
                .is_some_and(|(task, pid)| runs(host.endpoint.borrow_mut().snapshot(), task, pid));
            if !agent_runs {
                return system_code(SystemError::HmplClientNotConnected).into_lua_multi(lua);
            }
            host.shared.broadcast(message);
            0.into_lua_multi(lua)
        }
        other => unreachable!("not an agent function: {:?}", other.func()),
    }
}

/// Whether an agent claimed by `task`'s process `pid` still runs: its task is starting or
/// running with that process (a stopped task's or a restarted one's claim is stale).
fn runs(snapshot: &Snapshot, task: u8, pid: u32) -> bool {
    let Some(t) = snapshot.tasks.get(task as usize) else { return false };
    !TaskState::from(t.state).is_stopped() && t.pid == pid && ipc::process_alive(pid)
}

/// Whether this task runs the agent (and is not serving it right now).
pub fn active() -> bool {
    AGENT.with_borrow(Option::is_some)
}

/// Serves the agent's clients if this task runs one and it is time (a waiting program
/// calls this between its waits).
pub fn serve(lua: &Lua, host: &Host) {
    let Some(mut agent) = AGENT.take() else { return };
    if agent.served_at.elapsed() >= SERVE_PERIOD {
        agent.served_at = Instant::now();
        agent.serve(lua, host);
    }
    AGENT.set(Some(agent));
}

/// Whether the program started the agent: it is served between the cycles of a wait.
pub fn listening() -> bool {
    STARTED.get()
}

/// After the program has returned: serves the agent, if it started one, until the task is
/// stopped (its process is killed) or the controller is gone. It waits on its sockets, so a
/// line is answered as soon as it comes; broadcasts at least every `SERVE_PERIOD`.
pub fn serve_forever(lua: &Lua, host: &Host) -> mlua::Result<()> {
    if !STARTED.get() {
        return Ok(());
    }
    loop {
        host.beat();
        host.endpoint.borrow().check_controller().map_err(mlua::Error::external)?;
        let Some(mut agent) = AGENT.take() else { return Ok(()) };
        agent.serve(lua, host);
        agent.wait(SERVE_PERIOD);
        AGENT.set(Some(agent));
    }
}

impl Agent {
    /// Waits at most `timeout` for a client to connect, send, or take what it is owed.
    fn wait(&self, timeout: Duration) {
        let listener = libc::pollfd { fd: self.listener.as_raw_fd(), events: libc::POLLIN, revents: 0 };
        let mut fds: Vec<libc::pollfd> = std::iter::once(listener)
            .chain(self.clients.iter().map(|c| libc::pollfd {
                fd: c.stream.as_raw_fd(),
                events: libc::POLLIN | if c.out.is_empty() { 0 } else { libc::POLLOUT },
                revents: 0,
            }))
            .collect();
        // SAFETY: `fds` is a valid array of `fds.len()` pollfd structs for the call's duration.
        unsafe { libc::poll(fds.as_mut_ptr(), fds.len() as libc::nfds_t, timeout.as_millis() as libc::c_int) };
    }

    fn serve(&mut self, lua: &Lua, host: &Host) {
        self.accept();
        let mut lines = Vec::new();
        for (i, client) in self.clients.iter_mut().enumerate() {
            client.receive(|line| lines.push((i, line)));
        }
        for (i, line) in lines {
            let answer = answer(lua, &line);
            let out = &mut self.clients[i].out;
            out.extend_from_slice(answer.as_bytes());
            out.extend_from_slice(b"\r\n");
        }
        let clients = &mut self.clients;
        self.cursor = host.shared.broadcasts_since(self.cursor, |message| {
            for client in clients.iter_mut() {
                client.out.extend_from_slice(message);
                client.out.extend_from_slice(b"\r\n");
            }
        });
        self.clients.retain_mut(|client| client.flush(IDLE));
    }

    fn accept(&mut self) {
        loop {
            match self.listener.accept() {
                Ok((mut stream, _)) if self.clients.len() >= MAX_CLIENTS => {
                    let line = format!("ERROR too many connections ({MAX_CLIENTS} open)\r\n");
                    let _ = stream.write(line.as_bytes());
                }
                Ok((stream, _)) => {
                    if stream.set_nonblocking(true).is_ok() {
                        self.clients.push(Client::new(stream));
                    }
                }
                // WouldBlock: nobody waits; other errors (out of descriptors): next time.
                Err(_) => return,
            }
        }
    }
}

impl Client {
    fn new(stream: TcpStream) -> Self {
        Client { stream, line: Vec::new(), overlong: false, out: Vec::new(), last_line: Instant::now(), gone: false }
    }

    /// Reads what has come and hands over each whole line (or the error that answers it).
    fn receive(&mut self, mut line: impl FnMut(Result<Vec<u8>, String>)) {
        let mut chunk = [0u8; 1024];
        loop {
            match self.stream.read(&mut chunk) {
                Ok(0) => {
                    // A peer that vanished mid-line leaves nothing to answer.
                    self.out.clear();
                    self.gone = true;
                    return;
                }
                Ok(n) => {
                    for &b in &chunk[..n] {
                        if b != b'\n' {
                            if self.line.len() < MAX_LINE {
                                self.line.push(b);
                            } else if !std::mem::replace(&mut self.overlong, true) {
                                // Answered at once: a client that never sends its newline
                                // learns why nothing else comes.
                                line(Err(format!("ERROR line longer than {MAX_LINE} bytes")));
                            }
                            continue;
                        }
                        self.last_line = Instant::now();
                        let text = std::mem::take(&mut self.line);
                        if !std::mem::take(&mut self.overlong) {
                            line(checked(text));
                        }
                    }
                }
                Err(e) if e.kind() == ErrorKind::WouldBlock => return,
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(_) => {
                    self.gone = true;
                    return;
                }
            }
        }
    }

    /// Writes what it can; false when the client is to be closed (gone, idle, or not
    /// taking its answers). A client with no whole line for `idle` is told so first.
    fn flush(&mut self, idle: Duration) -> bool {
        if self.gone {
            return false;
        }
        let timed_out = self.last_line.elapsed() >= idle;
        if timed_out {
            let line = format!("ERROR no whole line within {} s, closing\r\n", idle.as_secs_f64());
            self.out.extend_from_slice(line.as_bytes());
        }
        while !self.out.is_empty() {
            match self.stream.write(&self.out) {
                Ok(0) => return false,
                Ok(n) => drop(self.out.drain(..n)),
                Err(e) if e.kind() == ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(_) => return false,
            }
        }
        self.out.len() <= MAX_BACKLOG && !timed_out
    }
}

/// A line without its `\r`, if it is text: binary garbage is answered with an error
/// rather than handed to the parser.
fn checked(mut line: Vec<u8>) -> Result<Vec<u8>, String> {
    if line.last() == Some(&b'\r') {
        line.pop();
    }
    match line.iter().position(|&b| !(b == b'\t' || (0x20..0x7F).contains(&b))) {
        Some(i) => Err(format!("ERROR not text: byte 0x{:02X} at column {}", line[i], i + 1)),
        None => Ok(line),
    }
}

/// The parser's answer to one line: its string (a number as its text, nil as an empty
/// line), or an error line; a parser that fails does not end the agent.
fn answer(lua: &Lua, line: &Result<Vec<u8>, String>) -> String {
    let line = match line {
        Ok(line) => line,
        Err(refusal) => return refusal.clone(),
    };
    let result = lua.named_registry_value::<Function>(PARSER).and_then(|parser| {
        let command = lua.create_string(line)?;
        parser.call::<Value>(command)
    });
    match result {
        Ok(Value::String(s)) => one_line(&s.as_bytes()),
        Ok(Value::Nil) => String::new(),
        Ok(Value::Integer(n)) => n.to_string(),
        Ok(Value::Number(n)) => n.to_string(),
        Ok(other) => format!("ERROR the parser returned a {}, not a string", other.type_name()),
        Err(e) => error_line(&e),
    }
}

/// A parser's error as one short line: its message without the traceback.
fn error_line(error: &mlua::Error) -> String {
    let message = crate::sandbox::root_cause(error).to_string();
    one_line(format!("ERROR {}", message.lines().next().unwrap_or_default()).as_bytes())
}

/// A response as one line of at most `MAX_ANSWER` bytes: its line breaks become spaces, a
/// longer one is cut with the marker that says how much.
fn one_line(text: &[u8]) -> String {
    let text = text.strip_suffix(b"\n").unwrap_or(text);
    let text = text.strip_suffix(b"\r").unwrap_or(text);
    let kept = ipc::output::char_boundary(text, MAX_ANSWER);
    let mut line = String::from_utf8_lossy(&text[..kept]).replace(['\r', '\n'], " ");
    if kept < text.len() {
        line.push_str(&ipc::output::cut_marker((text.len() - kept) as u64));
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 36.11: an answer is one line of at most `MAX_ANSWER` bytes, cut with a marker.
    #[test]
    fn answers_are_one_bounded_line() {
        assert_eq!(one_line(b"two\r\nlines\n"), "two  lines");
        let long = one_line(&vec![b'x'; 1 << 20]);
        assert_eq!(long, format!("{}{}", "x".repeat(MAX_ANSWER), ipc::output::cut_marker((1 << 20) - 512)));
        assert_eq!(one_line("é".repeat(300).as_bytes()).split(' ').next().unwrap().len(), 512, "whole characters");
    }

    /// A parser's failure is one short line, not its traceback.
    #[test]
    fn a_parser_error_is_one_short_line() {
        let lua = Lua::new();
        let parser: Function = lua.load("return function(cmd) error('no such command: ' .. cmd) end").eval().unwrap();
        lua.set_named_registry_value(PARSER, parser).unwrap();
        let answer = answer(&lua, &Ok(b"FOO".to_vec()));
        assert!(answer.starts_with("ERROR ") && answer.ends_with("no such command: FOO"), "{answer}");
        assert!(!answer.contains("traceback"), "{answer}");
    }

    /// A client that sends half a line and stalls gets an error line when its time is up,
    /// and is closed; one that sends whole lines is not.
    #[test]
    fn a_stalled_client_is_told_and_closed() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let mut peer = TcpStream::connect(listener.local_addr().unwrap()).unwrap();
        let (stream, _) = listener.accept().unwrap();
        stream.set_nonblocking(true).unwrap();
        let mut client = Client::new(stream);
        peer.write_all(b"half a li").unwrap();
        let idle = Duration::from_millis(200);
        let deadline = Instant::now() + Duration::from_secs(10);
        let mut lines = Vec::new();
        while client.flush(idle) {
            assert!(Instant::now() < deadline, "never closed");
            client.receive(|line| lines.push(line));
            std::thread::sleep(Duration::from_millis(10));
        }
        assert!(lines.is_empty(), "half a line is no line");
        assert!(client.last_line.elapsed() >= idle);
        drop(client);
        let mut told = String::new();
        peer.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        peer.read_to_string(&mut told).unwrap();
        assert_eq!(told, "ERROR no whole line within 0.2 s, closing\r\n");
    }
}

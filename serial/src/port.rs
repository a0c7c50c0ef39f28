//! Serial port 1's thread ("serial1"): it owns the pseudo-terminal and the scripts' socket
//! and waits on both with poll(2). In a FreePort protocol it cuts what the peer sends
//! into frames for `FreePort.Serial.Rx` and sends `Tx`'s frames; in Modbus RTU or ASCII it
//! answers requests through the handler the controller gives it.

use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::os::fd::AsRawFd;
use std::os::unix::net::{UnixListener, UnixStream};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::ascii;
use crate::format;
use crate::framing::{Deframer, Framing, Received};
use crate::link::{self, Code, MAX_DATA, Op};
use crate::protocol::{Kind, Protocol};
use crate::pty::{LineSettings, Pty};
use crate::rtu::{self, Assembler};

/// Answers a Modbus request PDU with a response PDU (an exception included).
pub type Handler = Box<dyn FnMut(&[u8]) -> Vec<u8> + Send>;

/// Serial port 1 as the machine file sets it.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Parameter 5-1.
    pub protocol: Protocol,
    /// Parameter 5-4, in baud.
    pub baud: u32,
    /// What is sent comes back, as with 485+ and 485- shorted (the manual's self-test).
    pub loopback: bool,
    /// The Modbus station (parameter 0-0); requests to 0 are broadcasts, done without reply.
    pub station: u8,
    /// A symlink to the pseudo-terminal, made at start (replacing one there) and removed at the end.
    pub link: Option<PathBuf>,
}

/// Told each chunk the peer sent and the cycle it takes effect at.
pub type Recorder = Box<dyn FnMut(u64, &[u8]) + Send>;

/// On the simulation clock (`luamotion run --clock sim`): what the peer sends in a FreePort
/// protocol takes effect at a cycle boundary. Each chunk is stamped with the cycle it takes
/// effect at, and `Rx` after cycle c frames only chunks stamped <= c, so the cycles at which
/// a program sees the bytes are those of the stamps, and a replay of the stamps is the same
/// run (docs/decisions.md, "Simulation clock").
pub struct SimLine {
    /// The cycle a chunk arriving now takes effect at; `Rx` is served after cycle `landing - 1`.
    pub landing: Arc<AtomicU64>,
    /// Told every chunk received and its stamp (`--record`).
    pub record: Recorder,
    /// A replay's chunks and their stamps, in order: the peer's bytes are then dropped.
    pub replay: Option<Vec<(u64, Vec<u8>)>>,
}

/// Why serial port 1 cannot be opened (the controller then runs without it).
#[derive(Debug, thiserror::Error)]
pub enum SerialError {
    /// posix_openpt(3) or the line settings failed.
    #[error("cannot open a pseudo-terminal: {0}")]
    Pty(io::Error),
    /// The symlink could not be made (a file that is not a symlink is in the way).
    #[error("cannot make the link {0}: {1}")]
    Link(PathBuf, io::Error),
    /// The scripts' socket is taken or cannot be bound.
    #[error("cannot listen for scripts on {0}: {1} (is another controller using this namespace?)")]
    Socket(String, io::Error),
    /// The thread "serial1" could not be spawned.
    #[error("cannot start the serial thread: {0}")]
    Thread(io::Error),
}

/// Frames waiting for `Rx`; more are refused and reported (`Code::Overrun`).
const MAX_FRAMES: usize = 64;
/// Scripts connected at once: one per task and a few more.
const MAX_CLIENTS: usize = 72;
/// DXMC 8.2: a Modbus RTU frame ends after more than 10 ms of silence.
const SILENCE: Duration = Duration::from_millis(10);
/// How often the thread looks at its stop flag when nothing happens.
const IDLE: Duration = Duration::from_millis(50);

/// A running serial port 1; dropping it stops the thread and removes the link.
pub struct Port {
    /// The pseudo-terminal's slave, `/dev/pts/N`.
    pub path: PathBuf,
    /// The symlink to `path` from the settings, removed when the port is dropped.
    pub link: Option<PathBuf>,
    handler: Arc<Mutex<Option<Handler>>>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Port {
    /// Opens the pseudo-terminal, its link and the scripts' socket of namespace `ns`, and
    /// starts the thread.
    pub fn open(ns: &str, settings: Settings) -> Result<Port, SerialError> {
        Port::open_with(ns, settings, None)
    }

    /// `open`, on the simulation clock with `sim`.
    pub fn open_with(ns: &str, settings: Settings, sim: Option<SimLine>) -> Result<Port, SerialError> {
        let pty = Pty::open(LineSettings { frame: settings.protocol.frame, baud: settings.baud })
            .map_err(SerialError::Pty)?;
        let path = pty.path().to_path_buf();
        let name = link::socket_name(ns);
        let listener = link::socket_addr(ns)
            .and_then(|addr| UnixListener::bind_addr(&addr))
            .and_then(|l| l.set_nonblocking(true).map(|()| l))
            .map_err(|e| SerialError::Socket(name, e))?;
        if let Some(link) = &settings.link {
            make_link(&path, link).map_err(|e| SerialError::Link(link.clone(), e))?;
        }
        let handler = Arc::new(Mutex::new(None));
        let stop = Arc::new(AtomicBool::new(false));
        let link = settings.link.clone();
        let mut line = Line::new(pty, settings, handler.clone());
        if let Some(sim) = sim {
            line.pending = sim.replay.clone().unwrap_or_default().into();
            line.sim = Some(sim);
        }
        let flag = stop.clone();
        let thread = std::thread::Builder::new()
            .name("serial1".into())
            .spawn(move || line.run(&listener, &flag))
            .map_err(SerialError::Thread)?;
        Ok(Port { path, link, handler, stop, thread: Some(thread) })
    }

    /// Who answers Modbus requests from now on (`luamotion serve`: the DRL console).
    pub fn serve_modbus(&self, handler: Handler) {
        *self.handler.lock().unwrap_or_else(|e| e.into_inner()) = Some(handler);
    }
}

impl Drop for Port {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
        // Only our own link: another controller may have taken the path since.
        if let Some(link) = &self.link
            && std::fs::read_link(link).is_ok_and(|target| target == self.path)
        {
            let _ = std::fs::remove_file(link);
        }
    }
}

/// Points `link` at `target`, replacing a symlink (a stale one of an earlier run) but
/// nothing else.
fn make_link(target: &Path, link: &Path) -> io::Result<()> {
    match std::fs::symlink_metadata(link) {
        Ok(meta) if meta.file_type().is_symlink() => std::fs::remove_file(link)?,
        Ok(_) => return Err(io::Error::new(io::ErrorKind::AlreadyExists, "a file that is not a symlink is there")),
        Err(_) => {}
    }
    std::os::unix::fs::symlink(target, link)
}

/// A script's connection and the bytes of its unfinished request.
struct Conn {
    stream: UnixStream,
    buf: Vec<u8>,
}

/// What the thread owns.
struct Line {
    pty: Pty,
    protocol: Protocol,
    baud: u32,
    loopback: bool,
    station: u8,
    deframer: Deframer,
    rtu: Assembler,
    ascii: ascii::Assembler,
    /// The line as the pseudo-terminal keeps the port's settings: a Linux pseudo-terminal
    /// always says 8 bits, and shows parity only through PARODD and INPCK (`pty.rs`).
    expected: LineSettings,
    /// Bytes dropped for a wrong line setting since the peer's line was last right.
    dropped: u64,
    /// When the last byte from the peer came (RTU's silence).
    last_byte: Instant,
    /// Bytes were dropped for a wrong line setting since the last `Rx`.
    line_error: bool,
    /// The last wrong setting logged, so each is logged once.
    logged_setting: Option<LineSettings>,
    handler: Arc<Mutex<Option<Handler>>>,
    unserved_logged: bool,
    sim: Option<SimLine>,
    /// A replay dropped the peer's bytes (said once).
    peer_dropped: bool,
    /// On the simulation clock: chunks and the cycle each takes effect at.
    pending: VecDeque<(u64, Vec<u8>)>,
}

impl Line {
    fn new(pty: Pty, settings: Settings, handler: Arc<Mutex<Option<Handler>>>) -> Self {
        let mut line = Line {
            pty,
            protocol: settings.protocol,
            baud: settings.baud,
            loopback: settings.loopback,
            station: settings.station,
            // Until a script's Init: no delimiters, every read is a frame.
            deframer: Deframer::new(Framing::default(), MAX_DATA, MAX_FRAMES),
            rtu: Assembler::default(),
            ascii: ascii::Assembler::default(),
            expected: LineSettings { frame: settings.protocol.frame, baud: settings.baud },
            dropped: 0,
            last_byte: Instant::now(),
            line_error: false,
            logged_setting: None,
            handler,
            unserved_logged: false,
            sim: None,
            peer_dropped: false,
            pending: VecDeque::new(),
        };
        line.expect_line();
        line
    }

    /// Reads back what the pseudo-terminal made of the port's settings.
    fn expect_line(&mut self) {
        self.expected = self.pty.line().unwrap_or(LineSettings { frame: self.protocol.frame, baud: self.baud });
    }

    fn run(&mut self, listener: &UnixListener, stop: &AtomicBool) {
        let mut conns: Vec<Conn> = Vec::new();
        while !stop.load(Ordering::Relaxed) {
            let mut fds = vec![poll_fd(self.pty.master_fd()), poll_fd(listener.as_raw_fd())];
            fds.extend(conns.iter().map(|c| poll_fd(c.stream.as_raw_fd())));
            let timeout = if self.rtu.is_empty() { IDLE } else { SILENCE.saturating_sub(self.last_byte.elapsed()) };
            // SAFETY: a valid array of pollfd.
            let ready = unsafe { libc::poll(fds.as_mut_ptr(), fds.len() as libc::nfds_t, timeout.as_millis() as i32) };
            if ready < 0 {
                if io::Error::last_os_error().kind() != io::ErrorKind::Interrupted {
                    tracing::error!("serial port 1: poll failed: {}", io::Error::last_os_error());
                    return;
                }
                continue;
            }
            if fds[0].revents != 0 {
                self.read_peer();
            }
            if !self.rtu.is_empty() && self.last_byte.elapsed() >= SILENCE {
                for request in self.rtu.silence() {
                    self.serve(request);
                }
            }
            let mut keep = Vec::with_capacity(conns.len());
            for (mut conn, fd) in conns.into_iter().zip(&fds[2..]) {
                if fd.revents == 0 || self.serve_script(&mut conn).is_ok() {
                    keep.push(conn);
                }
            }
            conns = keep;
            // After the connections polled above: `fds` has none of these.
            if fds[1].revents != 0 {
                while let Ok((stream, _)) = listener.accept() {
                    if conns.len() < MAX_CLIENTS && stream.set_nonblocking(true).is_ok() {
                        conns.push(Conn { stream, buf: Vec::new() });
                    }
                }
            }
        }
    }

    fn read_peer(&mut self) {
        let mut buf = [0u8; 4096];
        loop {
            match self.pty.read(&mut buf) {
                Ok(n @ 1..) => self.received(&buf[..n]),
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                _ => return,
            }
        }
    }

    /// Bytes from the peer: the line's settings must match the port's (DXMC 8.2), as a
    /// UART's must: on another baud rate, stop bits or parity it sees framing and parity
    /// errors, not data, and answers nothing.
    fn received(&mut self, bytes: &[u8]) {
        let expected = self.expected;
        match self.pty.line() {
            Ok(line) if !expected.admits(&line) => {
                self.line_error = true;
                self.dropped += bytes.len() as u64;
                if self.logged_setting != Some(line) {
                    self.logged_setting = Some(line);
                    tracing::warn!(
                        "serial port 1: the peer's line reads {line}, the port's is {} at {} baud (protocol {:#04x}): \
                         received bytes dropped",
                        self.protocol.frame,
                        self.baud,
                        self.protocol.code
                    );
                }
                return;
            }
            Ok(_) if self.dropped > 0 => {
                tracing::warn!(
                    "serial port 1: the peer's line is right again; {} byte(s) were dropped on a wrong setting",
                    std::mem::take(&mut self.dropped)
                );
                self.logged_setting = None;
            }
            _ => {}
        }
        match &mut self.sim {
            Some(sim) if self.protocol.kind == Kind::FreePort => {
                if sim.replay.is_some() {
                    if !std::mem::replace(&mut self.peer_dropped, true) {
                        tracing::warn!("serial port 1: a replay feeds the recorded bytes; the peer's are dropped");
                    }
                    return;
                }
                let at = sim.landing.load(Ordering::Acquire);
                (sim.record)(at, bytes);
                self.pending.push_back((at, bytes.to_vec()));
            }
            _ => self.take(bytes),
        }
    }

    /// On the simulation clock, before a script's request: the chunks whose cycle has come.
    fn due(&mut self) {
        let Some(sim) = &self.sim else { return };
        let served_after = sim.landing.load(Ordering::Acquire).saturating_sub(1);
        while let Some((at, _)) = self.pending.front()
            && *at <= served_after
        {
            let (_, bytes) = self.pending.pop_front().expect("a front");
            self.take(&bytes);
        }
    }

    fn take(&mut self, bytes: &[u8]) {
        match self.protocol.kind {
            Kind::FreePort => self.deframer.receive(bytes),
            Kind::ModbusRtu => {
                self.last_byte = Instant::now();
                for request in self.rtu.push(bytes) {
                    self.serve(request);
                }
            }
            Kind::ModbusAscii => {
                for request in self.ascii.push(bytes) {
                    self.serve(request);
                }
            }
        }
    }

    fn unserved(&mut self, why: &str) {
        if !self.unserved_logged {
            self.unserved_logged = true;
            tracing::warn!("serial port 1: Modbus requests are not answered: {why}");
        }
    }

    /// A Modbus request: answered when it is for this station, done without an
    /// answer when broadcast (writes only), ignored otherwise.
    fn serve(&mut self, request: rtu::Request) {
        let broadcast = request.address == 0;
        if request.address != self.station && !(broadcast && matches!(request.pdu[0], 0x06 | 0x10)) {
            return;
        }
        let response = self.handler.lock().unwrap_or_else(|e| e.into_inner()).as_mut().map(|h| h(&request.pdu));
        let Some(response) = response else {
            return self.unserved("`luamotion run` has no register console; `luamotion serve` has");
        };
        if !broadcast {
            let frame = match self.protocol.kind {
                Kind::ModbusAscii => ascii::frame(self.station, &response),
                _ => rtu::frame(self.station, &response),
            };
            self.pty.write(&frame);
        }
    }

    /// Reads a script's requests and answers each; an error drops the connection.
    fn serve_script(&mut self, conn: &mut Conn) -> io::Result<()> {
        let mut chunk = [0u8; 4096];
        loop {
            match conn.stream.read(&mut chunk) {
                Ok(0) => return Err(io::ErrorKind::UnexpectedEof.into()),
                Ok(n) => conn.buf.extend_from_slice(&chunk[..n]),
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
        while let Some((op, payload, len)) = link::split(&conn.buf) {
            let op = Op::decode(op, payload).ok_or(io::ErrorKind::InvalidData)?;
            let (code, payload) = self.request(op);
            conn.buf.drain(..len);
            // A reply is small and its reader waits for it: the socket takes it whole.
            conn.stream.set_nonblocking(false)?;
            conn.stream.set_write_timeout(Some(IDLE))?;
            conn.stream.write_all(&link::message(code as u8, &payload))?;
            conn.stream.set_nonblocking(true)?;
        }
        Ok(())
    }

    fn request(&mut self, op: Op) -> (Code, Vec<u8>) {
        self.due();
        if !matches!(op, Op::Init { .. }) && self.protocol.kind != Kind::FreePort {
            return (Code::NotFreePort, Vec::new());
        }
        match op {
            Op::Init { start, end, protocol } => {
                let protocol = match protocol.map(i64::from).map(Protocol::from_code) {
                    None => self.protocol.freeport(),
                    Some(Some(p)) if p.kind == Kind::FreePort => p,
                    Some(_) => return (Code::BadArgument, Vec::new()),
                };
                if protocol.frame != self.protocol.frame
                    && let Err(e) = self.pty.configure(LineSettings { frame: protocol.frame, baud: self.baud })
                {
                    tracing::warn!("serial port 1: cannot set the line to {}: {e}", protocol.frame);
                }
                self.protocol = protocol;
                self.expect_line();
                self.deframer = Deframer::new(Framing { start, end: end.bytes() }, MAX_DATA, MAX_FRAMES);
                self.rtu = Assembler::default();
                self.ascii = ascii::Assembler::default();
                self.line_error = false;
                (Code::Ok, format::word(start, end).to_le_bytes().to_vec())
            }
            Op::Tx(data) if data.len() > MAX_DATA => (Code::TooLong, Vec::new()),
            Op::Tx(data) => {
                let bytes = self.deframer.framing().frame(&data);
                self.pty.write(&bytes);
                if self.loopback {
                    self.take(&bytes);
                }
                (Code::Ok, Vec::new())
            }
            Op::Rx => {
                if std::mem::take(&mut self.line_error) {
                    return (Code::LineError, Vec::new());
                }
                match self.deframer.pop() {
                    Some(Received::Frame(data)) => (Code::Ok, data),
                    Some(Received::TooLong) => (Code::TooLong, Vec::new()),
                    Some(Received::Overrun(n)) => {
                        tracing::debug!("serial port 1: {n} frame(s) refused, the receive queue was full");
                        (Code::Overrun, Vec::new())
                    }
                    None => (Code::Ok, Vec::new()),
                }
            }
        }
    }
}

fn poll_fd(fd: libc::c_int) -> libc::pollfd {
    libc::pollfd { fd, events: libc::POLLIN, revents: 0 }
}

#[cfg(test)]
mod tests {
    use std::fs::OpenOptions;

    use super::*;
    use crate::format::End;
    use crate::link::Client;

    fn port(ns: &str, code: i64, loopback: bool) -> Port {
        let settings =
            Settings { protocol: Protocol::from_code(code).unwrap(), baud: 38400, loopback, station: 1, link: None };
        Port::open(ns, settings).unwrap()
    }

    fn ask(client: &mut Client, op: Op) -> (Code, Vec<u8>) {
        client.request(&op, Duration::from_millis(50), || {}).unwrap()
    }

    fn ns(tag: &str) -> String {
        format!("unit-{}-{tag}", std::process::id())
    }

    #[test]
    fn loopback_brings_back_what_was_sent() {
        let ns = ns("loop");
        let _port = port(&ns, 0x17, true);
        let mut client = Client::connect(&ns).unwrap();
        let init = ask(&mut client, Op::Init { start: Some(b':'), end: End::Byte(b';'), protocol: None });
        assert_eq!(init, (Code::Ok, 0x0011_3B3Au32.to_le_bytes().to_vec()));
        assert_eq!(ask(&mut client, Op::Tx(b"3.1415".to_vec())).0, Code::Ok);
        assert_eq!(ask(&mut client, Op::Rx), (Code::Ok, b"3.1415".to_vec()));
        assert_eq!(ask(&mut client, Op::Rx), (Code::Ok, Vec::new()));
        assert_eq!(ask(&mut client, Op::Tx(vec![b'x'; 257])).0, Code::TooLong);
    }

    /// On the simulation clock the peer's bytes wait for the cycle after the one they
    /// arrived in and are recorded with it; a replay's bytes wait for their cycle, and
    /// the peer's are dropped.
    #[test]
    fn sim_clock_bytes_take_effect_at_their_cycle() {
        let (recording, landing) = (ns("sim"), Arc::new(AtomicU64::new(5)));
        let recorded = Arc::new(Mutex::new(Vec::new()));
        let log = recorded.clone();
        let record = Box::new(move |at: u64, bytes: &[u8]| log.lock().unwrap().push((at, bytes.to_vec())));
        let settings = Settings {
            protocol: Protocol::from_code(0x17).unwrap(),
            baud: 38400,
            loopback: false,
            station: 1,
            link: None,
        };
        let sim = SimLine { landing: landing.clone(), record, replay: None };
        let port = Port::open_with(&recording, settings.clone(), Some(sim)).unwrap();
        let mut client = Client::connect(&recording).unwrap();
        assert_eq!(ask(&mut client, Op::Init { start: None, end: End::Byte(b';'), protocol: None }).0, Code::Ok);
        let mut peer = OpenOptions::new().read(true).write(true).open(&port.path).unwrap();
        peer.write_all(b"A;").unwrap();
        let deadline = Instant::now() + Duration::from_secs(10);
        while recorded.lock().unwrap().is_empty() && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(5));
        }
        assert_eq!(*recorded.lock().unwrap(), [(5, b"A;".to_vec())]);
        // Turns after cycle 4 do not see it; turns after cycle 5 do.
        assert_eq!(ask(&mut client, Op::Rx), (Code::Ok, Vec::new()));
        landing.store(6, Ordering::Release);
        assert_eq!(ask(&mut client, Op::Rx), (Code::Ok, b"A".to_vec()));

        let (replaying, landing) = (ns("sim-replay"), Arc::new(AtomicU64::new(1)));
        let replay = Some(vec![(3, b"B;".to_vec()), (3, b"C;".to_vec())]);
        let sim =
            SimLine { landing: landing.clone(), record: Box::new(|_, _| panic!("a replay records nothing")), replay };
        let port = Port::open_with(&replaying, settings, Some(sim)).unwrap();
        let mut client = Client::connect(&replaying).unwrap();
        assert_eq!(ask(&mut client, Op::Init { start: None, end: End::Byte(b';'), protocol: None }).0, Code::Ok);
        let mut peer = OpenOptions::new().read(true).write(true).open(&port.path).unwrap();
        peer.write_all(b"D;").unwrap();
        // Time for the port to read it (a port that kept it would show it below).
        std::thread::sleep(Duration::from_millis(200));
        landing.store(3, Ordering::Release);
        assert_eq!(ask(&mut client, Op::Rx), (Code::Ok, Vec::new()));
        landing.store(4, Ordering::Release);
        assert_eq!(ask(&mut client, Op::Rx), (Code::Ok, b"B".to_vec()));
        assert_eq!(ask(&mut client, Op::Rx), (Code::Ok, b"C".to_vec()));
        assert_eq!(ask(&mut client, Op::Rx), (Code::Ok, Vec::new()), "the peer's D is dropped");
    }

    #[test]
    fn modbus_ascii_on_a_7_bit_line() {
        let ns = ns("ascii");
        let port = port(&ns, 0x00, false); // 7,N,2 Modbus ASCII
        port.serve_modbus(Box::new(|pdu| vec![pdu[0], 2, 0x12, 0x34]));
        let mut peer = OpenOptions::new().read(true).write(true).open(&port.path).unwrap();
        peer.write_all(b":010300010001FA\r\n").unwrap();
        let expected = ascii::frame(1, &[0x03, 2, 0x12, 0x34]);
        let mut answer = vec![0u8; expected.len()];
        peer.read_exact(&mut answer).unwrap();
        assert_eq!(answer, expected);
    }

    /// Connections accepted together are all served (one task each, polled with the rest).
    #[test]
    fn several_scripts_share_the_port() {
        let ns = ns("many");
        let _port = port(&ns, 0x17, true);
        let mut clients: Vec<Client> = (0..5).map(|_| Client::connect(&ns).unwrap()).collect();
        assert_eq!(ask(&mut clients[4], Op::Init { start: None, end: End::Byte(b';'), protocol: None }).0, Code::Ok);
        for (i, client) in clients.iter_mut().enumerate() {
            assert_eq!(ask(client, Op::Tx(vec![b'0' + i as u8])).0, Code::Ok);
        }
        // One line: each frame is read once, by whichever task asks.
        let got: Vec<_> = clients.iter_mut().rev().map(|c| ask(c, Op::Rx).1).collect();
        assert_eq!(got, [b"0", b"1", b"2", b"3", b"4"]);
    }

    #[test]
    fn the_peer_at_the_pseudo_terminal_is_framed_and_checked() {
        let ns = ns("peer");
        let port = port(&ns, 0x16, false);
        let mut client = Client::connect(&ns).unwrap();
        // The port speaks RTU until a script switches it.
        assert_eq!(ask(&mut client, Op::Rx).0, Code::NotFreePort);
        let init = ask(&mut client, Op::Init { start: None, end: End::CrLf, protocol: Some(0x0C) });
        assert_eq!(init, (Code::Ok, 0x0020_0000u32.to_le_bytes().to_vec()));
        // Raw mode at open: what the peer writes arrives unchanged, and the peer has the
        // line Init set (8,N,2 at 38400), so nothing is a line error.
        let mut peer = OpenOptions::new().read(true).write(true).open(&port.path).unwrap();
        peer.write_all(b"AB12\r\nCD").unwrap();
        peer.write_all(b"34\r\n").unwrap();
        let rx = |client: &mut Client| loop {
            let got = ask(client, Op::Rx);
            if got != (Code::Ok, Vec::new()) {
                return got;
            }
            std::thread::sleep(Duration::from_millis(5));
        };
        assert_eq!(rx(&mut client), (Code::Ok, b"AB12".to_vec()));
        assert_eq!(rx(&mut client), (Code::Ok, b"CD34".to_vec()));
        assert_eq!(ask(&mut client, Op::Tx(b"ok".to_vec())).0, Code::Ok);
        let mut got = [0u8; 4];
        peer.read_exact(&mut got).unwrap();
        assert_eq!(&got, b"ok\r\n");
        // A protocol code that is not FreePort is refused.
        assert_eq!(
            ask(&mut client, Op::Init { start: None, end: End::None, protocol: Some(0x16) }).0,
            Code::BadArgument
        );
    }

    #[test]
    fn rtu_requests_reach_the_handler_and_broadcasts_get_no_answer() {
        let ns = ns("rtu");
        let port = port(&ns, 0x16, false);
        let seen = Arc::new(Mutex::new(Vec::new()));
        let log = seen.clone();
        port.serve_modbus(Box::new(move |pdu| {
            log.lock().unwrap().push(pdu.to_vec());
            vec![pdu[0], 2, 0x12, 0x34]
        }));
        let mut peer = OpenOptions::new().read(true).write(true).open(&port.path).unwrap();
        // A broadcast write, then garbage, then a read for station 1.
        peer.write_all(&rtu::frame(0, &[0x06, 0, 1, 0, 7])).unwrap();
        peer.write_all(&[0xDE, 0xAD]).unwrap();
        peer.write_all(&rtu::frame(1, &[0x03, 0, 1, 0, 1])).unwrap();
        let mut answer = [0u8; 7];
        peer.read_exact(&mut answer).unwrap();
        assert_eq!(answer.to_vec(), rtu::frame(1, &[0x03, 2, 0x12, 0x34]));
        assert_eq!(*seen.lock().unwrap(), [vec![0x06, 0, 1, 0, 7], vec![0x03, 0, 1, 0, 1]]);
    }
}

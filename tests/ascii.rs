//! The ASCII servers of HMPL 22.1: the Native server of `luamotion serve` (one HMPL call a
//! line, carried out as the agent task) driven with `nc` and std::net clients, and the
//! User ASCII agent of `START_ASCII_AGENT` with the manual's two examples, its one-agent
//! rule, broadcasts and the jog example.

mod common;

use std::io::{BufRead, BufReader, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::serve::{Serving, serve};
use common::*;

/// A line client: one line out, one line back.
struct Client {
    reader: BufReader<TcpStream>,
    writer: TcpStream,
}

impl Client {
    fn connect(port: u16) -> Self {
        let stream = TcpStream::connect(("127.0.0.1", port)).expect("connect");
        stream.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
        Client { reader: BufReader::new(stream.try_clone().unwrap()), writer: stream }
    }

    fn send(&mut self, bytes: &[u8]) {
        self.writer.write_all(bytes).expect("send");
    }

    fn read_line(&mut self) -> String {
        let mut line = String::new();
        self.reader.read_line(&mut line).expect("a line back");
        assert!(line.ends_with("\r\n"), "a whole line, got {line:?}");
        line.trim_end().to_string()
    }

    fn ask(&mut self, line: &str) -> String {
        self.send(format!("{line}\n").as_bytes());
        self.read_line()
    }

    /// Asks `line` until the answer satisfies `done` (at most 20 s); the last answer.
    fn ask_until(&mut self, line: &str, mut done: impl FnMut(&str) -> bool) -> String {
        let mut answer = String::new();
        let ok = eventually(Duration::from_secs(20), || {
            answer = self.ask(line);
            done(&answer)
        });
        assert!(ok, "{line}: last answer {answer:?}");
        answer
    }
}

/// A machine file whose tasks run `programs` (task 0, 1, ...) at start.
fn machine(dir: &Path, programs: &[&str], extra: &str) -> PathBuf {
    let mut toml = String::new();
    for (id, source) in programs.iter().enumerate() {
        let path = program(dir, &format!("task{id}.lua"), source);
        toml += &format!("[[tasks]]\nid = {id}\nprogram = {:?}\nautorun = true\n\n", path.display().to_string());
    }
    toml += extra;
    let path = dir.join("machine.toml");
    std::fs::write(&path, toml).unwrap();
    path
}

fn serve_with(ns: &str, dir: &Path, programs: &[&str]) -> Serving {
    let config = machine(dir, programs, "");
    serve(ns, dir, &["--config", config.to_str().unwrap()])
}

/// The port task `task`'s User ASCII agent listens on, as it printed it.
fn user_port(serving: &Serving, task: u8) -> u16 {
    let address = serving
        .await_line(task, "User ASCII on ", Duration::from_secs(20))
        .unwrap_or_else(|| panic!("task {task} starts no agent; output:\n{}", serving.stdout()));
    address.rsplit(':').next().unwrap().trim().parse().expect("port")
}

fn position(answer: &str) -> f64 {
    answer.parse().unwrap_or_else(|_| panic!("a position, got {answer:?}"))
}

/// The issue's session with `nc`: enable, wait, move, read the axis until it is there.
#[test]
fn native_nc_session_enables_moves_and_reads_an_axis() {
    let ns = unique_ns("ascii-nc");
    let dir = tempfile::tempdir().unwrap();
    let serving = serve(&ns, dir.path(), &[]);
    let mut nc = Command::new(debian_tool("nc"))
        .args(["127.0.0.1", &serving.ascii_port.to_string()])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("nc");
    let mut to_nc = nc.stdin.take().unwrap();
    let mut from_nc = BufReader::new(nc.stdout.take().unwrap());
    let mut ask = |line: &str| {
        writeln!(to_nc, "{line}").unwrap();
        let mut answer = String::new();
        from_nc.read_line(&mut answer).unwrap();
        answer.trim_end().to_string()
    };
    assert_eq!(ask("Enable(0)"), "0");
    assert!(eventually(Duration::from_secs(20), || ask("IsEnabled(0)") == "1"), "the axis enables");
    assert_eq!(ask("MoveAbs(0, 10);"), "0");
    assert_eq!(ask("IsMoving(0)"), "1", "moving in the cycle after the command");
    let mut last = String::new();
    assert!(
        eventually(Duration::from_secs(30), || {
            last = ask("GetPosFb(0)");
            (position(&last) - 10.0).abs() < 1e-3 && ask("IsInPos(0)") == "1"
        }),
        "the axis reaches 10, last {last}"
    );
    assert_eq!(ask("GetAxisNum()"), "4");
    let _ = nc.kill();
    let _ = nc.wait();
}

/// Whatever a client sends is answered with a line, and the connection goes on: functions
/// not flagged ASCII, unknown ones, wrong arguments, binary garbage, an 8 KiB line; a peer
/// that vanishes mid-line leaves the server answering the next one.
#[test]
fn native_refuses_with_a_clear_line_and_goes_on() {
    let ns = unique_ns("ascii-bad");
    let dir = tempfile::tempdir().unwrap();
    let serving = serve(&ns, dir.path(), &[]);
    let mut c = Client::connect(serving.ascii_port);
    let rows: [(&[u8], &str); 9] = [
        (b"MovePVT(0, 0, 0, 0, 0)", "ERROR MovePVT is not available over ASCII"),
        (b"Sleep(10)", "ERROR Sleep is not available over ASCII"),
        (b"Teleport(0)", "ERROR unknown function Teleport"),
        (b"MoveAbs(0)", "ERROR MoveAbs: argument 2 (pos) must be a number, not nothing"),
        (b"MoveAbs(0, 1, 2)", "ERROR MoveAbs takes 2 argument(s), got 3"),
        (b"Enable(0.5)", "ERROR Enable: argument 1 (axis_id) must be an integer, not 0.5"),
        (b"\x00\xff\xfe\x01garbage", "ERROR not text: byte 0x00 at column 1"),
        (b"Enable(", "ERROR bad argument at column 8: missing"),
        (b"GetPosFb(7)", "ERROR 0x0000138F eERR_HMPL_ARG_OUT_OF_RANGE (argument out of range)"),
    ];
    for (line, want) in rows {
        c.send(line);
        c.send(b"\n");
        assert_eq!(c.read_line(), want, "{}", String::from_utf8_lossy(line));
    }
    c.send(&vec![b'A'; 8192]);
    c.send(b"\nGetAxisNum()\r\n");
    assert_eq!(c.read_line(), "ERROR line longer than 256 bytes");
    assert_eq!(c.read_line(), "4", "the same connection goes on");
    assert_eq!(c.ask("SetTableValue(7, -2.5)"), "0");
    assert_eq!(c.ask("GetTableValue(7)"), "-2.5", "the user table, shared with the scripts");

    let mut vanishing = TcpStream::connect(("127.0.0.1", serving.ascii_port)).unwrap();
    vanishing.write_all(b"MoveAbs(0, 1").unwrap();
    drop(vanishing);
    let mut next = Client::connect(serving.ascii_port);
    assert_eq!(next.ask("GetAxisNum()"), "4");
    assert_eq!(c.ask("IsMoving(0)"), "0", "the half line moved nothing");
}

/// The Native server's motion goes through its agent task slot: an axis a script task
/// commands in the same cycle refuses it with the command-buffer-busy alarm (0x001F), as
/// for any two tasks, and the server goes on.
#[test]
fn native_commands_are_owned_like_a_tasks() {
    let ns = unique_ns("ascii-own");
    let dir = tempfile::tempdir().unwrap();
    let script = r#"
        Till(IsSystemOper)
        Enable(1)
        Till(function() return IsEnabled(1) end)
        SetTableValue(0, 1)
        local i = 0
        while true do
          i = i + 1
          MoveAbs(1, (i % 2) * 0.5)
        end
    "#;
    let serving = serve_with(&ns, dir.path(), &[script]);
    let mut c = Client::connect(serving.ascii_port);
    c.ask_until("GetTableValue(0)", |a| a == "1");
    let busy = c.ask_until("MoveAbs(1, 5)", |a| a != "0");
    assert!(busy.starts_with("ERROR 0x1001001F alarm: command buffer busy"), "{busy}");
    assert_eq!(c.ask("GetAxisNum()"), "4", "the server goes on");
    assert_eq!(c.ask("IsTaskStop(0)"), "0", "the script runs on: {}", serving.stderr());
}

/// Writes one holding register of `luamotion serve` over Modbus TCP (FC 06).
fn modbus_write(port: u16, address: u16, value: u16) {
    let mut stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    let [a, b] = address.to_be_bytes();
    let [v, w] = value.to_be_bytes();
    let frame = [0, 1, 0, 0, 0, 6, 1, 0x06, a, b, v, w];
    stream.write_all(&frame).unwrap();
    let mut echo = [0u8; 12];
    std::io::Read::read_exact(&mut stream, &mut echo).unwrap();
    assert_eq!(echo, frame, "the write is echoed");
}

/// The Native server's motion follows the controller state as a task's does (DXMC 3.6):
/// refused with the wrong-mode alarm in Edit, accepted again in Run.
#[test]
fn native_motion_follows_the_controller_state() {
    let ns = unique_ns("ascii-state");
    let dir = tempfile::tempdir().unwrap();
    let serving = serve(&ns, dir.path(), &[]);
    let mut c = Client::connect(serving.ascii_port);
    assert_eq!(c.ask("Enable(0)"), "0");
    c.ask_until("IsEnabled(0)", |a| a == "1");
    modbus_write(serving.port, 0x6A81, 2); // Edit
    let refused = c.ask_until("MoveAbs(0, 1)", |a| a != "0");
    assert!(refused.starts_with("ERROR 0x10000020 alarm: the controller is not in Run"), "{refused}");
    modbus_write(serving.port, 0x6A81, 4); // Run
    c.ask_until("MoveAbs(0, 1)", |a| a == "0");
    c.ask_until("GetPosFb(0)", |a| (position(a) - 1.0).abs() < 1e-3);
}

/// A client that sends no whole line within `[ascii] idle_timeout_ms` gets an error line
/// and is closed (issue 36.11: it was closed without a word); the others are served
/// meanwhile.
#[test]
fn native_closes_an_idle_client() {
    let ns = unique_ns("ascii-idle");
    let dir = tempfile::tempdir().unwrap();
    let config = machine(dir.path(), &[], "[ascii]\nidle_timeout_ms = 300\n");
    let serving = serve(&ns, dir.path(), &["--config", config.to_str().unwrap()]);
    let timed_out = "ERROR no whole line within 300 ms, closing";
    let mut idle = Client::connect(serving.ascii_port);
    idle.send(b"GetAxis");
    let mut busy = Client::connect(serving.ascii_port);
    assert_eq!(busy.ask("GetAxisNum()"), "4");
    assert_eq!(idle.read_line(), timed_out, "half a line, then nothing");
    let mut rest = String::new();
    let read = idle.reader.read_line(&mut rest);
    assert!(matches!(read, Ok(0)), "then closed: {read:?} {rest:?}");
    // A byte every 100 ms is no whole line within 300 ms either.
    let mut trickling = Client::connect(serving.ascii_port);
    for &b in b"GetAxisNum()\n" {
        if trickling.writer.write_all(&[b]).is_err() {
            break;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    assert_eq!(trickling.read_line(), timed_out, "a trickle");
    let mut answer = String::new();
    let read = trickling.reader.read_line(&mut answer);
    assert!(!matches!(read, Ok(n) if n > 0), "then closed, not answered: {answer:?}");
    let mut silent = Client::connect(serving.ascii_port);
    assert_eq!(silent.read_line(), timed_out, "nothing at all");
    // Nor is an endless line: bytes keep coming, no newline ever does.
    let mut endless = Client::connect(serving.ascii_port);
    let closed = eventually(Duration::from_secs(20), || {
        endless.writer.write_all(&[b'A'; 4096]).is_err() || {
            std::thread::sleep(Duration::from_millis(20));
            false
        }
    });
    assert!(closed, "an endless line is closed");
    assert_eq!(Client::connect(serving.ascii_port).ask("GetAxisNum()"), "4");
}

/// Issue 36.11: a 1 MB line with no newline is answered with the line-length error as
/// soon as it is too long, well within the idle timeout (60 s), not closed without a word;
/// once its newline comes the connection goes on.
#[test]
fn native_answers_a_megabyte_line_at_once() {
    let ns = unique_ns("ascii-long");
    let dir = tempfile::tempdir().unwrap();
    let serving = serve(&ns, dir.path(), &[]);
    let mut c = Client::connect(serving.ascii_port);
    c.writer.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let start = Instant::now();
    c.send(&vec![b'x'; 1 << 20]);
    assert_eq!(c.read_line(), "ERROR line longer than 256 bytes");
    assert!(start.elapsed() < Duration::from_secs(10), "{:?}", start.elapsed());
    c.send(b"still the same line\nGetAxisNum()\n");
    assert_eq!(c.read_line(), "4", "answered once, then the next line");
}

/// 200 clients at once: those past `max_connections` (32) get an error line and are
/// closed, the others are answered; once they leave, the next client is answered.
#[test]
fn native_two_hundred_clients_at_once() {
    let ns = unique_ns("ascii-flood");
    let dir = tempfile::tempdir().unwrap();
    let serving = serve(&ns, dir.path(), &[]);
    let mut clients: Vec<Client> = (0..200).map(|_| Client::connect(serving.ascii_port)).collect();
    let (mut served, mut refused) = (0, 0);
    for c in &mut clients {
        c.send(b"GetAxisNum()\n");
        match c.read_line().as_str() {
            "4" => served += 1,
            "ERROR too many connections (32 open)" => refused += 1,
            other => panic!("unexpected answer {other:?}"),
        }
    }
    assert_eq!((served, refused), (32, 168));
    assert!(
        eventually(Duration::from_secs(10), || serving.stderr().contains("(ascii.max_connections)")),
        "the refusals are logged: {}",
        serving.stderr()
    );
    drop(clients);
    assert!(
        eventually(Duration::from_secs(10), || Client::connect(serving.ascii_port).ask("GetAxisNum()") == "4"),
        "the server answers the next client"
    );
}

/// HMPL 22.2.1 example 1 in Lua: every character + 1. A parser that fails or returns no
/// string earns an error line, and the agent lives on.
#[test]
fn user_agent_runs_the_manuals_echo_example() {
    let ns = unique_ns("ascii-echo");
    let dir = tempfile::tempdir().unwrap();
    let agent = r#"
        local function AsciiAgent(cmd)
          if cmd == "boom" then error("parser failed on purpose") end
          if cmd == "table" then return {} end
          local res = {}
          for i = 1, #cmd do res[i] = string.char(cmd:byte(i) + 1) end
          return table.concat(res)
        end
        Till(IsSystemOper)
        Print("agent %d", START_ASCII_AGENT(AsciiAgent))
    "#;
    let serving = serve_with(&ns, dir.path(), &[agent]);
    let mut c = Client::connect(user_port(&serving, 0));
    assert_eq!(c.ask("hello"), "ifmmp");
    assert_eq!(c.ask("asdf"), "bteg");
    let boom = c.ask("boom");
    assert!(boom.starts_with("ERROR ") && boom.contains("parser failed on purpose"), "{boom}");
    assert_eq!(c.ask("table"), "ERROR the parser returned a table, not a string");
    c.send(b"\x01\x02\n");
    assert_eq!(c.read_line(), "ERROR not text: byte 0x01 at column 1");
    c.send(&vec![b'a'; 8192]);
    c.send(b"\n");
    assert_eq!(c.read_line(), "ERROR line longer than 512 bytes");
    assert_eq!(c.ask("HAL"), "IBM", "the agent lives on");
    let mut vanishing = TcpStream::connect(("127.0.0.1", user_port(&serving, 0))).unwrap();
    vanishing.write_all(b"half a li").unwrap();
    drop(vanishing);
    assert_eq!(c.ask("IBM"), "JCN", "a peer gone mid-line leaves the agent serving");
    assert!(serving.stdout().contains("[task 0] agent 0"));
}

/// HMPL 22.2.1 example 2 in Lua: ENABLE, MOVEABS, MOVEREL and STOP; the axis moves.
#[test]
fn user_agent_runs_the_manuals_command_parser() {
    let ns = unique_ns("ascii-parser");
    let dir = tempfile::tempdir().unwrap();
    let agent = r#"
        local function AsciiAgent(cmd)
          local token = {}
          for t in cmd:gmatch("%S+") do
            token[#token + 1] = t
            if #token == 3 then break end
          end
          local v2, v3 = tonumber(token[2] or "0") or 0, tonumber(token[3] or "0") or 0
          if token[1] == "ENABLE" then
            if #token == 2 then Enable(v2) end
          elseif token[1] == "MOVEABS" then
            if #token == 3 then MoveAbs(v2, v3) end
          elseif token[1] == "MOVEREL" then
            if #token == 3 then MoveRel(v2, v3) end
          elseif token[1] == "STOP" then
            if #token == 2 then Stop(v2) end
          end
        end
        Till(IsSystemOper)
        START_ASCII_AGENT(AsciiAgent)
    "#;
    let serving = serve_with(&ns, dir.path(), &[agent]);
    let mut user = Client::connect(user_port(&serving, 0));
    let mut native = Client::connect(serving.ascii_port);
    // The manual's parser writes no response: each line is answered with an empty one.
    assert_eq!(user.ask("ENABLE 0"), "");
    native.ask_until("IsEnabled(0)", |a| a == "1");
    assert_eq!(user.ask("MOVEABS 0  0.05"), "");
    native.ask_until("GetPosFb(0)", |a| (position(a) - 0.05).abs() < 1e-4);
    assert_eq!(user.ask("MOVEREL 0  0.01"), "");
    native.ask_until("GetPosFb(0)", |a| (position(a) - 0.06).abs() < 1e-4);
    assert_eq!(user.ask("MOVEABS 0 50"), "");
    native.ask_until("GetPosFb(0)", |a| position(a) > 1.0);
    assert_eq!(user.ask("STOP 0"), "");
    native.ask_until("IsMoving(0)", |a| a == "0");
    let stopped_at = position(&native.ask("GetPosFb(0)"));
    assert!(stopped_at > 1.0 && stopped_at < 50.0, "stopped on the way, at {stopped_at}");
}

/// A User ASCII port another program holds: START_ASCII_AGENT fails with a Lua error that
/// says where, and gives its claim up: another task's try, while the first task runs on,
/// fails on the port too rather than with 0x1392.
#[test]
fn user_agent_on_a_taken_port_says_so() {
    let ns = unique_ns("ascii-taken");
    let dir = tempfile::tempdir().unwrap();
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    let first = r#"
        Till(IsSystemOper)
        print(pcall(START_ASCII_AGENT, function(cmd) return cmd end))
        SetTableValue(0, 1)
        Till(function() return GetTableValue(0) == 2 end)
    "#;
    let second = r#"
        Till(function() return GetTableValue(0) == 1 end)
        print(pcall(START_ASCII_AGENT, function(cmd) return cmd end))
        SetTableValue(0, 2)
    "#;
    let first = program(dir.path(), "first.lua", first);
    let second = program(dir.path(), "second.lua", second);
    let out = run(&ns, &["--ascii-user-port", &port, first.to_str().unwrap(), second.to_str().unwrap()]);
    for task in [0, 1] {
        let lines = out.lines_of_task(task);
        let said = format!("cannot listen on 127.0.0.1:{port}");
        assert!(lines.len() == 1 && lines[0].starts_with("false") && lines[0].contains(&said), "{}", out.stdout);
    }
}

/// One agent controller-wide: a second task gets 0x1392 while the first runs; once the
/// first task is stopped, the next START_ASCII_AGENT succeeds and serves.
#[test]
fn one_agent_at_a_time_and_the_next_after_a_stop() {
    let ns = unique_ns("ascii-one");
    let dir = tempfile::tempdir().unwrap();
    let first = r#"
        Till(IsSystemOper)
        Print("first %d", START_ASCII_AGENT(function(cmd) return "first:" .. cmd end))
    "#;
    let second = r#"
        Till(IsSystemOper)
        Till(function() return GetTableValue(0) == 1 end)
        local last
        repeat
          local rc = START_ASCII_AGENT(function(cmd) return "second:" .. cmd end)
          if rc ~= last then Print("second %d", rc) end
          last = rc
          Sleep(5)
        until rc == 0
    "#;
    let serving = serve_with(&ns, dir.path(), &[first, second]);
    let mut c = Client::connect(user_port(&serving, 0));
    assert_eq!(c.ask("x"), "first:x");
    let mut native = Client::connect(serving.ascii_port);
    assert_eq!(native.ask("SetTableValue(0, 1)"), "0");
    let refused = serving.await_line(1, "second ", Duration::from_secs(20));
    assert_eq!(refused.as_deref(), Some("5010"), "0x1392 eERR_HMPL_ASCII_AGENT_RUNNING");
    assert_eq!(native.ask("StopTask(0)"), "0");
    let port = user_port(&serving, 1);
    assert_eq!(Client::connect(port).ask("y"), "second:y");
    assert!(serving.stdout().contains("[task 1] second 0"));
}

/// ASCII_ServerBroadcast from another task reaches every client of the agent; longer than
/// 128 bytes is refused.
#[test]
fn broadcast_reaches_every_client() {
    let ns = unique_ns("ascii-bcast");
    let dir = tempfile::tempdir().unwrap();
    let agent = r#"
        Till(IsSystemOper)
        START_ASCII_AGENT(function(cmd) return "ok " .. cmd end)
    "#;
    let broadcaster = r#"
        Till(function() return GetTableValue(0) == 1 end)
        Print("long %d", ASCII_ServerBroadcast(string.rep("x", 129)))
        Print("news %d", ASCII_ServerBroadcast("news for all, not this", 12))
    "#;
    let serving = serve_with(&ns, dir.path(), &[agent, broadcaster]);
    let port = user_port(&serving, 0);
    let mut a = Client::connect(port);
    let mut b = Client::connect(port);
    // Both are served before the broadcast, so both are known to the agent.
    assert_eq!((a.ask("a").as_str(), b.ask("b").as_str()), ("ok a", "ok b"));
    assert_eq!(Client::connect(serving.ascii_port).ask("SetTableValue(0, 1)"), "0");
    assert_eq!((a.read_line().as_str(), b.read_line().as_str()), ("news for all", "news for all"));
    assert_eq!(serving.await_line(1, "long ", Duration::from_secs(10)).as_deref(), Some("5005"), "0x138D");
    assert_eq!(serving.await_line(1, "news ", Duration::from_secs(10)).as_deref(), Some("0"));
}

/// scripts/examples/ascii_jog.lua under `luamotion run`: JOG+ moves the axis up, STOP
/// holds it, JOG- moves it down; unknown commands and axes are refused.
#[test]
fn ascii_jog_example_jogs_an_axis() {
    let ns = unique_ns("ascii-jog");
    let example = repo_path("scripts/examples/ascii_jog.lua");
    let mut child = start_run(&ns, &["--ascii-user-port", "0", example.to_str().unwrap()]);
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let mut line = String::new();
    stdout.read_line(&mut line).unwrap();
    let port: u16 = line
        .trim_end()
        .strip_prefix("[task 0] User ASCII on 127.0.0.1:")
        .unwrap_or_else(|| panic!("{line:?}"))
        .parse()
        .unwrap();
    let mut c = Client::connect(port);
    let start = position(&c.ask("POS 0"));
    assert_eq!(c.ask("JOG+ 0"), "OK");
    c.ask_until("POS 0", |a| position(a) > start + 1.0);
    assert_eq!(c.ask("STOP 0"), "OK");
    let mut held = 0.0;
    c.ask_until("POS 0", |a| {
        let p = position(a);
        let still = (p - held).abs() < 1e-6;
        held = p;
        still
    });
    // A still reading can come from a cycle late under load, before the stop's ramp has
    // ended; until it has, a jog is refused with eERR_AXIS_CMD_INVALID_STOPPING.
    let stopping = "ERROR 0x8300008C";
    assert_eq!(c.ask_until("jog- 0", |a| a != stopping), "OK");
    c.ask_until("POS 0", |a| position(a) < held - 1.0);
    assert_eq!(c.ask("STOP 0"), "OK");
    assert_eq!(c.ask("SPIN 0"), "ERROR unknown command: SPIN 0");
    assert_eq!(c.ask("POS 9"), "ERROR no axis 9");
    // SAFETY: asking the controller to shut down, as Ctrl-C does.
    unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
    let out = finish(child, Duration::from_secs(20));
    assert!(out.stderr.contains("stopped"), "{}", out.stderr);
}

/// HMPL 9.3, 9.5 over the Native server: an HMI sets and reads a digital I/O terminal's
/// outputs and reads the input a script switched (slave 4, after the four drives).
#[test]
fn native_drives_a_terminals_outputs_and_reads_its_inputs() {
    let ns = unique_ns("ascii-dio");
    let dir = tempfile::tempdir().unwrap();
    let terminal = "[[slaves]]\ndevice = \"digital_io\"\ninputs = 8\noutputs = 8\n";
    let config = machine(dir.path(), &["SimSetSlvGPI(4, 3, 1)"], terminal);
    let serving = serve(&ns, dir.path(), &["--config", config.to_str().unwrap()]);
    let mut c = Client::connect(serving.ascii_port);
    assert_eq!(c.ask("SetSlvAllGPO(4, 0x81)"), "0");
    assert_eq!(c.ask("ToggleSlvGPO(4, 8)"), "0");
    assert_eq!(c.ask("SetSlvGPO(4, 2, 1)"), "0");
    assert_eq!(c.ask("GetSlvAllGPO(4)"), "3", "outputs 1 and 2");
    let refused = "ERROR 0x0000138F eERR_HMPL_ARG_OUT_OF_RANGE (argument out of range)";
    assert_eq!(c.ask("SetSlvGPO(4, 9, 1)"), refused, "8 outputs: -1, with its reason");
    c.ask_until("GetSlvAllGPI(4)", |a| a == "4");
    assert_eq!(c.ask("GetSlvGPI(4, 3)"), "1");
    assert_eq!(c.ask("GetSlvAllGPIByStartIdx(4, 3)"), "1");
}

/// HMPL ch. 10 over the Native server: an HMI sets an analog terminal's conversion types by
/// their constants, writes an output in volts and reads it back, wired, on the input, and
/// binds an output to an axis variable (slave 4, after the four drives).
#[test]
fn native_sets_and_reads_an_analog_terminal() {
    let ns = unique_ns("ascii-aio");
    let dir = tempfile::tempdir().unwrap();
    let terminal = "[[slaves]]\ndevice = \"analog_io\"\ninputs = 2\noutputs = 2\nloopback = true\n";
    let config = machine(dir.path(), &[], terminal);
    let serving = serve(&ns, dir.path(), &["--config", config.to_str().unwrap()]);
    let mut c = Client::connect(serving.ascii_port);
    assert_eq!(c.ask("SetSlvAOType(4, 1, HMPL_DAC_N10_P10)"), "0");
    // The line grammar has no operators: HMPL_DAC_SIGNED | HMPL_DAC_N10_P10 is 0x101.
    assert_eq!(c.ask("SetSlvAIType(4, 1, 0x101)"), "0");
    assert_eq!(c.ask("GetSlvAIType(4, 1)"), "257");
    assert_eq!(c.ask("SetSlvAO(4, 1, -5)"), "0");
    assert_eq!(c.ask("GetSlvAORaw(4, 1)"), "16384", "HMPL table 10.1.1: -5 V");
    // The input reads the same word signed: 16384 is +5 V there.
    c.ask_until("GetSlvAIRaw(4, 1)", |a| a == "16384");
    assert!(c.ask("GetSlvAI(4, 1)").starts_with('5'), "signed 16384 is 5 V");
    assert_eq!(c.ask("SetSlvAOType(4, 2, HMPL_DAC_P0_P10)"), "0");
    assert_eq!(c.ask("SetSlvAOMonitor(4, 2, 0x401)"), "0", "HMPL_AXIS_1 | HMPL_POS_FB");
    assert_eq!(c.ask("SetSlvAOParam(4, 2, 1, 0.5, 2)"), "0");
    assert_eq!(c.ask("IsSlvAOBound(4, 2)"), "1");
    let not_ready = "ERROR 0x0000138C eERR_HMPL_MOTION_NOT_READY (controller not ready to run this HMPL)";
    assert_eq!(c.ask("SetSlvAO(4, 2, 1)"), not_ready, "a bound output has one writer");
}

/// The answer to a call naming the agent's own slot (HMPL 16.4: it is no HMPL task).
const NOT_A_TASK: &str = "ERROR 0x00000107 eERR_NOT_VALID_TASKID (invalid task ID)";

/// Issue 36.3: StopAllTask() and EStop() over the Native server stop the programs, not the
/// agent's slot that carries them out: each is answered (an empty line, both are void), the
/// program running at the time is stopped, the next line on this connection and on a new
/// one is answered, and the controller still ends on SIGINT.
#[test]
fn native_stops_are_answered_and_stop_the_programs_only() {
    let ns = unique_ns("ascii-stop");
    let dir = tempfile::tempdir().unwrap();
    let mut serving = serve_with(&ns, dir.path(), &["while true do Sleep(10) end"]);
    let mut c = Client::connect(serving.ascii_port);
    c.ask_until("IsTaskStop(0)", |a| a == "0");
    assert_eq!(c.ask("StopTask(62)"), NOT_A_TASK, "the agent's slot is not stopped by name");
    assert_eq!(c.ask("StopAllTask()"), "", "answered");
    c.ask_until("IsTaskStop(0)", |a| a == "1");
    assert_eq!(c.ask("GetAxisNum()"), "4", "the next line is answered");
    assert_eq!(c.ask("StartTask(0)"), "0");
    c.ask_until("IsTaskStop(0)", |a| a == "0");
    assert_eq!(c.ask("Enable(0)"), "0");
    c.ask_until("IsEnabled(0)", |a| a == "1");
    assert_eq!(c.ask("EStop()"), "", "answered");
    c.ask_until("IsTaskStop(0)", |a| a == "1");
    c.ask_until("IsEnabled(0)", |a| a == "0");
    assert_eq!(c.ask("IsTaskStop(62)"), "0", "the agent's slot runs on");
    assert_eq!(Client::connect(serving.ascii_port).ask("GetAxisNum()"), "4", "a new client is served");
    let ended = serving.interrupt(Duration::from_secs(15));
    assert!(ended.is_some(), "serve ends on SIGINT within 15 s; stderr:\n{}", serving.stderr());
}

/// The same from Lua programs, with socat as the client: `StopTask(62)` is refused with
/// 0x0107, a program's `StopAllTask()` stops every program (itself too) but not the agent,
/// which goes on answering.
#[test]
fn program_stops_leave_the_native_agent_serving() {
    let ns = unique_ns("ascii-lstop");
    let dir = tempfile::tempdir().unwrap();
    let refuser = r#"
        Print("StopTask(62) = 0x%04X", StopTask(62))
        SetTableValue(0, 1)
        while true do Sleep(10) end
    "#;
    let stopper = r#"
        Till(function() return GetTableValue(0) == 2 end)
        StopAllTask()
        Print("never printed: StopAllTask stopped this task")
    "#;
    let mut serving = serve_with(&ns, dir.path(), &[refuser, stopper]);
    assert_eq!(serving.await_line(0, "StopTask(62) = ", Duration::from_secs(20)).as_deref(), Some("0x0107"));
    let mut socat = Command::new(debian_tool("socat"))
        .args(["-", &format!("TCP:127.0.0.1:{}", serving.ascii_port)])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("socat");
    let mut to_socat = socat.stdin.take().unwrap();
    let (answers, from_socat) = std::sync::mpsc::channel();
    let mut reader = BufReader::new(socat.stdout.take().unwrap());
    std::thread::spawn(move || {
        let mut line = String::new();
        while reader.read_line(&mut line).is_ok_and(|n| n > 0) {
            let _ = answers.send(std::mem::take(&mut line).trim_end().to_string());
        }
    });
    let mut ask = |line: &str| {
        writeln!(to_socat, "{line}").unwrap();
        from_socat.recv_timeout(Duration::from_secs(20)).unwrap_or_else(|e| panic!("{line}: no answer ({e})"))
    };
    assert_eq!(ask("GetTableValue(0)"), "1");
    assert_eq!(ask("SetTableValue(0, 2)"), "0");
    assert!(
        eventually(Duration::from_secs(20), || ask("IsTaskStop(0)") == "1" && ask("IsTaskStop(1)") == "1"),
        "both programs stopped"
    );
    assert_eq!(ask("IsTaskStop(62)"), "0");
    assert_eq!(ask("StopTask(62)"), NOT_A_TASK);
    assert_eq!(ask("GetAxisNum()"), "4");
    assert!(!serving.stdout().contains("never printed"), "{}", serving.stdout());
    let _ = socat.kill();
    let _ = socat.wait();
    assert!(serving.interrupt(Duration::from_secs(15)).is_some(), "serve ends on SIGINT; {}", serving.stderr());
}

/// Ctrl-C while the agent waits in a call the controller answers only when it is done (a
/// homing at 0.01 mm/s, which holds the other clients' lines meanwhile): serve ends.
#[test]
fn serve_ends_on_sigint_while_the_agent_waits() {
    let ns = unique_ns("ascii-sigint");
    let dir = tempfile::tempdir().unwrap();
    let mut serving = serve(&ns, dir.path(), &[]);
    let mut c = Client::connect(serving.ascii_port);
    assert_eq!(c.ask("Enable(0)"), "0");
    c.ask_until("IsEnabled(0)", |a| a == "1");
    assert_eq!(c.ask("SetHomeSwitchVel(0, 0.01)"), "0");
    assert_eq!(c.ask("SetHomeZeroVel(0, 0.01)"), "0");
    c.send(b"MoveHome(0)\n");
    // The two clients' lines race to the agent: until the homing holds it, the other's
    // line is answered; once it goes unanswered, the agent is waiting in MoveHome.
    let mut other = Client::connect(serving.ascii_port);
    other.writer.set_read_timeout(Some(Duration::from_millis(500))).unwrap();
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        other.send(b"GetAxisNum()\n");
        let mut line = String::new();
        if other.reader.read_line(&mut line).is_err() {
            break;
        }
        assert!(Instant::now() < deadline, "the agent never went into the homing; last answer {line:?}");
        std::thread::sleep(Duration::from_millis(50));
    }
    let ended = serving.interrupt(Duration::from_secs(15));
    assert!(ended.is_some(), "serve ends on SIGINT within 15 s; stderr:\n{}", serving.stderr());
}

/// One well-formed line for `spec`, its arguments made from the registry's types and
/// quantities: axis, group and other integers 0 (a valid axis), numbers 1.5 (0.5 for a
/// quantity that is a time or a ratio makes no difference: a refusal is a code), strings
/// "ab", flags 1.
fn well_formed_line(spec: &api::FunctionSpec) -> String {
    use api::ArgType;
    let args: Vec<&str> = spec
        .args
        .iter()
        .map(|arg| match arg.ty {
            ArgType::Int | ArgType::Timer => "0",
            ArgType::Double => "1.5",
            ArgType::Bool => "1",
            ArgType::Str | ArgType::Bytes | ArgType::Any => "\"ab\"",
            other => panic!("{}: an ASCII function with a {other:?} argument has no line", spec.name),
        })
        .collect();
    format!("{}({})", spec.name, args.join(", "))
}

/// Issue 36.5: every function the registry marks ASCII (the manual's icon) is carried out
/// by the Native server: one well-formed call each, answered with its value(s) or an HMPL
/// error code, never "runs in a script only", "not available" or a parse or argument
/// error; the server answers after all of them.
#[test]
fn native_carries_out_every_ascii_function() {
    let ns = unique_ns("ascii-every");
    let dir = tempfile::tempdir().unwrap();
    let serving = serve(&ns, dir.path(), &[]);
    let mut c = Client::connect(serving.ascii_port);
    let mut refused = Vec::new();
    let mut count = 0;
    for spec in api::registry::all().filter(|s| s.ascii) {
        let line = well_formed_line(spec);
        let answer = c.ask(&line);
        count += 1;
        let code_answer = answer.starts_with("ERROR 0x") || answer.starts_with("ERROR SDO abort 0x");
        if answer.starts_with("ERROR") && !code_answer {
            refused.push(format!("{line} -> {answer}"));
        }
    }
    assert!(refused.is_empty(), "{} of {count} refused:\n{}", refused.len(), refused.join("\n"));
    assert!(count >= 270, "{count} functions marked ASCII");
    assert_eq!(c.ask("GetAxisNum()"), "4", "and the server goes on");
}

/// The functions a script carries out in its own process, over ASCII: the string
/// functions give what the manual's examples of HMPL 3.4-3.13 say (the same code as a
/// script's), `SendEvent` reaches the event stream as task 62's, the scope gate answers as
/// a script's `SetHMIScope`, and the user table is saved to and loaded from its file.
#[test]
fn native_carries_out_a_scripts_functions_as_the_manual_says() {
    let ns = unique_ns("ascii-str");
    let dir = tempfile::tempdir().unwrap();
    let serving = serve(&ns, dir.path(), &[]);
    let mut c = Client::connect(serving.ascii_port);
    let rows = [
        (r#"StringToDouble("1.5")"#, "1.5"),
        (r#"StringToDouble("  -12.5e2xyz")"#, "-1250"),
        (r#"StringLen("hello world")"#, "11"),
        (r#"IsStringEqual("abc", "abc")"#, "1"),
        (r#"IsStringEqual("abc", "abd")"#, "0"),
        (r#"StrFindCharEx("hello world", "ol", FALSE)"#, "2"),
        (r#"StrFindCharEx("hello world", "helo", TRUE)"#, "5"),
        (r#"StrFindStr("hello world", "world")"#, "6"),
        (r#"StrFindStr("hello", "xyz")"#, "-1"),
        ("RunScheduler()", ""),
        ("SetHMIScope(1)", "0"),
        ("SetHMIScope(0)", "0"),
        ("SetHMIScope(2)", "ERROR 0x0000138F eERR_HMPL_ARG_OUT_OF_RANGE (argument out of range)"),
        ("SendEvent(70000)", "ERROR 0x0000138F eERR_HMPL_ARG_OUT_OF_RANGE (argument out of range)"),
        ("StringLen(\"a\", \"b\")", "ERROR StringLen takes 1 argument(s), got 2"),
        // HMPL 11.6/11.7: the controller's one file, as a script saves and loads it.
        ("SetTableValue(5, 2.5)", "0"),
        ("SaveUserTable(5, 1)", "0"),
        ("SetTableValue(5, 0)", "0"),
        ("LoadUserTable(5, 1)", "0"),
        ("GetTableValue(5)", "2.5"),
        ("SaveUserTable(-1, 1)", "ERROR 0x0000138F eERR_HMPL_ARG_OUT_OF_RANGE (argument out of range)"),
    ];
    // SendEvent until the reader, once subscribed, has seen one (events sent before are
    // not handed to it).
    let mut events = start_events(&ns, 1);
    let seen = eventually(Duration::from_secs(20), || {
        assert_eq!(c.ask("SendEvent(4660)"), "0");
        std::thread::sleep(Duration::from_millis(50));
        events.try_wait().unwrap().is_some()
    });
    assert!(seen, "luamotion events saw no SendEvent");
    let out = finish(events, Duration::from_secs(5));
    let said = out.stdout.lines().next().and_then(|l| l.splitn(3, ' ').nth(2));
    assert_eq!(said, Some("task 62 event 4660"), "{}", out.stdout);
    for (line, want) in rows {
        assert_eq!(c.ask(line), want, "{line}");
    }
}

/// `luamotion events --ns NS --count N`.
fn start_events(ns: &str, count: usize) -> std::process::Child {
    Command::new(BIN)
        .args(["events", "--ns", ns, "--count", &count.to_string()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("luamotion events")
}

/// Issue 36.11, the User agent: a parser's error is one short line (no Lua traceback), a
/// 1 MB answer is cut to 512 bytes with the marker, a 1 MB line with no newline is answered
/// as soon as it is too long; the agent goes on.
#[test]
fn user_agent_bounds_its_answers_and_errors() {
    let ns = unique_ns("ascii-ubound");
    let dir = tempfile::tempdir().unwrap();
    let agent = r#"
        local function parser(cmd)
          if cmd == "big" then return string.rep("y", 1 << 20) end
          if cmd == "deep" then
            local function down(n) if n == 0 then error("bottom reached") end return down(n - 1) + 1 end
            return down(50)
          end
          return "ok " .. cmd
        end
        Till(IsSystemOper)
        START_ASCII_AGENT(parser)
    "#;
    let serving = serve_with(&ns, dir.path(), &[agent]);
    let mut c = Client::connect(user_port(&serving, 0));
    let big = c.ask("big");
    assert_eq!(big, format!("{} … [cut: {} bytes]", "y".repeat(512), (1 << 20) - 512));
    let deep = c.ask("deep");
    assert!(deep.starts_with("ERROR ") && deep.ends_with("bottom reached"), "{deep}");
    assert!(!deep.contains("traceback") && deep.len() < 200, "{deep}");
    c.writer.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    c.send(&vec![b'z'; 1 << 20]);
    assert_eq!(c.read_line(), "ERROR line longer than 512 bytes");
    c.send(b"\n");
    assert_eq!(c.ask("x"), "ok x", "the agent goes on");
}

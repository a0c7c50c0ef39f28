//! HMPL 22.2 and 22.3 from Lua: a task as the TCP client of an ASCII server (a line server
//! in the test), of a Modbus server luamotion did not write (pymodbus) and of luamotion's own
//! (`luamotion serve`); silent and vanished peers, refused connections and the manual's
//! limits give the manual's codes. Every wait in a client call is longer than the task's
//! 500 ms watchdog, so the calls must keep the task's heartbeat going.

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::time::Duration;

use common::serve::serve;
use common::*;

fn listener() -> (TcpListener, u16) {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    (listener, port)
}

/// Runs `source` as task 0 and returns its lines; the program must end normally.
fn run_program(tag: &str, source: &str) -> Vec<String> {
    let ns = unique_ns(tag);
    let dir = tempfile::tempdir().unwrap();
    let script = program(dir.path(), "client.lua", source);
    let out = run(&ns, &[script.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    out.lines_of_task(0)
}

fn assert_lines(lines: &[String], expected: &[&str]) {
    let missing: Vec<&&str> = expected.iter().filter(|e| !lines.iter().any(|l| l == **e)).collect();
    assert!(missing.is_empty(), "missing {missing:?} in:\n{}", lines.join("\n"));
}

/// Prints a Modbus reply as `name rc use_length bytes…` (hex).
const SHOW: &str = r#"
local function show(name, rc, bytes, n)
  local t = {}
  for i, b in ipairs(bytes) do t[i] = string.format("%02x", b) end
  Print("%s %x %d %s", name, rc, n, table.concat(t, " "))
end
"#;

#[test]
fn an_ascii_client_talks_to_a_line_server_and_gets_the_manuals_codes() {
    let (server, port) = listener();
    // Line in, line out; after "quit" the server goes away; otherwise it stays silent.
    let talker = std::thread::spawn(move || {
        let (stream, _) = server.accept().unwrap();
        let mut reader = BufReader::new(stream.try_clone().unwrap());
        let mut writer = stream;
        let mut lines = Vec::new();
        loop {
            let mut line = String::new();
            if reader.read_line(&mut line).unwrap() == 0 {
                break;
            }
            lines.push(line.clone());
            if line == "quit\n" {
                break;
            }
            writer.write_all(format!("echo {line}").as_bytes()).unwrap();
        }
        lines
    });
    let lines = run_program(
        "ascii",
        &format!(
            r#"
local rc, s = ASCII_ClientConnect("127.0.0.1", "{port}")
Print("connect %d %s", rc, tostring(s > 0))
Print("send %d", ASCII_ClientSend(s, 6, "hello\nNOT SENT"))
local rc2, text = ASCII_ClientRecv(s, 512)
Print("recv %d [%s]", rc2, (text:gsub("\n", "|")))
Print("send 513 %x", ASCII_ClientSend(s, 513, "x"))
Print("recv 513 %x", (ASCII_ClientRecv(s, 513)))
Print("recv 0 %x", (ASCII_ClientRecv(s, 0)))
Print("silent %x", (ASCII_ClientRecv(s, 10)))
Print("quit %d", ASCII_ClientSend(s, 5, "quit\n"))
Print("vanished %x", (ASCII_ClientRecv(s, 10)))
local code = 0
for i = 1, 100 do
  code = ASCII_ClientSend(s, 5, "more\n")
  if code ~= 0 then break end
  Sleep(10)
end
Print("send to the vanished %x", code)
Print("disconnect %d", ASCII_ClientDisconnect(s))
Print("disconnect again %x", ASCII_ClientDisconnect(s))
Print("recv unknown %x", (ASCII_ClientRecv(s, 10)))
Print("refused %x", (ASCII_ClientConnect("127.0.0.1", "{closed}")))
Print("bad port %x", (ASCII_ClientConnect("127.0.0.1", "http")))
Print("bad ip %x", (ASCII_ClientConnect("no.such.host", "{port}")))
"#,
            closed = free_port()
        ),
    );
    assert_lines(
        &lines,
        &[
            "connect 0 true",
            "send 0",
            "recv 0 [echo hello|]",
            "send 513 17e9",
            "recv 513 17df",
            "recv 0 17df",
            "silent 17de",
            "quit 0",
            "vanished 17df",
            "send to the vanished 17e9",
            "disconnect 0",
            "disconnect again 138f",
            "recv unknown 17df",
            "refused 17d5",
            "bad port 17d5",
            "bad ip 17d5",
        ],
    );
    assert_eq!(talker.join().unwrap(), ["hello\n", "quit\n"], "the server got the first `length` bytes only");
}

#[test]
fn the_modbus_client_reads_and_writes_a_pymodbus_server_within_the_manuals_limits() {
    let (_server, port) = pymodbus_server();
    let lines = run_program(
        "mb-py",
        &format!(
            r#"{SHOW}
local rc, s = Modbus_ClientConnect("127.0.0.1:{port}")
Print("connect %d", rc)
show("fc16", Modbus_ClientWrite_HoldReg(s, 10, 3, {{0x1234, 7, 65535}}))
show("fc03", Modbus_ClientRead_HoldReg(s, 9, 5))
show("fc04", Modbus_ClientRead_InputReg(s, 5, 2))
show("fc15", Modbus_ClientWrite_Coils(s, 30, 4, {{15}}))
show("fc01", Modbus_ClientRead_Coils(s, 28, 10))
show("fc02", Modbus_ClientRead_Inputs(s, 0, 10))
local words = {{}}
for i = 1, 123 do words[i] = 0xFFFF end
local rc3, _, n3 = Modbus_ClientRead_HoldReg(s, 0, 125)
local rc4, _, n4 = Modbus_ClientRead_InputReg(s, 0, 125)
local rc1, _, n1 = Modbus_ClientRead_Coils(s, 0, 2000)
local rc2, _, n2 = Modbus_ClientRead_Inputs(s, 0, 2000)
local rc16 = Modbus_ClientWrite_HoldReg(s, 1000, 123, words)
local rc15 = Modbus_ClientWrite_Coils(s, 1000, 1968, words)
Print("at the limits %d %d %d %d %d %d: %d %d %d %d", rc3, rc4, rc1, rc2, rc16, rc15, n3, n4, n1, n2)
show("coils after 1968", Modbus_ClientRead_Coils(s, 2960, 16))
Print("over the limits %x %x %x %x %x %x", (Modbus_ClientRead_HoldReg(s, 0, 126)),
  (Modbus_ClientRead_InputReg(s, 0, 126)), (Modbus_ClientRead_Coils(s, 0, 2001)),
  (Modbus_ClientRead_Inputs(s, 0, 2001)), (Modbus_ClientWrite_HoldReg(s, 0, 124, words)),
  (Modbus_ClientWrite_Coils(s, 0, 1969, words)))
Print("none %x, short table %x, not a word %x, past 65535 %x", (Modbus_ClientRead_HoldReg(s, 0, 0)),
  (Modbus_ClientWrite_HoldReg(s, 0, 3, {{1, 2}})), (Modbus_ClientWrite_HoldReg(s, 0, 1, {{65536}})),
  (Modbus_ClientRead_HoldReg(s, 65535, 2)))
show("unchanged", Modbus_ClientRead_HoldReg(s, 0, 3))
Print("disconnect %d", Modbus_ClientDisconnect(s))
Print("after %x, again %x", (Modbus_ClientRead_HoldReg(s, 0, 1)), Modbus_ClientDisconnect(s))
"#
        ),
    );
    assert_lines(
        &lines,
        &[
            "connect 0",
            "fc16 0 4 00 0a 00 03",
            "fc03 0 10 00 00 12 34 00 07 ff ff 00 00",
            "fc04 0 4 03 ed 03 ee",
            "fc15 0 4 00 1e 00 04",
            // Coils 30..33 of 28..37: bits 2..5 of the first byte.
            "fc01 0 2 3c 00",
            // Inputs 0, 3, 6, 9 (address % 3 == 0).
            "fc02 0 2 49 02",
            "at the limits 0 0 0 0 0 0: 250 250 250 250",
            // 1968 coils from 1000 end at 2967.
            "coils after 1968 0 2 ff 00",
            "over the limits 183d 183d 183d 183d 183d 183d",
            "none 183d, short table 183d, not a word 183d, past 65535 183d",
            "unchanged 0 6 00 00 00 00 00 00",
            "disconnect 0",
            "after 1840, again 138f",
        ],
    );
}

#[test]
fn the_modbus_client_writes_and_reads_the_dv_area_of_luamotion_serve() {
    let ns = unique_ns("mb-serve");
    let dir = tempfile::tempdir().unwrap();
    let server = serve(&ns, dir.path(), &[]);
    let lines = run_program(
        "mb-lm",
        &format!(
            r#"{SHOW}
local rc, s = Modbus_ClientConnect("127.0.0.1:{port}")
Print("connect %d", rc)
show("fc16", Modbus_ClientWrite_HoldReg(s, 0x0100, 2, {{0xBEEF, 42}}))
show("fc03", Modbus_ClientRead_HoldReg(s, 0x0100, 2))
-- luamotion's server answers only FC 03, 06 and 16 (exception 01 for the others).
Print("fc01 %x fc02 %x fc04 %x fc15 %x", (Modbus_ClientRead_Coils(s, 0, 8)), (Modbus_ClientRead_Inputs(s, 0, 8)),
  (Modbus_ClientRead_InputReg(s, 0, 1)), (Modbus_ClientWrite_Coils(s, 0, 4, {{15}})))
show("still there", Modbus_ClientRead_HoldReg(s, 0x0101, 1))
Print("disconnect %d", Modbus_ClientDisconnect(s))
"#,
            port = server.port
        ),
    );
    assert_lines(
        &lines,
        &[
            "connect 0",
            "fc16 0 4 01 00 00 02",
            "fc03 0 4 be ef 00 2a",
            "fc01 1840 fc02 1840 fc04 1840 fc15 1840",
            "still there 0 2 00 2a",
            "disconnect 0",
        ],
    );
}

#[test]
fn silent_vanished_and_absent_modbus_servers_give_the_manuals_codes() {
    // Accepts and never answers; the second connection is closed at once.
    let (silent, silent_port) = listener();
    let (vanishing, vanishing_port) = listener();
    let holder = std::thread::spawn(move || {
        let (mut stream, _) = silent.accept().unwrap();
        let mut request = [0u8; 12];
        stream.read_exact(&mut request).unwrap();
        let (gone, _) = vanishing.accept().unwrap();
        drop(gone);
        // Keep the silent connection open until the client gives up on it.
        let mut rest = Vec::new();
        let _ = stream.read_to_end(&mut rest);
        request
    });
    let lines = run_program(
        "mb-peers",
        &format!(
            r#"
local rc, s = Modbus_ClientConnect("127.0.0.1:{silent_port}")
Print("connect %d", rc)
Print("silent %x", (Modbus_ClientRead_HoldReg(s, 7, 2)))
local rc2, v = Modbus_ClientConnect("127.0.0.1:{vanishing_port}")
Print("connect %d", rc2)
Sleep(100)
Print("vanished %x", (Modbus_ClientRead_HoldReg(v, 0, 1)))
Print("refused %x", (Modbus_ClientConnect("127.0.0.1:{closed}")))
Print("bad ip %x", (Modbus_ClientConnect("no.such.host")))
Print("disconnect %d", Modbus_ClientDisconnect(s))
"#,
            closed = free_port()
        ),
    );
    assert_lines(&lines, &["connect 0", "silent 183f", "vanished 1840", "refused 1839", "bad ip 1839", "disconnect 0"]);
    let request = holder.join().unwrap();
    assert_eq!(request[7..], [0x03, 0x00, 0x07, 0x00, 0x02], "FC 03 at 7, 2 registers");
    assert_eq!(request[6], 1, "unit id 1 without `/unit`");
}

/// HMPL 22.3 takes no unit id: the client sends 1, which the pymodbus server (unit 1 only,
/// as a gateway with one device) answers, and `ip/unit` sends another; a unit the server
/// does not have goes unanswered, and a unit id that is not 0..255 does not connect.
#[test]
fn the_modbus_client_sends_unit_1_unless_the_address_names_another() {
    let (_server, port) = pymodbus_server();
    let lines = run_program(
        "mb-unit",
        &format!(
            r#"
local rc, s = Modbus_ClientConnect("127.0.0.1:{port}")
Print("default %x %x", rc, (Modbus_ClientRead_InputReg(s, 5, 1)))
local rc1, s1 = Modbus_ClientConnect("127.0.0.1:{port}/1")
Print("unit 1 %x %x", rc1, (Modbus_ClientRead_InputReg(s1, 5, 1)))
local rc7, s7 = Modbus_ClientConnect("127.0.0.1:{port}/7")
Print("unit 7 %x %x", rc7, (Modbus_ClientRead_InputReg(s7, 5, 1)))
Print("bad units %x %x %x", (Modbus_ClientConnect("127.0.0.1:{port}/256")),
  (Modbus_ClientConnect("127.0.0.1:{port}/x")), (Modbus_ClientConnect("127.0.0.1/")))
"#
        ),
    );
    assert_lines(&lines, &["default 0 0", "unit 1 0 0", "unit 7 0 183f", "bad units 1839 1839 1839"]);
}

#[test]
fn a_server_that_accepts_nothing_more_gives_the_connect_timeouts() {
    use std::os::fd::AsRawFd;
    let (full, port) = listener();
    // SAFETY: listen(2) again on our own listening socket: with a backlog of 0 the kernel
    // queues one connection and drops the SYNs after it, so a connect never completes.
    assert_eq!(unsafe { libc::listen(full.as_raw_fd(), 0) }, 0);
    let address = full.local_addr().unwrap();
    let queued: Vec<TcpStream> =
        (0..3).filter_map(|_| TcpStream::connect_timeout(&address, Duration::from_millis(300)).ok()).collect();
    assert!(!queued.is_empty(), "the queue takes one");
    let lines = run_program(
        "connect-timeout",
        &format!(
            r#"
Print("ascii %x", (ASCII_ClientConnect("127.0.0.1", "{port}")))
Print("modbus %x", (Modbus_ClientConnect("127.0.0.1:{port}")))
"#
        ),
    );
    assert_lines(&lines, &["ascii 17d4", "modbus 1838"]);
}

//! DRL `FreePort.Eth` (DXMC 8.3 FreePort) from Lua programs, against TCP peers the test
//! drives itself with std::net and against `nc` as client and server: framing, refusals
//! with codes, peers that vanish, a crowd of clients, the watchdog while a task polls, and
//! a killed task's port.

mod common;

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::Duration;

use common::*;

/// Connects once the Lua server listens.
fn connect(port: u16) -> TcpStream {
    let mut stream = None;
    assert!(
        eventually(Duration::from_secs(20), || {
            stream = TcpStream::connect(("127.0.0.1", port)).ok();
            stream.is_some()
        }),
        "the server listens on {port}"
    );
    let stream = stream.unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
    stream
}

/// Reads until `want` bytes arrived.
fn read_exactly(stream: &mut TcpStream, want: usize) -> String {
    let mut buf = vec![0; want];
    stream.read_exact(&mut buf).expect("the answer");
    String::from_utf8(buf).unwrap()
}

fn shut_down(child: std::process::Child) -> Finished {
    // SAFETY: asking the controller to shut down, as Ctrl-C does.
    unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
    finish(child, Duration::from_secs(20))
}

const ECHO_SERVER: &str = r#"
    Print("open %d", FreePort.Eth.OpenAsServer(7, PORT, nil, ";"))
    while true do
      local rc, data, count = FreePort.Eth.Rx(7)
      if rc == 0 and count > 0 then
        if data == "bye" then break end
        if count > 1000 then Print("got %d bytes", count) end
        local txrc, copy = FreePort.Eth.Tx(7, "echo:" .. data)
        if txrc ~= 0 or copy ~= "echo:" .. data then Print("tx %d", txrc) end
      elseif rc ~= 0 and rc ~= 5 then
        Print("rx code %d", rc)
      end
      Sleep(1)
    end
    local _, ids = FreePort.Eth.GetSessions()
    Print("sessions %d: %d", #ids, ids[1])
    Print("close %d, again %d", FreePort.Eth.Close(7), FreePort.Eth.Close(7))
"#;

#[test]
fn a_lua_server_echoes_frames_refuses_long_ones_and_outlives_a_vanished_peer() {
    let ns = unique_ns("fp-echo");
    let dir = tempfile::tempdir().unwrap();
    let port = freeport_port();
    let source = format!("local PORT = {port}\n{ECHO_SERVER}");
    let script = program(dir.path(), "echo.lua", &source);
    let child = start_run(&ns, &[script.to_str().unwrap()]);
    let mut peer = connect(port);
    // A frame split over two writes, and two frames in one.
    peer.write_all(b"hel").unwrap();
    std::thread::sleep(Duration::from_millis(50));
    peer.write_all(b"lo;a;b").unwrap();
    peer.write_all(b"c;").unwrap();
    assert_eq!(read_exactly(&mut peer, 26), "echo:hello;echo:a;echo:bc;");
    // 1500 bytes of data: dropped with code 6; the next frame still comes through.
    peer.write_all(&[b'x'; 1500]).unwrap();
    peer.write_all(b";after;").unwrap();
    assert_eq!(read_exactly(&mut peer, 11), "echo:after;");
    // Exactly 1024 bytes are received; their echo, 1029 bytes, is refused with 6.
    peer.write_all(format!("{};", "y".repeat(1024)).as_bytes()).unwrap();
    // A peer that vanishes mid-frame: its half frame is not glued to the next peer's.
    peer.write_all(b"half").unwrap();
    drop(peer);
    let mut next = connect(port);
    next.write_all(b"x;").unwrap();
    assert_eq!(read_exactly(&mut next, 7), "echo:x;");
    next.write_all(b"bye;").unwrap();
    let out = finish(child, Duration::from_secs(20));
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(
        out.lines_of_task(0),
        ["open 0", "rx code 6", "got 1024 bytes", "tx 6", "sessions 1: 7", "close 0, again 2"],
        "{}\n{}",
        out.stdout,
        out.stderr
    );
}

#[test]
fn a_lua_client_frames_with_a_start_byte_and_cr_lf_and_gets_codes_for_bad_calls() {
    let ns = unique_ns("fp-client");
    let dir = tempfile::tempdir().unwrap();
    // Kept bound from the search on: no other process can take the port in between.
    let listener = freeport_listener();
    let port = listener.local_addr().unwrap().port();
    let server = std::thread::spawn(move || {
        let (mut stream, _) = listener.accept().unwrap();
        stream.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
        let got = read_exactly(&mut stream, 18);
        stream.write_all(b"junk:pong\r\n").unwrap();
        // Stays until the client has closed.
        let mut rest = Vec::new();
        let _ = stream.read_to_end(&mut rest);
        got
    });
    let source = format!(
        r#"
        local PORT = {port}
        local E = FreePort.Eth
        Print("low port %d, high port %d", E.OpenAsClient(2, "127.0.0.1", 2999, ":", CR_LF),
              E.OpenAsClient(2, "127.0.0.1", 10001, ":", CR_LF))
        Print("two start bytes %d, three end bytes %d, byte 256 %d, bad address %d",
              E.OpenAsClient(2, "127.0.0.1", PORT, "::", CR_LF), E.OpenAsClient(2, "127.0.0.1", PORT, ":", "abc"),
              E.OpenAsClient(2, "127.0.0.1", PORT, 256, CR_LF), E.OpenAsClient(2, "no.where", PORT, ":", CR_LF))
        Print("open %d, again %d", E.OpenAsClient(2, "127.0.0.1", PORT, 0x3A, CR_LF),
              E.OpenAsClient(2, "127.0.0.1", PORT, 0x3A, CR_LF))
        Print("check %d, unknown %d", E.ConnectCheck(2), E.ConnectCheck(99))
        local rc, copy = E.Tx(2, 3.5)
        Print("tx %d %s", rc, tostring(copy))
        Print("tx table %d, bool %d", (E.Tx(2, {{104, 105}})), (E.Tx(2, true)))
        Print("tx nil %d, 1025 bytes %d, bad table %d", (E.Tx(2, nil)), (E.Tx(2, string.rep("y", 1025))),
              (E.Tx(2, {{1, 300}})))
        local rc, data, n
        repeat rc, data, n = E.Rx(2); Sleep(1) until n > 0 or rc ~= 0
        Print("rx %d %s %d", rc, data, n)
        Print("close %d, tx closed %d, rx closed %d", E.Close(2), (E.Tx(2, "x")), (E.Rx(2)))
        Print("clear unknown %d, closeall %d", E.BuffClear(2), E.CloseAll())
        "#
    );
    let script = program(dir.path(), "client.lua", &source);
    let out = run(&ns, &[script.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(server.join().unwrap(), ":3.5\r\n:hi\r\n:true\r\n");
    assert_eq!(
        out.lines_of_task(0),
        [
            "low port 1, high port 1",
            "two start bytes 1, three end bytes 1, byte 256 1, bad address 1",
            "open 0, again 3",
            "check 0, unknown 2",
            "tx 0 3.5",
            "tx table 0, bool 0",
            "tx nil 1, 1025 bytes 6, bad table 1",
            "rx 0 pong 4",
            "close 0, tx closed 2, rx closed 2",
            "clear unknown 2, closeall 0",
        ],
        "{}",
        out.stderr
    );
}

/// A task polling Rx with no other call for 10 watchdog periods is alive: each call beats.
/// (300 ms: a shorter watchdog can starve on a loaded 2-core machine, whatever the program.)
#[test]
fn a_task_polling_rx_outlives_its_watchdog() {
    let ns = unique_ns("fp-watchdog");
    let dir = tempfile::tempdir().unwrap();
    let port = freeport_port();
    program(
        dir.path(),
        "poll.lua",
        &format!(
            "FreePort.Eth.OpenAsServer(1, {port}, nil, \";\")\n\
             local polls = 0\n\
             repeat local rc, data = FreePort.Eth.Rx(1); polls = polls + 1 until data == \"stop\"\n\
             Print(\"stopped after more than 1000 polls: %s\", tostring(polls > 1000))\n"
        ),
    );
    let machine = dir.path().join("machine.toml");
    std::fs::write(
        &machine,
        "[[axes]]\n[[tasks]]\nid = 0\nprogram = \"poll.lua\"\nautorun = true\nwatchdog_ms = 300\n",
    )
    .unwrap();
    let child = start_run(&ns, &["--config", machine.to_str().unwrap()]);
    let mut peer = connect(port);
    std::thread::sleep(Duration::from_millis(3000));
    peer.write_all(b"stop;").unwrap();
    // The task has ended when its pid is 0, or the controller has ended with it.
    let namespace = ipc::Namespace::new(&ns).unwrap();
    let ended = || {
        let Ok(mut monitor) = ipc::Monitor::open(&namespace) else { return true };
        monitor.snapshot().map_or(true, |s| s.tasks[0].pid == 0)
    };
    assert!(eventually(Duration::from_secs(20), ended), "the task ends");
    let out = shut_down(child);
    assert_eq!(out.lines_of_task(0), ["stopped after more than 1000 polls: true"], "{}\n{}", out.stdout, out.stderr);
    assert!(!out.stderr.contains("4102"), "no watchdog alarm: {}", out.stderr);
}

/// A killed task's listening port, with a connection on it, can be opened again at once.
#[test]
fn killing_a_task_frees_its_port_for_the_next_run() {
    let dir = tempfile::tempdir().unwrap();
    let port = freeport_port();
    let script = program(
        dir.path(),
        "serve.lua",
        &format!(
            "Print(\"open %d\", FreePort.Eth.OpenAsServer(1, {port}, nil, \";\"))\n\
             while true do\n  local rc, data, n = FreePort.Eth.Rx(1)\n  if n > 0 then FreePort.Eth.Tx(1, data) end\n  Sleep(1)\nend\n"
        ),
    );
    let ns = unique_ns("fp-kill");
    let child = start_run(&ns, &[script.to_str().unwrap()]);
    let mut peer = connect(port);
    peer.write_all(b"ping;").unwrap();
    assert_eq!(read_exactly(&mut peer, 5), "ping;");
    let namespace = ipc::Namespace::new(&ns).unwrap();
    let mut monitor = ipc::Monitor::open(&namespace).unwrap();
    let pid = monitor.snapshot().unwrap().tasks[0].pid;
    assert_ne!(pid, 0);
    // SAFETY: killing the task's script process.
    unsafe { libc::kill(pid as i32, libc::SIGKILL) };
    let mut rest = Vec::new();
    assert_eq!(peer.read_to_end(&mut rest).unwrap(), 0, "the kill closed the connection");
    let _ = shut_down(child);
    let ns = unique_ns("fp-kill2");
    let child = start_run(&ns, &[script.to_str().unwrap()]);
    let mut peer = connect(port);
    peer.write_all(b"again;").unwrap();
    assert_eq!(read_exactly(&mut peer, 6), "again;");
    let out = shut_down(child);
    assert_eq!(out.lines_of_task(0).first().map(String::as_str), Some("open 0"), "{}\n{}", out.stdout, out.stderr);
}

/// The commented example, on a free port, answered by `nc` as the README shows.
#[test]
fn the_echo_example_answers_nc_and_quits() {
    let ns = unique_ns("fp-example");
    let dir = tempfile::tempdir().unwrap();
    let port = freeport_port();
    let example = std::fs::read_to_string(repo_path("scripts/examples/freeport_echo.lua")).unwrap();
    assert!(example.contains("local PORT = 9000\n"));
    let script =
        program(dir.path(), "echo.lua", &example.replace("local PORT = 9000\n", &format!("local PORT = {port}\n")));
    let child = start_run(&ns, &[script.to_str().unwrap()]);
    drop(connect(port));
    // nc sends both frames; the program answers the first and closes on "quit", which ends nc.
    let nc = std::process::Command::new(debian_tool("nc"))
        .args(["-N", "-w", "10", "127.0.0.1", &port.to_string()])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("start nc");
    nc.stdin.as_ref().unwrap().write_all(b"hi;quit;").unwrap();
    let nc = nc.wait_with_output().unwrap();
    assert_eq!(String::from_utf8_lossy(&nc.stdout), "echo:hi;");
    let out = finish(child, Duration::from_secs(20));
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(
        out.lines_of_task(0),
        [format!("echo server on port {port}"), "echo server done".to_string()],
        "{}",
        out.stderr
    );
}

/// A Lua client against `nc -l`: nc prints the framed message and its answer reaches Rx.
#[test]
fn a_lua_client_talks_to_an_nc_server() {
    let ns = unique_ns("fp-ncserver");
    let dir = tempfile::tempdir().unwrap();
    let port = freeport_port();
    let mut nc = std::process::Command::new(debian_tool("nc"))
        .args(["-l", "127.0.0.1", &port.to_string()])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("start nc -l");
    let script = program(
        dir.path(),
        "client.lua",
        &format!(
            r#"
            local rc
            repeat rc = FreePort.Eth.OpenAsClient(3, "127.0.0.1", {port}, nil, CR_LF); Sleep(20) until rc == 0
            Print("tx %d", (FreePort.Eth.Tx(3, "barcode 4711")))
            local data, n
            repeat rc, data, n = FreePort.Eth.Rx(3); Sleep(1) until n > 0 or rc ~= 0
            Print("rx %d %s %d", rc, data, n)
            "#
        ),
    );
    let child = start_run(&ns, &[script.to_str().unwrap()]);
    let mut stdout = nc.stdout.take().unwrap();
    let mut got = [0u8; 14];
    stdout.read_exact(&mut got).expect("nc prints the frame");
    assert_eq!(&got, b"barcode 4711\r\n");
    nc.stdin.as_ref().unwrap().write_all(b"ok\r\n").unwrap();
    let out = finish(child, Duration::from_secs(20));
    let _ = nc.kill();
    let _ = nc.wait();
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(out.lines_of_task(0), ["tx 0", "rx 0 ok 2"], "{}", out.stderr);
}

/// 200 clients at a server session that has a peer: each is closed at once (a session has
/// one peer), the peer is still served, and after it leaves the next client is.
#[test]
fn two_hundred_clients_at_once_are_closed_and_the_peer_is_served() {
    let dir = tempfile::tempdir().unwrap();
    let port = freeport_port();
    let script = program(
        dir.path(),
        "serve.lua",
        &format!(
            "FreePort.Eth.OpenAsServer(1, {port}, nil, \";\")\n\
             while true do\n  local rc, data, n = FreePort.Eth.Rx(1)\n  if n > 0 then FreePort.Eth.Tx(1, data) end\n  Sleep(1)\nend\n"
        ),
    );
    let ns = unique_ns("fp-flood");
    let child = start_run(&ns, &[script.to_str().unwrap()]);
    let mut peer = connect(port);
    peer.write_all(b"first;").unwrap();
    assert_eq!(read_exactly(&mut peer, 6), "first;");
    let crowd: Vec<TcpStream> = (0..200).map(|_| TcpStream::connect(("127.0.0.1", port)).unwrap()).collect();
    for mut extra in crowd {
        extra.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
        let mut rest = Vec::new();
        assert_eq!(extra.read_to_end(&mut rest).map(|_| rest.len()).unwrap_or(0), 0, "closed without data");
    }
    peer.write_all(b"still;").unwrap();
    assert_eq!(read_exactly(&mut peer, 6), "still;");
    drop(peer);
    // A client that half-closes after its requests still gets every answer.
    let mut next = connect(port);
    next.write_all(b"next;tail;").unwrap();
    next.shutdown(std::net::Shutdown::Write).unwrap();
    let mut answers = String::new();
    next.read_to_string(&mut answers).unwrap();
    assert_eq!(answers, "next;tail;");
    let out = shut_down(child);
    assert!(!out.stderr.contains("panicked"), "{}", out.stderr);
}

/// `[freeport] bind` sets where programs' servers listen: on 127.0.0.2 the server answers
/// there and not on 127.0.0.1.
#[test]
fn the_machine_file_sets_the_servers_address() {
    let ns = unique_ns("fp-bind");
    let dir = tempfile::tempdir().unwrap();
    let port = freeport_port();
    program(
        dir.path(),
        "serve.lua",
        &format!(
            "Print(\"open %d\", FreePort.Eth.OpenAsServer(1, {port}, nil, \";\"))\n\
             while true do\n  local rc, data, n = FreePort.Eth.Rx(1)\n  if n > 0 then FreePort.Eth.Tx(1, data) end\n  Sleep(1)\nend\n"
        ),
    );
    let machine = dir.path().join("machine.toml");
    std::fs::write(
        &machine,
        "[freeport]\nbind = \"127.0.0.2\"\n[[axes]]\n[[tasks]]\nid = 0\nprogram = \"serve.lua\"\nautorun = true\n",
    )
    .unwrap();
    let child = start_run(&ns, &["--config", machine.to_str().unwrap()]);
    let mut peer = None;
    assert!(
        eventually(Duration::from_secs(20), || {
            peer = TcpStream::connect(("127.0.0.2", port)).ok();
            peer.is_some()
        }),
        "the server listens on 127.0.0.2:{port}"
    );
    let mut peer = peer.unwrap();
    peer.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
    peer.write_all(b"there;").unwrap();
    assert_eq!(read_exactly(&mut peer, 6), "there;");
    assert!(TcpStream::connect(("127.0.0.1", port)).is_err(), "nothing listens on 127.0.0.1:{port}");
    let out = shut_down(child);
    assert_eq!(out.lines_of_task(0).first().map(String::as_str), Some("open 0"), "{}", out.stderr);
}

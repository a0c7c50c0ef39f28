//! DRL FreePort.Serial and Modbus RTU on serial port 1, the controller's pseudo-terminal
//! (DXMC 8.2, 8.3), against clients this project did not write: pyserial, socat, mbpoll.
//! Each controller has its own namespace (and so its own port socket) and its link to
//! the pseudo-terminal in its own temp dir.

mod common;

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use common::{debian_tool, finish, program, pymodbus_python, repo_path, run, start_run, unique_ns};

/// `python tests/python/serial_peer.py LINK SCENARIO` (pyserial), started.
fn peer(link: &Path, scenario: &str) -> std::process::Child {
    peer_with(link, &[scenario])
}

/// The peer with more arguments (`late`: it opens the line a second after it appears).
fn peer_with(link: &Path, args: &[&str]) -> std::process::Child {
    Command::new(pymodbus_python())
        .arg(repo_path("tests/python/serial_peer.py"))
        .arg(link)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start the pyserial peer")
}

fn peer_done(child: std::process::Child) {
    let out = finish(child, Duration::from_secs(60));
    assert!(out.status.success(), "pyserial peer: {}{}", out.stdout, out.stderr);
}

/// Frames from a pyserial peer: delimiters stripped, two in one write, one split across
/// writes, one too long, garbage before a good one, a peer on the wrong baud rate; the
/// peer gets Tx's frames with the framing added.
#[test]
fn freeport_frames_between_a_script_and_pyserial() {
    let ns = unique_ns("serial-frames");
    let dir = tempfile::tempdir().unwrap();
    let link = dir.path().join("ttyS1");
    let script = program(
        dir.path(),
        "frames.lua",
        r#"local rc, word = FreePort.Serial.Init(1, ":", CR_LF, 0x17)
my_print(string.format("init %d 0x%08X", rc, word))
-- pyserial's open() flushes what the line held: say READY until the peer answers.
repeat FreePort.Serial.Tx(1, "READY"); Sleep(20); local _, heard = FreePort.Serial.Rx(1) until heard == "go"
FreePort.Serial.Tx(1, "GO")
local acks = 0
while true do
  local rc, data, n = FreePort.Serial.Rx(1)
  if rc ~= 0 then
    my_print(string.format("rc %d", rc))
    if rc == 11 then FreePort.Serial.Tx(1, "line error") end
  elseif n > 0 then
    my_print(string.format("rx %s %d", data, n))
    if data == "END" then break end
    acks = acks + 1
    FreePort.Serial.Tx(1, "ack " .. acks)
  end
  Sleep(1)
end
"#,
    );
    let pyserial = peer(&link, "frames");
    let out = run(&ns, &["--serial-link", link.to_str().unwrap(), script.to_str().unwrap()]);
    peer_done(pyserial);
    assert_eq!(
        out.lines_of_task(0),
        [
            "init 0 0x0021003A",
            "rx one 3",
            "rx two 3",
            "rx split 5",
            "rc 6",
            "rx after long 10",
            "rx good 4",
            "rc 11",
            "rx END 3"
        ],
        "{}",
        out.stderr
    );
    assert!(out.stderr.contains("serial port 1: /dev/pts/"), "{}", out.stderr);
    assert!(!link.exists(), "the link goes with the controller");
}

/// DXMC 8.3's self-test as printed, with the line looped back, prints the manual's line.
#[test]
fn the_manual_s_self_test_prints_its_line() {
    let ns = unique_ns("serial-selftest");
    let out = run(
        &ns,
        &[
            "--config",
            repo_path("scripts/examples/serial_loopback.toml").to_str().unwrap(),
            repo_path("scripts/examples/serial_selftest.lua").to_str().unwrap(),
        ],
    );
    assert_eq!(out.lines_of_task(0), [">Rx: Rtn:0x0 Data:3.1415"], "{}", out.stderr);
}

/// Wrong arguments and a port in the wrong mode get codes, never a Lua error or a hang.
#[test]
fn bad_calls_get_codes() {
    let ns = unique_ns("serial-codes");
    let dir = tempfile::tempdir().unwrap();
    let script = program(
        dir.path(),
        "codes.lua",
        r#"local function show(...) my_print(table.concat({...}, " ")) end
show("rx before init", (FreePort.Serial.Rx(1)))
show("tx before init", (FreePort.Serial.Tx(1, "x")))
show("port 2", FreePort.Serial.Init(2, nil, CR_LF), (FreePort.Serial.Tx(2, "x")), (FreePort.Serial.Rx(2)))
show("rtu code", FreePort.Serial.Init(1, nil, CR_LF, 0x16))
show("two end bytes", FreePort.Serial.Init(1, nil, "ab"))
show("init", FreePort.Serial.Init(1, nil, CR_LF, 0x0C))
show("257 bytes", (FreePort.Serial.Tx(1, string.rep("x", 257))))
show("256 bytes", (FreePort.Serial.Tx(1, string.rep("x", 256))))
show("nil", (FreePort.Serial.Tx(1, nil)))
"#,
    );
    let out = run(&ns, &[script.to_str().unwrap()]);
    assert_eq!(
        out.lines_of_task(0),
        [
            "rx before init 13",
            "tx before init 13",
            "port 2 9 9 9",
            "rtu code 1 0",
            "two end bytes 1 0",
            "init 0 2097152",
            "257 bytes 6",
            "256 bytes 0",
            "nil 1"
        ],
        "{}",
        out.stderr
    );

    // Without a serial port: code 10.
    let machine = dir.path().join("machine.toml");
    std::fs::write(&machine, "[serial]\nenabled = false\n").unwrap();
    let none = program(dir.path(), "none.lua", "my_print(tostring((FreePort.Serial.Rx(1))))\n");
    let out = run(&unique_ns("serial-none"), &["--config", machine.to_str().unwrap(), none.to_str().unwrap()]);
    assert_eq!(out.lines_of_task(0), ["10"], "{}", out.stderr);
    assert!(!out.stderr.contains("serial port 1:"), "{}", out.stderr);
}

/// A task that does nothing but poll Rx is alive for a watchdog far shorter than its loop.
#[test]
fn a_task_polling_rx_outlives_its_watchdog() {
    polling_rx_outlives_its_watchdog(&["stop"]);
}

/// The same with a peer that opens the line a second late, as on a loaded machine:
/// pyserial's open flushes what the program sent before it, so the program must say
/// READY until it is answered (a single READY was lost and the test waited 60 s).
#[test]
fn a_peer_that_opens_the_line_late_still_meets_the_program() {
    polling_rx_outlives_its_watchdog(&["stop", "late"]);
}

fn polling_rx_outlives_its_watchdog(peer_args: &[&str]) {
    let ns = unique_ns("serial-poll");
    let dir = tempfile::tempdir().unwrap();
    let link = dir.path().join("ttyS1");
    program(
        dir.path(),
        "poll.lua",
        r#"FreePort.Serial.Init(1, ":", CR_LF)
-- pyserial's open() flushes what the line held: say READY until the peer answers.
repeat FreePort.Serial.Tx(1, "READY"); Sleep(20); local _, heard = FreePort.Serial.Rx(1) until heard == "go"
FreePort.Serial.Tx(1, "GO")
local polls = 0
repeat local rc, data = FreePort.Serial.Rx(1); polls = polls + 1 until data == "stop"
my_print("stopped after more than 100 polls: " .. tostring(polls > 100))
"#,
    );
    let machine = dir.path().join("machine.toml");
    std::fs::write(
        &machine,
        "[serial]\nprotocol = 0x17\n[[tasks]]\nid = 0\nprogram = \"poll.lua\"\nautorun = true\nwatchdog_ms = 100\n",
    )
    .unwrap();
    let pyserial = peer_with(&link, peer_args);
    let out = run(&ns, &["--config", machine.to_str().unwrap(), "--serial-link", link.to_str().unwrap()]);
    peer_done(pyserial);
    assert_eq!(out.lines_of_task(0), ["stopped after more than 100 polls: true"], "{}", out.stderr);
    assert!(!out.stderr.contains("4102"), "no watchdog alarm: {}", out.stderr);
}

/// The barcode reader example with socat as the scanner.
#[test]
fn the_barcode_reader_reads_codes_from_socat() {
    let socat = debian_tool("socat");
    let ns = unique_ns("serial-barcode");
    let dir = tempfile::tempdir().unwrap();
    let link = dir.path().join("ttyS1");
    let example = repo_path("scripts/examples/barcode_reader.lua");
    let mut child = start_run(&ns, &["--serial-link", link.to_str().unwrap(), example.to_str().unwrap()]);
    let stdout = child.stdout.take().unwrap();
    let (lines_tx, lines) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            let _ = lines_tx.send(line);
        }
    });
    let mut seen = Vec::new();
    // The reader has cleared its buffer once it says so: the codes come after.
    while !seen.last().is_some_and(|l: &String| l.contains("reading codes")) {
        seen.push(lines.recv_timeout(Duration::from_secs(30)).expect("the reader starts"));
    }
    let status = Command::new(socat)
        .args(["-u", "STDIN"])
        .arg(format!("{},raw,echo=0,b38400", link.display()))
        .stdin(Stdio::piped())
        .spawn()
        .and_then(|mut socat| {
            use std::io::Write;
            socat.stdin.take().unwrap().write_all(b"A123\r\nB456\r\nEND\r\n")?;
            socat.wait()
        })
        .expect("socat");
    assert!(status.success());
    while let Ok(line) = lines.recv_timeout(Duration::from_secs(30)) {
        seen.push(line);
    }
    let out = finish(child, Duration::from_secs(30));
    assert_eq!(
        seen,
        [
            "[task 0] reading codes on serial port 1 (format word 0x00200000)",
            "[task 0] code 1: A123",
            "[task 0] code 2: B456",
            "[task 0] 2 codes read"
        ],
        "{}",
        out.stderr
    );
}

/// `mbpoll -m rtu ARGS LINK VALUES` on the link of a `luamotion serve` (values: a write).
fn mbpoll_rtu(link: &Path, args: &[&str], values: &[&str]) -> String {
    let out = Command::new(debian_tool("mbpoll"))
        .args(["-m", "rtu", "-b", "38400", "-P", "none", "-a", "1", "-0", "-1", "-o", "2"])
        .args(args)
        .arg(link)
        .args(values)
        .output()
        .expect("mbpoll");
    format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr))
}

fn mbpoll_tcp(port: u16, args: &[&str]) -> String {
    let out = Command::new(debian_tool("mbpoll"))
        .args(["-m", "tcp", "-p", &port.to_string(), "-a", "1", "-0", "-1"])
        .args(args)
        .arg("127.0.0.1")
        .output()
        .expect("mbpoll");
    format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr))
}

/// The `[ref]: value` lines of mbpoll's output.
fn values(output: &str) -> Vec<String> {
    output.lines().filter(|l| l.starts_with('[')).map(|l| l.split_whitespace().collect::<Vec<_>>().join(" ")).collect()
}

/// Modbus RTU on the pseudo-terminal answers from the same registers as Modbus TCP: FC 03,
/// 06 and 16, exception 2 for an illegal address; pyserial sends a bad CRC (no answer),
/// garbage before a frame (answered), a frame for another station (no answer).
#[test]
fn modbus_rtu_on_the_pty_serves_the_tcp_registers() {
    let ns = unique_ns("serial-rtu");
    let dir = tempfile::tempdir().unwrap();
    let link = dir.path().join("ttyS1");
    let server = common::serve::serve(&ns, dir.path(), &["--serial-link", link.to_str().unwrap()]);
    assert!(common::eventually(Duration::from_secs(10), || link.exists()), "{}", server.stderr());

    let program_flow = ["-r", "0x6B00", "-c", "7"];
    let by_rtu = values(&mbpoll_rtu(&link, &program_flow, &[]));
    assert_eq!(by_rtu.len(), 7, "{by_rtu:?}");
    assert!(by_rtu.contains(&"[27395]: 100".to_string()), "run speed 100 %: {by_rtu:?}");
    assert_eq!(by_rtu, values(&mbpoll_tcp(server.port, &program_flow)));

    // FC 06 and FC 16 on DV, read back over TCP.
    let single = mbpoll_rtu(&link, &["-r", "32"], &["4321"]);
    assert!(single.contains("Written 1 references"), "{single}");
    let multiple = mbpoll_rtu(&link, &["-r", "33"], &["11", "22"]);
    assert!(multiple.contains("Written 2 references"), "{multiple}");
    assert_eq!(values(&mbpoll_tcp(server.port, &["-r", "32", "-c", "3"])), ["[32]: 4321", "[33]: 11", "[34]: 22"]);

    // 0x6B0F is no register: exception 2.
    let refused = mbpoll_rtu(&link, &["-r", "0x6B0F", "-c", "1"], &[]);
    assert!(refused.contains("Illegal data address"), "{refused}");

    let pyserial = peer(&link, "rtu");
    peer_done(pyserial);
    // Still serving after all that.
    assert_eq!(values(&mbpoll_rtu(&link, &["-r", "32", "-c", "1"], &[])), ["[32]: 4321"]);
}

/// The Modbus ASCII codes of parameter 5-1 are served on the port too (here 0x15, 8,N,1).
#[test]
fn modbus_ascii_on_the_pty() {
    let ns = unique_ns("serial-ascii");
    let dir = tempfile::tempdir().unwrap();
    let link = dir.path().join("ttyS1");
    let machine = dir.path().join("machine.toml");
    std::fs::write(&machine, "[serial]\nprotocol = 0x15\n").unwrap();
    let server = common::serve::serve(
        &ns,
        dir.path(),
        &["--config", machine.to_str().unwrap(), "--serial-link", link.to_str().unwrap()],
    );
    peer_done(peer(&link, "ascii"));
    assert!(server.stderr().contains("protocol 0x15"), "{}", server.stderr());
}

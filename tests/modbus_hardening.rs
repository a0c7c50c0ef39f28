//! The Modbus TCP server under abuse, against the real `luamotion serve`: answers as the
//! Modbus Application Protocol (v1.1b3) wants for requests it does not serve or cannot
//! decode, bounded connections and idle time, and no end when the process runs out of
//! file descriptors. Raw sockets, so that any byte sequence can be sent.

mod common;

use std::io::{ErrorKind, Read, Write};
use std::net::{Shutdown, TcpStream};
use std::path::{Path, PathBuf};
use std::time::Duration;

use common::serve::{Serving, serve};
use common::{eventually, unique_ns};

/// How long a client waits for an answer or a close before calling it missing. Far
/// longer than any idle timeout a test sets, far shorter than the default (60 s).
const PATIENCE: Duration = Duration::from_secs(15);

/// A machine file with these `[modbus]` lines.
fn machine(dir: &Path, modbus: &str) -> PathBuf {
    let path = dir.join("machine.toml");
    std::fs::write(&path, format!("[modbus]\n{modbus}\n")).unwrap();
    path
}

fn serve_with(tag: &str, dir: &Path, modbus: &str) -> Serving {
    let config = machine(dir, modbus);
    serve(&unique_ns(tag), dir, &["--config", config.to_str().unwrap()])
}

fn connect(port: u16) -> TcpStream {
    let stream = TcpStream::connect(("127.0.0.1", port)).expect("connect");
    stream.set_read_timeout(Some(PATIENCE)).unwrap();
    stream
}

/// An MBAP frame (transaction 0x1234, unit 1) around `pdu`.
fn frame(pdu: &[u8]) -> Vec<u8> {
    let mut frame = vec![0x12, 0x34, 0, 0];
    frame.extend((pdu.len() as u16 + 1).to_be_bytes());
    frame.push(1);
    frame.extend(pdu);
    frame
}

/// Sends `pdu` and returns the response PDU, or `None` if the server closed instead.
fn request(stream: &mut TcpStream, pdu: &[u8]) -> Option<Vec<u8>> {
    stream.write_all(&frame(pdu)).ok()?;
    let mut header = [0u8; 7];
    stream.read_exact(&mut header).ok()?;
    assert_eq!(&header[..4], &[0x12, 0x34, 0, 0], "transaction and protocol id echoed");
    assert_eq!(header[6], 1, "unit id echoed");
    let mut pdu = vec![0u8; u16::from_be_bytes([header[4], header[5]]) as usize - 1];
    stream.read_exact(&mut pdu).ok()?;
    Some(pdu)
}

/// FC 03 of the run speed (0x6B03): a request every server state answers.
const READ_SPEED: [u8; 5] = [0x03, 0x6B, 0x03, 0x00, 0x01];

fn answers(stream: &mut TcpStream) -> bool {
    request(stream, &READ_SPEED).is_some_and(|pdu| pdu == [0x03, 2, 0, 100])
}

/// A fresh connection is answered (retried until `PATIENCE` runs out).
fn serves_again(port: u16) -> bool {
    eventually(PATIENCE, || {
        TcpStream::connect(("127.0.0.1", port)).is_ok_and(|mut s| {
            s.set_read_timeout(Some(Duration::from_secs(2))).unwrap();
            answers(&mut s)
        })
    })
}

/// The server closed the connection (end of stream or reset) within `PATIENCE`.
fn closed_by_server(stream: &mut TcpStream) -> bool {
    let mut byte = [0u8; 1];
    match stream.read(&mut byte) {
        Ok(0) => true,
        Ok(_) => false,
        Err(e) => matches!(e.kind(), ErrorKind::ConnectionReset | ErrorKind::ConnectionAborted),
    }
}

#[test]
fn unsupported_function_codes_get_exception_01_and_the_connection_stays() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve(&unique_ns("fc01"), dir.path(), &[]);
    let mut stream = connect(server.port);
    let requests: [&[u8]; 12] = [
        &[0x01, 0x00, 0x00, 0x00, 0x01],          // read coils
        &[0x04, 0x00, 0x00, 0x00, 0x01],          // read input registers
        &[0x05, 0x00, 0x00, 0xFF, 0x00],          // write single coil
        &[0x17, 0, 0, 0, 1, 0, 0, 0, 1, 2, 0, 0], // read/write multiple registers
        &[0x2B, 0x0E, 0x01, 0x00],                // read device identification
        &[0x2B, 0x0D, 0x00],                      // another MEI type
        &[0x41],                                  // user-defined, no data
        &[0x41, 0x01, 0x02, 0x03],                // user-defined with data
        &[0x80, 0x00, 0x00, 0x00, 0x01],          // codes >= 0x80 are exception codes, never requests
        &[0x83, 0x6B, 0x03, 0x00, 0x01],
        &[0xC1],
        &[0xFF, 0xFF],
    ];
    for pdu in requests {
        let answer = request(&mut stream, pdu);
        assert_eq!(answer, Some(vec![pdu[0] | 0x80, 0x01]), "FC 0x{:02X}: exception 01 (ILLEGAL FUNCTION)", pdu[0]);
        assert!(answers(&mut stream), "the connection serves on after FC 0x{:02X}", pdu[0]);
    }
}

#[test]
fn malformed_requests_of_served_functions_get_exception_03_and_the_connection_stays() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve(&unique_ns("fc03"), dir.path(), &[]);
    let mut stream = connect(server.port);
    let requests: [&[u8]; 11] = [
        &[0x03, 0x6B, 0x03],                               // short PDU
        &[0x03],                                           // function code alone
        &[0x03, 0x6B, 0x03, 0x00, 0x01, 0x00],             // a byte too many
        &[0x03, 0x6B, 0x03, 0x00, 0x00],                   // quantity 0
        &[0x03, 0x6B, 0x03, 0x00, 0x7E],                   // quantity 126 (> 125)
        &[0x06, 0x00, 0x10, 0x00],                         // short PDU
        &[0x06, 0x00, 0x10, 0x00, 0x01, 0x02],             // a byte too many
        &[0x10, 0x00, 0x10, 0x00, 0x01, 0x04, 0x00, 0x01], // byte count 4 for one register
        &[0x10, 0x00, 0x10, 0x00, 0x02, 0x04, 0x00, 0x01], // byte count 4, two bytes sent
        &[0x10, 0x00, 0x10, 0x00, 0x00, 0x00],             // quantity 0
        &[0x10, 0x00, 0x10, 0x80, 0x00, 0x00],             // quantity 0x8000 (2 x quantity overflows)
    ];
    for pdu in requests {
        let answer = request(&mut stream, pdu);
        assert_eq!(answer, Some(vec![pdu[0] | 0x80, 0x03]), "{pdu:02X?}: exception 03 (ILLEGAL DATA VALUE)");
        assert!(answers(&mut stream), "the connection serves on after {pdu:02X?}");
    }
    // Well-formed requests still get their own answers.
    assert_eq!(request(&mut stream, &[0x06, 0x00, 0x10, 0x12, 0x34]), Some(vec![0x06, 0x00, 0x10, 0x12, 0x34]));
    let write = [0x10, 0x00, 0x11, 0x00, 0x02, 0x04, 0xAB, 0xCD, 0x00, 0x07];
    assert_eq!(request(&mut stream, &write), Some(vec![0x10, 0x00, 0x11, 0x00, 0x02]));
    let read = request(&mut stream, &[0x03, 0x00, 0x10, 0x00, 0x03]);
    assert_eq!(read, Some(vec![0x03, 6, 0x12, 0x34, 0xAB, 0xCD, 0x00, 0x07]));
}

#[test]
fn headers_that_cannot_be_answered_close_only_their_connection() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve(&unique_ns("mbap"), dir.path(), &[]);
    let mut bystander = connect(server.port);
    let headers: [(&str, [u8; 7]); 4] = [
        ("protocol id 1", [0, 1, 0, 1, 0, 6, 1]),
        ("length 255, more than a PDU can have", [0, 1, 0, 0, 0, 255, 1]),
        ("length 0xFFFF", [0, 1, 0, 0, 0xFF, 0xFF, 1]),
        ("length 1, no function code", [0, 1, 0, 0, 0, 1, 1]),
    ];
    for (what, header) in headers {
        let mut stream = connect(server.port);
        stream.write_all(&header).unwrap();
        assert!(closed_by_server(&mut stream), "{what}: closed at once (the idle timeout is 60 s)");
        assert!(answers(&mut bystander), "{what}: another connection is served on");
    }
}

#[test]
fn idle_and_half_sent_connections_are_closed() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve_with("idle", dir.path(), "idle_timeout_ms = 500");
    let mut silent = connect(server.port);
    let mut half_header = connect(server.port);
    half_header.write_all(&[0x12, 0x34, 0x00]).unwrap();
    let mut half_pdu = connect(server.port);
    half_pdu.write_all(&frame(&READ_SPEED)[..9]).unwrap();
    // One byte every 200 ms: never 500 ms without a byte, yet no whole request in 500 ms.
    let mut trickle = connect(server.port);
    let trickler = {
        let mut writer = trickle.try_clone().unwrap();
        std::thread::spawn(move || {
            for byte in frame(&READ_SPEED).into_iter().cycle().take(100) {
                if writer.write_all(&[byte]).is_err() {
                    return;
                }
                std::thread::sleep(Duration::from_millis(200));
            }
        })
    };
    // A client that asks every 100 ms is not idle.
    let mut busy = connect(server.port);
    for _ in 0..20 {
        assert!(answers(&mut busy), "a connection in use stays open");
        std::thread::sleep(Duration::from_millis(100));
    }
    for (what, stream) in [("silent", &mut silent), ("half a header", &mut half_header), ("half a PDU", &mut half_pdu)]
    {
        assert!(closed_by_server(stream), "{what}: closed by the idle timeout");
    }
    assert!(closed_by_server(&mut trickle), "a byte at a time: closed by the idle timeout");
    let _ = trickle.shutdown(Shutdown::Both);
    trickler.join().unwrap();
}

#[test]
fn connections_past_the_limit_are_closed_and_the_rest_served() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve_with("limit", dir.path(), "max_connections = 4");
    let mut served: Vec<TcpStream> = (0..4).map(|_| connect(server.port)).collect();
    for stream in &mut served {
        assert!(answers(stream), "within the limit");
    }
    for _ in 0..3 {
        let mut excess = connect(server.port);
        assert!(closed_by_server(&mut excess), "a fifth connection is closed at once");
    }
    for stream in &mut served {
        assert!(answers(stream), "the four are served on");
    }
    drop(served.pop());
    assert!(serves_again(server.port), "a freed place is taken again");
    assert!(
        eventually(PATIENCE, || server.stderr().contains("modbus.max_connections")),
        "the refusals are logged: {}",
        server.stderr()
    );
}

#[test]
fn silent_connections_at_the_limit_give_their_places_back_after_the_idle_timeout() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve_with("limit-idle", dir.path(), "max_connections = 3\nidle_timeout_ms = 2000");
    // Never closed by this client: only the server can free their places.
    let mut squatters: Vec<TcpStream> = (0..3).map(|_| connect(server.port)).collect();
    let mut excess = connect(server.port);
    let mut byte = [0u8; 1];
    excess.write_all(&frame(&READ_SPEED)).unwrap();
    assert!(matches!(excess.read(&mut byte), Ok(0) | Err(_)), "no answer past the limit");
    for stream in &mut squatters {
        assert!(closed_by_server(stream), "closed by the idle timeout");
    }
    assert!(serves_again(server.port), "their places are free again");
}

/// Open file descriptors of a process.
fn open_fds(pid: u32) -> u64 {
    std::fs::read_dir(format!("/proc/{pid}/fd")).unwrap().count() as u64
}

/// Lowers a running process' soft RLIMIT_NOFILE, as `prlimit --pid` does.
fn limit_fds(pid: u32, soft: u64) {
    let mut old = libc::rlimit { rlim_cur: 0, rlim_max: 0 };
    // SAFETY: prlimit(2) on our own child with valid pointers.
    let rc = unsafe { libc::prlimit(pid as i32, libc::RLIMIT_NOFILE, std::ptr::null(), &mut old) };
    assert_eq!(rc, 0, "read RLIMIT_NOFILE");
    let new = libc::rlimit { rlim_cur: soft, rlim_max: old.rlim_max };
    let rc = unsafe { libc::prlimit(pid as i32, libc::RLIMIT_NOFILE, &new, std::ptr::null_mut()) };
    assert_eq!(rc, 0, "set RLIMIT_NOFILE");
}

/// Connections that hold the server's file descriptors (each sends half a header).
fn flood(port: u16, count: usize) -> Vec<TcpStream> {
    (0..count)
        .map(|_| {
            let mut stream = connect(port);
            let _ = stream.write_all(&[0x12]);
            stream
        })
        .collect()
}

const EMFILE: &str = "Too many open files";

#[test]
fn running_out_of_file_descriptors_does_not_end_the_server() {
    let dir = tempfile::tempdir().unwrap();
    // No connection limit to speak of: the file descriptors run out first.
    let server = serve_with("emfile", dir.path(), "max_connections = 4096");
    let mut keeper = connect(server.port);
    assert!(answers(&mut keeper));
    limit_fds(server.pid(), open_fds(server.pid()) + 8);
    let flood = flood(server.port, 40);
    assert!(
        eventually(PATIENCE, || server.stderr().contains(EMFILE)),
        "the flood exhausts the descriptors: {}",
        server.stderr()
    );
    assert!(answers(&mut keeper), "a connection made before is served on");
    drop(flood);
    assert!(serves_again(server.port), "served again once the flood is gone: {}", server.stderr());
    assert!(answers(&mut keeper));
}

#[test]
fn a_flood_that_never_closes_is_drained_by_the_idle_timeout() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve_with("emfile-idle", dir.path(), "max_connections = 4096\nidle_timeout_ms = 500");
    limit_fds(server.pid(), open_fds(server.pid()) + 8);
    // Held open until the end of the test: the server must free the descriptors itself.
    let _flood = flood(server.port, 40);
    assert!(
        eventually(PATIENCE, || server.stderr().contains(EMFILE)),
        "the flood exhausts the descriptors: {}",
        server.stderr()
    );
    assert!(serves_again(server.port), "served again while the flood is held: {}", server.stderr());
}

#[test]
fn serve_listens_on_localhost_unless_told_otherwise() {
    let dir = tempfile::tempdir().unwrap();
    let server = serve(&unique_ns("bind"), dir.path(), &[]);
    assert!(server.address.starts_with("127.0.0.1:"), "no machine file: {}", server.address);
    drop(server);
    let server = serve_with("bind-file", dir.path(), "port = 0");
    assert!(server.address.starts_with("127.0.0.1:"), "a machine file without bind: {}", server.address);
    drop(server);
    // 127.0.0.2 is loopback too: an explicit choice that exposes nothing in a test.
    let server = serve_with("bind-chosen", dir.path(), "bind = \"127.0.0.2\"");
    assert!(server.address.starts_with("127.0.0.2:"), "the machine file's bind: {}", server.address);
    drop(server);
    let config = machine(dir.path(), "bind = \"127.0.0.2\"");
    let args = ["--config", config.to_str().unwrap(), "--bind", "127.0.0.3"];
    let server = serve(&unique_ns("bind-flag"), dir.path(), &args);
    assert!(server.address.starts_with("127.0.0.3:"), "--bind before the machine file: {}", server.address);
    let mut stream = TcpStream::connect(("127.0.0.3", server.port)).unwrap();
    stream.set_read_timeout(Some(PATIENCE)).unwrap();
    assert!(answers(&mut stream));
}

fn dh_temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.starts_with(".dh.bin."))
        .collect()
}

#[test]
fn temporary_dh_files_of_a_killed_serve_are_removed_at_start() {
    let dir = tempfile::tempdir().unwrap();
    let ns = unique_ns("dh-kill");
    let server = serve(&ns, dir.path(), &[]);
    let mut stream = connect(server.port);
    // Every FC 06 write of DH (0x8000) is saved at once: keep saving while the process dies.
    let writer = std::thread::spawn(move || {
        let mut last = 0u16;
        for value in 1..=u16::MAX {
            match request(&mut stream, &[0x06, 0x80, 0x00, (value >> 8) as u8, value as u8]) {
                Some(pdu) if pdu[0] == 0x06 => last = value,
                _ => break,
            }
        }
        last
    });
    std::thread::sleep(Duration::from_millis(300));
    server.kill9();
    let last = writer.join().unwrap();
    assert!(last > 0, "DH was written before the kill");
    // What a kill in the middle of a save leaves, whether or not this one did.
    std::fs::write(dir.path().join(".dh.bin.999999"), [0xEE; 16]).unwrap();
    let server = serve(&ns, dir.path(), &[]);
    assert_eq!(dh_temporaries(dir.path()), Vec::<String>::new(), "no temporary DH file after the restart");
    let mut stream = connect(server.port);
    let dh = request(&mut stream, &[0x03, 0x80, 0x00, 0x00, 0x01]).unwrap();
    let kept = u16::from_be_bytes([dh[2], dh[3]]);
    // The write after the last answered one may have been saved before its answer went out.
    assert!((1..=last + 1).contains(&kept), "DH holds a value that was written: {kept} of 1..={}", last + 1);
}

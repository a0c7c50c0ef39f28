//! Serial port 1 answers a Modbus RTU master only on the port's line settings (DXMC 8.2:
//! parameter 5-1's character frame, 5-4's baud rate), as a UART on another frame sees
//! parity and framing errors, not data. The masters are pyserial's, with the settings a
//! master on a real line would have. What a pseudo-terminal shows of a peer's parity is in
//! `serial/src/pty.rs` and docs/decisions.md, "Serial line settings".

mod common;

use std::path::Path;
use std::process::Command;
use std::time::Duration;

use common::{pymodbus_python, repo_path, unique_ns};

/// `python tests/python/line_peer.py LINK FRAME [inpck]`: "answered" or "silent".
fn master(link: &Path, frame: &str, extra: &[&str]) -> String {
    let out = Command::new(pymodbus_python())
        .arg(repo_path("tests/python/line_peer.py"))
        .arg(link)
        .arg(frame)
        .args(extra)
        .output()
        .expect("start the pyserial master");
    let stdout = String::from_utf8_lossy(&out.stdout).trim().to_string();
    assert!(out.status.success(), "master {frame} {extra:?}: {stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    stdout
}

/// `luamotion serve` with serial port 1 on `protocol`, and the link to its pseudo-terminal.
fn serve_port(tag: &str, protocol: &str) -> (common::serve::Serving, tempfile::TempDir, std::path::PathBuf) {
    let ns = unique_ns(tag);
    let dir = tempfile::tempdir().unwrap();
    let link = dir.path().join("ttyS1");
    let machine = dir.path().join("machine.toml");
    std::fs::write(&machine, format!("[serial]\nprotocol = {protocol}\n")).unwrap();
    let server = common::serve::serve(
        &ns,
        dir.path(),
        &["--config", machine.to_str().unwrap(), "--serial-link", link.to_str().unwrap()],
    );
    assert!(common::eventually(Duration::from_secs(10), || link.exists()), "no link: {}", server.stderr());
    (server, dir, link)
}

/// 0x16, 8,N,1: an 8,N,1 master is answered; an even-parity master that checks parity
/// (INPCK, as libmodbus sets it), an odd one and one on 2 stop bits are not, and the log
/// says why; the port answers again once the master is back on 8,N,1.
#[test]
fn an_8n1_port_answers_only_an_8n1_master() {
    let (server, _dir, link) = serve_port("parity-8n1", "0x16");
    assert_eq!(master(&link, "8N1", &[]), "answered");
    assert_eq!(master(&link, "8E1", &["inpck"]), "silent", "even parity on 8,N,1");
    assert_eq!(master(&link, "8O1", &[]), "silent", "odd parity on 8,N,1");
    assert_eq!(master(&link, "8N2", &[]), "silent", "2 stop bits on 8,N,1");
    assert_eq!(master(&link, "8N1", &[]), "answered", "back on the port's line");
    let log = server.stderr();
    assert!(log.contains("the peer's line reads 8,E,1 at 38400 baud, the port's is 8,N,1"), "{log}");
    assert!(log.contains("the peer's line reads 8,O,1 at 38400 baud"), "{log}");
    assert!(log.contains("byte(s) were dropped on a wrong setting"), "{log}");
}

/// 0x07, 8,E,1: even-parity masters are answered (pyserial's, which leaves INPCK off,
/// and one that checks parity); an odd-parity master is not, nor one on 2 stop bits.
#[test]
fn an_8e1_port_refuses_an_odd_master() {
    let (server, _dir, link) = serve_port("parity-8e1", "0x07");
    assert_eq!(master(&link, "8E1", &[]), "answered");
    assert_eq!(master(&link, "8E1", &["inpck"]), "answered");
    assert_eq!(master(&link, "8O1", &[]), "silent", "odd parity on 8,E,1");
    assert_eq!(master(&link, "8E2", &[]), "silent", "2 stop bits on 8,E,1");
    assert_eq!(master(&link, "8E1", &[]), "answered", "back on the port's line");
    assert!(server.stderr().contains("the port's is 8,E,1"), "{}", server.stderr());
}

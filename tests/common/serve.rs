//! A running `luamotion serve` for tests: its own namespace and data dir, a free port,
//! its output collected, stopped with SIGTERM when dropped (also when a test fails).

use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use super::{BIN, eventually};

pub struct Serving {
    child: Child,
    /// The address the server listens on, as it printed it.
    pub address: String,
    pub port: u16,
    /// The Native ASCII server's port (HMPL 22.1).
    pub ascii_port: u16,
    stderr: Arc<Mutex<String>>,
}

/// `luamotion serve --ns <ns> --data-dir <dir> --modbus-port 0 --ascii-port 0
/// --ascii-user-port 0 <args>`, once it listens.
pub fn serve(ns: &str, dir: &Path, args: &[&str]) -> Serving {
    let mut child = Command::new(BIN)
        .args(["serve", "--ns", ns, "--modbus-port", "0", "--ascii-port", "0", "--ascii-user-port", "0"])
        .arg("--data-dir")
        .arg(dir)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start luamotion serve");
    let stderr = Arc::new(Mutex::new(String::new()));
    let mut pipe = child.stderr.take().expect("stderr");
    let sink = stderr.clone();
    std::thread::spawn(move || {
        let mut chunk = [0u8; 4096];
        while let Ok(n @ 1..) = pipe.read(&mut chunk) {
            sink.lock().unwrap().push_str(&String::from_utf8_lossy(&chunk[..n]));
        }
    });
    let mut stdout = BufReader::new(child.stdout.take().expect("stdout"));
    let mut line = String::new();
    stdout.read_line(&mut line).expect("first line");
    let mut ascii = String::new();
    stdout.read_line(&mut ascii).expect("second line");
    // Programs' output goes on coming: keep the pipe drained.
    std::thread::spawn(move || std::io::copy(&mut stdout, &mut std::io::sink()));
    let address = line
        .split_once("Modbus TCP on ")
        .and_then(|(_, rest)| rest.split(';').next())
        .unwrap_or_else(|| panic!("no address in {line:?}; stderr:\n{}", stderr.lock().unwrap()))
        .to_string();
    let port = address.rsplit(':').next().and_then(|port| port.parse().ok()).expect("port");
    let ascii_port = ascii
        .split_once("Native ASCII on ")
        .and_then(|(_, rest)| rest.split(';').next())
        .and_then(|a| a.rsplit(':').next())
        .and_then(|port| port.parse().ok())
        .unwrap_or_else(|| panic!("no Native ASCII address in {ascii:?}"));
    Serving { child, address, port, ascii_port, stderr }
}

impl Serving {
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// What the server logged so far.
    pub fn stderr(&self) -> String {
        self.stderr.lock().unwrap().clone()
    }

    /// SIGKILL, as a crash or the OOM killer would end it.
    pub fn kill9(mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Serving {
    fn drop(&mut self) {
        if self.child.try_wait().ok().flatten().is_some() {
            return;
        }
        // SAFETY: plain kill(2) of our own child.
        unsafe { libc::kill(self.child.id() as i32, libc::SIGTERM) };
        if !eventually(Duration::from_secs(10), || self.child.try_wait().ok().flatten().is_some()) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

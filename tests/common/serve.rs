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
    /// The web view's address, `http://HOST:PORT/`, with `--http`.
    pub web: Option<String>,
    stdout: Arc<Mutex<String>>,
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
    // Programs that run at start may print before the servers' addresses come.
    let output = Arc::new(Mutex::new(String::new()));
    let mut said = |start: &str| loop {
        let mut line = String::new();
        if stdout.read_line(&mut line).expect("read stdout") == 0 {
            panic!("serve ended before it said {start:?}; stderr:\n{}", stderr.lock().unwrap());
        }
        match line.split_once(start) {
            Some((_, rest)) => return rest.split(';').next().unwrap_or_default().trim().to_string(),
            None => output.lock().unwrap().push_str(&line),
        }
    };
    let address = said("Modbus TCP on ");
    let ascii = said("Native ASCII on ");
    let web = args.contains(&"--http").then(|| said("Web view on "));
    // Programs' output goes on coming: keep the pipe drained, and what it said.
    let sink = output.clone();
    std::thread::spawn(move || {
        let mut line = String::new();
        while stdout.read_line(&mut line).is_ok_and(|n| n > 0) {
            sink.lock().unwrap().push_str(&std::mem::take(&mut line));
        }
    });
    let port_of = |address: &str| address.rsplit(':').next().and_then(|port| port.parse().ok()).expect("port");
    let (port, ascii_port) = (port_of(&address), port_of(&ascii));
    Serving { child, address, port, ascii_port, web, stdout: output, stderr }
}

impl Serving {
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// What the programs printed so far (`[task N] ...` lines).
    pub fn stdout(&self) -> String {
        self.stdout.lock().unwrap().clone()
    }

    /// The rest of the first output line of task `task` that starts with `prefix`, once
    /// it has been printed (at most `timeout`).
    pub fn await_line(&self, task: u8, prefix: &str, timeout: Duration) -> Option<String> {
        let start = format!("[task {task}] {prefix}");
        let find = || self.stdout().lines().find_map(|l| l.strip_prefix(&start).map(str::to_string));
        eventually(timeout, || find().is_some()).then(find).flatten()
    }

    /// What the server logged so far.
    pub fn stderr(&self) -> String {
        self.stderr.lock().unwrap().clone()
    }

    /// SIGINT, as Ctrl-C: how it ended, once it has within `timeout`; `None` while it runs.
    pub fn interrupt(&mut self, timeout: Duration) -> Option<std::process::ExitStatus> {
        // SAFETY: plain kill(2) of our own child.
        unsafe { libc::kill(self.child.id() as i32, libc::SIGINT) };
        let mut status = None;
        eventually(timeout, || {
            status = self.child.try_wait().ok().flatten();
            status.is_some()
        });
        status
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

//! Helpers for end-to-end tests: every controller gets its own namespace and temp dir,
//! and every process is waited for with a timeout, so that tests run in parallel and
//! never hang.

#![allow(dead_code)]

pub mod e2e;
pub mod serve;
pub mod wire;

use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

pub const BIN: &str = env!("CARGO_BIN_EXE_luamotion");

/// How long one test binary may run, s (`LUAMOTION_TEST_DEADLINE_S` sets another): the
/// longest, `faults`, takes about 3 minutes, 10 on a loaded machine.
const BINARY_DEADLINE_S: u64 = 1500;

/// The backstop under every wait's own deadline: each end-to-end test binary starts a
/// watchdog before `main` (an `.init_array` entry), which ends the binary once it has run
/// longer than `BINARY_DEADLINE_S`, so that a wait this file's helpers do not cover cannot
/// hang the suite. The harness has named the tests still running ("has been running for
/// over 60 seconds").
#[used]
#[unsafe(link_section = ".init_array")]
static BINARY_DEADLINE: extern "C" fn() = start_binary_deadline;

extern "C" fn start_binary_deadline() {
    let limit =
        std::env::var("LUAMOTION_TEST_DEADLINE_S").ok().and_then(|s| s.parse().ok()).unwrap_or(BINARY_DEADLINE_S);
    std::thread::spawn(move || {
        std::thread::sleep(Duration::from_secs(limit));
        eprintln!(
            "this test binary ran longer than its deadline of {limit} s (LUAMOTION_TEST_DEADLINE_S): a test hangs; \
             the tests still running were named above as running for over 60 seconds"
        );
        std::process::exit(124);
    });
}

/// A namespace no other test (or test run) uses.
pub fn unique_ns(tag: &str) -> String {
    static NEXT: AtomicU32 = AtomicU32::new(0);
    format!("t{}-{}-{tag}", std::process::id(), NEXT.fetch_add(1, Ordering::Relaxed))
}

pub fn repo_path(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

/// Writes a Lua program into `dir` and returns its path.
pub fn program(dir: &Path, name: &str, source: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, source).expect("write program");
    path
}

#[derive(Debug)]
pub struct Finished {
    pub status: ExitStatus,
    pub stdout: String,
    pub stderr: String,
}

impl Finished {
    pub fn lines_of_task(&self, task: u8) -> Vec<String> {
        let prefix = format!("[task {task}] ");
        self.stdout.lines().filter_map(|l| l.strip_prefix(&prefix)).map(str::to_string).collect()
    }
}

/// `luamotion run --ns <ns> <args>`, started.
/// The controller's own data directory (`--data-dir`), under cargo's temp dir for tests.
pub fn data_dir(ns: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("data").join(ns)
}

pub fn start_run(ns: &str, args: &[&str]) -> Child {
    Command::new(BIN)
        .args(["run", "--ns", ns])
        .arg("--data-dir")
        .arg(data_dir(ns))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        // Its own group: a timeout kills it with whatever it started.
        .process_group(0)
        .spawn()
        .expect("start luamotion")
}

/// A free TCP port on 127.0.0.1, asked of the OS.
pub fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

/// A listener on 127.0.0.1 at a free port of FreePort's range 3000..10000, asked of the OS
/// by binding to it.
pub fn freeport_listener() -> std::net::TcpListener {
    static NEXT: AtomicU32 = AtomicU32::new(0);
    // u64: a pid times 7919 overflows u32 once pids pass 542 000 (pid_max may be 4 M).
    let seed = u64::from(std::process::id()) * 7919 + u64::from(NEXT.fetch_add(1, Ordering::Relaxed)) * 101;
    (0..7001)
        .find_map(|i| std::net::TcpListener::bind(("127.0.0.1", 3000 + ((seed + i) % 7001) as u16)).ok())
        .expect("a free port in 3000..10000")
}

/// A free port in FreePort's range for a server the Lua program opens.
pub fn freeport_port() -> u16 {
    freeport_listener().local_addr().unwrap().port()
}

/// Waits for a child, killing it after `timeout`. Its pipes are read while it runs, so a
/// child that prints more than a pipe holds cannot block on its output and look hung; on
/// the deadline its process group goes too (a `luamotion test` child's controllers hold
/// the pipes open), and the output is collected for at most a few seconds more.
pub fn finish(mut child: Child, timeout: Duration) -> Finished {
    let stdout = drain(child.stdout.take());
    let stderr = drain(child.stderr.take());
    let deadline = Instant::now() + timeout;
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break Some(status);
        }
        if Instant::now() > deadline {
            break None;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let Some(status) = status else {
        kill_all(&mut child);
        let until = Instant::now() + Duration::from_secs(5);
        panic!("timed out after {timeout:?}\nstdout:\n{}\nstderr:\n{}", collect(stdout, until), collect(stderr, until));
    };
    // A grandchild that outlived the child may hold the pipes: what it wrote in the next
    // seconds is kept, then the test goes on without it.
    let until = Instant::now() + Duration::from_secs(10);
    Finished { status, stdout: collect(stdout, until), stderr: collect(stderr, until) }
}

/// Kills a child and, where it leads one, its process group, and reaps it.
pub fn kill_all(child: &mut Child) {
    // SAFETY: kill(2) of the group our own child leads, if it leads one (else ESRCH).
    unsafe { libc::kill(-(child.id() as libc::pid_t), libc::SIGKILL) };
    let _ = child.kill();
    let _ = child.wait();
}

/// A pipe read to its end by a thread of its own; the text arrives on the channel.
fn drain(pipe: Option<impl std::io::Read + Send + 'static>) -> std::sync::mpsc::Receiver<String> {
    let (text, received) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        if let Some(mut pipe) = pipe {
            let _ = pipe.read_to_end(&mut bytes);
        }
        let _ = text.send(String::from_utf8_lossy(&bytes).into_owned());
    });
    received
}

/// What a drained pipe gave, waiting for its end until `until` at most.
fn collect(reader: std::sync::mpsc::Receiver<String>, until: Instant) -> String {
    reader
        .recv_timeout(until.saturating_duration_since(Instant::now()))
        .unwrap_or_else(|_| "(the pipe was still open seconds after the process ended)".to_string())
}

/// A child's output stream line by line, read on its own thread, as it comes.
pub fn lines_of(stream: impl std::io::Read + Send + 'static) -> std::sync::mpsc::Receiver<String> {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in std::io::BufRead::lines(std::io::BufReader::new(stream)).map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    rx
}

/// The lines still to come once the process has ended: until its pipe closes, at most
/// `timeout` (a grandchild that outlived it may hold the pipe). The reader thread may
/// still be reading the pipe when the process is reaped, so `try_iter` would lose the end.
pub fn rest_of(lines: &std::sync::mpsc::Receiver<String>, timeout: Duration) -> Vec<String> {
    let until = Instant::now() + timeout;
    let mut rest = Vec::new();
    while let Ok(line) = lines.recv_timeout(until.saturating_duration_since(Instant::now())) {
        rest.push(line);
    }
    rest
}

/// Accepts one connection within `timeout`, or fails the test saying what it waited for.
pub fn accept_within(
    listener: &std::net::TcpListener,
    timeout: Duration,
    what: &str,
) -> (std::net::TcpStream, std::net::SocketAddr) {
    listener.set_nonblocking(true).expect("non-blocking listener");
    let deadline = Instant::now() + timeout;
    loop {
        match listener.accept() {
            Ok((stream, peer)) => {
                stream.set_nonblocking(false).expect("blocking stream");
                // Its reads wait no longer than the accept did.
                stream.set_read_timeout(Some(timeout)).expect("read timeout");
                return (stream, peer);
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock && Instant::now() < deadline => {
                std::thread::sleep(Duration::from_millis(5));
            }
            Err(e) => panic!("no connection from {what} within {timeout:?}: {e}"),
        }
    }
}

/// `luamotion run` to its end.
pub fn run(ns: &str, args: &[&str]) -> Finished {
    finish(start_run(ns, args), Duration::from_secs(60))
}

/// Child processes of `pid`, from /proc: a controller's script processes that run a
/// task (its waiting ones, `[rt] script_pool`, left out).
pub fn children_of(pid: u32) -> Vec<u32> {
    all_children_of(pid).into_iter().filter(|&child| !waiting(child)).collect()
}

/// A controller's waiting script processes (`[rt] script_pool`).
pub fn waiting_children_of(pid: u32) -> Vec<u32> {
    all_children_of(pid).into_iter().filter(|&child| waiting(child)).collect()
}

/// A waiting script process names itself so (`script_host::run_pooled`).
fn waiting(pid: u32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/comm")).is_ok_and(|name| name.trim_end() == "luamotion-pool")
}

fn all_children_of(pid: u32) -> Vec<u32> {
    let mut children = Vec::new();
    for entry in std::fs::read_dir("/proc").expect("proc").flatten() {
        let Ok(child) = entry.file_name().to_string_lossy().parse::<u32>() else { continue };
        let Ok(stat) = std::fs::read_to_string(format!("/proc/{child}/stat")) else { continue };
        // Fields after the command name in parentheses: state, ppid, ...
        let Some(rest) = stat.rsplit_once(')').map(|(_, r)| r) else { continue };
        let fields: Vec<&str> = rest.split_whitespace().collect();
        if fields.get(1).and_then(|p| p.parse::<u32>().ok()) == Some(pid) && fields[0] != "Z" {
            children.push(child);
        }
    }
    children
}

pub fn process_alive(pid: u32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .map(|stat| stat.rsplit_once(')').map(|(_, r)| !r.trim_start().starts_with('Z')).unwrap_or(false))
        .unwrap_or(false)
}

/// CPU time a thread of `pid` named `name` has used, ns, from its `schedstat` (the
/// scheduler's own account, finer than the clock ticks of `stat`).
pub fn thread_cpu_ns(pid: u32, name: &str) -> u64 {
    for entry in std::fs::read_dir(format!("/proc/{pid}/task")).expect("the process' threads").flatten() {
        let path = entry.path();
        if std::fs::read_to_string(path.join("comm")).is_ok_and(|comm| comm.trim() == name) {
            let schedstat = std::fs::read_to_string(path.join("schedstat")).expect("schedstat");
            return schedstat.split_whitespace().next().and_then(|ns| ns.parse().ok()).expect("run time");
        }
    }
    panic!("no thread {name} in process {pid}")
}

/// The RT thread's share of a core (%) and the overruns (read by `overruns`) while `span`
/// runs, for controller process `pid`.
pub fn rt_cost(pid: u32, overruns: &dyn Fn() -> u64, span: &mut dyn FnMut()) -> (f64, u64) {
    let (cpu, overrun, start) = (thread_cpu_ns(pid, "rt-cycle"), overruns(), Instant::now());
    span();
    let busy = (thread_cpu_ns(pid, "rt-cycle") - cpu) as f64 / start.elapsed().as_nanos() as f64;
    (100.0 * busy, overruns() - overrun)
}

/// GETs a JSON document (the web view's `/api/state`).
pub fn get_json(url: &str) -> serde_json::Value {
    ureq::get(url).call().unwrap_or_else(|e| panic!("GET {url}: {e}")).body_mut().read_json().expect("JSON")
}

/// Files the namespace has in shared memory.
pub fn shm_files(ns: &str) -> Vec<String> {
    let prefix = format!("lm.{ns}.");
    std::fs::read_dir("/dev/shm")
        .map(|d| {
            d.flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with(&prefix))
                .collect()
        })
        .unwrap_or_default()
}

/// Polls `f` until it holds or `timeout` passes.
pub fn eventually(timeout: Duration, mut f: impl FnMut() -> bool) -> bool {
    let deadline = Instant::now() + timeout;
    while Instant::now() < deadline {
        if f() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    f()
}

/// Whether this run is CI's (`CI` set to anything but empty, `false` or `0`): there a
/// missing prerequisite fails the test, it never skips and passes.
pub fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|ci| !ci.is_empty() && ci != "false" && ci != "0")
}

/// The virtualenv's python, with pymodbus installed once per build directory.
pub fn pymodbus_python() -> &'static Path {
    static PYTHON: OnceLock<PathBuf> = OnceLock::new();
    PYTHON.get_or_init(|| {
        let venv = Path::new(env!("CARGO_TARGET_TMPDIR")).join("pymodbus-venv");
        let python = venv.join("bin/python");
        let requirements = repo_path("tests/python/requirements.txt");
        let marker = venv.join("installed.txt");
        let wanted = std::fs::read_to_string(&requirements).expect("requirements");
        if std::fs::read_to_string(&marker).ok().as_deref() != Some(wanted.as_str()) {
            let _ = std::fs::remove_dir_all(&venv);
            let ok = |c: &mut Command| c.status().map(|s| s.success()).unwrap_or(false);
            assert!(ok(Command::new("python3").args(["-m", "venv"]).arg(&venv)), "python3 -m venv failed");
            assert!(
                ok(Command::new(&python).args(["-m", "pip", "install", "-q", "-r"]).arg(&requirements)),
                "pip install -r {} failed",
                requirements.display()
            );
            std::fs::write(&marker, wanted).expect("marker");
        }
        python
    })
}

/// The path of a Debian tool the tests use as an outside client (`tests/debian-packages.txt`),
/// installed with apt-get on first use when missing (CI runs as root on a clean machine).
pub fn debian_tool(command: &str) -> PathBuf {
    try_debian_tool(command).unwrap_or_else(|e| panic!("{e}"))
}

/// `debian_tool`, or why the tool cannot be had.
pub fn try_debian_tool(command: &str) -> Result<PathBuf, String> {
    static INSTALLED: OnceLock<Result<(), String>> = OnceLock::new();
    let find = || {
        std::env::var_os("PATH")
            .and_then(|paths| std::env::split_paths(&paths).map(|dir| dir.join(command)).find(|p| p.is_file()))
    };
    if let Some(path) = find() {
        return Ok(path);
    }
    let installed = INSTALLED.get_or_init(|| {
        let list = std::fs::read_to_string(repo_path("tests/debian-packages.txt")).expect("tests/debian-packages.txt");
        let packages: Vec<&str> = list
            .lines()
            .filter(|l| !l.trim_start().starts_with('#'))
            .filter_map(|l| l.split_whitespace().nth(1))
            .collect();
        let apt = |args: &[&str]| {
            Command::new("apt-get")
                .args(args)
                .env("DEBIAN_FRONTEND", "noninteractive")
                .stdout(Stdio::null())
                .status()
                .is_ok_and(|s| s.success())
        };
        let install = [&["install", "-y", "-q", "--no-install-recommends"][..], &packages].concat();
        // A clean machine's package lists may be stale: update once and retry.
        if apt(&install) || (apt(&["update", "-q"]) && apt(&install)) {
            Ok(())
        } else {
            Err(format!("apt-get install {} failed (run as root, or install them)", packages.join(" ")))
        }
    });
    if let Err(e) = installed {
        return Err(format!("{command} is missing: {e}"));
    }
    find().ok_or_else(|| format!("{command} is still missing after installing tests/debian-packages.txt"))
}

/// `tests/python/modbus_server.py` (pymodbus, a Modbus TCP server luamotion did not write),
/// killed when dropped.
pub struct PyServer(Child);

impl Drop for PyServer {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Starts the pymodbus server on a free port; returns it and its port once it listens.
pub fn pymodbus_server() -> (PyServer, u16) {
    let port = free_port();
    let child = Command::new(pymodbus_python())
        .arg(repo_path("tests/python/modbus_server.py"))
        .arg(port.to_string())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start the pymodbus server");
    let server = PyServer(child);
    assert!(
        eventually(Duration::from_secs(30), || std::net::TcpStream::connect(("127.0.0.1", port)).is_ok()),
        "the pymodbus server does not listen on {port}"
    );
    (server, port)
}

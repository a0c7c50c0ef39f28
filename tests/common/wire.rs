//! A wire for the EtherCAT tests: a network namespace and a veth pair of the test's own,
//! removed when dropped, also when the test fails. Making one needs root or CAP_NET_ADMIN.

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};

use std::time::Duration;

use super::{BIN, Finished, finish, in_ci, lines_of, try_debian_tool};

/// A network namespace with one end of a veth pair in it, the other end up in ours;
/// both gone when dropped (deleting the namespace deletes its end, and the pair with it).
pub struct Wire {
    /// Debian's `ip`.
    pub ip: PathBuf,
    /// The namespace the inside end is in.
    pub namespace: String,
    /// The end in the test's own namespace.
    pub outside: String,
    /// The end in `namespace`.
    pub inside: String,
}

impl Wire {
    /// A new namespace and pair, or why they cannot be made here.
    pub fn new() -> Result<Wire, String> {
        static NEXT: AtomicU32 = AtomicU32::new(0);
        let ip = try_debian_tool("ip")?;
        // Interface names have at most 15 bytes: "lmv" + pid (7 digits at most) + n + a/b.
        let tag = format!("{}{}", std::process::id(), NEXT.fetch_add(1, Ordering::Relaxed));
        let wire = Wire {
            ip,
            namespace: format!("luamotion-wire-{tag}"),
            outside: format!("lmv{tag}a"),
            inside: format!("lmv{tag}b"),
        };
        wire.run(&["netns", "add", &wire.namespace])?;
        wire.run(&["link", "add", &wire.outside, "type", "veth", "peer", "name", &wire.inside])?;
        wire.run(&["link", "set", &wire.inside, "netns", &wire.namespace])?;
        wire.run(&["link", "set", &wire.outside, "up"])?;
        wire.run(&["-n", &wire.namespace, "link", "set", &wire.inside, "up"])?;
        Ok(wire)
    }

    /// `program` run in the wire's namespace.
    pub fn in_namespace(&self, program: impl AsRef<std::ffi::OsStr>) -> Command {
        let mut command = Command::new(&self.ip);
        command.args(["netns", "exec", &self.namespace]).arg(program);
        command
    }

    pub fn run(&self, args: &[&str]) -> Result<(), String> {
        let output = Command::new(&self.ip).args(args).output().map_err(|e| format!("ip {}: {e}", args.join(" ")))?;
        if output.status.success() {
            Ok(())
        } else {
            Err(format!("ip {}: {}", args.join(" "), String::from_utf8_lossy(&output.stderr).trim()))
        }
    }
}

impl Drop for Wire {
    fn drop(&mut self) {
        let _ = self.run(&["link", "del", &self.outside]);
        let _ = self.run(&["netns", "del", &self.namespace]);
    }
}

/// The wire, or: in CI a failure, elsewhere a skip (None) that says why.
pub fn wire() -> Option<Wire> {
    match Wire::new() {
        Ok(wire) => Some(wire),
        Err(why) if in_ci() => panic!("the test needs root or CAP_NET_ADMIN and CAP_NET_RAW: {why}"),
        Err(why) => {
            eprintln!("skipped: the test needs root or CAP_NET_ADMIN and CAP_NET_RAW: {why}");
            None
        }
    }
}

/// Which end of the wire a program runs on.
#[derive(Clone, Copy, Debug)]
pub enum End {
    /// The end in the test's own namespace.
    Outside,
    /// The end in the wire's namespace (`ip netns exec`).
    Inside,
}

/// `luamotion subdevices` on one end of the wire, killed when dropped.
pub struct Segment(Option<Child>);

impl Segment {
    /// The built-in machine's drives, started; returns once it serves, or fails saying
    /// what it printed.
    pub fn serve(wire: &Wire, end: End) -> Segment {
        Segment::serve_machine(wire, end, None)
    }

    /// The drives and slaves of the machine file `config` (the built-in machine's without).
    pub fn serve_machine(wire: &Wire, end: End, config: Option<&std::path::Path>) -> Segment {
        match end {
            End::Outside => Segment::serve_on(Command::new(BIN), &wire.outside, config),
            End::Inside => Segment::serve_on(wire.in_namespace(BIN), &wire.inside, config),
        }
    }

    /// `command` (the binary, or `ip netns exec` of it) serving on `interface`.
    pub fn serve_on(mut command: Command, interface: &str, config: Option<&std::path::Path>) -> Segment {
        command.args(["-v", "subdevices", "--interface", interface]);
        if let Some(config) = config {
            command.arg("--config").arg(config);
        }
        let mut child =
            command.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("start luamotion subdevices");
        let lines = lines_of(child.stdout.take().unwrap());
        match lines.recv_timeout(Duration::from_secs(30)) {
            Ok(line) if line.starts_with("serving ") => Segment(Some(child)),
            other => {
                let _ = child.kill();
                let finished = finish(child, Duration::from_secs(5));
                panic!("luamotion subdevices did not serve within 30 s: {other:?}\n{}", finished.stderr)
            }
        }
    }

    /// SIGTERM, and what it said as it ended.
    pub fn stop(mut self) -> Finished {
        let child = self.0.take().expect("running");
        // SAFETY: asking our own child to end.
        unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGTERM) };
        finish(child, Duration::from_secs(10))
    }
}

impl Drop for Segment {
    fn drop(&mut self) {
        if let Some(child) = &mut self.0 {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

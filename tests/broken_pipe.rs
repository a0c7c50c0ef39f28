//! Every command ends quietly when the reader of its stdout is gone (`luamotion tasks |
//! head -1`): here stdout is a pipe whose read end was closed before the command started,
//! so its first write fails with EPIPE. A command that hosts no controller ends at once
//! with 141 (128 + SIGPIPE) and says nothing; one that hosts a controller (`run`, `serve`,
//! `test`, `soak`) goes on to its usual end, says once on stderr that its output is
//! dropped, and leaves nothing in shared memory. None panics (exit code 101).

mod common;

use std::os::fd::{FromRawFd, OwnedFd};
use std::process::{Command, Stdio};
use std::time::Duration;

use common::*;

/// The commands this file runs with a closed stdout, as `luamotion --help` lists them.
const COVERED: [&str; 13] =
    ["run", "test", "scope", "serve", "subdevices", "drl", "tasks", "events", "soak", "api", "check", "lsp", "help"];

/// What the shell shows for a writer that SIGPIPE ended, and what a tool exits with here.
const CLOSED: i32 = 128 + libc::SIGPIPE;

/// The write end of a pipe whose read end is closed.
fn closed_stdout() -> Stdio {
    let mut fds = [0; 2];
    // SAFETY: pipe2 fills two descriptors we then own; the read end is closed at once.
    unsafe {
        assert_eq!(libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC), 0, "pipe2");
        libc::close(fds[0]);
        Stdio::from(OwnedFd::from_raw_fd(fds[1]))
    }
}

/// `luamotion <args>` with a closed stdout, to its end.
fn with_closed_stdout(args: &[&str], timeout: Duration) -> Finished {
    let child = Command::new(BIN).args(args).stdout(closed_stdout()).stderr(Stdio::piped()).spawn().unwrap();
    let out = finish(child, timeout);
    assert_ne!(out.status.code(), Some(101), "{args:?} panicked:\n{}", out.stderr);
    assert!(!out.stderr.contains("panicked"), "{args:?}:\n{}", out.stderr);
    out
}

/// A tool ends at once, with 141 and not a word.
fn ends_quietly(args: &[&str]) {
    let out = with_closed_stdout(args, Duration::from_secs(30));
    assert_eq!(out.status.code(), Some(CLOSED), "{args:?}:\n{}", out.stderr);
    assert_eq!(out.stderr, "", "{args:?} says nothing");
}

/// A command that hosts a controller ends as it would have, says once that its output
/// is dropped, and removes the namespace's shared memory.
fn goes_on(ns: &str, args: &[&str], exit_code: i32, out: Finished) {
    assert_eq!(out.status.code(), Some(exit_code), "{args:?}:\n{}", out.stderr);
    assert_eq!(out.stderr.matches("stdout is closed").count(), 1, "{args:?} says it once:\n{}", out.stderr);
    assert_eq!(shm_files(ns), Vec::<String>::new(), "{args:?} left shared memory");
}

/// `subdevices` serves its segment on after its line went into the closed pipe (a master
/// may be driving its drives), and ends on SIGTERM as it would with a reader.
#[test]
fn subdevices_serve_on_until_stopped() {
    let Some(wire) = common::wire::wire() else { return };
    let args = ["subdevices", "--interface", &wire.outside];
    let mut child = Command::new(BIN).args(args).stdout(closed_stdout()).stderr(Stdio::piped()).spawn().unwrap();
    let running = |child: &mut std::process::Child| child.try_wait().unwrap().is_none();
    // Its one line is written (and dropped) once the socket is bound.
    std::thread::sleep(Duration::from_millis(1500));
    let still_up = running(&mut child);
    // SAFETY: plain kill(2) of our own child.
    unsafe { libc::kill(child.id() as i32, libc::SIGTERM) };
    let out = finish(child, Duration::from_secs(30));
    assert!(still_up, "subdevices ended with its stdout closed:\n{}", out.stderr);
    assert_eq!(out.status.code(), Some(0), "{}", out.stderr);
    assert_eq!(out.stderr.matches("stdout is closed").count(), 1, "it says so once:\n{}", out.stderr);
}

/// Every command of `luamotion --help` is run below: a new one needs its row.
#[test]
fn every_command_is_covered() {
    let help = Command::new(BIN).arg("--help").output().unwrap();
    let help = String::from_utf8(help.stdout).unwrap();
    let listed: Vec<&str> = help
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    assert!(listed.len() > 5, "{help}");
    let mut covered = COVERED.to_vec();
    covered.sort();
    let mut listed = listed;
    listed.sort();
    assert_eq!(listed, covered);
}

#[test]
fn the_tools_end_quietly() {
    ends_quietly(&["api", "markdown"]);
    ends_quietly(&["api", "lua"]);
    ends_quietly(&["api", "luacheckrc"]);
    ends_quietly(&["check", "scripts"]);
    // The language server's stdout is the editor's connection: with the editor gone
    // before it said anything, it ends with a word, not a panic.
    let lsp = Command::new(BIN).arg("lsp").stdin(Stdio::null()).stdout(closed_stdout()).stderr(Stdio::piped()).spawn();
    let out = finish(lsp.unwrap(), Duration::from_secs(30));
    assert_eq!(out.status.code(), Some(1), "{}", out.stderr);
    assert!(out.stderr.contains("the editor ended the connection"), "{}", out.stderr);
    // clap prints help and version; a failed print is no error there.
    for args in [&["help"][..], &["help", "run"], &["--help"], &["run", "--help"], &["--version"]] {
        with_closed_stdout(args, Duration::from_secs(30));
    }
}

/// `tasks`, `events`, `drl status` and `scope` on a served controller; `events` prints the
/// events a DRL project sends every 50 ms.
#[test]
fn the_tools_on_a_running_controller_end_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let project = dir.path().join("projects/3");
    std::fs::create_dir_all(&project).unwrap();
    std::fs::write(project.join("main.lua"), "while true do SendEvent(7) Sleep(50) end\n").unwrap();
    let ns = unique_ns("pipe-tools");
    let server = common::serve::serve(&ns, dir.path(), &[]);
    let at = format!("127.0.0.1:{}", server.port);
    let opened = finish(
        Command::new(BIN).args(["drl", "open", "3", "--run", "--at", &at]).stdout(Stdio::piped()).spawn().unwrap(),
        Duration::from_secs(30),
    );
    assert!(opened.status.success(), "{}", opened.stdout);
    ends_quietly(&["tasks", "--ns", &ns]);
    ends_quietly(&["events", "--ns", &ns]);
    ends_quietly(&["drl", "status", "--at", &at]);
    // The scope writes its file, not stdout: it ends as usual.
    let csv = dir.path().join("scope.csv");
    let out = with_closed_stdout(
        &["scope", "--ns", &ns, "--duration-ms", "100", "--out", csv.to_str().unwrap()],
        Duration::from_secs(30),
    );
    assert!(out.status.success() && csv.exists(), "{}", out.stderr);
}

/// `run` drops its programs' output and its own lines, runs its programs to their end,
/// and shuts down in order; with `--http` too, which prints the web view's address.
#[test]
fn run_goes_on_to_the_end_of_its_programs() {
    let dir = tempfile::tempdir().unwrap();
    let program = program(
        dir.path(),
        "prints.lua",
        "for i = 1, 50 do Print('line %d', i) end\nEnable(0)\nTill(function() return IsEnabled(0) end)\n\
         MoveRel(0, 5)\nTill(function() return IsInPos(0) end)\nPrint('at %f', GetPosFb(0))\n",
    );
    let program = program.to_str().unwrap();
    for extra in [&[][..], &["--http", "0"]] {
        let ns = unique_ns("pipe-run");
        let mut args = vec!["run", "--ns", &ns];
        args.extend_from_slice(extra);
        args.push(program);
        let out = with_closed_stdout(&args, Duration::from_secs(60));
        assert!(out.stderr.contains("task 0 (") && out.stderr.contains("finished"), "{args:?}:\n{}", out.stderr);
        if extra.is_empty() {
            // Its programs' lines are dropped without a word, as a closed pipe always was.
            assert_eq!(out.status.code(), Some(0), "{args:?}:\n{}", out.stderr);
            assert_eq!(shm_files(&ns), Vec::<String>::new(), "{args:?} left shared memory");
        } else {
            goes_on(&ns, &args, 0, out);
        }
    }
}

/// `serve` serves on with a closed stdout until SIGTERM, then shuts down in order.
#[test]
fn serve_serves_on_until_stopped() {
    let ns = unique_ns("pipe-serve");
    let dir = tempfile::tempdir().unwrap();
    let data_dir = dir.path().to_str().unwrap();
    let args = [
        "serve",
        "--ns",
        &ns,
        "--data-dir",
        data_dir,
        "--modbus-port",
        "0",
        "--ascii-port",
        "0",
        "--ascii-user-port",
        "0",
    ];
    let child = Command::new(BIN).args(args).stdout(closed_stdout()).stderr(Stdio::piped()).spawn().unwrap();
    let pid = child.id();
    let serving = || Command::new(BIN).args(["tasks", "--ns", &ns]).output().is_ok_and(|out| out.status.success());
    let up = eventually(Duration::from_secs(30), serving);
    // Still serving a moment after it printed its addresses into the closed pipe.
    std::thread::sleep(Duration::from_millis(300));
    let still_up = serving();
    // SAFETY: plain kill(2) of our own child.
    unsafe { libc::kill(pid as i32, libc::SIGTERM) };
    let out = finish(child, Duration::from_secs(30));
    assert!(up && still_up, "serve did not keep serving (up {up}, later {still_up}):\n{}", out.stderr);
    assert!(!out.stderr.contains("panicked"), "{}", out.stderr);
    goes_on(&ns, &args, 128 + libc::SIGTERM, out);
}

/// `test` runs its file and answers with its exit code; `soak` finishes its run.
#[test]
fn test_and_soak_finish_their_runs() {
    let dir = tempfile::tempdir().unwrap();
    let file = program(dir.path(), "passes.lua", "Print('fine')\n");
    let out = with_closed_stdout(&["test", file.to_str().unwrap()], Duration::from_secs(120));
    assert_eq!(out.status.code(), Some(0), "the test passes:\n{}", out.stderr);
    assert_eq!(out.stderr.matches("stdout is closed").count(), 1, "said once:\n{}", out.stderr);
    let ns = unique_ns("pipe-soak");
    let args = ["soak", "--ns", &ns, "--duration", "1", "--scripts", "1", "--no-huge-pages"];
    let out = with_closed_stdout(&args, Duration::from_secs(300));
    goes_on(&ns, &args, 0, out);
}

//! The end-to-end tests' own helpers keep the promise of tests/common: no wait without a
//! deadline, whatever the child does with its pipes.

mod common;

use std::os::unix::process::CommandExt;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{accept_within, finish, process_alive};

fn sh(script: &str) -> Command {
    let mut command = Command::new("sh");
    command.args(["-c", script]).stdout(Stdio::piped()).stderr(Stdio::piped()).process_group(0);
    command
}

/// A child that prints more than a pipe holds finishes (it used to block on its write
/// while the helper waited for it to end, and time out).
#[test]
fn a_child_that_prints_more_than_a_pipe_holds_finishes() {
    let child =
        sh("head -c 300000 /dev/zero | tr '\\0' x; echo; head -c 100000 /dev/zero | tr '\\0' y >&2").spawn().unwrap();
    let out = finish(child, Duration::from_secs(30));
    assert!(out.status.success());
    assert_eq!((out.stdout.len(), out.stderr.len()), (300_001, 100_000));
}

/// On the deadline the child's whole process group is killed and the test fails saying
/// so, instead of waiting for the pipes its grandchildren hold (the 53-minute hang of a
/// `luamotion test` whose controllers outlived it).
#[test]
fn a_child_past_its_deadline_is_killed_with_its_group() {
    let pid_file = tempfile::NamedTempFile::new().unwrap();
    let script = format!("sleep 600 & echo $! > {}; wait", pid_file.path().display());
    let child = sh(&script).spawn().unwrap();
    let started = Instant::now();
    let failed = std::panic::catch_unwind(|| finish(child, Duration::from_secs(1))).unwrap_err();
    let message = failed.downcast_ref::<String>().cloned().unwrap_or_default();
    assert!(message.starts_with("timed out after 1s"), "{message}");
    assert!(started.elapsed() < Duration::from_secs(10), "gave up in {:?}", started.elapsed());
    let grandchild: u32 = std::fs::read_to_string(pid_file.path()).unwrap().trim().parse().unwrap();
    assert!(
        common::eventually(Duration::from_secs(5), || !process_alive(grandchild)),
        "the grandchild {grandchild} was killed with its group"
    );
}

/// A child that ends while a process it left behind holds its pipes: its output is
/// collected for a grace period, then the test goes on.
#[test]
fn a_grandchild_holding_the_pipes_does_not_hold_the_test() {
    let pid_file = tempfile::NamedTempFile::new().unwrap();
    let child = sh(&format!("echo before; sleep 600 & echo $! > {}", pid_file.path().display())).spawn().unwrap();
    let started = Instant::now();
    let out = finish(child, Duration::from_secs(30));
    let grandchild: u32 = std::fs::read_to_string(pid_file.path()).unwrap().trim().parse().unwrap();
    // SAFETY: kill(2) of the sleep the child left behind.
    unsafe { libc::kill(grandchild as libc::pid_t, libc::SIGKILL) };
    assert!(out.status.success());
    assert!(started.elapsed() < Duration::from_secs(20), "took {:?}", started.elapsed());
    assert!(out.stdout.contains("the pipe was still open"), "{}", out.stdout);
}

/// An accept with no one connecting fails with what it waited for.
#[test]
fn an_accept_nobody_answers_fails_with_what_it_waited_for() {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let failed =
        std::panic::catch_unwind(|| accept_within(&listener, Duration::from_millis(200), "the program's client"))
            .map(|_| ())
            .unwrap_err();
    let message = failed.downcast_ref::<String>().cloned().unwrap_or_default();
    assert!(message.starts_with("no connection from the program's client within 200ms"), "{message}");
}

/// A test binary that runs past its deadline ends, saying so: this binary run again with a
/// deadline of 1 s and only the test below, which outlasts it.
#[test]
fn a_test_binary_past_its_deadline_ends_saying_so() {
    let mut command = Command::new(std::env::current_exe().unwrap());
    command.args(["--exact", "sleeper_for_the_deadline", "--nocapture"]);
    command
        .env("LUAMOTION_TEST_DEADLINE_S", "1")
        .env("HARNESS_SLEEPER", "1")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let started = Instant::now();
    let out = finish(command.spawn().unwrap(), Duration::from_secs(30));
    assert_eq!(out.status.code(), Some(124), "{out:?}");
    assert!(out.stderr.contains("ran longer than its deadline of 1 s"), "{}", out.stderr);
    assert!(started.elapsed() < Duration::from_secs(20), "took {:?}", started.elapsed());
}

/// Run only by the test above (which sets `HARNESS_SLEEPER`): a test that outlasts its
/// binary's deadline.
#[test]
fn sleeper_for_the_deadline() {
    if std::env::var_os("HARNESS_SLEEPER").is_some() {
        std::thread::sleep(Duration::from_secs(60));
    }
}

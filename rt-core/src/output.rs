//! A script's output on its way to the operator: the supervisor forwards each line with
//! `[task N] ` in front. Whatever a program writes, the controller holds one bounded line
//! per stream (`ipc::output::Lines`), the operator's terminal gets no control characters
//! (they and bytes that are no UTF-8 arrive escaped, `\r` as `\r`, ESC as `\x1b`), and a
//! task's flood is cut to `LINES_PER_SECOND`: the lines beyond are dropped and counted,
//! and the count is said once lines pass again.

use std::io::{ErrorKind, Read, Write};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use ipc::output::{Lines, MARKER_BYTES, MAX_LINE_BYTES, cut_marker, escape};

/// The lines of one task (stdout and stderr together) that reach the operator each second.
pub const LINES_PER_SECOND: u32 = 1000;
const WINDOW: Duration = Duration::from_secs(1);

/// Counts one task's lines per second.
#[derive(Debug)]
pub struct Throttle {
    window: Instant,
    passed: u32,
    dropped: u64,
}

impl Throttle {
    pub fn new(now: Instant) -> Self {
        Throttle { window: now, passed: 0, dropped: 0 }
    }

    /// Whether a line passes at `now`, and how many lines were dropped before it that have
    /// not been reported yet (said once a new second begins).
    fn admit(&mut self, now: Instant) -> (bool, u64) {
        let mut report = 0;
        if now.duration_since(self.window) >= WINDOW {
            report = std::mem::take(&mut self.dropped);
            self.window = now;
            self.passed = 0;
        }
        if self.passed < LINES_PER_SECOND {
            self.passed += 1;
            (true, report)
        } else {
            self.dropped += 1;
            (false, report)
        }
    }

    /// The drops not reported yet, at the end of a stream.
    fn take_dropped(&mut self) -> u64 {
        std::mem::take(&mut self.dropped)
    }
}

/// Copies one output stream of task `task` to `out` until the stream ends. With
/// `last_line` (stderr) keeps the last line, as shown: a failing script writes its error
/// there last.
pub fn forward(
    mut stream: impl Read,
    mut out: impl Write,
    task: u8,
    throttle: &Mutex<Throttle>,
    last_line: Option<&Mutex<Option<String>>>,
) {
    // The script process cut its lines already; its marker is not cut again.
    let mut lines = Lines::new(MAX_LINE_BYTES + MARKER_BYTES);
    let mut buffer = [0u8; 8192];
    let mut one_line = |line: &[u8], cut: u64| {
        let mut text = escape(line);
        if cut > 0 {
            text += &cut_marker(cut);
        }
        let (pass, dropped) = throttle.lock().map(|mut t| t.admit(Instant::now())).unwrap_or((true, 0));
        if dropped > 0 {
            let _ = out.write_all(dropped_notice(task, dropped).as_bytes());
        }
        if pass {
            let _ = out.write_all(format!("[task {task}] {text}\n").as_bytes());
        }
        if let Some(last) = last_line
            && let Ok(mut last) = last.lock()
        {
            *last = Some(text);
        }
    };
    loop {
        match stream.read(&mut buffer) {
            Ok(0) => break,
            Ok(n) => lines.feed(&buffer[..n], &mut one_line),
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(_) => break,
        }
    }
    lines.finish(&mut one_line);
    let dropped = throttle.lock().map(|mut t| t.take_dropped()).unwrap_or(0);
    if dropped > 0 {
        let _ = out.write_all(dropped_notice(task, dropped).as_bytes());
    }
}

/// `forward` in a thread of its own, sharing the task's throttle.
pub fn spawn_forward(
    stream: impl Read + Send + 'static,
    out: impl Write + Send + 'static,
    task: u8,
    throttle: Arc<Mutex<Throttle>>,
    last_line: Option<Arc<Mutex<Option<String>>>>,
) -> std::thread::JoinHandle<()> {
    // A small stack: the controller locks its memory, so each thread's whole stack is
    // touched and kept (2 MiB by default, two threads per task).
    std::thread::Builder::new()
        .stack_size(FORWARDER_STACK)
        .spawn(move || forward(stream, out, task, &throttle, last_line.as_deref()))
        .expect("the OS starts a thread")
}

/// The stack of a thread forwarding one stream: `forward`'s buffer and one line beside.
const FORWARDER_STACK: usize = 256 * 1024;

fn dropped_notice(task: u8, dropped: u64) -> String {
    format!("[task {task}] … [{dropped} lines dropped: more than {LINES_PER_SECOND} a second]\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn forwarded(input: &[u8]) -> (String, Option<String>) {
        let throttle = Mutex::new(Throttle::new(Instant::now()));
        let last = Mutex::new(None);
        let mut out = Vec::new();
        forward(input, &mut out, 7, &throttle, Some(&last));
        (String::from_utf8(out).unwrap(), last.into_inner().unwrap())
    }

    #[test]
    fn control_characters_and_bytes_that_are_no_utf8_arrive_escaped() {
        let (out, last) = forwarded(b"a\rb\x1b[2J\tc\xff\xfe\xc3\xa9\n\x07bell");
        assert_eq!(out, "[task 7] a\\rb\\x1b[2J\tc\\xff\\xfe\u{e9}\n[task 7] \\x07bell\n");
        assert_eq!(last.as_deref(), Some("\\x07bell"), "a last line without newline counts");
    }

    #[test]
    fn a_long_line_is_cut_with_a_marker_and_kept_as_the_last_line() {
        let mut input = vec![b'y'; 5_000_000];
        input.push(b'\n');
        let (out, last) = forwarded(&input);
        let kept = MAX_LINE_BYTES + MARKER_BYTES;
        let expected = format!("{}{}", "y".repeat(kept), cut_marker(5_000_000 - kept as u64));
        assert_eq!(out, format!("[task 7] {expected}\n"));
        assert_eq!(last, Some(expected));
    }

    #[test]
    fn a_flood_is_throttled_and_the_drops_are_counted() {
        let input: Vec<u8> = (0..50_000).flat_map(|i| format!("line {i}\n").into_bytes()).collect();
        let (out, last) = forwarded(&input);
        let (mut passed, mut dropped) = (0, 0);
        for line in out.lines() {
            let text = line.strip_prefix("[task 7] ").expect("prefixed");
            match text.strip_prefix("… [").and_then(|t| t.split_once(" lines dropped: more than 1000 a second]")) {
                Some((n, "")) => dropped += n.parse::<u64>().unwrap(),
                _ => passed += 1,
            }
        }
        assert!(out.starts_with("[task 7] line 0\n[task 7] line 1\n"));
        assert!(passed >= LINES_PER_SECOND as u64 && passed < 50_000, "{passed} lines passed");
        assert_eq!(passed + dropped, 50_000, "every line is shown or counted");
        assert_eq!(last.as_deref(), Some("line 49999"), "the last line is kept even when dropped");
    }

    #[test]
    fn the_drops_of_one_second_are_said_before_the_next_line() {
        let start = Instant::now();
        let mut throttle = Throttle::new(start);
        let results: Vec<(bool, u64)> = (0..LINES_PER_SECOND + 5).map(|_| throttle.admit(start)).collect();
        assert!(results[..LINES_PER_SECOND as usize].iter().all(|&r| r == (true, 0)));
        assert!(results[LINES_PER_SECOND as usize..].iter().all(|&r| r == (false, 0)));
        assert_eq!(throttle.admit(start + WINDOW), (true, 5));
        assert_eq!(throttle.take_dropped(), 0);
    }
}

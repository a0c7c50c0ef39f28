//! `luamotion test`: Lua test programs, each on a fresh controller (`luamotion run` in a
//! process of its own: its own namespace, data directory and User ASCII port), several at
//! a time, with a summary, JUnit XML and an exit code for CI.
//!
//! A file passes when its run ends well (every task finished), none of its expectations
//! (`expect_eq`, `expect_near`, `expect_true`) failed, and, if a `.expected` file lies
//! beside it, its task 0 printed those lines in that order (see `Expected`).

use std::fmt::Write as _;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitCode, Stdio};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use api::Local;

/// How the controllers of the tests keep time: the simulation clock as fast as the programs
/// allow, so a test takes the CPU time it needs and prints the same lines run after run.
const CLOCK: &[&str] = &["--clock", "sim", "--speed", "max"];

/// How long a stopped run may take to shut down before it is killed.
const SHUTDOWN_GRACE: Duration = Duration::from_secs(10);

#[derive(clap::Args, Debug)]
pub struct TestArgs {
    /// Lua test programs, or folders: every `*.lua` directly in a folder, in name order.
    /// Beside a program, `NAME.toml` is its machine file and `NAME.expected` the lines its
    /// task 0 must print, in order (`#` starts a comment, `~ text` matches a part of a
    /// line, `{version}` is luamotion's version).
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// How many files run at the same time [default: the number of cores].
    #[arg(short = 'j', long)]
    jobs: Option<usize>,
    /// Write the results as JUnit XML into this file.
    #[arg(long)]
    junit: Option<PathBuf>,
    /// Seconds a file may run; a run still going then is stopped and counts as an error.
    #[arg(long, default_value_t = 300)]
    timeout: u64,
}

pub fn test(args: TestArgs) -> Result<ExitCode> {
    let files = match collect(&args.paths) {
        Ok(files) => files,
        Err(message) => {
            eprintln!("error: {message}");
            return Ok(ExitCode::from(2));
        }
    };
    let jobs = args.jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())).max(1);
    let exe = std::env::current_exe().context("locate the luamotion binary")?;
    let timeout = Duration::from_secs(args.timeout);
    let started = Instant::now();

    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<FileResult>>> = Mutex::new((0..files.len()).map(|_| None).collect());
    std::thread::scope(|scope| {
        for _ in 0..jobs.min(files.len()) {
            scope.spawn(|| {
                loop {
                    let index = next.fetch_add(1, Ordering::Relaxed);
                    let Some(file) = files.get(index) else { break };
                    let result = run_file(&exe, file, index, timeout);
                    crate::stdout::sayln!("{:<5} {} ({:.1} s)", result.verdict.word(), file.display(), result.seconds);
                    results.lock().unwrap_or_else(|e| e.into_inner())[index] = Some(result);
                }
            });
        }
    });
    let results: Vec<FileResult> =
        results.into_inner().unwrap_or_else(|e| e.into_inner()).into_iter().flatten().collect();
    let seconds = started.elapsed().as_secs_f64();

    crate::stdout::say!("{}", summary(&results, seconds));
    if let Some(path) = &args.junit {
        std::fs::write(path, junit(&results, seconds)).with_context(|| format!("write {}", path.display()))?;
    }
    Ok(if results.iter().all(|r| r.verdict == Verdict::Passed) { ExitCode::SUCCESS } else { ExitCode::FAILURE })
}

/// The test programs the paths name, each once, in the order given (a folder's in name
/// order); what is wrong with a path otherwise.
fn collect(paths: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    let mut files = Vec::new();
    for path in paths {
        let metadata = std::fs::metadata(path).map_err(|e| format!("{}: {e}", path.display()))?;
        if metadata.is_dir() {
            let entries = std::fs::read_dir(path).map_err(|e| format!("{}: {e}", path.display()))?;
            let mut found: Vec<PathBuf> =
                entries.flatten().map(|e| e.path()).filter(|p| is_lua(p) && p.is_file()).collect();
            if found.is_empty() {
                return Err(format!("{}: no Lua test programs (*.lua) in this folder", path.display()));
            }
            found.sort();
            files.extend(found);
        } else if is_lua(path) {
            files.push(path.clone());
        } else {
            return Err(format!("{}: not a Lua program (the name must end in .lua)", path.display()));
        }
    }
    let mut seen = std::collections::HashSet::new();
    files.retain(|f| seen.insert(std::fs::canonicalize(f).unwrap_or_else(|_| f.clone())));
    Ok(files)
}

fn is_lua(path: &Path) -> bool {
    path.extension().is_some_and(|e| e == "lua")
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Verdict {
    Passed,
    /// An expectation or an expected line failed.
    Failed,
    /// The program or its controller did not end well (a Lua error, a timeout, a bad machine file).
    Error,
}

impl Verdict {
    fn word(self) -> &'static str {
        match self {
            Verdict::Passed => "PASS",
            Verdict::Failed => "FAIL",
            Verdict::Error => "ERROR",
        }
    }
}

/// One thing that went wrong in a file: where (`file:line`, when known) and what.
#[derive(Debug)]
struct Failure {
    error: bool,
    location: Option<String>,
    message: String,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.location {
            Some(location) => write!(f, "{location}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

struct FileResult {
    file: PathBuf,
    seconds: f64,
    verdict: Verdict,
    failures: Vec<Failure>,
    stdout: String,
    stderr: String,
}

/// Runs one file on a controller of its own and judges it.
fn run_file(exe: &Path, file: &Path, index: usize, timeout: Duration) -> FileResult {
    let started = Instant::now();
    let ran = run_controller(exe, file, index, timeout);
    let seconds = started.elapsed().as_secs_f64();
    let (stdout, stderr, failures) = match ran {
        Ok(run) => {
            let failures = judge(file, &run);
            (run.stdout, run.stderr, failures)
        }
        Err(message) => (String::new(), String::new(), vec![Failure { error: true, location: None, message }]),
    };
    let verdict = if failures.iter().any(|f| f.error) {
        Verdict::Error
    } else if failures.is_empty() {
        Verdict::Passed
    } else {
        Verdict::Failed
    };
    FileResult { file: file.to_path_buf(), seconds, verdict, failures, stdout, stderr }
}

struct Run {
    /// None: stopped after the timeout.
    success: Option<bool>,
    stdout: String,
    stderr: String,
    timeout: Duration,
}

/// `luamotion run` with the file as task 0, on the built-in machine or `NAME.toml` beside it.
fn run_controller(exe: &Path, file: &Path, index: usize, timeout: Duration) -> Result<Run, String> {
    let dir = tempfile::Builder::new()
        .prefix("luamotion-test-")
        .tempdir()
        .map_err(|e| format!("cannot make a temporary folder: {e}"))?;
    let ns = format!("test-{}-{index}", std::process::id());
    let mut command = Command::new(exe);
    // A test program's mistakes are its result, in the VM's own words (`run` would refuse
    // them before the start, with the check's).
    command
        .args(["run", "--no-check", "--ns", &ns, "--ascii-user-port", "0", "--data-dir"])
        .arg(dir.path())
        .args(CLOCK);
    let machine = file.with_extension("toml");
    if machine.is_file() {
        command.arg("--config").arg(&machine);
    }
    let mut child = command
        .arg(file)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start {}: {e}", exe.display()))?;
    let stdout = drain(child.stdout.take());
    let stderr = drain(child.stderr.take());
    let success = wait(&mut child, timeout);
    let text = |reader: std::thread::JoinHandle<String>| reader.join().unwrap_or_default();
    Ok(Run { success, stdout: text(stdout), stderr: text(stderr), timeout })
}

/// A pipe read to its end in a thread, so that neither pipe fills while the other is read.
fn drain(pipe: Option<impl Read + Send + 'static>) -> std::thread::JoinHandle<String> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        if let Some(mut pipe) = pipe {
            let _ = pipe.read_to_end(&mut bytes);
        }
        String::from_utf8_lossy(&bytes).into_owned()
    })
}

/// Whether the run succeeded; None when it was still going after `timeout` and was
/// stopped (SIGTERM: the controller shuts down in order, then SIGKILL after a grace).
fn wait(child: &mut Child, timeout: Duration) -> Option<bool> {
    let deadline = Instant::now() + timeout;
    let child_status = |child: &mut Child| child.try_wait().ok().flatten();
    loop {
        if let Some(status) = child_status(child) {
            return Some(status.success());
        }
        if Instant::now() >= deadline {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    // SAFETY: kill(2) of our own child, which has not been reaped yet.
    unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGTERM) };
    let grace = Instant::now() + SHUTDOWN_GRACE;
    while child_status(child).is_none() && Instant::now() < grace {
        std::thread::sleep(Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
    None
}

/// Everything that went wrong in a finished run.
fn judge(file: &Path, run: &Run) -> Vec<Failure> {
    let mut failures = Vec::new();
    for (_, text) in task_lines(&run.stdout) {
        if let Some(failure) = expectation_failure(text) {
            failures.push(failure);
        }
    }
    let expectations = failures.len();
    // `run` says how each task ended; a Lua error's reason is `file:line: message`.
    for line in run.stderr.lines() {
        let Some((_, reason)) = line.strip_prefix("task ").and_then(|l| l.split_once("): failed: ")) else { continue };
        // The end of a program whose expectations failed: they are listed already.
        if expectations > 0 && reason.ends_with(" failed") && reason.contains(" expectation") {
            continue;
        }
        let (location, message) = split_location(reason);
        failures.push(Failure { error: true, location, message: message.to_string() });
    }
    let expected = file.with_extension("expected");
    if expected.is_file() {
        match std::fs::read_to_string(&expected) {
            Ok(text) => {
                let printed: Vec<&str> = task_lines(&run.stdout).filter(|(t, _)| *t == 0).map(|(_, l)| l).collect();
                failures.extend(Expected::parse(&text).missing(&printed).into_iter().map(|(line, want)| Failure {
                    error: false,
                    location: Some(format!("{}:{line}", expected.display())),
                    message: format!("{want} was not printed (in order)"),
                }));
            }
            Err(e) => {
                failures.push(Failure { error: true, location: None, message: format!("{}: {e}", expected.display()) })
            }
        }
    }
    match run.success {
        None => failures.push(Failure {
            error: true,
            location: None,
            message: format!("still running after {} s: stopped (--timeout)", run.timeout.as_secs()),
        }),
        Some(false) if failures.is_empty() => {
            // The controller itself failed (a machine file it refused, no room in /dev/shm).
            let said = run.stderr.lines().filter(|l| l.starts_with("error: ")).collect::<Vec<_>>().join("; ");
            let message = if said.is_empty() { "luamotion run failed".to_string() } else { said };
            failures.push(Failure { error: true, location: None, message });
        }
        _ => {}
    }
    failures
}

/// The program lines of a run's stdout: (task, text).
fn task_lines(stdout: &str) -> impl Iterator<Item = (u8, &str)> {
    stdout.lines().filter_map(|line| {
        let rest = line.strip_prefix("[task ")?;
        let (task, text) = rest.split_once("] ")?;
        Some((task.parse().ok()?, text))
    })
}

/// `file:line: expect_x failed: why`, as the expectations print it.
fn expectation_failure(text: &str) -> Option<Failure> {
    let (location, rest) = split_location(text);
    let location = location?;
    let names = [Local::expect_eq, Local::expect_near, Local::expect_true].map(|l| l.spec().name);
    names.iter().any(|name| rest.strip_prefix(name).is_some_and(|r| r.starts_with(" failed: "))).then(|| Failure {
        error: false,
        location: Some(location),
        message: rest.to_string(),
    })
}

/// Lua's `file:line: message` split at the first `:<digits>: `; no location if it has none.
fn split_location(text: &str) -> (Option<String>, &str) {
    for (colon, _) in text.match_indices(':') {
        let after = &text[colon + 1..];
        let digits = after.bytes().take_while(u8::is_ascii_digit).count();
        if digits > 0 && after[digits..].starts_with(": ") {
            let end = colon + 1 + digits;
            return (Some(text[..end].to_string()), &text[end + 2..]);
        }
    }
    (None, text)
}

/// `NAME.expected`: the lines task 0 must print, in this order; other lines may come
/// between. Empty lines and lines starting with `#` (the manual's references) are
/// comments; `~ text` matches a line that contains `text`; `= text` a line equal to
/// `text` (for texts that start with `#`, `~` or `=`); any other line must be printed
/// as it is, whole. `{version}` stands for luamotion's version (`GetFirmwareVer`).
#[derive(Debug, PartialEq)]
struct Expected {
    /// (line in the file, what to match)
    lines: Vec<(usize, Match)>,
}

#[derive(Debug, PartialEq)]
enum Match {
    Whole(String),
    Contains(String),
}

impl std::fmt::Display for Match {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Match::Whole(text) => write!(f, "the line {text:?}"),
            Match::Contains(text) => write!(f, "a line with {text:?}"),
        }
    }
}

impl Expected {
    fn parse(text: &str) -> Self {
        let lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
            .map(|(i, l)| {
                let l = l.replace("{version}", env!("CARGO_PKG_VERSION"));
                let wanted = match (l.strip_prefix("~ "), l.strip_prefix("= ")) {
                    (Some(part), _) => Match::Contains(part.to_string()),
                    (None, Some(whole)) => Match::Whole(whole.to_string()),
                    (None, None) => Match::Whole(l.to_string()),
                };
                (i + 1, wanted)
            })
            .collect();
        Expected { lines }
    }

    /// The expected lines not printed in order. Each is looked for after the last one
    /// found, so one missing line does not hide the others.
    fn missing<'a>(&'a self, printed: &[&str]) -> Vec<(usize, &'a Match)> {
        let mut from = 0;
        let mut missing = Vec::new();
        for (line, wanted) in &self.lines {
            let found = printed[from..].iter().position(|p| match wanted {
                Match::Whole(text) => p == text,
                Match::Contains(text) => p.contains(text.as_str()),
            });
            match found {
                Some(at) => from += at + 1,
                None => missing.push((*line, wanted)),
            }
        }
        missing
    }
}

/// What the operator reads at the end: every file that did not pass with its failures
/// and the end of its output, then the counts.
fn summary(results: &[FileResult], seconds: f64) -> String {
    const TAIL: usize = 20;
    let mut out = String::new();
    for result in results.iter().filter(|r| r.verdict != Verdict::Passed) {
        let _ = writeln!(out, "\n{} {}", result.verdict.word(), result.file.display());
        for failure in &result.failures {
            let _ = writeln!(out, "  {failure}");
        }
        let output: Vec<&str> = result.stdout.lines().chain(result.stderr.lines()).collect();
        if !output.is_empty() {
            let _ = writeln!(out, "  last lines of its output:");
            for line in &output[output.len().saturating_sub(TAIL)..] {
                let _ = writeln!(out, "    {line}");
            }
        }
    }
    let count = |v| results.iter().filter(|r| r.verdict == v).count();
    let _ = writeln!(
        out,
        "\n{} files: {} passed, {} failed, {} errors in {seconds:.1} s",
        results.len(),
        count(Verdict::Passed),
        count(Verdict::Failed),
        count(Verdict::Error)
    );
    out
}

/// The JUnit XML CI servers read: one testsuite, a testcase per file with a `failure` (an
/// expectation or expected line) or an `error` (the program or its controller did not
/// end well), and the run's output.
fn junit(results: &[FileResult], seconds: f64) -> String {
    let count = |v| results.iter().filter(|r| r.verdict == v).count();
    let totals = format!(
        r#"tests="{}" failures="{}" errors="{}" time="{seconds:.3}""#,
        results.len(),
        count(Verdict::Failed),
        count(Verdict::Error)
    );
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(out, r#"<testsuites name="luamotion test" {totals}>"#);
    let _ = writeln!(out, r#"  <testsuite name="luamotion test" {totals} skipped="0">"#);
    for result in results {
        let name = result.file.file_name().map(|n| n.to_string_lossy()).unwrap_or_default();
        let folder = result.file.parent().map(|p| p.display().to_string()).unwrap_or_default();
        let _ = writeln!(
            out,
            r#"    <testcase name="{}" classname="{}" file="{}" time="{:.3}">"#,
            xml(&name),
            xml(&folder),
            xml(&result.file.display().to_string()),
            result.seconds
        );
        if let Some(first) = result.failures.first() {
            let element = if result.verdict == Verdict::Error { "error" } else { "failure" };
            let all: Vec<String> = result.failures.iter().map(ToString::to_string).collect();
            let _ = writeln!(
                out,
                r#"      <{element} message="{}" type="{element}">{}</{element}>"#,
                xml(&first.to_string()),
                xml(&all.join("\n"))
            );
        }
        let _ = writeln!(out, "      <system-out>{}</system-out>", xml(&result.stdout));
        let _ = writeln!(out, "      <system-err>{}</system-err>", xml(&result.stderr));
        out.push_str("    </testcase>\n");
    }
    out.push_str("  </testsuite>\n</testsuites>\n");
    out
}

/// Text as XML 1.0 takes it in an attribute or an element: the markup characters escaped,
/// line ends kept, and the control characters XML cannot hold at all replaced by U+FFFD.
fn xml(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\n' => out.push_str("&#10;"),
            '\r' => out.push_str("&#13;"),
            '\t' => out.push_str("&#9;"),
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expected_lines_are_found_in_order_and_each_missing_one_is_named() {
        let expected = Expected::parse("# HMPL 2.1\nfirst\n~ sec\n\n= # third\nfourth\n");
        assert_eq!(expected.lines.len(), 4);
        let version = Expected::parse("v{version}");
        assert_eq!(version.lines, [(1, Match::Whole(format!("v{}", env!("CARGO_PKG_VERSION"))))]);
        assert!(expected.missing(&["first", "a second", "# third", "fourth"]).is_empty());
        // Out of order, and a part of a line where the whole is wanted.
        let missing = expected.missing(&["second", "first", "# third x", "fourth"]);
        assert_eq!(missing.iter().map(|(line, _)| *line).collect::<Vec<_>>(), [3, 5]);
    }

    #[test]
    fn lua_locations_and_expectation_lines_are_read() {
        assert_eq!(split_location("a/b.lua:12: boom: 3"), (Some("a/b.lua:12".into()), "boom: 3"));
        assert_eq!(split_location("no line here: x"), (None, "no line here: x"));
        let failure = expectation_failure("t.lua:7: expect_near failed: got 1.0, expected 2.0").expect("a failure");
        assert_eq!(failure.location.as_deref(), Some("t.lua:7"));
        assert!(expectation_failure("t.lua:7: expect_nearly failed: x").is_none());
        assert!(expectation_failure("expect_eq failed: no location").is_none());
    }

    #[test]
    fn xml_text_is_escaped_and_holds_no_character_xml_forbids() {
        assert_eq!(xml("a<b>&\"'\n\u{1}"), "a&lt;b&gt;&amp;&quot;&apos;&#10;\u{FFFD}");
    }
}

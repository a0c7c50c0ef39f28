//! End to end: what programs print, and how their errors read. Output is bounded per line
//! and per task whatever a program prints, and the controller's memory does not grow with
//! it; extreme `Print` formats return -1; the sandbox's messages say where and what.

mod common;

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::*;

/// `luamotion run` to its end, its output read while it runs (a flood would fill the
/// pipes), and the peak resident memory of the controller process (VmHWM, kB).
fn run_measured(ns: &str, config: &Path) -> (Finished, u64) {
    let mut child = Command::new(BIN)
        .args(["run", "--ns", ns, "--data-dir"])
        .arg(data_dir(ns))
        .arg("--config")
        .arg(config)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start luamotion");
    let pid = child.id();
    let read = |mut stream: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            let _ = stream.read_to_end(&mut bytes);
            String::from_utf8_lossy(&bytes).into_owned()
        })
    };
    let stdout = read(Box::new(child.stdout.take().unwrap()));
    let stderr = read(Box::new(child.stderr.take().unwrap()));
    let deadline = Instant::now() + Duration::from_secs(240);
    let mut peak_kb = 0;
    while child.try_wait().unwrap().is_none() {
        if let Ok(status) = std::fs::read_to_string(format!("/proc/{pid}/status"))
            && let Some(kb) = status.lines().find_map(|l| l.strip_prefix("VmHWM:"))
        {
            peak_kb = peak_kb.max(kb.trim().trim_end_matches(" kB").trim().parse().unwrap_or(0));
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("timed out");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let status = child.wait().unwrap();
    let finished = Finished { status, stdout: stdout.join().unwrap(), stderr: stderr.join().unwrap() };
    (finished, peak_kb)
}

/// A machine file in `dir` with one autorun task per (program, memory limit). Building a
/// 24 MB string takes a loaded machine longer than the default watchdog.
fn machine(dir: &Path, tasks: &[(&str, &str, u32)]) -> std::path::PathBuf {
    let mut toml = String::from("cycle_us = 1000\n[[axes]]\n");
    for (id, (name, source, memory_mib)) in tasks.iter().enumerate() {
        let path = program(dir, name, source);
        toml += &format!(
            "[[tasks]]\nid = {id}\nprogram = {:?}\nautorun = true\nmemory_limit_mib = {memory_mib}\nwatchdog_ms = 10000\n",
            path.display().to_string()
        );
    }
    let path = dir.join("machine.toml");
    std::fs::write(&path, toml).unwrap();
    path
}

/// Issue 11, defect 3: a 300 MB `Print` field in a 16 MiB task, a 24 MB `my_print`, a
/// 5 MB `print` (the second variant: Lua's own print) and a flood of a million lines.
/// The controller stays small, long lines arrive cut with the marker, the flood is
/// throttled and every line is either shown or counted, and every program ends normally.
#[test]
fn output_is_bounded_per_line_and_per_task() {
    let dir = tempfile::tempdir().unwrap();
    let config = machine(
        dir.path(),
        &[
            ("wide.lua", "local r = Print('%300000000d', 7)\nPrint('wide returned %d', r)\n", 16),
            (
                "long.lua",
                "my_print(string.rep('m', 24000000))\nprint(string.rep('p', 5000000), 'tail')\nmy_print('long done')\n",
                64,
            ),
            ("flood.lua", "for i = 1, 1000000 do Print('flood %d', i) end\n", 64),
        ],
    );
    let (out, peak_kb) = run_measured(&unique_ns("output"), &config);
    let context = format!("{}\n{}", &out.stderr[out.stderr.len().saturating_sub(3000)..], peak_kb);
    assert!(out.status.success(), "{context}");
    for name in ["wide.lua", "long.lua", "flood.lua"] {
        assert!(out.stderr.contains(&format!("/{name}): finished")), "{name}: {context}");
    }
    // The controller started at about 40 MB; it used to reach 1.4 GB.
    assert!(peak_kb < 120_000, "the controller's peak memory: {peak_kb} kB");

    assert_eq!(out.lines_of_task(0), vec!["wide returned -1"], "{context}");
    let long = out.lines_of_task(1);
    assert_eq!(long.len(), 3, "{context}");
    assert_eq!(long[0], format!("{} … [cut: {} bytes]", "m".repeat(4096), 24_000_000 - 4096));
    assert_eq!(long[1], format!("{} … [cut: {} bytes]", "p".repeat(4096), 5_000_000 + 5 - 4096));
    assert_eq!(long[2], "long done");

    let (mut shown, mut dropped) = (0u64, 0u64);
    for line in out.stdout.lines().chain(out.stderr.lines()).filter_map(|l| l.strip_prefix("[task 2] ")) {
        match line.strip_prefix("… [").and_then(|l| l.strip_suffix(" lines dropped: more than 1000 a second]")) {
            Some(n) => dropped += n.parse::<u64>().unwrap(),
            None => {
                assert!(line.starts_with("flood "), "{line}");
                shown += 1;
            }
        }
    }
    assert!(dropped > 0 && shown < 1_000_000, "shown {shown}, dropped {dropped}");
    assert_eq!(shown + dropped, 1_000_000, "every line is shown or counted");
}

/// Issue 11, defect 4 (HMPL 3.2: -1 on a bad format): widths and precisions that used to
/// panic or abort the script process, and the second variants (`%g`, `%s`, `*`).
#[test]
fn extreme_print_formats_return_minus_one() {
    let dir = tempfile::tempdir().unwrap();
    let formats = [
        "%.100000000f",
        "%99999999999999999999999d",
        "%.99999999999g",
        "%99999999999s",
        "%-099999999999e",
        "%*d",
        "%.*f",
    ];
    let mut source = String::new();
    for fmt in formats {
        source += &format!("assert(Print({fmt:?}, 1.5, 2) == -1, {fmt:?})\n");
        source += &format!("assert(SendMsgEvent({fmt:?}, 1.5, 2) ~= 0, {fmt:?})\n");
    }
    source += "Print('alive %d', 1)\n";
    let path = program(dir.path(), "formats.lua", &source);
    let out = run(&unique_ns("formats"), &[path.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    assert_eq!(out.lines_of_task(0), vec!["alive 1"], "{}", out.stderr);
    assert!(out.stderr.contains("warning: Print(\"%.100000000f\"): a width or precision above 512"), "{}", out.stderr);
}

/// Issue 11, defect 9: each row is a program (a task of one run) and what its output or
/// its end must say; the second half of the table are variants the fixes were not written
/// for.
#[test]
fn sandbox_messages_say_where_and_what() {
    let dir = tempfile::tempdir().unwrap();
    let rows: &[(&str, &str, &str)] = &[
        ("load.lua", "print(load('return math.pi')())", "[task 0] 3.1415926535898"),
        ("error_table.lua", "local x = 1\nerror({})", "error_table.lua:2: (error object is a table value)"),
        ("error_nil.lua", "local x = 1\nerror()", "error_nil.lua:2: (error object is a nil value)"),
        (
            "tostring_fails.lua",
            "local x = 1\nerror(setmetatable({}, {__tostring = function() error('inner') end}))",
            "tostring_fails.lua:2: (error object is a table value whose __tostring failed: /",
        ),
        (
            "recursion.lua",
            "local function f(n) return 1 + f(n + 1) end\nf(1)",
            "recursion.lua:1: stack overflow (more than 50000 nested calls)",
        ),
        (
            "bytes.lua",
            "print('a\\255b\\r\\27[31m')\nPrint('%s|', '\\254')",
            "[task 5] a\\xffb\\r\\x1b[31m\n[task 5] \\xfe|",
        ),
        (
            "caught.lua",
            "local ok, e = pcall(MoveAbs, 'x')\nprint(e)",
            "caught.lua:1: bad argument #1 to 'MoveAbs' (integer expected, got string)\n",
        ),
        ("mutex.lua", "MutexLock(8)", "mutex.lua:1: MutexLock: mutex ids are 0..7, not integer 8 (0x138F)"),
        (
            "hang_in_c.lua",
            "local s = string.find(string.rep('a', 40), string.rep('a*', 20) .. 'b')",
            "watchdog: no progress for 500 ms at line 1 ",
        ),
        // Second variants.
        (
            "load_in_function.lua",
            "local function f() return load('return Print')() end\nprint(f() ~= nil)",
            "[task 9] true",
        ),
        ("error_number.lua", "local x = 1\nerror(42)", "error_number.lua:2: 42"),
        (
            "error_tostring.lua",
            "local x = 1\nerror(setmetatable({}, {__tostring = function() return 'custom' end}))",
            "error_tostring.lua:2: custom",
        ),
        (
            "call_recursion.lua",
            "local t = setmetatable({}, {__call = function(self, n) return 1 + self(n + 1) end})\nt(1)",
            "call_recursion.lua:1: stack overflow (more than 50000 nested calls)",
        ),
        (
            "caught_in_coroutine.lua",
            "local co = coroutine.create(function() GetPosFb({}) end)\nprint(select(2, coroutine.resume(co)))",
            "caught_in_coroutine.lua:1: bad argument #1 to 'GetPosFb' (integer expected, got table)\n",
        ),
        ("mutex_float.lua", "MutexUnlock(2.5)", "MutexUnlock: mutex ids are 0..7, not number 2.5 (0x138F)"),
        ("long_error.lua", "error(string.rep('e', 100000))", "long_error.lua:1: eeeeeeee"),
    ];
    let paths: Vec<String> =
        rows.iter().map(|(name, source, _)| program(dir.path(), name, source).display().to_string()).collect();
    // The VM's own messages: the check would refuse several of these programs first.
    let args: Vec<&str> = ["--no-check"].into_iter().chain(paths.iter().map(String::as_str)).collect();
    let out = run(&unique_ns("messages"), &args);
    let all = format!("{}\n{}", out.stdout, out.stderr);
    for (task, (name, _, expected)) in rows.iter().enumerate() {
        // Lines of different tasks interleave, so each expected line is looked for alone.
        for line in expected.split_inclusive('\n') {
            assert!(all.contains(line), "task {task} ({name}) should say {line:?}:\n{all}");
        }
    }
    assert!(!out.stdout.contains("[task 6] stack traceback") && !out.stdout.contains("runtime error"), "{all}");
    // The controller cut the long error line (the script process does not cut errors).
    let failed = all.lines().find(|l| l.contains("long_error.lua): failed:")).unwrap();
    assert!(failed.len() < 4300 && failed.ends_with(" bytes]"), "{}", &failed[failed.len().saturating_sub(100)..]);
}

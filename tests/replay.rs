//! End to end: a run on the simulation clock fed from outside (Modbus TCP writes of DV
//! words by mbpoll, serial port 1's bytes from socat) is recorded with `--record`, then
//! replayed with `--replay` without the outside peers: the same trace digest and the same
//! output, replay after replay. Bad record files are refused with their line.

mod common;

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{self, Receiver};
use std::time::Duration;

use common::*;

/// What a run said: its output lines and its end.
struct Said {
    lines: Vec<String>,
    out: Finished,
}

impl Said {
    /// The `fnv1a64:...` digest and the cycles it covers, from the end line.
    fn digest(&self) -> String {
        let stderr = &self.out.stderr;
        let line = stderr.lines().find(|l| l.contains("trace digest")).unwrap_or_else(|| panic!("no digest: {stderr}"));
        line.split_once("trace digest ").map(|(_, digest)| digest.to_string()).expect("digest")
    }

    fn task_lines(&self) -> Vec<&str> {
        self.lines.iter().filter_map(|l| l.strip_prefix("[task 0] ")).collect()
    }
}

/// `luamotion run --clock sim ARGS`, its stdout lines read as they come.
fn start(ns: &str, args: &[&str]) -> (Child, Receiver<String>) {
    let mut child = start_run(ns, &[&["--clock", "sim"], args].concat());
    let stdout = child.stdout.take().expect("stdout");
    let (tx, lines) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    (child, lines)
}

/// Reads lines until one contains `text`; returns the lines read (that one last).
fn until(lines: &Receiver<String>, text: &str, seen: &mut Vec<String>) -> String {
    loop {
        let line = lines.recv_timeout(Duration::from_secs(60)).unwrap_or_else(|_| panic!("no {text:?} in {seen:#?}"));
        seen.push(line.clone());
        if line.contains(text) {
            return line;
        }
    }
}

/// Waits for the run's end and the rest of its output.
fn end(child: Child, lines: Receiver<String>, mut seen: Vec<String>) -> Said {
    let out = finish(child, Duration::from_secs(240));
    seen.extend(lines.try_iter());
    Said { lines: seen, out }
}

/// Replays `record` twice (fresh namespaces, no peers): both like `recorded`.
fn replays_match(recorded: &Said, record: &Path, args: &[&str]) {
    assert!(recorded.out.status.success(), "{:#?}\n{}", recorded.lines, recorded.out.stderr);
    for _ in 0..2 {
        let ns = unique_ns("replay");
        let (child, lines) = start(&ns, &[&["--speed", "max", "--replay", record.to_str().unwrap()], args].concat());
        let replayed = end(child, lines, Vec::new());
        assert!(replayed.out.status.success(), "{}", replayed.out.stderr);
        assert_eq!(replayed.task_lines(), recorded.task_lines(), "{}", replayed.out.stderr);
        assert_eq!(replayed.digest(), recorded.digest(), "{}", replayed.out.stderr);
    }
}

fn machine(dir: &Path) -> PathBuf {
    let path = dir.join("machine.toml");
    std::fs::write(&path, "[[axes]]\n").unwrap();
    path
}

/// `mbpoll` on the controller's Modbus TCP port: holding registers from `reference`,
/// 0-based; writes `values`, or reads one word without them.
fn mbpoll(port: &str, reference: &str, values: &[&str]) -> String {
    let out = Command::new(debian_tool("mbpoll"))
        .args(["-m", "tcp", "-p", port, "-a", "1", "-0", "-1", "-r", reference, "127.0.0.1"])
        .args(values)
        .output()
        .expect("mbpoll");
    // mbpoll writes `[1]: <tab>7`.
    let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    said.lines().map(|l| l.split_whitespace().collect::<Vec<_>>().join(" ")).collect::<Vec<_>>().join("\n")
}

/// DV word 0 written three times by mbpoll (the second time with FC 16, DV 5 beside it,
/// after a write of DH 0), each write moving the axis once the program sees it; the
/// program acknowledges each value in DV 1, which mbpoll reads before it writes the next.
#[test]
fn modbus_writes_are_recorded_and_replayed() {
    let dir = tempfile::tempdir().unwrap();
    let program = program(
        dir.path(),
        "dv.lua",
        "Enable(0)\n\
         Till(function() return IsEnabled(0) end)\n\
         local last, start = 0, system_fclk\n\
         while last ~= 3 and system_fclk - start < 120000 do\n\
           local v = ReadModbusWord(0)\n\
           if v ~= last then\n\
             last = v\n\
             Print('dv0 %d at %d: dv5 %d, dh0 %d', v, system_fclk - start, ReadModbusWord(5), ReadModbusWord(0x8000))\n\
             MoveAbs(0, v * 10)\n\
             Till(function() return IsInPos(0) end)\n\
             WriteModbusWord(1, v)\n\
           end\n\
           Sleep(2)\n\
         end\n\
         Print('last %d at %.3f mm', last, GetPosFb(0))\n",
    );
    let (config, record) = (machine(dir.path()), dir.path().join("inputs.txt"));
    let ns = unique_ns("record-modbus");
    let paced = ["--config", config.to_str().unwrap(), "--speed", "20", "--modbus-port", "0"];
    let (child, lines) =
        start(&ns, &[&paced[..], &["--record", record.to_str().unwrap(), program.to_str().unwrap()]].concat());
    let mut seen = Vec::new();
    let address = until(&lines, "Modbus TCP on ", &mut seen);
    let port = address.rsplit(':').next().unwrap().to_string();
    let writes: [&[&str]; 3] = [&["1"], &["2", "0", "0", "0", "0", "42"], &["3"]];
    for (n, values) in writes.iter().enumerate() {
        if n == 1 {
            assert!(mbpoll(&port, "0x8000", &["7"]).contains("Written"));
        }
        let written = mbpoll(&port, "0", values);
        assert!(written.contains("Written"), "{written}");
        let acked = format!("[1]: {}", n + 1);
        assert!(
            eventually(Duration::from_secs(60), || mbpoll(&port, "1", &[]).contains(&acked)),
            "no {acked}: {seen:#?}"
        );
    }
    let recorded = end(child, lines, seen);
    let text = std::fs::read_to_string(&record).unwrap();
    let inputs: Vec<&str> = text.lines().skip(1).map(|l| l.split_once(' ').unwrap().1).collect();
    assert_eq!(
        inputs,
        [
            "modbus 0x0000 1",
            "modbus 0x8000 7",
            "modbus 0x0000 2",
            "modbus 0x0001 0",
            "modbus 0x0002 0",
            "modbus 0x0003 0",
            "modbus 0x0004 0",
            "modbus 0x0005 42",
            "modbus 0x0000 3"
        ],
        "{text}"
    );
    let said = recorded.task_lines();
    assert_eq!(said.len(), 4, "{said:?}\n{}", recorded.out.stderr);
    assert!(said[1].starts_with("dv0 2 at ") && said[1].ends_with("dv5 42, dh0 7"), "{said:?}");
    assert!(said[3].starts_with("last 3 at 30.000"), "{said:?}");
    replays_match(&recorded, &record, &["--config", config.to_str().unwrap(), program.to_str().unwrap()]);
}

/// Codes from socat on serial port 1's link, read by a program polling
/// `FreePort.Serial.Rx`, each moving the axis: recorded, then replayed without socat.
#[test]
fn serial_bytes_are_recorded_and_replayed() {
    let dir = tempfile::tempdir().unwrap();
    let program = program(
        dir.path(),
        "codes.lua",
        "Enable(0)\n\
         Till(function() return IsEnabled(0) end)\n\
         FreePort.Serial.Init(1, nil, CR_LF, 0x17)\n\
         my_print('reading codes')\n\
         local start, count = system_fclk, 0\n\
         while system_fclk - start < 120000 do\n\
           local rc, code, n = FreePort.Serial.Rx(1)\n\
           if rc == 0 and n > 0 then\n\
             if code == 'END' then break end\n\
             count = count + 1\n\
             Print('code %s at %d', code, system_fclk - start)\n\
             MoveRel(0, #code)\n\
           end\n\
           Sleep(1)\n\
         end\n\
         Till(function() return IsInPos(0) end)\n\
         Print('%d codes, at %.3f mm', count, GetPosFb(0))\n",
    );
    let (config, record, link) = (machine(dir.path()), dir.path().join("inputs.txt"), dir.path().join("ttyS1"));
    let ns = unique_ns("record-serial");
    let args = ["--config", config.to_str().unwrap(), "--speed", "20", "--serial-link", link.to_str().unwrap()];
    let (child, lines) =
        start(&ns, &[&args[..], &["--record", record.to_str().unwrap(), program.to_str().unwrap()]].concat());
    let mut seen = Vec::new();
    until(&lines, "reading codes", &mut seen);
    for chunk in [&b"A1\r\nBB22"[..], b"2\r\n", b"END\r\n"] {
        let mut socat = Command::new(debian_tool("socat"))
            .args(["-u", "STDIN"])
            .arg(format!("{},raw,echo=0,b38400", link.display()))
            .stdin(Stdio::piped())
            .spawn()
            .expect("socat");
        socat.stdin.take().unwrap().write_all(chunk).unwrap();
        assert!(socat.wait().unwrap().success());
        std::thread::sleep(Duration::from_millis(200));
    }
    let recorded = end(child, lines, seen);
    let text = std::fs::read_to_string(&record).unwrap();
    assert!(text.lines().count() >= 4 && text.lines().skip(1).all(|l| l.contains(" serial ")), "{text}");
    let said = recorded.task_lines();
    assert_eq!(said.len(), 4, "{said:?}\n{}", recorded.out.stderr);
    assert!(said[1].starts_with("code A1 at ") && said[2].starts_with("code BB222 at "), "{said:?}");
    assert_eq!(said[3], "2 codes, at 7.000 mm");
    replays_match(&recorded, &record, &["--config", config.to_str().unwrap(), program.to_str().unwrap()]);
}

/// A record that cannot be replayed is refused before anything starts, with its line.
#[test]
fn bad_records_are_refused_with_their_line() {
    let dir = tempfile::tempdir().unwrap();
    let program = program(dir.path(), "p.lua", "Print('ran')\n");
    let huge = format!("luamotion-inputs 1\n5 serial {}\n", "00".repeat(100_000));
    let cases: [(&str, &[u8], &str); 6] = [
        ("garbage", b"\x7fELF\x02\x01\x01\x00\x00\xff\xfe\n", "line 1: not a luamotion input record"),
        ("order", b"luamotion-inputs 1\n9 modbus 0x0000 1\n3 modbus 0x0000 2\n", "line 3: cycle 3 comes after cycle 9"),
        ("kind", b"luamotion-inputs 1\n1 modbus 0x0000 1\n2 freeport 0 6869\n", "line 3: unknown input `freeport`"),
        ("huge", huge.as_bytes(), "line 2: longer than 16384 bytes"),
        ("address", b"luamotion-inputs 1\n1 modbus 0x6B02 1\n", "line 2: 0x6B02 is not a DV, DH or FUN147 word"),
        ("empty", b"", "line 1: empty"),
    ];
    for (name, content, expected) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, content).unwrap();
        let out = run(&unique_ns("bad-record"), &["--replay", path.to_str().unwrap(), program.to_str().unwrap()]);
        assert!(!out.status.success(), "{name}");
        assert!(out.stderr.contains(expected), "{name}: {}", out.stderr);
        assert!(!out.stderr.contains("panicked") && out.stdout.is_empty(), "{name}: {}{}", out.stdout, out.stderr);
    }
    let missing = run(&unique_ns("bad-record"), &["--replay", "/nonexistent/inputs.txt", program.to_str().unwrap()]);
    assert!(missing.stderr.contains("cannot read /nonexistent/inputs.txt"), "{}", missing.stderr);
}

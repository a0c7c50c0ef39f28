//! End to end: a run on the simulation clock fed from outside (Modbus TCP writes of DV
//! words by mbpoll, serial port 1's bytes from socat, simulated inputs set through the web
//! view by nc) is recorded with `--record`, then
//! replayed with `--replay` without the outside peers: the same trace digest and the same
//! output, replay after replay. Bad record files are refused with their line.

mod common;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::Receiver;
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
    let lines = lines_of(child.stdout.take().expect("stdout"));
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
    seen.extend(rest_of(&lines, Duration::from_secs(10)));
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

/// One axis (slave 0) and an analog terminal (slave 1) with two inputs.
fn machine_with_terminal(dir: &Path) -> PathBuf {
    let path = dir.join("machine.toml");
    std::fs::write(&path, "[[axes]]\n\n[[slaves]]\ndevice = \"analog_io\"\ninputs = 2\noutputs = 2\n").unwrap();
    path
}

/// A program that prints controller input 3 and the terminal's input 1 whenever they
/// change (and the DV word 0 with `dv`), moving the axis to the input word in um while
/// input 3 is on; it ends when input 3 goes off again with the word at 5000.
fn inputs_program(dir: &Path) -> PathBuf {
    program(
        dir,
        "inputs.lua",
        "Enable(0)\n\
         Till(function() return IsEnabled(0) end)\n\
         my_print('waiting for inputs')\n\
         local start, seen = system_fclk, ''\n\
         while system_fclk - start < 600000 do\n\
           local g, a = GetGPI(3), GetSlvAIRaw(1, 1)\n\
           local now = string.format('gpi %d ai %d dv %d', g, a, ReadModbusWord(0))\n\
           if now ~= seen then\n\
             seen = now\n\
             Print('%s at %d', now, system_fclk)\n\
             if g == 1 then MoveAbs(0, a / 1000) Till(function() return IsInPos(0) end) end\n\
             if g == 0 and a == 5000 then break end\n\
           end\n\
           Sleep(1)\n\
         end\n\
         Print('at %.3f mm', GetPosFb(0))\n",
    )
}

/// An HTTP POST by nc to the web view at `port`, as its page sends it (its Host, Origin
/// and the token cookie the page sets); the answer's body.
fn post(port: &str, path: &str) -> String {
    let page = ureq::get(&format!("http://127.0.0.1:{port}/")).call().expect("the page");
    let cookie = page.headers().get("set-cookie").and_then(|c| c.to_str().ok()).expect("the token's cookie");
    let cookie = cookie.split(';').next().unwrap();
    let mut nc = Command::new(debian_tool("nc"))
        .args(["-w", "10", "127.0.0.1", port])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("nc");
    let host = format!("127.0.0.1:{port}");
    let request = format!(
        "POST {path} HTTP/1.1\r\nHost: {host}\r\nOrigin: http://{host}\r\nCookie: {cookie}\r\nContent-Length: 0\r\nConnection: close\r\n\r\n"
    );
    nc.stdin.take().unwrap().write_all(request.as_bytes()).unwrap();
    let out = nc.wait_with_output().expect("nc");
    String::from_utf8_lossy(&out.stdout).into_owned()
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

/// A program that moves the axis to 10 times DV word 0 whenever it changes and
/// acknowledges each value in DV 1, until DV 0 is 3.
fn dv_program(dir: &Path) -> PathBuf {
    program(
        dir,
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
    )
}

/// DV word 0 written three times by mbpoll (the second time with FC 16, DV 5 beside it,
/// after a write of DH 0), each write moving the axis once the program sees it; the
/// program acknowledges each value in DV 1, which mbpoll reads before it writes the next
/// (the last, 3, ends the program and the run).
#[test]
fn modbus_writes_are_recorded_and_replayed() {
    let dir = tempfile::tempdir().unwrap();
    let program = dv_program(dir.path());
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
        if n == writes.len() - 1 {
            // The program ends once it has seen the last value, and the run with it: no
            // acknowledgement to read, its last line tells.
            break;
        }
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
         Sleep(100)\n\
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
    // In position is within the window; 100 ms later the drive has settled on the target,
    // however the codes' arrival split the two moves (a loaded machine: 7.001 mm at once).
    assert_eq!(said[3], "2 codes, at 7.000 mm");
    replays_match(&recorded, &record, &["--config", config.to_str().unwrap(), program.to_str().unwrap()]);
}

/// A record that cannot be replayed is refused before anything starts, with its line.
#[test]
fn bad_records_are_refused_with_their_line() {
    let dir = tempfile::tempdir().unwrap();
    let program = program(dir.path(), "p.lua", "Print('ran')\n");
    let huge = format!("luamotion-inputs 1\n5 serial {}\n", "00".repeat(100_000));
    let cases: [(&str, &[u8], &str); 15] = [
        ("garbage", b"\x7fELF\x02\x01\x01\x00\x00\xff\xfe\n", "line 1: not a luamotion input record"),
        ("order", b"luamotion-inputs 1\n9 modbus 0x0000 1\n3 modbus 0x0000 2\n", "line 3: cycle 3 comes after cycle 9"),
        ("kind", b"luamotion-inputs 1\n1 modbus 0x0000 1\n2 freeport 0 6869\n", "line 3: unknown input `freeport`"),
        ("huge", huge.as_bytes(), "line 2: longer than 16384 bytes"),
        ("address", b"luamotion-inputs 1\n1 modbus 0x6B02 1\n", "line 2: 0x6B02 is not a DV, DH or FUN147 word"),
        ("empty", b"", "line 1: empty"),
        ("pin", b"luamotion-inputs 1\n1 gpi 9 1\n", "line 2: `9` is not a controller input (1..8)"),
        ("level", b"luamotion-inputs 1\n1 gpi 1 1\n2 gpi 1 5\n", "line 3: `5` is not a level (0 or 1)"),
        ("word", b"luamotion-inputs 1\n1 ai 1 1 99999\n", "line 2: `99999` is not a word (0..65535)"),
        ("channel", b"luamotion-inputs 1\n1 ai 1 x 1\n", "line 2: `x` is not an analog input (1..4)"),
        ("eth", b"luamotion-inputs 1\n1 eth 0 1 connect\n2 eth 0 1 data 4z\n", "line 3: `data 4z` is not connect"),
        ("task", b"luamotion-inputs 1\n1 eth 99 1 end\n", "line 2: `99` is not a task (0..63)"),
        ("client", b"luamotion-inputs 1\n1 client 0 GetPosFb 0\n", "line 2: `GetPosFb 0` is not a ch. 22 client"),
        (
            "client bytes",
            b"luamotion-inputs 1\n1 client 0 Modbus_ClientConnect 0 1\n2 client 0 Modbus_ClientRead_Coils 0 0z\n",
            "line 3: `Modbus_ClientRead_Coils 0 0z` is not",
        ),
        (
            "client id",
            b"luamotion-inputs 1\n1 client 0 ASCII_ClientConnect 0\n",
            "line 2: `ASCII_ClientConnect 0` is not",
        ),
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

/// `program` recording into `record` on the simulation clock with the web view on; the
/// run, its lines so far and the web view's port, once the program waits for inputs.
fn recording_with_web_view(
    name: &str,
    config: &Path,
    record: &Path,
    program: &Path,
) -> (Child, Receiver<String>, Vec<String>, String) {
    let ns = unique_ns(name);
    let args = ["--config", config.to_str().unwrap(), "--speed", "20", "--http", "0"];
    let (child, lines) =
        start(&ns, &[&args[..], &["--record", record.to_str().unwrap(), program.to_str().unwrap()]].concat());
    let mut seen = Vec::new();
    let said = until(&lines, "Web view on http://", &mut seen);
    let address = said.split(';').next().unwrap();
    let port = address.trim_end_matches('/').rsplit(':').next().unwrap().to_string();
    if !seen.iter().any(|l| l.contains("waiting for inputs")) {
        until(&lines, "waiting for inputs", &mut seen);
    }
    (child, lines, seen, port)
}

/// The web view's simulated inputs (controller input 3, the analog terminal's input 1),
/// posted by nc while the program waits for them: recorded with their cycles, then
/// replayed without the web view.
#[test]
fn simulated_inputs_are_recorded_and_replayed() {
    let dir = tempfile::tempdir().unwrap();
    let (config, record, program) =
        (machine_with_terminal(dir.path()), dir.path().join("inputs.txt"), inputs_program(dir.path()));
    let (child, lines, mut seen, port) = recording_with_web_view("record-sim-inputs", &config, &record, &program);
    let steps = [
        ("/api/sim/ai/1/1/2000", "gpi 0 ai 2000"),
        ("/api/sim/gpi/3/1", "gpi 1 ai 2000"),
        ("/api/sim/ai/1/1/5000", "gpi 1 ai 5000"),
        ("/api/sim/gpi/3/0", "gpi 0 ai 5000"),
    ];
    for (path, then) in steps {
        let answer = post(&port, path);
        assert!(answer.contains("queued for the next cycle"), "{path}: {answer}");
        until(&lines, then, &mut seen);
    }
    assert!(post(&port, "/api/sim/gpi/9/1").contains("400 Bad Request"), "inputs are 1..8");
    let recorded = end(child, lines, seen);
    let text = std::fs::read_to_string(&record).unwrap();
    let inputs: Vec<&str> = text.lines().skip(1).map(|l| l.split_once(' ').unwrap().1).collect();
    assert_eq!(inputs, ["ai 1 1 2000", "gpi 3 1", "ai 1 1 5000", "gpi 3 0"], "{text}");
    let mut said: Vec<&str> = recorded.task_lines().into_iter().map(|l| l.split(" at ").next().unwrap()).collect();
    // Where the axis stands when the last input lands depends on how soon nc's post came
    // after the move to 5 mm: still settling inside its in-position window, or settled.
    let at = said.pop().and_then(|l| l.strip_prefix("at ")?.strip_suffix(" mm")?.parse::<f64>().ok());
    assert!(at.is_some_and(|at| (at - 5.0).abs() < 0.01), "at {at:?}: {}", recorded.out.stderr);
    assert_eq!(
        said,
        [
            "waiting for inputs",
            "gpi 0 ai 0 dv 0",
            "gpi 0 ai 2000 dv 0",
            "gpi 1 ai 2000 dv 0",
            "gpi 1 ai 5000 dv 0",
            "gpi 0 ai 5000 dv 0"
        ],
        "{}",
        recorded.out.stderr
    );
    replays_match(&recorded, &record, &["--config", config.to_str().unwrap(), program.to_str().unwrap()]);
}

/// A digital I/O terminal's input switched from the web view (`SimSetSlvGPI`, HMPL 9.5):
/// recorded as `slvgpi` lines with their cycles; the replays give the same run. The
/// program prints input 2 and the cycle it saw it at, so a switch landing one cycle off in
/// a replay shows in the output as well as in the digest.
#[test]
fn terminal_inputs_are_recorded_and_replayed() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("machine.toml");
    std::fs::write(&config, "[[axes]]\n\n[[slaves]]\ndevice = \"digital_io\"\ninputs = 4\noutputs = 4\n").unwrap();
    let record = dir.path().join("inputs.txt");
    let program = program(
        dir.path(),
        "switch.lua",
        "my_print('waiting for inputs')\n\
         local seen, changes = 0, 0\n\
         while changes < 2 do\n\
           local now = GetSlvGPI(1, 2)\n\
           if now ~= seen then seen, changes = now, changes + 1 Print('input 2 is %d at %d', now, system_fclk) end\n\
           Sleep(1)\n\
         end\n",
    );
    let (child, lines, mut seen, port) = recording_with_web_view("record-terminal-inputs", &config, &record, &program);
    for (path, then) in [("/api/sim/slvgpi/1/2/1", "input 2 is 1"), ("/api/sim/slvgpi/1/2/0", "input 2 is 0")] {
        let answer = post(&port, path);
        assert!(answer.contains("queued for the next cycle"), "{path}: {answer}");
        until(&lines, then, &mut seen);
    }
    let recorded = end(child, lines, seen);
    let text = std::fs::read_to_string(&record).unwrap();
    let inputs: Vec<&str> = text.lines().skip(1).map(|l| l.split_once(' ').unwrap().1).collect();
    assert_eq!(inputs, ["slvgpi 1 2 1", "slvgpi 1 2 0"], "{text}");
    replays_match(&recorded, &record, &["--config", config.to_str().unwrap(), program.to_str().unwrap()]);
}

/// A record written by hand: a controller input, a DV word and an analog word in one
/// cycle, from what would be two servers (the web view, Modbus TCP): the program sees all
/// three in its turn after that cycle. Replays without `--clock sim`, at `--speed 10` and
/// `max`, give the same run.
#[test]
fn inputs_of_one_cycle_from_two_sources_land_together() {
    let dir = tempfile::tempdir().unwrap();
    let (config, program) = (machine_with_terminal(dir.path()), inputs_program(dir.path()));
    let record = dir.path().join("inputs.txt");
    std::fs::write(
        &record,
        "luamotion-inputs 1\n400 gpi 3 1\n400 modbus 0x0000 7\n400 ai 1 1 3000\n3000 ai 1 1 5000\n3000 gpi 3 0\n",
    )
    .unwrap();
    let mut runs = Vec::new();
    for speed in ["10", "max"] {
        let ns = unique_ns("replay-one-cycle");
        let args = ["--replay", record.to_str().unwrap(), "--speed", speed, "--config", config.to_str().unwrap()];
        let out = finish(start_run(&ns, &[&args[..], &[program.to_str().unwrap()]].concat()), Duration::from_secs(240));
        assert!(out.status.success(), "{}", out.stderr);
        runs.push(out);
    }
    let said = runs[0].lines_of_task(0);
    assert_eq!(
        said,
        [
            "waiting for inputs",
            "gpi 0 ai 0 dv 0 at 4",
            "gpi 1 ai 3000 dv 7 at 400",
            "gpi 0 ai 5000 dv 7 at 3000",
            "at 3.000 mm"
        ],
        "{}",
        runs[0].stderr
    );
    assert_eq!(runs[1].lines_of_task(0), said);
    let digest = |out: &Finished| {
        out.stderr
            .lines()
            .find(|l| l.contains("trace digest"))
            .map(|l| l.split_once("trace digest ").unwrap().1.to_string())
    };
    assert_eq!(digest(&runs[0]), digest(&runs[1]), "{}", runs[1].stderr);
    assert!(digest(&runs[0]).is_some(), "{}", runs[0].stderr);
}

/// `--speed` without the simulation clock is refused; `--replay` brings the clock.
#[test]
fn speed_needs_the_simulation_clock() {
    let dir = tempfile::tempdir().unwrap();
    let program = program(dir.path(), "p.lua", "Print('ran')\n");
    let out = run(&unique_ns("speed-alone"), &["--speed", "10", program.to_str().unwrap()]);
    assert!(!out.status.success() && out.stderr.contains("--speed needs the simulation clock"), "{}", out.stderr);
}

/// A `FreePort.Eth` server session fed by nc in two chunks that split a frame: each frame
/// moves the axis and is echoed; recorded (the peer's connect, bytes and end with their
/// cycles), then replayed without a peer: the same frames in the same turns.
#[test]
fn freeport_server_inputs_are_recorded_and_replayed() {
    let dir = tempfile::tempdir().unwrap();
    let port = freeport_port();
    let program = program(
        dir.path(),
        "server.lua",
        &format!(
            "Enable(0)\n\
             Till(function() return IsEnabled(0) end)\n\
             Print('open %d', FreePort.Eth.OpenAsServer(1, {port}, nil, ';'))\n\
             my_print('listening')\n\
             local start, peer = system_fclk, false\n\
             while system_fclk - start < 600000 do\n\
               if (FreePort.Eth.ConnectCheck(1) == 0) ~= peer then\n\
                 peer = not peer\n\
                 Print('peer %s at %d', tostring(peer), system_fclk)\n\
               end\n\
               local rc, data, n = FreePort.Eth.Rx(1)\n\
               if rc == 0 and n > 0 then\n\
                 Print('frame %s at %d', data, system_fclk)\n\
                 if data == 'quit' then break end\n\
                 MoveRel(0, n)\n\
                 Print('tx %d', (FreePort.Eth.Tx(1, 'echo:' .. data)))\n\
               end\n\
               Sleep(1)\n\
             end\n\
             FreePort.Eth.Close(1)\n\
             Till(function() return IsInPos(0) end)\n\
             Print('at %.3f mm', GetPosFb(0))\n"
        ),
    );
    let (config, record) = (machine(dir.path()), dir.path().join("inputs.txt"));
    let ns = unique_ns("record-freeport");
    let args = ["--config", config.to_str().unwrap(), "--speed", "20"];
    let (child, lines) =
        start(&ns, &[&args[..], &["--record", record.to_str().unwrap(), program.to_str().unwrap()]].concat());
    let mut seen = Vec::new();
    until(&lines, "listening", &mut seen);
    let mut nc = Command::new(debian_tool("nc"))
        .args(["-N", "-w", "10", "127.0.0.1", &port.to_string()])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("nc");
    let mut to_nc = nc.stdin.take().unwrap();
    to_nc.write_all(b"A1;BB").unwrap();
    until(&lines, "frame A1", &mut seen);
    to_nc.write_all(b"22;").unwrap();
    until(&lines, "frame BB22", &mut seen);
    to_nc.write_all(b"quit;").unwrap();
    drop(to_nc);
    let echoed = nc.wait_with_output().unwrap();
    assert_eq!(String::from_utf8_lossy(&echoed.stdout), "echo:A1;echo:BB22;");
    let recorded = end(child, lines, seen);
    let text = std::fs::read_to_string(&record).unwrap();
    let inputs: Vec<&str> = text.lines().skip(1).map(|l| l.split_once(' ').unwrap().1).collect();
    assert_eq!(inputs.first(), Some(&"eth 0 1 connect"), "{text}");
    assert!(inputs.iter().all(|l| l.starts_with("eth 0 1 ")), "{text}");
    let data: String = inputs.iter().filter_map(|l| l.strip_prefix("eth 0 1 data ")).collect();
    assert_eq!(data, "41313b424232323b717569743b", "every byte, in order: {text}");
    let said: Vec<&str> = recorded.task_lines().into_iter().map(|l| l.split(" at ").next().unwrap()).collect();
    assert_eq!(
        said,
        ["open 0", "listening", "peer true", "frame A1", "tx 0", "frame BB22", "tx 0", "frame quit", "at 6.000 mm"],
        "{}",
        recorded.out.stderr
    );
    replays_match(&recorded, &record, &["--config", config.to_str().unwrap(), program.to_str().unwrap()]);
}

/// A `FreePort.Eth` client that opens until `nc -l` listens (the refused opens are inputs
/// too), sends a request and reads the answer: replayed without nc, the opens fail and
/// succeed as recorded.
#[test]
fn freeport_client_opens_and_answers_are_replayed() {
    let dir = tempfile::tempdir().unwrap();
    let port = freeport_port();
    let program = program(
        dir.path(),
        "client.lua",
        &format!(
            "my_print('connecting')\n\
             local rc, tries, start = 1, 0, system_fclk\n\
             repeat rc = FreePort.Eth.OpenAsClient(3, '127.0.0.1', {port}, nil, CR_LF); tries = tries + 1; Sleep(50)\n\
             until rc == 0 or tries > 2000\n\
             Print('open %d at %d', rc, system_fclk)\n\
             Print('tx %d', (FreePort.Eth.Tx(3, 'barcode?')))\n\
             local data, n = '', 0\n\
             repeat rc, data, n = FreePort.Eth.Rx(3); Sleep(1) until n > 0 or system_fclk - start > 600000\n\
             Print('answer %s at %d', data, system_fclk)\n\
             FreePort.Eth.Close(3)\n\
             Print('tries %d', tries)\n"
        ),
    );
    let (config, record) = (machine(dir.path()), dir.path().join("inputs.txt"));
    let ns = unique_ns("record-freeport-client");
    let args = ["--config", config.to_str().unwrap(), "--speed", "20"];
    let (child, lines) =
        start(&ns, &[&args[..], &["--record", record.to_str().unwrap(), program.to_str().unwrap()]].concat());
    let mut seen = Vec::new();
    until(&lines, "connecting", &mut seen);
    std::thread::sleep(Duration::from_millis(300));
    let mut nc = Command::new(debian_tool("nc"))
        .args(["-l", "127.0.0.1", &port.to_string()])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("nc -l");
    until(&lines, "tx 0", &mut seen);
    let mut to_nc = nc.stdin.take().unwrap();
    to_nc.write_all(b"4711\r\n").unwrap();
    until(&lines, "answer 4711", &mut seen);
    drop(to_nc);
    let recorded = end(child, lines, seen);
    let _ = nc.kill();
    let asked = nc.wait_with_output().unwrap();
    assert_eq!(String::from_utf8_lossy(&asked.stdout), "barcode?\r\n");
    let text = std::fs::read_to_string(&record).unwrap();
    assert!(text.contains(" eth 0 3 refused\n") && text.contains(" eth 0 3 connect\n"), "{text}");
    assert!(text.contains(" eth 0 3 data 343731310d0a\n"), "{text}");
    replays_match(&recorded, &record, &["--config", config.to_str().unwrap(), program.to_str().unwrap()]);
}

/// Modbus RTU on serial port 1 (`run --modbus-port` serves it with the same registers):
/// mbpoll's writes of DV 0 over the pseudo-terminal are recorded as Modbus writes at
/// their cycles and replayed without mbpoll or the TCP server.
#[test]
fn modbus_rtu_writes_are_recorded_and_replayed() {
    let dir = tempfile::tempdir().unwrap();
    let program = dv_program(dir.path());
    let (config, record, link) = (machine(dir.path()), dir.path().join("inputs.txt"), dir.path().join("ttyS1"));
    let ns = unique_ns("record-rtu");
    let args = ["--config", config.to_str().unwrap(), "--speed", "20", "--modbus-port", "0"];
    let serial = ["--serial-link", link.to_str().unwrap(), "--record", record.to_str().unwrap()];
    let (child, lines) = start(&ns, &[&args[..], &serial, &[program.to_str().unwrap()]].concat());
    let mut seen = Vec::new();
    until(&lines, "Modbus TCP on ", &mut seen);
    let rtu = |reference: &str, values: &[&str]| {
        let out = Command::new(debian_tool("mbpoll"))
            .args(["-m", "rtu", "-b", "38400", "-P", "none", "-a", "1", "-0", "-1", "-o", "2", "-r", reference])
            .arg(&link)
            .args(values)
            .output()
            .expect("mbpoll");
        let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        said.lines().map(|l| l.split_whitespace().collect::<Vec<_>>().join(" ")).collect::<Vec<_>>().join("\n")
    };
    for value in ["1", "2", "3"] {
        assert!(rtu("0", &[value]).contains("Written"), "{seen:#?}");
        if value == "3" {
            // The run ends with the program, which ends once it has seen 3: its last line tells.
            break;
        }
        let acked = format!("[1]: {value}");
        assert!(eventually(Duration::from_secs(60), || rtu("1", &[]).contains(&acked)), "no {acked}: {seen:#?}");
    }
    let recorded = end(child, lines, seen);
    let text = std::fs::read_to_string(&record).unwrap();
    let inputs: Vec<&str> = text.lines().skip(1).map(|l| l.split_once(' ').unwrap().1).collect();
    assert_eq!(inputs, ["modbus 0x0000 1", "modbus 0x0000 2", "modbus 0x0000 3"], "{text}");
    let said = recorded.task_lines();
    assert!(said.last().is_some_and(|l| l.starts_with("last 3 at 30.000")), "{said:?}");
    replays_match(&recorded, &record, &["--config", config.to_str().unwrap(), program.to_str().unwrap()]);
}

/// A Modbus client (HMPL 22.3) of an outside pymodbus server: it writes holding registers,
/// reads them and the input registers back and moves the axis by a word it read; recorded
/// (each call's outcome a `client` line), then replayed twice without the server.
#[test]
fn modbus_client_calls_are_recorded_and_replayed() {
    let dir = tempfile::tempdir().unwrap();
    let (server, port) = pymodbus_server();
    let program = program(
        dir.path(),
        "mbclient.lua",
        &format!(
            "Enable(0)\n\
             Till(function() return IsEnabled(0) end)\n\
             local rc, s = Modbus_ClientConnect('127.0.0.1:{port}')\n\
             Print('connect %d %d at %d', rc, s, system_fclk)\n\
             Print('write %d', (Modbus_ClientWrite_HoldReg(s, 10, 2, {{3, 700}})))\n\
             local rc, b, n = Modbus_ClientRead_HoldReg(s, 10, 2)\n\
             local steps = b[3] * 256 + b[4]\n\
             Print('read %d: %d %d words at %d', rc, b[1] * 256 + b[2], steps, system_fclk)\n\
             rc, b, n = Modbus_ClientRead_InputReg(s, 5, 1)\n\
             Print('input %d: %d', rc, b[1] * 256 + b[2])\n\
             MoveRel(0, steps / 100)\n\
             Till(function() return IsInPos(0) end)\n\
             Print('disconnect %d at %d', Modbus_ClientDisconnect(s), system_fclk)\n\
             Print('at %.3f mm', GetPosFb(0))\n"
        ),
    );
    let (config, record) = (machine(dir.path()), dir.path().join("inputs.txt"));
    let (child, lines) = start(
        &unique_ns("record-mbclient"),
        &["--config", config.to_str().unwrap(), "--record", record.to_str().unwrap(), program.to_str().unwrap()],
    );
    let recorded = end(child, lines, Vec::new());
    drop(server);
    let text = std::fs::read_to_string(&record).unwrap();
    let inputs: Vec<&str> = text.lines().skip(1).map(|l| l.split_once(' ').unwrap().1).collect();
    assert_eq!(
        inputs,
        [
            "client 0 Modbus_ClientConnect 0 1",
            "client 0 Modbus_ClientWrite_HoldReg 0 000a0002",
            "client 0 Modbus_ClientRead_HoldReg 0 000302bc",
            "client 0 Modbus_ClientRead_InputReg 0 03ed",
            "client 0 Modbus_ClientDisconnect 0",
        ],
        "{text}\n{}",
        recorded.out.stderr
    );
    let said: Vec<&str> = recorded.task_lines().into_iter().map(|l| l.split(" at ").next().unwrap()).collect();
    assert_eq!(
        said,
        ["connect 0 1", "write 0", "read 0: 3 700 words", "input 0: 1005", "disconnect 0", "at 7.000 mm"],
        "{}",
        recorded.out.stderr
    );
    replays_match(&recorded, &record, &["--config", config.to_str().unwrap(), program.to_str().unwrap()]);
}

/// An ASCII client (HMPL 22.2) of `nc -l`: it sends a request and prints the answer nc
/// gives; replayed twice without nc, the same answer at the same cycle.
#[test]
fn ascii_client_calls_are_recorded_and_replayed() {
    let dir = tempfile::tempdir().unwrap();
    let port = free_port();
    let mut nc = Command::new(debian_tool("nc"))
        .args(["-l", "127.0.0.1", &port.to_string()])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("nc -l");
    let program = program(
        dir.path(),
        "asciiclient.lua",
        &format!(
            "local rc, s, tries = 1, 0, 0\n\
             repeat rc, s = ASCII_ClientConnect('127.0.0.1', '{port}'); tries = tries + 1; Sleep(10)\n\
             until rc == 0 or tries > 1000\n\
             Print('connect %d at %d', rc, system_fclk)\n\
             Print('sent %d', ASCII_ClientSend(s, 9, 'barcode?\\n'))\n\
             local data = ''\n\
             repeat rc, data = ASCII_ClientRecv(s, 64) until rc == 0 or tries > 1000\n\
             Print('answer %s at %d', data, system_fclk)\n\
             Print('disconnect %d', ASCII_ClientDisconnect(s))\n"
        ),
    );
    let (config, record) = (machine(dir.path()), dir.path().join("inputs.txt"));
    let (child, lines) = start(
        &unique_ns("record-asciiclient"),
        &["--config", config.to_str().unwrap(), "--record", record.to_str().unwrap(), program.to_str().unwrap()],
    );
    let mut seen = Vec::new();
    until(&lines, "sent 0", &mut seen);
    let mut to_nc = nc.stdin.take().unwrap();
    to_nc.write_all(b"4711").unwrap();
    until(&lines, "answer 4711", &mut seen);
    drop(to_nc);
    let recorded = end(child, lines, seen);
    let _ = nc.kill();
    let asked = nc.wait_with_output().unwrap();
    assert_eq!(String::from_utf8_lossy(&asked.stdout), "barcode?\n");
    let text = std::fs::read_to_string(&record).unwrap();
    assert!(text.contains(" client 0 ASCII_ClientConnect 0 1\n"), "{text}");
    assert!(text.contains(" client 0 ASCII_ClientSend 0\n"), "{text}");
    assert!(text.contains(" client 0 ASCII_ClientRecv 0 34373131\n"), "{text}");
    replays_match(&recorded, &record, &["--config", config.to_str().unwrap(), program.to_str().unwrap()]);
}

/// A record whose client calls are not the program's (another call next, or none left)
/// stops the task with an error naming the record; nothing panics.
#[test]
fn a_program_that_differs_from_its_client_record_is_told() {
    let dir = tempfile::tempdir().unwrap();
    let program = program(
        dir.path(),
        "p.lua",
        "local rc, s = Modbus_ClientConnect('127.0.0.1:1502')\nPrint('connect %d', rc)\n\
         Print('disconnect %d', Modbus_ClientDisconnect(s))\n",
    );
    let cases = [
        ("other", "2 client 0 ASCII_ClientConnect 0 1\n", "has ASCII_ClientConnect next for task 0 (cycle 2)"),
        ("short", "2 client 0 Modbus_ClientConnect 0 1\n", "has no more client calls of task 0"),
    ];
    for (name, lines, expected) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, format!("luamotion-inputs 1\n{lines}")).unwrap();
        let out = run(&unique_ns("client-record"), &["--replay", path.to_str().unwrap(), program.to_str().unwrap()]);
        let said = format!("{}{}", out.stdout, out.stderr);
        assert!(said.contains(expected) && said.contains(path.to_str().unwrap()), "{name}: {said}");
        assert!(!said.contains("panicked"), "{name}: {said}");
    }
}

//! A line of two controllers on real sockets: station A's program is a Modbus TCP client
//! (HMPL 22.3) of station B's `luamotion serve`, and hands B jobs through B's DV words
//! (DXMC A.1); B's program waits on those words, moves its axis, and reports back in its
//! own DV words, which A reads and follows.

mod common;

use std::time::Duration;

use common::serve::serve;
use common::*;

/// B's DV words (DXMC A.1 addresses).
const JOB_TARGET: u16 = 0x0100; // 0.1 mm
const JOB_NUMBER: u16 = 0x0101;
const DONE_POSITION: u16 = 0x0110; // 0.1 mm
const DONE_NUMBER: u16 = 0x0111;
const READY: u16 = 0x0112;

/// The targets A hands B, mm.
const TARGETS: [f64; 3] = [25.0, 62.5, 10.0];

/// Station B: a job is a target and a number, the number written last; B moves there and
/// reports where it stopped, the number last.
fn station_b() -> String {
    format!(
        r#"Enable(0)
Till(function() return IsEnabled(0) end)
WriteModbusWord({READY}, 1)
for job = 1, {jobs} do
  Till(function() return ReadModbusWord({JOB_NUMBER}) == job end)
  local target = ReadModbusWord({JOB_TARGET}) / 10
  MoveAbs(0, target)
  Till(function() return IsInPos(0) end)
  local at = GetPosFb(0)
  Print("job %d: moved to %.1f mm", job, at)
  WriteModbusWord({DONE_POSITION}, math.floor(at * 10 + 0.5))
  WriteModbusWord({DONE_NUMBER}, job)
end
Print("station B done")
"#,
        jobs = TARGETS.len()
    )
}

/// Station A: B's Modbus client; after each job it moves its own axis where B stopped.
fn station_a(b_port: u16) -> String {
    let targets: Vec<String> = TARGETS.iter().map(|t| t.to_string()).collect();
    format!(
        r#"local rc, b = Modbus_ClientConnect("127.0.0.1:{b_port}")
Print("connect %d", rc)
local function word(address)
  local rc, bytes = Modbus_ClientRead_HoldReg(b, address, 1)
  if rc ~= 0 then error(string.format("reading B's 0x%04X: 0x%X", address, rc)) end
  return bytes[1] * 256 + bytes[2]
end
Enable(0)
Till(function() return IsEnabled(0) and word({READY}) == 1 end)
for job, target in ipairs({{{targets}}}) do
  local rc = Modbus_ClientWrite_HoldReg(b, {JOB_TARGET}, 2, {{math.floor(target * 10), job}})
  Till(function() return word({DONE_NUMBER}) == job end)
  -- Read once the number is there: B writes the position before it.
  local at = word({DONE_POSITION}) / 10
  MoveAbs(0, at)
  Till(function() return IsInPos(0) end)
  Print("job %d: sent %d, B reports %.1f mm, A follows to %.1f mm", job, rc, at, GetPosFb(0))
end
Print("disconnect %d", Modbus_ClientDisconnect(b))
"#,
        targets = targets.join(", ")
    )
}

/// A machine file with one axis and `program` as task 0, run at start.
fn machine(dir: &std::path::Path, program: &str) -> std::path::PathBuf {
    let path = dir.join("main.lua");
    std::fs::write(&path, program).unwrap();
    let toml = dir.join("machine.toml");
    std::fs::write(
        &toml,
        format!("[[axes]]\n\n[[tasks]]\nid = 0\nprogram = {:?}\nautorun = true\n", path.display().to_string()),
    )
    .unwrap();
    toml
}

fn task_lines(stdout: &str) -> Vec<&str> {
    stdout.lines().filter_map(|l| l.strip_prefix("[task 0] ")).collect()
}

#[test]
fn station_a_hands_station_b_jobs_through_b_s_modbus_server() {
    let (dir_a, dir_b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let toml_b = machine(dir_b.path(), &station_b());
    let b = serve(&unique_ns("line-b"), dir_b.path(), &["--config", toml_b.to_str().unwrap()]);
    let toml_a = machine(dir_a.path(), &station_a(b.port));
    let a = serve(&unique_ns("line-a"), dir_a.path(), &["--config", toml_a.to_str().unwrap()]);

    let timeout = Duration::from_secs(60);
    let ended =
        a.await_line(0, "disconnect", timeout).is_some() && b.await_line(0, "station B done", timeout).is_some();
    let (out_a, out_b) = (a.stdout(), b.stdout());
    assert!(ended, "A:\n{out_a}\n{}\nB:\n{out_b}\n{}", a.stderr(), b.stderr());

    let mut want_a = vec!["connect 0".to_string()];
    let mut want_b = Vec::new();
    for (i, target) in TARGETS.iter().enumerate() {
        let job = i + 1;
        want_a.push(format!("job {job}: sent 0, B reports {target:.1} mm, A follows to {target:.1} mm"));
        want_b.push(format!("job {job}: moved to {target:.1} mm"));
    }
    want_a.push("disconnect 0".into());
    want_b.push("station B done".into());
    assert_eq!(task_lines(&out_a), want_a, "A:\n{out_a}");
    assert_eq!(task_lines(&out_b), want_b, "B:\n{out_b}");

    // What a third party reads in B's DV afterwards: the last job, and B's report of it.
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
    let words = runtime.block_on(async {
        let address = format!("127.0.0.1:{}", b.port).parse().unwrap();
        let mut client = drl::modbus::Client::connect(address, 1).await.expect("connect to B");
        let job = client.read(JOB_TARGET, 2).await.expect("read B's job");
        let done = client.read(DONE_POSITION, 3).await.expect("read B's report");
        (job, done)
    });
    let last = (TARGETS[TARGETS.len() - 1] * 10.0) as u16;
    let jobs = TARGETS.len() as u16;
    assert_eq!(words, (vec![last, jobs], vec![last, jobs, 1]));
}

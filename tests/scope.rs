//! End to end: the scope recorder. `run --scope` records a program's move every cycle (the
//! CSV checked against the trapezoid the program asked for, no cycle missing), SetHMIScope
//! (HMPL 2.17) pauses and resumes it, a trigger keeps its pre- and post-trigger samples of
//! the decimated rows, `luamotion scope` attaches to a running `serve`, and the plots are
//! written as SVG and PNG with one panel per unit.

mod common;

use std::path::Path;
use std::process::Command;
use std::time::Duration;

use common::*;

/// A CSV the scope wrote: its header and rows.
struct Csv {
    header: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl Csv {
    fn read(path: &Path) -> Csv {
        let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut lines = text.lines();
        let header = lines.next().expect("a header").split(',').map(String::from).collect();
        let rows = lines.map(|l| l.split(',').map(|v| v.parse().expect("a number")).collect()).collect();
        Csv { header, rows }
    }

    fn column(&self, name: &str) -> Vec<f64> {
        let i = self.header.iter().position(|h| h.split(' ').next() == Some(name)).expect(name);
        self.rows.iter().map(|r| r[i]).collect()
    }

    fn cycles(&self) -> Vec<u64> {
        self.column("cycle").into_iter().map(|c| c as u64).collect()
    }
}

/// A trapezoid of 100 mm at 200 mm/s and 2000 mm/s²: 0.1 s up, 0.4 s at speed, 0.1 s down.
const MOVE: &str = r#"
    Enable(0)
    Till(function() return IsEnabled(0) end)
    SetVel(0, 200) SetAcc(0, 2000) SetDec(0, 2000)
    system_dtest0 = 1
    MoveAbs(0, 100)
    Till(function() return not IsMoving(0) end)
    Sleep(20)
    Print("done")
"#;

/// 16 variables, the scope's most.
const SIXTEEN: &str = "a0.ref_pos,a0.pos_out,a0.pos_fb,a0.pos_err,a0.vel_fb,a0.ref_vel,a0.motion_status,\
    a0.fault_status,a1.pos_fb,a1.vel_fb,g0.carte_pose_cmd[0],g0.grp_pg_vel,gpi,gpo,system_dtest0,system_user_table[5]";

fn run_scoped(tag: &str, program_source: &str, args: &[&str]) -> (tempfile::TempDir, Finished) {
    let dir = tempfile::tempdir().unwrap();
    let main = program(dir.path(), "main.lua", program_source);
    let mut all: Vec<String> = args.iter().map(|a| a.replace("{dir}", dir.path().to_str().unwrap())).collect();
    all.push(main.display().to_string());
    let all: Vec<&str> = all.iter().map(String::as_str).collect();
    let out = run(&unique_ns(tag), &all);
    assert!(out.status.success(), "{}\n{}", out.stdout, out.stderr);
    (dir, out)
}

#[test]
fn run_scope_records_every_cycle_of_a_move_against_its_profile() {
    let (dir, out) = run_scoped(
        "scope-run",
        MOVE,
        &[
            "--scope",
            "{dir}/move.csv",
            "--scope",
            "{dir}/move.svg",
            "--scope",
            "{dir}/move.png",
            "--scope-vars",
            SIXTEEN,
        ],
    );
    assert!(out.stderr.contains("of 16 variables") && out.stderr.contains(", 0 lost"), "{}", out.stderr);
    let csv = Csv::read(&dir.path().join("move.csv"));
    assert_eq!(csv.header.len(), 18, "cycle, time and 16 variables: {:?}", csv.header);
    assert_eq!(&csv.header[2..4], ["a0.ref_pos [mm]", "a0.pos_out [mm]"]);
    assert!(csv.header.contains(&"a0.vel_fb [mm/s]".to_string()) && csv.header.contains(&"gpo [bits]".into()));

    // Every cycle of the run, from the first, none lost; time in ms at 1 ms a cycle.
    let cycles = csv.cycles();
    assert_eq!(cycles[0], 1);
    assert!(cycles.windows(2).all(|w| w[1] == w[0] + 1), "a cycle is missing");
    assert_eq!(csv.column("time_ms"), cycles.iter().map(|&c| c as f64).collect::<Vec<_>>());

    // The profile: 600 cycles under way, halfway at its middle, 200 mm/s at the top, at 100 at the end.
    let reference = csv.column("a0.ref_pos");
    let moving: Vec<usize> = (0..reference.len()).filter(|&i| reference[i] > 0.0 && reference[i] < 100.0).collect();
    assert!((597..=603).contains(&moving.len()), "{} cycles under way", moving.len());
    let middle = reference[moving[0] + 300];
    assert!((middle - 50.0).abs() < 0.5, "halfway at the middle: {middle}");
    let top = csv.column("a0.vel_fb").into_iter().fold(0.0, f64::max);
    assert!((top - 200.0).abs() < 2.0, "top speed {top}");
    let end = *csv.column("a0.pos_fb").last().unwrap();
    assert!((end - 100.0).abs() < 0.01, "at the target: {end}");
    // The program's variable goes to 1 before the move starts.
    let flag = csv.column("system_dtest0");
    assert!(flag[moving[0]] == 1.0 && flag[0] == 0.0);

    // Plots: one panel per unit (mm, mm/s, bits, value), readable sizes.
    let svg = std::fs::read_to_string(dir.path().join("move.svg")).unwrap();
    assert_eq!(svg.matches("time [ms]").count(), 4, "one panel per unit");
    for label in ["a0.ref_pos", "a1.vel_fb", "g0.grp_pg_vel", "system_user_table[5]", "\nmm/s\n", "\nbits\n"] {
        assert!(svg.contains(label), "the SVG names {label}");
    }
    let png = std::fs::read(dir.path().join("move.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG") && png.len() > 20_000, "a PNG of {} bytes", png.len());
}

#[test]
fn set_hmi_scope_pauses_and_resumes_the_recording() {
    let program_source = r#"
        Sleep(50)
        SetHMIScope(0)
        system_dtest0 = 7
        Sleep(100)
        SetHMIScope(1)
        Sleep(50)
        system_dtest0 = 8
        Sleep(10)
    "#;
    let (dir, _) =
        run_scoped("scope-hmi", program_source, &["--scope", "{dir}/hmi.csv", "--scope-vars", "system_dtest0"]);
    let csv = Csv::read(&dir.path().join("hmi.csv"));
    let cycles = csv.cycles();
    let gaps: Vec<(u64, u64)> = cycles.windows(2).filter(|w| w[1] != w[0] + 1).map(|w| (w[0], w[1])).collect();
    assert_eq!(gaps.len(), 1, "one pause: {gaps:?}");
    let (before, after) = gaps[0];
    assert!((95..=110).contains(&(after - before)), "paused for about 100 cycles: {gaps:?}");
    let value = csv.column("system_dtest0");
    let split = cycles.iter().position(|&c| c == after).unwrap();
    assert!(value[..split].iter().all(|&v| v == 0.0), "nothing recorded while paused");
    assert_eq!(value[split], 7.0);
    assert_eq!(*value.last().unwrap(), 8.0);
}

#[test]
fn a_trigger_keeps_its_pre_and_post_samples_of_the_decimated_rows() {
    let (dir, out) = run_scoped(
        "scope-trigger",
        MOVE,
        &[
            "--scope",
            "{dir}/trigger.csv",
            "--scope-vars",
            "a0.vel_fb",
            "--scope-trigger",
            "a0.ref_pos>50",
            "--scope-pre",
            "20",
            "--scope-post",
            "30",
            "--scope-decimate",
            "3",
        ],
    );
    assert!(out.stderr.contains("triggered at"), "{}", out.stderr);
    let csv = Csv::read(&dir.path().join("trigger.csv"));
    // The trigger's variable is recorded after the named ones.
    assert_eq!(csv.header[2..], ["a0.vel_fb [mm/s]", "a0.ref_pos [mm]"]);
    let cycles = csv.cycles();
    assert_eq!(cycles.len(), 20 + 1 + 30);
    assert!(cycles.iter().all(|c| c % 3 == 0), "one cycle in 3: {cycles:?}");
    assert!(cycles.windows(2).all(|w| w[1] == w[0] + 3), "none skipped: {cycles:?}");
    let reference = csv.column("a0.ref_pos");
    assert!(reference[19] <= 50.0 && reference[20] > 50.0, "the 21st row is the crossing: {reference:?}");
    // At 200 mm/s, 3 cycles are 0.6 mm.
    assert!((reference[50] - reference[20] - 30.0 * 0.6).abs() < 0.01);
}

#[test]
fn scope_attaches_to_a_running_serve() {
    let dir = tempfile::tempdir().unwrap();
    let main = program(
        dir.path(),
        "loop.lua",
        r#"
        Enable(0)
        Till(function() return IsEnabled(0) end)
        SetVel(0, 500) SetAcc(0, 5000) SetDec(0, 5000)
        local n = 0
        while true do
            MoveAbs(0, 100)
            Till(function() return not IsMoving(0) end)
            MoveAbs(0, 0)
            Till(function() return not IsMoving(0) end)
            n = n + 1
            system_dtest1 = n
        end
        "#,
    );
    let machine = dir.path().join("machine.toml");
    std::fs::write(
        &machine,
        format!("[[axes]]\n[[tasks]]\nid = 0\nprogram = {:?}\nautorun = true\n", main.display().to_string()),
    )
    .unwrap();
    let ns = unique_ns("scope-serve");
    let _serving = common::serve::serve(&ns, &dir.path().join("data"), &["--config", machine.to_str().unwrap()]);
    let scope = |args: &[&str]| {
        let child = Command::new(BIN)
            .args(["scope", "--ns", &ns])
            .args(args)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let out = finish(child, Duration::from_secs(30));
        assert!(out.status.success(), "{}", out.stderr);
        out
    };

    // For a while: every cycle, none lost.
    let csv_path = dir.path().join("serve.csv");
    let out = scope(&[
        "--out",
        csv_path.to_str().unwrap(),
        "--scope-vars",
        "a0.pos_fb,system_dtest1",
        "--duration-ms",
        "500",
    ]);
    assert!(out.stderr.contains(", 0 lost"), "{}", out.stderr);
    let csv = Csv::read(&csv_path);
    let cycles = csv.cycles();
    assert!(cycles.len() >= 300, "{} rows in 500 ms", cycles.len());
    assert!(cycles.windows(2).all(|w| w[1] == w[0] + 1), "a cycle is missing");
    let position = csv.column("a0.pos_fb");
    assert!(position.iter().any(|&p| p > 1.0) && position.iter().any(|&p| p < 99.0), "the axis moves");

    // Around a trigger: the tool ends on its own once the post-trigger samples are in;
    // another variable set, asked for by this second reader.
    let svg = dir.path().join("serve.svg");
    let csv_path = dir.path().join("trigger.csv");
    scope(&[
        "--out",
        csv_path.to_str().unwrap(),
        "--out",
        svg.to_str().unwrap(),
        "--scope-vars",
        "a0.vel_fb",
        "--scope-trigger",
        "a0.pos_fb<50",
        "--scope-pre",
        "5",
        "--scope-post",
        "5",
    ]);
    let csv = Csv::read(&csv_path);
    assert_eq!(csv.rows.len(), 11);
    let position = csv.column("a0.pos_fb");
    assert!(position[4] >= 50.0 && position[5] < 50.0, "falling through 50 at the 6th row: {position:?}");
    assert!(csv.column("a0.vel_fb").iter().all(|&v| v < 0.0), "moving back");
    let svg = std::fs::read_to_string(svg).unwrap();
    assert_eq!(svg.matches("time [ms]").count(), 2, "mm/s and mm");
}

#[test]
fn unknown_variables_and_bad_triggers_are_refused_with_the_names_to_use() {
    let out = run(&unique_ns("scope-bad"), &["--scope", "x.csv", "--scope-vars", "a0.position", "nothing.lua"]);
    assert!(!out.status.success());
    assert!(
        out.stderr.contains("unknown scope variable \"a0.position\"") && out.stderr.contains("pos_fb"),
        "{}",
        out.stderr
    );
    let out = run(&unique_ns("scope-bad"), &["--scope", "x.csv", "--scope-trigger", "a0.pos_fb=3", "nothing.lua"]);
    assert!(out.stderr.contains("VAR>LEVEL"), "{}", out.stderr);
}

/// The figure for the README (run by hand, release build): `luamotion scope` records the 16
/// variables of `SIXTEEN` every cycle of a `serve` at 1 kHz while a program moves two axes;
/// rows lost, cycles missing, and the RT thread's share of a core and the overruns over the
/// same seconds without and with the recording.
#[test]
#[ignore = "a measurement: cargo test --release --test scope -- --ignored --nocapture"]
fn measure_sixteen_variables_every_cycle() {
    const SECONDS: u64 = 10;
    let dir = tempfile::tempdir().unwrap();
    let main = program(
        dir.path(),
        "loop.lua",
        r#"
        Enable(0) Enable(1)
        Till(function() return IsEnabled(0) and IsEnabled(1) end)
        while true do
            MoveAbs(0, 100) MoveAbs(1, 50)
            Till(function() return not IsMoving(0) and not IsMoving(1) end)
            MoveAbs(0, 0) MoveAbs(1, 0)
            Till(function() return not IsMoving(0) and not IsMoving(1) end)
        end
        "#,
    );
    let machine = dir.path().join("machine.toml");
    let task = format!("[[tasks]]\nid = 0\nprogram = {:?}\nautorun = true\n", main.display().to_string());
    std::fs::write(&machine, format!("{}{task}", "[[axes]]\n".repeat(4))).unwrap();
    let ns = unique_ns("scope-rate");
    let serving =
        common::serve::serve(&ns, &dir.path().join("data"), &["--http", "0", "--config", machine.to_str().unwrap()]);
    let state = format!("{}api/state", serving.web.clone().expect("the web view's address"));
    let overruns = || get_json(&state)["overruns"].as_u64().unwrap();
    let cost = |span: &mut dyn FnMut()| rt_cost(serving.pid(), &overruns, span);
    let quiet = cost(&mut || std::thread::sleep(Duration::from_secs(SECONDS)));
    let csv_path = dir.path().join("sixteen.csv");
    let mut out = None;
    let recording = cost(&mut || {
        let child = Command::new(BIN)
            .args(["scope", "--ns", &ns, "--scope-vars", SIXTEEN, "--out", csv_path.to_str().unwrap()])
            .args(["--duration-ms", &(SECONDS * 1000).to_string()])
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        out = Some(finish(child, Duration::from_secs(SECONDS + 30)));
    });
    let out = out.unwrap();
    assert!(out.status.success(), "{}", out.stderr);
    let cycles = Csv::read(&csv_path).cycles();
    let missing: u64 = cycles.windows(2).map(|w| w[1] - w[0] - 1).sum();
    println!(
        "16 variables at 1 kHz for {SECONDS} s: {} rows, {missing} cycles missing ({}); RT thread: {:.1} % of a core and {} overruns without the scope, {:.1} % and {} recording",
        cycles.len(),
        out.stderr.trim(),
        quiet.0,
        quiet.1,
        recording.0,
        recording.1
    );
}

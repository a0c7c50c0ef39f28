//! The simulation clock's speed (`luamotion run --clock sim --speed max`) on programs that
//! mostly wait: `scripts/examples/hello_axis.lua` on the built-in machine, and the 30 s
//! pick-and-place loop (`scripts/examples/pick_and_place.lua`, two axes a task) with 1, 8
//! and 64 tasks (64 tasks: 48 loops on 96 axes and 16 tasks polling an input every 10 ms).
//! Beside each, the bound in the same run: the same machine and number of tasks, each
//! only sleeping for as long, so that the core runs its cycles without a single turn to
//! grant; no program can go faster.
//!
//! `cargo bench --bench sim_speed` (release). Each row is the best of `RUNS`; it reports
//! the speed-up the run prints (simulated time over the RT loop's wall time) and the
//! whole command's wall time, controller start and end included, and checks that the
//! runs of a row give one digest.

#[path = "../tests/common/mod.rs"]
mod common;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

const RUNS: usize = 3;

const POLLER: &str = "\
while system_timeInMs < 30000 do
  Sleep(10)
  local _ = GetGPI(1)
end
";

/// A task that only sleeps as long as `seconds` of the others' work.
fn sleeper(seconds: f64) -> String {
    format!("Sleep({})\n", (seconds * 1000.0) as u64)
}

struct Row {
    name: String,
    config: Option<PathBuf>,
    programs: Vec<PathBuf>,
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().expect("temp dir");
    let examples = root.join("scripts/examples");
    let machine = |axes: usize| {
        let path = dir.path().join(format!("m{axes}.toml"));
        std::fs::write(&path, "[[axes]]\n".repeat(axes)).unwrap();
        path
    };
    let write = |name: &str, source: &str| common::program(dir.path(), name, source);
    let poller = write("poller.lua", POLLER);
    let pick_and_place = examples.join("pick_and_place.lua");
    let (hello_sleep, loop_sleep) = (write("sleep_hello.lua", &sleeper(2.216)), write("sleep_30.lua", &sleeper(30.85)));

    let mut rows =
        vec![Row { name: "hello_axis".into(), config: None, programs: vec![examples.join("hello_axis.lua")] }];
    rows.push(Row { name: "  bound: a sleeping task".into(), config: None, programs: vec![hello_sleep] });
    for tasks in [1usize, 8, 64] {
        let moving = tasks.min(48);
        let mut programs = vec![pick_and_place.clone(); moving];
        programs.extend(std::iter::repeat_n(poller.clone(), tasks - moving));
        let config = Some(machine(2 * moving));
        rows.push(Row { name: format!("pick-and-place, {tasks} tasks"), config: config.clone(), programs });
        let bound = vec![loop_sleep.clone(); tasks];
        rows.push(Row { name: format!("  bound: {tasks} sleeping tasks"), config, programs: bound });
    }

    println!("best of {RUNS} runs; luamotion: {}", common::BIN);
    println!("{:<32} {:>11} {:>9} {:>9} {:>10}  digest", "program", "simulated", "RT loop", "speed-up", "command");
    for row in &rows {
        let mut best: Option<Measured> = None;
        for _ in 0..RUNS {
            let run = measure(row);
            if let Some(b) = &best {
                assert_eq!(b.digest, run.digest, "{}: two runs gave different digests", row.name);
            }
            if best.as_ref().is_none_or(|b| run.speed_up > b.speed_up) {
                best = Some(run);
            }
        }
        let b = best.expect("runs");
        println!(
            "{:<32} {:>9.3} s {:>7.3} s {:>8.1}x {:>8.3} s  {}",
            row.name, b.simulated_s, b.loop_s, b.speed_up, b.command_s, b.digest
        );
    }
}

struct Measured {
    simulated_s: f64,
    loop_s: f64,
    speed_up: f64,
    command_s: f64,
    digest: String,
}

fn measure(row: &Row) -> Measured {
    let ns = common::unique_ns("simspeed");
    let mut args = vec!["--clock", "sim", "--speed", "max"];
    if let Some(config) = &row.config {
        args.extend(["--config", config.to_str().unwrap()]);
    }
    args.extend(row.programs.iter().map(|p| p.to_str().unwrap()));
    let started = Instant::now();
    let out = common::finish(common::start_run(&ns, &args), Duration::from_secs(600));
    let command_s = started.elapsed().as_secs_f64();
    assert!(out.status.success(), "{}: {}", row.name, out.stderr);
    // "simulated X s in Y s (Nx); trace digest fnv1a64:D over C cycles"
    let line = out.stderr.lines().find(|l| l.starts_with("simulated ")).unwrap_or_else(|| panic!("{}", out.stderr));
    let words: Vec<&str> = line.split_whitespace().collect();
    Measured {
        simulated_s: words[1].parse().unwrap(),
        loop_s: words[4].parse().unwrap(),
        speed_up: words[6].trim_start_matches('(').trim_end_matches("x);").parse().unwrap(),
        command_s,
        digest: words[9].to_string(),
    }
}

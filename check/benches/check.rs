//! The check's cost on a generated 2,000-line program (issue 40: at most 50 ms), beside
//! full_moon's parse of the same text alone and, when installed, luacheck on the same
//! file, in the same run. `cargo bench -p check --bench check`.

use std::time::{Duration, Instant};

use api::ArgType;
use check::{Checker, Options};

/// 2,000 lines: functions of a few dozen lines each, locals, loops, conditions and a
/// call of a registry function with right arguments on most lines.
fn program(lines: usize) -> String {
    let calls: Vec<String> = api::registry::all()
        .filter(|spec| !spec.name.contains('.'))
        .filter(|spec| {
            spec.args.iter().all(|a| matches!(a.ty, ArgType::Int | ArgType::Double | ArgType::Str | ArgType::Bool))
        })
        .map(|spec| {
            let args: Vec<&str> = spec
                .args
                .iter()
                .map(|a| match a.ty {
                    ArgType::Int => "axis",
                    ArgType::Double => "10.5",
                    ArgType::Str => "'text'",
                    _ => "true",
                })
                .collect();
            format!("{}({})", spec.name, args.join(", "))
        })
        .collect();
    let mut text = String::new();
    let mut n = 0;
    let mut function = 0;
    while text.lines().count() < lines {
        text.push_str(&format!("function step{function}(axis)\n  local total = 0\n  for i = 1, 10 do\n"));
        for _ in 0..20 {
            text.push_str(&format!("    if {} == 0 then total = total + i end\n", calls[n % calls.len()]));
            n += 1;
        }
        text.push_str("  end\n  Till(function() return IsInPos(axis) end)\n  return total\nend\n");
        function += 1;
    }
    text
}

fn timed(runs: usize, mut f: impl FnMut()) -> (Duration, Duration) {
    let mut times: Vec<Duration> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed()
        })
        .collect();
    times.sort();
    (times[runs / 2], times[runs - 1])
}

fn main() {
    let text = program(2000);
    let lines = text.lines().count();
    let checker = Checker::new(Options::default());
    let found = checker.check_source("bench.lua", &text, None);
    assert!(found.is_empty(), "the generated program checks clean: {:?}", &found[..found.len().min(3)]);
    let runs = 30;
    let (check_p50, check_max) = timed(runs, || {
        std::hint::black_box(checker.check_source("bench.lua", &text, None));
    });
    let (parse_p50, parse_max) = timed(runs, || {
        std::hint::black_box(full_moon::parse_fallible(&text, full_moon::LuaVersion::lua54()));
    });
    println!("a generated program of {lines} lines ({} bytes), {runs} runs each:", text.len());
    println!("| what | median | slowest |\n|---|---|---|");
    println!("| luamotion check | {:.1} ms | {:.1} ms |", ms(check_p50), ms(check_max));
    println!("| full_moon parse alone | {:.1} ms | {:.1} ms |", ms(parse_p50), ms(parse_max));
    let file = std::env::temp_dir().join(format!("luamotion-check-bench-{}.lua", std::process::id()));
    std::fs::write(&file, &text).unwrap();
    let luacheck = || std::process::Command::new("luacheck").args(["--no-config", "-q"]).arg(&file).output();
    if luacheck().is_ok() {
        let (p50, max) = timed(5, || {
            let _ = luacheck();
        });
        println!("| luacheck 1.x (a process each) | {:.1} ms | {:.1} ms |", ms(p50), ms(max));
    }
    let _ = std::fs::remove_file(&file);
    assert!(check_p50 <= Duration::from_millis(50), "the check took {check_p50:?} (target: 50 ms)");
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

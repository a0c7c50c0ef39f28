//! End to end: `[rt] script_cpus`. Every script process the controller starts (an
//! autorun task, one started by `StartTask`, the waiting ones of the pool) runs where the
//! machine file says: off the RT thread's CPU with "others", anywhere with "all".

mod common;

use std::time::Duration;

use common::{children_of, eventually, finish, program, start_run, unique_ns, waiting_children_of};

/// The CPUs `/proc/<pid>/status` lets the process run on ("0-2,5" read as 0, 1, 2, 5).
fn allowed_cpus(pid: u32) -> Vec<usize> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    let Some(list) = status.lines().find_map(|l| l.strip_prefix("Cpus_allowed_list:")) else { return Vec::new() };
    let number = |s: &str| s.trim().parse::<usize>().expect("a CPU number");
    list.split(',')
        .flat_map(|part| match part.split_once('-') {
            Some((first, last)) => (number(first)..=number(last)).collect::<Vec<_>>(),
            None => vec![number(part)],
        })
        .collect()
}

#[test]
fn script_processes_run_where_the_machine_file_says() {
    let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
    if cpus < 2 {
        return eprintln!("one CPU: the scripts share it with the RT thread whatever is asked");
    }
    // The RT thread's CPU by default: the last.
    let rt_cpu = cpus - 1;
    // (script_cpus, script_pool, whether the scripts may run on the RT thread's CPU)
    for (choice, pool, on_rt_cpu) in [("others", 2, false), ("all", 0, true), ("others", 0, false)] {
        let dir = tempfile::tempdir().unwrap();
        let main = program(dir.path(), "main.lua", "StartTask(1)\nSleep(4000)\n");
        let second = program(dir.path(), "second.lua", "Sleep(4000)\n");
        let machine = dir.path().join("machine.toml");
        std::fs::write(
            &machine,
            format!(
                "[rt]\nscript_cpus = {choice:?}\nscript_pool = {pool}\n[[axes]]\n\
                 [[tasks]]\nid = 0\nprogram = {:?}\nautorun = true\n\
                 [[tasks]]\nid = 1\nprogram = {:?}\n",
                main.display().to_string(),
                second.display().to_string()
            ),
        )
        .unwrap();
        let ns = unique_ns("script-cpus");
        let child = start_run(&ns, &["--config", machine.to_str().unwrap()]);
        let pid = child.id();
        let all_up = eventually(Duration::from_secs(20), || {
            children_of(pid).len() == 2 && waiting_children_of(pid).len() == pool
        });
        let scripts: Vec<(u32, Vec<usize>)> =
            [children_of(pid), waiting_children_of(pid)].concat().into_iter().map(|p| (p, allowed_cpus(p))).collect();
        let out = finish(child, Duration::from_secs(60));
        assert!(out.status.success(), "{choice}: {}", out.stderr);
        assert!(all_up, "{choice}: two tasks and {pool} waiting processes: {scripts:?}\n{}", out.stderr);
        for (script, allowed) in &scripts {
            assert!(!allowed.is_empty(), "{choice}: process {script} read");
            assert_eq!(
                allowed.contains(&rt_cpu),
                on_rt_cpu,
                "{choice}: script process {script} may run on {allowed:?}, the RT thread is on {rt_cpu}"
            );
        }
    }
}

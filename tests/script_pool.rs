//! End to end: the supervisor's pool of started script processes (`[rt] script_pool`).
//! A pooled process runs one task start, in a VM made for it; a waiting one that dies is
//! replaced; they die with their controller; a start with the pool empty starts a
//! process as before.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use common::{
    BIN, Finished, children_of, data_dir, eventually, finish, process_alive, program, unique_ns, waiting_children_of,
};

/// A machine file with `[rt] script_pool = pool` and task i running `tasks[i]`, the ones
/// marked with the controller.
fn machine(dir: &Path, pool: usize, tasks: &[(&Path, bool)]) -> PathBuf {
    let mut toml = format!("[rt]\nscript_pool = {pool}\n[[axes]]\n");
    for (id, (program, autorun)) in tasks.iter().enumerate() {
        toml += &format!("[[tasks]]\nid = {id}\nprogram = {:?}\nautorun = {autorun}\n", program.display().to_string());
    }
    let path = dir.join("machine.toml");
    std::fs::write(&path, toml).unwrap();
    path
}

/// `luamotion run`, logging each process start (`pooled = true` when from the pool).
fn start(ns: &str, config: &Path) -> Child {
    Command::new(BIN)
        .args(["run", "--ns", ns, "--config", config.to_str().unwrap()])
        .arg("--data-dir")
        .arg(data_dir(ns))
        .env("RUST_LOG", "warn,rt_core::supervisor=info")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start luamotion")
}

/// How many of task `task`'s process starts were from the pool, and how many not.
fn starts(out: &Finished, task: u8) -> (usize, usize) {
    let of_task = |pooled: bool| {
        let wanted = format!("task={task} ");
        let flag = format!("pooled={pooled} ");
        out.stderr.lines().filter(|l| l.contains(" started") && l.contains(&wanted) && l.contains(&flag)).count()
    };
    (of_task(true), of_task(false))
}

/// A task restarted from the pool runs its own program in a fresh VM (made before the
/// process knew its task) as that task: the global the previous run set is not there,
/// `_TASKID_` is its own, and `StartTaskFunc` runs its function after the top level.
#[test]
fn a_pooled_start_runs_its_program_in_a_fresh_vm() {
    let dir = tempfile::tempdir().unwrap();
    let main = program(
        dir.path(),
        "main.lua",
        "Sleep(1500)\nfor i = 1, 5 do\n  StartTask(1)\n  Till(function() return IsTaskStop(1) end)\n  Sleep(50)\nend\n\
         StartTaskFunc(2, 'probe')\nTill(function() return IsTaskStop(2) end)\n",
    );
    let counter = program(dir.path(), "counter.lua", "Print('before %s in %d', tostring(left), _TASKID_)\nleft = 1\n");
    let probe = program(
        dir.path(),
        "probe.lua",
        "Print('top %s', tostring(left))\nleft = 2\nfunction probe() Print('probe %s in %d', tostring(left), _TASKID_) end\n",
    );
    let ns = unique_ns("pool-fresh");
    let out = finish(
        start(&ns, &machine(dir.path(), 2, &[(main.as_path(), true), (&counter, false), (&probe, false)])),
        Duration::from_secs(60),
    );
    let context = format!("{}\n{}", out.stdout, out.stderr);
    assert!(out.status.success(), "{context}");
    assert_eq!(out.lines_of_task(1), vec!["before nil in 1"; 5], "no run sees the last one's global: {context}");
    assert_eq!(out.lines_of_task(2), vec!["top nil", "probe 2 in 2"], "{context}");
    let (pooled, spawned) = starts(&out, 1);
    assert_eq!(pooled + spawned, 5, "{context}");
    assert!(pooled >= 4, "the restarts came from the pool ({pooled} of 5): {context}");
    assert_eq!(starts(&out, 2), (1, 0), "StartTaskFunc from the pool: {context}");
}

/// Four tasks that start with the controller find the pool empty (it is filled after the
/// first orders): each gets a process started for it, as without a pool.
#[test]
fn a_start_with_the_pool_empty_starts_a_process() {
    let dir = tempfile::tempdir().unwrap();
    let main = program(dir.path(), "main.lua", "Print('main')\n");
    let config = machine(dir.path(), 1, &[(main.as_path(), true); 4]);
    let out = finish(start(&unique_ns("pool-empty"), &config), Duration::from_secs(60));
    let context = format!("{}\n{}", out.stdout, out.stderr);
    assert!(out.status.success(), "{context}");
    for task in 0..4 {
        assert_eq!(out.lines_of_task(task), vec!["main"], "{context}");
    }
    let spawned: usize = (0..4).map(|t| starts(&out, t).1).sum();
    assert!(spawned >= 3, "at most one from the pool of 1: {context}");
}

/// A waiting process that dies is replaced (and said so in the log); starts go on. The
/// waiting processes die with their controller, even on its `kill -9`.
#[test]
fn a_waiting_process_that_dies_is_replaced_and_all_die_with_the_controller() {
    let dir = tempfile::tempdir().unwrap();
    let main = program(
        dir.path(),
        "main.lua",
        "Till(function() return system_user_table[0] == 1 end)\n\
         while true do\n  StartTask(1)\n  Till(function() return IsTaskStop(1) end)\n  Sleep(100)\nend\n",
    );
    let short = program(dir.path(), "short.lua", "system_user_table[1] = system_user_table[1] + 1\n");
    let ns = unique_ns("pool-death");
    let mut child = start(&ns, &machine(dir.path(), 2, &[(main.as_path(), true), (&short, false)]));
    let pid = child.id();
    assert!(eventually(Duration::from_secs(20), || waiting_children_of(pid).len() == 2), "two waiting processes");
    let victim = waiting_children_of(pid)[0];
    // SAFETY: killing one waiting script process of this test's controller.
    unsafe { libc::kill(victim as i32, libc::SIGKILL) };
    let replaced = eventually(Duration::from_secs(20), || {
        let now = waiting_children_of(pid);
        now.len() == 2 && !now.contains(&victim)
    });
    let survivors = waiting_children_of(pid);
    // Now the starts, from the replaced pool.
    let namespace = ipc::Namespace::new(&ns).unwrap();
    let shared = ipc::shm::Region::<schema::shared::SharedData>::open(&namespace, "shared").unwrap();
    shared.set_user_table(0, 1.0);
    let ran = eventually(Duration::from_secs(20), || shared.user_table(1).is_some_and(|runs| runs >= 2.0));
    // SAFETY: killing this test's controller as a crash would.
    unsafe { libc::kill(pid as i32, libc::SIGKILL) };
    let gone = eventually(Duration::from_secs(10), || survivors.iter().all(|&p| !process_alive(p)));
    let _ = child.wait();
    let mut stderr = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut stderr).unwrap();
    ipc::remove_namespace_files(&namespace);
    assert!(replaced, "a new waiting process for the killed one: {survivors:?}\n{stderr}");
    assert!(stderr.contains("a waiting script process ended"), "{stderr}");
    assert!(ran, "starts went on: {stderr}");
    assert!(gone, "the waiting processes died with the controller: {survivors:?}");
}

/// More pooled tasks that keep running than the pool's board has places all start from
/// the pool: a place is free again once its process has read its task, not when the task
/// ends. Then every script process, started ahead or for its task, dies with its
/// controller's `kill -9`, even one computing without an API call (nothing but its death
/// signal, which it sets itself, can end it).
#[test]
fn places_come_back_while_their_tasks_run_and_every_script_dies_with_the_controller() {
    let starts = ipc::pool::PLACES + 2;
    let dir = tempfile::tempdir().unwrap();
    let main = program(
        dir.path(),
        "main.lua",
        &format!(
            "for k = 1, {starts} do\n  Till(function() return system_user_table[0] >= k end)\n  StartTask(k)\nend\n\
             while true do end\n"
        ),
    );
    let sleeper = program(dir.path(), "sleeper.lua", "while true do Sleep(50) end\n");
    let busy = program(dir.path(), "busy.lua", "while true do end\n");
    let mut toml = "[rt]\nscript_pool = 2\n[[axes]]\n".to_string();
    for id in 0..=starts {
        let program = match id {
            0 => &main,
            id if id == starts => &busy,
            _ => &sleeper,
        };
        toml += &format!(
            "[[tasks]]\nid = {id}\nprogram = {:?}\nautorun = {}\nwatchdog_ms = 600000\n",
            program.display().to_string(),
            id == 0
        );
    }
    let config = dir.path().join("machine.toml");
    std::fs::write(&config, toml).unwrap();
    let ns = unique_ns("pool-places");
    let mut child = start(&ns, &config);
    let pid = child.id();
    let namespace = ipc::Namespace::new(&ns).unwrap();
    assert!(eventually(Duration::from_secs(20), || ipc::controller_ready(&namespace).unwrap_or(false)));
    let table = ipc::shm::Region::<ipc::task_table::TaskTable>::open(&namespace, "tasks").unwrap();
    let shared = ipc::shm::Region::<schema::shared::SharedData>::open(&namespace, "shared").unwrap();
    let ready = || table.pool.places.iter().filter(|p| p.state() == ipc::pool::PlaceState::Ready).count();
    let mut started = 0;
    for k in 1..=starts {
        // Both waiting processes ready: the start is handed to one of them.
        if !eventually(Duration::from_secs(30), || ready() == 2) {
            break;
        }
        shared.set_user_table(0, k as f64);
        if !eventually(Duration::from_secs(30), || table.slots[k].started()) {
            break;
        }
        started = k;
    }
    // The last start's replacement named itself a waiting process: the two lists below
    // are read one after the other and must not see it change sides in between.
    let refilled = eventually(Duration::from_secs(30), || ready() == 2);
    let scripts: Vec<u32> = [children_of(pid), waiting_children_of(pid)].concat();
    // SAFETY: killing this test's controller as a crash would.
    unsafe { libc::kill(pid as i32, libc::SIGKILL) };
    let gone = eventually(Duration::from_secs(10), || scripts.iter().all(|&p| !process_alive(p)));
    let _ = child.wait();
    let mut stderr = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut stderr).unwrap();
    ipc::remove_namespace_files(&namespace);
    assert_eq!(started, starts, "every start got a ready waiting process: {stderr}");
    assert!(refilled, "the pool refilled after the last start: {stderr}");
    let pooled = stderr.lines().filter(|l| l.contains(" started") && l.contains("pooled=true")).count();
    assert_eq!(pooled, starts, "all from the pool: {stderr}");
    assert_eq!(scripts.len(), 1 + starts + 2, "main, the started tasks, two waiting: {scripts:?}");
    assert!(gone, "every script process died with the controller: {scripts:?}");
}

/// The supervisor sleeps while nothing happens (a task asleep, the pool full): it wakes
/// for an order or a process' end, and otherwise looks every 10 ms, not every
/// millisecond. Counted by its thread's voluntary context switches (the controller's
/// main thread in `luamotion run`) over 2 s: about 200 then, 2000 with a 1 ms poll.
#[test]
fn the_supervisor_sleeps_while_nothing_happens() {
    let dir = tempfile::tempdir().unwrap();
    let main = program(dir.path(), "main.lua", "Sleep(6000)\nPrint('woke')\n");
    let ns = unique_ns("pool-quiet");
    let child = start(&ns, &machine(dir.path(), 2, &[(main.as_path(), true)]));
    let pid = child.id();
    let switches = || {
        let status = std::fs::read_to_string(format!("/proc/{pid}/task/{pid}/status")).unwrap_or_default();
        status
            .lines()
            .find_map(|l| l.strip_prefix("voluntary_ctxt_switches:"))
            .and_then(|n| n.trim().parse::<u64>().ok())
    };
    let full = eventually(Duration::from_secs(20), || waiting_children_of(pid).len() == 2);
    let before = switches();
    std::thread::sleep(Duration::from_secs(2));
    let after = switches();
    let out = finish(child, Duration::from_secs(60));
    let context = format!("{}\n{}", out.stdout, out.stderr);
    assert!(out.status.success() && full, "{context}");
    assert_eq!(out.lines_of_task(0), vec!["woke"], "{context}");
    let (Some(before), Some(after)) = (before, after) else { panic!("the main thread's status read: {context}") };
    assert!(after - before < 600, "{} wake-ups of the supervisor in 2 s", after - before);
}

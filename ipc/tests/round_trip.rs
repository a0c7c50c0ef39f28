//! The core and a task, each on its own thread with its own node, talk as two processes would.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use ipc::call::Request;
use ipc::{CoreEndpoint, CoreIpcStats, Monitor, Namespace, TaskEndpoint};
use schema::Snapshot;

fn unique_ns(tag: &str) -> Namespace {
    Namespace::new(&format!("t{}-{tag}", std::process::id())).unwrap()
}

/// A fake core on its own thread, started and attachable; `stop` ends it, and joining it
/// gives its counters.
/// With `waker`, the futex wakes of more than one task due go through a task waker.
fn start_core(ns: &Namespace, waker: bool) -> (Arc<AtomicBool>, std::thread::JoinHandle<CoreIpcStats>) {
    let stop = Arc::new(AtomicBool::new(false));
    let ready = Arc::new(AtomicBool::new(false));
    let core = {
        let (ns, stop, ready) = (ns.clone(), stop.clone(), ready.clone());
        std::thread::spawn(move || run_core(ns, waker, stop, ready))
    };
    while !ready.load(Ordering::Acquire) {
        std::thread::sleep(Duration::from_millis(1));
    }
    (stop, core)
}

/// A fake core: serves requests by doubling the first argument, publishes a snapshot
/// every millisecond.
fn run_core(ns: Namespace, waker: bool, stop: Arc<AtomicBool>, ready: Arc<AtomicBool>) -> CoreIpcStats {
    ipc::claim_namespace(&ns).unwrap();
    let mut core = CoreEndpoint::create(&ns, &[1, 2, 3]).unwrap();
    if waker {
        core.hand_wakes_to_threads(&ns, &[0], |_| ()).unwrap();
    }
    let mut snapshot = Snapshot::default();
    ready.store(true, Ordering::Release);
    while !stop.load(Ordering::Acquire) {
        snapshot.cycle += 1;
        core.serve(snapshot.cycle, |task, request, reply| {
            assert!((1..=3).contains(&task));
            reply.rc = 0;
            reply.values[0] = (request.int(0) * 2) as u64;
            reply.valuec = 1;
            ipc::Disposition::Reply
        });
        let mut sample = core.loan_snapshot(&snapshot, 0).expect("a sample");
        sample.payload_mut().cycle = snapshot.cycle;
        core.send_snapshot(sample);
        core.wake(snapshot.cycle);
        std::thread::sleep(Duration::from_millis(1));
    }
    core.stats()
}

#[test]
fn a_call_returns_its_reply_and_the_snapshot_of_its_cycle() {
    let ns = unique_ns("call");
    let (stop, core) = start_core(&ns, false);
    let mut task = TaskEndpoint::open(&ns, 3, std::process::id()).unwrap();
    for i in 0..50 {
        let mut request = Request::new(0);
        request.push_int(i);
        let reply = task.call(&mut request).unwrap();
        assert_eq!(reply.rc, 0);
        assert_eq!(reply.values[0] as i64, 2 * i);
        assert!(task.snapshot().cycle >= reply.cycle);
    }
    let start = task.snapshot().cycle;
    task.wait_until_cycle(start + 20).unwrap();
    assert!(task.snapshot().cycle >= start + 20);
    stop.store(true, Ordering::Release);
    core.join().unwrap();
    drop(task);
    ipc::remove_namespace_files(&ns);
}

/// The core writes each cycle's snapshot into the loaned sample itself. A reader sees the
/// layout (what changes only with the bus) and that cycle's fields in every sample, also
/// in the chunks iceoryx2 hands out again (the reader holds one, history another), and a
/// new layout reaches every chunk.
#[test]
fn a_snapshot_written_in_place_holds_its_layout_in_every_sample() {
    let ns = unique_ns("in-place");
    ipc::claim_namespace(&ns).unwrap();
    let mut core = CoreEndpoint::create(&ns, &[]).unwrap();
    let mut monitor = Monitor::open(&ns).unwrap();
    let mut layout = Snapshot { period_ns: 1_000_000, slave_count: 3, ..Snapshot::default() };
    for generation in 0..3u64 {
        layout.slaves[2].rx_count = 5 + generation as u8;
        for cycle in 1..=50 {
            let mut sample = core.loan_snapshot(&layout, generation).expect("a sample");
            let s = sample.payload_mut();
            s.cycle = generation * 1000 + cycle;
            s.axes[1].pos_fb = cycle as f64;
            core.send_snapshot(sample);
            monitor.refresh();
            let seen = monitor.latest().expect("the sample just sent");
            assert_eq!((seen.cycle, seen.axes[1].pos_fb), (generation * 1000 + cycle, cycle as f64));
            assert_eq!(
                (seen.period_ns, seen.slave_count, seen.slaves[2].rx_count, seen.axes[0].pos_fb),
                (1_000_000, 3, 5 + generation as u8, 0.0),
                "cycle {cycle} of layout {generation}"
            );
        }
    }
    assert_eq!(core.stats().publish_failures, 0);
    drop((monitor, core));
    ipc::remove_namespace_files(&ns);
}

/// A task waiting for a cycle far ahead (a `Sleep`) is woken when that cycle comes, not
/// every cycle until then.
#[test]
fn a_waiting_task_is_woken_once_for_its_cycle() {
    let ns = unique_ns("wake-once");
    let (stop, core) = start_core(&ns, false);
    let mut task = TaskEndpoint::open(&ns, 3, std::process::id()).unwrap();
    let start = task.snapshot().cycle;
    task.wait_until_cycle(start + 200).unwrap();
    assert!(task.snapshot().cycle >= start + 200);
    stop.store(true, Ordering::Release);
    let stats = core.join().unwrap();
    assert_eq!(stats.wakes, 1, "one wake-up for one wait over 200 cycles");
    drop(task);
    ipc::remove_namespace_files(&ns);
}

/// Three tasks due in the same cycle are woken by a task waker, the RT thread making one
/// futex wake instead of three; each sees its cycle within a few cycles (without the
/// waker's wakes they would sleep on until their 100 ms liveness check).
#[test]
fn the_task_waker_wakes_the_tasks_due_in_one_cycle() {
    let ns = unique_ns("waker");
    let (stop, core) = start_core(&ns, true);
    let target = {
        let mut first = TaskEndpoint::open(&ns, 1, std::process::id()).unwrap();
        first.snapshot().cycle + 200
    };
    let tasks: Vec<_> = [1u8, 2, 3]
        .into_iter()
        .map(|id| {
            let ns = ns.clone();
            std::thread::spawn(move || {
                let mut task = TaskEndpoint::open(&ns, id, std::process::id()).unwrap();
                task.wait_until_cycle(target).unwrap();
                task.snapshot().cycle
            })
        })
        .collect();
    for task in tasks {
        let seen = task.join().unwrap();
        assert!((target..target + 30).contains(&seen), "woken at cycle {seen} for cycle {target}");
    }
    stop.store(true, Ordering::Release);
    let stats = core.join().unwrap();
    assert_eq!((stats.wakes, stats.handed_off), (3, 3), "{stats:?}");
    ipc::remove_namespace_files(&ns);
}

#[test]
fn a_second_controller_in_the_same_namespace_is_refused() {
    let ns = unique_ns("claim");
    ipc::claim_namespace(&ns).unwrap();
    let _core = CoreEndpoint::create(&ns, &[]).unwrap();
    let claim = ipc::claim_namespace(&ns);
    drop(_core);
    ipc::remove_namespace_files(&ns);
    match claim {
        Err(ipc::IpcError::NamespaceInUse { pid, .. }) => assert_eq!(pid, std::process::id()),
        other => panic!("expected NamespaceInUse, got {other:?}"),
    }
}

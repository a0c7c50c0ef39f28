//! The core and a task, each on its own thread with its own node, talk as two processes would.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use ipc::messages::{Request, Snapshot};
use ipc::{CoreEndpoint, Namespace, TaskEndpoint};

fn unique_ns(tag: &str) -> Namespace {
    Namespace::new(&format!("t{}-{tag}", std::process::id())).unwrap()
}

/// A fake core: serves requests by doubling the first argument, publishes a snapshot
/// every millisecond.
fn run_core(ns: Namespace, stop: Arc<AtomicBool>, ready: Arc<AtomicBool>) {
    ipc::claim_namespace(&ns).unwrap();
    let mut core = CoreEndpoint::create(&ns, &[3]).unwrap();
    let mut snapshot = Snapshot::default();
    ready.store(true, Ordering::Release);
    while !stop.load(Ordering::Acquire) {
        snapshot.cycle += 1;
        core.serve(snapshot.cycle, 4, |task, request, reply| {
            assert_eq!(task, 3);
            reply.rc = 0;
            reply.values[0] = (request.int(0) * 2) as u64;
            reply.valuec = 1;
            ipc::Disposition::Reply
        });
        core.publish(&snapshot);
        core.wake(snapshot.cycle);
        std::thread::sleep(Duration::from_millis(1));
    }
}

#[test]
fn a_call_returns_its_reply_and_the_snapshot_of_its_cycle() {
    let ns = unique_ns("call");
    let stop = Arc::new(AtomicBool::new(false));
    let ready = Arc::new(AtomicBool::new(false));
    let core = {
        let (ns, stop, ready) = (ns.clone(), stop.clone(), ready.clone());
        std::thread::spawn(move || run_core(ns, stop, ready))
    };
    while !ready.load(Ordering::Acquire) {
        std::thread::sleep(Duration::from_millis(1));
    }
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

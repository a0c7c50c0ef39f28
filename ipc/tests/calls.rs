//! The core's end of the call mailboxes: which posted calls it takes, which it refuses,
//! and a call kept aside (deferred) while the same task posts again.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use ipc::call::Request;
use ipc::{CoreEndpoint, Disposition, Namespace, TaskEndpoint};
use schema::Snapshot;

fn unique_ns(tag: &str) -> Namespace {
    Namespace::new(&format!("t{}-{tag}", std::process::id())).unwrap()
}

fn request(seq: u64, arg: i64) -> Request {
    let mut request = Request::new(1);
    request.seq = seq;
    request.push_int(arg);
    request
}

/// Serves one cycle; the first arguments of the calls handled, by task.
fn serve(core: &mut CoreEndpoint, cycle: u64) -> Vec<(u8, i64)> {
    let mut handled = Vec::new();
    core.serve(cycle, |task, request, _reply| {
        handled.push((task, request.int(0)));
        Disposition::Reply
    });
    handled
}

/// Only a whole request of the process in the slot, not taken before, of a task the core
/// serves is taken: another process' sequence, the same call posted again, a task not
/// configured and a posted bit over a half-written mailbox are refused and counted.
#[test]
fn the_core_takes_only_whole_new_calls_of_the_slots_process() {
    let ns = unique_ns("hostile");
    ipc::claim_namespace(&ns).unwrap();
    let mut core = CoreEndpoint::create(&ns, &[1, 2]).unwrap();
    let table = core.table();
    table.slots[1].set_pid(1234);
    table.slots[2].set_pid(77);

    table.calls.post(1, &request(999 << 32 | 1, 10));
    assert_eq!(serve(&mut core, 1), [], "another process' sequence");
    let table = core.table();
    table.calls.post(1, &request(1234 << 32 | 1, 11));
    table.calls.post(2, &request(77 << 32 | 5, 12));
    assert_eq!(serve(&mut core, 2), [(1, 11), (2, 12)]);
    let table = core.table();
    table.calls.post(1, &request(1234 << 32 | 1, 11));
    table.calls.post(5, &request(1234 << 32 | 2, 13));
    assert_eq!(serve(&mut core, 3), [], "the same call again; a task not served");
    // A writer that died after its bit but halfway through the words: the sequence word is 0.
    let table = core.table();
    table.calls.post(2, &request(77 << 32 | 6, 14));
    table.calls.mailbox(2).write_request(&request(0, 15));
    assert_eq!(serve(&mut core, 4), []);
    let stats = core.stats();
    assert_eq!((stats.requests, stats.replies, stats.refused), (2, 2, 4), "{stats:?}");
    drop(core);
    ipc::remove_namespace_files(&ns);
}

/// A task with a deferred call that posts again (it gave up waiting) is served the new
/// call only once the deferred one is answered.
#[test]
fn a_call_posted_behind_a_deferred_one_waits_for_it() {
    let ns = unique_ns("held");
    ipc::claim_namespace(&ns).unwrap();
    let mut core = CoreEndpoint::create(&ns, &[3]).unwrap();
    core.table().slots[3].set_pid(9);
    core.table().slots[3].set_state(ipc::task_table::RunState::InCall);
    core.table().calls.post(3, &request(9 << 32 | 1, 1));
    core.serve(1, |_, _, _| Disposition::Defer);
    assert_eq!(core.deferred_tasks(), 1 << 3);
    core.table().calls.post(3, &request(9 << 32 | 2, 2));
    assert_eq!(serve(&mut core, 2), [], "held behind the deferred call");
    core.resume(2, |_, _, _| false);
    assert_eq!(serve(&mut core, 3), [], "still held");
    let mut resumed = Vec::new();
    core.resume(3, |task, request, _| {
        resumed.push((task, request.int(0)));
        true
    });
    assert_eq!(resumed, [(3, 1)]);
    assert_eq!(serve(&mut core, 4), [(3, 2)], "served once the deferred call is answered");
    assert_eq!(core.stats().refused, 0);
    drop(core);
    ipc::remove_namespace_files(&ns);
}

/// A task that gave up on a call (its reply timeout) and calls again sees the late reply
/// of the first in its mailbox while it waits: counted once as out of order, however often
/// it looks, and its own call is answered after it (not lost behind the deferred one). A task the controller does not serve
/// cannot attach.
#[test]
fn a_late_reply_to_a_call_given_up_on_is_counted_once() {
    let ns = unique_ns("late");
    ipc::claim_namespace(&ns).unwrap();
    let stop = Arc::new(AtomicBool::new(false));
    let (ready_tx, ready) = std::sync::mpsc::channel();
    let core = {
        let (ns, stop) = (ns.clone(), stop.clone());
        std::thread::spawn(move || {
            let mut core = CoreEndpoint::create(&ns, &[4]).unwrap();
            ready_tx.send(()).unwrap();
            let mut snapshot = Snapshot::default();
            let mut deferred = None;
            while !stop.load(Ordering::Acquire) {
                snapshot.cycle += 1;
                let cycle = snapshot.cycle;
                core.serve(cycle, |_, request, reply| {
                    reply.values[0] = request.int(0) as u64;
                    reply.valuec = 1;
                    // The first call takes 150 cycles (a MoveHome), the second 300 (its
                    // task looks at its mailbox on each liveness check meanwhile), the
                    // third none.
                    match request.int(0) {
                        1 | 2 => {
                            deferred = Some(cycle + 150 * request.int(0) as u64);
                            Disposition::Defer
                        }
                        _ => Disposition::Reply,
                    }
                });
                core.resume(cycle, |_, _, _| deferred.is_some_and(|done| cycle >= done));
                let mut sample = core.loan_snapshot(&snapshot, 0).expect("a sample");
                sample.payload_mut().cycle = cycle;
                core.send_snapshot(sample);
                core.wake(cycle);
                std::thread::sleep(Duration::from_millis(1));
            }
            core.stats()
        })
    };
    ready.recv().unwrap();
    assert!(TaskEndpoint::open(&ns, 5, std::process::id()).is_err(), "task 5 is not configured");
    let mut task = TaskEndpoint::open(&ns, 4, std::process::id()).unwrap();
    task.set_reply_timeout(Some(Duration::from_millis(20)));
    assert!(matches!(task.call(&mut request(0, 1)), Err(ipc::IpcError::ReplyLost(_))));
    task.set_reply_timeout(Some(Duration::from_secs(20)));
    let reply = task.call(&mut request(0, 2)).unwrap();
    assert_eq!(reply.values[0], 2);
    let counters = task.reply_counters();
    assert_eq!((counters.lost, counters.out_of_order, counters.duplicated), (1, 1, 0), "{counters:?}");
    assert_eq!(task.call(&mut request(0, 3)).unwrap().values[0], 3);
    assert_eq!(task.reply_counters(), counters, "the last call's reply left in the mailbox is not counted");
    stop.store(true, Ordering::Release);
    let stats = core.join().unwrap();
    assert_eq!((stats.requests, stats.replies, stats.refused), (3, 3, 0), "{stats:?}");
    drop(task);
    ipc::remove_namespace_files(&ns);
}

/// Tasks are served in the order the controller was given them (the machine file's), not
/// by id: of two commands on one axis in a cycle the later is refused, as it always was.
#[test]
fn calls_are_served_in_the_order_the_tasks_were_configured() {
    let ns = unique_ns("order");
    ipc::claim_namespace(&ns).unwrap();
    let mut core = CoreEndpoint::create(&ns, &[63, 2, 62]).unwrap();
    for (task, pid) in [(2u8, 20u64), (62, 620), (63, 630)] {
        core.table().slots[task as usize].set_pid(pid as u32);
        core.table().calls.post(task, &request(pid << 32 | 1, task.into()));
    }
    assert_eq!(serve(&mut core, 1), [(63, 63), (2, 2), (62, 62)]);
    drop(core);
    ipc::remove_namespace_files(&ns);
}

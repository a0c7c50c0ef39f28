//! Issue 39, item 2: the RT thread's invariant holds with the wire transport. After
//! start-up a cycle never allocates while its network is on a wire (`maindevice`, against
//! `luamotion subdevices` across a veth pair) and a task moves an axis, reads the
//! statusword by SDO and writes an object by SDO through the wire's mailbox (deferred
//! calls, answered cycles later). Needs root or CAP_NET_ADMIN and CAP_NET_RAW; with
//! `CI=true` a missing capability fails, never skips.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

use api::Command;
use api::call::Value;
use common::wire::{End, Segment, wire};
use devices::ecat::Network;
use ipc::call::Request;
use ipc::{CoreEndpoint, Namespace, TaskEndpoint};
use kernel::Kernel;
use rt_core::MachineConfig;
use rt_core::config::TaskConfig;
use rt_core::cycle::CycleWork;
use rt_core::machine::Machine;
use rt_core::tasks::{self, Tasks};
use schema::motion_status::ENABLED;

/// The system allocator, counting the allocations made inside `run_cycle`.
struct Counting;

thread_local! {
    static IN_CYCLE: Cell<bool> = const { Cell::new(false) };
}
static CYCLE_ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

// SAFETY: every call goes to the system allocator unchanged.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if IN_CYCLE.try_with(Cell::get).unwrap_or(false) {
            CYCLE_ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// A command with its arguments in the declaration's order, as a request.
fn request(command: Command, values: &[Value]) -> Request {
    let call: api::CommandCall = api::call::from_values(command, values).expect("arguments as declared");
    let mut request = Request::new(command.id());
    calls::wire::encode(&call, &mut request).unwrap();
    request
}

/// Task 0: enables axis 0, then moves it back and forth, reads drive 1's statusword and
/// writes its following-error window by SDO, every round; counts the SDO answers.
fn busy_task(ns: Namespace, stop: Arc<AtomicBool>, answered: Arc<AtomicU64>) {
    use Value::{Double, Int};
    let mut task = TaskEndpoint::open(&ns, 0, std::process::id()).unwrap();
    assert_eq!(task.call(&mut request(Command::Enable, &[Int(0)])).unwrap().rc, 0);
    while task.snapshot().axes[0].motion_status & ENABLED == 0 {
        let target = task.snapshot().cycle + 1;
        task.wait_until_cycle(target).unwrap();
    }
    let mut i = 0i64;
    while !stop.load(Ordering::Acquire) {
        i += 1;
        task.call(&mut request(Command::MoveAbs, &[Int(0), Double((i % 2) as f64)])).unwrap();
        let read = task.call(&mut request(Command::ReadSDO, &[Int(1), Int(0x6041), Int(0), Int(2)])).unwrap();
        let window = Value::Int(10_000 + i % 100);
        let wrote = task.call(&mut request(Command::WriteSDO, &[Int(1), Int(0x6065), Int(0), Int(4), window])).unwrap();
        if read.rc == 0 && read.valuec == 1 && (read.values[0] as i64) > 0 && wrote.rc == 0 {
            answered.fetch_add(1, Ordering::Relaxed);
        }
        let target = task.snapshot().cycle + 1;
        task.wait_until_cycle(target).unwrap();
    }
}

fn run(work: &mut CycleWork, cycles: usize) {
    for _ in 0..cycles {
        IN_CYCLE.set(true);
        work.run_cycle();
        IN_CYCLE.set(false);
        // About the 1 ms cycle, so that the master's frames keep up.
        std::thread::sleep(Duration::from_micros(900));
    }
}

#[test]
fn a_cycle_on_the_wire_never_allocates_in_steady_state() {
    let wire = wire().expect("CI=true: the wire");
    let segment = Segment::serve(&wire, End::Inside);
    let config = MachineConfig::default();
    let mut network = Network::for_machine(&config);
    let plan = maindevice::Plan::new(&mut network, config.period_ns()).unwrap();
    let bus = maindevice::WireBus::start(&wire.outside, plan, config.period_ns(), 0).expect("the segment in Op");
    network.put_on_wire(Box::new(bus), maindevice::WireBus::lost_after_cycles(config.period_ns()));
    let kernel = Kernel::new(&config, &network);
    let task = TaskConfig { autorun: false, external: true, ..TaskConfig::autorun(0, "-".into()) };
    let (link, _supervisor) = tasks::link().expect("the bell");
    let tasks = Tasks::new(&[task], config.period_ns(), link);
    let machine = Machine::new(network, kernel, tasks, config.period_ns());
    let ns = Namespace::new(&format!("t{}-wire-alloc", std::process::id())).unwrap();
    ipc::claim_namespace(&ns).unwrap();
    let mut work = CycleWork::new(machine, CoreEndpoint::create(&ns, &[0]).unwrap());

    let (stop, answered) = (Arc::new(AtomicBool::new(false)), Arc::new(AtomicU64::new(0)));
    let task = {
        let (ns, stop, answered) = (ns.clone(), stop.clone(), answered.clone());
        std::thread::spawn(move || busy_task(ns, stop, answered))
    };
    run(&mut work, 500);
    let (allocations_before, answered_before) =
        (CYCLE_ALLOCATIONS.load(Ordering::Relaxed), answered.load(Ordering::Relaxed));
    run(&mut work, 2000);
    let allocations = CYCLE_ALLOCATIONS.load(Ordering::Relaxed) - allocations_before;
    let answers = answered.load(Ordering::Relaxed) - answered_before;
    let enabled = work.machine_mut().kernel.axes()[0].is_enabled();
    let counters = work.machine_mut().network.wire_counters().expect("on the wire");

    stop.store(true, Ordering::Release);
    run(&mut work, 50);
    task.join().unwrap();
    drop(work);
    ipc::remove_namespace_files(&ns);
    drop(segment);

    eprintln!("2000 cycles on the wire: {answers} rounds of SDO answers, {counters:?}");
    assert!(enabled, "the task's commands went over the wire");
    assert!(answers > 10, "the SDO calls were answered through the wire's mailbox: {answers}");
    assert!(counters.good > 1000, "frames came back: {counters:?}");
    assert_eq!(allocations, 0, "allocations in 2000 steady-state cycles on the wire ({counters:?})");
}

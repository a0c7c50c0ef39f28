//! The RT thread's invariant: after start-up, a cycle never allocates, even while a
//! task's commands are served (axis moves, a group's lines and arcs with look-ahead and
//! corner blends), snapshots published and wake-ups sent, and a FUN147 box
//! runs its step table on the group interpolator, and a digital I/O terminal's output
//! toggles (HMPL 9.3), with input shaping on axis 0 (which carries a flexible load) and
//! on the group, and the VSF on axis 6 (HMPL ch. 15), and axis 1's position trigger
//! pulses twice a cycle (HMPL ch. 12), and an analog output follows an axis (HMPL 10.4),
//! and axis 7 is compensated by a 2-D spline table over axes 0 and 4 that is read again
//! from the user table every few cycles (HMPL ch. 14).

mod rig;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

use api::Command;
use api::call::Value;
use calls::plc::SharedPlc;
use devices::ecat::Network;
use fun147::{Plc, Reg, Relay};
use ipc::call::Request;
use ipc::shm::Region;
use ipc::{CoreEndpoint, Namespace, TaskEndpoint};
use kernel::Kernel;
use rt_core::MachineConfig;
use rt_core::config::{SlaveConfig, SlaveDevice, TaskConfig};
use rt_core::cycle::CycleWork;
use rt_core::fun147_boxes::Contacts;
use rt_core::machine::Machine;
use rt_core::tasks::{self, Tasks};
use schema::motion_status::{ENABLED, INPUT_SHAPE, VSF};
use schema::shared::SharedData;

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

/// `command` with its `Int` arguments from `ints` and its `Double` ones from `doubles`,
/// each where the registry declares it, as a request.
fn request(command: Command, ints: &[i64], doubles: &[f64]) -> Request {
    typed(command, &rig::declared(command, ints, doubles))
}

/// A command with its arguments in the declaration's order (tables and strings included).
fn typed(command: Command, values: &[Value]) -> Request {
    let call: api::CommandCall = api::call::from_values(command, values).expect("arguments as declared");
    let mut request = Request::new(command.id());
    calls::wire::encode(&call, &mut request).unwrap();
    request
}

/// The digital I/O terminal after the eight axes' drives.
const TERMINAL: i64 = 8;
/// The analog I/O terminal after it (HMPL ch. 10).
const ANALOG: i64 = 9;

fn int(v: i64) -> Value {
    Value::Int(v)
}

fn list(v: &[f64]) -> Value {
    Value::List(v.iter().map(|&x| Value::Double(x)).collect())
}

fn text(t: &str) -> Value {
    Value::Str(t.as_bytes().to_vec())
}

/// {vel, acc, dec, smooth_time} of HMPL 8.5.
fn profile() -> Value {
    list(&[100.0, 5000.0, 5000.0, 0.0])
}

/// HMPL 14.5: axis 7's 2-D table (4 x 3 values from user table index 0) over axes 0 and 4.
fn comp_setup() -> Request {
    let axes = [int(7), int(0), list(&[-1.0, -1.0]), list(&[1.0, 1.0]), list(&[4.0, 3.0]), list(&[0.0, 4.0])];
    typed(Command::SetupComp2D, &axes)
}

/// A task that enables axes 0, 1 and 6 and moves them without pause, while axes 4 and 5, as
/// group 0 (HMPL ch. 8), run lines and arcs with look-ahead and rounded corners.
fn busy_task(ns: Namespace, stop: Arc<AtomicBool>) {
    let mut task = TaskEndpoint::open(&ns, 0, std::process::id()).unwrap();
    for mut setup in [
        request(Command::SetHomedStatus, &[0, 1], &[]),
        request(Command::SetHomedStatus, &[7, 1], &[]),
        request(Command::SetHomedStatus, &[4, 1], &[]),
        request(Command::SetCompAlgType, &[7, 1], &[]),
        comp_setup(),
        request(Command::EnableComp, &[7], &[]),
    ] {
        assert_eq!(task.call(&mut setup).unwrap().rc, 0);
    }
    for a in [0, 1, 4, 5, 6] {
        task.call(&mut request(Command::Enable, &[a], &[])).unwrap();
    }
    let enabled = |a: usize, task: &mut TaskEndpoint| task.snapshot().axes[a].motion_status & ENABLED != 0;
    while ![0, 1, 4, 5].iter().all(|&a| enabled(a, &mut task)) {
        let target = task.snapshot().cycle + 1;
        task.wait_until_cycle(target).unwrap();
    }
    for setup in [
        request(Command::AddAxisToGrp, &[0, 4], &[]),
        request(Command::AddAxisToGrp, &[0, 5], &[]),
        request(Command::EnableGroup, &[0], &[]),
        request(Command::SetGrpBufferMode, &[0, 6], &[]),
        request(Command::SetGrpTransMode, &[0, 2], &[]),
        request(Command::SetGrpTransPrm, &[0], &[50.0, 0.2, 0.0, 0.0]),
        // HMPL ch. 15: a robust shaper on axis 0, the VSF on axis 6, a shaper on the group.
        typed(Command::SetAxisInShape, &[int(0), Value::Double(20.0), Value::Double(0.05), int(0)]),
        request(Command::EnableAxisInShape, &[0], &[]),
        request(Command::SetAxisVsf, &[6], &[30.0, 1.0]),
        request(Command::EnableAxisVsf, &[6], &[]),
        typed(Command::SetGrpInShape, &[int(0), Value::Double(10.0), Value::Double(0.1), int(1)]),
        request(Command::EnableGrpInShape, &[0], &[]),
        // HMPL ch. 12: axis 1 at 100 mm/s over a point every 0.05 mm.
        request(Command::SetHomedStatus, &[1, 1], &[]),
        request(Command::SetPT_StartPos, &[1], &[0.1]),
        request(Command::SetPT_Interval, &[1], &[0.05]),
        request(Command::SetPT_EndPos, &[1], &[900.0]),
        request(Command::EnablePT, &[1], &[]),
        request(Command::MoveVel, &[1], &[100.0]),
        // HMPL 10.4: analog output 1 follows axis 0's reference velocity every cycle.
        request(Command::SetSlvAOType, &[ANALOG, 1, 1], &[]),
        request(Command::SetSlvAOMonitor, &[ANALOG, 1, 0x200], &[]),
        request(Command::SetSlvAOParam, &[ANALOG, 1, 1], &[0.01, 0.5]),
        request(Command::SetSlvAOType, &[ANALOG, 2, 1], &[]),
    ] {
        let mut setup = setup;
        assert_eq!(task.call(&mut setup).unwrap().rc, 0);
    }
    let mut i = 0;
    while !stop.load(Ordering::Acquire) {
        i += 1;
        for a in [0, 6] {
            task.call(&mut request(Command::MoveAbs, &[a], &[(i % 2) as f64])).unwrap();
        }
        let mut path = match i % 5 {
            0 => request(Command::LineAbs2D, &[0], &[1.0, 0.0]),
            1 => request(Command::ArcCW2D, &[0], &[1.0, 0.5, 1.0, 1.0]),
            2 => request(Command::LineAbs2D, &[0], &[0.0, 0.0]),
            // HMPL 8.5: tables of numbers (profile, pose, transition) read in the cycle.
            3 => typed(
                Command::LineAbs,
                &[
                    int(0),
                    list(&[1.0, 1.0, 0.0, 0.0, 0.0, 0.0]),
                    profile(),
                    int(1),
                    int(6),
                    int(2),
                    list(&[50.0, 0.2, 0.0, 0.0]),
                ],
            ),
            _ => typed(
                Command::CircleAbs,
                &[
                    int(0),
                    list(&[0.5, 0.5, 0.0]),
                    list(&[0.0, 0.0, 1.0]),
                    int(0),
                    list(&[0.0; 6]),
                    profile(),
                    int(1),
                    int(6),
                    int(0),
                    int(0),
                ],
            ),
        };
        task.call(&mut path).unwrap();
        // A refused MHSPO (no such register): the refusal allocates nothing either.
        let refused = typed(
            Command::MHSPO,
            &[int(0), text("Q1"), text("D0"), text("M1"), text("M2"), text("M3"), text("M4"), text("M5"), text("M6")],
        );
        assert_ne!(task.call(&mut { refused }).unwrap().rc, 0);
        task.call(&mut request(Command::GetPTPulse, &[1, 0], &[])).unwrap();
        // HMPL 14.3, 14.5, 14.2: the table cleared, set up and read again.
        if i % 10 == 0 {
            for mut comp in
                [request(Command::DisableComp, &[7], &[]), comp_setup(), request(Command::EnableComp, &[7], &[])]
            {
                assert_eq!(task.call(&mut comp).unwrap().rc, 0);
            }
        }
        // HMPL 9.3: the terminal's output 1 toggled and its input 1 switched.
        for mut io in [
            request(Command::ToggleSlvGPO, &[TERMINAL, 1], &[]),
            request(Command::SimSetSlvGPI, &[TERMINAL, 1, i % 2], &[]),
            // HMPL ch. 10: an analog output written, an input driven and its type changed.
            request(Command::SetSlvAO, &[ANALOG, 2], &[(i % 20) as f64 - 10.0]),
            request(Command::SimSetSlvAIRaw, &[ANALOG, 1, i % 65536], &[]),
            request(Command::SetSlvAIType, &[ANALOG, 1, i % 8], &[]),
        ] {
            assert_eq!(task.call(&mut io).unwrap().rc, 0);
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
        std::thread::sleep(Duration::from_micros(200));
    }
}

#[test]
fn a_cycle_never_allocates_in_steady_state() {
    // Axis 0 for the task's moves, 1 for the position trigger, 2 and 3 for the box (Ps2, Ps3),
    // 4 and 5 for the group, 6 for the VSF, 7 compensated.
    let mut config = MachineConfig::default();
    let first = config.axes[0].clone();
    config.axes = (0..8).map(|i| rt_core::config::AxisConfig { name: format!("axis{i}"), ..first.clone() }).collect();
    config.axes[0].plant.load_frequency_hz = 20.0;
    config.slaves.push(SlaveConfig { device: SlaveDevice::DigitalIo, inputs: 8, outputs: 8, loopback: false });
    config.slaves.push(SlaveConfig { device: SlaveDevice::AnalogIo, inputs: 2, outputs: 2, loopback: false });
    config.axes[1].pt = Some(rt_core::config::PtConfig { output: 2 });
    let mut network = Network::for_machine(&config);
    network.start(config.period_ns()).unwrap();
    let kernel = Kernel::new(&config, &network);
    // Task 0 is played by a thread of this test: attached, as a tool would be.
    let task = TaskConfig { autorun: false, external: true, ..TaskConfig::autorun(0, "-".into()) };
    let (link, _supervisor) = tasks::link().expect("the bell");
    let tasks = Tasks::new(&[task], config.period_ns(), link);
    let machine = Machine::new(network, kernel, tasks, config.period_ns()).with_position_triggers(&config);
    let ns = Namespace::new(&format!("t{}-alloc", std::process::id())).unwrap();
    ipc::claim_namespace(&ns).unwrap();
    // The scope on: 16 channels of every kind, a tool changing them inside the window.
    let names = [
        "a0.pos_fb",
        "a0.ref_pos",
        "a0.pos_out",
        "a0.pos_err",
        "a0.vel_fb",
        "a0.motion_status",
        "a2.pos_fb",
        "a3.vel_fb",
        "g0.carte_pose_cmd[0]",
        "g0.carte_pose_fb[1]",
        "g0.grp_pg_vel",
        "gpi",
        "gpo",
        "system_dtest0",
        "system_ltest1",
        "system_user_table[3]",
    ];
    let codes: Vec<u32> = names.iter().map(|n| calls::scope::Var::parse(n).unwrap().code()).collect();
    let ring = ipc::scope::ScopeRing::create(&ns, config.period_ns(), &codes).unwrap();
    let tool = ipc::scope::ScopeRing::open(&ns).unwrap();
    let mut work = CycleWork::new(machine, CoreEndpoint::create(&ns, &[0]).unwrap())
        .with_scope(Some(rt_core::scope::ScopeSampler::new(ring)));

    // A Gp1 box moving Ps2/Ps3 back and forth without end (GOTO 1).
    let shared = Region::<SharedData>::open(&ns, "shared").unwrap();
    for i in 0..12 {
        shared.set_user_table(i, 0.01 * i as f64);
    }
    let table = "001 SPD 20000\n LIN ADR,,,500,500,Ps\n002 SPD 20000\n LIN ADR,,,-500,-500,Ps\n GOTO 1";
    fun147::assemble(table).unwrap().write(&mut SharedPlc(shared.plc()), Reg::R(2000)).unwrap();
    let m = |n| Relay::M(n);
    let contacts = Contacts { en: m(100), pau: m(101), abt: m(102), act: m(110), err: m(111), dn: m(112) };
    let machine = work.machine_mut();
    machine.boxes.declare(1, Reg::R(2000), Reg::D(0), contacts).unwrap();
    for axis in [2, 3] {
        machine.kernel.enable(axis).unwrap();
    }

    let stop = Arc::new(AtomicBool::new(false));
    let task = {
        let (ns, stop) = (ns.clone(), stop.clone());
        std::thread::spawn(move || busy_task(ns, stop))
    };
    run(&mut work, 500);
    SharedPlc(shared.plc()).set_relay(Relay::M(100), true);
    let allocations_before = CYCLE_ALLOCATIONS.load(Ordering::Relaxed);
    let rows_before = tool.written();
    run(&mut work, 1000);
    let request = tool.request(&codes[8..]);
    run(&mut work, 2000);
    let scoped = (tool.written() - rows_before, tool.active_request() == request);
    let allocations = CYCLE_ALLOCATIONS.load(Ordering::Relaxed) - allocations_before;
    let enabled = work.machine_mut().kernel.axes()[0].is_enabled();
    let filters = work.machine_mut().kernel.axis_snapshot(0).motion_status & INPUT_SHAPE != 0
        && work.machine_mut().kernel.axis_snapshot(6).motion_status & VSF != 0
        && work.machine_mut().kernel.groups()[0].in_shape();
    let grouped = work.machine_mut().kernel.groups()[0].is_enabled();
    let pulsed = work.machine_mut().triggers.pulse(1, 255).is_ok();
    // The task clears and sets up axis 7's table again every tenth round, so it may be off
    // for a few cycles just now: it must be on again within a round.
    let compensating = (0..200).any(|_| {
        run(&mut work, 1);
        work.machine_mut().kernel.is_comp_active(7)
    });
    let plc = SharedPlc(shared.plc());
    let (box_running, box_error) = (plc.relay(Relay::M(110)), plc.word(Reg::D(4061)));

    stop.store(true, Ordering::Release);
    run(&mut work, 50);
    task.join().unwrap();
    drop(work);
    ipc::remove_namespace_files(&ns);

    assert!(enabled, "the task's commands were applied");
    assert!(grouped, "the group's commands were applied");
    assert!(filters, "the filters of ch. 15 were on");
    assert_eq!(scoped, (3000, true), "the scope recorded every cycle and took over a new request");
    assert!(pulsed, "axis 1's position trigger gave pulses");
    assert!(compensating, "axis 7 is compensated");
    assert!(box_running && box_error == 0, "the box runs its table (ACT {box_running}, error {box_error})");
    assert_eq!(allocations, 0, "allocations in 3000 steady-state cycles");
}

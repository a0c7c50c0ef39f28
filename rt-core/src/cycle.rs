//! The RT thread: one cycle every period, on an absolute deadline.
//!
//! 1. wake at the deadline, record lateness;
//! 2. exchange the frame with the drives;
//! 3. serve the tasks' commands;
//! 4. step the kernel;
//! 5. publish the snapshot and wake the tasks whose reply or wake cycle has come;
//! 6. account the cycle's execution time.
//!
//! After start-up nothing here allocates, locks or blocks: the iceoryx2 ports and the
//! histograms are created before the first cycle.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use hdrhistogram::Histogram;
use ipc::clock::monotonic_ns;
use ipc::messages::Snapshot;
use ipc::{CoreEndpoint, CoreIpcStats};

use crate::dispatch;
use crate::ecat::Network;
use crate::master::{self, PdoForces};
use crate::motion::Kernel;
use crate::realtime::{self, Granted};

/// Requests one task may have applied per cycle; the rest wait for the next cycle.
const MAX_COMMANDS_PER_TASK_AND_CYCLE: usize = 4;
/// How long a shutdown waits for the drives to disable.
const SHUTDOWN_CYCLES: u64 = 500;

/// Everything the RT thread owns and steps.
pub struct Machine {
    pub network: Network,
    pub kernel: Kernel,
    pub forces: PdoForces,
    pub period_ns: u64,
}

impl Machine {
    pub fn new(network: Network, kernel: Kernel, period_ns: u64) -> Self {
        Machine { network, kernel, forces: PdoForces::default(), period_ns }
    }
}

/// Shared between the RT thread and the supervisor.
#[derive(Default)]
pub struct RtControl {
    shutdown: AtomicBool,
    cycle: AtomicU64,
}

impl RtControl {
    /// Asks the RT thread to disable the axes and stop.
    pub fn request_shutdown(&self) {
        self.shutdown.store(true, Ordering::Release);
    }

    /// The last cycle completed.
    pub fn cycle(&self) -> u64 {
        self.cycle.load(Ordering::Acquire)
    }
}

/// Timing of the cycles run.
pub struct CycleStats {
    pub cycles: u64,
    /// Cycles whose work ran past the next deadline.
    pub overruns: u64,
    /// Wake-up lateness after the deadline, ns.
    pub lateness: Histogram<u64>,
    /// Execution time of one cycle's work, ns.
    pub execution: Histogram<u64>,
    pub ipc: CoreIpcStats,
    pub granted: Granted,
}

impl CycleStats {
    fn new(granted: Granted) -> Self {
        let histogram = || Histogram::new_with_bounds(1, 60_000_000_000, 3).expect("valid bounds");
        CycleStats {
            cycles: 0,
            overruns: 0,
            lateness: histogram(),
            execution: histogram(),
            ipc: CoreIpcStats::default(),
            granted,
        }
    }
}

/// The work of one cycle, without its timing: what the RT thread does between two sleeps.
pub struct CycleWork {
    machine: Machine,
    endpoint: CoreEndpoint,
    snapshot: Snapshot,
    cycle: u64,
}

impl CycleWork {
    pub fn new(machine: Machine, endpoint: CoreEndpoint) -> Self {
        let mut snapshot = Snapshot { period_ns: machine.period_ns, ..Snapshot::default() };
        master::describe_slaves(&machine.network, &mut snapshot);
        snapshot.system_error = machine.network.start_error().is_some() as u32;
        CycleWork { machine, endpoint, snapshot, cycle: 0 }
    }

    pub fn machine_mut(&mut self) -> &mut Machine {
        &mut self.machine
    }

    /// Steps 2 to 5: drives, commands, kernel, snapshot and wake-ups.
    pub fn run_cycle(&mut self) {
        self.cycle += 1;
        let cycle = self.cycle;
        let period = self.machine.period_ns;
        self.machine.network.exchange(period as f64 * 1e-9);
        let machine = &mut self.machine;
        self.endpoint.serve(cycle, MAX_COMMANDS_PER_TASK_AND_CYCLE, |_task, request, reply| {
            dispatch::execute(machine, request, reply)
        });
        self.machine.kernel.step(cycle, &mut self.machine.network);
        let machine = &mut self.machine;
        self.endpoint.resume(cycle, |_task, request, reply| dispatch::resume(machine, request, reply));
        let (_, outputs) = self.machine.network.images_mut();
        self.machine.forces.apply(outputs);

        self.snapshot.cycle = cycle;
        self.snapshot.time_in_ms = cycle * period / 1_000_000;
        master::update_slaves(&self.machine.network, &mut self.snapshot);
        self.machine.kernel.fill(&mut self.snapshot);
        self.endpoint.publish(&self.snapshot);
        self.endpoint.wake(cycle);
    }
}

/// Runs cycles until a shutdown is requested and the axes are disabled.
pub fn run(machine: Machine, endpoint: CoreEndpoint, control: Arc<RtControl>, granted: Granted) -> CycleStats {
    let period = machine.period_ns;
    let mut work = CycleWork::new(machine, endpoint);
    let mut stats = CycleStats::new(granted);
    let mut deadline = monotonic_ns() + period;
    let mut shutdown_since = None;

    loop {
        realtime::sleep_until(deadline);
        let woke = monotonic_ns();
        let _ = stats.lateness.record(woke.saturating_sub(deadline).max(1));

        if shutdown_since.is_none() && control.shutdown.load(Ordering::Acquire) {
            shutdown_since = Some(work.cycle);
            work.machine.kernel.disable_all();
        }
        work.run_cycle();
        control.cycle.store(work.cycle, Ordering::Release);

        let done = monotonic_ns();
        let _ = stats.execution.record(done.saturating_sub(woke).max(1));
        stats.cycles = work.cycle;
        deadline += period;
        if done > deadline {
            // Missed the next deadline: count it and resume on the period grid.
            stats.overruns += 1;
            deadline += (done - deadline).div_ceil(period) * period;
        }

        if let Some(since) = shutdown_since {
            let all_disabled = work.machine.kernel.axes().iter().all(|a| a.is_disabled());
            if all_disabled || work.cycle - since > SHUTDOWN_CYCLES {
                break;
            }
        }
    }
    stats.ipc = work.endpoint.stats();
    stats
}

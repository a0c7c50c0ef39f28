//! The RT thread: one cycle every period, on an absolute deadline.
//!
//! 1. wake at the deadline, record lateness;
//! 2. exchange the frame with the drives;
//! 3. serve the tasks' commands;
//! 4. tasks: the supervisor's reports, starts, watchdogs and fault reactions; the E-stop input;
//! 5. step the kernel;
//! 6. publish the snapshot and wake the tasks whose reply or wake cycle has come;
//! 7. account the cycle's execution time.
//!
//! After start-up nothing here allocates, locks or blocks: the iceoryx2 ports and the
//! histograms are created before the first cycle.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use api::ErrorCode;
use hdrhistogram::Histogram;
use ipc::clock::monotonic_ns;
use ipc::{CoreEndpoint, CoreIpcStats};
use schema::Snapshot;

use crate::console::{ConsoleInbox, ControllerState};
use crate::dispatch;
use crate::huge_pages::HugePages;
use crate::machine::Machine;
use crate::master;
use crate::overrun::{OverrunCauses, OverrunCycle};
use crate::realtime::{self, Granted};
use crate::scope::ScopeSampler;
use crate::sim_clock::Lockstep;
use crate::trace::{CycleTiming, Digest, TraceRow, TraceSender};

/// How long a shutdown waits for the drives to disable.
const SHUTDOWN_CYCLES: u64 = 500;

/// Shared between the RT thread and the supervisor.
#[derive(Default)]
pub struct RtControl {
    shutdown: AtomicBool,
    stop_tasks: AtomicBool,
    cycle: AtomicU64,
    active_tasks: AtomicU64,
}

impl RtControl {
    /// Asks the RT thread to disable the axes and stop.
    pub fn request_shutdown(&self) {
        self.shutdown.store(true, Ordering::Release);
    }

    /// Asks the RT thread to stop every task, as `StopAllTask` does, and start no other.
    pub fn request_stop_tasks(&self) {
        self.stop_tasks.store(true, Ordering::Release);
    }

    /// The last cycle completed.
    pub fn cycle(&self) -> u64 {
        self.cycle.load(Ordering::Acquire)
    }

    /// Tasks starting, running or being stopped, as of the last cycle.
    pub fn active_tasks(&self) -> u64 {
        self.active_tasks.load(Ordering::Acquire)
    }
}

/// Timing of the cycles run.
pub struct CycleStats {
    /// Cycles run.
    pub cycles: u64,
    /// Cycles whose work ran past the next deadline...
    pub overruns: u64,
    /// ...and why (`overrun.rs`).
    pub overrun_causes: OverrunCauses,
    /// Wake-up lateness after the deadline, ns.
    pub lateness: Histogram<u64>,
    /// Execution time of one cycle's work, ns.
    pub execution: Histogram<u64>,
    /// The RT thread's CPU time for one cycle (from its wake-up to its sleep), ns.
    pub cpu: Histogram<u64>,
    /// The CPU time charged to the RT thread on its way out of each sleep, before the wake-up
    /// is timed (`realtime::WokeCpuTime`), ns: what the machine charges as CPU time while
    /// the thread does next to nothing.
    pub wake_up_cpu: Histogram<u64>,
    /// The core's requests, replies and notifications over the run.
    pub ipc: CoreIpcStats,
    /// What the OS granted the RT thread (priority, CPU, locked memory).
    pub granted: Granted,
    /// What the kernel rebuilt in huge pages before the first cycle; none: not asked.
    pub huge_pages: Option<HugePages>,
    /// CPU time the RT thread used over the run, and the run's length, ns.
    pub cpu_ns: u64,
    /// The run's length, wall time, ns.
    pub wall_ns: u64,
    /// Of the RT thread's time, the frame exchange with the simulated drives (their
    /// servo loops and plants), ns: on a real machine, the drives' own hardware.
    pub simulation_ns: u64,
    /// On the simulation clock, the time the RT thread waited between cycles for the tasks'
    /// turns, ns.
    pub lockstep_ns: u64,
    /// The digest of the recorded cycles' trace rows.
    pub digest: Digest,
    /// Wall time from the start to the end of the last recorded cycle, ns: on the
    /// simulation clock, what the recorded cycles took (the run's speed-up).
    pub recorded_wall_ns: u64,
}

impl CycleStats {
    fn new(granted: Granted) -> Self {
        let histogram = || Histogram::new_with_bounds(1, 60_000_000_000, 3).expect("valid bounds");
        CycleStats {
            cycles: 0,
            overruns: 0,
            overrun_causes: OverrunCauses::default(),
            lateness: histogram(),
            execution: histogram(),
            cpu: histogram(),
            wake_up_cpu: histogram(),
            ipc: CoreIpcStats::default(),
            granted,
            huge_pages: None,
            cpu_ns: 0,
            wall_ns: 0,
            simulation_ns: 0,
            lockstep_ns: 0,
            digest: Digest::default(),
            recorded_wall_ns: 0,
        }
    }
}

/// The work of one cycle, without its timing: what the RT thread does between two sleeps.
pub struct CycleWork {
    machine: Machine,
    endpoint: CoreEndpoint,
    /// What changes only with the bus (the slaves' mappings, the period): the layout every
    /// published sample starts from; also the snapshot of a cycle that got no sample.
    snapshot: Snapshot,
    /// Numbers the versions of that layout (a `ScanNetwork` makes a new one).
    layout: u64,
    cycle: u64,
    overruns: u64,
    /// Timing the RT loop hands in for the trace.
    timing: CycleTiming,
    /// Time spent exchanging the frame with the simulated drives, ns.
    simulation_ns: u64,
    trace: Option<TraceSender>,
    scope: Option<ScopeSampler>,
    console: Option<ConsoleInbox>,
    /// On the simulation clock: no wall time in the rows, no row dropped.
    sim: bool,
    /// Rows go to the trace and the digest (on the simulation clock, until every program ended).
    recording: bool,
    digest: Digest,
    /// The tasks this cycle answered or whose wake cycle came.
    woken: u64,
    /// On the simulation clock, the tasks whose watched `Till` condition read something
    /// else in this cycle's snapshot (`sim_clock::changed_watches`).
    watches_changed: u64,
}

impl CycleWork {
    /// The cycle's work on `machine`, answering the tasks through `endpoint`; a network that
    /// failed to start leaves the controller in Fail (DXMC 3.6).
    pub fn new(machine: Machine, endpoint: CoreEndpoint) -> Self {
        let mut snapshot = Snapshot { period_ns: machine.period_ns, ..Snapshot::default() };
        master::describe_slaves(&machine.network, &mut snapshot);
        snapshot.system_error = machine.network.start_error().is_some() as u32;
        let mut machine = machine;
        if machine.network.start_error().is_some() {
            machine.state = ControllerState::Fail;
        }
        // FUN147 expl. 4: the axes are Ready at power-up.
        fun147::plc::power_up(&mut calls::plc::SharedPlc(endpoint.shared().plc()));
        CycleWork {
            machine,
            endpoint,
            snapshot,
            layout: 0,
            cycle: 0,
            overruns: 0,
            timing: CycleTiming::default(),
            simulation_ns: 0,
            trace: None,
            scope: None,
            console: None,
            sim: false,
            recording: true,
            digest: Digest::default(),
            woken: 0,
            watches_changed: 0,
        }
    }

    /// Takes the console's orders (the Modbus server's DRL and state registers).
    pub fn with_console(mut self, console: Option<ConsoleInbox>) -> Self {
        self.console = console;
        self
    }

    /// Records every cycle into `trace`.
    pub(crate) fn with_trace(mut self, trace: Option<TraceSender>) -> Self {
        self.trace = trace;
        self
    }

    /// Samples the scope's channels every cycle.
    pub fn with_scope(mut self, scope: Option<ScopeSampler>) -> Self {
        self.scope = scope;
        self
    }

    /// The machine between cycles, to change it there (the tests do).
    pub fn machine_mut(&mut self) -> &mut Machine {
        &mut self.machine
    }

    /// Steps 2 to 6: drives, commands, tasks, kernel, snapshot and wake-ups.
    pub fn run_cycle(&mut self) {
        self.cycle += 1;
        let cycle = self.cycle;
        self.machine.cycle = cycle;
        let period = self.machine.period_ns;
        let exchange_start = monotonic_ns();
        self.machine.network.exchange(period as f64 * 1e-9);
        self.machine.watch_bus();
        self.simulation_ns += monotonic_ns() - exchange_start;
        let machine = &mut self.machine;
        self.endpoint.serve(cycle, |task, request, reply| dispatch::execute(machine, task, request, reply));
        if std::mem::take(&mut self.machine.rescanned) {
            master::describe_slaves(&self.machine.network, &mut self.snapshot);
            self.snapshot.system_error = self.machine.network.start_error().is_some() as u32;
            self.layout += 1;
        }
        let deferred = self.endpoint.deferred_tasks();
        {
            let Machine { tasks, kernel, .. } = &mut self.machine;
            let (table, shared) = (self.endpoint.table(), self.endpoint.shared());
            tasks.step(cycle, table, shared, deferred, &mut |t, reaction| kernel.react(t, reaction));
            if let Some(error) = tasks.take_runtime_error() {
                kernel.record_system_error(ErrorCode::System(error).code());
            }
        }
        if let Some(console) = &self.console {
            for order in console.drain() {
                self.machine.carry_out(order);
            }
        }
        if self.machine.io.emo_edge() {
            self.machine.emergency_stop();
        }
        {
            let Machine { boxes, kernel, .. } = &mut self.machine;
            let mut plc = calls::plc::SharedPlc(self.endpoint.shared().plc());
            boxes.step(kernel, &mut plc, period as f64 * 1e-9);
        }
        // HMPL 14.2: the tables EnableComp asked for, copied before the kernel uses them.
        let shared = self.endpoint.shared();
        self.machine.kernel.load_compensation(|i| shared.user_table(i));
        self.machine.kernel.step(cycle, &mut self.machine.network);
        {
            let Machine { triggers, kernel, io, .. } = &mut self.machine;
            triggers.step(cycle, period, kernel, io);
        }
        let machine = &mut self.machine;
        self.endpoint.resume(cycle, |_task, request, reply| dispatch::resume(machine, request, reply));
        // The snapshot is written in place into a slot of the board; without one (counted,
        // not published) into `self.snapshot`, which also holds the layout a new sample
        // starts from.
        let mut loaned = self.endpoint.loan_snapshot(&self.snapshot, self.layout);
        let snapshot = match &mut loaned {
            Some(sample) => sample.payload_mut(),
            None => &mut self.snapshot,
        };
        // The bound analog outputs follow this cycle's axis variables as the snapshot
        // shows them; forced values still win.
        self.machine.kernel.fill(snapshot);
        let period_s = period as f64 * 1e-9;
        self.machine.analog.step(&snapshot.axes, &mut self.machine.network, period_s);
        let (_, outputs) = self.machine.network.images_mut();
        self.machine.forces.apply(outputs);

        snapshot.cycle = cycle;
        snapshot.time_in_ms = cycle * period / 1_000_000;
        snapshot.overruns = self.overruns;
        snapshot.controller_state = self.machine.state.into();
        snapshot.gpio = self.machine.io.snapshot();
        master::update_slaves(&self.machine.network, snapshot);
        self.machine.triggers.fill(&mut snapshot.position_triggers);
        self.machine.analog.fill(snapshot);
        self.machine.tasks.fill(&mut snapshot.tasks, &self.machine.run_speed);
        if self.sim {
            self.watches_changed = crate::sim_clock::changed_watches(self.endpoint.table(), snapshot);
        }
        if let Some(scope) = &mut self.scope {
            scope.sample(snapshot, self.endpoint.shared());
        }
        // On the real-time clock a row is only made for a trace file: a digest of wall-time
        // runs would say nothing.
        let row = (self.recording && (self.sim || self.trace.is_some())).then(|| {
            let timing = if self.sim { CycleTiming::default() } else { self.timing };
            TraceRow::of(snapshot, timing)
                .with_loads(&self.machine.kernel, &self.machine.network)
                .with_position_triggers(&self.machine.triggers)
        });
        if let Some(sample) = loaned {
            self.endpoint.send_snapshot(sample);
        }
        self.woken = self.endpoint.wake(cycle);
        if let Some(row) = row {
            self.record(row);
        }
    }

    /// The cycle's trace row, into the trace file and, on the simulation clock, the digest.
    fn record(&mut self, row: TraceRow) {
        if self.sim {
            self.digest.add(&row);
        }
        match &self.trace {
            Some(trace) if self.sim => trace.push_all(row),
            Some(trace) => trace.push(row),
            None => {}
        }
    }
}

/// Runs cycles until a shutdown is requested and the axes are disabled; with `lockstep`,
/// on the simulation clock (`sim_clock`). `huge_pages`: what `huge_pages` rebuilt before,
/// for the statistics.
pub fn run(
    mut work: CycleWork,
    control: Arc<RtControl>,
    granted: Granted,
    huge_pages: Option<HugePages>,
    mut lockstep: Option<Lockstep>,
) -> CycleStats {
    work.sim = lockstep.is_some();
    // The wall time between two deadlines; none: no sleep (`--speed max`).
    let period = work.machine.period_ns;
    let pace = match &lockstep {
        None => Some(period),
        Some(lockstep) => lockstep.speed().pace_ns(period),
    };
    let mut stats = CycleStats { huge_pages, ..CycleStats::new(granted) };
    let started_ns = monotonic_ns();
    let started_cpu_ns = realtime::thread_cpu_ns();
    // A cycle's CPU time is known at the next wake-up (`CycleCpuTime`), and so is an
    // overrun's cause: it waits there, its CPU time to be filled in.
    let mut cycle_cpu = realtime::CycleCpuTime::default();
    let mut unclassified_overrun: Option<OverrunCycle> = None;
    let mut deadline = started_ns + pace.unwrap_or(0);
    let mut shutdown_since = None;
    let stopping = || control.shutdown.load(Ordering::Acquire) || control.stop_tasks.load(Ordering::Acquire);

    loop {
        if pace.is_some() {
            realtime::sleep_until(deadline);
        }
        let cpu = cycle_cpu.woke();
        let woke = monotonic_ns();
        if let Some(cpu) = cpu {
            work.timing.previous_cpu_ns = cpu.previous_cycle_ns;
            work.timing.previous_faults = cpu.previous_faults;
            work.timing.previous_preemptions = cpu.previous_preemptions;
            let _ = stats.cpu.record(cpu.previous_cycle_ns.max(1));
            let _ = stats.wake_up_cpu.record(cpu.wake_up_ns.max(1));
            if let Some(mut overrun) = unclassified_overrun.take() {
                overrun.cpu_ns = cpu.previous_cycle_ns;
                stats.overrun_causes.count(period, overrun);
            }
        }
        work.timing.lateness_ns = woke.saturating_sub(deadline);
        let _ = stats.lateness.record(work.timing.lateness_ns.max(1));

        if control.stop_tasks.load(Ordering::Acquire) {
            work.machine.stop_all_tasks();
        }
        if shutdown_since.is_none() && control.shutdown.load(Ordering::Acquire) {
            shutdown_since = Some(work.cycle);
            work.machine.kernel.disable_all();
        }
        if let Some(lockstep) = &mut lockstep {
            // The run's record ends with its programs: what follows depends on when the
            // supervisor notices, which is wall time.
            work.recording &= work.cycle == 0 || !lockstep.all_ended(&work.machine.tasks, &work.endpoint);
            lockstep.begin(work.cycle + 1, &mut work.machine, work.endpoint.shared());
        }
        work.run_cycle();
        control.cycle.store(work.cycle, Ordering::Release);
        control.active_tasks.store(work.machine.tasks.active() as u64, Ordering::Release);

        let done = monotonic_ns();
        if work.recording {
            stats.recorded_wall_ns = done - started_ns;
        }
        work.timing.previous_execution_ns = done.saturating_sub(woke);
        let _ = stats.execution.record(work.timing.previous_execution_ns.max(1));
        stats.cycles = work.cycle;
        if let Some(lockstep) = &mut lockstep {
            lockstep.settle(
                work.cycle,
                work.woken,
                work.watches_changed,
                &work.machine.tasks,
                &work.endpoint,
                &stopping,
            );
            stats.lockstep_ns += monotonic_ns() - done;
        }
        match pace {
            // Never ahead of `speed` times real time; a late cycle is not made up for.
            Some(pace) if lockstep.is_some() => deadline = (deadline + pace).max(monotonic_ns()),
            Some(pace) => {
                deadline += pace;
                if done > deadline {
                    // Missed the next deadline: count it and resume on the period grid.
                    stats.overruns += 1;
                    unclassified_overrun = Some(OverrunCycle {
                        lateness_ns: work.timing.lateness_ns,
                        execution_ns: work.timing.previous_execution_ns,
                        cpu_ns: 0,
                    });
                    work.overruns = stats.overruns;
                    deadline += (done - deadline).div_ceil(pace) * pace;
                }
            }
            // No deadline: the lateness recorded is the wait for the tasks.
            None => deadline = done,
        }

        if let Some(since) = shutdown_since {
            let all_disabled = work.machine.kernel.axes().iter().all(|a| a.is_disabled());
            if all_disabled || work.cycle - since > SHUTDOWN_CYCLES {
                break;
            }
        }
    }
    if let Some(mut overrun) = unclassified_overrun {
        // The last cycle did not sleep: its CPU time is read after it.
        overrun.cpu_ns = cycle_cpu.since_woke();
        stats.overrun_causes.count(period, overrun);
    }
    stats.ipc = work.endpoint.stats();
    stats.cpu_ns = realtime::thread_cpu_ns() - started_cpu_ns;
    stats.simulation_ns = work.simulation_ns;
    stats.digest = work.digest;
    stats.wall_ns = monotonic_ns() - started_ns;
    stats
}

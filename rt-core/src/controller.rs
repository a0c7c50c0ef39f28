//! A controller from start to shutdown: claim the namespace, bring the EtherCAT network
//! up, start the RT thread, start the tasks, watch them, shut down in order.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, mpsc};
use std::time::Duration;

use ipc::{CoreEndpoint, Namespace};

use crate::config::MachineConfig;
use crate::console::ConsoleInbox;
use crate::cycle::{self, CycleStats, RtControl};
use crate::huge_pages;
use crate::machine::Machine;
use crate::realtime;
use crate::scope::ScopeSampler;
use crate::sim_clock::{Clock, Lockstep};
use crate::supervisor::{ScriptLauncher, Supervisor, TaskReport};
use crate::tasks::{self, Tasks};
use crate::trace;
use devices::ecat::Network;
use kernel::Kernel;

/// How long the tasks have to be stopped in order at shutdown before the rest are killed.
const STOP_PATIENCE: Duration = Duration::from_secs(2);

/// Why a controller could not run to its end.
#[derive(Debug, thiserror::Error)]
pub enum ControllerError {
    /// The namespace or a shared-memory service could not be set up.
    #[error(transparent)]
    Ipc(#[from] ipc::IpcError),
    /// The RT thread or the supervisor's link could not be set up; why.
    #[error("the RT thread failed to start: {0}")]
    RtStart(String),
    /// The RT thread panicked or ended before its time; why.
    #[error("the RT thread died: {0}")]
    RtDied(String),
    /// The data directory (`RunOptions::data_dir`) could not be created.
    #[error("cannot use the data directory {path}: {source}")]
    DataDir {
        /// The directory.
        path: PathBuf,
        /// The OS's error.
        source: std::io::Error,
    },
    /// The trace file (`--trace`) could not be created.
    #[error("cannot write the trace {path}: {source}")]
    Trace {
        /// The trace file.
        path: PathBuf,
        /// The OS's error.
        source: std::io::Error,
    },
    /// `[bus] interface`: the segment on the wire is not the machine file's, or could
    /// not be brought to Op; the controller does not start.
    #[error("EtherCAT on {interface}: {error}")]
    Wire {
        /// The interface of `[bus]`.
        interface: String,
        /// What stopped the start-up.
        error: maindevice::WireError,
    },
    /// The machine's own network could not lay out the image the wire must carry.
    #[error("EtherCAT on {interface}: the machine file's devices did not start: {error}")]
    Plan {
        /// The interface of `[bus]`.
        interface: String,
        /// Where the in-memory start-up stopped.
        error: devices::ecat::StartError,
    },
    /// A machine on a wire runs on the wall clock: its drives do not wait for a program.
    #[error("a machine on a wire ([bus] interface) runs on the real-time clock, not the simulation clock")]
    WireNeedsRealTime,
}

/// How to run a controller (`run`, `controller::Background::start`).
pub struct RunOptions {
    /// The namespace of its shared-memory services: a second controller needs its own.
    pub ns: Namespace,
    /// How the supervisor starts the script processes.
    pub launcher: ScriptLauncher,
    /// End when no task runs any more (`luamotion run`); otherwise run until interrupted.
    pub exit_when_tasks_end: bool,
    /// Where `SaveUserTable` keeps its file.
    pub data_dir: PathBuf,
    /// A CSV file for every cycle's axis data (`--trace`).
    pub trace: Option<PathBuf>,
    /// The scope's channels from the first cycle (`run --scope`): `calls::scope::Var`
    /// codes. Tools can ask for others later through the ring.
    pub scope: Vec<u32>,
    /// Set by the caller to shut the controller down (the soak test ends its run so).
    pub stop: Option<Arc<AtomicBool>>,
    /// The RT thread's end of a console (`console::channel`): the Modbus server's orders.
    pub console: Option<ConsoleInbox>,
    /// Real time, or the simulation clock (`run --clock sim`).
    pub clock: Clock,
    /// On the simulation clock: the outside inputs to apply at cycle boundaries (`replay`).
    pub inputs: Option<crate::replay::Feed>,
}

impl RunOptions {
    /// A controller that runs until it is stopped, on the real-time clock, without a
    /// trace, a scope, a console or recorded inputs: what `serve`, the DRL console and the
    /// soak start from.
    pub fn serving(ns: Namespace, launcher: ScriptLauncher, data_dir: PathBuf) -> Self {
        RunOptions {
            ns,
            launcher,
            exit_when_tasks_end: false,
            data_dir,
            trace: None,
            scope: Vec::new(),
            stop: None,
            console: None,
            clock: Clock::RealTime,
            inputs: None,
        }
    }
}

/// What a finished run leaves.
pub struct RunReport {
    /// How each task's program ended, in the order they ended.
    pub tasks: Vec<TaskReport>,
    /// The cycles' timing and counts.
    pub stats: CycleStats,
    /// The stop signal that ended the run, if one did.
    pub interrupted: Option<i32>,
}

/// Runs a controller until its tasks end or it is interrupted.
pub fn run(config: MachineConfig, options: RunOptions) -> Result<RunReport, ControllerError> {
    crate::signals::install();
    let ns = options.ns.clone();
    ipc::claim_namespace(&ns)?;
    let result = run_claimed(config, options);
    ipc::remove_namespace_files(&ns);
    result
}

/// The machine's EtherCAT network: in memory, started here (a failed start-up leaves
/// the controller up, in Fail, as `ScanNetwork` can retry it); or planned for the wire of
/// `[bus] interface`, whose start-up (`start_wire`) must succeed before the first cycle.
fn bus(config: &MachineConfig, clock: Clock) -> Result<(Network, Option<WireStart>), ControllerError> {
    let mut network = Network::for_machine(config);
    let Some(interface) = &config.bus.interface else {
        if let Err(e) = network.start(config.period_ns()) {
            tracing::error!("EtherCAT start-up stopped in {:?}: {e}", network.state());
        }
        return Ok((network, None));
    };
    if clock != Clock::RealTime {
        return Err(ControllerError::WireNeedsRealTime);
    }
    let plan = maindevice::Plan::new(&mut network, config.period_ns())
        .map_err(|error| ControllerError::Plan { interface: interface.clone(), error })?;
    Ok((network, Some(WireStart { interface: interface.clone(), plan })))
}

/// A wire to bring up: where, and what it must carry.
struct WireStart {
    interface: String,
    plan: maindevice::Plan,
}

/// Brings the segment to Op, on this thread (not the RT thread, whose CPU the master's
/// threads would inherit). They carry the cycle's frames one SCHED_FIFO priority below the
/// RT thread, which hands them its images and so must come first.
fn start_wire(wire: WireStart, config: &MachineConfig, slaves: usize) -> Result<maindevice::WireBus, ControllerError> {
    let WireStart { interface, plan } = wire;
    let priority = config.rt.priority.saturating_sub(1);
    let bus = maindevice::WireBus::start(&interface, plan, config.period_ns(), priority)
        .map_err(|error| ControllerError::Wire { interface: interface.clone(), error })?;
    tracing::info!("EtherCAT on {interface}: {slaves} slaves in Op");
    Ok(bus)
}

fn run_claimed(config: MachineConfig, options: RunOptions) -> Result<RunReport, ControllerError> {
    ipc::room::check_room()?;
    std::fs::create_dir_all(&options.data_dir)
        .map_err(|source| ControllerError::DataDir { path: options.data_dir.clone(), source })?;
    let (trace, trace_writer) = match &options.trace {
        Some(path) => {
            let (sender, writer) =
                trace::start(path, &config).map_err(|source| ControllerError::Trace { path: path.clone(), source })?;
            (Some(sender), Some(writer))
        }
        None => (None, None),
    };
    let (network, wire) = bus(&config, options.clock)?;
    let slaves = network.slaves().len();
    let kernel = Kernel::new(&config, &network);
    let (core_link, supervisor_end) =
        tasks::link().map_err(|e| ControllerError::RtStart(format!("the supervisor's bell: {e}")))?;
    let tasks = Tasks::new(&config.tasks, config.period_ns(), core_link);
    let machine = Machine::new(network, kernel, tasks, config.period_ns()).with_position_triggers(&config);
    let task_ids: Vec<u8> = config.tasks.iter().map(|t| t.id).collect();

    let control = Arc::new(RtControl::default());
    let (ready_tx, ready_rx) = mpsc::channel::<Result<realtime::Granted, ControllerError>>();
    // The wire comes up once the RT thread has rebuilt the memory in huge pages: that stalls
    // the whole process, longer than the drives' process data watchdog allows.
    let (pages_tx, pages_rx) = mpsc::channel::<()>();
    let (wire_tx, wire_rx) = mpsc::channel::<Result<maindevice::WireBus, ControllerError>>();
    let on_wire = wire.is_some();
    let rt = {
        let (ns, control, rt_config) = (options.ns.clone(), control.clone(), config.rt.clone());
        // Read here, before the RT thread pins itself: the CPUs the scripts will run on.
        let task_cpus = realtime::task_cpus(&rt_config);
        let console = options.console;
        let identity = config.identity.clone();
        let (period_ns, scope_codes) = (config.period_ns(), options.scope);
        let (clock, task_configs, feed) = (options.clock, config.tasks.clone(), options.inputs);
        std::thread::Builder::new()
            .name("rt-cycle".into())
            .stack_size(huge_pages::RT_STACK)
            .spawn(move || {
                // Held until the RT thread ends, with the controller.
                let idle_poll = realtime::IdlePoll::hold(&rt_config);
                let granted =
                    realtime::Granted { idle_poll: idle_poll.is_some(), ..realtime::setup_current_thread(&rt_config) };
                let mut endpoint = match CoreEndpoint::create(&ns, &task_ids) {
                    Ok(endpoint) => endpoint,
                    Err(e) => {
                        let _ = ready_tx.send(Err(e.into()));
                        return None;
                    }
                };
                // On the simulation clock a turn is one task's wake: no hop in between.
                if clock == Clock::RealTime {
                    let waker_config = rt_config.clone();
                    let setup = move |cpu| realtime::setup_waker_thread(&waker_config, cpu);
                    if let Err(e) = endpoint.hand_wakes_to_threads(&ns, &task_cpus, setup) {
                        let _ = ready_tx.send(Err(e.into()));
                        return None;
                    }
                }
                // After the endpoint (whose services are the room check's first concern), before
                // any task starts: SetHMIScope finds the ring.
                let scope = match ipc::scope::ScopeRing::create(&ns, period_ns, &scope_codes) {
                    Ok(ring) => ScopeSampler::new(ring),
                    Err(e) => {
                        let _ = ready_tx.send(Err(e.into()));
                        return None;
                    }
                };
                // Before any task can start: what GetModelNum and GetSerialNum report.
                endpoint.shared().set_identity(&identity.model, &identity.serial);
                let lockstep = match clock {
                    Clock::RealTime => None,
                    Clock::Sim { speed } => Some(Lockstep::new(&task_configs, speed, &endpoint).with_feed(feed)),
                };
                let mut work = cycle::CycleWork::new(machine, endpoint)
                    .with_trace(trace)
                    .with_scope(Some(scope))
                    .with_console(console);
                // Once everything the cycles use is allocated, and before the controller is
                // announced: the first cycle follows the word at once.
                let huge_pages = rt_config.huge_pages.then(huge_pages::back_with_huge_pages);
                if on_wire {
                    let _ = pages_tx.send(());
                    match wire_rx.recv() {
                        Ok(Ok(bus)) => {
                            let lost_after = maindevice::WireBus::lost_after_cycles(period_ns);
                            work.machine_mut().network.put_on_wire(Box::new(bus), lost_after);
                        }
                        Ok(Err(e)) => {
                            let _ = ready_tx.send(Err(e));
                            return None;
                        }
                        Err(_) => return None,
                    }
                }
                let _ = ready_tx.send(Ok(granted));
                Some(cycle::run(work, control, granted, huge_pages, lockstep))
            })
            .map_err(|e| ControllerError::RtStart(e.to_string()))?
    };
    if let Some(wire) = wire
        && pages_rx.recv().is_ok()
    {
        let _ = wire_tx.send(start_wire(wire, &config, slaves));
    }
    let granted = ready_rx.recv().map_err(|_| ControllerError::RtStart("no word from the RT thread".into()))??;
    tracing::info!(?granted, cycle_us = config.cycle_us, axes = config.axes.len(), ns = %options.ns, "controller up");
    // The supervisor's thread takes the scripts' CPUs, and so does every script process
    // it starts from now on (the RT thread pinned only itself).
    if let Some(cpus) = realtime::script_cpus(&config.rt) {
        if realtime::confine_current_thread(&cpus) {
            tracing::info!(?cpus, "script processes run off the RT thread's CPU");
        } else {
            tracing::warn!(?cpus, "cannot keep the script processes to these CPUs; they run anywhere");
        }
    }

    let mut supervisor = Supervisor::new(
        options.ns.clone(),
        options.launcher.clone(),
        options.data_dir.clone(),
        &config.tasks,
        supervisor_end,
        config.rt.script_pool,
    )?;
    let mut interrupted = None;
    let mut failure = None;
    loop {
        supervisor.poll();
        // Ctrl-C, SIGTERM, SIGHUP, SIGQUIT: shut down in order.
        if let Some(signal) = crate::signals::received() {
            interrupted = Some(signal);
            break;
        }
        if options.stop.as_ref().is_some_and(|stop| stop.load(Ordering::Acquire)) {
            break;
        }
        let idle = control.cycle() > 0 && control.active_tasks() == 0 && supervisor.running() == 0;
        if options.exit_when_tasks_end && idle {
            break;
        }
        if rt.is_finished() {
            failure = Some(ControllerError::RtDied("the cycle ended on its own".into()));
            break;
        }
        supervisor.wait();
    }

    stop_tasks(&mut supervisor, &control);
    control.request_shutdown();
    let stats = match rt.join() {
        Ok(Some(stats)) => stats,
        Ok(None) => return Err(ControllerError::RtDied("the RT thread ended before its first cycle".into())),
        Err(panic) => return Err(ControllerError::RtDied(panic_message(&panic))),
    };
    supervisor.poll();
    if let Some(writer) = trace_writer {
        let (dropped, written) = writer.finish();
        let path = options.trace.clone().unwrap_or_default();
        let rows = written.map_err(|source| ControllerError::Trace { path, source })?;
        tracing::info!(rows, dropped, "trace written");
    }
    if let Some(e) = failure {
        return Err(e);
    }
    Ok(RunReport { tasks: supervisor.into_reports(), stats, interrupted })
}

/// The end of a run: every task is stopped as `StopAllTask` stops them (their motion reacts,
/// no alarm: the user asked for it), then whatever process is left is killed.
fn stop_tasks(supervisor: &mut Supervisor, control: &RtControl) {
    supervisor.refuse_starts();
    control.request_stop_tasks();
    let since = std::time::Instant::now();
    while (supervisor.running() > 0 || control.active_tasks() > 0) && since.elapsed() < STOP_PATIENCE {
        supervisor.poll();
        supervisor.wait();
    }
    supervisor.stop_all();
}

/// A controller running in a thread of this process (`luamotion soak`, `luamotion serve`).
pub struct Background {
    thread: std::thread::JoinHandle<Result<RunReport, ControllerError>>,
    stop: Arc<AtomicBool>,
}

/// How long a controller may take to come up.
const START_PATIENCE: Duration = Duration::from_secs(10);

impl Background {
    /// Starts a controller and returns once programs can attach to it. A namespace that
    /// another live controller holds is refused here, with its pid, before the thread
    /// starts: that controller being ready must not pass for this one.
    pub fn start(config: MachineConfig, mut options: RunOptions) -> Result<Self, ControllerError> {
        let stop = options.stop.get_or_insert_with(Default::default).clone();
        let ns = options.ns.clone();
        ipc::claim_namespace(&ns)?;
        let thread = std::thread::spawn(move || run(config, options));
        let since = std::time::Instant::now();
        loop {
            // Ours, should another controller have claimed the namespace since.
            let ours = ipc::controller_pid(&ns)? == Some(std::process::id());
            if ours && ipc::controller_ready(&ns)? {
                return Ok(Background { thread, stop });
            }
            if thread.is_finished() || since.elapsed() > START_PATIENCE {
                stop.store(true, Ordering::Release);
                return Err(match thread.join() {
                    Ok(Err(e)) => e,
                    Ok(Ok(_)) => ControllerError::RtStart("the controller ended at once".into()),
                    Err(panic) => ControllerError::RtDied(panic_message(&panic)),
                });
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Shuts the controller down in order and returns its report.
    pub fn stop(self) -> Result<RunReport, ControllerError> {
        self.stop.store(true, Ordering::Release);
        self.join()
    }

    /// Waits for the controller to end (on Ctrl-C or SIGTERM).
    pub fn join(self) -> Result<RunReport, ControllerError> {
        self.thread.join().map_err(|panic| ControllerError::RtDied(panic_message(&panic)))?
    }
}

fn panic_message(panic: &Box<dyn std::any::Any + Send>) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "panic".into())
}

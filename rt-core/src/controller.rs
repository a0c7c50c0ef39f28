//! A controller from start to shutdown: claim the namespace, bring the EtherCAT network
//! up, start the RT thread, start the tasks, watch them, shut down in order.

use std::sync::{Arc, mpsc};
use std::time::Duration;

use ipc::{CoreEndpoint, Namespace};

use crate::config::MachineConfig;
use crate::cycle::{self, CycleStats, Machine, RtControl};
use crate::ecat::Network;
use crate::motion::Kernel;
use crate::realtime;
use crate::supervisor::{ScriptLauncher, Supervisor, TaskReport};

#[derive(Debug, thiserror::Error)]
pub enum ControllerError {
    #[error(transparent)]
    Ipc(#[from] ipc::IpcError),
    #[error("the RT thread failed to start: {0}")]
    RtStart(String),
    #[error("the RT thread died: {0}")]
    RtDied(String),
    #[error("cannot start task {task}: {source}")]
    TaskStart { task: u8, source: std::io::Error },
}

pub struct RunOptions {
    pub ns: Namespace,
    pub launcher: ScriptLauncher,
    /// End when every started task has ended (`luamotion run`); otherwise run until interrupted.
    pub exit_when_tasks_end: bool,
}

pub struct RunReport {
    pub tasks: Vec<TaskReport>,
    pub stats: CycleStats,
    pub interrupted: bool,
}

/// Runs a controller until its tasks end or it is interrupted.
pub fn run(config: MachineConfig, options: RunOptions) -> Result<RunReport, ControllerError> {
    let ns = options.ns.clone();
    ipc::claim_namespace(&ns)?;
    let result = run_claimed(config, options);
    ipc::remove_namespace_files(&ns);
    result
}

fn run_claimed(config: MachineConfig, options: RunOptions) -> Result<RunReport, ControllerError> {
    let mut network = Network::new(&config.axes);
    if let Err(e) = network.start(config.period_ns()) {
        tracing::error!("EtherCAT start-up stopped in {:?}: {e}", network.state());
    }
    let kernel = Kernel::new(&config, &network);
    let machine = Machine::new(network, kernel, config.period_ns());
    let task_ids: Vec<u8> = config.tasks.iter().map(|t| t.id).collect();

    let control = Arc::new(RtControl::default());
    let (ready_tx, ready_rx) = mpsc::channel();
    let rt = {
        let (ns, control, rt_config) = (options.ns.clone(), control.clone(), config.rt.clone());
        std::thread::Builder::new()
            .name("rt-cycle".into())
            .spawn(move || {
                let granted = realtime::setup_current_thread(&rt_config);
                crate::rt_alloc::claim_pool_for_this_thread();
                let endpoint = match CoreEndpoint::create(&ns, &task_ids) {
                    Ok(endpoint) => endpoint,
                    Err(e) => {
                        let _ = ready_tx.send(Err(e.to_string()));
                        return None;
                    }
                };
                let _ = ready_tx.send(Ok(granted));
                Some(cycle::run(machine, endpoint, control, granted))
            })
            .map_err(|e| ControllerError::RtStart(e.to_string()))?
    };
    let granted = ready_rx
        .recv()
        .map_err(|_| ControllerError::RtStart("no word from the RT thread".into()))?
        .map_err(ControllerError::RtStart)?;
    tracing::info!(?granted, cycle_us = config.cycle_us, axes = config.axes.len(), ns = %options.ns, "controller up");

    let mut supervisor = Supervisor::new(options.ns.clone(), options.launcher.clone())?;
    let mut started = 0;
    let mut failure = None;
    for task in config.tasks.iter().filter(|t| t.autorun) {
        match supervisor.start(task) {
            Ok(()) => started += 1,
            Err(source) => {
                failure = Some(ControllerError::TaskStart { task: task.id, source });
                break;
            }
        }
    }

    let mut interrupted = false;
    while failure.is_none() {
        supervisor.poll();
        // Ctrl-C (SIGINT) or SIGTERM: shut down in order.
        if ipc::termination_requested() {
            interrupted = true;
            break;
        }
        if options.exit_when_tasks_end && started > 0 && supervisor.running() == 0 {
            break;
        }
        if rt.is_finished() {
            failure = Some(ControllerError::RtDied("the cycle ended on its own".into()));
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }

    supervisor.stop_all(Duration::from_millis(500));
    control.request_shutdown();
    let stats = match rt.join() {
        Ok(Some(stats)) => stats,
        Ok(None) => return Err(ControllerError::RtDied("the RT thread ended before its first cycle".into())),
        Err(panic) => return Err(ControllerError::RtDied(panic_message(&panic))),
    };
    if let Some(e) = failure {
        return Err(e);
    }
    Ok(RunReport { tasks: supervisor.into_reports(), stats, interrupted })
}

fn panic_message(panic: &Box<dyn std::any::Any + Send>) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "panic".into())
}

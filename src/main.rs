//! `luamotion`: the command line. A thin edge over `rt-core` (the controller) and
//! `script-host` (the script processes it starts by re-running this binary).

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};
use config::{MachineConfig, TaskConfig};
use ipc::Namespace;
use rt_core::sim_clock::{Clock, Speed};
use rt_core::supervisor::{Outcome, ScriptLauncher};
use schema::MAX_TASKS;

mod check_cli;
mod drl_cli;
mod lsp;
mod replay_cli;
mod scope;
mod soak;
mod stdout;
mod subdevices_cli;
mod test_runner;
mod tools;
mod web;

#[derive(Parser)]
#[command(name = "luamotion", version, about = "A controller runtime for motion applications written in Lua")]
struct Cli {
    /// Log more (-v: info, -vv: debug).
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    verbose: u8,
    #[command(subcommand)]
    command: Cmd,
}

/// The clock of `run`.
#[derive(clap::Args)]
struct ClockArgs {
    /// `realtime` (one cycle per period) or `sim`: the cycles in lockstep with the
    /// programs, as fast as they allow, the same run after run (a trace digest at the end).
    #[arg(long, value_enum, default_value_t = ClockKind::Realtime)]
    clock: ClockKind,
    /// With `--clock sim` or `--replay`: at most N times real time, or `max` (the default).
    #[arg(long)]
    speed: Option<Speed>,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum ClockKind {
    /// One cycle per period of the wall clock.
    Realtime,
    /// The cycles in lockstep with the programs, at most `--speed` times real time.
    Sim,
}

impl ClockArgs {
    fn clock(&self) -> Clock {
        match self.clock {
            ClockKind::Realtime => Clock::RealTime,
            ClockKind::Sim => Clock::Sim { speed: self.speed.unwrap_or(Speed::Max) },
        }
    }
}

#[derive(Subcommand)]
enum Cmd {
    /// Start a controller and run Lua programs, one script process each.
    Run {
        #[command(flatten)]
        controller: ControllerArgs,
        /// Write every cycle's reference, feedback and status of the first 8 axes to this CSV file.
        #[arg(long)]
        trace: Option<PathBuf>,
        /// Serve the live web view at this port (0: a free one) on the machine file's `[web]
        /// bind`, 127.0.0.1; its axis commands go through task slot `[ascii] agent_task`.
        #[arg(long)]
        http: Option<u16>,
        /// Record the scope's variables (--scope-vars) every cycle of the run into this
        /// .csv, .svg or .png file (repeat for several).
        #[arg(long)]
        scope: Vec<PathBuf>,
        #[command(flatten)]
        scope_options: scope::ScopeOptions,
        #[command(flatten)]
        clock: ClockArgs,
        #[command(flatten)]
        inputs: replay_cli::InputArgs,
        /// Start without checking the programs first (`luamotion check`).
        #[arg(long)]
        no_check: bool,
        /// Programs to run as tasks 0, 1, 2, ...
        scripts: Vec<PathBuf>,
    },
    /// Check Lua programs against the API before they run: unknown names, argument counts
    /// and types, callbacks, the sandbox; exit code 1 on errors.
    Check(check_cli::CheckArgs),
    /// A language server over stdio for any editor: the check's findings as you type,
    /// completion, hover and signature help from the registry.
    Lsp,
    /// Run Lua test programs, each on a fresh controller, several at a time: a summary,
    /// JUnit XML, and exit code 1 when any fails.
    Test(test_runner::TestArgs),
    /// Record variables of a running controller (`run` or `serve`) every cycle into CSV,
    /// SVG or PNG: decimation, a trigger, pre- and post-trigger samples.
    Scope(scope::ScopeArgs),
    /// Start a controller that runs until stopped, with the Modbus TCP server and DRL
    /// program control (DXMC appendix A).
    Serve(drl_cli::ServeArgs),
    /// Control DRL projects over Modbus TCP: open, run, stop, pause, step, breakpoints, status.
    Drl(drl_cli::DrlArgs),
    /// Show the task table of a running controller: state, process, CPU, watchdog, last alarm.
    Tasks {
        /// Namespace of the controller to look at.
        #[arg(long, default_value = "luamotion")]
        ns: String,
    },
    /// Follow a running controller's events: SendEvent, SendMsgEvent and alarms.
    Events {
        /// Namespace of the controller to look at.
        #[arg(long, default_value = "luamotion")]
        ns: String,
        /// Stop after this many events.
        #[arg(long)]
        count: Option<usize>,
    },
    /// Serve the machine file's drives and I/O slaves as an EtherCAT segment on a network
    /// interface (raw socket: CAP_NET_RAW), for a master on the other end of the wire.
    Subdevices(subdevices_cli::SubdevicesArgs),
    /// Soak-test the IPC and the cycle: latency and jitter under N scripts, beside this
    /// machine's floors measured in the same run.
    Soak(soak::SoakArgs),
    /// (internal) One soak worker process.
    #[command(hide = true)]
    SoakWorker {
        /// Namespace of the soak's controller.
        #[arg(long)]
        ns: String,
        /// The task slot this worker attaches to.
        #[arg(long)]
        task: u8,
        /// The axis it commands.
        #[arg(long)]
        axis: u8,
        /// How long it sends commands, ms.
        #[arg(long)]
        duration_ms: u64,
        /// The soak's process: the worker ends when it is gone.
        #[arg(long)]
        controller_pid: u32,
        /// File the worker writes its timings to.
        #[arg(long)]
        out: PathBuf,
    },
    /// (internal) The echoing side of the soak's transport floor.
    #[command(hide = true)]
    SoakPong {
        /// Namespace of the soak's floor services.
        #[arg(long)]
        ns: String,
        /// Sleep on a futex word in a task table, as a task does, instead of an iceoryx2 event.
        #[arg(long)]
        futex: bool,
    },
    /// Print the API reference generated from the registry.
    Api {
        /// Which reference.
        #[arg(value_enum)]
        format: ApiFormat,
    },
    /// (internal) One script process; the controller starts these.
    #[command(hide = true)]
    Script {
        /// Namespace of the controller.
        #[arg(long)]
        ns: String,
        /// The task id (slot) this process runs.
        #[arg(long, required_unless_present = "pool")]
        task: Option<u8>,
        /// The controller's process: the script ends when it is gone.
        #[arg(long)]
        controller_pid: u32,
        /// Memory limit of the Lua VM, MiB.
        #[arg(long, default_value_t = 64)]
        memory_limit_mib: u32,
        /// The controller's data directory (user table).
        #[arg(long)]
        data_dir: PathBuf,
        /// StartTaskFunc: the function to run after the program's top level.
        #[arg(long)]
        entry: Option<String>,
        /// Where FreePort.Eth.OpenAsServer listens (the machine file's `[freeport] bind`).
        #[arg(long, default_value = "127.0.0.1")]
        freeport_bind: std::net::IpAddr,
        /// Where START_ASCII_AGENT listens, HOST:PORT.
        #[arg(long, default_value = script_host::bindings::DEFAULT_USER_ASCII)]
        ascii_user: String,
        /// On the simulation clock: write FreePort.Eth's inputs into DIR/task-<id>.txt.
        #[arg(long, value_name = "DIR")]
        freeport_record: Option<PathBuf>,
        /// On the simulation clock: FreePort.Eth's inputs are this record's, without sockets.
        #[arg(long, value_name = "FILE", conflicts_with = "freeport_record")]
        freeport_replay: Option<PathBuf>,
        /// Wait on this place of the pool's board until the core hands it a task, ready to
        /// run it at once: the controller's pool of started script processes.
        #[arg(long, value_name = "PLACE", conflicts_with_all = ["task", "program", "entry"])]
        pool: Option<usize>,
        /// The Lua program.
        #[arg(required_unless_present = "pool")]
        program: Option<PathBuf>,
    },
}

/// What every command that starts a controller takes.
#[derive(clap::Args, Debug)]
pub struct ControllerArgs {
    /// Machine file (TOML); without it, the built-in machine: 4 axes on D1 drives, mm, 1 ms.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Namespace of this controller's IPC resources (controllers side by side need different ones).
    #[arg(long, default_value = "luamotion")]
    ns: String,
    /// Where the user table, DH and the DRL projects are kept [default: $XDG_STATE_HOME/luamotion/<ns>].
    #[arg(long)]
    data_dir: Option<PathBuf>,
    /// The User ASCII port a task's START_ASCII_AGENT listens on [default: the machine
    /// file's, 4000]; 0 asks the OS for a free one, which the agent prints.
    #[arg(long)]
    ascii_user_port: Option<u16>,
    /// A symlink to serial port 1's pseudo-terminal, made at start and removed at the end
    /// [default: the machine file's `[serial] link`, else none].
    #[arg(long)]
    serial_link: Option<PathBuf>,
}

impl ControllerArgs {
    fn machine(&self) -> Result<MachineConfig> {
        Ok(match &self.config {
            Some(path) => MachineConfig::load(path)?,
            None => MachineConfig::default(),
        })
    }

    /// The namespace of the controller to start. One a live controller holds is refused
    /// here, with that controller's pid, before anything of the namespace is opened
    /// (serial port 1's socket, the DRL console), whose own errors would come first.
    fn namespace(&self) -> Result<Namespace> {
        let ns = Namespace::new(&self.ns)?;
        ipc::claim_namespace(&ns)?;
        Ok(ns)
    }

    fn data_dir(&self) -> PathBuf {
        self.data_dir.clone().unwrap_or_else(|| default_data_dir(&self.ns))
    }

    /// How the controller starts script processes: this binary's `script`, told where a
    /// User ASCII agent listens (`bind`: the machine file's `[ascii] bind` or `--bind`)
    /// and where FreePort servers do (`[freeport] bind`).
    fn launcher(&self, config: &MachineConfig, bind: &str) -> Result<ScriptLauncher> {
        let port = self.ascii_user_port.unwrap_or(config.ascii.user_port);
        let ip: std::net::IpAddr = bind.parse().with_context(|| format!("the ASCII bind address {bind:?}"))?;
        Ok(ScriptLauncher {
            executable: std::env::current_exe().context("locate the luamotion binary")?,
            subcommand: vec![
                "script".into(),
                "--ascii-user".into(),
                std::net::SocketAddr::new(ip, port).to_string(),
                "--freeport-bind".into(),
                config.freeport.bind.to_string(),
            ],
        })
    }

    /// Opens serial port 1 unless the machine file disables it, and says where it is. A
    /// port that cannot be opened is a warning: the controller runs without it (scripts'
    /// `FreePort.Serial` calls return 10).
    fn serial_port(&self, config: &MachineConfig, sim: Option<serial::SimLine>) -> Option<serial::Port> {
        let s = &config.serial;
        if !s.enabled {
            return None;
        }
        let protocol = serial::protocol::Protocol::from_code(s.protocol.into())?;
        let settings = serial::Settings {
            protocol,
            baud: serial::protocol::BAUDS[s.baud as usize],
            loopback: s.loopback,
            station: config.modbus.station,
            link: self.serial_link.clone().or_else(|| s.link.clone()),
        };
        match serial::Port::open_with(&self.ns, settings, sim) {
            Ok(port) => {
                let link = port.link.as_ref().map(|l| format!(" (link {})", l.display())).unwrap_or_default();
                eprintln!(
                    "serial port 1: {}{link}, protocol {:#04x} ({} {:?}), {} baud",
                    port.path.display(),
                    protocol.code,
                    protocol.frame,
                    protocol.kind,
                    serial::protocol::BAUDS[s.baud as usize]
                );
                Some(port)
            }
            Err(e) => {
                tracing::warn!("serial port 1 is not available: {e}");
                None
            }
        }
    }
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum ApiFormat {
    /// Markdown reference (docs/api.md).
    Markdown,
    /// lua-language-server annotations (scripts/luamotion.d.lua).
    Lua,
    /// A `.luacheckrc` with the API's globals, for luacheck.
    Luacheckrc,
}

/// The commands that run a controller in this process, whose heap is then kept as the RT
/// thread wants it (`rt_core::huge_pages::keep_one_heap`).
const HOSTING_COMMANDS: [&str; 4] = ["run", "test", "serve", "soak"];

/// Whether the command line names one of `HOSTING_COMMANDS` (the first word not an option:
/// the only options before the command are flags). Read before clap parses the line, whose
/// allocations, freed, would sit in the heap's first page and be reused for the
/// controller's data, outside its huge pages.
fn hosts_a_controller(args: impl IntoIterator<Item = std::ffi::OsString>) -> bool {
    let command = args.into_iter().skip(1).find(|arg| !arg.to_string_lossy().starts_with('-'));
    command.is_some_and(|command| HOSTING_COMMANDS.iter().any(|hosting| command == *hosting))
}

fn main() -> ExitCode {
    if hosts_a_controller(std::env::args_os()) {
        // Before any thread starts.
        rt_core::huge_pages::keep_one_heap();
    }
    let cli = Cli::parse();
    init_logging(cli.verbose);
    // plotters lays text out with it (the soak's report and the scope's plots).
    scope::register_font();
    let result = match cli.command {
        Cmd::Run { controller, trace, http, scope, scope_options, clock, inputs, no_check, scripts } => {
            inputs.clock(clock.clock(), clock.speed).and_then(|clock| {
                run(&controller, trace, http, (scope, scope_options), (clock, inputs), (!no_check, scripts))
            })
        }
        Cmd::Check(args) => check_cli::check(args),
        Cmd::Lsp => lsp::lsp(),
        Cmd::Scope(args) => scope::scope(args),
        Cmd::Test(args) => test_runner::test(args),
        Cmd::Tasks { ns } => tools::tasks(&ns),
        Cmd::Serve(args) => drl_cli::serve(args),
        Cmd::Drl(args) => drl_cli::drl(args),
        Cmd::Soak(args) => soak::soak(args),
        Cmd::Subdevices(args) => subdevices_cli::subdevices(args),
        Cmd::SoakWorker { ns, task, axis, duration_ms, controller_pid, out } => {
            soak::worker::run(soak::worker::WorkerArgs { ns, task, axis, duration_ms, controller_pid, out })
                .map(|()| ExitCode::SUCCESS)
        }
        Cmd::SoakPong { ns, futex } => soak::floor::pong(&ns, futex).map(|()| ExitCode::SUCCESS),
        Cmd::Events { ns, count } => tools::events(&ns, count),
        Cmd::Api { format } => {
            let text = match format {
                ApiFormat::Markdown => api::docs::markdown(),
                ApiFormat::Lua => api::docs::lua_meta(),
                ApiFormat::Luacheckrc => check::luacheckrc::generate(&check::Environment::new()),
            };
            stdout::out!("{text}").map(|()| ExitCode::SUCCESS).map_err(Into::into)
        }
        Cmd::Script {
            ns,
            task,
            controller_pid,
            memory_limit_mib,
            data_dir,
            entry,
            freeport_bind,
            ascii_user,
            freeport_record,
            freeport_replay,
            pool,
            program,
        } => {
            let freeport_inputs = match (freeport_record, freeport_replay) {
                (Some(dir), _) => script_host::FreePortInputs::Record(dir),
                (None, Some(file)) => script_host::FreePortInputs::Replay(file),
                (None, None) => script_host::FreePortInputs::Live,
            };
            let ns = match Namespace::new(&ns) {
                Ok(ns) => ns,
                Err(e) => {
                    eprintln!("error: {e}");
                    return ExitCode::FAILURE;
                }
            };
            // clap requires both unless `--pool` is given, which excludes them.
            let (Some(task), Some(program)) = (task, program) else {
                let place = pool.unwrap_or_default();
                let pooled = script_host::PoolArgs {
                    ns,
                    place,
                    controller_pid,
                    data_dir,
                    user_ascii: ascii_user,
                    freeport_bind,
                    freeport_inputs,
                };
                return script(script_host::run_pooled(pooled));
            };
            let args = script_host::ScriptArgs {
                ns,
                task,
                controller_pid,
                memory_limit_mib,
                data_dir,
                entry,
                program,
                user_ascii: ascii_user,
                freeport_bind,
                freeport_inputs,
            };
            Ok(script(script_host::run(args)))
        }
    };
    result.unwrap_or_else(|e| {
        // The reader of the output has what it wanted (`luamotion api lua | head`).
        if stdout::closed(&e) {
            return exit_code_of_signal(libc::SIGPIPE);
        }
        eprintln!("error: {e:#}");
        ExitCode::FAILURE
    })
}

fn init_logging(verbose: u8) {
    let default = match verbose {
        0 => "warn",
        1 => "info",
        _ => "debug",
    };
    // ethercrab says "failed to claim receiving frame" as an error for every frame that
    // matches nothing in flight; the master counts those (`luamotion tasks`), so they
    // show from -vv on.
    let frames = if verbose >= 2 { "" } else { ",ethercrab::pdu_loop::frame_element=off" };
    let filter = tracing_subscriber::EnvFilter::try_from_default_env()
        .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(format!("{default}{frames}")));
    let ansi = std::io::IsTerminal::is_terminal(&std::io::stderr());
    tracing_subscriber::fmt().with_env_filter(filter).with_writer(std::io::stderr).with_ansi(ansi).init();
    ipc::quiet_transport_logs();
}

/// `$XDG_STATE_HOME/luamotion/<ns>`, else `~/.local/state/luamotion/<ns>`.
fn default_data_dir(ns: &str) -> PathBuf {
    let state = std::env::var_os("XDG_STATE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|home| PathBuf::from(home).join(".local").join("state")));
    state.unwrap_or_else(std::env::temp_dir).join("luamotion").join(ns)
}

fn run(
    controller: &ControllerArgs,
    trace: Option<PathBuf>,
    http: Option<u16>,
    (scope, scope_options): (Vec<PathBuf>, scope::ScopeOptions),
    (clock, input_args): (Clock, replay_cli::InputArgs),
    (check_first, scripts): (bool, Vec<PathBuf>),
) -> Result<ExitCode> {
    // Before anything starts: a name the scope does not know is the operator's first error.
    let scope_codes = if scope.is_empty() { Vec::new() } else { scope::Reader::codes(&scope_options)? };
    let mut config = controller.machine()?;
    if scripts.len() > MAX_TASKS {
        bail!("at most {MAX_TASKS} programs (HMPL tasks 0..63)");
    }
    for (id, program) in scripts.into_iter().enumerate() {
        let id = id as u8;
        config.tasks.retain(|t| t.id != id);
        config.tasks.push(TaskConfig::autorun(id, program));
    }
    config.tasks.sort_by_key(|t| t.id);
    config.validate()?;
    // Before anything moves: a program the check refuses does not start at all.
    let programs = config.tasks.iter().filter(|t| !t.external).map(|t| t.program.clone());
    if check_first && check_cli::refuses_to_start(programs) {
        return Ok(ExitCode::from(1));
    }
    let config_period_s = config.period_ns() as f64 * 1e-9;
    let ns = controller.namespace()?;

    let mut launcher = controller.launcher(&config, &config.ascii.bind)?;
    // An external task's program is the user's to start: `run` would end at once.
    if !config.tasks.iter().any(|t| t.autorun && !t.external) {
        eprintln!(
            "error: nothing to run: name a program (`luamotion run a.lua`) or give a machine file with a task \
             that has `autorun = true` and is not `external`; `luamotion serve` keeps a controller running \
             without programs"
        );
        return Ok(ExitCode::from(2));
    }
    let data_dir = controller.data_dir();
    let inputs = input_args.prepare(clock)?;
    if let Some(inputs) = &inputs {
        launcher.subcommand.extend(inputs.script_args());
    }
    // Before the tasks start, so their first FreePort.Serial call finds it.
    let mut serial = controller.serial_port(&config, inputs.as_ref().map(|i| i.serial()));
    let scope_stop = Arc::new(AtomicBool::new(false));
    let recorder = (!scope.is_empty()).then(|| scope::record_run(ns.clone(), scope_options, scope, scope_stop.clone()));
    let options = rt_core::RunOptions {
        ns,
        launcher,
        exit_when_tasks_end: true,
        data_dir,
        trace,
        scope: scope_codes,
        stop: None,
        console: None,
        clock,
        inputs: inputs.as_ref().map(|i| i.feed()),
    };
    let report = match (http, input_args.modbus_port()) {
        (None, None) => rt_core::run(config, options),
        (http, modbus) => {
            let inputs = inputs.as_ref().map(|i| i.inputs.clone());
            let modbus = modbus.map(|port| (port, inputs.clone()));
            run_served(config, options, http, modbus, inputs, serial.take())?
        }
    };
    drop(serial);
    if let Some(inputs) = &inputs {
        inputs.finish()?;
    }
    scope_stop.store(true, Ordering::Release);
    if let Some(recorder) = recorder {
        recorder.join().map_err(|_| anyhow::anyhow!("the scope's reader panicked"))??;
    }
    let report = report?;

    let mut failed = false;
    for task in &report.tasks {
        let name = task.program.display();
        match &task.outcome {
            Outcome::Finished => eprintln!("task {} ({name}): finished", task.id),
            Outcome::Stopped => eprintln!("task {} ({name}): stopped", task.id),
            Outcome::Failed(reason) => {
                failed = true;
                eprintln!("task {} ({name}): failed: {reason}", task.id);
            }
        }
    }
    let stats = &report.stats;
    if let Clock::Sim { .. } = clock {
        let simulated_s = stats.digest.rows() as f64 * config_period_s;
        let wall_s = stats.recorded_wall_ns as f64 * 1e-9;
        eprintln!(
            "simulated {simulated_s:.3} s in {wall_s:.3} s ({:.1}x); trace digest fnv1a64:{:016x} over {} cycles",
            simulated_s / wall_s.max(1e-9),
            stats.digest.value(),
            stats.digest.rows()
        );
    }
    tracing::info!(
        cycles = stats.cycles,
        overruns = stats.overruns,
        lateness_p99_us = stats.lateness.value_at_quantile(0.99) as f64 / 1000.0,
        execution_p99_us = stats.execution.value_at_quantile(0.99) as f64 / 1000.0,
        execution_mean_us = stats.execution.mean() / 1000.0,
        drives_ms = stats.simulation_ns / 1_000_000,
        lockstep_ms = stats.lockstep_ns / 1_000_000,
        rt_cpu_ms = stats.cpu_ns / 1_000_000,
        wall_ms = stats.wall_ns / 1_000_000,
        "cycle statistics"
    );
    Ok(if let Some(signal) = report.interrupted {
        exit_code_of_signal(signal)
    } else if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// `run` with the web view (`--http`) or the Modbus TCP server (`--modbus-port`, with
/// the simulation clock's inputs; serial port 1 then answers Modbus RTU/ASCII with it)
/// beside the controller, until its programs end.
fn run_served(
    mut config: MachineConfig,
    mut options: rt_core::RunOptions,
    http: Option<u16>,
    modbus: Option<(u16, Option<Arc<rt_core::replay::Inputs>>)>,
    sim_inputs: Option<Arc<rt_core::replay::Inputs>>,
    serial: Option<serial::Port>,
) -> Result<Result<rt_core::RunReport, rt_core::ControllerError>> {
    let ns = options.ns.clone();
    let mut console = None;
    if let Some((port, inputs)) = modbus {
        config = config.with_drl_task()?;
        let (orders, inbox) = rt_core::console::channel();
        options.console = Some(inbox);
        let folders = (None, None);
        let (setup, _) = drl_cli::console_setup(&config, &ns, options.data_dir.clone(), orders, folders, inputs)?;
        console = Some((setup, config.modbus.bind.clone(), port, drl_cli::modbus_limits(&config)));
    }
    if http.is_some() {
        // The web view's commands need a task slot of their own: the ASCII agent's.
        config = config.with_ascii_task()?;
    }
    let (agent_task, data_dir) = (config.ascii.agent_task, options.data_dir.clone());
    let web_config = config.web.clone();
    let controller = rt_core::controller::Background::start(config, options)?;
    let servers = (|| -> Result<_> {
        let modbus = console.map(|(setup, bind, port, limits)| drl::Server::start(setup, &bind, port, limits));
        let modbus = modbus.transpose()?;
        let web = match http {
            Some(port) => {
                let (agent, thread) = drl::ascii::start_agent(ns.clone(), agent_task, data_dir)?;
                Some((web::WebView::start(ns, (&web_config, port), agent, None, sim_inputs)?, thread))
            }
            None => None,
        };
        Ok((modbus, web))
    })();
    let (modbus, web) = match servers {
        Ok(servers) => servers,
        Err(e) => {
            let _ = controller.stop();
            return Err(e);
        }
    };
    if let Some(modbus) = &modbus {
        crate::stdout::sayln!("Modbus TCP on {}", modbus.address);
        if let Some(port) = &serial {
            // Modbus RTU/ASCII on serial port 1: the same register logic, so on the
            // simulation clock its writes are queued and recorded as Modbus TCP's are.
            port.serve_modbus(Box::new(modbus.pdu_handler()));
        }
    }
    if let Some((web, _)) = &web {
        crate::stdout::sayln!("Web view on http://{}/; {}", web.address, web.access_note);
    }
    let report = controller.join();
    // The web view holds the agent's last handle: the agent ends after it.
    if let Some((web, agent_thread)) = web {
        drop(web);
        agent_thread.join();
    }
    // The port holds a handle on the Modbus server's registers: it goes first.
    drop(serial);
    drop(modbus);
    Ok(report)
}

/// The shell's convention: a run ended by signal N exits with 128 + N (130 for Ctrl-C).
fn exit_code_of_signal(signal: i32) -> ExitCode {
    ExitCode::from(128u8.saturating_add(signal as u8))
}

fn script(result: Result<(), script_host::ScriptError>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(script_host::ScriptError::ControllerGone) => ExitCode::from(3),
        // The controller reports the last line a failed program writes to stderr.
        Err(e) => {
            if let script_host::ScriptError::Lua { traceback: Some(traceback), .. } = &e {
                eprintln!("{traceback}");
            }
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    /// The commands that host a controller are told from the command line as clap will
    /// read it, and each is one of `luamotion`'s commands.
    #[test]
    fn hosting_commands_are_told_from_the_command_line() {
        let rows: [(&[&str], bool); 7] = [
            (&["luamotion", "run", "app.lua"], true),
            (&["luamotion", "-vv", "soak", "--scripts", "64"], true),
            (&["luamotion", "test", "-v", "tests/"], true),
            (&["luamotion", "serve", "project"], true),
            (&["luamotion", "script", "--ns", "run"], false),
            (&["luamotion", "--help"], false),
            (&["luamotion"], false),
        ];
        for (line, hosts) in rows {
            assert_eq!(super::hosts_a_controller(line.iter().map(Into::into)), hosts, "{line:?}");
        }
        for command in super::HOSTING_COMMANDS {
            assert!(super::Cli::command().find_subcommand(command).is_some(), "no command {command}");
        }
    }

    /// Every argument of every command, hidden ones included, and every value of an
    /// argument that takes a fixed set, says in `--help` what it is.
    #[test]
    fn every_argument_has_a_description() {
        fn walk(command: &clap::Command, path: &str, missing: &mut Vec<String>) {
            for arg in command.get_arguments() {
                let id = arg.get_id().as_str();
                if matches!(id, "help" | "version") {
                    continue;
                }
                if arg.get_help().is_none() {
                    missing.push(format!("{path} <{id}>"));
                }
                // A flag's true/false are not values a user types.
                let values = if arg.get_action().takes_values() { arg.get_possible_values() } else { Vec::new() };
                for value in values {
                    if value.get_help().is_none() {
                        missing.push(format!("{path} <{id}> value {}", value.get_name()));
                    }
                }
            }
            for sub in command.get_subcommands() {
                if sub.get_about().is_none() {
                    missing.push(format!("{path} {}", sub.get_name()));
                }
                walk(sub, &format!("{path} {}", sub.get_name()), missing);
            }
        }
        let mut missing = Vec::new();
        walk(&super::Cli::command(), "luamotion", &mut missing);
        assert!(missing.is_empty(), "without a description in --help: {missing:#?}");
    }
}

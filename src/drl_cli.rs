//! `luamotion serve`: a controller that runs until stopped, with the Modbus TCP server
//! and DRL program control; `luamotion drl ...`: a Modbus client of the same registers.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use config::MachineConfig;
use drl::codes::{ExecState, Status};
use drl::modbus::Client;
use drl::program::ProgramControl;
use drl::projects::Projects;
use ipc::Namespace;

use crate::stdout::{outln, sayln};

#[derive(clap::Args, Debug)]
pub struct ServeArgs {
    #[command(flatten)]
    controller: crate::ControllerArgs,
    /// Address the Modbus TCP, ASCII and web servers listen on [default: the machine
    /// file's `[modbus] bind`, `[ascii] bind` and `[web] bind`, 127.0.0.1]; 0.0.0.0 serves
    /// every network the host is on.
    #[arg(long)]
    bind: Option<std::net::IpAddr>,
    /// Modbus TCP port [default: the machine file's, 502]; 0 asks the OS for a free one.
    #[arg(long)]
    modbus_port: Option<u16>,
    /// Native ASCII server port (HMPL 22.1) [default: the machine file's, 3999]; 0 asks
    /// the OS for a free one.
    #[arg(long)]
    ascii_port: Option<u16>,
    /// Serve the live web view on this port (on `--bind`'s address, else the machine
    /// file's `[web] bind`); 0 asks the OS for a free one. Without it, no web view.
    #[arg(long)]
    http: Option<u16>,
    /// DRL projects folder [default: the machine file's, else <data dir>/projects].
    #[arg(long)]
    projects: Option<PathBuf>,
    /// Export/import folder [default: the machine file's, else <data dir>/export].
    #[arg(long)]
    export: Option<PathBuf>,
    /// Start without checking the machine file's task programs first (`luamotion check`).
    #[arg(long)]
    no_check: bool,
}

pub fn serve(args: ServeArgs) -> Result<ExitCode> {
    let config = args.controller.machine()?;
    config.validate()?;
    // The programs `StartTask` may start, checked before anything does (DRL projects are
    // checked as they are opened).
    let programs = config.tasks.iter().filter(|t| !t.external).map(|t| t.program.clone());
    if !args.no_check && crate::check_cli::refuses_to_start(programs) {
        return Ok(ExitCode::from(1));
    }
    let config = config.with_drl_task()?.with_ascii_task()?;
    let ns = args.controller.namespace()?;
    let data_dir = args.controller.data_dir();
    let port = args.modbus_port.unwrap_or(config.modbus.port);
    let chosen = |machine_file: &String| args.bind.map_or_else(|| machine_file.clone(), |ip| ip.to_string());
    let bind = chosen(&config.modbus.bind);
    let limits = modbus_limits(&config);
    let ascii_bind = chosen(&config.ascii.bind);
    let web = config::WebConfig { bind: chosen(&config.web.bind), ..config.web.clone() };
    let ascii_port = args.ascii_port.unwrap_or(config.ascii.native_port);
    let ascii_limits = drl::listener::Limits {
        max_connections: config.ascii.max_connections as usize,
        idle_timeout: Duration::from_millis(config.ascii.idle_timeout_ms),
    };
    let agent_task = config.ascii.agent_task;
    let (console, inbox) = rt_core::console::channel();
    let (setup, projects) = console_setup(&config, &ns, data_dir.clone(), console, (args.projects, args.export), None)?;

    // Before the tasks start, so their first FreePort.Serial call finds it.
    let serial = args.controller.serial_port(&config, None);
    let launcher = args.controller.launcher(&config, &ascii_bind)?;
    let options = rt_core::RunOptions {
        console: Some(inbox),
        ..rt_core::RunOptions::serving(ns.clone(), launcher, data_dir.clone())
    };
    let controller = rt_core::controller::Background::start(config, options)?;
    let servers = drl::Server::start(setup, &bind, port, limits).and_then(|modbus| {
        let ascii = drl::ascii::Server::start(
            (ns.clone(), data_dir.clone()),
            agent_task,
            &ascii_bind,
            ascii_port,
            ascii_limits,
        )?;
        Ok((modbus, ascii))
    });
    let (server, ascii) = match servers {
        Ok(servers) => servers,
        Err(e) => {
            let _ = controller.stop();
            return Err(e.into());
        }
    };
    let web = match args.http {
        Some(http_port) => {
            match crate::web::WebView::start(
                ns,
                (&web, http_port),
                ascii.agent(),
                Some(Box::new(server.pdu_handler())),
                None,
            ) {
                Ok(web) => Some(web),
                Err(e) => {
                    drop((ascii, server));
                    let _ = controller.stop();
                    return Err(e);
                }
            }
        }
        None => None,
    };
    if let Some(port) = &serial {
        // Modbus RTU on the serial port: the same register logic as Modbus TCP.
        port.serve_modbus(Box::new(server.pdu_handler()));
    }
    sayln!("Modbus TCP on {}; DRL projects in {}", server.address, projects.dir.display());
    sayln!("Native ASCII on {}; task {agent_task} carries out its commands", ascii.address);
    if let Some(web) = &web {
        sayln!("Web view on http://{}/; {}", web.address, web.access_note);
    }
    // The controller ends on Ctrl-C or SIGTERM; the servers go with it, the serial port
    // before the Modbus server (its Modbus handler holds the console's channel).
    let report = controller.join();
    // The web view holds the agent and the console: it goes first.
    drop(web);
    drop(ascii);
    drop(serial);
    drop(server);
    let report = report?;
    Ok(report.interrupted.map_or(ExitCode::SUCCESS, crate::exit_code_of_signal))
}

/// The Modbus TCP server's connection limits of the machine file.
pub fn modbus_limits(config: &MachineConfig) -> drl::listener::Limits {
    drl::listener::Limits {
        max_connections: config.modbus.max_connections as usize,
        idle_timeout: Duration::from_millis(config.modbus.idle_timeout_ms),
    }
}

/// The register console of a controller of `config` (its DRL slot added) and its projects,
/// where `folders` (projects, export) or the machine file say, else in `data_dir`;
/// `inputs`: on the simulation clock, where its DV, DH and FUN147 writes go.
pub fn console_setup(
    config: &MachineConfig,
    ns: &Namespace,
    data_dir: PathBuf,
    console: rt_core::console::Console,
    folders: (Option<PathBuf>, Option<PathBuf>),
    inputs: Option<Arc<rt_core::replay::Inputs>>,
) -> Result<(drl::Setup, Projects)> {
    let projects = Projects {
        dir: folders.0.or(config.drl.projects.clone()).unwrap_or_else(|| data_dir.join("projects")),
        export: folders.1.or(config.drl.export.clone()).unwrap_or_else(|| data_dir.join("export")),
    };
    std::fs::create_dir_all(&projects.dir).with_context(|| format!("create {}", projects.dir.display()))?;
    let (drl_task, agent_task) = (config.drl.task, config.ascii.agent_task);
    // PLC control (0x6B10) starts and stops the machine file's programs, not the servers' slots.
    let plc_tasks =
        config.tasks.iter().filter(|t| t.id != drl_task && t.id != agent_task).map(|t| (t.id, t.autorun)).collect();
    let setup = drl::Setup {
        ns: ns.clone(),
        console,
        program: ProgramControl::new(projects.clone()),
        drl_task,
        plc_tasks,
        data_dir,
        inputs,
    };
    Ok((setup, projects))
}

#[derive(clap::Args, Debug)]
pub struct DrlArgs {
    /// The controller's Modbus TCP address, HOST:PORT (before or after the subcommand).
    #[arg(long, global = true, default_value = "127.0.0.1:502")]
    at: SocketAddr,
    #[command(subcommand)]
    command: DrlCommand,
}

#[derive(clap::Subcommand, Debug)]
enum DrlCommand {
    /// Select project ID and open it (Open, code 1); with --run, Open & Release Run (6),
    /// with --debug, Open & Debug Run (45).
    Open {
        /// DRL id, 0..9999: the project folder `<projects>/<id>` holding `main.lua`.
        id: u16,
        /// Run it at once (Open & Release Run, 6).
        #[arg(long)]
        run: bool,
        /// Run it at once under the debugger (Open & Debug Run, 45).
        #[arg(long, conflicts_with = "run")]
        debug: bool,
    },
    /// Release Run (2), or Debug Run (44) with --debug: run the opened project or go on
    /// from a stop.
    Run {
        /// Honour breakpoints (Debug Run, 44).
        #[arg(long)]
        debug: bool,
    },
    /// Stop (3).
    Stop,
    /// Pause (4).
    Pause,
    /// Step into (11), over (12) or out (13).
    Step {
        /// Which step.
        #[arg(value_enum, default_value = "over")]
        kind: StepKind,
    },
    /// Breakpoints: set up to 8 lines before a run (41), add (42) or delete (43) one.
    Bp {
        /// What to do with the lines.
        #[arg(value_enum)]
        action: BpAction,
        /// Lines of `main.lua`: up to 8 for set, one for add and delete.
        lines: Vec<u16>,
    },
    /// Set the run speed, 1..100 % (0x6B03).
    Speed {
        /// Run speed, 1..100 %.
        percent: u16,
    },
    /// Print the DRL registers.
    Status,
}

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum StepKind {
    /// Step Into (11): the next line of `main.lua`, into called functions.
    Into,
    /// Step Over (12): the next line in the same function or a caller.
    Over,
    /// Step Out (13): on in the caller.
    Out,
}

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum BpAction {
    /// Set BP (41): up to 8 lines, before a run.
    Set,
    /// Add BP (42): one line, also while running.
    Add,
    /// Delete BP (43): one line.
    Delete,
}

/// DXMC A.3 registers.
const ID_SELECT: u16 = 0x6B04;
const CONTROL: u16 = 0x6B05;
const RUN_SPEED: u16 = 0x6B03;
const BREAKPOINTS: u16 = 0x6B07;

pub fn drl(args: DrlArgs) -> Result<ExitCode> {
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build()?;
    runtime.block_on(async move {
        let mut client = Client::connect(args.at, 1).await?;
        let control = match &args.command {
            DrlCommand::Open { id, run, debug } => {
                client.write(ID_SELECT, &[*id]).await?;
                Some(if *run {
                    6
                } else if *debug {
                    45
                } else {
                    1
                })
            }
            DrlCommand::Run { debug } => Some(if *debug { 44 } else { 2 }),
            DrlCommand::Stop => Some(3),
            DrlCommand::Pause => Some(4),
            DrlCommand::Step { kind } => Some(match kind {
                StepKind::Into => 11,
                StepKind::Over => 12,
                StepKind::Out => 13,
            }),
            DrlCommand::Bp { action, lines } => {
                let (code, words) = match action {
                    BpAction::Set if lines.len() <= 8 => {
                        (41, (0..8).map(|i| lines.get(i).copied().unwrap_or(0)).collect::<Vec<_>>())
                    }
                    BpAction::Set => bail!("Set BP takes at most 8 lines"),
                    BpAction::Add | BpAction::Delete if lines.len() == 1 => {
                        (if matches!(action, BpAction::Add) { 42 } else { 43 }, lines.clone())
                    }
                    _ => bail!("Add BP and Delete BP take one line at a time"),
                };
                client.write(BREAKPOINTS, &words).await?;
                Some(code)
            }
            DrlCommand::Speed { percent } => {
                client.write(RUN_SPEED, &[*percent]).await?;
                None
            }
            DrlCommand::Status => None,
        };
        let status = match control {
            Some(code) => {
                client.write(CONTROL, &[code]).await?;
                Some(settle(&mut client).await?)
            }
            None => None,
        };
        print_status(&mut client).await?;
        match status.and_then(|code| Status::try_from(code).ok()) {
            Some(status) if status.is_failure() => bail!("{}", refusal(&args.command, status)),
            _ => Ok(ExitCode::SUCCESS),
        }
    })
}

/// Why a command failed, as far as the registers tell (the controller's log has the reason).
fn refusal(command: &DrlCommand, status: Status) -> String {
    let code = format!("status {} {}", status as u16, status.name());
    match (command, status) {
        (DrlCommand::Open { id, .. }, Status::CannotOpen) => format!(
            "the controller cannot open project {id} ({code}): it has no projects/{id}/main.lua, or that does not compile"
        ),
        _ => format!("the controller did not carry out the command ({code}); its log says why"),
    }
}

/// Waits until the status has settled (BUSY, STOPPING, ... are over; at most 5 s), as an
/// HMI would poll; returns the last status read.
async fn settle(client: &mut Client) -> Result<u16> {
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        let status = client.read(0x6B06, 1).await?[0];
        if !Status::in_progress(status) || Instant::now() >= deadline {
            return Ok(status);
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
}

async fn print_status(client: &mut Client) -> Result<()> {
    let r = client.read(0x6B00, 7).await?;
    let state = ExecState::try_from(r[1]).ok().map_or("unknown", ExecState::name);
    let status = Status::try_from(r[6]).ok().map_or("unknown", Status::name);
    outln!("id {}  state {} ({state})  line {}  speed {} %  status {} ({status})", r[0], r[1], r[2], r[3], r[6])?;
    Ok(())
}

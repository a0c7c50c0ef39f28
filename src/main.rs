//! `luamotion`: the command line. A thin edge over `rt-core` (the controller) and
//! `script-host` (the script processes it starts by re-running this binary).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};
use ipc::Namespace;
use rt_core::config::{MAX_TASKS, MachineConfig, TaskConfig};
use rt_core::supervisor::{Outcome, ScriptLauncher};

/// Small allocations of the RT thread come from a pre-touched pool (see rt_core::rt_alloc).
#[global_allocator]
static ALLOCATOR: rt_core::rt_alloc::RtAllocator = rt_core::rt_alloc::RtAllocator;

#[derive(Parser)]
#[command(name = "luamotion", version, about = "A controller runtime for motion applications written in Lua")]
struct Cli {
    /// Log more (-v: info, -vv: debug).
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    verbose: u8,
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Start a controller and run Lua programs, one script process each.
    Run {
        /// Machine file (TOML); without it, the built-in machine: 4 axes on D1 drives, mm, 1 ms.
        #[arg(long)]
        config: Option<PathBuf>,
        /// Namespace of this controller's IPC resources (controllers side by side need different ones).
        #[arg(long, default_value = "luamotion")]
        ns: String,
        /// Programs to run as tasks 0, 1, 2, ...
        scripts: Vec<PathBuf>,
    },
    /// Print the API reference generated from the registry.
    Api {
        #[arg(value_enum)]
        format: ApiFormat,
    },
    /// (internal) One script process; the controller starts these.
    #[command(hide = true)]
    Script {
        #[arg(long)]
        ns: String,
        #[arg(long)]
        task: u8,
        #[arg(long)]
        controller_pid: u32,
        #[arg(long, default_value_t = 64)]
        memory_limit_mib: u32,
        program: PathBuf,
    },
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum ApiFormat {
    /// Markdown reference (docs/api.md).
    Markdown,
    /// lua-language-server annotations (scripts/luamotion.d.lua).
    Lua,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    init_logging(cli.verbose);
    let result = match cli.command {
        Cmd::Run { config, ns, scripts } => run(config, &ns, scripts),
        Cmd::Api { format } => {
            print!(
                "{}",
                match format {
                    ApiFormat::Markdown => api::docs::markdown(),
                    ApiFormat::Lua => api::docs::lua_meta(),
                }
            );
            Ok(ExitCode::SUCCESS)
        }
        Cmd::Script { ns, task, controller_pid, memory_limit_mib, program } => {
            script(&ns, task, controller_pid, memory_limit_mib, program)
        }
    };
    result.unwrap_or_else(|e| {
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
    let filter = tracing_subscriber::EnvFilter::try_from_default_env()
        .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(default));
    tracing_subscriber::fmt().with_env_filter(filter).with_writer(std::io::stderr).init();
}

fn run(config_path: Option<PathBuf>, ns: &str, scripts: Vec<PathBuf>) -> Result<ExitCode> {
    let mut config = match &config_path {
        Some(path) => MachineConfig::load(path)?,
        None => MachineConfig::default(),
    };
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
    let ns = Namespace::new(ns)?;

    let launcher = ScriptLauncher {
        executable: std::env::current_exe().context("locate the luamotion binary")?,
        subcommand: vec!["script".into()],
    };
    let exit_when_tasks_end = config.tasks.iter().any(|t| t.autorun);
    let report = rt_core::run(config, rt_core::RunOptions { ns, launcher, exit_when_tasks_end })?;

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
    tracing::info!(
        cycles = stats.cycles,
        overruns = stats.overruns,
        lateness_p99_us = stats.lateness.value_at_quantile(0.99) as f64 / 1000.0,
        execution_p99_us = stats.execution.value_at_quantile(0.99) as f64 / 1000.0,
        "cycle statistics"
    );
    Ok(if report.interrupted {
        ExitCode::from(130)
    } else if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

fn script(ns: &str, task: u8, controller_pid: u32, memory_limit_mib: u32, program: PathBuf) -> Result<ExitCode> {
    let args = script_host::ScriptArgs { ns: Namespace::new(ns)?, task, controller_pid, memory_limit_mib, program };
    match script_host::run(args) {
        Ok(()) => Ok(ExitCode::SUCCESS),
        Err(script_host::ScriptError::ControllerGone) => Ok(ExitCode::from(3)),
        // The controller reports the last line a failed program writes to stderr.
        Err(e) => {
            if let script_host::ScriptError::Lua { traceback: Some(traceback), .. } = &e {
                eprintln!("{traceback}");
            }
            eprintln!("{e}");
            Ok(ExitCode::FAILURE)
        }
    }
}

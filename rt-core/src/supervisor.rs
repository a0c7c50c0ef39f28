//! The supervisor: starts one script process per task, forwards its output line by line
//! with the task id in front, and reaps it when it ends.

use std::io::{BufRead, BufReader, Read, Write};
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use ipc::Namespace;
use ipc::shm::Region;
use ipc::task_table::TaskTable;

use crate::config::TaskConfig;

/// How a script process is started: the luamotion binary and its hidden subcommand.
#[derive(Clone, Debug)]
pub struct ScriptLauncher {
    pub executable: PathBuf,
    pub subcommand: Vec<String>,
}

/// How a task's program ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// The program ran to its end.
    Finished,
    /// The program stopped with an error: its message (`file:line: message`).
    Failed(String),
    /// The controller stopped it (shutdown).
    Stopped,
}

#[derive(Clone, Debug)]
pub struct TaskReport {
    pub id: u8,
    pub program: PathBuf,
    pub outcome: Outcome,
}

struct Running {
    id: u8,
    program: PathBuf,
    child: Child,
    last_error_line: Arc<Mutex<Option<String>>>,
    forwarders: Vec<JoinHandle<()>>,
    stop_requested: bool,
}

pub struct Supervisor {
    ns: Namespace,
    launcher: ScriptLauncher,
    table: Region<TaskTable>,
    running: Vec<Running>,
    ended: Vec<TaskReport>,
}

impl Supervisor {
    pub fn new(ns: Namespace, launcher: ScriptLauncher) -> Result<Self, ipc::IpcError> {
        let table = Region::<TaskTable>::open(&ns, "tasks")?;
        Ok(Supervisor { ns, launcher, table, running: Vec::new(), ended: Vec::new() })
    }

    /// Starts the task's script process.
    pub fn start(&mut self, task: &TaskConfig) -> std::io::Result<()> {
        self.table.slots[task.id as usize].reset();
        let mut command = Command::new(&self.launcher.executable);
        command
            .args(&self.launcher.subcommand)
            .args(["--ns", self.ns.as_str()])
            .args(["--task", &task.id.to_string()])
            .args(["--controller-pid", &std::process::id().to_string()])
            .args(["--memory-limit-mib", &task.memory_limit_mib.to_string()])
            .arg(&task.program)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        let parent = std::process::id();
        // SAFETY: only async-signal-safe calls between fork and exec.
        unsafe {
            command.pre_exec(move || {
                // Own process group: a Ctrl-C at the terminal reaches the controller, which
                // then stops its scripts in order.
                libc::setpgid(0, 0);
                // Die with the controller, even on its kill -9.
                libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL);
                if libc::getppid() as u32 != parent {
                    libc::_exit(1);
                }
                Ok(())
            });
        }
        let mut child = command.spawn()?;
        let last_error_line = Arc::new(Mutex::new(None));
        let id = task.id;
        let stdout = child.stdout.take().expect("piped");
        let stderr = child.stderr.take().expect("piped");
        let forwarders = vec![forward(stdout, id, None), forward(stderr, id, Some(last_error_line.clone()))];
        tracing::info!(task = id, pid = child.id(), program = %task.program.display(), "started");
        self.running.push(Running {
            id,
            program: task.program.clone(),
            child,
            last_error_line,
            forwarders,
            stop_requested: false,
        });
        Ok(())
    }

    /// Reaps the script processes that have ended.
    pub fn poll(&mut self) {
        let mut i = 0;
        while i < self.running.len() {
            match self.running[i].child.try_wait() {
                Ok(Some(status)) => {
                    let task = self.running.swap_remove(i);
                    self.reap(task, status);
                }
                _ => i += 1,
            }
        }
    }

    fn reap(&mut self, task: Running, status: ExitStatus) {
        for forwarder in task.forwarders {
            let _ = forwarder.join();
        }
        let message = task.last_error_line.lock().map(|l| l.clone()).unwrap_or_default();
        let outcome = if status.success() {
            Outcome::Finished
        } else if task.stop_requested {
            Outcome::Stopped
        } else if let Some(signal) = status.signal() {
            Outcome::Failed(format!("killed by signal {signal}"))
        } else {
            Outcome::Failed(message.unwrap_or_else(|| format!("exit code {}", status.code().unwrap_or(-1))))
        };
        tracing::info!(task = task.id, ?outcome, "ended");
        self.ended.push(TaskReport { id: task.id, program: task.program, outcome });
    }

    pub fn running(&self) -> usize {
        self.running.len()
    }

    /// Stops every script process: SIGTERM, then SIGKILL after a grace period.
    pub fn stop_all(&mut self, grace: Duration) {
        for task in &mut self.running {
            task.stop_requested = true;
            // SAFETY: signalling a child we spawned and have not reaped.
            unsafe { libc::kill(task.child.id() as libc::pid_t, libc::SIGTERM) };
        }
        let deadline = Instant::now() + grace;
        while !self.running.is_empty() && Instant::now() < deadline {
            self.poll();
            std::thread::sleep(Duration::from_millis(5));
        }
        for task in &mut self.running {
            let _ = task.child.kill();
        }
        while !self.running.is_empty() {
            self.poll();
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    /// Reports of the tasks that have ended, in the order they ended.
    pub fn into_reports(self) -> Vec<TaskReport> {
        self.ended
    }
}

/// Copies a child's output to ours line by line, `[task N] ` in front. Keeps the last
/// stderr line: a script that fails writes its error there last.
fn forward(
    stream: impl Read + Send + 'static,
    task: u8,
    last_line: Option<Arc<Mutex<Option<String>>>>,
) -> JoinHandle<()> {
    std::thread::spawn(move || {
        let to_stderr = last_line.is_some();
        for line in BufReader::new(stream).lines() {
            let Ok(line) = line else { break };
            let text = format!("[task {task}] {line}\n");
            if to_stderr {
                let _ = std::io::stderr().lock().write_all(text.as_bytes());
            } else {
                let _ = std::io::stdout().lock().write_all(text.as_bytes());
            }
            if let Some(last) = &last_line
                && let Ok(mut last) = last.lock()
            {
                *last = Some(line);
            }
        }
    })
}

/// The program's name as tests and messages show it.
pub fn display_name(program: &Path) -> String {
    program.file_name().map_or_else(|| program.display().to_string(), |n| n.to_string_lossy().into_owned())
}

//! The supervisor: carries out the core's orders (start a task's script process, kill
//! one, publish an alarm), reaps the processes and reports how each ended, forwards their
//! output line by line with the task id in front (`crate::output`), and keeps each task's CPU time in the
//! task table for the tools.

use std::os::fd::{AsFd, AsRawFd, BorrowedFd, FromRawFd, OwnedFd};
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use api::alarms::{Alarm, Event};
use ipc::Namespace;
use ipc::event_record::{EventKind, EventRecord};
use ipc::events::EventSender;
use ipc::services::{self, IpcNode, Open};
use ipc::shm::Region;
use ipc::task_table::TaskTable;
use schema::MAX_TASKS;

use crate::config::TaskConfig;
use crate::output::{Throttle, spawn_forward};
use crate::pool::Pool;
use crate::tasks::{AlarmReport, Entry, Exit, Order, Report, SupervisorEnd};

/// How a script process is started: the luamotion binary and its hidden subcommand.
#[derive(Clone, Debug)]
pub struct ScriptLauncher {
    /// The luamotion binary (the CLI passes its own, `std::env::current_exe`).
    pub executable: PathBuf,
    /// The arguments before the task's own: the hidden subcommand.
    pub subcommand: Vec<String>,
}

/// How a task's program ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// The program ran to its end.
    Finished,
    /// The program stopped with an error: its message (`file:line: message`) or the alarm.
    Failed(String),
    /// Stopped by `StopTask`, `StopAllTask`, an E-stop or the controller's shutdown.
    Stopped,
}

/// How one task's program ended, for the run's report.
#[derive(Clone, Debug)]
pub struct TaskReport {
    /// The task, 0..MAX_TASKS.
    pub id: u8,
    /// Its program file.
    pub program: PathBuf,
    /// How it ended.
    pub outcome: Outcome,
}

struct Running {
    id: u8,
    program: PathBuf,
    child: Child,
    /// The place on the pool's board it was handed its task on.
    place: Option<usize>,
    last_error_line: Arc<Mutex<Option<String>>>,
    forwarders: Vec<JoinHandle<()>>,
    kill_ordered: bool,
    alarm: Option<String>,
    /// Readable once the process has ended (`pidfd_open`), to wake the supervisor's wait;
    /// none where the OS has no pidfds: the end is then seen at the next look.
    ended: Option<OwnedFd>,
}

/// How often CPU times are read from /proc.
const CPU_PERIOD: Duration = Duration::from_millis(100);
/// How long the supervisor sleeps when neither an order nor a process' end wakes it: the
/// pool, the CPU times and the controller's stop are looked at this often.
const IDLE_LOOK: Duration = Duration::from_millis(10);
/// As `IDLE_LOOK`, while the pool is short of a process or a task handed to one has not
/// started yet, which nothing rings for.
const BUSY_LOOK: Duration = Duration::from_millis(1);

pub(crate) struct Supervisor {
    ns: Namespace,
    launcher: ScriptLauncher,
    data_dir: PathBuf,
    configs: Vec<Option<TaskConfig>>,
    link: SupervisorEnd,
    table: Region<TaskTable>,
    events: EventSender,
    running: Vec<Running>,
    pool: Pool,
    ended: Vec<TaskReport>,
    last_cpu_read: Instant,
    shutting_down: bool,
    _node: IpcNode,
}

impl Supervisor {
    /// Writes each configured task's program into the task table and creates the event
    /// stream the scripts write to; keeps `pool` script processes started and waiting.
    pub fn new(
        ns: Namespace,
        launcher: ScriptLauncher,
        data_dir: PathBuf,
        tasks: &[TaskConfig],
        link: SupervisorEnd,
        pool: usize,
    ) -> Result<Self, ipc::IpcError> {
        let table = Region::<TaskTable>::open(&ns, "tasks")?;
        let mut configs = vec![None; MAX_TASKS];
        for task in tasks.iter().filter(|t| !t.program.as_os_str().is_empty()) {
            table.slots[task.id as usize].set_program(&task.program.display().to_string());
        }
        for task in tasks {
            configs[task.id as usize] = Some(task.clone());
        }
        let node = services::node(&ns, "luamotion-supervisor")?;
        let events = EventSender::new(&node, &ns, Open::Create)?;
        Ok(Supervisor {
            ns,
            launcher,
            data_dir,
            configs,
            link,
            table,
            events,
            running: Vec::new(),
            pool: Pool::new(pool),
            ended: Vec::new(),
            last_cpu_read: Instant::now(),
            shutting_down: false,
            _node: node,
        })
    }

    /// One round: the core's orders, the processes that ended, the CPU times.
    pub fn poll(&mut self) {
        self.link.clear_bell();
        while let Some(order) = self.link.next_order() {
            match order {
                Order::Start { task, entry } => self.start(task, entry),
                Order::Handed { task, entry, place, pid } => self.handed(task, entry, place, pid),
                Order::Kill { task, pid } => self.kill(task, pid),
                Order::Alarm(report) => self.alarm(&report),
            }
        }
        let mut i = 0;
        while i < self.running.len() {
            match self.running[i].child.try_wait() {
                Ok(Some(status)) => {
                    let task = self.running.swap_remove(i);
                    self.reap(task, status);
                }
                Ok(None) => i += 1,
                Err(e) => {
                    // Not ours to reap (someone else waited for it): its pidfd would read
                    // ready for good and wake every wait, so it is watched by the looks only.
                    if self.running[i].ended.take().is_some() {
                        tracing::warn!(task = self.running[i].id, "cannot wait for the task's process: {e}");
                    }
                    i += 1;
                }
            }
        }
        if self.pool.reap(&self.table.pool) {
            ipc::clean_dead_nodes(&self.ns);
        }
        // A replacement waits until the processes handed a task have started it: its own
        // start (ms of CPU) would compete with theirs, which a program is waiting for.
        if !self.shutting_down && !self.handed_starting() {
            let (launcher, ns, data_dir) = (&self.launcher, &self.ns, &self.data_dir);
            self.pool.refill(&self.table.pool, |place| {
                let mut command = script_command(launcher, ns, data_dir);
                command.args(["--pool", &place.to_string()]);
                command
            });
        }
        if self.last_cpu_read.elapsed() >= CPU_PERIOD {
            self.last_cpu_read = Instant::now();
            if let Err(e) = self.events.greet_new_readers() {
                tracing::debug!("{e}");
            }
            for task in &self.running {
                if let Some(ms) = cpu_ms(task.child.id()) {
                    self.table.slots[task.id as usize].set_cpu_ms(ms);
                }
            }
        }
    }

    /// Sleeps until the core orders something or a task's process ends, at most until
    /// the next look (`IDLE_LOOK`, `BUSY_LOOK` while the pool refills or a handed task
    /// starts). A signal cuts it short.
    pub fn wait(&self) {
        let busy = !self.shutting_down && (!self.pool.is_full() || self.handed_starting());
        let ends = self.running.iter().filter_map(|r| r.ended.as_ref()).map(|fd| fd.as_fd());
        wait_for_any(std::iter::once(self.link.bell()).chain(ends), if busy { BUSY_LOOK } else { IDLE_LOOK });
    }

    /// A process handed a task from the pool has not started it yet.
    fn handed_starting(&self) -> bool {
        self.running.iter().any(|r| r.place.is_some() && !self.table.slots[r.id as usize].started())
    }

    fn start(&mut self, id: u8, entry: Entry) {
        let Some(task) = self.task_config(id).filter(|_| !self.shutting_down) else {
            self.link.report(Report::SpawnFailed { task: id });
            return;
        };
        match self.spawn(&task, entry) {
            Ok(pid) => self.link.report(Report::Spawned { task: id, pid }),
            Err(e) => {
                tracing::error!(task = id, "cannot start {}: {e}", task.program.display());
                self.link.report(Report::SpawnFailed { task: id });
            }
        }
    }

    /// The core handed task `id` to the pool's waiting process `pid`: it is the task's
    /// process from now on. One that died before it could be told is replaced by a start
    /// as without a pool.
    fn handed(&mut self, id: u8, entry: Entry, place: usize, pid: u32) {
        // The core hands out only configured tasks.
        let (Some(task), Some(child)) = (self.task_config(id), self.pool.take(pid, &self.table.pool)) else {
            return self.start(id, entry);
        };
        self.track(&task, child, Some(place));
    }

    /// Task `id`'s configuration, `None` when it has none. A slot without a program in the
    /// machine file (the DRL project's) runs what the console wrote into the task table.
    fn task_config(&self, id: u8) -> Option<TaskConfig> {
        let mut task = self.configs[id as usize].clone()?;
        if task.program.as_os_str().is_empty() {
            task.program = PathBuf::from(self.table.slots[id as usize].program());
        }
        Some(task)
    }

    /// A new script process for `task` (the pool's are handed out by the core).
    fn spawn(&mut self, task: &TaskConfig, entry: Entry) -> std::io::Result<u32> {
        self.table.slots[task.id as usize].reset();
        let mut command = script_command(&self.launcher, &self.ns, &self.data_dir);
        command.args(["--task", &task.id.to_string()]).args(["--memory-limit-mib", &task.memory_limit_mib.to_string()]);
        if let Some(function) = entry.function_name() {
            command.args(["--entry", &function]);
        }
        command.arg(&task.program).stdin(Stdio::null());
        let child = command.spawn()?;
        Ok(self.track(task, child, None))
    }

    /// Forwards the output of `task`'s process `child` and watches it until it ends.
    fn track(&mut self, task: &TaskConfig, mut child: Child, place: Option<usize>) -> u32 {
        let pid = child.id();
        let last_error_line = Arc::new(Mutex::new(None));
        let stdout = child.stdout.take().expect("piped");
        let stderr = child.stderr.take().expect("piped");
        let throttle = Arc::new(Mutex::new(Throttle::new(Instant::now())));
        let forwarders = vec![
            spawn_forward(stdout, std::io::stdout(), task.id, throttle.clone(), None),
            spawn_forward(stderr, std::io::stderr(), task.id, throttle, Some(last_error_line.clone())),
        ];
        let pooled = place.is_some();
        tracing::info!(task = task.id, pid, pooled, program = %task.program.display(), "started");
        let ended = end_of(pid);
        self.running.push(Running {
            id: task.id,
            program: task.program.clone(),
            child,
            place,
            last_error_line,
            forwarders,
            kill_ordered: false,
            alarm: None,
            ended,
        });
        pid
    }

    fn kill(&mut self, task: u8, pid: u32) {
        if let Some(running) = self.running.iter_mut().find(|r| r.id == task && r.child.id() == pid) {
            running.kill_ordered = true;
            let _ = running.child.kill();
        }
    }

    fn alarm(&mut self, report: &AlarmReport) {
        let text = describe(report);
        tracing::warn!(task = report.task, cycle = report.cycle, "{text}");
        let who = if Alarm(report.alarm).is_general() { ipc::event_record::CONTROLLER } else { report.task as u32 };
        let record = EventRecord::new(EventKind::Alarm, who, report.cycle, report.alarm, &text);
        if let Err(e) = self.events.send(&record) {
            tracing::debug!("alarm not published: {e}");
        }
        // The alarms that explain why the core killed a process become its outcome; a
        // program that ended by itself says best why, on its last line.
        let killed = matches!(Event::from(Alarm(report.alarm).event_code()), Event::Watchdog | Event::StartTimeout);
        if killed && let Some(running) = self.running.iter_mut().find(|r| r.id == report.task) {
            running.alarm = Some(text);
        }
    }

    fn reap(&mut self, task: Running, status: ExitStatus) {
        for forwarder in task.forwarders {
            let _ = forwarder.join();
        }
        if let Some(place) = task.place {
            // Handed a task it never took: the place is free again.
            self.table.pool.places[place].forget(task.child.id());
        }
        let slot = &self.table.slots[task.id as usize];
        let exit = if status.success() {
            Exit::Finished
        } else if let Some(signal) = status.signal() {
            Exit::Signal(signal)
        } else {
            Exit::Failed { end_code: slot.end_code() }
        };
        self.link.report(Report::Exited { task: task.id, pid: task.child.id(), exit });
        if exit != Exit::Finished {
            // A process that died left its iceoryx2 ports behind; its next start needs them gone.
            ipc::clean_dead_nodes(&self.ns);
        }
        let message = task.last_error_line.lock().map(|l| l.clone()).unwrap_or_default();
        let outcome = match (exit, task.alarm, task.kill_ordered) {
            (Exit::Finished, _, _) => Outcome::Finished,
            (_, Some(alarm), _) => Outcome::Failed(alarm),
            (_, None, true) => Outcome::Stopped,
            (Exit::Signal(signal), None, false) => Outcome::Failed(format!("killed by signal {signal}")),
            (Exit::Failed { .. }, None, false) => {
                Outcome::Failed(message.unwrap_or_else(|| format!("exit code {}", status.code().unwrap_or(-1))))
            }
        };
        tracing::info!(task = task.id, ?outcome, "ended");
        self.ended.push(TaskReport { id: task.id, program: task.program, outcome });
    }

    pub(crate) fn running(&self) -> usize {
        self.running.len()
    }

    /// From now on, starts no script process (the controller is shutting down); the
    /// waiting ones end.
    pub fn refuse_starts(&mut self) {
        self.shutting_down = true;
        self.pool.close(&self.table.pool);
    }

    /// Ends every script process (shutdown) and reaps them; starts no new ones.
    pub fn stop_all(&mut self) {
        self.refuse_starts();
        loop {
            for task in self.running.iter_mut().filter(|t| !t.kill_ordered) {
                task.kill_ordered = true;
                let _ = task.child.kill();
            }
            if self.running.is_empty() {
                return;
            }
            self.poll();
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    /// Reports of the processes that have ended, in the order they ended.
    pub fn into_reports(self) -> Vec<TaskReport> {
        self.ended
    }
}

/// `luamotion script` with what every script process is told, its output piped, in
/// its own process group. Started with `posix_spawn` (std's choice when no code runs
/// between fork and exec): a fork would copy the page tables of the controller's locked
/// memory, and the exec throw them away, most of a start's CPU time and a pause for the
/// RT thread. The script sets its death signal itself (`script_host`).
fn script_command(launcher: &ScriptLauncher, ns: &Namespace, data_dir: &Path) -> Command {
    let mut command = Command::new(&launcher.executable);
    command
        .args(&launcher.subcommand)
        .args(["--ns", ns.as_str()])
        .args(["--controller-pid", &std::process::id().to_string()])
        .arg("--data-dir")
        .arg(data_dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        // Own process group: a Ctrl-C at the terminal reaches the controller, which then
        // stops its scripts in order.
        .process_group(0);
    command
}

/// A descriptor that reads ready once process `pid`, a child not reaped yet, has ended
/// (`pidfd_open`, Linux 5.3); none where the OS refuses it.
fn end_of(pid: u32) -> Option<OwnedFd> {
    // SAFETY: pidfd_open with no flags; the result is checked before it is owned.
    let fd = unsafe { libc::syscall(libc::SYS_pidfd_open, pid as libc::pid_t, 0) };
    // SAFETY: a fresh descriptor nothing else owns.
    (fd >= 0).then(|| unsafe { OwnedFd::from_raw_fd(fd as i32) })
}

/// Sleeps until one of `fds` reads ready, at most `timeout` (a signal cuts it short).
fn wait_for_any<'a>(fds: impl Iterator<Item = BorrowedFd<'a>>, timeout: Duration) {
    let mut fds: Vec<libc::pollfd> =
        fds.map(|fd| libc::pollfd { fd: fd.as_raw_fd(), events: libc::POLLIN, revents: 0 }).collect();
    // SAFETY: `fds` is a live array of `fds.len()` pollfds on open descriptors.
    unsafe { libc::poll(fds.as_mut_ptr(), fds.len() as libc::nfds_t, timeout.as_millis() as i32) };
}

/// An alarm as the log and the event stream say it.
pub fn describe(report: &AlarmReport) -> String {
    let alarm = Alarm(report.alarm);
    let event = Event::from(alarm.event_code());
    let what = match event {
        Event::Watchdog => format!(
            "watchdog: no progress for {} ms at line {} (a program that computes this long without calling \
             the API needs a larger `watchdog_ms` for task {} in the machine file)",
            report.detail, report.line, report.task
        ),
        Event::ProcessDied => format!("the task's process died of signal {}", report.detail),
        Event::CommandBufferBusy => {
            format!("command buffer busy: axis {} is commanded by another task", report.detail)
        }
        Event::Hmpl(code) => format!("stopped by {}", api::errors::describe(code as u32)),
        other => other.meaning().to_string(),
    };
    if alarm.is_general() {
        return format!("controller: {what} (alarm {alarm})");
    }
    format!("task {}: {what} (alarm {alarm})", report.task)
}

/// User + system CPU time of a process, ms (/proc/<pid>/stat fields 14 and 15).
fn cpu_ms(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The command name may hold spaces; the fields after it are plain.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: u64 = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    // SAFETY: sysconf only reads a constant.
    let per_second = unsafe { libc::sysconf(libc::_SC_CLK_TCK) }.max(1) as u64;
    Some(ticks * 1000 / per_second)
}

/// The program's name as tests and messages show it.
pub fn display_name(program: &Path) -> String {
    program.file_name().map_or_else(|| program.display().to_string(), |n| n.to_string_lossy().into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wait ends when a watched process ends, not at its timeout.
    #[test]
    fn a_wait_ends_with_a_process_end() {
        let mut child = Command::new("sleep").arg("0.2").spawn().unwrap();
        let end = end_of(child.id()).expect("pidfd_open (Linux 5.3)");
        let since = Instant::now();
        wait_for_any(std::iter::once(end.as_fd()), Duration::from_secs(30));
        assert!(since.elapsed() < Duration::from_secs(15), "woken by the end, not the timeout: {:?}", since.elapsed());
        assert!(child.try_wait().unwrap().is_some(), "the process has ended");
    }

    /// An order rings the supervisor's bell and a wait ends with it; with nothing rung, or
    /// the bell cleared before the orders are taken, a wait sleeps its whole timeout.
    #[test]
    fn an_order_wakes_the_supervisor() {
        let (mut core, supervisor) = crate::tasks::link().unwrap();
        let quiet = Instant::now();
        wait_for_any(std::iter::once(supervisor.bell()), Duration::from_millis(50));
        assert!(quiet.elapsed() >= Duration::from_millis(50), "nothing rang");
        std::thread::scope(|scope| {
            let core = &mut core;
            scope.spawn(move || {
                std::thread::sleep(Duration::from_millis(100));
                core.order(Order::Kill { task: 0, pid: 1 });
            });
            let since = Instant::now();
            wait_for_any(std::iter::once(supervisor.bell()), Duration::from_secs(30));
            assert!(since.elapsed() < Duration::from_secs(15), "woken by the order: {:?}", since.elapsed());
        });
        supervisor.clear_bell();
        assert!(matches!(supervisor.next_order(), Some(Order::Kill { task: 0, pid: 1 })));
        let cleared = Instant::now();
        wait_for_any(std::iter::once(supervisor.bell()), Duration::from_millis(50));
        assert!(cleared.elapsed() >= Duration::from_millis(50), "the bell was cleared");
    }
}

//! The console thread: it owns everything the Modbus registers reach (the DRL program
//! control, the controller's snapshot and task table, the user areas, the alarms) and
//! answers the Modbus connections' requests one at a time, so that two clients never
//! interleave halfway through a command. Between requests it follows the DRL task
//! every few milliseconds and saves DH when it changed.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender};
use std::time::{Duration, Instant};

use api::alarms::{Alarm, Event, Source};
use ipc::event_record::{CONTROLLER, EventKind, EventRecord};
use ipc::events::EventSender;
use ipc::services::{self, Open};
use ipc::shm::Region;
use ipc::{IpcError, Monitor, Namespace};
use rt_core::console::{Console, ConsoleOrder, ControllerState};
use rt_core::replay::Inputs;
use schema::TaskState;
use schema::debug::DebugBlock;
use schema::shared::SharedData;
use tokio::sync::oneshot;

use crate::program::{Host, ProgramControl};
use crate::registers::{Refusal, Register, span};
use crate::retentive;

/// How often the console follows the DRL task when no request comes.
const TICK: Duration = Duration::from_millis(5);
/// How often the console saves DH written by scripts (a Modbus write is saved at once)
/// and hands the event history to new readers.
const HOUSEKEEPING_PERIOD: Duration = Duration::from_millis(100);

/// A Modbus request in register terms.
#[derive(Debug)]
pub(crate) enum Op {
    Read { address: u16, count: u16 },
    Write { address: u16, values: Vec<u16> },
}

pub(crate) type Answer = Result<Vec<u16>, Refusal>;
pub(crate) type Request = (Op, oneshot::Sender<Answer>);

/// What the console serves.
pub struct Setup {
    /// The controller's namespace.
    pub ns: Namespace,
    /// The console's way into the core: the orders (program control, controller state)
    /// the RT thread carries out.
    pub console: Console,
    /// The DRL program control over the projects.
    pub program: ProgramControl,
    /// The DRL project's task slot.
    pub drl_task: u8,
    /// The machine file's tasks: PLC control (0x6B10) starts the autorun ones, stops all.
    pub plc_tasks: Vec<(u8, bool)>,
    /// Where DH is kept.
    pub data_dir: PathBuf,
    /// On the simulation clock: the DV, DH and FUN147 words written go here, to be applied
    /// at the start of the next cycle (`rt_core::replay`); otherwise they are written at once.
    pub inputs: Option<Arc<Inputs>>,
}

struct State {
    program: ProgramControl,
    res: Resources,
}

/// What the registers read and the program control's host reaches.
struct Resources {
    console: Console,
    drl_task: u8,
    plc_tasks: Vec<(u8, bool)>,
    data_dir: PathBuf,
    inputs: Option<Arc<Inputs>>,
    monitor: Monitor,
    shared: Region<SharedData>,
    events: EventSender,
    _node: iceoryx2::node::Node<services::Ipc>,
    target: ControllerState,
    plc_control: u16,
    dh_saved: u64,
    housekept_at: Instant,
}

/// The DRL slot as program control sees it.
impl Host for Resources {
    fn task_state(&self) -> TaskState {
        self.task_state_of(self.drl_task)
    }

    fn debug(&self) -> &DebugBlock {
        &self.monitor.table().slots[self.drl_task as usize].debug
    }

    fn set_program(&self, path: &Path) {
        self.monitor.table().slots[self.drl_task as usize].set_program(&path.display().to_string());
    }

    fn start(&self) -> bool {
        self.console.send(ConsoleOrder::StartTask(self.drl_task)).is_ok()
    }

    fn stop(&self) -> bool {
        self.console.send(ConsoleOrder::StopTask(self.drl_task)).is_ok()
    }

    /// 100 until the core's first snapshot.
    fn run_speed(&self) -> u16 {
        self.monitor.latest().map_or(100, |s| s.tasks[self.drl_task as usize].run_speed_pct as u16)
    }

    fn set_run_speed(&self, pct: u16) -> bool {
        let Ok(pct) = u8::try_from(pct) else { return false };
        self.console.send(ConsoleOrder::SetRunSpeed { task: self.drl_task, pct }).is_ok()
    }

    fn wake(&self) {
        self.monitor.table().wake(self.drl_task as usize, ipc::clock::monotonic_ns());
    }
}

/// Runs the console in the calling thread until the request channel closes: opens the
/// controller's resources (it must be ready: `ipc::controller_ready`), restores DH from its file, says whether it is
/// ready, then serves.
pub(crate) fn run(setup: Setup, requests: Receiver<Request>, ready: Sender<Result<(), IpcError>>) {
    if let Some(state) = crate::listener::opened(&ready, open_resources(&setup).map(|parts| assemble(setup, parts))) {
        state.serve(requests);
    }
}

/// What the console opens of the controller.
type Parts = (Monitor, Region<SharedData>, EventSender, iceoryx2::node::Node<services::Ipc>);

fn open_resources(setup: &Setup) -> Result<Parts, IpcError> {
    let mut monitor = Monitor::open(&setup.ns)?;
    monitor.refresh();
    let shared = Region::<SharedData>::open(&setup.ns, "shared")?;
    let node = services::node(&setup.ns, "luamotion-drl-console")?;
    let events = EventSender::new(&node, &setup.ns, Open::Existing)?;
    Ok((monitor, shared, events, node))
}

fn assemble(setup: Setup, (monitor, shared, events, node): Parts) -> State {
    match retentive::remove_leftovers(&setup.data_dir) {
        Ok(0) => {}
        Ok(n) => tracing::info!("removed {n} temporary DH file(s) of an earlier run that was killed"),
        Err(e) => tracing::warn!("temporary DH files of an earlier run not removed: {e}"),
    }
    match retentive::load(&setup.data_dir) {
        Ok(Some(bytes)) => shared.load_dh(&bytes),
        Ok(None) => {}
        Err(e) => tracing::error!("DH not restored: {e}"),
    }
    let dh_saved = shared.dh_writes();
    let Setup { ns: _, console, program, drl_task, plc_tasks, data_dir, inputs } = setup;
    let res = Resources {
        console,
        drl_task,
        plc_tasks,
        data_dir,
        inputs,
        monitor,
        shared,
        events,
        _node: node,
        target: ControllerState::Run,
        plc_control: 0,
        dh_saved,
        housekept_at: Instant::now(),
    };
    State { program, res }
}

impl State {
    fn serve(mut self, requests: Receiver<Request>) {
        loop {
            match requests.recv_timeout(TICK) {
                Ok((op, reply)) => {
                    self.follow();
                    let answer = self.answer(op);
                    let _ = reply.send(answer);
                }
                Err(RecvTimeoutError::Timeout) => self.follow(),
                Err(RecvTimeoutError::Disconnected) => break,
            }
        }
        self.res.save_dh();
    }

    /// The newest snapshot, the DRL task's progress; now and then DH written by scripts
    /// and the event history for new readers.
    fn follow(&mut self) {
        self.res.monitor.refresh();
        self.program.poll(&self.res);
        if self.res.housekept_at.elapsed() >= HOUSEKEEPING_PERIOD {
            if self.res.shared.dh_writes() != self.res.dh_saved {
                self.res.save_dh();
            }
            self.res.housekept_at = Instant::now();
            if let Err(e) = self.res.events.greet_new_readers() {
                tracing::debug!("{e}");
            }
        }
    }

    fn answer(&mut self, op: Op) -> Answer {
        match op {
            Op::Read { address, count } => {
                let registers = span(address, count, false)?;
                Ok(registers.into_iter().map(|r| self.res.read(r, &self.program)).collect())
            }
            Op::Write { address, values } => {
                let registers = span(address, values.len() as u16, true)?;
                for (&register, &value) in registers.iter().zip(&values) {
                    check(register, value)?;
                }
                let mut dh_written = false;
                for (register, value) in registers.into_iter().zip(values) {
                    dh_written |= matches!(register, Register::User(a) if a >= calls::user_area::DH_BASE);
                    self.res.write(register, value, &mut self.program);
                }
                if dh_written {
                    self.res.save_dh();
                }
                self.follow();
                Ok(Vec::new())
            }
        }
    }
}

impl Resources {
    fn task_state_of(&self, task: u8) -> TaskState {
        self.monitor.latest().map_or(TaskState::Empty, |s| TaskState::from(s.tasks[task as usize].state))
    }

    fn save_dh(&mut self) {
        let writes = self.shared.dh_writes();
        match retentive::save(&self.data_dir, &self.shared.dh_bytes()) {
            Ok(()) => self.dh_saved = writes,
            Err(e) => tracing::error!("DH not saved: {e}"),
        }
    }

    fn read(&self, register: Register, program: &ProgramControl) -> u16 {
        match register {
            Register::User(a) => calls::user_area::read(&self.shared, a as i64).unwrap_or(0),
            Register::Plc(a) => calls::plc::read(self.shared.plc(), a).unwrap_or(0),
            Register::ControllerState => self.monitor.latest().map_or(0, |s| s.controller_state as u16),
            Register::TargetState => self.target as u16,
            Register::DrlId => program.current_id(),
            Register::ExecState => program.state().into(),
            Register::Line => program.line(self),
            Register::RunSpeed => self.run_speed(),
            Register::IdSelect => program.selected(),
            Register::Control => program.last_control(),
            Register::Status => program.status().into(),
            Register::Breakpoint(i) => program.breakpoint_register(i),
            Register::PlcControl => self.plc_control,
            Register::PlcStatus => self.plc_status(),
        }
    }

    fn write(&mut self, register: Register, value: u16, program: &mut ProgramControl) {
        match register {
            Register::User(a) | Register::Plc(a) => match &self.inputs {
                Some(inputs) => {
                    if !inputs.modbus_write(a, value) {
                        tracing::warn!(
                            "Modbus write of 0x{a:04X} dropped: a replay takes none, or too many are queued"
                        );
                    }
                }
                None => {
                    rt_core::replay::write_word(&self.shared, a, value);
                }
            },
            Register::TargetState => {
                if let Some(target) = ControllerState::target(value) {
                    self.target = target;
                    let _ = self.console.send(ConsoleOrder::SwitchState(target));
                }
            }
            Register::IdSelect => {
                program.select(value);
            }
            Register::RunSpeed => {
                program.set_speed(value, self);
            }
            Register::Control => {
                if program.control(value, self).is_none() {
                    self.alarm(
                        Alarm::error(Source::RlCore, 0, Event::DrlControl),
                        &format!("DRL control code {value}"),
                    );
                }
            }
            Register::Breakpoint(i) => program.set_breakpoint_register(i, value),
            Register::PlcControl => self.plc(value),
            Register::ControllerState
            | Register::DrlId
            | Register::ExecState
            | Register::Line
            | Register::Status
            | Register::PlcStatus => {}
        }
    }

    /// DXMC A.3, 0x6B10: 0 ColdStart, 1 WarmStart, 2 HotStart start the machine file's
    /// autorun tasks (all three alike: a task's process always starts afresh), 3 Stop
    /// stops them all; another code is alarm 0x4105.
    fn plc(&mut self, code: u16) {
        let orders: Vec<ConsoleOrder> = match code {
            0..=2 => self.plc_tasks.iter().filter(|t| t.1).map(|t| ConsoleOrder::StartTask(t.0)).collect(),
            3 => self.plc_tasks.iter().map(|t| ConsoleOrder::StopTask(t.0)).collect(),
            _ => {
                self.alarm(Alarm::error(Source::PlcCore, 0, Event::PlcControl), &format!("PLC control code {code}"));
                return;
            }
        };
        self.plc_control = code;
        for order in orders {
            let _ = self.console.send(order);
        }
    }

    /// DXMC A.3, 0x6B11: 3 PlcRunning while a machine-file task runs, else 7 PlcStop.
    fn plc_status(&self) -> u16 {
        let running = self
            .plc_tasks
            .iter()
            .any(|&(t, _)| matches!(self.task_state_of(t), TaskState::Starting | TaskState::Running));
        if running { 3 } else { 7 }
    }

    fn alarm(&self, alarm: Alarm, what: &str) {
        let cycle = self.monitor.latest().map_or(0, |s| s.cycle);
        let text = format!("{what}: {} ({alarm})", Event::from(alarm.event_code()).meaning());
        tracing::warn!("{text}");
        let record = EventRecord::new(EventKind::Alarm, CONTROLLER, cycle, alarm.0, &text);
        if let Err(e) = self.events.send(&record) {
            tracing::debug!("alarm not published: {e}");
        }
    }
}

/// Values a register refuses (exception 03). Invalid command codes are not refused: they
/// are written, raise their alarm and change nothing (DXMC 0x7000, 0x4105).
fn check(register: Register, value: u16) -> Result<(), Refusal> {
    let ok = match register {
        Register::TargetState => ControllerState::target(value).is_some(),
        Register::IdSelect => ProgramControl::valid_id(value),
        Register::RunSpeed => ProgramControl::valid_speed(value),
        _ => true,
    };
    if ok { Ok(()) } else { Err(Refusal::IllegalValue) }
}

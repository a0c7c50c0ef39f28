//! The machine the RT thread owns and steps: the EtherCAT network, the motion kernel, the
//! tasks, the controller's I/O, and the controller state of DXMC 3.6 with each task's run
//! speed. The cycle (`cycle.rs`) steps it; dispatch (`dispatch/`) applies commands to it.

use api::alarms::Event;
use api::{ErrorCode, SystemError};
use schema::MAX_TASKS;

use crate::analog::AnalogIo;
use crate::console::{ConsoleOrder, ControllerState};
use crate::fun147_boxes::Boxes;
use crate::io::ControllerIo;
use crate::master::PdoForces;
use crate::ownership;
use crate::position_trigger::PositionTriggers;
use crate::tasks::Tasks;
use devices::ecat::Network;
use kernel::Kernel;

/// Everything the RT thread owns and steps.
pub struct Machine {
    /// The EtherCAT segment and its process image.
    pub network: Network,
    /// The axes and groups.
    pub kernel: Kernel,
    /// The HMPL tasks (ch. 16) and their link to the supervisor.
    pub tasks: Tasks,
    pub(crate) io: ControllerIo,
    /// The slaves' analog conversion types and output bindings (HMPL ch. 10).
    pub analog: AnalogIo,
    /// RxPDO values forced by ForceWritePDO (HMPL 17.2.8), written after the kernel.
    pub forces: PdoForces,
    /// The cycle time, ns.
    pub period_ns: u64,
    /// The cycle being run.
    pub cycle: u64,
    /// DXMC 3.6: motion commands only in Run or Diagnosis.
    pub state: ControllerState,
    /// Each task's run speed, % (DXMC A.3, 0x6B03; 100 but for a DRL project).
    pub run_speed: [u32; MAX_TASKS],
    /// The FUN147 boxes (docs/fun147.md), stepped before the kernel.
    pub boxes: Boxes,
    /// The network was scanned again this cycle: the snapshot's slave table is renewed.
    pub rescanned: bool,
    /// HMPL ch. 12: the axes' position triggers, stepped after the kernel (none until
    /// `with_position_triggers`).
    pub triggers: PositionTriggers,
    /// On a wire: whether the segment answered in Op last cycle (`watch_bus`).
    bus_up: bool,
}

impl Machine {
    /// In Run, every task's run speed 100 %, no FUN147 box and no position trigger.
    pub fn new(network: Network, kernel: Kernel, tasks: Tasks, period_ns: u64) -> Self {
        Machine {
            network,
            kernel,
            tasks,
            io: ControllerIo::default(),
            analog: AnalogIo::default(),
            forces: PdoForces::default(),
            period_ns,
            cycle: 0,
            state: ControllerState::Run,
            run_speed: [100; MAX_TASKS],
            boxes: Boxes::default(),
            rescanned: false,
            triggers: PositionTriggers::default(),
            bus_up: true,
        }
    }

    /// The position triggers of the machine file's axes (`[axes.pt]`).
    pub fn with_position_triggers(mut self, config: &config::MachineConfig) -> Self {
        self.triggers = PositionTriggers::new(config);
        self
    }

    /// A task's run speed as a factor.
    pub fn run_speed(&self, task: u8) -> f64 {
        self.run_speed[task as usize] as f64 / 100.0
    }

    /// DXMC 3.6, 0x6A81: a switch needs the EtherCAT network in Op, else the controller
    /// is in Fail. Leaving Run or Diagnosis stops every axis as `StopAll` does, and the
    /// programs whose motion it cut short are told (docs/decisions.md, "Axis ownership").
    pub fn switch_state(&mut self, target: ControllerState) {
        let next = if self.network.state() == devices::ecat::AlState::Op { target } else { ControllerState::Fail };
        if self.state.allows_motion() && !next.allows_motion() {
            let owners = ownership::owners_reached(&self.kernel, &self.tasks, &ownership::Reach::All, None);
            self.kernel.stop_all();
            ownership::tell_owners(&mut self.kernel, &mut self.tasks, self.cycle, &owners);
        }
        self.state = next;
    }

    /// HMPL 2.16 `ScanNetwork`: the master's start-up again (every slave back to Pre-Op,
    /// configured, to Op; the image laid out anew from the same machine file, so the
    /// axes' links stay valid). Refused with 0x138C while an axis or a group is enabled
    /// (as DXMC 3.6 allows a rescan only in standby, with no motion) or before the
    /// controller is up; 0x012C when the network does not come back to Op, and the
    /// controller is in Fail until a rescan succeeds (docs/decisions.md, "System").
    pub fn scan_network(&mut self) -> Result<(), SystemError> {
        let enabled =
            self.kernel.axes().iter().any(|a| a.is_enabled()) || self.kernel.groups().iter().any(|g| g.is_enabled());
        if enabled || self.state == ControllerState::Initial {
            return Err(SystemError::HmplMotionNotReady);
        }
        // On a wire the master restores its slaves itself; a new scan is a new start.
        if !self.network.is_simulated() {
            return Err(SystemError::HmplNotSupported);
        }
        let result = self.network.start(self.period_ns);
        self.rescanned = true;
        match result {
            Ok(()) => {
                if self.state == ControllerState::Fail {
                    self.state = ControllerState::Run;
                }
                Ok(())
            }
            Err(_) => {
                self.state = ControllerState::Fail;
                Err(SystemError::NicInitTout)
            }
        }
    }

    /// On a wire, after each exchange: the segment that stops answering in Op raises DXMC
    /// event 0x6103 (EtherCAT disconnected) once, and records 0x012C (the fieldbus network
    /// not ready) as the system's last error; the axes see no drive (`Network::inputs_valid`)
    /// and count as faulted. Once it answers again the master has its slaves back in Op;
    /// the drives need `Reset` and `Enable`.
    pub fn watch_bus(&mut self) {
        let up = self.network.inputs_valid();
        if self.bus_up && !up {
            self.tasks.general_alarm(Event::EtherCatDisconnected, self.cycle);
            self.kernel.record_system_error(ErrorCode::System(SystemError::NicInitTout).code());
        }
        self.bus_up = up;
    }

    /// The console watches the tasks' states in the snapshot: a refused start or stop
    /// changes none, so its error is not passed on.
    pub fn carry_out(&mut self, order: ConsoleOrder) {
        let Machine { tasks, kernel, cycle, .. } = self;
        match order {
            ConsoleOrder::StartTask(t) => {
                let _ = tasks.start(t as i64, crate::tasks::Entry::TOP_LEVEL, *cycle);
            }
            ConsoleOrder::StopTask(t) => {
                let _ = tasks.stop(t as i64, *cycle, &mut |t, reaction| kernel.react(t, reaction));
            }
            ConsoleOrder::SwitchState(target) => self.switch_state(target),
            ConsoleOrder::SetRunSpeed { task, pct } => self.set_run_speed(task, pct),
        }
    }

    /// DXMC A.3, 0x6B03: the speed of a task's program, 1..100 % (the console checks the
    /// range; anything else is ignored here). The motion it commands follows at once.
    fn set_run_speed(&mut self, task: u8, pct: u8) {
        let Some(speed) = self.run_speed.get_mut(task as usize) else { return };
        if (1..=100).contains(&pct) && *speed != pct as u32 {
            *speed = pct as u32;
            self.kernel.set_run_speed(task, pct as f64 / 100.0);
        }
    }

    /// HMPL 2.9, 9.1: every task stopped, every axis disabled.
    pub fn emergency_stop(&mut self) {
        self.kernel.emergency_stop();
        self.stop_all_tasks();
    }

    /// HMPL 16.5: every task that runs is stopped; its motion reacts as configured.
    pub fn stop_all_tasks(&mut self) {
        let Machine { tasks, kernel, cycle, .. } = self;
        tasks.stop_all(*cycle, &mut |t, reaction| kernel.react(t, reaction));
    }
}

//! The default machine with attached (external) tasks whose requests go straight to
//! `dispatch`, as the RT thread sends them, cycle by cycle and deterministic.

#![allow(dead_code)]

use api::call::Value;
use api::{ArgType, Command};
use devices::ecat::Network;
use ipc::call::{Reply, Request};
use ipc::task_table::TaskTable;
use kernel::Kernel;
use rt_core::MachineConfig;
use rt_core::config::{FaultReaction, TaskConfig};
use rt_core::dispatch;
use rt_core::machine::Machine;
use rt_core::tasks::{self, SupervisorEnd, Tasks};
use schema::layout::zeroed;
use schema::shared::SharedData;

pub struct Rig {
    pub machine: Machine,
    table: Box<TaskTable>,
    shared: Box<SharedData>,
    _supervisor: SupervisorEnd,
}

impl Rig {
    /// Tasks 0 and 1 attached, with fault reaction `reaction`.
    pub fn new(reaction: FaultReaction) -> Self {
        Self::with_config(MachineConfig::default(), reaction)
    }

    /// The default machine with `n` axes like its first.
    pub fn with_axes(n: usize) -> Self {
        let mut config = MachineConfig::default();
        let first = config.axes[0].clone();
        config.axes =
            (0..n).map(|i| rt_core::config::AxisConfig { name: format!("axis{i}"), ..first.clone() }).collect();
        Self::with_config(config, FaultReaction::None)
    }

    pub fn with_config(config: MachineConfig, reaction: FaultReaction) -> Self {
        let mut network = Network::for_machine(&config);
        network.start(config.period_ns()).unwrap();
        let kernel = Kernel::new(&config, &network);
        let attached = |id| TaskConfig {
            autorun: false,
            external: true,
            fault_reaction: reaction,
            ..TaskConfig::autorun(id, "-".into())
        };
        let (link, supervisor) = tasks::link().expect("the bell");
        let tasks = Tasks::new(&[attached(0), attached(1)], config.period_ns(), link);
        let machine = Machine::new(network, kernel, tasks, config.period_ns());
        Rig { machine, table: zeroed(), shared: zeroed(), _supervisor: supervisor }
    }

    pub fn cycle(&mut self) {
        let m = &mut self.machine;
        m.cycle += 1;
        m.network.exchange(1e-3);
        let Machine { tasks, kernel, cycle, .. } = m;
        tasks.step(*cycle, &self.table, &self.shared, 0, &mut |t, r| kernel.react(t, r));
        m.kernel.step(m.cycle, &mut m.network);
    }

    pub fn cycles(&mut self, n: usize) {
        for _ in 0..n {
            self.cycle();
        }
    }

    /// A request from `task` in the present cycle: its return value (`i64::MIN` when the
    /// answer is deferred).
    pub fn send(&mut self, task: u8, request: &Request) -> i64 {
        let mut reply = Reply::to(request);
        if dispatch::execute(&mut self.machine, task, request, &mut reply) == ipc::Disposition::Defer {
            return i64::MIN;
        }
        reply.values[0] as i64
    }

    /// `command` from `task` with its `Int` and `Bool` arguments from `ints` and its
    /// `Double` ones from `doubles`, each where the registry declares it: its return value.
    pub fn call(&mut self, task: u8, command: Command, ints: &[i64], doubles: &[f64]) -> i64 {
        self.call_values(task, command, &declared(command, ints, doubles)).0
    }

    /// `command(values...)` from `task`, the arguments in the declaration's order: its
    /// return value and the reply.
    pub fn call_values(&mut self, task: u8, command: Command, values: &[Value]) -> (i64, Reply) {
        let call: api::CommandCall = api::call::from_values(command, values).expect("arguments as declared");
        let mut request = Request::new(command.id());
        calls::wire::encode(&call, &mut request).unwrap();
        let mut reply = Reply::to(&request);
        if dispatch::execute(&mut self.machine, task, &request, &mut reply) == ipc::Disposition::Defer {
            return (i64::MIN, reply);
        }
        (reply.values[0] as i64, reply)
    }

    pub fn enable(&mut self, axis: i64) {
        assert_eq!(self.call(0, Command::Enable, &[axis], &[]), 0);
        self.cycles(20);
        assert!(self.machine.kernel.axes()[axis as usize].is_enabled(), "axis {axis} enables");
    }

    pub fn moving(&self, axis: usize) -> bool {
        self.machine.kernel.axes()[axis].is_moving()
    }
}

/// The values of a call of `command` whose `Int` and `Bool` arguments are `ints` and whose
/// `Double` ones are `doubles`, each in the place the registry declares it (a test names
/// numbers by their type, the declaration decides where they go).
pub fn declared(command: Command, ints: &[i64], doubles: &[f64]) -> Vec<Value> {
    let (mut ints, mut doubles) = (ints.iter(), doubles.iter());
    let spec = command.spec();
    let values: Vec<Value> = spec
        .args
        .iter()
        .map(|arg| match arg.ty {
            ArgType::Int | ArgType::Bool => ints.next().map(|&i| Value::Int(i)),
            ArgType::Double => doubles.next().map(|&d| Value::Double(d)),
            other => panic!("{}: a {other:?} argument is passed with call_values", spec.name),
        })
        .map(|value| value.unwrap_or_else(|| panic!("{}: too few arguments", spec.name)))
        .collect();
    assert!(ints.next().is_none() && doubles.next().is_none(), "{}: too many arguments", spec.name);
    values
}

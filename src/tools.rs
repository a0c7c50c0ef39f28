//! The tools that look at a running controller: `luamotion tasks` and `luamotion events`.

use std::process::ExitCode;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use api::alarms::Alarm;
use ipc::event_record::{EventKind, EventRecord};
use ipc::events::EventReader;
use ipc::{Monitor, Namespace};
use schema::TaskState;

use crate::stdout::outln;

fn open(ns: &str) -> Result<Namespace> {
    let ns = Namespace::new(ns)?;
    if ipc::controller_pid(&ns)?.is_none() {
        bail!("no controller is running in namespace {ns}");
    }
    Ok(ns)
}

/// `luamotion tasks`: one line per configured task.
pub fn tasks(ns: &str) -> Result<ExitCode> {
    let ns = open(ns)?;
    let mut monitor = Monitor::open(&ns).context("read the controller's state")?;
    let snapshot = *monitor.snapshot()?;
    outln!("cycle {} ({} ms), {} overruns", snapshot.cycle, snapshot.time_in_ms, snapshot.overruns)?;
    let wire = snapshot.wire;
    if wire.on_wire != 0 {
        outln!(
            "EtherCAT on a wire: {} frames back, {} missing, {} short of the working counter, {} matching nothing sent",
            wire.good,
            wire.missing,
            wire.short,
            wire.unmatched
        )?;
    }
    outln!(
        "{:<4} {:<9} {:>7} {:>8} {:>9}  {:<10}  program",
        "task",
        "state",
        "pid",
        "cpu ms",
        "watchdog",
        "last alarm"
    )?;
    for (id, task) in snapshot.tasks.iter().enumerate() {
        let state = TaskState::from(task.state);
        if state == TaskState::Empty {
            continue;
        }
        let slot = &monitor.table().slots[id];
        let pid = if task.pid == 0 { "-".to_string() } else { task.pid.to_string() };
        let alarm = if task.alarm == 0 { "-".to_string() } else { Alarm(task.alarm).to_string() };
        outln!(
            "{id:<4} {:<9} {pid:>7} {:>8} {:>7}ms  {alarm:<10}  {}",
            state.name(),
            slot.cpu_ms(),
            task.watchdog_ms,
            slot.program()
        )?;
    }
    Ok(ExitCode::SUCCESS)
}

/// One event in words, as `luamotion events` prints it and the web view lists it.
pub fn describe(record: &EventRecord) -> String {
    let who = if record.task == ipc::event_record::CONTROLLER {
        "controller".to_string()
    } else {
        format!("task {}", record.task)
    };
    match record.kind() {
        Some(EventKind::Event) => format!("cycle {} {who} event {}", record.cycle, record.code),
        Some(EventKind::Message) => format!("cycle {} {who} message {:?}", record.cycle, record.text()),
        Some(EventKind::Alarm) => {
            format!("cycle {} {who} alarm {}: {}", record.cycle, Alarm(record.code), record.text())
        }
        None => format!("cycle {} {who} unknown record kind {}", record.cycle, record.kind),
    }
}

/// `luamotion events`: prints the event stream until the controller ends, Ctrl-C, or
/// `count` events.
pub fn events(ns: &str, count: Option<usize>) -> Result<ExitCode> {
    let ns = open(ns)?;
    let reader = EventReader::open(&ns).context("follow the controller's events")?;
    let mut seen = 0;
    let mut last_check = Instant::now();
    loop {
        while let Some(record) = reader.try_next()? {
            outln!("{}", describe(&record))?;
            seen += 1;
            if count.is_some_and(|n| seen >= n) {
                return Ok(ExitCode::SUCCESS);
            }
        }
        if rt_core::signals::termination_requested() {
            return Ok(ExitCode::from(130));
        }
        if last_check.elapsed() > Duration::from_millis(200) {
            last_check = Instant::now();
            if ipc::controller_pid(&ns)?.is_none() {
                return Ok(ExitCode::SUCCESS);
            }
        }
        std::thread::sleep(Duration::from_millis(2));
    }
}

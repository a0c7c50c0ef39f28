//! The live web view (`serve --http PORT`): one page embedded in the binary, the
//! controller's state sent to it as server-sent events 20 times a second, and its
//! commands. Axis commands are ASCII lines carried out by the Native ASCII agent from its
//! task slot (docs/decisions.md, "Web view"), so ownership, the controller state and
//! alarms apply as to any client; DRL program control writes the registers of DXMC A.3
//! through the DRL console, as a Modbus HMI does. The state is read from the published
//! snapshot by a thread of its own: the RT thread does nothing for the page.

use std::collections::VecDeque;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, mpsc};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::Result;
use api::alarms::Alarm;
use axum::extract::{Path, Query, State};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{Html, IntoResponse};
use axum::routing::{get, post};
use axum::{Json, Router};
use drl::ascii::Agent;
use drl::codes::{ExecState, Status};
use ipc::events::EventReader;
use ipc::messages::{Snapshot, TaskState, motion_status};
use ipc::task_table::TaskTable;
use ipc::{IpcError, Monitor, Namespace};
use rt_core::replay::{Input, Inputs};
use serde::Deserialize;
use serde_json::{Value, json};
use tokio::sync::watch;
use tokio_stream::StreamExt;
use tokio_stream::wrappers::WatchStream;

const PAGE: &str = include_str!("page.html");
/// How often the page gets the state: 20 a second, twice the 10 a live view needs.
const PERIOD: Duration = Duration::from_millis(50);
/// The newest events the page is sent.
const EVENTS: usize = 20;
/// How long a DRL command may take to settle (BUSY, STOPPING) before its answer is sent.
const DRL_SETTLE: Duration = Duration::from_secs(5);

/// The DRL console's register logic, a Modbus PDU in, its response out (`drl::Server::pdu_handler`).
pub type DrlHandler = Box<dyn FnMut(&[u8]) -> Vec<u8> + Send>;

#[derive(Clone)]
struct App {
    state: watch::Receiver<Arc<str>>,
    agent: Agent,
    /// None in `run`, which has no DRL console.
    drl: Option<Arc<Mutex<DrlHandler>>>,
    /// On the simulation clock: where the simulated inputs go, to land at a cycle boundary.
    inputs: Option<Arc<Inputs>>,
}

/// A running web view: its server and the thread that reads the controller's state. Drop
/// it before the ASCII and Modbus servers whose agent and console it holds.
pub struct WebView {
    pub address: SocketAddr,
    stop: Arc<AtomicBool>,
    runtime: Option<tokio::runtime::Runtime>,
    reader: Option<JoinHandle<()>>,
}

impl WebView {
    /// Follows the controller in `ns` and serves the page on `bind:port` (0: a free port,
    /// see `address`); `inputs`: the simulation clock's (`run --clock sim`).
    pub fn start(
        ns: Namespace,
        (bind, port): (&str, u16),
        agent: Agent,
        drl: Option<DrlHandler>,
        inputs: Option<Arc<Inputs>>,
    ) -> Result<Self> {
        let (publish, state) = watch::channel(Arc::<str>::from("{}"));
        let stop = Arc::new(AtomicBool::new(false));
        let stopped = stop.clone();
        let reader = drl::listener::start_owner("web-state", move |ready| read_state(ns, publish, &stopped, ready))?;
        let (runtime, listener, address) = drl::listener::listen("web", bind, port)?;
        let app = Router::new()
            .route("/", get(|| async { Html(PAGE) }))
            .route("/api/state", get(current))
            .route("/api/stream", get(stream))
            .route("/api/axis/{id}/{action}", post(axis_command))
            .route("/api/drl", get(drl_status))
            .route("/api/drl/{op}", post(drl_command))
            .route("/api/sim/gpi/{pin}/{level}", post(sim_gpi))
            .route("/api/sim/slvgpi/{slave}/{pin}/{level}", post(sim_slave_gpi))
            .route("/api/sim/ai/{slave}/{channel}/{raw}", post(sim_ai))
            .with_state(App { state, agent, drl: drl.map(|drl| Arc::new(Mutex::new(drl))), inputs });
        runtime.spawn(async move {
            if let Err(e) = axum::serve(listener, app).await {
                tracing::warn!("web view: {e}");
            }
        });
        tracing::info!(%address, "web view up");
        Ok(WebView { address, stop, runtime: Some(runtime), reader: Some(reader) })
    }
}

impl Drop for WebView {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        // The runtime's end drops the page's handles on the agent and the console.
        if let Some(runtime) = self.runtime.take() {
            runtime.shutdown_timeout(Duration::from_millis(200));
        }
        if let Some(reader) = self.reader.take() {
            let _ = reader.join();
        }
    }
}

/// The state thread: every `PERIOD` the newest snapshot, the task table and the newest
/// events as one JSON text for every page.
fn read_state(
    ns: Namespace,
    publish: watch::Sender<Arc<str>>,
    stop: &AtomicBool,
    ready: mpsc::Sender<Result<(), IpcError>>,
) {
    let mut recent = VecDeque::with_capacity(EVENTS);
    let mut look = |monitor: &mut Monitor, events: &EventReader| {
        monitor.refresh();
        while let Ok(Some(record)) = events.try_next() {
            if recent.len() == EVENTS {
                recent.pop_front();
            }
            recent.push_back(crate::tools::describe(&record));
        }
        if let Some(snapshot) = monitor.latest() {
            publish.send_replace(view(snapshot, monitor.table(), &recent).to_string().into());
        }
    };
    // The first state is published before the view says it is ready: once announced, it
    // never answers `{}` for a controller that has a state.
    let opened = Monitor::open(&ns).and_then(|mut monitor| {
        let events = EventReader::open(&ns)?;
        look(&mut monitor, &events);
        Ok((monitor, events))
    });
    let Some((mut monitor, events)) = drl::listener::opened(&ready, opened) else { return };
    let mut next = Instant::now();
    while !stop.load(Ordering::Relaxed) {
        next += PERIOD;
        std::thread::sleep(next.saturating_duration_since(Instant::now()));
        look(&mut monitor, &events);
    }
}

/// What the page shows of one snapshot.
fn view(s: &Snapshot, table: &TaskTable, events: &VecDeque<String>) -> Value {
    let axes: Vec<Value> = s.axes[..s.axis_count as usize]
        .iter()
        .enumerate()
        .map(|(id, a)| {
            let state = if a.fault_status != 0 {
                "fault"
            } else if a.motion_status & motion_status::ENABLED == 0 {
                "disabled"
            } else if a.motion_status & motion_status::HOMING != 0 {
                "homing"
            } else if a.motion_status & motion_status::MOVING != 0 {
                "moving"
            } else {
                "standstill"
            };
            json!({"id": id, "pos": a.pos_fb, "vel": a.vel_fb, "ref_pos": a.ref_pos, "pos_err": a.pos_err,
                   "state": state, "motion_status": a.motion_status, "fault_status": a.fault_status,
                   "last_err": a.last_err})
        })
        .collect();
    let groups: Vec<Value> = s
        .groups
        .iter()
        .enumerate()
        .filter(|(_, g)| g.axis_count > 0)
        .map(|(id, g)| {
            json!({"id": id, "axes": &g.axes[..g.axis_count as usize], "motion_status": g.motion_status,
                   "fault_status": g.fault_status, "last_err": s.group_last_err[id],
                   "pose": &g.carte_pose_fb[..3], "vel": g.grp_pg[1]})
        })
        .collect();
    let tasks: Vec<Value> = s
        .tasks
        .iter()
        .enumerate()
        .filter(|(_, t)| TaskState::from(t.state) != TaskState::Empty)
        .map(|(id, t)| {
            let slot = &table.slots[id];
            let alarm = if t.alarm == 0 { String::new() } else { Alarm(t.alarm).to_string() };
            json!({"id": id, "state": TaskState::from(t.state).name(), "pid": t.pid, "cpu_ms": slot.cpu_ms(),
                   "watchdog_ms": t.watchdog_ms, "alarm": alarm, "program": slot.program()})
        })
        .collect();
    let controller_state = match s.controller_state {
        0 => "Initial",
        1 => "Fail",
        2 => "Edit",
        4 => "Run",
        5 => "Diagnosis",
        _ => "unknown",
    };
    json!({"cycle": s.cycle, "time_ms": s.time_in_ms, "overruns": s.overruns,
           "controller_state": controller_state, "axes": axes, "groups": groups, "tasks": tasks,
           "events": events})
}

async fn current(State(app): State<App>) -> impl IntoResponse {
    ([("content-type", "application/json")], app.state.borrow().to_string())
}

/// Server-sent events: the state each time the state thread has a new one.
async fn stream(State(app): State<App>) -> impl IntoResponse {
    let states =
        WatchStream::new(app.state).map(|state| Ok::<_, std::convert::Infallible>(Event::default().data(&*state)));
    Sse::new(states).keep_alive(KeepAlive::default())
}

#[derive(Deserialize)]
struct AxisArgs {
    /// The jog step (MoveRel), in the axis' units.
    dist: Option<f64>,
}

/// One axis command as the line the agent carries out, answered with the agent's text.
async fn axis_command(
    State(app): State<App>,
    Path((id, action)): Path<(u32, String)>,
    Query(args): Query<AxisArgs>,
) -> impl IntoResponse {
    let line = match (action.as_str(), args.dist) {
        ("enable", _) => format!("Enable({id})"),
        ("disable", _) => format!("Disable({id})"),
        ("reset", _) => format!("Reset({id})"),
        ("stop", _) => format!("Stop({id})"),
        ("jog", Some(dist)) if dist.is_finite() => format!("MoveRel({id}, {dist:?})"),
        ("jog", _) => return Err((axum::http::StatusCode::BAD_REQUEST, "jog needs a finite ?dist=".to_string())),
        _ => return Err((axum::http::StatusCode::NOT_FOUND, format!("no axis command {action}"))),
    };
    let answer = app.agent.call(&line).await;
    Ok(Json(json!({"call": line, "ok": !answer.starts_with("ERROR"), "answer": answer})))
}

/// A controller input's level as a switch wired to it sets it (`SimSetGPI`).
async fn sim_gpi(State(app): State<App>, Path((pin, level)): Path<(u8, u8)>) -> impl IntoResponse {
    if level > 1 || !(1..=ipc::messages::GPIO_PINS as u8).contains(&pin) {
        return Err((axum::http::StatusCode::BAD_REQUEST, "inputs are 1..8, levels 0 or 1".to_string()));
    }
    Ok(simulate(&app, format!("SimSetGPI({pin}, {level})"), Input::Gpi { pin, on: level == 1 }).await)
}

/// A digital I/O terminal's input as a switch wired to it sets it (`SimSetSlvGPI`).
async fn sim_slave_gpi(State(app): State<App>, Path((slave, pin, level)): Path<(u16, u16, u8)>) -> impl IntoResponse {
    if level > 1 || pin == 0 {
        return Err((axum::http::StatusCode::BAD_REQUEST, "inputs count from 1, levels are 0 or 1".to_string()));
    }
    let line = format!("SimSetSlvGPI({slave}, {pin}, {level})");
    Ok(simulate(&app, line, Input::SlvGpi { slave, pin, on: level == 1 }).await)
}

/// The word on an analog terminal's input (`SimSetSlvAIRaw`).
async fn sim_ai(State(app): State<App>, Path((slave, channel, raw)): Path<(u16, u8, u16)>) -> impl IntoResponse {
    simulate(&app, format!("SimSetSlvAIRaw({slave}, {channel}, {raw})"), Input::Ai { slave, channel, raw }).await
}

/// A simulated input: on the simulation clock queued to land at the next cycle boundary
/// (and be recorded, docs/replay.md), in real time the agent's call.
async fn simulate(app: &App, line: String, input: Input) -> Json<Value> {
    let answer = match &app.inputs {
        Some(inputs) if inputs.sim_input(input) => "queued for the next cycle".to_string(),
        Some(_) => "ERROR not taken: a replay's inputs are the record's, or the queue is full".to_string(),
        None => app.agent.call(&line).await,
    };
    Json(json!({"call": line, "ok": !answer.starts_with("ERROR"), "answer": answer}))
}

/// DXMC A.3 registers.
const DRL_REGISTERS: u16 = 0x6B00;
const ID_SELECT: u16 = 0x6B04;
const CONTROL: u16 = 0x6B05;
const STATUS: u16 = 0x6B06;

#[derive(Deserialize)]
struct DrlArgs {
    /// The DRL id to open (0x6B04).
    id: Option<u16>,
}

/// A DRL control (DXMC A.3, 0x6B05) by name, as `luamotion drl` gives them; waits until
/// the status settles and answers the registers.
async fn drl_command(State(app): State<App>, Path(op): Path<String>, Query(args): Query<DrlArgs>) -> impl IntoResponse {
    let code = match op.as_str() {
        "open" => 1,
        "run" => 2,
        "stop" => 3,
        "pause" => 4,
        "open-run" => 6,
        _ => return Err((axum::http::StatusCode::NOT_FOUND, format!("no DRL command {op}"))),
    };
    let drl = app.drl.ok_or_else(no_console)?;
    let answer = tokio::task::spawn_blocking(move || {
        let mut drl = drl.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(id) = args.id {
            write_register(&mut drl, ID_SELECT, id)?;
        }
        write_register(&mut drl, CONTROL, code)?;
        let deadline = Instant::now() + DRL_SETTLE;
        while Status::in_progress(read_registers(&mut drl, STATUS, 1)?[0]) && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(10));
        }
        drl_registers(&mut drl)
    })
    .await;
    registers_answer(answer)
}

async fn drl_status(State(app): State<App>) -> impl IntoResponse {
    let drl = app.drl.ok_or_else(no_console)?;
    let answer =
        tokio::task::spawn_blocking(move || drl_registers(&mut drl.lock().unwrap_or_else(|e| e.into_inner()))).await;
    registers_answer(answer)
}

/// The registers read after a DRL command, or why not.
fn registers_answer(
    answer: Result<Result<Value, String>, tokio::task::JoinError>,
) -> Result<Json<Value>, (axum::http::StatusCode, String)> {
    match answer {
        Ok(Ok(registers)) => Ok(Json(registers)),
        Ok(Err(e)) => Err((axum::http::StatusCode::CONFLICT, e)),
        Err(e) => Err((axum::http::StatusCode::INTERNAL_SERVER_ERROR, e.to_string())),
    }
}

fn no_console() -> (axum::http::StatusCode, String) {
    (axum::http::StatusCode::NOT_FOUND, "no DRL program control here: it is `luamotion serve`'s".into())
}

/// The DRL registers 0x6B00..0x6B06 with the names of their codes.
fn drl_registers(drl: &mut DrlHandler) -> Result<Value, String> {
    let r = read_registers(drl, DRL_REGISTERS, 7)?;
    Ok(
        json!({"id": r[0], "state": r[1], "state_name": ExecState::try_from(r[1]).ok().map_or("unknown", ExecState::name),
              "line": r[2], "speed": r[3], "status": r[6],
              "status_name": Status::try_from(r[6]).ok().map_or("unknown", Status::name)}),
    )
}

/// Modbus function 3 on the console's registers.
fn read_registers(drl: &mut DrlHandler, address: u16, count: u16) -> Result<Vec<u16>, String> {
    let [a, b] = address.to_be_bytes();
    let [c, d] = count.to_be_bytes();
    let response = drl(&[0x03, a, b, c, d]);
    match response.as_slice() {
        [0x03, _, words @ ..] if words.len() == 2 * count as usize => {
            Ok(words.chunks(2).map(|w| u16::from_be_bytes([w[0], w[1]])).collect())
        }
        _ => Err(format!("the DRL console refused to read {address:#06X}: {response:02X?}")),
    }
}

/// Modbus function 6 on one of the console's registers.
fn write_register(drl: &mut DrlHandler, address: u16, value: u16) -> Result<(), String> {
    let [a, b] = address.to_be_bytes();
    let [c, d] = value.to_be_bytes();
    let response = drl(&[0x06, a, b, c, d]);
    match response.first() {
        Some(0x06) => Ok(()),
        _ => Err(format!("the DRL console refused {value} at {address:#06X}: {response:02X?}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The state thread publishes the controller's state before it says it is ready, so
    /// the view, once announced, never answers `{}`: with its loop stopped from the start,
    /// what it published before the ready is all there is, and it has the axes.
    #[test]
    fn the_first_state_is_published_before_the_view_is_ready() {
        let ns = Namespace::new(&format!("web-first-{}", std::process::id())).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let config = config::MachineConfig {
            axes: vec![config::AxisConfig::default(); 2],
            rt: config::RtConfig { priority: 0, lock_memory: false, ..config::RtConfig::default() },
            ..config::MachineConfig::default()
        };
        let launcher = rt_core::supervisor::ScriptLauncher { executable: "/bin/false".into(), subcommand: Vec::new() };
        let options = rt_core::RunOptions::serving(ns.clone(), launcher, dir.path().to_path_buf());
        let controller = rt_core::controller::Background::start(config, options).unwrap();
        let (publish, state) = watch::channel(Arc::<str>::from("{}"));
        let (ready_tx, ready) = mpsc::channel();
        read_state(ns.clone(), publish, &AtomicBool::new(true), ready_tx);
        assert!(matches!(ready.try_recv(), Ok(Ok(()))), "the view said it was ready");
        let published: serde_json::Value = serde_json::from_str(&state.borrow()).unwrap();
        controller.stop().unwrap();
        ipc::remove_namespace_files(&ns);
        assert_eq!(published["axes"].as_array().map(Vec::len), Some(2), "{published}");
    }
}

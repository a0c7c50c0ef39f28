//! The live web view (`serve --http PORT`): one page embedded in the binary, the
//! controller's state sent to it as server-sent events 20 times a second, and its
//! commands. Axis commands are typed calls carried out by the Native ASCII agent from its
//! task slot as a client's line of them (docs/decisions.md, "Web view"), so ownership, the
//! controller state and alarms apply as to any client; DRL program control writes the registers of DXMC A.3
//! through the DRL console, as a Modbus HMI does. The state is read from the published
//! snapshot by a thread of its own: the RT thread does nothing for the page. Who may read
//! and command it is `access.rs`'s; connections are bounded in number and in the time
//! their request heads may take (machine file `[web]`).

mod access;

use std::collections::VecDeque;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, mpsc};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use access::{Access, Refusal};
use anyhow::Result;
use api::CommandCall;
use api::alarms::Alarm;
use axum::extract::{ConnectInfo, Form, FromRequest, Path, Query, Request, State};
use axum::http::{HeaderMap, StatusCode, header};
use axum::middleware::Next;
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{Html, IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use drl::ascii::Agent;
use drl::codes::{ExecState, Status};
use ipc::events::EventReader;
use ipc::task_table::TaskTable;
use ipc::{IpcError, Monitor, Namespace};
use rt_core::replay::{Input, Inputs};
use schema::{Snapshot, TaskState, motion_status};
use serde::Deserialize;
use serde_json::{Value, json};
use tokio::io::AsyncWriteExt;
use tokio::net::TcpStream;
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
    access: Arc<Access>,
}

/// A running web view: its server and the thread that reads the controller's state. Drop
/// it before the ASCII and Modbus servers whose agent and console it holds.
pub struct WebView {
    pub address: SocketAddr,
    /// What the operator is told of the view's access, after its address.
    pub access_note: &'static str,
    stop: Arc<AtomicBool>,
    runtime: Option<tokio::runtime::Runtime>,
    reader: Option<JoinHandle<()>>,
}

impl WebView {
    /// Follows the controller in `ns` and serves the page on `web.bind` at `port` (0: a
    /// free port, see `address`); `inputs`: the simulation clock's (`run --clock sim`).
    pub fn start(
        ns: Namespace,
        (web, port): (&config::WebConfig, u16),
        agent: Agent,
        drl: Option<DrlHandler>,
        inputs: Option<Arc<Inputs>>,
    ) -> Result<Self> {
        let (publish, state) = watch::channel(Arc::<str>::from("{}"));
        let stop = Arc::new(AtomicBool::new(false));
        let stopped = stop.clone();
        let reader = drl::listener::start_owner("web-state", move |ready| read_state(ns, publish, &stopped, ready))?;
        let (runtime, listener, address) = drl::listener::listen("web", &web.bind, port)?;
        let access = Access::new(address, web)?;
        let access_note = match (access.writable(), access.login()) {
            (false, _) => "read-only: not a loopback address, and the machine file sets no [web] password",
            (true, true) => "commands after the [web] password",
            (true, false) => "commands from this page only",
        };
        if !access.writable() {
            tracing::warn!(%address, "the web view is read-only: {access_note}");
        }
        let drl = drl.map(|drl| Arc::new(Mutex::new(drl)));
        let router = router(App { state, agent, drl, inputs, access: Arc::new(access) });
        let header_timeout = Duration::from_millis(web.header_timeout_ms);
        let limits =
            drl::listener::Limits { max_connections: web.max_connections as usize, idle_timeout: header_timeout };
        let serve = move |stream, peer| serve_connection(router.clone(), stream, peer, header_timeout);
        runtime.spawn(drl::listener::accept_loop(("web view", "web"), listener, limits, serve, refuse_connection));
        tracing::info!(%address, "web view up");
        Ok(WebView { address, access_note, stop, runtime: Some(runtime), reader: Some(reader) })
    }
}

/// The routes, every request (also one that matches none) behind the access check.
fn router(app: App) -> Router {
    Router::new()
        .route("/", get(page))
        .route("/api/access", get(access_state))
        .route(access::LOGIN, post(log_in))
        .route("/api/state", get(current))
        .route("/api/stream", get(stream))
        .route("/api/axis/{id}/{action}", post(axis_command))
        .route("/api/drl", get(drl_status))
        .route("/api/drl/{op}", post(drl_command))
        .route("/api/sim/gpi/{pin}/{level}", post(sim_gpi))
        .route("/api/sim/slvgpi/{slave}/{pin}/{level}", post(sim_slave_gpi))
        .route("/api/sim/ai/{slave}/{channel}/{raw}", post(sim_ai))
        .layer(axum::middleware::from_fn_with_state(app.clone(), guard))
        .with_state(app)
}

/// One HTTP/1.1 connection: closed when a request head takes longer than
/// `header_timeout` (also the wait for the next request on a kept-alive connection).
async fn serve_connection(router: Router, stream: TcpStream, peer: SocketAddr, header_timeout: Duration) {
    use tower::ServiceExt as _;
    let service = hyper::service::service_fn(move |mut request: hyper::Request<hyper::body::Incoming>| {
        request.extensions_mut().insert(ConnectInfo(peer));
        router.clone().oneshot(request)
    });
    let connection = hyper::server::conn::http1::Builder::new()
        .timer(hyper_util::rt::TokioTimer::new())
        .header_read_timeout(header_timeout)
        .serve_connection(hyper_util::rt::TokioIo::new(stream), service);
    if let Err(e) = connection.await {
        tracing::debug!(%peer, "web view connection: {e}");
    }
}

/// A connection past `[web] max_connections`: told so and closed.
async fn refuse_connection(mut stream: TcpStream) {
    const BUSY: &str = "too many connections ([web] max_connections)\n";
    let response = format!(
        "HTTP/1.1 503 Service Unavailable\r\ncontent-type: text/plain\r\ncontent-length: {}\r\nconnection: close\r\n\r\n{BUSY}",
        BUSY.len()
    );
    let _ = tokio::time::timeout(Duration::from_secs(1), stream.write_all(response.as_bytes())).await;
}

/// Every request passes the access rules first; a refusal is a 403 with its reason, logged.
async fn guard(State(app): State<App>, request: Request, next: Next) -> Response {
    match app.access.check(request.method(), request.uri().path(), request.headers()) {
        Ok(()) => next.run(request).await,
        Err(refusal) => refuse(&Asker::of(&request), refusal),
    }
}

/// Who asked what, for the log line of a refusal.
struct Asker {
    peer: Option<SocketAddr>,
    method: axum::http::Method,
    path: String,
}

impl Asker {
    fn of(request: &Request) -> Self {
        let peer = request.extensions().get::<ConnectInfo<SocketAddr>>().map(|ConnectInfo(peer)| *peer);
        Asker { peer, method: request.method().clone(), path: request.uri().path().to_string() }
    }
}

fn refuse(asker: &Asker, refusal: Refusal) -> Response {
    let Asker { peer, method, path } = asker;
    let peer = peer.map_or("-".to_string(), |peer| peer.to_string());
    tracing::warn!(peer, %method, path, "web view: {refusal}");
    (StatusCode::FORBIDDEN, format!("{refusal}\n")).into_response()
}

/// The page; on a loopback address without a password, with the token's cookie.
async fn page(State(app): State<App>) -> Response {
    match app.access.page_cookie() {
        Some(cookie) => ([(header::SET_COOKIE, cookie)], Html(PAGE)).into_response(),
        None => Html(PAGE).into_response(),
    }
}

/// What the page may do: whether the view takes commands, asks for the password, and
/// whether this page holds the token.
async fn access_state(State(app): State<App>, headers: HeaderMap) -> Json<Value> {
    let access = &app.access;
    Json(json!({"writable": access.writable(), "login": access.login(), "token": access.has_token(&headers)}))
}

#[derive(Deserialize)]
struct Login {
    password: String,
}

/// The password (a form field) for the token's cookie.
async fn log_in(State(app): State<App>, request: Request) -> Response {
    let asker = Asker::of(&request);
    let Form(login) = match Form::<Login>::from_request(request, &()).await {
        Ok(form) => form,
        Err(rejection) => return rejection.into_response(),
    };
    match app.access.log_in(&login.password) {
        Ok(()) => (StatusCode::NO_CONTENT, [(header::SET_COOKIE, app.access.cookie())]).into_response(),
        Err(refusal) => {
            // A guess costs a second.
            tokio::time::sleep(Duration::from_secs(1)).await;
            refuse(&asker, refusal)
        }
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

/// One axis command, carried out by the agent as a client's line of it; the answer names
/// the call by that line.
async fn axis_command(
    State(app): State<App>,
    Path((id, action)): Path<(u32, String)>,
    Query(args): Query<AxisArgs>,
) -> impl IntoResponse {
    let axis_id = i64::from(id);
    let call = match (action.as_str(), args.dist) {
        ("enable", _) => CommandCall::Enable { axis_id },
        ("disable", _) => CommandCall::Disable { axis_id },
        ("reset", _) => CommandCall::Reset { axis_id },
        ("stop", _) => CommandCall::Stop { axis_id },
        ("jog", Some(rel_dist)) if rel_dist.is_finite() => CommandCall::MoveRel { axis_id, rel_dist },
        ("jog", _) => return Err((axum::http::StatusCode::BAD_REQUEST, "jog needs a finite ?dist=".to_string())),
        _ => return Err((axum::http::StatusCode::NOT_FOUND, format!("no axis command {action}"))),
    };
    let line = drl::ascii::line::text(&call);
    let answer = app.agent.command(call).await;
    Ok(Json(json!({"call": line, "ok": !answer.starts_with("ERROR"), "answer": answer})))
}

/// A controller input's level as a switch wired to it sets it (`SimSetGPI`).
async fn sim_gpi(State(app): State<App>, Path((pin, level)): Path<(u8, u8)>) -> impl IntoResponse {
    if level > 1 || !(1..=schema::GPIO_PINS as u8).contains(&pin) {
        return Err((axum::http::StatusCode::BAD_REQUEST, "inputs are 1..8, levels 0 or 1".to_string()));
    }
    let call = CommandCall::SimSetGPI { gpi_idx: pin.into(), on_off: level.into() };
    Ok(simulate(&app, call, Input::Gpi { pin, on: level == 1 }).await)
}

/// A digital I/O terminal's input as a switch wired to it sets it (`SimSetSlvGPI`).
async fn sim_slave_gpi(State(app): State<App>, Path((slave, pin, level)): Path<(u16, u16, u8)>) -> impl IntoResponse {
    if level > 1 || pin == 0 {
        return Err((axum::http::StatusCode::BAD_REQUEST, "inputs count from 1, levels are 0 or 1".to_string()));
    }
    let call = CommandCall::SimSetSlvGPI { slv_slot_id: slave.into(), gpi_idx: pin.into(), on_off: level.into() };
    Ok(simulate(&app, call, Input::SlvGpi { slave, pin, on: level == 1 }).await)
}

/// The word on an analog terminal's input (`SimSetSlvAIRaw`).
async fn sim_ai(State(app): State<App>, Path((slave, channel, raw)): Path<(u16, u8, u16)>) -> impl IntoResponse {
    let call =
        CommandCall::SimSetSlvAIRaw { slv_slot_id: slave.into(), ai_idx: channel.into(), ai_raw_val: raw.into() };
    simulate(&app, call, Input::Ai { slave, channel, raw }).await
}

/// A simulated input: on the simulation clock queued to land at the next cycle boundary
/// (and be recorded, docs/replay.md), in real time the agent's `call`.
async fn simulate(app: &App, call: CommandCall<'static>, input: Input) -> Json<Value> {
    let line = drl::ascii::line::text(&call);
    let answer = match &app.inputs {
        Some(inputs) if inputs.sim_input(input) => "queued for the next cycle".to_string(),
        Some(_) => "ERROR not taken: a replay's inputs are the record's, or the queue is full".to_string(),
        None => app.agent.command(call).await,
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

    /// The token of the router benches: no generated cookie can be it by chance.
    const TOKEN: &str = "the-real-token-0123456789abcdef-XYZ";
    const HOST: &str = "127.0.0.1:8080";
    const ORIGIN: &str = "http://127.0.0.1:8080";

    /// A controller (the built-in machine and the agent's slot) for routers that serve no
    /// socket: their axis commands reach it through the agent; their DRL console counts
    /// the writes it is asked for and reads zeros.
    struct Bench {
        ns: Namespace,
        controller: Option<rt_core::controller::Background>,
        agent: Option<(Agent, drl::ascii::AgentThread)>,
        drl_writes: Arc<std::sync::atomic::AtomicUsize>,
        monitor: Monitor,
        _dir: tempfile::TempDir,
    }

    impl Bench {
        fn start(name: &str) -> Bench {
            let ns = Namespace::new(&format!("{name}-{}", std::process::id())).unwrap();
            let dir = tempfile::tempdir().unwrap();
            let config = config::MachineConfig {
                rt: config::RtConfig { priority: 0, lock_memory: false, ..config::RtConfig::default() },
                ..config::MachineConfig::default()
            };
            let config = config.with_ascii_task().unwrap();
            let agent_task = config.ascii.agent_task;
            let launcher =
                rt_core::supervisor::ScriptLauncher { executable: "/bin/false".into(), subcommand: Vec::new() };
            let options = rt_core::RunOptions::serving(ns.clone(), launcher, dir.path().to_path_buf());
            let controller = rt_core::controller::Background::start(config, options).unwrap();
            let agent = drl::ascii::start_agent(ns.clone(), agent_task, dir.path().to_path_buf()).unwrap();
            let monitor = Monitor::open(&ns).unwrap();
            let drl_writes = Arc::default();
            Bench { ns, controller: Some(controller), agent: Some(agent), drl_writes, monitor, _dir: dir }
        }

        /// A router as `WebView::start` makes it, bound to `bound` (only as its rules see it).
        fn router(&self, bound: &str, web: &config::WebConfig) -> Router {
            let writes = self.drl_writes.clone();
            let console: DrlHandler = Box::new(move |pdu: &[u8]| match pdu {
                [0x03, _, _, _, count] => [&[0x03, count * 2][..], &vec![0; *count as usize * 2]].concat(),
                _ => {
                    writes.fetch_add(1, Ordering::Relaxed);
                    pdu.to_vec()
                }
            });
            let access = Access::with_token(bound.parse().unwrap(), web, TOKEN.into());
            let (_, state) = watch::channel(Arc::<str>::from("{}"));
            let agent = self.agent.as_ref().unwrap().0.clone();
            let drl = Some(Arc::new(Mutex::new(console)));
            router(App { state, agent, drl, inputs: None, access: Arc::new(access) })
        }

        /// How many calls the agent's slot has made (its heartbeat: one per call).
        fn agent_calls(&mut self) -> u64 {
            self.monitor.refresh();
            self.monitor.table().slots[config::AsciiConfig::default().agent_task as usize].heartbeat()
        }
    }

    impl Drop for Bench {
        fn drop(&mut self) {
            drop(self.agent.take());
            if let Some(controller) = self.controller.take() {
                let _ = controller.stop();
            }
            ipc::remove_namespace_files(&self.ns);
        }
    }

    /// One request through the router, without a socket: its status and body.
    async fn answer(router: &Router, request: axum::http::Request<axum::body::Body>) -> (u16, String) {
        use tower::ServiceExt as _;
        let response = router.clone().oneshot(request).await.unwrap();
        let status = response.status().as_u16();
        // A stream's body never ends: only a finished answer is read.
        if response.headers().get(header::CONTENT_TYPE).is_some_and(|t| t == "text/event-stream") {
            return (status, String::new());
        }
        let body = axum::body::to_bytes(response.into_body(), 1 << 20).await.unwrap();
        (status, String::from_utf8_lossy(&body).into_owned())
    }

    fn request(method: &str, uri: &str, headers: &[(&str, &str)]) -> axum::http::Request<axum::body::Body> {
        let mut request = axum::http::Request::builder().method(method).uri(uri);
        for (name, value) in headers {
            request = request.header(*name, *value);
        }
        request.body(axum::body::Body::empty()).unwrap()
    }

    /// A generated request: method, path and query, and the headers the rules look at
    /// (any of them missing), never with the token.
    #[derive(Debug)]
    struct Generated {
        method: String,
        uri: String,
        host: Option<String>,
        origin: Option<String>,
        referer: Option<String>,
        cookie: Option<String>,
    }

    fn generated() -> impl proptest::strategy::Strategy<Value = Generated> {
        use proptest::prelude::*;
        use proptest::sample::select;
        let method = select(vec!["GET", "HEAD", "POST", "PUT", "DELETE", "PATCH", "OPTIONS", "TRACE", "BREW"]);
        let route = select(vec![
            "",
            "api",
            "api/state",
            "api/stream",
            "api/access",
            "api/login",
            "api/drl",
            "api/axis",
            "api/sim/gpi",
            "api/sim/slvgpi",
            "api/sim/ai",
            "index.html",
            "api/axis/0",
        ]);
        let segment = prop_oneof![
            "[0-9]{1,3}",
            "-?[0-9]{1,25}",
            "[a-z-]{1,10}",
            "%[0-9A-F]{2}[a-z]{0,3}",
            select(vec!["enable", "disable", "reset", "stop", "jog", "open", "run", "pause", "open-run", "..", ""])
                .prop_map(String::from),
        ];
        let query = prop_oneof![
            Just(String::new()),
            "\\?dist=-?[0-9]{1,6}(\\.[0-9]{1,3})?",
            "\\?id=[0-9]{1,6}",
            "\\?[a-z]{1,5}=[a-zA-Z0-9%.+-]{0,12}(&[a-z]{1,5}=[a-z0-9]{0,5})?",
            select(vec!["?dist=NaN", "?dist=inf", "?dist=1e309", "?dist=25", "?id=5", "?token=x", "?"])
                .prop_map(String::from),
        ];
        let path = (route, proptest::collection::vec(segment, 0..4), query).prop_map(|(route, segments, query)| {
            format!("/{}{query}", [&[route.to_string()][..], &segments].concat().join("/"))
        });
        let some = |values: Vec<&'static str>| select(values).prop_map(|v| Some(v.to_string()));
        let host = prop_oneof![
            some(vec![HOST, "localhost:8080", "LOCALHOST:8080", "rebind.evil.example:8080", "127.0.0.1", "[::1]:8080"]),
            Just(None),
            "[ -~]{0,20}".prop_map(Some),
        ];
        let origin = prop_oneof![
            Just(None),
            some(vec![ORIGIN, "http://localhost:8080", "http://attacker.example", "null", "https://127.0.0.1:8080"]),
            "[ -~]{0,30}".prop_map(Some),
        ];
        let referer = prop_oneof![Just(None), some(vec!["http://127.0.0.1:8080/", "http://attacker.example/", ORIGIN])];
        let cookie = prop_oneof![
            Just(None),
            some(vec!["lm_token=wrong", "lm_token=", "lm_token", "x=1; lm_token=the-real-token", "LM_TOKEN=x"]),
            Just(Some(format!("x{}={TOKEN}", access::COOKIE))),
            Just(Some(format!("{}={TOKEN}x", access::COOKIE))),
            Just(Some(format!("{}={}", access::COOKIE, &TOKEN[..TOKEN.len() - 1]))),
            Just(Some(format!("{} = {TOKEN}", access::COOKIE))),
            "lm_token=[0-9a-f]{0,64}".prop_map(Some),
            "[ -~]{0,40}".prop_map(Some),
        ];
        (method, path, host, origin, referer, cookie).prop_map(|(method, uri, host, origin, referer, cookie)| {
            Generated { method: method.into(), uri, host, origin, referer, cookie }
        })
    }

    /// 10^4 random requests against the router (methods, paths, queries, Host, Origin,
    /// Referer, Cookie): none panics, every one with a foreign Host and every write is
    /// refused with a 403 that says why, and nothing reaches the controller: the agent's
    /// slot makes no call and the DRL console gets no write. The same router then takes a
    /// write with the token, so the count could have moved.
    #[test]
    fn random_requests_without_the_token_change_nothing() {
        use proptest::test_runner::{Config, TestCaseError, TestRunner};
        let mut bench = Bench::start("web-fuzz");
        let router = bench.router(HOST, &config::WebConfig::default());
        let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
        let calls = bench.agent_calls();
        let mut runner = TestRunner::new(Config { cases: 10_000, failure_persistence: None, ..Config::default() });
        let ours = ["127.0.0.1:8080", "localhost:8080", "LOCALHOST:8080"];
        runner
            .run(&generated(), |g| {
                let Ok(uri) = axum::http::Uri::try_from(g.uri.as_str()) else { return Ok(()) };
                let mut request = axum::http::Request::builder().method(g.method.as_str()).uri(uri);
                for (name, value) in
                    [("host", &g.host), ("origin", &g.origin), ("referer", &g.referer), ("cookie", &g.cookie)]
                {
                    if let Some(value) = value {
                        request = request.header(name, value.as_str());
                    }
                }
                let request = request.body(axum::body::Body::empty()).unwrap();
                let (status, body) = runtime.block_on(answer(&router, request));
                let safe = g.method == "GET" || g.method == "HEAD";
                let our_host = g.host.as_deref().is_some_and(|h| ours.contains(&h));
                if !safe || !our_host {
                    proptest::prop_assert_eq!(status, 403, "{:?}: {}", g, body);
                    let said = body.starts_with("refused: ") || body.starts_with("read-only: ") || g.method == "HEAD";
                    proptest::prop_assert!(said, "{:?}: {}", g, body);
                }
                Ok::<(), TestCaseError>(())
            })
            .unwrap();
        assert_eq!(bench.agent_calls(), calls, "no refused request reached the agent");
        assert_eq!(bench.drl_writes.load(Ordering::Relaxed), 0, "no refused request wrote a DRL register");

        let cookie = format!("{}={TOKEN}", access::COOKIE);
        let own = [("host", HOST), ("origin", ORIGIN), ("cookie", cookie.as_str())];
        let (status, body) = runtime.block_on(answer(&router, request("POST", "/api/axis/0/reset", &own)));
        assert_eq!(status, 200, "{body}");
        assert!(bench.agent_calls() > calls, "the page's own write reached the agent");
        let (status, body) = runtime.block_on(answer(&router, request("POST", "/api/drl/stop", &own)));
        assert_eq!((status, bench.drl_writes.load(Ordering::Relaxed)), (200, 1), "{body}");
    }

    /// Bound to an address other than loopback without a password, the view is
    /// read-only: the state is served, and every write, even with the token and the page's
    /// Origin, is refused with "read-only". With a password, the login gives the token.
    #[test]
    fn a_non_loopback_bind_without_a_password_serves_read_only() {
        let mut bench = Bench::start("web-read-only");
        let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
        let calls = bench.agent_calls();
        let cookie = format!("{}={TOKEN}", access::COOKIE);
        for bound in ["192.168.1.5:8080", "0.0.0.0:8080", "[fd00::5]:8080"] {
            let router = bench.router(bound, &config::WebConfig::default());
            let host = bound.to_string();
            let origin = format!("http://{host}");
            let own = [("host", host.as_str()), ("origin", origin.as_str()), ("cookie", cookie.as_str())];
            let (status, page) = runtime.block_on(answer(&router, request("GET", "/", &own[..1])));
            assert_eq!(status, 200, "{bound}: the page");
            assert!(page.contains("<title>luamotion</title>"));
            let (status, body) = runtime.block_on(answer(&router, request("GET", "/api/access", &own[..1])));
            assert_eq!((status, body.as_str()), (200, r#"{"login":false,"token":false,"writable":false}"#));
            for path in ["/api/axis/0/enable", "/api/drl/open-run?id=5", "/api/sim/gpi/1/1", access::LOGIN] {
                let (status, body) = runtime.block_on(answer(&router, request("POST", path, &own)));
                assert_eq!(status, 403, "{bound} {path}: {body}");
                assert!(body.starts_with("read-only: the web view listens on "), "{bound} {path}: {body}");
            }
        }
        assert_eq!(
            (bench.agent_calls(), bench.drl_writes.load(Ordering::Relaxed)),
            (calls, 0),
            "nothing reached the controller"
        );

        let web = config::WebConfig { password: Some("s3cret".into()), ..config::WebConfig::default() };
        let router = bench.router("192.168.1.5:8080", &web);
        let own = [("host", "192.168.1.5:8080"), ("origin", "http://192.168.1.5:8080")];
        let response = runtime.block_on(tower::ServiceExt::oneshot(router.clone(), request("GET", "/", &own[..1])));
        assert!(response.unwrap().headers().get(header::SET_COOKIE).is_none(), "the page asks for the password first");
        let login = |password: &str| {
            let mut login = request("POST", access::LOGIN, &own);
            *login.body_mut() = axum::body::Body::from(format!("password={password}"));
            let form = "application/x-www-form-urlencoded".parse().unwrap();
            login.headers_mut().insert(header::CONTENT_TYPE, form);
            runtime.block_on(tower::ServiceExt::oneshot(router.clone(), login)).unwrap()
        };
        assert_eq!(login("s3cre").status(), 403);
        let logged_in = login("s3cret");
        assert_eq!(logged_in.status(), 204);
        let cookie = logged_in.headers()[header::SET_COOKIE].to_str().unwrap().to_string();
        assert!(cookie.starts_with(&format!("{}={TOKEN}; SameSite=Strict; HttpOnly", access::COOKIE)), "{cookie}");
        let token = cookie.split(';').next().unwrap();
        let with_token = [own[0], own[1], ("cookie", token)];
        let (status, body) = runtime.block_on(answer(&router, request("POST", "/api/axis/0/reset", &with_token)));
        assert_eq!(status, 200, "{body}");
        assert!(bench.agent_calls() > calls, "the logged-in page's write reached the agent");
    }
}

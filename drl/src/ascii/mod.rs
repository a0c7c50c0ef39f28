//! The Native ASCII server of HMPL 22.1 (port 3999): one line in, one line out. A line is
//! an HMPL call of a registry function flagged ASCII (`MoveAbs(0, 100)`, `IsEnabled(0)`);
//! the answer is its return value(s) as text, or `ERROR ...` (docs/decisions.md, "Native
//! ASCII server"). Commands go to the core as task `[ascii] agent_task`, an external slot,
//! so ownership, the controller state and alarms apply as for any task; queries read the
//! newest snapshot. One thread owns that slot and answers the connections' lines one at a
//! time, in the order they come.

pub mod line;

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::mpsc::{self, Receiver, SyncSender};
use std::thread::JoinHandle;
use std::time::Duration;

use api::call::{ArgError, Expected, Got, Value};
use api::event_rate::Throttle;
use api::strings;
use api::{CommandCall, ErrorCode, Func, FunctionSpec, LocalCall, QueryCall, SystemError, ValueType};
use calls::{query, reply, user_table, wire};
use ipc::call::Request as WireRequest;
use ipc::event_record::{EventKind, EventRecord};
use ipc::events::EventSender;
use ipc::shm::Region;
use ipc::{IpcError, Namespace, TaskEndpoint};
use schema::shared::SharedData;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio::sync::oneshot;

use crate::ServerError;
use crate::listener::{Limits, accept_loop, listen, start_owner};
use line::{Call, MAX_LINE};

/// Lines queued for the agent thread before a client is told the server is busy.
const QUEUE: usize = 64;
/// How long a refused client gets to take its error line.
const REFUSAL_WRITE: Duration = Duration::from_millis(500);
/// How long the server's end waits for the agent's call in progress; a call the stopped
/// controller will never answer (a `MoveHome` under way at Ctrl-C) leaves the agent
/// thread behind, to end with the process.
const AGENT_END: Duration = Duration::from_secs(1);

/// What the agent thread carries out: a client's line, or another front end's typed
/// command (the web view's).
enum Work {
    Line(Call),
    Command(CommandCall<'static>),
}

type Job = (Work, oneshot::Sender<String>);

/// A running Native ASCII server and its agent thread; both end when it is dropped.
pub struct Server {
    /// Where it listens (with the port chosen when 0 was asked).
    pub address: SocketAddr,
    /// For other front ends (`agent`); dropped before the runtime so the agent can end.
    jobs: Option<Agent>,
    runtime: Option<tokio::runtime::Runtime>,
    agent: Option<AgentThread>,
}

impl Server {
    /// Attaches to task slot `agent_task` of the controller in this process (`ns`, its
    /// data folder `data_dir`), then listens on `bind:port` (port 0: a free port, see
    /// `address`) within `limits`.
    pub fn start(
        (ns, data_dir): (Namespace, PathBuf),
        agent_task: u8,
        bind: &str,
        port: u16,
        limits: Limits,
    ) -> Result<Self, ServerError> {
        let (own, agent) = start_agent(ns, agent_task, data_dir)?;
        let jobs = own.0.clone();
        let (runtime, listener, address) = listen("ascii", bind, port)?;
        let serve = move |stream, peer: SocketAddr| {
            let jobs = jobs.clone();
            async move {
                match connection(stream, &jobs, limits.idle_timeout).await {
                    Ok(()) => tracing::debug!(%peer, "ASCII connection ended"),
                    Err(e) => tracing::debug!(%peer, "ASCII connection closed: {e}"),
                }
            }
        };
        let refuse = move |mut stream: TcpStream| async move {
            let line = format!("ERROR too many connections ({} open)\r\n", limits.max_connections);
            let _ = tokio::time::timeout(REFUSAL_WRITE, stream.write_all(line.as_bytes())).await;
        };
        runtime.spawn(accept_loop(("Native ASCII", "ascii"), listener, limits, serve, refuse));
        tracing::info!(%address, "Native ASCII server up");
        Ok(Server { address, jobs: Some(own), runtime: Some(runtime), agent: Some(agent) })
    }

    /// The agent, for another front end's calls (the web view): they queue with the
    /// clients' lines and go to the core from the same task slot. Every handle must be gone
    /// before the server is dropped (the agent ends when the last one goes).
    pub fn agent(&self) -> Agent {
        self.jobs.clone().expect("taken only on drop")
    }
}

/// The agent thread alone, attached to task slot `agent_task` of the controller in this
/// process (`run --http` has no ASCII listener), which saves the user table in `data_dir`:
/// its handle, and the thread, which ends once the last handle is gone.
pub fn start_agent(ns: Namespace, agent_task: u8, data_dir: PathBuf) -> Result<(Agent, AgentThread), ServerError> {
    let (jobs, inbox) = mpsc::sync_channel(QUEUE);
    let thread = start_owner("ascii-agent", move |ready| agent(ns, agent_task, data_dir, inbox, ready))?;
    Ok((Agent(jobs), AgentThread(Some(thread))))
}

/// The agent thread, joined when dropped (after its last handle is gone) for at most
/// `AGENT_END`.
pub struct AgentThread(Option<JoinHandle<()>>);

impl AgentThread {
    /// Waits for the agent to end, at most `AGENT_END`.
    pub fn join(mut self) {
        self.end();
    }

    fn end(&mut self) {
        let Some(thread) = self.0.take() else { return };
        let deadline = std::time::Instant::now() + AGENT_END;
        while !thread.is_finished() {
            if std::time::Instant::now() > deadline {
                tracing::warn!("the ASCII agent is still in a call the controller will not answer; left behind");
                return;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        let _ = thread.join();
    }
}

impl Drop for AgentThread {
    fn drop(&mut self) {
        self.end();
    }
}

/// A handle on the agent thread: a typed command is carried out as a client's line of it
/// would be (the ASCII flag, the agent's task slot, and in the core ownership and the
/// controller state), and answered with the same text.
#[derive(Clone)]
pub struct Agent(SyncSender<Job>);

impl Agent {
    /// Carries out `call` (`Enable(0)`, `MoveRel(0, 5.0)`) and answers it: the return
    /// value(s) as text, or `ERROR ...`.
    pub async fn command(&self, call: CommandCall<'static>) -> String {
        ask(&self.0, Work::Command(call)).await
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        // The runtime's end drops the last job sender: the agent thread ends.
        self.jobs = None;
        if let Some(runtime) = self.runtime.take() {
            runtime.shutdown_timeout(Duration::from_millis(200));
        }
        if let Some(agent) = self.agent.take() {
            agent.join();
        }
    }
}

#[derive(Debug, thiserror::Error)]
enum ConnectionError {
    #[error("{0}")]
    Io(#[from] std::io::Error),
    #[error("no whole line within the idle timeout")]
    Idle,
    #[error("the client takes no answers")]
    NotReading,
}

/// One client: line after line until it closes or is idle too long. A line longer than
/// `MAX_LINE` is answered with an error as soon as it is too long (a client that never
/// sends its newline learns why nothing else comes) and skipped up to its newline; the
/// connection stays. A client that sends no whole line within `idle` gets an error line
/// and is closed.
async fn connection(mut stream: TcpStream, jobs: &SyncSender<Job>, idle: Duration) -> Result<(), ConnectionError> {
    let mut line = Vec::with_capacity(MAX_LINE);
    let mut overlong = false;
    let mut chunk = [0u8; 1024];
    // A whole line within the timeout, not each byte: a client trickling is idle too.
    let mut deadline = tokio::time::Instant::now() + idle;
    loop {
        let mut answers = Vec::new();
        let Ok(read) = tokio::time::timeout_at(deadline, stream.read(&mut chunk)).await else {
            let line = format!("ERROR no whole line within {} ms, closing\r\n", idle.as_millis());
            let _ = tokio::time::timeout(REFUSAL_WRITE, stream.write_all(line.as_bytes())).await;
            return Err(ConnectionError::Idle);
        };
        let n = read?;
        if n == 0 {
            // A peer that vanishes mid-line leaves nothing to answer.
            return Ok(());
        }
        for &b in &chunk[..n] {
            if b != b'\n' {
                if line.len() < MAX_LINE {
                    line.push(b);
                } else if !std::mem::replace(&mut overlong, true) {
                    answers.extend_from_slice(format!("ERROR line longer than {MAX_LINE} bytes\r\n").as_bytes());
                }
                continue;
            }
            deadline = tokio::time::Instant::now() + idle;
            // An overlong line was answered when it grew too long.
            let parsed = (!std::mem::take(&mut overlong)).then(|| line::parse(&line));
            line.clear();
            let answer = match parsed {
                Some(Ok(call)) => ask(jobs, Work::Line(call)).await,
                None | Some(Err(line::ParseError::Empty)) => continue,
                Some(Err(e)) => format!("ERROR {e}"),
            };
            answers.extend_from_slice(answer.as_bytes());
            answers.extend_from_slice(b"\r\n");
        }
        if !answers.is_empty() {
            tokio::time::timeout(idle, stream.write_all(&answers)).await.map_err(|_| ConnectionError::NotReading)??;
        }
    }
}

/// The agent thread's answer to a call.
async fn ask(jobs: &SyncSender<Job>, work: Work) -> String {
    let (tx, rx) = oneshot::channel();
    // A full queue means the agent is far behind (a command the core holds, like MoveHome).
    if jobs.try_send((work, tx)).is_err() {
        return "ERROR server busy, try again".into();
    }
    rx.await.unwrap_or_else(|_| "ERROR the controller is gone".into())
}

/// What the agent thread holds: its slot's endpoint, the shared data, its own writer of
/// the event stream and `SendEvent`'s rate (HMPL 2.19) as a script's.
struct AgentSlot {
    ns: Namespace,
    /// The controller's data folder, where the user table is saved.
    data_dir: PathBuf,
    endpoint: TaskEndpoint,
    shared: Region<SharedData>,
    events: EventSender,
    throttle: Throttle,
}

/// The agent thread: attached to the agent slot, it answers the calls one at a time.
fn agent(ns: Namespace, task: u8, data_dir: PathBuf, inbox: Receiver<Job>, ready: mpsc::Sender<Result<(), IpcError>>) {
    let opened = TaskEndpoint::open(&ns, task, std::process::id()).and_then(|endpoint| {
        let shared = Region::<SharedData>::open(&ns, "shared")?;
        let events = endpoint.event_sender(&ns)?;
        Ok(AgentSlot { ns: ns.clone(), data_dir, endpoint, shared, events, throttle: Throttle::default() })
    });
    let Some(mut slot) = crate::listener::opened(&ready, opened) else { return };
    while let Ok((work, answer)) = inbox.recv() {
        let answer_text = match &work {
            Work::Line(call) => carry_out(&mut slot, call),
            Work::Command(call) => {
                let spec = call.func().spec();
                admit(&mut slot, spec)
                    .and_then(|()| command_answer(&mut slot.endpoint, spec, call))
                    .unwrap_or_else(|e| e)
            }
        };
        let _ = answer.send(answer_text);
    }
}

/// One call: looked up, checked against the ASCII flag and its arguments, carried out.
fn carry_out(slot: &mut AgentSlot, call: &Call) -> String {
    let Some(spec) = api::registry::find(&call.name) else {
        return format!("ERROR unknown function {}", call.name);
    };
    if let Err(refused) = admit(slot, spec) {
        return refused;
    }
    let endpoint = &mut slot.endpoint;
    let result = match spec.func {
        Func::Command(command) => api::call::from_values::<CommandCall>(command, &call.args)
            .map_err(|e| argument_error(spec, e))
            .and_then(|typed| command_answer(endpoint, spec, &typed)),
        Func::Query(q) => {
            api::call::from_values::<QueryCall>(q, &call.args).map_err(|e| argument_error(spec, e)).and_then(|typed| {
                let query::Answer(first, second) =
                    query::evaluate(&typed, endpoint.snapshot()).map_err(|code| format!("ERROR {code}"))?;
                Ok(std::iter::once(first).chain(second).map(query_text).collect::<Vec<_>>().join(" "))
            })
        }
        Func::Local(local) => api::call::from_values::<LocalCall<Value>>(local, &call.args)
            .map_err(|e| argument_error(spec, e))
            .and_then(|typed| local_value(slot, spec, typed)),
    };
    result.unwrap_or_else(|e| e)
}

/// A call of `spec` is taken only when the manual flags it ASCII; each taken call is the
/// slot's heartbeat.
fn admit(slot: &mut AgentSlot, spec: &FunctionSpec) -> Result<(), String> {
    if !spec.ascii {
        return Err(format!("ERROR {} is not available over ASCII", spec.name));
    }
    slot.endpoint.slot().beat();
    Ok(())
}

fn command_answer(endpoint: &mut TaskEndpoint, spec: &FunctionSpec, call: &CommandCall) -> Result<String, String> {
    let mut request = WireRequest::new(call.func().id());
    wire::encode(call, &mut request).map_err(|e| format!("ERROR {}: {e}", spec.name))?;
    let answer = endpoint.call(&mut request).map_err(|e: IpcError| format!("ERROR {e}"))?;
    if answer.rc != 0 {
        return Err(format!("ERROR {}", reply::explain(answer.rc)));
    }
    let values = reply::decode(call.func(), &answer).into_iter().map(|value| match value {
        reply::Value::Int(i) => i.to_string(),
        reply::Value::Double(d) => d.to_string(),
        // HMPL's TRUE and FALSE.
        reply::Value::Bool(b) => (b as i32).to_string(),
        reply::Value::Bytes(bytes) => hex(bytes),
        reply::Value::Doubles(numbers) => numbers.iter().map(f64::to_string).collect::<Vec<_>>().join(" "),
    });
    Ok(values.collect::<Vec<_>>().join(" "))
}

/// A byte buffer as an answer shows it: two hex digits a byte.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02X}")).collect::<Vec<_>>().join(" ")
}

fn query_text(value: query::Value) -> String {
    match value {
        query::Value::Int(i) => i.to_string(),
        query::Value::Double(d) => d.to_string(),
        // HMPL's TRUE and FALSE.
        query::Value::Bool(b) => (b as i32).to_string(),
        query::Value::Bytes { data, len } => hex(&data[..len as usize]),
    }
}

/// The ASCII-flagged functions a script carries out in its own process, carried out here
/// with the same code: the user table's values (in shared memory), ch. 3's pure string
/// functions and ch. 4's math, the events and the scope gate; the user table's file is a
/// task's.
fn local_value(slot: &mut AgentSlot, spec: &FunctionSpec, call: LocalCall<'_, Value>) -> Result<String, String> {
    let code = |e: SystemError| format!("ERROR {}", ErrorCode::System(e));
    let result = match call {
        LocalCall::GetTableValue { index } => {
            let value = usize::try_from(index).ok().and_then(|i| slot.shared.user_table(i));
            value.ok_or_else(|| code(SystemError::HmplArgOutOfRange))?.to_string()
        }
        LocalCall::SetTableValue { index, value } => {
            if !usize::try_from(index).is_ok_and(|i| slot.shared.set_user_table(i, value)) {
                return Err(code(SystemError::HmplArgOutOfRange));
            }
            "0".into()
        }
        // HMPL ch. 3.
        LocalCall::StringLen { str } => strings::len(&str).to_string(),
        LocalCall::IsStringEqual { str1, str2 } => i32::from(strings::equal(&str1, &str2)).to_string(),
        LocalCall::StrFindCharEx { str, char_set, complement_set } => {
            strings::find_char_ex(&str, &char_set, complement_set).to_string()
        }
        LocalCall::StrFindStr { str1, str2 } => strings::find_str(&str1, &str2).to_string(),
        LocalCall::StringToDouble { str } => strings::to_double(&str).to_string(),
        // HMPL ch. 4: pure functions of numbers, the same as a script's.
        math if api::libm::is_math(math.func()) => {
            let value = api::libm::evaluate(&math).expect("a ch. 4 function");
            match spec.returns.first() {
                Some(ValueType::Int) => (value as i64).to_string(),
                _ => value.to_string(),
            }
        }
        // HMPL 2.19: as from a task, at a script's rate.
        LocalCall::SendEvent { evt_id } => {
            let Ok(id) = u16::try_from(evt_id) else {
                return Err(code(SystemError::HmplArgOutOfRange));
            };
            slot.wait_for_event_token();
            slot.send_event(id.into())?
        }
        // HMPL 2.21: the agent thread gives the processor away for a moment.
        LocalCall::RunScheduler {} => {
            std::thread::yield_now();
            String::new()
        }
        // HMPL 2.17: the scope ring's gate and the event that says so (docs/decisions.md
        // "SetHMIScope").
        LocalCall::SetHMIScope { start } => {
            let (event, open) = match start {
                1 => (0xB2C8, true),
                0 => (0xB2C9, false),
                _ => return Err(code(SystemError::HmplArgOutOfRange)),
            };
            ipc::scope::ScopeRing::open(&slot.ns).map_err(|_| code(SystemError::HmplExecFailed))?.set_gate(open);
            slot.send_event(event)?
        }
        // HMPL 11.6/11.7: the controller's one file, as a script saves and loads it.
        LocalCall::SaveUserTable { start_idx, num_data } | LocalCall::LoadUserTable { start_idx, num_data } => {
            let range = slot
                .shared
                .user_table_range(start_idx, num_data)
                .ok_or_else(|| code(SystemError::HmplArgOutOfRange))?;
            let save = spec.func == Func::Local(api::Local::SaveUserTable);
            let result = user_table::save_or_load(save, &slot.data_dir, &slot.shared, range);
            if let Err((error, why)) = result {
                tracing::warn!("{} over ASCII: {why}", spec.name);
                return Err(code(error));
            }
            "0".into()
        }
        _ => return Err(format!("ERROR {} runs in a script only", spec.name)),
    };
    Ok(result)
}

impl AgentSlot {
    /// Waits until `SendEvent`'s rate lets another event go (HMPL 2.19, on controller time).
    fn wait_for_event_token(&mut self) {
        loop {
            let now_ms = self.endpoint.snapshot().time_in_ms;
            match self.throttle.take(now_ms) {
                Ok(()) => return,
                Err(ms) => std::thread::sleep(Duration::from_millis(ms)),
            }
        }
    }

    /// Puts event `code` on the event stream as this slot's task: "0", or the HMPL error.
    fn send_event(&mut self, code: u32) -> Result<String, String> {
        let cycle = self.endpoint.snapshot().cycle;
        let record = EventRecord::new(EventKind::Event, self.endpoint.task().into(), cycle, code, "");
        match self.events.send(&record) {
            Ok(()) => Ok("0".into()),
            Err(_) => Err(format!("ERROR {}", ErrorCode::System(SystemError::HmplExecFailed))),
        }
    }
}

/// A neutral argument error in words.
fn argument_error(spec: &FunctionSpec, error: ArgError) -> String {
    let (index, expected, got) = match error {
        ArgError::Type { index, expected, got } => (index, expected, got),
        ArgError::TooMany { takes, given } => {
            return format!("ERROR {} takes {takes} argument(s), got {given}", spec.name);
        }
    };
    let expected = match expected {
        Expected::Integer => "an integer",
        Expected::Number => "a number",
        Expected::BoolOrNumber => "a number",
        Expected::Utf8String | Expected::String => "a string",
        Expected::ByteTable | Expected::BytesOrString | Expected::Numbers => "a table",
        Expected::Function => "a function",
        Expected::Timer => "a timer",
    };
    let got = match got {
        Got::Missing | Got::Nil => "nothing".to_string(),
        Got::Bool => "a boolean".to_string(),
        Got::Int(n) => n.to_string(),
        Got::Double(n) => n.to_string(),
        Got::Str => "a string".to_string(),
        Got::List => "a table".to_string(),
        Got::Other(name) => name.to_string(),
    };
    let name = spec.args.get(index).map_or("?", |a| a.name);
    format!("ERROR {}: argument {} ({name}) must be {expected}, not {got}", spec.name, index + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A call the stopped controller never answers leaves the agent thread behind: the
    /// server's end waits `AGENT_END` for it, no longer.
    #[test]
    fn the_end_leaves_a_stuck_agent_behind() {
        let stuck = std::thread::spawn(|| std::thread::sleep(Duration::from_secs(3600)));
        let start = std::time::Instant::now();
        AgentThread(Some(stuck)).join();
        let waited = start.elapsed();
        assert!(waited >= AGENT_END && waited < AGENT_END + Duration::from_millis(500), "{waited:?}");
        let done = std::thread::spawn(|| {});
        let start = std::time::Instant::now();
        AgentThread(Some(done)).join();
        assert!(start.elapsed() < Duration::from_millis(200), "an agent that ends is joined at once");
    }
}

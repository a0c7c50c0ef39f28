//! The Native ASCII server of HMPL 22.1 (port 3999): one line in, one line out. A line is
//! an HMPL call of a registry function flagged ASCII (`MoveAbs(0, 100)`, `IsEnabled(0)`);
//! the answer is its return value(s) as text, or `ERROR ...` (docs/decisions.md, "Native
//! ASCII server"). Commands go to the core as task `[ascii] agent_task`, an external slot,
//! so ownership, the controller state and alarms apply as for any task; queries read the
//! newest snapshot. One thread owns that slot and answers the connections' lines one at a
//! time, in the order they come.

pub mod line;

use std::net::SocketAddr;
use std::sync::mpsc::{self, Receiver, SyncSender};
use std::thread::JoinHandle;
use std::time::Duration;

use api::alarms::{Alarm, Event};
use api::call::{ArgError, Expected, Got, Value};
use api::{ArgType, CommandCall, ErrorCode, Func, FunctionSpec, Local, QueryCall, SdoAbort, SystemError, ValueType};
use calls::{query, wire};
use ipc::messages::Request as WireRequest;
use ipc::shared::SharedData;
use ipc::shm::Region;
use ipc::{IpcError, Namespace, TaskEndpoint};
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

type Job = (Call, oneshot::Sender<String>);

/// A running Native ASCII server and its agent thread; both end when it is dropped.
pub struct Server {
    pub address: SocketAddr,
    /// For other front ends (`agent`); dropped before the runtime so the agent can end.
    jobs: Option<Agent>,
    runtime: Option<tokio::runtime::Runtime>,
    agent: Option<JoinHandle<()>>,
}

impl Server {
    /// Attaches to task slot `agent_task` of the controller in this process (`ns`), then
    /// listens on `bind:port` (port 0: a free port, see `address`) within `limits`.
    pub fn start(ns: Namespace, agent_task: u8, bind: &str, port: u16, limits: Limits) -> Result<Self, ServerError> {
        let (own, agent) = start_agent(ns, agent_task)?;
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
/// process (`run --http` has no ASCII listener): its handle, and the thread, which ends
/// once the last handle is gone.
pub fn start_agent(ns: Namespace, agent_task: u8) -> Result<(Agent, JoinHandle<()>), ServerError> {
    let (jobs, inbox) = mpsc::sync_channel(QUEUE);
    let thread = start_owner("ascii-agent", move |ready| agent(ns, agent_task, inbox, ready))?;
    Ok((Agent(jobs), thread))
}

/// A handle on the agent thread: a call given as an ASCII line is carried out as a
/// client's line would be, and answered with the same text.
#[derive(Clone)]
pub struct Agent(SyncSender<Job>);

impl Agent {
    /// Carries out one line (`Enable(0)`, `MoveRel(0, 5)`) and answers it: the return
    /// value(s) as text, or `ERROR ...`.
    pub async fn call(&self, text: &str) -> String {
        match line::parse(text.as_bytes()) {
            Ok(call) => ask(&self.0, call).await,
            Err(e) => format!("ERROR {e}"),
        }
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
            let _ = agent.join();
        }
    }
}

#[derive(Debug, thiserror::Error)]
enum ConnectionError {
    #[error("{0}")]
    Io(#[from] std::io::Error),
    #[error("no whole line within the idle timeout")]
    Idle,
}

/// One client: line after line until it closes or is idle too long. A line longer than
/// `MAX_LINE` is answered with an error and skipped up to its newline; the connection stays.
async fn connection(mut stream: TcpStream, jobs: &SyncSender<Job>, idle: Duration) -> Result<(), ConnectionError> {
    let mut line = Vec::with_capacity(MAX_LINE);
    let mut overlong = false;
    let mut chunk = [0u8; 1024];
    // A whole line within the timeout, not each byte: a client trickling is idle too.
    let mut deadline = tokio::time::Instant::now() + idle;
    loop {
        let mut answers = Vec::new();
        let n =
            tokio::time::timeout_at(deadline, stream.read(&mut chunk)).await.map_err(|_| ConnectionError::Idle)??;
        if n == 0 {
            // A peer that vanishes mid-line leaves nothing to answer.
            return Ok(());
        }
        for &b in &chunk[..n] {
            if b != b'\n' {
                if line.len() < MAX_LINE {
                    line.push(b);
                } else {
                    overlong = true;
                }
                continue;
            }
            deadline = tokio::time::Instant::now() + idle;
            let answer = if std::mem::take(&mut overlong) {
                format!("ERROR line longer than {MAX_LINE} bytes")
            } else {
                match line::parse(&line) {
                    Ok(call) => ask(jobs, call).await,
                    Err(line::ParseError::Empty) => {
                        line.clear();
                        continue;
                    }
                    Err(e) => format!("ERROR {e}"),
                }
            };
            line.clear();
            answers.extend_from_slice(answer.as_bytes());
            answers.extend_from_slice(b"\r\n");
        }
        if !answers.is_empty() {
            tokio::time::timeout(idle, stream.write_all(&answers)).await.map_err(|_| ConnectionError::Idle)??;
        }
    }
}

/// The agent thread's answer to a call.
async fn ask(jobs: &SyncSender<Job>, call: Call) -> String {
    let (tx, rx) = oneshot::channel();
    // A full queue means the agent is far behind (a command the core holds, like MoveHome).
    if jobs.try_send((call, tx)).is_err() {
        return "ERROR server busy, try again".into();
    }
    rx.await.unwrap_or_else(|_| "ERROR the controller is gone".into())
}

/// The agent thread: attached to the agent slot, it answers the calls one at a time.
fn agent(ns: Namespace, task: u8, inbox: Receiver<Job>, ready: mpsc::Sender<Result<(), IpcError>>) {
    let opened = TaskEndpoint::open(&ns, task, std::process::id())
        .and_then(|endpoint| Ok((endpoint, Region::<SharedData>::open(&ns, "shared")?)));
    let Some((mut endpoint, shared)) = crate::listener::opened(&ready, opened) else { return };
    while let Ok((call, answer)) = inbox.recv() {
        let _ = answer.send(carry_out(&mut endpoint, &shared, &call));
    }
}

/// One call: looked up, checked against the ASCII flag and its arguments, carried out.
fn carry_out(endpoint: &mut TaskEndpoint, shared: &SharedData, call: &Call) -> String {
    let Some(spec) = api::registry::find(&call.name) else {
        return format!("ERROR unknown function {}", call.name);
    };
    if !spec.ascii {
        return format!("ERROR {} is not available over ASCII", spec.name);
    }
    endpoint.slot().beat();
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
        Func::Local(local) => table_value(shared, spec, local, &call.args),
    };
    result.unwrap_or_else(|e| e)
}

fn command_answer(endpoint: &mut TaskEndpoint, spec: &FunctionSpec, call: &CommandCall) -> Result<String, String> {
    let mut request = WireRequest::new(call.func().id());
    wire::encode(call, &mut request).map_err(|e| format!("ERROR {}: {e}", spec.name))?;
    let reply = endpoint.call(&mut request).map_err(|e: IpcError| format!("ERROR {e}"))?;
    if reply.rc != 0 {
        return Err(format!("ERROR {}", explain(reply.rc)));
    }
    let values = spec.returns.iter().enumerate().map(|(i, ty)| match ty {
        ValueType::Double => f64::from_bits(reply.values[i]).to_string(),
        _ => (reply.values[i] as i64).to_string(),
    });
    Ok(values.collect::<Vec<_>>().join(" "))
}

/// A nonzero reply code in words: an HMPL error code, an SDO abort or an alarm.
fn explain(rc: u32) -> String {
    if let Some(code) = ErrorCode::from_code(rc) {
        return code.to_string();
    }
    if let Ok(abort) = SdoAbort::try_from(rc) {
        return abort.to_string();
    }
    let alarm = Alarm(rc);
    format!("{alarm} alarm: {}", Event::from(alarm.event_code()).meaning())
}

fn query_text(value: query::Value) -> String {
    match value {
        query::Value::Int(i) => i.to_string(),
        query::Value::Double(d) => d.to_string(),
        // HMPL's TRUE and FALSE.
        query::Value::Bool(b) => (b as i32).to_string(),
        query::Value::Bytes { data, len } => {
            data[..len as usize].iter().map(|b| format!("{b:02X}")).collect::<Vec<_>>().join(" ")
        }
    }
}

/// The ASCII-flagged functions that run in a script process: the user table's values are
/// in shared memory, so the server reads and writes them itself; its file is a script's.
fn table_value(shared: &SharedData, spec: &FunctionSpec, local: Local, args: &[Value]) -> Result<String, String> {
    use api::call::Source;
    let mut source = api::call::Values::new(args);
    let out_of_range = || format!("ERROR {}", ErrorCode::System(SystemError::HmplArgOutOfRange));
    let bad = |e| argument_error(spec, e);
    let result = match local {
        Local::GetTableValue => {
            let index = source.int().map_err(bad)?;
            let value = usize::try_from(index).ok().and_then(|i| shared.user_table(i)).ok_or_else(out_of_range)?;
            value.to_string()
        }
        Local::SetTableValue => {
            let (index, value) = (source.int().map_err(bad)?, source.double().map_err(bad)?);
            if !usize::try_from(index).is_ok_and(|i| shared.set_user_table(i, value)) {
                return Err(out_of_range());
            }
            "0".into()
        }
        // HMPL ch. 4: pure functions of numbers, the same as a script's.
        _ if api::libm::is_math(local) => {
            let numbers = spec
                .args
                .iter()
                .map(|arg| match arg.ty {
                    ArgType::Int => source.int().map(|i| i as f64),
                    _ => source.double(),
                })
                .collect::<Result<Vec<f64>, _>>()
                .map_err(bad)?;
            let value = api::libm::evaluate(local, &numbers)
                .ok_or_else(|| format!("ERROR {} takes {} argument(s)", spec.name, spec.args.len()))?;
            match spec.returns.first() {
                Some(ValueType::Int) => (value as i64).to_string(),
                _ => value.to_string(),
            }
        }
        _ if matches!(local, Local::SaveUserTable | Local::LoadUserTable) => {
            return Err(format!("ERROR {} runs in a script only (the user table's file is a task's)", spec.name));
        }
        _ => return Err(format!("ERROR {} runs in a script only", spec.name)),
    };
    if args.len() > spec.args.len() {
        return Err(bad(ArgError::TooMany { takes: spec.args.len(), given: args.len() }));
    }
    Ok(result)
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

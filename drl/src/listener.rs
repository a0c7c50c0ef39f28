//! The accept loop both TCP servers of `luamotion serve` share (Modbus, Native ASCII):
//! at most `max_connections` served at once (the excess is handed to `refuse` and
//! closed), a failed accept (out of file descriptors) retried with a back-off instead of
//! ending the server, and refusals logged at most once a second with a count.

use std::future::Future;
use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::mpsc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use ipc::IpcError;
use tokio::net::{TcpListener, TcpStream};
use tokio::runtime::Runtime;
use tokio::sync::Semaphore;

use crate::ServerError;

/// Starts the thread that owns a server's side of the controller (`run` says on `ready`
/// whether it could attach) and returns once it is ready.
pub fn start_owner(
    name: &str,
    run: impl FnOnce(mpsc::Sender<Result<(), IpcError>>) + Send + 'static,
) -> Result<JoinHandle<()>, ServerError> {
    let (ready_tx, ready_rx) = mpsc::channel();
    let owner =
        std::thread::Builder::new().name(name.into()).spawn(move || run(ready_tx)).map_err(ServerError::Runtime)?;
    let died = || ServerError::Runtime(std::io::Error::other(format!("the {name} thread died")));
    ready_rx.recv().map_err(|_| died())??;
    Ok(owner)
}

/// What an owner thread of `start_owner` opened, once it has told the starter whether it
/// could; `None` when it could not (the thread then ends).
pub fn opened<T>(ready: &mpsc::Sender<Result<(), IpcError>>, opened: Result<T, IpcError>) -> Option<T> {
    match opened {
        Ok(opened) => {
            let _ = ready.send(Ok(()));
            Some(opened)
        }
        Err(e) => {
            let _ = ready.send(Err(e));
            None
        }
    }
}

/// A one-worker tokio runtime (threads named `name`) and a listener on `bind:port` (port
/// 0: a free port), with the address it got.
pub fn listen(name: &str, bind: &str, port: u16) -> Result<(Runtime, TcpListener, SocketAddr), ServerError> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .thread_name(name)
        .enable_all()
        .build()
        .map_err(ServerError::Runtime)?;
    let listen = format!("{bind}:{port}");
    // A pair, not the text: `::1:502` is no socket address, (`::1`, 502) is.
    let listener =
        runtime.block_on(TcpListener::bind((bind, port))).map_err(|e| ServerError::Bind(listen.clone(), e))?;
    let address = listener.local_addr().map_err(|e| ServerError::Bind(listen, e))?;
    Ok((runtime, listener, address))
}

/// What one client may hold of a server (machine file `[modbus]`, `[ascii]`).
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Connections served at once; more are closed as soon as they are accepted.
    pub max_connections: usize,
    /// The longest wait for a whole request (and for a client to take its answer).
    pub idle_timeout: Duration,
}

/// The first wait after a failed accept; it doubles up to `MAX_BACKOFF`.
const MIN_BACKOFF: Duration = Duration::from_millis(10);
const MAX_BACKOFF: Duration = Duration::from_secs(1);
/// Refused connections are logged at most this often, with a count (a flood must not flood the log).
const LOG_PERIOD: Duration = Duration::from_secs(1);

/// Accepts on `listener` until the runtime stops: each connection within the limit runs
/// `serve` as its own tokio task; one past it runs `refuse` (which should be brief). `name`
/// and `section` (the machine file's) name the server in the log.
pub async fn accept_loop<S, SF, R, RF>(
    (name, section): (&'static str, &'static str),
    listener: TcpListener,
    limits: Limits,
    serve: S,
    refuse: R,
) where
    S: Fn(TcpStream, SocketAddr) -> SF,
    SF: Future<Output = ()> + Send + 'static,
    R: Fn(TcpStream) -> RF,
    RF: Future<Output = ()> + Send + 'static,
{
    let slots = Arc::new(Semaphore::new(limits.max_connections));
    let mut backoff = MIN_BACKOFF;
    let mut refused = Throttled::default();
    loop {
        let (stream, peer) = match listener.accept().await {
            Ok(accepted) => accepted,
            Err(e) => {
                // EMFILE/ENFILE end when connections close; the listener stays readable
                // meanwhile, so retrying at once would only spin.
                tracing::warn!("{name}: accept failed ({e}); retrying in {} ms", backoff.as_millis());
                tokio::time::sleep(backoff).await;
                backoff = (backoff * 2).min(MAX_BACKOFF);
                continue;
            }
        };
        backoff = MIN_BACKOFF;
        let Ok(slot) = slots.clone().try_acquire_owned() else {
            if let Some(count) = refused.tick() {
                tracing::warn!(
                    "{name}: {count} connection(s) refused, the last from {peer}: {} already open ({section}.max_connections)",
                    limits.max_connections
                );
            }
            tokio::spawn(refuse(stream));
            continue;
        };
        let connection = serve(stream, peer);
        tokio::spawn(async move {
            let _slot = slot;
            connection.await;
        });
    }
}

/// Counts events and says when to log them: at most once per `LOG_PERIOD`.
#[derive(Default)]
struct Throttled {
    count: u64,
    logged_at: Option<Instant>,
}

impl Throttled {
    fn tick(&mut self) -> Option<u64> {
        self.count += 1;
        if self.logged_at.is_some_and(|t| t.elapsed() < LOG_PERIOD) {
            return None;
        }
        self.logged_at = Some(Instant::now());
        Some(std::mem::take(&mut self.count))
    }
}

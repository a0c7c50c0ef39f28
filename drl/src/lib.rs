//! DRL projects and their program control over Modbus TCP, as on a Delta DXMC (manual
//! 8.2, 8.3 and appendix A): the register map (`registers.rs`) and its codes
//! (`codes.rs`), the projects on disk (`projects.rs`), the program control state machine
//! (`program.rs`), the console thread that owns the controller's side (`console.rs`), DH
//! kept across restarts (`retentive.rs`) and the Modbus TCP server and client
//! (`modbus.rs`).

pub mod ascii;
pub mod codes;
pub mod console;
pub mod listener;
pub mod modbus;
pub mod program;
pub mod projects;
pub mod registers;
pub(crate) mod retentive;

use std::net::SocketAddr;
use std::sync::mpsc;
use std::thread::JoinHandle;

pub use console::Setup;

/// Requests queued for the console before clients are told the device is busy.
const QUEUE: usize = 64;

/// Why a server (Modbus TCP or Native ASCII) could not start.
#[derive(Debug, thiserror::Error)]
pub enum ServerError {
    /// The address `bind:port` cannot be listened on (taken, or not this host's).
    #[error("cannot listen on {0}: {1}")]
    Bind(String, std::io::Error),
    /// The console could not attach to the controller's shared memory.
    #[error("the DRL console cannot reach the controller: {0}")]
    Ipc(#[from] ipc::IpcError),
    /// The server's tokio runtime or thread could not start.
    #[error("cannot start the Modbus server: {0}")]
    Runtime(std::io::Error),
}

/// A running Modbus server and its console thread; both end when it is dropped.
pub struct Server {
    /// Where it listens (with the port chosen when 0 was asked).
    pub address: SocketAddr,
    /// The console's requests, for Modbus on other lines (serial port 1); dropped first.
    requests: Option<mpsc::SyncSender<console::Request>>,
    runtime: Option<tokio::runtime::Runtime>,
    console: Option<JoinHandle<()>>,
}

impl Server {
    /// Starts the console for a controller that is up, then listens on `bind:port`
    /// (port 0: a free port, see `address`) within `limits`.
    pub fn start(setup: Setup, bind: &str, port: u16, limits: modbus::Limits) -> Result<Self, ServerError> {
        let (requests, inbox) = mpsc::sync_channel(QUEUE);
        let console = listener::start_owner("drl-console", move |ready| console::run(setup, inbox, ready))?;
        let (runtime, listener, address) = listener::listen("modbus", bind, port)?;
        runtime.spawn(modbus::serve(listener, requests.clone(), limits));
        tracing::info!(%address, "Modbus TCP server up");
        Ok(Server { address, requests: Some(requests), runtime: Some(runtime), console: Some(console) })
    }

    /// Answers a Modbus request PDU with the TCP server's register logic, waiting for the
    /// console. Whoever holds it must be gone before the server is dropped (the console
    /// ends when the last of these goes).
    pub fn pdu_handler(&self) -> impl FnMut(&[u8]) -> Vec<u8> + Send + 'static {
        let requests = self.requests.clone().expect("taken only on drop");
        move |pdu| modbus::answer_pdu(&requests, pdu)
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        // The runtime's end drops the last request sender: the console saves DH and ends.
        self.requests = None;
        if let Some(runtime) = self.runtime.take() {
            runtime.shutdown_timeout(std::time::Duration::from_millis(200));
        }
        if let Some(console) = self.console.take() {
            let _ = console.join();
        }
    }
}

//! The Modbus TCP server (DXMC manual 8.2: FC 03, 06 and 16, at most 10 words per request)
//! and the client `luamotion drl` uses. Each connection is served by tokio; every request
//! goes to the console thread, which answers them one at a time.

use std::future::Future;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::mpsc::SyncSender;

use tokio::sync::oneshot;
use tokio_modbus::prelude::*;
use tokio_modbus::server::tcp::{Server, accept_tcp_connection};

use crate::console::{Op, Request as ConsoleRequest};
use crate::registers::Refusal;

impl From<Refusal> for ExceptionCode {
    fn from(refusal: Refusal) -> Self {
        match refusal {
            Refusal::IllegalFunction => ExceptionCode::IllegalFunction,
            Refusal::IllegalAddress => ExceptionCode::IllegalDataAddress,
            Refusal::IllegalValue => ExceptionCode::IllegalDataValue,
        }
    }
}

/// One connection's service: the same console for every connection.
#[derive(Clone)]
struct Registers {
    console: SyncSender<ConsoleRequest>,
}

impl tokio_modbus::server::Service for Registers {
    type Request = Request<'static>;
    type Response = Response;
    type Exception = ExceptionCode;
    type Future = Pin<Box<dyn Future<Output = Result<Response, ExceptionCode>> + Send>>;

    fn call(&self, request: Self::Request) -> Self::Future {
        let console = self.console.clone();
        Box::pin(async move {
            match request {
                Request::ReadHoldingRegisters(address, count) => {
                    answer(&console, Op::Read { address, count }).await.map(Response::ReadHoldingRegisters)
                }
                Request::WriteSingleRegister(address, value) => {
                    answer(&console, Op::Write { address, values: vec![value] }).await?;
                    Ok(Response::WriteSingleRegister(address, value))
                }
                Request::WriteMultipleRegisters(address, values) => {
                    let count = values.len() as u16;
                    answer(&console, Op::Write { address, values: values.into_owned() }).await?;
                    Ok(Response::WriteMultipleRegisters(address, count))
                }
                _ => Err(ExceptionCode::IllegalFunction),
            }
        })
    }
}

async fn answer(console: &SyncSender<ConsoleRequest>, op: Op) -> Result<Vec<u16>, ExceptionCode> {
    let (tx, rx) = oneshot::channel();
    // A full queue means the console thread is far behind: the client is told the device is busy.
    console.try_send((op, tx)).map_err(|_| ExceptionCode::ServerDeviceBusy)?;
    let answer = rx.await.map_err(|_| ExceptionCode::ServerDeviceFailure)?;
    answer.map_err(ExceptionCode::from)
}

/// Serves Modbus TCP on `listener` until the runtime stops. Every unit id is answered
/// (Modbus TCP clients often send 0 or 255 for the one device behind an address).
pub async fn serve(listener: tokio::net::TcpListener, console: SyncSender<ConsoleRequest>) -> std::io::Result<()> {
    let server = Server::new(listener);
    let service = Registers { console };
    let on_connected = |stream, address: SocketAddr| {
        let service = service.clone();
        async move { accept_tcp_connection(stream, address, move |_| Ok(Some(service.clone()))) }
    };
    let on_process_error = |e| tracing::debug!("Modbus connection ended: {e}");
    server.serve(&on_connected, on_process_error).await
}

/// A Modbus TCP client of the same registers (`luamotion drl`).
pub struct Client {
    context: tokio_modbus::client::Context,
}

#[derive(Debug, thiserror::Error)]
pub enum ClientError {
    #[error("cannot reach the controller at {0}: {1}")]
    Connect(SocketAddr, std::io::Error),
    #[error("Modbus: {0}")]
    Transport(#[from] tokio_modbus::Error),
    #[error("the controller answered with exception {0:?}")]
    Exception(ExceptionCode),
}

impl Client {
    pub async fn connect(address: SocketAddr, station: u8) -> Result<Self, ClientError> {
        let context = tokio_modbus::client::tcp::connect_slave(address, Slave(station))
            .await
            .map_err(|e| ClientError::Connect(address, e))?;
        Ok(Client { context })
    }

    pub async fn read(&mut self, address: u16, count: u16) -> Result<Vec<u16>, ClientError> {
        self.context.read_holding_registers(address, count).await?.map_err(ClientError::Exception)
    }

    pub async fn write(&mut self, address: u16, values: &[u16]) -> Result<(), ClientError> {
        match values {
            [one] => self.context.write_single_register(address, *one).await?,
            _ => self.context.write_multiple_registers(address, values).await?,
        }
        .map_err(ClientError::Exception)
    }
}

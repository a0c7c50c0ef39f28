//! The Modbus TCP server (DXMC manual 8.2: FC 03, 06 and 16, at most 10 words per request),
//! its PDUs answered for Modbus RTU too (`answer_pdu`), and the client `luamotion drl` uses. Every request goes to the console thread, which
//! answers them one at a time.
//!
//! The server reads the frames itself (MBAP header, then the PDU) rather than through
//! tokio-modbus's server, which closes a connection on any frame it cannot decode: the
//! Modbus Application Protocol (v1.1b3, 6 and 7) wants an exception for those. Only a
//! header that cannot be answered (protocol id not 0, a length outside 2..254) closes.
//! Resources are bounded: at most `max_connections` at once (the excess is accepted and
//! closed at once), a whole frame must arrive within the idle timeout, and a failed
//! accept (out of file descriptors) is retried with a back-off instead of ending the server.

use std::net::SocketAddr;
use std::sync::mpsc::SyncSender;
use std::time::Duration;

use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt};
use tokio::net::TcpListener;
use tokio::sync::oneshot;
use tokio_modbus::prelude::*;

use crate::console::{Answer, Op, Request as ConsoleRequest};
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

pub use crate::listener::Limits;

/// Serves Modbus TCP on `listener` until the runtime stops. Every unit id is answered
/// (Modbus TCP clients often send 0 or 255 for the one device behind an address).
pub(crate) async fn serve(listener: TcpListener, console: SyncSender<ConsoleRequest>, limits: Limits) {
    let serve = move |stream, peer: SocketAddr| {
        let console = console.clone();
        async move {
            match connection(stream, &console, limits.idle_timeout).await {
                Ok(()) => tracing::debug!(%peer, "Modbus connection ended"),
                Err(e) => tracing::debug!(%peer, "Modbus connection closed: {e}"),
            }
        }
    };
    // The excess is closed at once: Modbus has no frame to say why.
    crate::listener::accept_loop(("Modbus", "modbus"), listener, limits, serve, |stream| async move { drop(stream) })
        .await
}

/// MBAP header (Modbus TCP): transaction id, protocol id, length, unit id.
const HEADER: usize = 7;
/// The largest PDU (Modbus Application Protocol 4.1): 253 bytes, so the length field
/// (unit id + PDU) is at most 254.
const MAX_PDU: usize = 253;

#[derive(Debug, thiserror::Error)]
enum ConnectionError {
    #[error("{0}")]
    Io(#[from] std::io::Error),
    #[error("no whole request within the idle timeout")]
    Idle,
    #[error("MBAP header with protocol id {protocol} and length {length} cannot be answered")]
    Header { protocol: u16, length: u16 },
}

/// One client: frame after frame until it closes, sends a header that cannot be
/// answered, or is idle too long.
async fn connection(
    mut stream: impl AsyncRead + AsyncWrite + Unpin,
    console: &SyncSender<ConsoleRequest>,
    idle: Duration,
) -> Result<(), ConnectionError> {
    let mut frame = [0u8; HEADER + MAX_PDU];
    loop {
        // The whole frame within the timeout, not each byte: a client trickling a
        // byte at a time is idle too.
        let Some(pdu_len) = tokio::time::timeout(idle, read_frame(&mut stream, &mut frame))
            .await
            .map_err(|_| ConnectionError::Idle)??
        else {
            return Ok(());
        };
        let pdu = &frame[HEADER..HEADER + pdu_len];
        let response = match decode(pdu) {
            Ok(request) => answer(console, pdu[0], request).await,
            Err(exception) => Err(exception),
        };
        let response = encode(&frame[..HEADER], pdu[0], response);
        tokio::time::timeout(idle, stream.write_all(&response)).await.map_err(|_| ConnectionError::Idle)??;
    }
}

/// Reads one frame into `frame`; its PDU length, or `None` when the client closed
/// between frames.
async fn read_frame(stream: &mut (impl AsyncRead + Unpin), frame: &mut [u8]) -> Result<Option<usize>, ConnectionError> {
    match stream.read_exact(&mut frame[..HEADER]).await {
        Ok(_) => {}
        Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => return Ok(None),
        Err(e) => return Err(e.into()),
    }
    let protocol = u16::from_be_bytes([frame[2], frame[3]]);
    let length = u16::from_be_bytes([frame[4], frame[5]]);
    // A length below 2 has no function code to answer an exception for.
    if protocol != 0 || !(2..=MAX_PDU as u16 + 1).contains(&length) {
        return Err(ConnectionError::Header { protocol, length });
    }
    let pdu_len = length as usize - 1;
    stream.read_exact(&mut frame[HEADER..HEADER + pdu_len]).await?;
    Ok(Some(pdu_len))
}

/// A request the console answers, or the exception its PDU earns: 01 for a function
/// other than 03, 06 and 16; 03 for a PDU whose length, quantity or byte count is wrong
/// for its function (Modbus Application Protocol 6.3, 6.6, 6.12).
fn decode(pdu: &[u8]) -> Result<Op, ExceptionCode> {
    let word = |i: usize| u16::from_be_bytes([pdu[i], pdu[i + 1]]);
    match pdu[0] {
        0x03 if pdu.len() == 5 && (1..=125).contains(&word(3)) => Ok(Op::Read { address: word(1), count: word(3) }),
        0x06 if pdu.len() == 5 => Ok(Op::Write { address: word(1), values: vec![word(3)] }),
        0x10 if pdu.len() >= 6 => {
            let count = word(3) as usize;
            let bytes = pdu[5] as usize;
            if !(1..=123).contains(&count) || bytes != 2 * count || pdu.len() != 6 + bytes {
                return Err(ExceptionCode::IllegalDataValue);
            }
            Ok(Op::Write { address: word(1), values: (0..count).map(|i| word(6 + 2 * i)).collect() })
        }
        0x03 | 0x06 | 0x10 => Err(ExceptionCode::IllegalDataValue),
        _ => Err(ExceptionCode::IllegalFunction),
    }
}

/// What a request answers: the words read, or the write echoed as the protocol says.
enum Answered {
    Read(Vec<u16>),
    Written { address: u16, value_or_count: u16 },
}

async fn answer(console: &SyncSender<ConsoleRequest>, function: u8, op: Op) -> Result<Answered, ExceptionCode> {
    let (reply, echo) = submit(console, function, op)?;
    answered(reply.await, echo)
}

/// How a write is echoed: its address and its value (FC 06) or count (FC 16).
type Echo = Option<(u16, u16)>;

/// Queues `op` (of function code `function`) with the console.
fn submit(
    console: &SyncSender<ConsoleRequest>,
    function: u8,
    op: Op,
) -> Result<(oneshot::Receiver<Answer>, Echo), ExceptionCode> {
    let (tx, rx) = oneshot::channel();
    // By the function code, not the number of words: an FC 16 of one register echoes 1.
    let echo = match &op {
        Op::Read { .. } => None,
        Op::Write { address, values } if function == 0x06 => Some((*address, values[0])),
        Op::Write { address, values } => Some((*address, values.len() as u16)),
    };
    // A full queue means the console thread is far behind: the client is told the device is busy.
    console.try_send((op, tx)).map_err(|_| ExceptionCode::ServerDeviceBusy)?;
    Ok((rx, echo))
}

fn answered(answer: Result<Answer, oneshot::error::RecvError>, echo: Echo) -> Result<Answered, ExceptionCode> {
    let words = answer.map_err(|_| ExceptionCode::ServerDeviceFailure)?.map_err(ExceptionCode::from)?;
    Ok(match echo {
        None => Answered::Read(words),
        Some((address, value_or_count)) => Answered::Written { address, value_or_count },
    })
}

/// A request PDU answered by the console, waiting for it (Modbus RTU on serial port 1:
/// the same register logic and exceptions as Modbus TCP, outside an async runtime).
pub(crate) fn answer_pdu(console: &SyncSender<ConsoleRequest>, pdu: &[u8]) -> Vec<u8> {
    let Some(&function) = pdu.first() else { return Vec::new() };
    let response = decode(pdu)
        .and_then(|op| submit(console, function, op))
        .and_then(|(reply, echo)| answered(reply.blocking_recv(), echo));
    response_pdu(function, response)
}

/// The response frame: the request's header with the new length, then the PDU. An
/// exception carries the function code with bit 7 set (a code that has it already keeps it).
fn encode(header: &[u8], function: u8, response: Result<Answered, ExceptionCode>) -> Vec<u8> {
    let pdu = response_pdu(function, response);
    let mut frame = Vec::with_capacity(HEADER + pdu.len());
    frame.extend(&header[..4]);
    frame.extend((pdu.len() as u16 + 1).to_be_bytes());
    frame.push(header[6]);
    frame.extend(pdu);
    frame
}

/// The response PDU: the words read, the write echoed, or the exception.
fn response_pdu(function: u8, response: Result<Answered, ExceptionCode>) -> Vec<u8> {
    let mut pdu = Vec::with_capacity(MAX_PDU);
    match response {
        Ok(Answered::Read(words)) => {
            pdu.extend([function, (words.len() * 2) as u8]);
            pdu.extend(words.iter().flat_map(|w| w.to_be_bytes()));
        }
        Ok(Answered::Written { address, value_or_count }) => {
            pdu.push(function);
            pdu.extend(address.to_be_bytes());
            pdu.extend(value_or_count.to_be_bytes());
        }
        Err(exception) => pdu.extend([function | 0x80, u8::from(exception)]),
    }
    pdu
}

/// A Modbus TCP client of the same registers (`luamotion drl`).
pub struct Client {
    context: tokio_modbus::client::Context,
}

/// Why a Modbus request of the client failed.
#[derive(Debug, thiserror::Error)]
pub enum ClientError {
    /// No TCP connection to the server at this address.
    #[error("cannot reach the controller at {0}: {1}")]
    Connect(SocketAddr, std::io::Error),
    /// The connection failed during the request.
    #[error("Modbus: {0}")]
    Transport(#[from] tokio_modbus::Error),
    /// The server answered with a Modbus exception (an illegal address or value).
    #[error("the controller answered with exception {0:?}")]
    Exception(ExceptionCode),
}

impl Client {
    /// Connects to the server at `address` as unit `station` (`[modbus] station`).
    pub async fn connect(address: SocketAddr, station: u8) -> Result<Self, ClientError> {
        let context = tokio_modbus::client::tcp::connect_slave(address, Slave(station))
            .await
            .map_err(|e| ClientError::Connect(address, e))?;
        Ok(Client { context })
    }

    /// Reads `count` holding registers from `address` (function 03).
    pub async fn read(&mut self, address: u16, count: u16) -> Result<Vec<u16>, ClientError> {
        self.context.read_holding_registers(address, count).await?.map_err(ClientError::Exception)
    }

    /// Writes `values` from `address`: function 06 for one register, 16 for more.
    pub async fn write(&mut self, address: u16, values: &[u16]) -> Result<(), ClientError> {
        match values {
            [one] => self.context.write_single_register(address, *one).await?,
            _ => self.context.write_multiple_registers(address, values).await?,
        }
        .map_err(ClientError::Exception)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pdus_decode_or_earn_their_exception() {
        let read = decode(&[0x03, 0x6B, 0x00, 0x00, 0x07]);
        assert!(matches!(read, Ok(Op::Read { address: 0x6B00, count: 7 })), "{read:?}");
        let write = decode(&[0x10, 0x00, 0x10, 0x00, 0x02, 0x04, 0x00, 0x01, 0x00, 0x02]);
        assert!(matches!(&write, Ok(Op::Write { address: 0x10, values }) if values == &[1, 2]), "{write:?}");
        let value = ExceptionCode::IllegalDataValue;
        let function = ExceptionCode::IllegalFunction;
        let rows: [(&[u8], ExceptionCode); 10] = [
            (&[0x03, 0x00, 0x00], value),                               // short PDU
            (&[0x03, 0x00, 0x00, 0x00, 0x01, 0x00], value),             // one byte too many
            (&[0x03, 0x00, 0x00, 0x00, 0x00], value),                   // quantity 0
            (&[0x06, 0x00, 0x00, 0x00], value),                         // short PDU
            (&[0x10, 0x00, 0x00, 0x00, 0x01, 0x04, 0x00, 0x01], value), // byte count != 2 x quantity
            (&[0x10, 0x00, 0x00, 0x80, 0x00, 0x00], value),             // quantity 0x8000 (2 x quantity overflows u16)
            (&[0x10, 0x00, 0x00, 0x00, 0x00, 0x00], value),             // quantity 0
            (&[0x2B, 0x0E, 0x01, 0x00], function),                      // read device identification
            (&[0x41], function),                                        // user-defined code
            (&[0x81, 0x00, 0x00, 0x00, 0x01], function),                // an exception code as a request
        ];
        for (pdu, exception) in rows {
            assert_eq!(decode(pdu).err(), Some(exception), "{pdu:02X?}");
        }
    }

    #[test]
    fn exceptions_set_bit_7_of_the_function_code() {
        let header = [0x12, 0x34, 0, 0, 0, 2, 0xFF];
        let frame = encode(&header, 0x41, Err(ExceptionCode::IllegalFunction));
        assert_eq!(frame, [0x12, 0x34, 0, 0, 0, 3, 0xFF, 0xC1, 0x01]);
        assert_eq!(encode(&header, 0xC1, Err(ExceptionCode::IllegalFunction))[7], 0xC1);
        let frame = encode(&header, 0x03, Ok(Answered::Read(vec![0x0102, 0x0304])));
        assert_eq!(frame, [0x12, 0x34, 0, 0, 0, 7, 0xFF, 0x03, 4, 1, 2, 3, 4]);
    }

    /// A write is echoed by its function code: FC 06 its value, FC 16 its count, also of
    /// one register (a client checks the count it sent).
    #[test]
    fn writes_echo_value_or_count_by_function_code() {
        let (console, requests) = std::sync::mpsc::sync_channel::<ConsoleRequest>(4);
        let server = std::thread::spawn(move || {
            for (_, reply) in requests {
                let _ = reply.send(Ok(Vec::new()));
            }
        });
        let rows: [(&[u8], &[u8]); 3] = [
            (&[0x06, 0x01, 0x00, 0x00, 0x07], &[0x06, 0x01, 0x00, 0x00, 0x07]),
            (&[0x10, 0x01, 0x00, 0x00, 0x01, 0x02, 0x00, 0x07], &[0x10, 0x01, 0x00, 0x00, 0x01]),
            (&[0x10, 0x01, 0x00, 0x00, 0x02, 0x04, 0x00, 0x07, 0x00, 0x08], &[0x10, 0x01, 0x00, 0x00, 0x02]),
        ];
        for (request, response) in rows {
            assert_eq!(answer_pdu(&console, request), response, "{request:02X?}");
        }
        drop(console);
        server.join().unwrap();
    }
}

/// Property tests of the Modbus TCP decoder: whatever a client sends, the server never
/// panics, answers each frame it can frame with a well-formed response carrying the
/// request's transaction and unit id, and hands the console only the requests it decoded.
/// 10^4 cases each, a fixed budget.
#[cfg(test)]
mod fuzz {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicUsize, Ordering};

    use proptest::prelude::*;

    use super::*;

    fn config() -> ProptestConfig {
        ProptestConfig { cases: 10_000, failure_persistence: None, ..ProptestConfig::default() }
    }

    /// A console that answers every request (reads with zeros) and counts them.
    fn console() -> (SyncSender<ConsoleRequest>, Arc<AtomicUsize>, std::thread::JoinHandle<()>) {
        let (console, requests) = std::sync::mpsc::sync_channel::<ConsoleRequest>(16);
        let served = Arc::new(AtomicUsize::new(0));
        let count = served.clone();
        let thread = std::thread::spawn(move || {
            for (op, reply) in requests {
                count.fetch_add(1, Ordering::Relaxed);
                let words = match op {
                    Op::Read { count, .. } => vec![0; count as usize],
                    Op::Write { .. } => Vec::new(),
                };
                let _ = reply.send(Ok(words));
            }
        });
        (console, served, thread)
    }

    /// The frames of `bytes` as MBAP (v1.1b3, 4.1) cuts them: header, then length - 1 PDU
    /// bytes; framing stops at a header that cannot be answered or an unfinished frame.
    fn frames(bytes: &[u8]) -> Vec<(&[u8], &[u8])> {
        let mut out = Vec::new();
        let mut rest = bytes;
        while rest.len() >= HEADER {
            let (header, tail) = rest.split_at(HEADER);
            let length = u16::from_be_bytes([header[4], header[5]]) as usize;
            if header[2..4] != [0, 0] || !(2..=MAX_PDU + 1).contains(&length) || tail.len() < length - 1 {
                break;
            }
            out.push((header, &tail[..length - 1]));
            rest = &tail[length - 1..];
        }
        out
    }

    /// A request frame of a function the server serves, right or nearly right.
    fn request() -> impl Strategy<Value = Vec<u8>> {
        let pdu = prop_oneof![
            (any::<u16>(), 0u16..130).prop_map(|(a, n)| [&[0x03][..], &a.to_be_bytes(), &n.to_be_bytes()].concat()),
            (any::<u16>(), any::<u16>()).prop_map(|(a, v)| [&[0x06][..], &a.to_be_bytes(), &v.to_be_bytes()].concat()),
            (any::<u16>(), proptest::collection::vec(any::<u16>(), 0..126)).prop_map(|(a, values)| {
                let mut pdu = vec![0x10];
                pdu.extend(a.to_be_bytes());
                pdu.extend((values.len() as u16).to_be_bytes());
                pdu.push((values.len() * 2) as u8);
                pdu.extend(values.iter().flat_map(|v| v.to_be_bytes()));
                pdu
            }),
            proptest::collection::vec(any::<u8>(), 1..40),
        ];
        (any::<u16>(), any::<u8>(), pdu).prop_map(|(transaction, unit, pdu)| {
            let mut frame = transaction.to_be_bytes().to_vec();
            frame.extend([0, 0]);
            frame.extend((pdu.len() as u16 + 1).to_be_bytes());
            frame.push(unit);
            frame.extend(pdu);
            frame
        })
    }

    /// A client's bytes: requests, bytes at random, or both.
    fn stream() -> impl Strategy<Value = Vec<u8>> {
        prop_oneof![
            proptest::collection::vec(request(), 0..6).prop_map(|r| r.concat()),
            proptest::collection::vec(any::<u8>(), 0..300),
            (proptest::collection::vec(request(), 0..4), proptest::collection::vec(any::<u8>(), 0..40))
                .prop_map(|(r, tail)| [r.concat(), tail].concat()),
        ]
    }

    proptest! {
        #![proptest_config(config())]

        /// Any PDU: `answer_pdu` gives a response of the same function (bit 7 set for an
        /// exception, two bytes) and asks the console only for a request it decoded.
        #[test]
        fn any_pdu_is_answered_or_refused(pdu in proptest::collection::vec(any::<u8>(), 0..300)) {
            let (console, served, thread) = console();
            let response = answer_pdu(&console, &pdu);
            drop(console);
            thread.join().unwrap();
            let Some(&function) = pdu.first() else {
                prop_assert!(response.is_empty());
                return Ok(());
            };
            let decoded = decode(&pdu).is_ok();
            prop_assert_eq!(served.load(Ordering::Relaxed), usize::from(decoded));
            if decoded {
                prop_assert_eq!(response[0], function);
            } else {
                prop_assert_eq!(response.len(), 2);
                prop_assert_eq!(response[0], function | 0x80);
            }
        }

        /// Any bytes on a connection: one response per frame, each with its request's
        /// transaction id, protocol 0, a length that matches and its unit id; a read's
        /// byte count is twice its quantity; the console sees only what was answered.
        #[test]
        fn any_stream_is_framed_and_answered(bytes in stream()) {
            let (console, served, thread) = console();
            let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
            let (mut client, server) = tokio::io::duplex(64 * 1024);
            let responses = runtime.block_on(async {
                let serving = connection(server, &console, Duration::from_secs(5));
                let talking = async {
                    client.write_all(&bytes).await.unwrap();
                    client.shutdown().await.unwrap();
                    let mut out = Vec::new();
                    client.read_to_end(&mut out).await.unwrap();
                    out
                };
                let (ended, out) = tokio::join!(serving, talking);
                prop_assert!(!matches!(ended, Err(ConnectionError::Idle)), "{ended:?}");
                Ok(out)
            })?;
            drop(console);
            thread.join().unwrap();
            let requests = frames(&bytes);
            let answers = frames(&responses);
            prop_assert_eq!(answers.iter().map(|(h, p)| h.len() + p.len()).sum::<usize>(), responses.len());
            prop_assert_eq!(answers.len(), requests.len());
            let mut answered = 0;
            for ((request, asked), (response, pdu)) in requests.iter().zip(&answers) {
                prop_assert_eq!(&request[..4], &response[..4]);
                prop_assert_eq!(request[6], response[6]);
                prop_assert_eq!(pdu[0] & 0x7F, asked[0] & 0x7F);
                if pdu.len() == 2 {
                    prop_assert_eq!(pdu[0], asked[0] | 0x80);
                    continue;
                }
                answered += 1;
                if asked[0] == 0x03 {
                    prop_assert_eq!(pdu[1] as usize, 2 * u16::from_be_bytes([asked[3], asked[4]]) as usize);
                }
            }
            prop_assert_eq!(served.load(Ordering::Relaxed), answered);
        }
    }
}

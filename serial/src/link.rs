//! How scripts reach serial port 1: a Unix stream socket in the abstract namespace,
//! `lm.<ns>.serial1` (no file to clean up, gone with the controller), and a request/reply
//! protocol of one small message each way: `op, length (u16 LE), payload` in,
//! `code, length (u16 LE), payload` out.

use std::io::{self, Read, Write};
use std::os::linux::net::SocketAddrExt;
use std::os::unix::net::{SocketAddr, UnixStream};
use std::time::{Duration, Instant};

use crate::format::End;

/// DXMC 8.3: "0 = success, other = error" with no list. The numbers up to 8 are those of
/// `FreePort.Eth` (docs/decisions.md); 9 on are the serial port's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Code {
    /// DXMC 8.3: success.
    Ok = 0,
    /// A start or end byte that is not one, a protocol that is not a FreePort code, a
    /// message with no bytes.
    BadArgument = 1,
    /// More than 256 bytes to send, or a received frame longer than that (dropped).
    TooLong = 6,
    /// A port other than 1 (DXMC 8.3: only port 1).
    NoSuchPort = 9,
    /// No serial port: the controller has none (`[serial] enabled = false`) or is gone.
    Unavailable = 10,
    /// Bytes arrived with a character frame or baud rate other than the port's (a
    /// real UART sees framing and parity errors): dropped.
    LineError = 11,
    /// Frames arrived while the receive queue was full: the newest were dropped.
    Overrun = 12,
    /// The port speaks Modbus (parameter 5-1): `FreePort.Serial.Init` first.
    NotFreePort = 13,
}

impl Code {
    const ALL: [Code; 8] = [
        Code::Ok,
        Code::BadArgument,
        Code::TooLong,
        Code::NoSuchPort,
        Code::Unavailable,
        Code::LineError,
        Code::Overrun,
        Code::NotFreePort,
    ];

    /// A code from the wire; one this side does not know means the port is no use.
    fn from_u8(b: u8) -> Code {
        Code::ALL.into_iter().find(|c| *c as u8 == b).unwrap_or(Code::Unavailable)
    }
}

/// DXMC 8.3 packet table: at most 256 data bytes a serial frame.
pub const MAX_DATA: usize = 256;

/// The socket's name for a namespace.
pub fn socket_name(ns: &str) -> String {
    format!("lm.{ns}.serial1")
}

/// The socket's address in the abstract namespace.
pub(crate) fn socket_addr(ns: &str) -> io::Result<SocketAddr> {
    SocketAddr::from_abstract_name(socket_name(ns))
}

/// A script's request to the port: one per `FreePort.Serial` function (DXMC 8.3).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Op {
    /// Switch to FreePort with these delimiters and protocol (`None`: the line's frame),
    /// clearing the receive buffer.
    Init {
        /// The start byte (5-5's YX), `None` for none.
        start: Option<u8>,
        /// The end of a frame (5-5's nibble B and UZ).
        end: End,
        /// A FreePort code of parameter 5-1.
        protocol: Option<u8>,
    },
    /// `FreePort.Serial.Tx`: send these data bytes as one frame.
    Tx(Vec<u8>),
    /// `FreePort.Serial.Rx`: the next received frame, if any.
    Rx,
}

impl Op {
    /// The request as a message on the socket.
    pub(crate) fn encode(&self) -> Vec<u8> {
        let (op, payload) = match self {
            Op::Init { start, end, protocol } => {
                let (end_kind, end_byte) = match end {
                    End::None => (0, 0),
                    End::Byte(b) => (1, *b),
                    End::CrLf => (2, 0),
                };
                let flags = u8::from(start.is_some()) | u8::from(protocol.is_some()) << 1;
                (1, vec![flags, start.unwrap_or(0), end_kind, end_byte, protocol.unwrap_or(0)])
            }
            Op::Tx(data) => (2, data.clone()),
            Op::Rx => (3, Vec::new()),
        };
        message(op, &payload)
    }

    /// The request in a message's op and payload; `None` for one this side cannot read.
    pub fn decode(op: u8, payload: &[u8]) -> Option<Op> {
        match (op, payload) {
            (1, &[flags, start, end_kind, end_byte, protocol]) => Some(Op::Init {
                start: (flags & 1 != 0).then_some(start),
                end: match end_kind {
                    0 => End::None,
                    1 => End::Byte(end_byte),
                    2 => End::CrLf,
                    _ => return None,
                },
                protocol: (flags & 2 != 0).then_some(protocol),
            }),
            (2, data) => Some(Op::Tx(data.to_vec())),
            (3, []) => Some(Op::Rx),
            _ => None,
        }
    }
}

/// One message: a leading byte, the payload's length and the payload.
pub fn message(first: u8, payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(3 + payload.len());
    out.push(first);
    out.extend((payload.len() as u16).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

/// The first whole message at the front of `buf`: its leading byte, payload and length.
pub fn split(buf: &[u8]) -> Option<(u8, &[u8], usize)> {
    let len = u16::from_le_bytes([*buf.get(1)?, *buf.get(2)?]) as usize;
    let payload = buf.get(3..3 + len)?;
    Some((buf[0], payload, 3 + len))
}

/// A script's connection to the port.
pub struct Client {
    stream: UnixStream,
}

/// How long a request may wait for its reply in all (the port answers at once; this
/// bounds a controller that hangs).
const REPLY_TIMEOUT: Duration = Duration::from_secs(1);

impl Client {
    /// Connects to serial port 1 of the controller of namespace `ns`.
    pub fn connect(ns: &str) -> io::Result<Client> {
        let stream = UnixStream::connect_addr(&socket_addr(ns)?)?;
        Ok(Client { stream })
    }

    /// Sends `op` and waits for its reply in slices of `slice`, calling `between` after
    /// each (the heartbeat). An error means the connection is no use any more.
    pub fn request(&mut self, op: &Op, slice: Duration, mut between: impl FnMut()) -> io::Result<(Code, Vec<u8>)> {
        self.stream.set_write_timeout(Some(REPLY_TIMEOUT))?;
        self.stream.write_all(&op.encode())?;
        self.stream.set_read_timeout(Some(slice))?;
        let deadline = Instant::now() + REPLY_TIMEOUT;
        let mut buf = Vec::with_capacity(3 + MAX_DATA);
        let mut chunk = [0u8; 512];
        loop {
            if let Some((code, payload, _)) = split(&buf) {
                return Ok((Code::from_u8(code), payload.to_vec()));
            }
            match self.stream.read(&mut chunk) {
                Ok(0) => return Err(io::ErrorKind::UnexpectedEof.into()),
                Ok(n) => buf.extend_from_slice(&chunk[..n]),
                Err(e) if matches!(e.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut) => {
                    between();
                    if Instant::now() >= deadline {
                        return Err(e);
                    }
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_survive_the_wire() {
        let ops = [
            Op::Init { start: Some(b':'), end: End::Byte(b';'), protocol: None },
            Op::Init { start: None, end: End::CrLf, protocol: Some(0x0C) },
            Op::Tx(b"3.1415".to_vec()),
            Op::Rx,
        ];
        for op in ops {
            let wire = op.encode();
            let (first, payload, len) = split(&wire).unwrap();
            assert_eq!(len, wire.len());
            assert_eq!(Op::decode(first, payload), Some(op));
        }
        assert_eq!(split(&[2, 5, 0, 1]), None);
        assert_eq!(Op::decode(1, &[0, 0, 3, 0, 0]), None);
    }
}

//! What a `FreePort.Eth` session's socket brings a program on the simulation clock, as the
//! script process records it and the controller's record keeps it (`<cycle> eth <task>
//! <session> <event>`, docs/replay.md).

use std::fmt;

/// One input of a session.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EthEvent {
    /// The client's connect succeeded, or the server took a peer.
    Connect,
    /// An open failed (the peer refused, the port was taken).
    Refused,
    /// Bytes from the peer.
    Data(Vec<u8>),
    /// The peer ended its stream.
    End,
}

impl EthEvent {
    /// The words after `<session>` in a record line: `connect`, `refused`, `data <hex>` or
    /// `end`.
    pub fn parse(words: &[&str]) -> Option<EthEvent> {
        Some(match words {
            ["connect"] => EthEvent::Connect,
            ["refused"] => EthEvent::Refused,
            ["end"] => EthEvent::End,
            ["data", hex] => EthEvent::Data(from_hex(hex)?),
            _ => return None,
        })
    }
}

impl fmt::Display for EthEvent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EthEvent::Connect => f.write_str("connect"),
            EthEvent::Refused => f.write_str("refused"),
            EthEvent::Data(bytes) => {
                f.write_str("data ")?;
                bytes.iter().try_for_each(|b| write!(f, "{b:02x}"))
            }
            EthEvent::End => f.write_str("end"),
        }
    }
}

/// Bytes in hex, two digits each (lowercase or uppercase); at least one byte.
pub fn from_hex(hex: &str) -> Option<Vec<u8>> {
    if hex.is_empty() || !hex.len().is_multiple_of(2) {
        return None;
    }
    (0..hex.len()).step_by(2).map(|i| u8::from_str_radix(hex.get(i..i + 2)?, 16).ok()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_survive_their_text() {
        for event in [EthEvent::Connect, EthEvent::Refused, EthEvent::Data(vec![0, 0xff, b'h']), EthEvent::End] {
            let text = event.to_string();
            assert_eq!(EthEvent::parse(&text.split(' ').collect::<Vec<_>>()), Some(event), "{text}");
        }
        for bad in
            [&["data", "6g"][..], &["data", "abc"], &["data", ""], &["data"], &["open"], &["end", "1"], &["close"]]
        {
            assert_eq!(EthEvent::parse(bad), None, "{bad:?}");
        }
    }
}

//! Modbus ASCII framing (DXMC 8.2): `:`, address, PDU and LRC as pairs of hex digits,
//! CR LF. The LRC is the two's complement of the 8-bit sum of the bytes.

use crate::rtu::Request;

/// The LRC of `bytes`: a frame with its LRC sums to 0.
pub(crate) fn lrc(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0u8, |sum, b| sum.wrapping_add(*b)).wrapping_neg()
}

/// `address`, `pdu` and their LRC: one frame for the line.
pub fn frame(address: u8, pdu: &[u8]) -> Vec<u8> {
    let mut bytes = vec![address];
    bytes.extend_from_slice(pdu);
    bytes.push(lrc(&bytes));
    let mut out = Vec::with_capacity(2 * bytes.len() + 3);
    out.push(b':');
    for b in bytes {
        out.extend(format!("{b:02X}").bytes());
    }
    out.extend(b"\r\n");
    out
}

/// The longest frame: 256 bytes as hex, `:` and CR LF (Modbus over serial line 2.5.2.1: 513).
const MAX_CHARS: usize = 513;

/// Collects a line's characters into request frames; a frame with a bad digit or LRC,
/// or too long, is dropped, and a `:` always starts a new one.
#[derive(Debug, Default)]
pub struct Assembler {
    /// The characters after the last `:`, `None` outside a frame.
    frame: Option<Vec<u8>>,
    /// Frames dropped.
    pub dropped: u64,
}

impl Assembler {
    /// Takes characters from the line; returns the requests whose frames they complete.
    pub fn push(&mut self, bytes: &[u8]) -> Vec<Request> {
        let mut requests = Vec::new();
        for &b in bytes {
            match (b, &mut self.frame) {
                (b':', frame) => {
                    self.dropped += u64::from(frame.is_some());
                    *frame = Some(Vec::new());
                }
                (b'\n', Some(chars)) if chars.last() == Some(&b'\r') => {
                    chars.pop();
                    match decode(chars) {
                        Some(request) => requests.push(request),
                        None => self.dropped += 1,
                    }
                    self.frame = None;
                }
                (_, Some(chars)) if chars.len() < MAX_CHARS => chars.push(b),
                (_, frame @ Some(_)) => {
                    self.dropped += 1;
                    *frame = None;
                }
                (_, None) => {}
            }
        }
        requests
    }
}

fn decode(chars: &[u8]) -> Option<Request> {
    if !chars.len().is_multiple_of(2) {
        return None;
    }
    let bytes: Vec<u8> = chars
        .chunks(2)
        .map(|pair| std::str::from_utf8(pair).ok().and_then(|s| u8::from_str_radix(s, 16).ok()))
        .collect::<Option<_>>()?;
    // Address, function code, LRC.
    if bytes.len() < 3 || lrc(&bytes) != 0 {
        return None;
    }
    Some(Request { address: bytes[0], pdu: bytes[1..bytes.len() - 1].to_vec() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lrc_and_frames_of_the_manual() {
        // DXMC 8.2: 7F+03+05+C4+00+01 = 0x14C -> LRC 0xB4.
        assert_eq!(lrc(&[0x7F, 0x03, 0x05, 0xC4, 0x00, 0x01]), 0xB4);
        assert_eq!(frame(1, &[0x03, 0x02, 0x00, 0x00, 0x02]), b":010302000002F8\r\n");
        assert_eq!(lrc(&[1, 6, 2, 0, 0, 0x64]), 0x93);
    }

    #[test]
    fn requests_are_read_and_bad_ones_dropped() {
        let mut a = Assembler::default();
        let line = b"junk:0103020000\r\n:010302000002F7\r\n:01030200\r\n:0103020000:010302000002F8\r\n";
        assert_eq!(a.push(line), [Request { address: 1, pdu: vec![0x03, 0x02, 0x00, 0x00, 0x02] }]);
        assert_eq!(a.dropped, 4);
        // Split across reads.
        assert_eq!(a.push(b":0106020000").len() + a.push(b"6493\r\n").len(), 1);
    }
}

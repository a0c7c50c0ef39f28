//! Modbus RTU framing (DXMC 8.2): address, PDU, CRC-16/MODBUS low byte first. Frames are
//! cut by the length their function code gives (03, 06, 16), else by the line's
//! silence; bytes that make no frame with a good CRC are skipped one at a time, so
//! garbage before a frame does not hide it.

/// DXMC 8.2's CRC: init 0xFFFF, each byte XORed into the low byte, 8 shifts right with
/// 0xA001 when the bit shifted out is 1.
pub fn crc16(bytes: &[u8]) -> u16 {
    let mut crc = 0xFFFFu16;
    for &b in bytes {
        crc ^= u16::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 { (crc >> 1) ^ 0xA001 } else { crc >> 1 };
        }
    }
    crc
}

/// `address`, `pdu` and their CRC: one frame for the line.
pub fn frame(address: u8, pdu: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(pdu.len() + 3);
    out.push(address);
    out.extend_from_slice(pdu);
    out.extend(crc16(&out).to_le_bytes());
    out
}

/// The largest RTU frame (Modbus over serial line 2.5.1.1).
pub const MAX_FRAME: usize = 256;
/// Address, function code and CRC: the shortest frame.
const MIN_FRAME: usize = 4;

/// A request frame received whole: its address and its PDU.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Request {
    /// The station addressed (parameter 0-0), 0 for a broadcast.
    pub address: u8,
    /// Function code and data, without address and CRC.
    pub pdu: Vec<u8>,
}

/// Collects a line's bytes into request frames.
#[derive(Debug, Default)]
pub struct Assembler {
    buf: Vec<u8>,
    /// Bytes skipped since the last frame (garbage, or a frame with a bad CRC).
    pub skipped: u64,
}

/// The whole length of a request frame starting with `frame`, when its function code
/// gives one and enough of it has arrived to read it.
fn length(frame: &[u8]) -> Option<Option<usize>> {
    match frame.get(1)? {
        0x03 | 0x06 => Some(Some(8)),
        0x10 => Some(frame.get(6).map(|&count| 9 + count as usize)),
        _ => None,
    }
}

fn good(frame: &[u8]) -> bool {
    frame.len() >= MIN_FRAME && {
        let (body, crc) = frame.split_at(frame.len() - 2);
        crc16(body).to_le_bytes() == crc
    }
}

impl Assembler {
    /// Whether no bytes wait for the rest of a frame (the port then needs no silence
    /// timer).
    pub fn is_empty(&self) -> bool {
        self.buf.is_empty()
    }

    /// Takes bytes; returns the requests they complete.
    pub fn push(&mut self, bytes: &[u8]) -> Vec<Request> {
        self.buf.extend_from_slice(bytes);
        self.scan(false)
    }

    /// The line has been silent (DXMC 8.2: over 10 ms ends a frame): what is left is a
    /// frame of its own (a function code this side knows no length for) or is dropped.
    pub fn silence(&mut self) -> Vec<Request> {
        let requests = self.scan(true);
        self.skipped += self.buf.len() as u64;
        self.buf.clear();
        requests
    }

    fn scan(&mut self, silent: bool) -> Vec<Request> {
        let mut requests = Vec::new();
        let mut at = 0;
        while self.buf.len() - at >= MIN_FRAME {
            let rest = &self.buf[at..];
            let whole = match length(rest) {
                Some(Some(n)) if n > MAX_FRAME => None,
                Some(Some(n)) if rest.len() >= n => Some(n).filter(|&n| good(&rest[..n])),
                // Not all there yet: wait, unless the line has gone silent.
                Some(_) if !silent => break,
                Some(_) => None,
                None if silent && good(rest) => Some(rest.len()),
                None => None,
            };
            match whole {
                Some(n) => {
                    self.skipped += at as u64;
                    requests.push(Request { address: rest[0], pdu: rest[1..n - 2].to_vec() });
                    self.buf.drain(..at + n);
                    at = 0;
                }
                None => at += 1,
            }
        }
        // Bounded: what cannot begin a frame any more is dropped.
        if self.buf.len() > MAX_FRAME {
            let excess = self.buf.len() - MAX_FRAME;
            self.skipped += excess as u64;
            self.buf.drain(..excess);
        }
        requests
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_of_the_manual_s_frames() {
        // DXMC 8.2: 01 03 01 01 00 02 -> 0x3794, sent 94 37.
        assert_eq!(crc16(&[0x01, 0x03, 0x01, 0x01, 0x00, 0x02]), 0x3794);
        assert_eq!(frame(1, &[0x03, 0x02, 0x00, 0x00, 0x02]), [0x01, 0x03, 0x02, 0x00, 0x00, 0x02, 0xC5, 0xB3]);
        assert_eq!(frame(1, &[0x03, 0x04, 0x00, 0xB1, 0x1F, 0x40]), [1, 3, 4, 0x00, 0xB1, 0x1F, 0x40, 0xA3, 0xD4]);
        assert_eq!(frame(1, &[0x06, 0x02, 0x00, 0x00, 0x64]), [1, 6, 2, 0, 0, 0x64, 0x89, 0x99]);
        let write = frame(1, &[0x10, 0x01, 0x12, 0x00, 0x02, 0x04, 0x0B, 0xB8, 0x00, 0x00]);
        assert_eq!(&write[write.len() - 2..], [0xFC, 0xEB]);
        assert_eq!(frame(1, &[0x10, 0x01, 0x12, 0x00, 0x02]), [1, 0x10, 1, 0x12, 0, 2, 0xE0, 0x31]);
        // CRC-16/MODBUS check value of "123456789".
        assert_eq!(crc16(b"123456789"), 0x4B37);
    }

    #[test]
    fn frames_are_cut_by_their_function_code() {
        let read = frame(1, &[0x03, 0x02, 0x00, 0x00, 0x02]);
        let write = frame(1, &[0x10, 0x01, 0x12, 0x00, 0x02, 0x04, 0x0B, 0xB8, 0x00, 0x00]);
        let mut a = Assembler::default();
        assert_eq!(a.push(&read[..5]), []);
        let both = [&read[5..], &write[..]].concat();
        let got = a.push(&both);
        assert_eq!(got.iter().map(|r| r.pdu[0]).collect::<Vec<_>>(), [0x03, 0x10]);
        assert_eq!(got[1].pdu.len(), 10);
        assert!(a.is_empty());
    }

    #[test]
    fn garbage_and_bad_crcs_are_skipped() {
        let read = frame(1, &[0x03, 0x02, 0x00, 0x00, 0x02]);
        let mut bad = read.clone();
        bad[7] ^= 0xFF;
        let mut a = Assembler::default();
        let line = [&[0xDE, 0xAD, 0x03, 0xBE, 0xEF][..], &bad, &read].concat();
        let got = a.push(&line);
        assert_eq!(got, [Request { address: 1, pdu: read[1..6].to_vec() }]);
        assert_eq!(a.skipped, 5 + 8);
    }

    #[test]
    fn silence_ends_a_frame_of_unknown_length() {
        let other = frame(1, &[0x2B, 0x0E, 0x01, 0x00]);
        let mut a = Assembler::default();
        assert_eq!(a.push(&other), []);
        assert_eq!(a.silence(), [Request { address: 1, pdu: vec![0x2B, 0x0E, 0x01, 0x00] }]);
        // A frame cut short is dropped at the silence.
        a.push(&frame(1, &[0x03, 0x02, 0x00, 0x00, 0x02])[..6]);
        assert_eq!(a.silence(), []);
        assert!(a.is_empty());
    }
}

//! FreePort framing (DXMC 8.3 packet table): a frame is an optional start byte, the data
//! and optional end bytes. Serial port 1 and the `FreePort.Eth` sessions of a script
//! share it.

use std::collections::VecDeque;

/// How a line delimits its frames.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Framing {
    /// The byte that begins a frame, `None` when frames have none.
    pub start: Option<u8>,
    /// The bytes that end a frame; empty when every read is a frame.
    pub end: Vec<u8>,
}

impl Framing {
    /// The bytes on the line for `data`.
    pub fn frame(&self, data: &[u8]) -> Vec<u8> {
        let mut out = Vec::with_capacity(data.len() + 3);
        out.extend(self.start);
        out.extend_from_slice(data);
        out.extend_from_slice(&self.end);
        out
    }
}

/// What the receiving side makes of the bytes: frames, or a notice that some were lost.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Received {
    /// A frame's data, without its start and end bytes.
    Frame(Vec<u8>),
    /// A frame longer than the limit, dropped.
    TooLong,
    /// Frames refused because the queue was full (counted since the last notice).
    Overrun(u64),
}

/// Cuts received bytes into frames. Bounded: a frame beyond `max_data` bytes is dropped
/// until its end, and at most `max_frames` wait; more are refused and counted, as a
/// UART's overrun loses the newest characters.
#[derive(Debug)]
pub struct Deframer {
    framing: Framing,
    max_data: usize,
    max_frames: usize,
    /// Bytes received and not yet a frame.
    pending: Vec<u8>,
    /// Bytes of the frame under way beyond `max_data` are dropped until its end.
    overflowing: bool,
    /// The frame under way has had its start byte: the same byte as an end byte then
    /// ends it, before that it begins it.
    begun: bool,
    frames: VecDeque<Received>,
    refused: u64,
}

impl Deframer {
    /// A deframer for `framing` that keeps frames of at most `max_data` bytes (at least
    /// 1) and at most `max_frames` of them waiting.
    pub fn new(framing: Framing, max_data: usize, max_frames: usize) -> Self {
        Deframer {
            framing,
            // A frame holds at least a byte: pieces of unframed data are never empty.
            max_data: max_data.max(1),
            max_frames,
            pending: Vec::new(),
            overflowing: false,
            begun: false,
            frames: VecDeque::new(),
            refused: 0,
        }
    }

    /// The delimiters it cuts by (a sender frames its data with the same).
    pub fn framing(&self) -> &Framing {
        &self.framing
    }

    /// Bytes from the line: frames end at the end bytes. Without end bytes every read is
    /// a frame (its data after the start byte, if one is set), in pieces of at most
    /// `max_data` bytes, so nothing is lost and no frame is too long.
    pub fn receive(&mut self, bytes: &[u8]) {
        if self.framing.end.is_empty() {
            self.pending.extend_from_slice(bytes);
            let data = self.take_data();
            for piece in data.chunks(self.max_data) {
                self.push(Received::Frame(piece.to_vec()));
            }
            return;
        }
        for &b in bytes {
            self.pending.push(b);
            let begins = !self.begun && Some(b) == self.framing.start;
            self.begun |= begins;
            let end = self.framing.end.len();
            if !begins && self.pending.ends_with(&self.framing.end) {
                self.pending.truncate(self.pending.len() - end);
                let data = self.take_data();
                let too_long = self.overflowing || data.len() > self.max_data;
                self.push(if too_long { Received::TooLong } else { Received::Frame(data) });
                self.overflowing = false;
                self.begun = false;
            } else if self.pending.len() > self.max_data + 1 + end {
                self.overflowing = true;
                let keep = end.saturating_sub(1);
                self.pending.drain(..self.pending.len() - keep);
            }
        }
    }

    fn push(&mut self, frame: Received) {
        if self.frames.len() < self.max_frames {
            self.frames.push_back(frame);
        } else {
            self.refused += 1;
        }
    }

    /// The next frame, or the notice of frames refused before it.
    pub fn pop(&mut self) -> Option<Received> {
        if self.refused > 0 {
            return Some(Received::Overrun(std::mem::take(&mut self.refused)));
        }
        self.frames.pop_front()
    }

    /// Drops the frame under way (its sender has gone).
    pub fn drop_unfinished(&mut self) {
        self.pending.clear();
        self.overflowing = false;
        self.begun = false;
    }

    /// Drops everything received and not yet read.
    pub fn clear(&mut self) {
        self.drop_unfinished();
        self.frames.clear();
        self.refused = 0;
    }

    /// The pending bytes without what precedes and includes the start byte.
    fn take_data(&mut self) -> Vec<u8> {
        let mut data = std::mem::take(&mut self.pending);
        if let Some(start) = self.framing.start
            && let Some(at) = data.iter().position(|&b| b == start)
        {
            data.drain(..=at);
        }
        data
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn deframer(start: Option<u8>, end: &[u8]) -> Deframer {
        Deframer::new(Framing { start, end: end.to_vec() }, 8, 2)
    }

    fn frames(d: &mut Deframer) -> Vec<Received> {
        std::iter::from_fn(|| d.pop()).collect()
    }

    #[test]
    fn frames_are_cut_at_their_end_and_lose_their_start() {
        let mut d = deframer(Some(b':'), b";");
        d.receive(b"xx:3.14");
        assert_eq!(frames(&mut d), []);
        d.receive(b"15;:a;");
        assert_eq!(frames(&mut d), [Received::Frame(b"3.1415".to_vec()), Received::Frame(b"a".to_vec())]);
        assert_eq!(Framing { start: Some(b':'), end: b";".to_vec() }.frame(b"ab"), b":ab;");
    }

    #[test]
    fn a_long_frame_is_dropped_and_the_next_arrives() {
        let mut d = deframer(None, b"\r\n");
        d.receive(&[b'7'; 30]);
        d.receive(b"\r\nok\r\n");
        assert_eq!(frames(&mut d), [Received::TooLong, Received::Frame(b"ok".to_vec())]);
    }

    /// Found by `tests/fuzz.rs`: without end bytes a read over `max_data` was one frame of
    /// `max_data + 1` bytes and the rest was lost; it comes in pieces now.
    #[test]
    fn without_end_bytes_a_long_read_comes_in_pieces() {
        let mut d = Deframer::new(Framing::default(), 8, 8);
        d.receive(b"0123456789abcdefghij");
        let pieces = [&b"01234567"[..], b"89abcdef", b"ghij"].map(|p| Received::Frame(p.to_vec()));
        assert_eq!(frames(&mut d), pieces);
        let mut d = Deframer::new(Framing { start: Some(b':'), end: Vec::new() }, 1, 8);
        d.receive(b"x:ab");
        assert_eq!(frames(&mut d), [Received::Frame(b"a".to_vec()), Received::Frame(b"b".to_vec())]);
    }

    /// Found by `tests/fuzz.rs`: with the start byte also the end byte, `:ab:` was an empty
    /// frame and `ab` never ended; the byte begins a frame when none is under way.
    #[test]
    fn a_start_byte_that_is_also_the_end_byte() {
        let mut d = deframer(Some(b':'), b":");
        d.receive(b":ab::cd:");
        assert_eq!(frames(&mut d), [Received::Frame(b"ab".to_vec()), Received::Frame(b"cd".to_vec())]);
        let mut d = deframer(Some(b'\n'), b"\r\n");
        d.receive(b"\nab\r\n\n\r\n");
        assert_eq!(frames(&mut d), [Received::Frame(b"ab".to_vec()), Received::Frame(Vec::new())]);
    }

    #[test]
    fn a_full_queue_refuses_the_newest_and_says_how_many() {
        let mut d = deframer(None, b";");
        d.receive(b"1;2;3;4;");
        assert_eq!(
            frames(&mut d),
            [Received::Overrun(2), Received::Frame(b"1".to_vec()), Received::Frame(b"2".to_vec())]
        );
        d.receive(b"5;");
        assert_eq!(frames(&mut d), [Received::Frame(b"5".to_vec())]);
    }
}

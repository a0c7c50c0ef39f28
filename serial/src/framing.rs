//! FreePort framing (DXMC 8.3 packet table): a frame is an optional start byte, the data
//! and optional end bytes. Serial port 1 and the `FreePort.Eth` sessions of a script
//! share it.

use std::collections::VecDeque;

/// How a line delimits its frames.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Framing {
    pub start: Option<u8>,
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
    frames: VecDeque<Received>,
    refused: u64,
}

impl Deframer {
    pub fn new(framing: Framing, max_data: usize, max_frames: usize) -> Self {
        Deframer {
            framing,
            max_data,
            max_frames,
            pending: Vec::new(),
            overflowing: false,
            frames: VecDeque::new(),
            refused: 0,
        }
    }

    pub fn framing(&self) -> &Framing {
        &self.framing
    }

    pub fn receive(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.pending.push(b);
            let end = &self.framing.end;
            if !end.is_empty() && self.pending.ends_with(end) {
                self.pending.truncate(self.pending.len() - end.len());
                let data = self.take_data();
                let frame = if self.overflowing { Received::TooLong } else { Received::Frame(data) };
                self.push(frame);
                self.overflowing = false;
            } else if self.pending.len() > self.max_data + 1 + end.len() {
                // Keep the tail an end sequence may finish; count the rest as lost.
                self.overflowing = true;
                let keep = end.len().saturating_sub(1);
                self.pending.drain(..self.pending.len() - keep);
            }
        }
        if self.framing.end.is_empty() && !self.pending.is_empty() {
            // No end bytes: whatever arrived is the frame (DXMC 8.3 with EByte nil).
            let data = self.take_data();
            if !data.is_empty() {
                self.push(Received::Frame(data));
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
        if data.len() > self.max_data {
            self.overflowing = true;
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

//! A segment: ESCs in a line, port 1 of each to port 0 of the next, the last one's port 1
//! closed. A frame from the master passes them in order, each processing every datagram
//! of it (several datagrams per frame, the working counters adding up), and returns
//! through port 0 of the first.
//!
//! The segment's clock is the caller's (ns): each ESC sees the frame `HOP_NS` after the one
//! before, and again on its way back. When the slaves step (at SYNC0 with DC, else at each
//! process-data frame) is the ESCs' (docs/decisions.md, "When the drives step").
//!
//! The circulating bit: an ESC whose port 0 is closed marks a frame (and destroys a
//! marked one); in this line every port 0 leads to the master or the ESC before, so the
//! bit comes back as the master sent it (docs/decisions.md, "Circulating bit").

use crate::esc::{Esc, FrameArrival};
use crate::frame::{self, DATAGRAM_HEADER_LEN, DatagramHeader, DatagramPlace, FrameError};

/// Time a frame takes from one ESC's port 0 to the next one's (forwarding and cable),
/// and the same on the way back.
pub const HOP_NS: u64 = 500;

/// The ESCs of one line.
pub struct Segment {
    escs: Vec<Esc>,
    places: Vec<DatagramPlace>,
}

impl Segment {
    /// The ESCs in ring order.
    pub fn new(mut escs: Vec<Esc>) -> Self {
        let last = escs.len().saturating_sub(1);
        for (i, esc) in escs.iter_mut().enumerate() {
            esc.set_last(i == last);
        }
        Segment { escs, places: Vec::new() }
    }

    /// The ESCs.
    pub fn escs(&self) -> &[Esc] {
        &self.escs
    }

    /// The ESCs, for what the wire does not carry (the simulation's faults).
    pub fn escs_mut(&mut self) -> &mut [Esc] {
        &mut self.escs
    }

    /// One frame from the master at segment time `now`, processed in place; on `Ok` it is
    /// what goes back to the master. A broken frame is left as it is and dropped.
    pub fn process(&mut self, frame: &mut [u8], now: u64) -> Result<(), FrameError> {
        frame::layout(frame, &mut self.places)?;
        let count = self.escs.len() as u64;
        for (i, esc) in self.escs.iter_mut().enumerate() {
            let i = i as u64;
            let port0 = now + i * HOP_NS;
            let port1 = (i + 1 < count).then(|| now + (2 * (count - 1) - i) * HOP_NS);
            esc.frame_arrives(FrameArrival { port0, port1 });
            for place in &self.places {
                let mut bytes = [0u8; DATAGRAM_HEADER_LEN];
                bytes.copy_from_slice(&frame[place.header..place.header + DATAGRAM_HEADER_LEN]);
                let mut header = DatagramHeader::parse(&bytes);
                let mut wkc = u16::from_le_bytes([frame[place.wkc], frame[place.wkc + 1]]);
                esc.datagram(&mut header, &mut frame[place.data.clone()], &mut wkc);
                header.write(&mut bytes);
                frame[place.header..place.header + DATAGRAM_HEADER_LEN].copy_from_slice(&bytes);
                frame[place.wkc..place.wkc + 2].copy_from_slice(&wkc.to_le_bytes());
            }
            esc.frame_leaves();
        }
        frame::mark_returned(frame);
        Ok(())
    }
}

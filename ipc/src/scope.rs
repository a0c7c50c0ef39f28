//! The scope ring (`lm.<ns>.scope`): up to [`CHANNELS`] values a cycle, written by the
//! RT thread into a ring of [`ROWS`] rows in shared memory and read by any number of tools.
//! Each row carries a sequence number (a seqlock), so a reader that fell a whole ring
//! behind sees it and counts the rows lost instead of reading torn ones.
//!
//! The channels are opaque `u32` codes here (`calls::scope` names them). A tool asks for
//! its channels by writing them into the request words and bumping the request number;
//! the RT thread takes them over at the start of its next cycle and says so in
//! [`ScopeRing::active_request`].

use std::sync::atomic::{AtomicU32, AtomicU64, Ordering, fence};

use schema::layout::Shareable;

use crate::error::IpcError;
use crate::namespace::Namespace;
use crate::shm::Region;

/// Values a row holds.
pub const CHANNELS: usize = 16;
/// Rows in the ring: 8.192 s at 1 ms, a power of two.
pub const ROWS: usize = 8192;
/// The shared-memory file's name under the namespace.
pub const SCOPE_REGION: &str = "scope";

/// One cycle's values.
#[repr(C)]
struct Row {
    /// 0 while being written, else the row's index + 1.
    seq: AtomicU64,
    cycle: AtomicU64,
    /// `f64` bits.
    values: [AtomicU64; CHANNELS],
}

/// The ring and its channel selection.
#[repr(C)]
pub struct ScopeRing {
    /// The controller's cycle period, ns (for time in ms).
    period_ns: AtomicU64,
    /// Rows written since start.
    written: AtomicU64,
    /// HMPL 2.17 `SetHMIScope`: 1 records, 0 pauses.
    gate: AtomicU32,
    request_len: AtomicU32,
    /// Bumped by a tool after it wrote `request`.
    request: AtomicU64,
    /// The request the RT thread took over last.
    active_request: AtomicU64,
    request_codes: [AtomicU32; CHANNELS],
    rows: [Row; ROWS],
}

// SAFETY: repr(C), all atomics (valid when zeroed), changed only through atomics.
unsafe impl Shareable for ScopeRing {}

/// What reading a row found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowRead {
    /// The row's cycle; the values are in the caller's buffer.
    Row(u64),
    /// Not written yet.
    Pending,
    /// Overwritten before it was read: the reader is more than a ring behind.
    Lost,
}

impl ScopeRing {
    /// Creates the controller's ring, gate open, recording `codes` from the first cycle.
    pub fn create(ns: &Namespace, period_ns: u64, codes: &[u32]) -> Result<Region<ScopeRing>, IpcError> {
        let ring = Region::<ScopeRing>::create(ns, SCOPE_REGION)?;
        ring.period_ns.store(period_ns, Ordering::Relaxed);
        ring.gate.store(1, Ordering::Relaxed);
        if !codes.is_empty() {
            ring.request(codes);
        }
        Ok(ring)
    }

    /// Opens a running controller's ring.
    pub fn open(ns: &Namespace) -> Result<Region<ScopeRing>, IpcError> {
        Region::open(ns, SCOPE_REGION)
    }

    /// The cycle period, ns.
    pub fn period_ns(&self) -> u64 {
        self.period_ns.load(Ordering::Relaxed)
    }

    /// Asks for these channels (the first [`CHANNELS`]); returns the request's number,
    /// which [`ScopeRing::active_request`] shows once the RT thread records them.
    pub fn request(&self, codes: &[u32]) -> u64 {
        let len = codes.len().min(CHANNELS);
        for (slot, &code) in self.request_codes.iter().zip(&codes[..len]) {
            slot.store(code, Ordering::Relaxed);
        }
        self.request_len.store(len as u32, Ordering::Relaxed);
        self.request.fetch_add(1, Ordering::Release) + 1
    }

    /// The RT thread's side: when a new request came, copies its codes into `codes` and
    /// returns how many there are.
    pub fn take_request(&self, codes: &mut [u32; CHANNELS]) -> Option<usize> {
        let request = self.request.load(Ordering::Acquire);
        if request == self.active_request.load(Ordering::Relaxed) {
            return None;
        }
        let len = (self.request_len.load(Ordering::Relaxed) as usize).min(CHANNELS);
        for (code, slot) in codes.iter_mut().zip(&self.request_codes[..len]) {
            *code = slot.load(Ordering::Relaxed);
        }
        // Rows after this point hold the new channels.
        self.active_request.store(request, Ordering::Release);
        Some(len)
    }

    /// The request the RT thread records now.
    pub fn active_request(&self) -> u64 {
        self.active_request.load(Ordering::Acquire)
    }

    /// HMPL 2.17: opens (true) or closes the gate.
    pub fn set_gate(&self, open: bool) {
        self.gate.store(open as u32, Ordering::Relaxed);
    }

    /// Whether rows are recorded.
    pub fn gate_open(&self) -> bool {
        self.gate.load(Ordering::Relaxed) != 0
    }

    /// Rows written since start: the index of the next one.
    pub fn written(&self) -> u64 {
        self.written.load(Ordering::Acquire)
    }

    /// The RT thread's side: appends one row (no allocation, no waiting).
    pub fn push(&self, cycle: u64, values: &[f64]) {
        let index = self.written.load(Ordering::Relaxed);
        let row = &self.rows[index as usize % ROWS];
        row.seq.store(0, Ordering::Relaxed);
        fence(Ordering::Release);
        row.cycle.store(cycle, Ordering::Relaxed);
        for (slot, value) in row.values.iter().zip(values) {
            slot.store(value.to_bits(), Ordering::Relaxed);
        }
        row.seq.store(index + 1, Ordering::Release);
        self.written.store(index + 1, Ordering::Release);
    }

    /// Reads row `index` into `values`.
    pub fn read(&self, index: u64, values: &mut [f64]) -> RowRead {
        let row = &self.rows[index as usize % ROWS];
        let before = row.seq.load(Ordering::Acquire);
        if before != index + 1 {
            return if self.written() > index + ROWS as u64 - 1 || before > index + 1 {
                RowRead::Lost
            } else {
                RowRead::Pending
            };
        }
        let cycle = row.cycle.load(Ordering::Relaxed);
        for (value, slot) in values.iter_mut().zip(&row.values) {
            *value = f64::from_bits(slot.load(Ordering::Relaxed));
        }
        fence(Ordering::Acquire);
        if row.seq.load(Ordering::Relaxed) != before { RowRead::Lost } else { RowRead::Row(cycle) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reader_a_ring_behind_sees_the_rows_it_lost() {
        let ring = schema::layout::zeroed::<ScopeRing>();
        let mut values = [0.0; CHANNELS];
        assert_eq!(ring.read(0, &mut values), RowRead::Pending);
        for cycle in 1..=(ROWS as u64 + 10) {
            ring.push(cycle, &[cycle as f64 * 0.5, -1.0]);
        }
        assert_eq!(ring.read(0, &mut values), RowRead::Lost);
        assert_eq!(ring.read(9, &mut values), RowRead::Lost);
        assert_eq!(ring.read(10, &mut values), RowRead::Row(11));
        assert_eq!(&values[..2], &[5.5, -1.0]);
        assert_eq!(ring.read(ROWS as u64 + 10, &mut values), RowRead::Pending);
    }

    #[test]
    fn a_request_is_taken_over_once() {
        let ring = schema::layout::zeroed::<ScopeRing>();
        let number = ring.request(&[7, 8, 9]);
        let mut codes = [0; CHANNELS];
        assert_eq!(ring.take_request(&mut codes), Some(3));
        assert_eq!(&codes[..3], &[7, 8, 9]);
        assert_eq!(ring.active_request(), number);
        assert_eq!(ring.take_request(&mut codes), None);
    }
}

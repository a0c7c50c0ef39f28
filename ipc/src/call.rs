//! The call words a task's mailbox carries (`mailbox.rs`): a request of untyped 64-bit
//! argument words and a blob, and the reply. They are the mailbox's wire format, not the
//! domain's: what the words mean is the registry's (`api`) and `calls::wire`'s. The soak's
//! transport floor sends them over iceoryx2 as well, hence `ZeroCopySend`.

use iceoryx2::prelude::ZeroCopySend;

/// Scalar arguments of one call; no HMPL function has more.
pub const MAX_ARGS: usize = 12;
/// Bytes for string and array arguments (`MovePVT` sends 3 x 50 doubles).
pub const BLOB_SIZE: usize = 1536;

/// One API call that needs the core (`api::Kind::Command`).
///
/// Arguments are 64-bit words whose meaning the registry gives: an `Int` argument is an
/// `i64`, a `Double` the bits of an `f64`.
#[derive(Debug, Clone, Copy, ZeroCopySend)]
#[repr(C)]
pub struct Request {
    /// Per-task sequence number, echoed by the reply: lost or duplicated replies show.
    pub seq: u64,
    /// CLOCK_MONOTONIC when the script sent it.
    pub sent_ns: u64,
    /// `api::Command::id()`.
    pub func: u16,
    /// Arguments used in `args`.
    pub argc: u16,
    /// Bytes used in `blob`.
    pub blob_len: u32,
    /// The argument words.
    pub args: [u64; MAX_ARGS],
    /// Bytes that do not fit in words (a string, a PVT table).
    pub blob: [u8; BLOB_SIZE],
}

impl Request {
    /// An empty request for function id `func`.
    pub fn new(func: u16) -> Self {
        Request { seq: 0, sent_ns: 0, func, argc: 0, blob_len: 0, args: [0; MAX_ARGS], blob: [0; BLOB_SIZE] }
    }

    /// Appends an `Int` argument.
    pub fn push_int(&mut self, v: i64) {
        self.push_word(v as u64);
    }

    /// Appends a `Double` argument.
    pub fn push_double(&mut self, v: f64) {
        self.push_word(v.to_bits());
    }

    fn push_word(&mut self, w: u64) {
        self.args[self.argc as usize] = w;
        self.argc += 1;
    }

    /// Argument `i` as an `Int`.
    pub fn int(&self, i: usize) -> i64 {
        self.args[i] as i64
    }

    /// The blob's used bytes.
    pub fn blob(&self) -> &[u8] {
        &self.blob[..self.blob_len as usize]
    }

    /// Sets the blob; bytes past `BLOB_SIZE` are cut.
    pub fn set_blob(&mut self, bytes: &[u8]) {
        let n = bytes.len().min(BLOB_SIZE);
        self.blob[..n].copy_from_slice(&bytes[..n]);
        self.blob_len = n as u32;
    }

    /// Appends bytes after what the blob holds; false when they do not fit.
    pub fn append_blob(&mut self, bytes: &[u8]) -> bool {
        let start = self.blob_len as usize;
        let Some(end) = start.checked_add(bytes.len()).filter(|&e| e <= BLOB_SIZE) else { return false };
        self.blob[start..end].copy_from_slice(bytes);
        self.blob_len = end as u32;
        true
    }
}

/// The core's answer to one `Request`.
#[derive(Debug, Clone, Copy, ZeroCopySend)]
#[repr(C)]
pub struct Reply {
    /// The request's sequence number.
    pub seq: u64,
    /// The request's `sent_ns`, echoed for the round trip.
    pub request_sent_ns: u64,
    /// CLOCK_MONOTONIC when the core took the request.
    pub received_ns: u64,
    /// CLOCK_MONOTONIC when the core sent this reply.
    pub sent_ns: u64,
    /// The cycle in which the command was applied; the snapshot of that cycle shows it.
    pub cycle: u64,
    /// 0 on success, otherwise why it failed: the HMPL error code (`0x83IIEEEE`, ...),
    /// or for SDO services the CiA 301 abort code.
    pub rc: u32,
    /// Values used in `values`.
    pub valuec: u16,
    /// Bytes used in `blob`.
    pub blob_len: u16,
    /// Returned values as words, typed by the registry's `returns`.
    pub values: [u64; MAX_ARGS],
    /// A returned out-pointer buffer.
    pub blob: [u8; BLOB_SIZE],
}

impl Reply {
    /// Appends a returned value (the C return value first, then out-pointers).
    pub fn push_int(&mut self, v: i64) {
        self.values[self.valuec as usize] = v as u64;
        self.valuec += 1;
    }

    /// Appends a returned `double` (an element of an out-pointer array).
    pub fn push_double(&mut self, v: f64) {
        self.values[self.valuec as usize] = v.to_bits();
        self.valuec += 1;
    }

    /// Sets the blob; bytes past `BLOB_SIZE` are cut.
    pub fn set_blob(&mut self, bytes: &[u8]) {
        let n = bytes.len().min(BLOB_SIZE);
        self.blob[..n].copy_from_slice(&bytes[..n]);
        self.blob_len = n as u16;
    }

    /// The blob's used bytes.
    pub fn blob(&self) -> &[u8] {
        &self.blob[..self.blob_len as usize]
    }

    /// An empty successful reply to `request`.
    pub fn to(request: &Request) -> Self {
        Reply {
            seq: request.seq,
            request_sent_ns: request.sent_ns,
            received_ns: 0,
            sent_ns: 0,
            cycle: 0,
            rc: 0,
            valuec: 0,
            blob_len: 0,
            values: [0; MAX_ARGS],
            blob: [0; BLOB_SIZE],
        }
    }
}

//! Each task's calls to the core through a mailbox in the task table, in place of a pair of
//! iceoryx2 services per task (whose receive and publish were a third of the RT thread's
//! time, and whose ports every start of a task had to open and connect).
//!
//! A task has one call in flight. It writes its `Request` into its mailbox, publishes the
//! call's sequence number (Release) and sets its bit in the table-wide `posted` word, so the
//! core finds every posted call with one swap per cycle. The core copies the request out
//! (a process may rewrite shared memory while it is read: it is never decoded in place),
//! answers it, writes the `Reply` and publishes the reply's sequence number the same way.
//!
//! Each half is a sequence lock: the writer clears the sequence word, writes the words,
//! then stores the new sequence number; a reader that finds the word changed across its
//! copy (or 0) drops the copy. A process that dies halfway through a write leaves 0, which
//! no reader takes. Sequence numbers start from the writer's pid (`TaskEndpoint`), so a
//! restarted task never takes an earlier process' reply, and the core takes only requests
//! whose sequence names the process in the slot.

use std::sync::atomic::{AtomicU64, Ordering, fence};

use schema::MAX_TASKS;
use schema::layout::Shareable;

use crate::call::{BLOB_SIZE, MAX_ARGS, Reply, Request};

const BLOB_WORDS: usize = BLOB_SIZE / 8;
const _: () = assert!(BLOB_SIZE.is_multiple_of(8), "the blob is copied in whole words");

/// A request's words before its blob: `sent_ns`, `func | argc << 16 | blob_len << 32`, the arguments.
const REQUEST_HEAD: usize = 2 + MAX_ARGS;
/// A reply's words before its blob: three timestamps, the cycle, `rc | valuec << 32 |
/// blob_len << 48`, the values.
const REPLY_HEAD: usize = 5 + MAX_ARGS;

/// One side of a mailbox without its blob: the sequence word and the words before the blob,
/// on cache lines of their own (the side's writer is another process than its reader).
#[repr(C, align(64))]
struct Head<const WORDS: usize> {
    seq: AtomicU64,
    words: [AtomicU64; WORDS],
}

/// What every call of one task touches: its request's head and its reply's, 320 bytes.
#[repr(C)]
struct Heads {
    request: Head<REQUEST_HEAD>,
    reply: Head<REPLY_HEAD>,
}

/// One task's blobs, kept apart from the heads: only a call that carries a blob touches them.
#[repr(C)]
struct Blobs {
    request: [AtomicU64; BLOB_WORDS],
    reply: [AtomicU64; BLOB_WORDS],
}

/// One task's mailbox: its request and the core's reply, each behind its sequence word.
#[derive(Clone, Copy)]
pub struct Mailbox<'a> {
    heads: &'a Heads,
    blobs: &'a Blobs,
}

/// The words that hold `len` bytes of a blob (`len` at most `BLOB_SIZE`).
fn blob_words(len: usize) -> usize {
    len.min(BLOB_SIZE).div_ceil(8)
}

fn store_blob(words: &[AtomicU64; BLOB_WORDS], blob: &[u8; BLOB_SIZE], len: usize) {
    for (word, chunk) in words.iter().zip(blob.chunks_exact(8)).take(blob_words(len)) {
        word.store(u64::from_le_bytes(chunk.try_into().expect("8 bytes")), Ordering::Relaxed);
    }
}

fn load_blob(words: &[AtomicU64; BLOB_WORDS], blob: &mut [u8; BLOB_SIZE], len: usize) {
    for (word, chunk) in words.iter().zip(blob.chunks_exact_mut(8)).take(blob_words(len)) {
        chunk.copy_from_slice(&word.load(Ordering::Relaxed).to_le_bytes());
    }
}

/// Starts a write behind `seq`: a reader that copies from here on sees its word changed.
fn begin_write(seq: &AtomicU64) {
    seq.store(0, Ordering::Relaxed);
    fence(Ordering::Release);
}

/// Whether a copy started when `seq` held `seen` is whole: the word still holds it.
fn copy_is_whole(seq: &AtomicU64, seen: u64) -> bool {
    fence(Ordering::Acquire);
    seq.load(Ordering::Relaxed) == seen
}

impl Mailbox<'_> {
    /// The task's side: writes `request` (its `seq` set) and publishes its sequence number.
    pub fn write_request(&self, request: &Request) {
        let head = &self.heads.request;
        begin_write(&head.seq);
        let words =
            [request.sent_ns, request.func as u64 | (request.argc as u64) << 16 | (request.blob_len as u64) << 32];
        for (word, value) in head.words.iter().zip(words.iter().chain(&request.args)) {
            word.store(*value, Ordering::Relaxed);
        }
        store_blob(&self.blobs.request, &request.blob, request.blob_len as usize);
        head.seq.store(request.seq, Ordering::Release);
    }

    /// The core's side: copies the request out into `into`; its sequence number, or `None`
    /// when the mailbox holds none or was rewritten during the copy. The argument count and
    /// blob length are copied as written (the decoder refuses what no binding sends); only
    /// the blob's words up to `BLOB_SIZE` are read.
    pub fn read_request(&self, into: &mut Request) -> Option<u64> {
        let head = &self.heads.request;
        let seq = head.seq.load(Ordering::Acquire);
        if seq == 0 {
            return None;
        }
        into.seq = seq;
        into.sent_ns = head.words[0].load(Ordering::Relaxed);
        let packed = head.words[1].load(Ordering::Relaxed);
        (into.func, into.argc, into.blob_len) = (packed as u16, (packed >> 16) as u16, (packed >> 32) as u32);
        for (arg, word) in into.args.iter_mut().zip(&head.words[2..]) {
            *arg = word.load(Ordering::Relaxed);
        }
        load_blob(&self.blobs.request, &mut into.blob, into.blob_len as usize);
        copy_is_whole(&head.seq, seq).then_some(seq)
    }

    /// The core's side: writes `reply` and publishes its sequence number.
    pub fn write_reply(&self, reply: &Reply) {
        let words = &self.heads.reply;
        begin_write(&words.seq);
        let head = [
            reply.request_sent_ns,
            reply.received_ns,
            reply.sent_ns,
            reply.cycle,
            reply.rc as u64 | (reply.valuec as u64) << 32 | (reply.blob_len as u64) << 48,
        ];
        for (word, value) in words.words.iter().zip(head.iter().chain(&reply.values)) {
            word.store(*value, Ordering::Relaxed);
        }
        store_blob(&self.blobs.reply, &reply.blob, reply.blob_len as usize);
        words.seq.store(reply.seq, Ordering::Release);
    }

    /// The task's side: the sequence number of the reply the mailbox holds, copied into
    /// `into`; `None` when it holds none or was rewritten during the copy. The value count
    /// and blob length are kept within their arrays.
    pub fn read_reply(&self, into: &mut Reply) -> Option<u64> {
        let head = &self.heads.reply;
        let seq = head.seq.load(Ordering::Acquire);
        if seq == 0 {
            return None;
        }
        into.seq = seq;
        let word = |i: usize| head.words[i].load(Ordering::Relaxed);
        (into.request_sent_ns, into.received_ns, into.sent_ns, into.cycle) = (word(0), word(1), word(2), word(3));
        let packed = word(4);
        into.rc = packed as u32;
        into.valuec = ((packed >> 32) as u16).min(MAX_ARGS as u16);
        into.blob_len = ((packed >> 48) as u16).min(BLOB_SIZE as u16);
        for (value, word) in into.values.iter_mut().zip(&head.words[5..]) {
            *value = word.load(Ordering::Relaxed);
        }
        load_blob(&self.blobs.reply, &mut into.blob, into.blob_len as usize);
        copy_is_whole(&head.seq, seq).then_some(seq)
    }
}

/// Every task's mailbox, the word that says which hold a posted call, and the tasks the
/// core serves.
#[repr(C)]
pub struct Calls {
    /// Bit t: task t posted a call since the core last looked.
    posted: AtomicU64,
    /// Bit t: the core serves task t (written once, when the core creates the table).
    configured: AtomicU64,
    /// Every task's heads, side by side: a cycle that serves 64 calls touches 5 pages of
    /// them, not 64 (on a virtual machine each page the RT thread touches may stall it,
    /// README "Huge pages"); the blobs after them.
    heads: [Heads; MAX_TASKS],
    blobs: [Blobs; MAX_TASKS],
}

// SAFETY: repr(C), only atomics, valid when zeroed (nothing posted, empty mailboxes).
unsafe impl Shareable for Calls {}

impl Calls {
    /// Task `task`'s mailbox.
    pub fn mailbox(&self, task: u8) -> Mailbox<'_> {
        Mailbox { heads: &self.heads[task as usize], blobs: &self.blobs[task as usize] }
    }

    /// The task's side: writes `request` into task `task`'s mailbox and posts it.
    pub fn post(&self, task: u8, request: &Request) {
        self.mailbox(task).write_request(request);
        self.posted.fetch_or(1 << task, Ordering::Release);
    }

    /// The core's side: the tasks that posted since the last look, bit t for task t.
    pub fn take_posted(&self) -> u64 {
        self.posted.swap(0, Ordering::AcqRel)
    }

    /// The tasks the core serves, bit t for task t.
    pub fn configured(&self) -> u64 {
        self.configured.load(Ordering::Acquire)
    }

    /// The core says which tasks it serves.
    pub fn set_configured(&self, tasks: u64) {
        self.configured.store(tasks, Ordering::Release);
    }
}

#[cfg(test)]
mod tests {
    use schema::layout::zeroed;

    use super::*;

    fn request(seq: u64, words: &[u64], blob: &[u8]) -> Request {
        let mut request = Request::new(42);
        request.seq = seq;
        request.sent_ns = 7;
        for &w in words {
            request.push_int(w as i64);
        }
        request.set_blob(blob);
        request
    }

    /// The heads the core touches for every call fit 5 pages for the 64 tasks, and no two
    /// writers share a cache line: a task's request head, the core's reply head, the next
    /// task's request head.
    #[test]
    fn the_heads_are_dense_and_each_writer_has_its_own_cache_lines() {
        assert_eq!(size_of::<Head<REQUEST_HEAD>>(), 128);
        assert_eq!(size_of::<Heads>(), 320);
        assert_eq!(std::mem::offset_of!(Heads, reply), 128);
        assert_eq!(std::mem::offset_of!(Calls, heads) % 64, 0);
        assert!(size_of::<[Heads; MAX_TASKS]>() <= 5 * 4096);
    }

    /// A posted request reaches the core whole, once; the core's reply reaches the task.
    #[test]
    fn a_posted_call_is_taken_once_and_answered() {
        let calls: Box<Calls> = zeroed();
        let mut taken = Request::new(0);
        assert_eq!(calls.mailbox(5).read_request(&mut taken), None, "an empty mailbox");
        let sent = request(1 << 32 | 1, &[3, u64::MAX], b"hello, core");
        calls.post(5, &sent);
        calls.post(9, &request(2 << 32 | 1, &[], b""));
        assert_eq!(calls.take_posted(), 1 << 5 | 1 << 9);
        assert_eq!(calls.take_posted(), 0, "taken once");
        assert_eq!(calls.mailbox(5).read_request(&mut taken), Some(sent.seq));
        assert_eq!((taken.func, taken.argc, taken.sent_ns), (42, 2, 7));
        assert_eq!((&taken.args[..2], taken.blob()), (&[3, u64::MAX][..], &b"hello, core"[..]));

        let mut reply = Reply::to(&taken);
        (reply.cycle, reply.rc) = (99, 0x8302_0078);
        reply.push_double(1.5);
        reply.set_blob(&[0xAB; BLOB_SIZE]);
        calls.mailbox(5).write_reply(&reply);
        let mut got = Reply::to(&Request::new(0));
        assert_eq!(calls.mailbox(5).read_reply(&mut got), Some(sent.seq));
        assert_eq!((got.cycle, got.rc, got.request_sent_ns), (99, 0x8302_0078, 7));
        assert_eq!((got.valuec, f64::from_bits(got.values[0])), (1, 1.5));
        assert_eq!(got.blob(), &[0xAB; BLOB_SIZE][..]);
        assert_eq!(calls.mailbox(9).read_reply(&mut got), None, "no reply for task 9 yet");
    }

    /// The mailbox holds the last reply until the next: a task that waits for call n+1
    /// reads call n's reply, by its sequence number not its own.
    #[test]
    fn a_stale_reply_shows_its_own_sequence() {
        let calls: Box<Calls> = zeroed();
        let mailbox = calls.mailbox(1);
        let first = request(7 << 32 | 1, &[1], b"");
        mailbox.write_request(&first);
        mailbox.write_reply(&Reply::to(&first));
        let second = request(7 << 32 | 2, &[2], b"");
        mailbox.write_request(&second);
        let mut got = Reply::to(&second);
        assert_eq!(mailbox.read_reply(&mut got), Some(first.seq), "the earlier call's reply");
        assert_eq!(got.seq, first.seq);
        mailbox.write_reply(&Reply::to(&second));
        assert_eq!(mailbox.read_reply(&mut got), Some(second.seq));
    }

    /// A request whose words no binding writes (an argument count past the arguments, a
    /// blob length past the blob) is copied out without a panic, read no further than the
    /// blob, and keeps its counts for the decoder to refuse.
    #[test]
    fn a_request_with_impossible_counts_is_copied_without_panic() {
        let calls: Box<Calls> = zeroed();
        let mailbox = calls.mailbox(2);
        let mut hostile = request(3 << 32 | 1, &[1, 2], &[0x55; 16]);
        (hostile.argc, hostile.blob_len) = (u16::MAX, u32::MAX);
        mailbox.write_request(&hostile);
        let mut taken = Request::new(0);
        assert_eq!(mailbox.read_request(&mut taken), Some(hostile.seq));
        assert_eq!((taken.argc, taken.blob_len), (u16::MAX, u32::MAX), "kept for the decoder");
        assert_eq!(&taken.blob[..16], &[0x55; 16]);

        let mut reply = Reply::to(&taken);
        (reply.valuec, reply.blob_len) = (u16::MAX, u16::MAX);
        mailbox.write_reply(&reply);
        let mut got = Reply::to(&taken);
        assert_eq!(mailbox.read_reply(&mut got), Some(hostile.seq));
        assert_eq!((got.valuec as usize, got.blob().len()), (MAX_ARGS, BLOB_SIZE), "kept within the arrays");
    }

    /// A write cut short (a process that died in it, or one rewriting while the core
    /// copies) leaves nothing a reader takes.
    #[test]
    fn a_half_written_request_is_not_taken() {
        let calls: Box<Calls> = zeroed();
        let mailbox = calls.mailbox(4);
        mailbox.write_request(&request(5 << 32 | 1, &[1], b""));
        begin_write(&mailbox.heads.request.seq);
        mailbox.heads.request.words[2].store(666, Ordering::Relaxed);
        let mut taken = Request::new(0);
        assert_eq!(mailbox.read_request(&mut taken), None, "died halfway: nothing to take");

        mailbox.write_request(&request(5 << 32 | 2, &[2], b""));
        let seen = mailbox.heads.request.seq.load(Ordering::Acquire);
        mailbox.write_request(&request(5 << 32 | 3, &[3], b""));
        assert!(!copy_is_whole(&mailbox.heads.request.seq, seen), "rewritten during a copy: dropped");
    }

    /// Two threads, one posting calls and waiting for their replies, one serving: every
    /// call is answered with its own arguments, none torn.
    #[test]
    fn calls_between_two_threads_are_never_torn() {
        let calls: std::sync::Arc<Box<Calls>> = std::sync::Arc::new(zeroed());
        let task = {
            let calls = calls.clone();
            std::thread::spawn(move || {
                let mut got = Reply::to(&Request::new(0));
                for n in 1..=2000u64 {
                    let blob = [n as u8; 40];
                    calls.post(3, &request(1 << 32 | n, &[n, !n], &blob));
                    while calls.mailbox(3).read_reply(&mut got) != Some(1 << 32 | n) {
                        std::hint::spin_loop();
                    }
                    assert_eq!((got.values[0], got.rc), (n * 2, 40), "call {n}");
                }
            })
        };
        let mut taken = Request::new(0);
        let mut served = 0;
        while served < 2000 {
            if calls.take_posted() & 1 << 3 == 0 {
                std::hint::spin_loop();
                continue;
            }
            let seq = calls.mailbox(3).read_request(&mut taken).expect("posted whole");
            assert_eq!((taken.args[1], taken.blob()), (!taken.args[0], &[taken.args[0] as u8; 40][..]));
            let mut reply = Reply::to(&taken);
            reply.push_int(taken.args[0] as i64 * 2);
            reply.rc = taken.blob_len;
            assert_eq!(reply.seq, seq);
            calls.mailbox(3).write_reply(&reply);
            served += 1;
        }
        task.join().unwrap();
    }
}

//! What every task shares (HMPL 1.5, 23.2, ch. 11, 2.22): the user table, the test
//! variables, the 8 mutexes and each task's persistent variables. One shared-memory
//! region per controller, read and written in place by the scripts; the core releases
//! the mutexes of a task that stops.

use std::sync::atomic::{AtomicI64, AtomicU8, AtomicU16, AtomicU32, AtomicU64, Ordering};

use num_enum::{FromPrimitive, IntoPrimitive};

use crate::ids::MAX_TASKS;
use crate::layout::Shareable;
use crate::plc_image::PlcImage;

/// HMPL ch. 11: `system_user_table[512000]`.
pub const USER_TABLE_LEN: usize = 512_000;
/// HMPL 23.2: `system_ltest0..9`, `system_dtest0..9`, `system_mtest[10]`.
pub const TEST_VARS: usize = 10;
/// HMPL 2.22: mutexes 0..7.
pub const MUTEXES: usize = 8;
/// Persistent variables per task.
pub const TASK_VARS: usize = 64;
/// Longest variable name and longest string value, bytes.
pub const VAR_NAME_BYTES: usize = 31;
/// Longest string value of a persistent variable, bytes.
pub const VAR_TEXT_BYTES: usize = 64;
/// Longest model name and serial number (HMPL 2.14, 2.15), bytes.
pub const IDENTITY_BYTES: usize = 64;

#[repr(C)]
/// The data all processes of a namespace share (HMPL ch. 11, 23.2, 16; DXMC A.1): user table, test variables, mutexes, task variables, DV and DH.
pub struct SharedData {
    user_table: [AtomicU64; USER_TABLE_LEN],
    ltest: [AtomicI64; TEST_VARS],
    dtest: [AtomicU64; TEST_VARS],
    mtest: [AtomicU64; TEST_VARS],
    /// 0: free; otherwise the owner's task id + 1. Also the futex word waiters sleep on.
    mutexes: [AtomicU32; MUTEXES],
    task_vars: [TaskVars; MAX_TASKS],
    /// DXMC A.1: the Modbus user areas, DV (volatile) and DH (kept by the controller).
    dv: [AtomicU16; USER_AREA_WORDS],
    dh: [AtomicU16; USER_AREA_WORDS],
    /// Bumped by every write to DH: the controller saves DH when it moves.
    dh_writes: AtomicU64,
    /// The FUN147 register image (docs/fun147.md).
    plc: PlcImage,
    /// HMPL 22.2.1: the one User ASCII agent, `pid << 8 | task + 1`; 0 when none claimed it.
    ascii_agent: AtomicU64,
    /// HMPL 22.2.2: the newest broadcasts, a ring the agent's process reads.
    broadcasts: [Broadcast; BROADCASTS],
    /// The number the next broadcast gets (its slot is that number modulo `BROADCASTS`).
    broadcast_next: AtomicU64,
    /// HMPL 2.14, 2.15: the model and the serial number the controller was started with,
    /// NUL-padded; written once before any task starts.
    model: [AtomicU8; IDENTITY_BYTES],
    serial: [AtomicU8; IDENTITY_BYTES],
}

/// HMPL 22.2.2: the longest `ASCII_ServerBroadcast` message, bytes.
pub const BROADCAST_BYTES: usize = 128;
/// Broadcasts kept for an agent that has not sent them yet.
pub const BROADCASTS: usize = 16;

/// One broadcast, written as a sequence lock: `stamp` is 0 while it is written, then its
/// number + 1, so that a reader can tell a torn or overwritten copy.
#[repr(C)]
struct Broadcast {
    stamp: AtomicU64,
    len: AtomicU64,
    bytes: [AtomicU64; BROADCAST_BYTES / 8],
}

/// Words of DV and of DH: 24 KiB each (DXMC A.1). Which Modbus address names which word
/// is the `calls` crate's business; this is the storage.
pub const USER_AREA_WORDS: usize = 0x3000;

// SAFETY: repr(C), only atomics, valid when zeroed (a zero table, free mutexes, no variables).
unsafe impl Shareable for SharedData {}

/// The test variables of HMPL 23.2.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TestVar {
    /// `system_ltest0..9`: integers.
    L(usize),
    /// `system_dtest0..9`: doubles.
    D(usize),
    /// `system_mtest[0..9]`: doubles.
    M(usize),
}

/// What `MutexLock` found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lock {
    /// The caller holds it now.
    Acquired,
    /// The caller holds it already: HMPL stops the task (0x13EC).
    Twice,
    /// Another task holds it.
    HeldBy(u8),
}

impl SharedData {
    /// Records the model and serial number (each cut to `IDENTITY_BYTES`).
    pub fn set_identity(&self, model: &str, serial: &str) {
        for (field, text) in [(&self.model, model), (&self.serial, serial)] {
            let bytes = text.as_bytes();
            for (i, b) in field.iter().enumerate() {
                b.store(bytes.get(i).copied().unwrap_or(0), Ordering::Relaxed);
            }
        }
    }

    /// The model and the serial number; empty before the controller wrote them.
    pub fn identity(&self) -> (Vec<u8>, Vec<u8>) {
        let read = |field: &[AtomicU8; IDENTITY_BYTES]| {
            field.iter().map(|b| b.load(Ordering::Relaxed)).take_while(|&b| b != 0).collect()
        };
        (read(&self.model), read(&self.serial))
    }

    /// The FUN147 register image.
    pub fn plc(&self) -> &PlcImage {
        &self.plc
    }

    /// Word `i` of DV (volatile); `None` past its end.
    pub fn dv_word(&self, i: usize) -> Option<u16> {
        self.dv.get(i).map(|w| w.load(Ordering::Relaxed))
    }

    /// Writes word `i` of DV; false past its end.
    pub fn set_dv_word(&self, i: usize, value: u16) -> bool {
        self.dv.get(i).map(|w| w.store(value, Ordering::Relaxed)).is_some()
    }

    /// Word `i` of DH (retentive); `None` past its end.
    pub fn dh_word(&self, i: usize) -> Option<u16> {
        self.dh.get(i).map(|w| w.load(Ordering::Relaxed))
    }

    /// Writes word `i` of DH and counts the write (DH is saved when it moves); false past its end.
    pub fn set_dh_word(&self, i: usize, value: u16) -> bool {
        let Some(word) = self.dh.get(i) else { return false };
        word.store(value, Ordering::Relaxed);
        self.dh_writes.fetch_add(1, Ordering::Release);
        true
    }

    /// How many writes DH has had: a change means it must be saved.
    pub fn dh_writes(&self) -> u64 {
        self.dh_writes.load(Ordering::Acquire)
    }

    /// DH as bytes (big-endian words, as on the wire), for its file.
    pub fn dh_bytes(&self) -> Vec<u8> {
        self.dh.iter().flat_map(|w| w.load(Ordering::Relaxed).to_be_bytes()).collect()
    }

    /// Restores DH from its file's bytes (a short file restores what it holds).
    pub fn load_dh(&self, bytes: &[u8]) {
        for (word, pair) in self.dh.iter().zip(bytes.chunks_exact(2)) {
            word.store(u16::from_be_bytes([pair[0], pair[1]]), Ordering::Relaxed);
        }
    }

    /// Entry `index` of the user table; `None` past its end.
    pub fn user_table(&self, index: usize) -> Option<f64> {
        self.user_table.get(index).map(|w| f64::from_bits(w.load(Ordering::Relaxed)))
    }

    /// Writes entry `index` of the user table; false past its end.
    pub fn set_user_table(&self, index: usize, value: f64) -> bool {
        self.user_table.get(index).map(|w| w.store(value.to_bits(), Ordering::Relaxed)).is_some()
    }

    /// The range `start .. start + len`, when it lies in the table.
    pub fn user_table_range(&self, start: i64, len: i64) -> Option<std::ops::Range<usize>> {
        let start = usize::try_from(start).ok()?;
        let len = usize::try_from(len).ok()?;
        let end = start.checked_add(len)?;
        (end <= USER_TABLE_LEN).then_some(start..end)
    }

    /// A test variable's value; `None` for an index past 9.
    pub fn test_var(&self, var: TestVar) -> Option<TestValue> {
        Some(match var {
            TestVar::L(i) => TestValue::Int(self.ltest.get(i)?.load(Ordering::Relaxed)),
            TestVar::D(i) => TestValue::Double(f64::from_bits(self.dtest.get(i)?.load(Ordering::Relaxed))),
            TestVar::M(i) => TestValue::Double(f64::from_bits(self.mtest.get(i)?.load(Ordering::Relaxed))),
        })
    }

    /// Stores a value; an integer variable takes the value truncated toward zero.
    pub fn set_test_var(&self, var: TestVar, value: f64) -> bool {
        match var {
            TestVar::L(i) => self.ltest.get(i).map(|w| w.store(value as i64, Ordering::Relaxed)),
            TestVar::D(i) => self.dtest.get(i).map(|w| w.store(value.to_bits(), Ordering::Relaxed)),
            TestVar::M(i) => self.mtest.get(i).map(|w| w.store(value.to_bits(), Ordering::Relaxed)),
        }
        .is_some()
    }

    /// HMPL 22.2.1: makes `task` (process `pid`) the User ASCII agent, unless another one
    /// holds the claim and `stale(task, pid)` says it still runs: then its task id. The
    /// same process claiming again keeps its claim.
    pub fn claim_ascii_agent(&self, task: u8, pid: u32, stale: impl Fn(u8, u32) -> bool) -> Result<(), u8> {
        let mine = (pid as u64) << 8 | (task as u64 + 1);
        let mut current = self.ascii_agent.load(Ordering::Acquire);
        loop {
            let owner = ((current & 0xFF) as u8).wrapping_sub(1);
            if current != 0 && current != mine && !stale(owner, (current >> 8) as u32) {
                return Err(owner);
            }
            match self.ascii_agent.compare_exchange(current, mine, Ordering::AcqRel, Ordering::Acquire) {
                Ok(_) => return Ok(()),
                Err(now) => current = now,
            }
        }
    }

    /// Gives up the claim of `task`'s process `pid`, if it holds it.
    pub fn release_ascii_agent(&self, task: u8, pid: u32) {
        let mine = (pid as u64) << 8 | (task as u64 + 1);
        let _ = self.ascii_agent.compare_exchange(mine, 0, Ordering::AcqRel, Ordering::Acquire);
    }

    /// The User ASCII agent's task and process, if one claimed it (it may have ended since).
    pub fn ascii_agent(&self) -> Option<(u8, u32)> {
        let word = self.ascii_agent.load(Ordering::Acquire);
        (word != 0).then(|| (((word & 0xFF) as u8).wrapping_sub(1), (word >> 8) as u32))
    }

    /// HMPL 22.2.2: queues `message` (at most `BROADCAST_BYTES`) for the agent's clients;
    /// false when it is longer.
    pub fn broadcast(&self, message: &[u8]) -> bool {
        if message.len() > BROADCAST_BYTES {
            return false;
        }
        let n = self.broadcast_next.fetch_add(1, Ordering::AcqRel);
        let slot = &self.broadcasts[n as usize % BROADCASTS];
        slot.stamp.store(0, Ordering::Release);
        std::sync::atomic::fence(Ordering::Release);
        slot.len.store(message.len() as u64, Ordering::Relaxed);
        let mut padded = [0u8; BROADCAST_BYTES];
        padded[..message.len()].copy_from_slice(message);
        for (word, bytes) in slot.bytes.iter().zip(padded.chunks_exact(8)) {
            word.store(u64::from_le_bytes(bytes.try_into().expect("8 bytes")), Ordering::Relaxed);
        }
        slot.stamp.store(n + 1, Ordering::Release);
        true
    }

    /// The number the next broadcast gets: an agent starting now sends what comes after.
    pub fn broadcast_cursor(&self) -> u64 {
        self.broadcast_next.load(Ordering::Acquire)
    }

    /// Hands each broadcast from number `cursor` on to `each` (those overwritten meanwhile
    /// are lost), and returns the cursor to go on from: one still being written stops it.
    pub fn broadcasts_since(&self, cursor: u64, mut each: impl FnMut(&[u8])) -> u64 {
        let next = self.broadcast_next.load(Ordering::Acquire);
        let mut n = cursor.max(next.saturating_sub(BROADCASTS as u64));
        while n < next {
            let slot = &self.broadcasts[n as usize % BROADCASTS];
            let stamp = slot.stamp.load(Ordering::Acquire);
            if stamp < n + 1 {
                break;
            }
            let mut bytes = [0u8; BROADCAST_BYTES];
            for (word, out) in slot.bytes.iter().zip(bytes.chunks_exact_mut(8)) {
                out.copy_from_slice(&word.load(Ordering::Relaxed).to_le_bytes());
            }
            let len = (slot.len.load(Ordering::Relaxed) as usize).min(BROADCAST_BYTES);
            std::sync::atomic::fence(Ordering::Acquire);
            if stamp == n + 1 && slot.stamp.load(Ordering::Relaxed) == stamp {
                each(&bytes[..len]);
            }
            n += 1;
        }
        n
    }

    /// HMPL 2.22: one attempt to take mutex `id` for `task`.
    pub fn try_lock(&self, id: usize, task: u8) -> Option<Lock> {
        let word = self.mutexes.get(id)?;
        let me = task as u32 + 1;
        Some(match word.compare_exchange(0, me, Ordering::Acquire, Ordering::Relaxed) {
            Ok(_) => Lock::Acquired,
            Err(owner) if owner == me => Lock::Twice,
            Err(owner) => Lock::HeldBy((owner - 1) as u8),
        })
    }

    /// Mutex `id`'s word: 0 free, otherwise the owner's task id + 1; the futex word its
    /// waiters sleep on (`ipc::mutex`).
    pub fn mutex_word(&self, id: usize) -> Option<&AtomicU32> {
        self.mutexes.get(id)
    }

    /// HMPL 2.23: frees mutex `id` if `task` holds it; whether it did. The waiters are
    /// the caller's to wake (`ipc::mutex::unlock`).
    pub fn release(&self, id: usize, task: u8) -> bool {
        let Some(word) = self.mutexes.get(id) else { return false };
        word.compare_exchange(task as u32 + 1, 0, Ordering::Release, Ordering::Relaxed).is_ok()
    }

    /// The owner of mutex `id`, if held.
    pub fn mutex_owner(&self, id: usize) -> Option<u8> {
        self.mutexes.get(id).map(|w| w.load(Ordering::Acquire)).filter(|&v| v != 0).map(|v| (v - 1) as u8)
    }

    /// The persistent variables of task `task`.
    pub fn task_vars(&self, task: u8) -> &TaskVars {
        &self.task_vars[task as usize]
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
/// A test variable's value (HMPL 23.2).
pub enum TestValue {
    /// `system_ltest0..9`.
    Int(i64),
    /// `system_dtest0..9` and `system_mtest`.
    Double(f64),
}

/// A value a persistent variable holds.
#[derive(Clone, Debug, PartialEq)]
pub enum VarValue {
    /// A Lua integer.
    Int(i64),
    /// A Lua float.
    Double(f64),
    /// A Lua boolean.
    Bool(bool),
    /// A Lua string, at most `VAR_TEXT_BYTES`.
    Text(String),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
/// Why a persistent variable was not stored.
pub enum VarError {
    #[error("names are 1 to {VAR_NAME_BYTES} bytes")]
    /// The name is empty, too long or holds a NUL.
    Name,
    #[error("strings hold at most {VAR_TEXT_BYTES} bytes")]
    /// The string is too long.
    TooLong,
    #[error("a task keeps at most {TASK_VARS} variables")]
    /// The task has no free entry.
    Full,
}

/// One task's variables that survive its restarts (HMPL 1.5: task variables keep their
/// values from one run to the next). Written only by the task's own process; each entry
/// keeps two copies and flips between them, so that a process killed in the middle of a
/// write leaves the previous value.
#[repr(C)]
pub struct TaskVars {
    entries: [VarEntry; TASK_VARS],
}

const IN_USE: u32 = 1 << 31;

#[repr(C)]
struct VarEntry {
    name: [AtomicU64; 4],
    /// `IN_USE` once the name is written; bit 0: which copy is current.
    header: AtomicU32,
    copies: [VarCopy; 2],
}

/// What a copy of a persistent variable holds. An unknown word reads as `Nil`: the
/// variable is not set.
#[derive(Clone, Copy, FromPrimitive, IntoPrimitive)]
#[repr(u32)]
enum VarKind {
    #[num_enum(default)]
    Nil = 0,
    Int = 1,
    Double = 2,
    Bool = 3,
    Text = 4,
}

#[repr(C)]
struct VarCopy {
    /// A `VarKind`.
    kind: AtomicU32,
    len: AtomicU32,
    word: AtomicU64,
    text: [AtomicU64; VAR_TEXT_BYTES / 8],
}

fn pack(bytes: &[u8], words: &[AtomicU64]) {
    let mut buf = vec![0u8; words.len() * 8];
    buf[..bytes.len()].copy_from_slice(bytes);
    for (w, chunk) in words.iter().zip(buf.chunks(8)) {
        w.store(u64::from_le_bytes(chunk.try_into().expect("8 bytes")), Ordering::Relaxed);
    }
}

fn unpack(words: &[AtomicU64]) -> Vec<u8> {
    words.iter().flat_map(|w| w.load(Ordering::Relaxed).to_le_bytes()).collect()
}

impl VarEntry {
    fn name_is(&self, name: &[u8]) -> bool {
        let stored = unpack(&self.name);
        stored[..name.len()] == *name && stored.get(name.len()).is_none_or(|&b| b == 0)
    }
}

impl TaskVars {
    fn find(&self, name: &[u8]) -> Option<&VarEntry> {
        self.entries.iter().find(|e| e.header.load(Ordering::Acquire) & IN_USE != 0 && e.name_is(name))
    }

    /// The value of variable `name`; `None` when it is not set.
    pub fn get(&self, name: &str) -> Option<VarValue> {
        let entry = self.find(name.as_bytes())?;
        let copy = &entry.copies[(entry.header.load(Ordering::Acquire) & 1) as usize];
        let word = copy.word.load(Ordering::Relaxed);
        Some(match VarKind::from(copy.kind.load(Ordering::Relaxed)) {
            VarKind::Int => VarValue::Int(word as i64),
            VarKind::Double => VarValue::Double(f64::from_bits(word)),
            VarKind::Bool => VarValue::Bool(word != 0),
            VarKind::Text => {
                let len = (copy.len.load(Ordering::Relaxed) as usize).min(VAR_TEXT_BYTES);
                VarValue::Text(String::from_utf8_lossy(&unpack(&copy.text)[..len]).into_owned())
            }
            VarKind::Nil => return None,
        })
    }

    /// Stores a value; `None` forgets the variable.
    pub fn set(&self, name: &str, value: Option<&VarValue>) -> Result<(), VarError> {
        let key = name.as_bytes();
        if key.is_empty() || key.len() > VAR_NAME_BYTES || key.contains(&0) {
            return Err(VarError::Name);
        }
        if let Some(VarValue::Text(t)) = value
            && t.len() > VAR_TEXT_BYTES
        {
            return Err(VarError::TooLong);
        }
        let entry = match self.find(key) {
            Some(entry) => entry,
            None if value.is_none() => return Ok(()),
            None => {
                let free = self
                    .entries
                    .iter()
                    .find(|e| e.header.load(Ordering::Acquire) & IN_USE == 0)
                    .ok_or(VarError::Full)?;
                pack(key, &free.name);
                free.copies[0].kind.store(VarKind::Nil.into(), Ordering::Relaxed);
                free.header.store(IN_USE, Ordering::Release);
                free
            }
        };
        let header = entry.header.load(Ordering::Acquire);
        let next = (header & 1) ^ 1;
        let copy = &entry.copies[next as usize];
        let (kind, word) = match value {
            None => (VarKind::Nil, 0),
            Some(VarValue::Int(i)) => (VarKind::Int, *i as u64),
            Some(VarValue::Double(d)) => (VarKind::Double, d.to_bits()),
            Some(VarValue::Bool(b)) => (VarKind::Bool, *b as u64),
            Some(VarValue::Text(t)) => {
                pack(t.as_bytes(), &copy.text);
                copy.len.store(t.len() as u32, Ordering::Relaxed);
                (VarKind::Text, 0)
            }
        };
        copy.kind.store(kind.into(), Ordering::Relaxed);
        copy.word.store(word, Ordering::Relaxed);
        entry.header.store(IN_USE | next, Ordering::Release);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn zeroed() -> Box<SharedData> {
        crate::layout::zeroed()
    }

    /// HMPL 22.2.1: one agent at a time; a stale owner (its process gone) gives way.
    #[test]
    fn one_ascii_agent_at_a_time() {
        let d = zeroed();
        let running = |_, _| false;
        assert_eq!(d.claim_ascii_agent(3, 100, running), Ok(()));
        assert_eq!(d.claim_ascii_agent(3, 100, running), Ok(()), "the agent again keeps it");
        assert_eq!(d.claim_ascii_agent(0, 200, running), Err(3), "another task while it runs: 0x1392");
        assert_eq!(d.claim_ascii_agent(3, 101, running), Err(3), "a new process of the same task too");
        assert_eq!(d.ascii_agent(), Some((3, 100)));
        assert_eq!(d.claim_ascii_agent(0, 200, |task, pid| (task, pid) == (3, 100)), Ok(()), "a stale owner");
        assert_eq!(d.ascii_agent(), Some((0, 200)));
        d.release_ascii_agent(3, 100);
        assert_eq!(d.ascii_agent(), Some((0, 200)), "only the owner releases");
        d.release_ascii_agent(0, 200);
        assert_eq!(d.claim_ascii_agent(5, 300, running), Ok(()), "released: free");
    }

    /// HMPL 22.2.2: broadcasts reach a reader in order, at most 128 bytes, the oldest lost
    /// when it falls more than the ring behind.
    #[test]
    fn broadcasts_in_order() {
        let d = zeroed();
        let read = |cursor| {
            let mut got = Vec::new();
            let next = d.broadcasts_since(cursor, |m| got.push(String::from_utf8_lossy(m).into_owned()));
            (next, got)
        };
        let start = d.broadcast_cursor();
        assert!(d.broadcast(b"one") && d.broadcast(&[b'x'; BROADCAST_BYTES]));
        assert!(!d.broadcast(&[b'x'; BROADCAST_BYTES + 1]), "129 bytes are refused");
        let (cursor, got) = read(start);
        assert_eq!(got, ["one".to_string(), "x".repeat(BROADCAST_BYTES)]);
        assert_eq!(read(cursor), (cursor, vec![]), "nothing twice");
        for i in 0..BROADCASTS + 3 {
            d.broadcast(format!("m{i}").as_bytes());
        }
        let (_, got) = read(cursor);
        assert_eq!(got.len(), BROADCASTS);
        assert_eq!((got[0].as_str(), got[BROADCASTS - 1].as_str()), ("m3", "m18"));
    }

    #[test]
    fn task_variables_keep_their_values() {
        let d = zeroed();
        let vars = d.task_vars(2);
        assert_eq!(vars.get("runs"), None);
        vars.set("runs", Some(&VarValue::Int(1))).unwrap();
        vars.set("runs", Some(&VarValue::Int(2))).unwrap();
        vars.set("name", Some(&VarValue::Text("axis 0".into()))).unwrap();
        vars.set("ratio", Some(&VarValue::Double(0.5))).unwrap();
        vars.set("on", Some(&VarValue::Bool(true))).unwrap();
        assert_eq!(vars.get("runs"), Some(VarValue::Int(2)));
        assert_eq!(vars.get("name"), Some(VarValue::Text("axis 0".into())));
        assert_eq!(vars.get("ratio"), Some(VarValue::Double(0.5)));
        assert_eq!(vars.get("on"), Some(VarValue::Bool(true)));
        assert_eq!(d.task_vars(3).get("runs"), None, "each task has its own");
        vars.set("runs", None).unwrap();
        assert_eq!(vars.get("runs"), None);
        assert_eq!(vars.set("", Some(&VarValue::Int(1))), Err(VarError::Name));
        assert_eq!(vars.set("s", Some(&VarValue::Text("x".repeat(65)))), Err(VarError::TooLong));
        for i in 0..TASK_VARS - 4 {
            vars.set(&format!("v{i}"), Some(&VarValue::Int(i as i64))).unwrap();
        }
        assert_eq!(vars.set("one_more", Some(&VarValue::Int(0))), Err(VarError::Full));
    }

    #[test]
    fn user_table_and_test_variables() {
        let d = zeroed();
        assert!(d.set_user_table(511_999, 2.5));
        assert_eq!(d.user_table(511_999), Some(2.5));
        assert!(!d.set_user_table(512_000, 1.0));
        assert_eq!(d.user_table_range(511_990, 10), Some(511_990..512_000));
        assert_eq!(d.user_table_range(511_991, 10), None);
        assert_eq!(d.user_table_range(-1, 2), None);
        assert!(d.set_test_var(TestVar::L(9), 7.9));
        assert_eq!(d.test_var(TestVar::L(9)), Some(TestValue::Int(7)));
        assert!(d.set_test_var(TestVar::M(0), 1.25));
        assert_eq!(d.test_var(TestVar::M(0)), Some(TestValue::Double(1.25)));
        assert_eq!(d.test_var(TestVar::D(10)), None);
    }
}

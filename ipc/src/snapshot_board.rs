//! The snapshot board (`lm.<ns>.snapshots`): the newest value of what one writer publishes
//! every cycle (the controller's state snapshot, `schema::Snapshot`), for every task and
//! tool to read in place. The board knows nothing of the value but that it is `Plain`.
//!
//! The RT thread writes each cycle's snapshot into a free slot and then makes it the
//! latest. A reader pins the slot it reads (one byte of its own in `pins`, a hazard
//! pointer) and the writer never writes a pinned slot or the latest one. So the writer
//! pays the same whatever the number of readers: one look at the pins (two cache lines),
//! where a publish-subscribe service delivers and takes back a sample per subscriber
//! (at 64 tasks that was 14 % of the RT thread's time; docs/decisions.md, "The snapshot
//! board").
//!
//! Readers: task `t` is reader `t` (a task's next process, started once the one before
//! was reaped, takes over its pin); a tool claims one of the [`TOOLS`] readers after the
//! tasks by writing its pid into `owners`, and takes over the reader of a dead one. Every
//! reader pins at most one slot, so with two slots more than readers the writer always
//! finds a free one, whatever the readers do or however they die.

use std::cell::UnsafeCell;
use std::sync::atomic::{AtomicU8, AtomicU32, Ordering};

use schema::MAX_TASKS;
use schema::layout::{Plain, Shareable};

use crate::error::IpcError;
use crate::limits::MAX_TOOLS;
use crate::namespace::Namespace;
use crate::process::process_alive;
use crate::shm::Region;

/// Readers that are tools (monitors, the web view, the soak), after the tasks'.
pub const TOOLS: usize = MAX_TOOLS;
/// Every reader: the tasks, then the tools.
pub const READERS: usize = MAX_TASKS + TOOLS;
/// One slot pinned by each reader at most, the latest, and the one being written.
pub const SLOTS: usize = READERS + 2;
/// The shared-memory file's name under the namespace.
pub const BOARD_REGION: &str = "snapshots";

/// A slot: a whole value, written only by the RT thread while no reader pins it.
#[repr(C, align(64))]
struct Slot<T>(UnsafeCell<T>);

/// A slot's place in `pins` and `latest`: its index plus one, 0 for none.
type SlotTag = u8;

/// The board. Each group of fields that one side writes has cache lines of its own.
#[repr(C)]
pub struct SnapshotBoard<T: Plain> {
    /// The slot holding the newest snapshot (a `SlotTag`; 0 before the first cycle).
    latest: Padded<AtomicU8>,
    /// The slot each reader reads (a `SlotTag`): written by the readers, read by the writer.
    pins: Padded<[AtomicU8; READERS]>,
    /// The pid of the tool holding each tool reader, 0 when free.
    owners: Padded<[AtomicU32; TOOLS]>,
    slots: [Slot<T>; SLOTS],
}

/// Fields on cache lines of their own.
#[repr(C, align(64))]
struct Padded<T>(T);

// SAFETY: repr(C); atomics and plain-number snapshots are valid when zeroed; the atomics
// change through atomics, and a slot is written (through its `UnsafeCell`) only by the one
// writer while the pin protocol keeps every reader off it.
unsafe impl<T: Plain> Shareable for SnapshotBoard<T> {}
// SAFETY: see above: the pins make the writer's and the readers' accesses to a slot exclusive.
unsafe impl<T: Plain> Sync for Slot<T> {}

impl<T: Plain> SnapshotBoard<T> {
    /// Creates the controller's board, empty.
    pub fn create(ns: &Namespace) -> Result<Region<SnapshotBoard<T>>, IpcError> {
        Region::create(ns, BOARD_REGION)
    }

    /// Opens a running controller's board.
    pub fn open(ns: &Namespace) -> Result<Region<SnapshotBoard<T>>, IpcError> {
        Region::open(ns, BOARD_REGION)
    }

    fn unpin(&self, reader: usize) {
        self.pins.0[reader].store(0, Ordering::SeqCst);
    }

    /// Slots pinned or latest, bit i for slot i. Tags out of range (a hostile process can
    /// write any byte here) are ignored.
    fn taken(&self) -> u128 {
        let tag_bit = |tag: SlotTag| match tag as usize {
            1..=SLOTS => 1u128 << (tag - 1),
            _ => 0,
        };
        let pinned = self.pins.0.iter().fold(0, |taken, pin| taken | tag_bit(pin.load(Ordering::SeqCst)));
        pinned | tag_bit(self.latest.0.load(Ordering::SeqCst))
    }

    fn slot(&self, index: usize) -> *mut T {
        self.slots[index].0.get()
    }
}

const _: () = assert!(SLOTS <= 128 && SLOTS < SlotTag::MAX as usize, "the taken slots fit a u128 and a tag");

/// The RT thread's end: writes each cycle's value in place into a free slot.
pub struct BoardWriter<T: Plain> {
    board: Region<SnapshotBoard<T>>,
    /// The layout generation each slot holds, plus one (0: none yet).
    layouts: [u64; SLOTS],
    /// The slot handed out by `begin` and not yet published.
    writing: Option<usize>,
}

/// A slot the writer is filling, from `BoardWriter::begin` to `BoardWriter::publish`.
pub struct SlotWrite<T> {
    index: usize,
    snapshot: *mut T,
}

impl<T> SlotWrite<T> {
    /// The value being written.
    pub fn payload_mut(&mut self) -> &mut T {
        // SAFETY: the slot is neither pinned nor the latest, so no reader looks at it, and
        // the writer hands out one `SlotWrite` at a time.
        unsafe { &mut *self.snapshot }
    }
}

impl<T: Plain> BoardWriter<T> {
    /// The writer of `board` (the controller's only one).
    pub fn new(board: Region<SnapshotBoard<T>>) -> Self {
        BoardWriter { board, layouts: [0; SLOTS], writing: None }
    }

    /// A free slot holding `layout` (what changes only with the bus; `generation` numbers
    /// its versions): copied in only when the slot holds another generation. The caller
    /// writes every other field. `None` when a slot is being written already or every slot
    /// is taken (only a process writing pins that are not its own can do that).
    pub fn begin(&mut self, layout: &T, generation: u64) -> Option<SlotWrite<T>> {
        if self.writing.is_some() {
            return None;
        }
        let free = !self.board.taken();
        let index = free.trailing_zeros() as usize;
        if index >= SLOTS {
            return None;
        }
        let snapshot = self.board.slot(index);
        if std::mem::replace(&mut self.layouts[index], generation + 1) != generation + 1 {
            // SAFETY: the slot is free (see `SlotWrite::payload_mut`).
            unsafe { std::ptr::copy_nonoverlapping(layout, snapshot, 1) };
        }
        self.writing = Some(index);
        Some(SlotWrite { index, snapshot })
    }

    /// Makes the slot written the latest.
    pub fn publish(&mut self, slot: SlotWrite<T>) {
        debug_assert_eq!(self.writing, Some(slot.index));
        self.writing = None;
        self.board.latest.0.store(slot.index as SlotTag + 1, Ordering::SeqCst);
    }
}

/// A reader's end: the newest value, pinned until the next look.
pub struct BoardReader<T: Plain> {
    board: Region<SnapshotBoard<T>>,
    /// Its reader; `READERS` for none yet (a pooled script process before its task).
    reader: usize,
    /// The tag this reader's pin holds.
    pinned: SlotTag,
    /// A tool's claim on its reader, released when dropped.
    tool: bool,
}

impl<T: Plain> BoardReader<T> {
    /// A reader of `board` that reads nothing until `attach_task`.
    pub fn standby(board: Region<SnapshotBoard<T>>) -> Self {
        BoardReader { board, reader: READERS, pinned: 0, tool: false }
    }

    /// Becomes task `task`'s reader (once).
    pub fn attach_task(&mut self, task: u8) {
        debug_assert!(self.reader == READERS && (task as usize) < MAX_TASKS);
        self.reader = task as usize;
    }

    /// A tool's reader: a free one, or one whose owner is dead.
    pub fn tool(board: Region<SnapshotBoard<T>>) -> Result<Self, IpcError> {
        let pid = std::process::id();
        for (i, owner) in board.owners.0.iter().enumerate() {
            let held = owner.load(Ordering::Acquire);
            if (held == 0 || !process_alive(held))
                && owner.compare_exchange(held, pid, Ordering::AcqRel, Ordering::Acquire).is_ok()
            {
                let reader = MAX_TASKS + i;
                board.unpin(reader);
                return Ok(BoardReader { board, reader, pinned: 0, tool: true });
            }
        }
        Err(IpcError::ToolReadersTaken(TOOLS))
    }

    /// The newest snapshot; `None` before the controller's first cycle. It stays as it is
    /// (pinned) until the next look.
    pub fn latest(&mut self) -> Option<&T> {
        self.refresh();
        self.pinned()
    }

    /// Pins the newest snapshot, for `pinned`.
    pub fn refresh(&mut self) {
        let Some(pin) = self.board.pins.0.get(self.reader) else { return };
        loop {
            let latest = self.board.latest.0.load(Ordering::SeqCst);
            if latest == self.pinned || !(1..=SLOTS).contains(&(latest as usize)) {
                return;
            }
            pin.store(latest, Ordering::SeqCst);
            self.pinned = latest;
            // Still the latest after the pin is visible: the writer, which looks at the
            // pins only after it has made another slot the latest, sees this pin before it
            // could choose this slot again.
            if self.board.latest.0.load(Ordering::SeqCst) == latest {
                return;
            }
        }
    }

    /// The snapshot the last `refresh` pinned; `None` before the first.
    pub fn pinned(&self) -> Option<&T> {
        // SAFETY: pinned (`refresh`), so the writer leaves the slot alone until the pin
        // moves, which takes `&mut self`.
        (self.pinned != 0).then(|| unsafe { &*self.board.slot(self.pinned as usize - 1) })
    }
}

impl<T: Plain> Drop for BoardReader<T> {
    fn drop(&mut self) {
        if self.reader == READERS {
            return;
        }
        self.board.unpin(self.reader);
        if self.tool {
            self.board.owners.0[self.reader - MAX_TASKS].store(0, Ordering::Release);
        }
    }
}

#[cfg(test)]
mod tests {
    use schema::layout::zeroed;

    use super::*;

    /// A small value for the board: a cycle number and a layout part the writer copies in
    /// only when its generation changes.
    #[derive(Clone, Copy, Default)]
    #[repr(C)]
    struct Counter {
        cycle: u64,
        layout: u32,
    }

    // SAFETY: repr(C), plain numbers, valid when zeroed.
    unsafe impl Plain for Counter {}

    type Board = SnapshotBoard<Counter>;

    fn region_pair() -> (Region<Board>, Region<Board>, Namespace) {
        static NEXT: AtomicU32 = AtomicU32::new(0);
        let ns = Namespace::new(&format!("board-{}-{}", std::process::id(), NEXT.fetch_add(1, Ordering::Relaxed)))
            .expect("namespace");
        let created = Board::create(&ns).expect("board");
        let opened = Board::open(&ns).expect("open");
        (created, opened, ns)
    }

    fn write(writer: &mut BoardWriter<Counter>, cycle: u64) -> usize {
        let layout = Counter::default();
        let mut slot = writer.begin(&layout, 0).expect("a free slot");
        slot.payload_mut().cycle = cycle;
        let index = slot.index;
        writer.publish(slot);
        index
    }

    /// A reader sees the newest snapshot, and the slot it holds is not written again
    /// until it looks again.
    #[test]
    fn a_pinned_snapshot_is_not_overwritten() {
        let (created, opened, _ns) = region_pair();
        let mut writer = BoardWriter::new(created);
        let mut reader = BoardReader::standby(opened);
        reader.attach_task(3);
        assert!(reader.latest().is_none(), "nothing before the first cycle");
        let first = write(&mut writer, 1);
        assert_eq!(reader.latest().map(|s| s.cycle), Some(1));
        let mut used = vec![first];
        for cycle in 2..200 {
            used.push(write(&mut writer, cycle));
        }
        assert!(!used[1..].contains(&first), "slot {first} is pinned by reader 3: never written again");
        assert_eq!(unsafe { (*writer.board.slot(first)).cycle }, 1);
        assert_eq!(reader.latest().map(|s| s.cycle), Some(199), "the next look moves the pin to the newest");
        // Another process writes a tag out of range: the reader keeps what it holds, the
        // writer's next publish puts it right.
        writer.board.latest.0.store(250, Ordering::SeqCst);
        assert_eq!(reader.latest().map(|s| s.cycle), Some(199));
        write(&mut writer, 200);
        assert_eq!(reader.latest().map(|s| s.cycle), Some(200));
        let mut distinct = used[1..].to_vec();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct.len(), 2, "with one slot pinned the writer alternates between two others");
    }

    /// Every reader holding another slot leaves the writer exactly one free slot;
    /// pins a hostile process wrote out of range are ignored.
    #[test]
    fn every_reader_pinned_still_leaves_a_slot() {
        let board = zeroed::<Board>();
        for (reader, pin) in board.pins.0.iter().enumerate() {
            pin.store(reader as u8 + 1, Ordering::SeqCst);
        }
        board.latest.0.store(READERS as u8 + 1, Ordering::SeqCst);
        let free = !board.taken();
        assert_eq!(free.trailing_zeros() as usize, SLOTS - 1, "the last slot is free");
        board.pins.0[0].store(200, Ordering::SeqCst);
        assert_eq!((!board.taken()).trailing_zeros(), 0, "an out-of-range pin pins nothing");
    }

    /// A tool's reader is freed when dropped, and the reader of a dead tool is taken over.
    #[test]
    fn tools_claim_free_and_dead_readers() {
        let (created, _opened, ns) = region_pair();
        let mut tools: Vec<BoardReader<Counter>> =
            (0..TOOLS).map(|_| BoardReader::tool(Board::open(&ns).unwrap()).unwrap()).collect();
        assert!(BoardReader::tool(Board::open(&ns).unwrap()).is_err(), "all {TOOLS} taken by a live process");
        let freed = tools.pop().unwrap().reader;
        assert_eq!(BoardReader::tool(Board::open(&ns).unwrap()).unwrap().reader, freed);
        // A pid that is not running (pid_max is at most 2^22).
        created.owners.0[0].store(1 << 23, Ordering::SeqCst);
        created.pins.0[MAX_TASKS].store(5, Ordering::SeqCst);
        let taken_over = BoardReader::tool(Board::open(&ns).unwrap()).unwrap();
        assert_eq!(taken_over.reader, MAX_TASKS);
        assert_eq!(created.pins.0[MAX_TASKS].load(Ordering::SeqCst), 0, "the dead tool's pin is released");
    }

    /// The layout part is copied into a slot only when the slot holds another generation;
    /// the rest of the value is the writer's to write each time.
    #[test]
    fn the_layout_is_copied_once_per_slot_and_generation() {
        let (created, opened, _ns) = region_pair();
        let mut writer = BoardWriter::new(created);
        let mut reader = BoardReader::standby(opened);
        reader.attach_task(0);
        let publish = |writer: &mut BoardWriter<Counter>, layout: u32, generation: u64, scribble: bool| {
            let mut slot = writer.begin(&Counter { cycle: 0, layout }, generation).expect("a free slot");
            if scribble {
                slot.payload_mut().layout = 99;
            }
            writer.publish(slot);
        };
        // Without a pin the writer alternates between slots 0 and 1.
        publish(&mut writer, 7, 0, false);
        publish(&mut writer, 7, 0, true);
        publish(&mut writer, 8, 0, false);
        assert_eq!(reader.latest().map(|c| c.layout), Some(7), "slot 0 again, generation 0: not copied again");
        publish(&mut writer, 8, 0, false);
        assert_eq!(reader.latest().map(|c| c.layout), Some(99), "slot 1 keeps what the writer wrote into it");
        publish(&mut writer, 8, 1, false);
        assert_eq!(reader.latest().map(|c| c.layout), Some(8), "a new generation is copied in");
    }
}

//! The process' global allocator, with a block pool for the RT thread.
//!
//! iceoryx2 0.10 creates one small `Rc` per publisher loan, so publishing the snapshot
//! and the replies allocates every cycle. On the RT thread those small allocations are
//! served from pre-touched, memory-locked free lists: O(1), no system call, no lock.
//! Every other allocation, and every other thread, goes to the system allocator.
//! `owner_system_allocations` counts the RT thread's falls back to the system allocator;
//! the steady-state test holds it at zero.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::ptr::null_mut;
use std::sync::atomic::{AtomicPtr, AtomicU64, Ordering};

/// Block sizes of the pool; each class is one contiguous slab.
const CLASSES: [usize; 5] = [32, 64, 128, 256, 512];
const BLOCKS_PER_CLASS: usize = 1024;
const MAX_ALIGN: usize = 16;

struct Node {
    next: *mut Node,
}

struct Class {
    size: usize,
    start: usize,
    end: usize,
    /// Free blocks, touched only by the owner thread.
    local: Cell<*mut Node>,
    /// Blocks other threads freed; the owner takes them all at once.
    remote: AtomicPtr<Node>,
}

struct Pool {
    classes: [Class; CLASSES.len()],
}

// SAFETY: `local` is only touched by the owner thread; `remote` is atomic.
unsafe impl Sync for Pool {}

static POOL: AtomicPtr<Pool> = AtomicPtr::new(null_mut());
static POOL_ALLOCATIONS: AtomicU64 = AtomicU64::new(0);
static OWNER_SYSTEM_ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

thread_local! {
    static IS_OWNER: Cell<bool> = const { Cell::new(false) };
}

fn is_owner() -> bool {
    IS_OWNER.try_with(Cell::get).unwrap_or(false)
}

/// Gives the calling thread the pool. Call once, from the RT thread, before its first
/// cycle; later calls from any thread do nothing.
pub fn claim_pool_for_this_thread() {
    if !POOL.load(Ordering::Acquire).is_null() {
        return;
    }
    let classes = CLASSES.map(|size| {
        let layout = Layout::from_size_align(size * BLOCKS_PER_CLASS, MAX_ALIGN).expect("valid slab");
        // SAFETY: non-zero size; the slab lives for the rest of the process.
        let start = unsafe { System.alloc(layout) } as usize;
        assert!(start != 0, "cannot reserve the RT pool");
        let mut head: *mut Node = null_mut();
        // Threading the free list writes every block: the slab is touched (and locked by mlockall).
        for i in (0..BLOCKS_PER_CLASS).rev() {
            let node = (start + i * size) as *mut Node;
            // SAFETY: `node` is inside the slab and aligned to 16.
            unsafe { node.write(Node { next: head }) };
            head = node;
        }
        Class {
            size,
            start,
            end: start + size * BLOCKS_PER_CLASS,
            local: Cell::new(head),
            remote: AtomicPtr::new(null_mut()),
        }
    });
    let pool = Box::into_raw(Box::new(Pool { classes }));
    if POOL.compare_exchange(null_mut(), pool, Ordering::AcqRel, Ordering::Acquire).is_ok() {
        IS_OWNER.with(|o| o.set(true));
    }
}

/// Allocations the pool has served.
pub fn pool_allocations() -> u64 {
    POOL_ALLOCATIONS.load(Ordering::Relaxed)
}

/// Allocations of the owner thread that went to the system allocator (too large, or the
/// pool class was empty).
pub fn owner_system_allocations() -> u64 {
    OWNER_SYSTEM_ALLOCATIONS.load(Ordering::Relaxed)
}

pub struct RtAllocator;

impl RtAllocator {
    fn pool() -> Option<&'static Pool> {
        // SAFETY: once published, the pool is never freed.
        unsafe { POOL.load(Ordering::Acquire).as_ref() }
    }

    unsafe fn pool_alloc(layout: Layout) -> *mut u8 {
        let Some(pool) = Self::pool() else { return null_mut() };
        if layout.align() > MAX_ALIGN {
            return null_mut();
        }
        let Some(class) = pool.classes.iter().find(|c| c.size >= layout.size()) else { return null_mut() };
        let mut head = class.local.get();
        if head.is_null() {
            head = class.remote.swap(null_mut(), Ordering::Acquire);
        }
        if head.is_null() {
            return null_mut();
        }
        // SAFETY: `head` is a free block of this class.
        class.local.set(unsafe { (*head).next });
        POOL_ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        head as *mut u8
    }
}

unsafe impl GlobalAlloc for RtAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if is_owner() {
            // SAFETY: only the owner thread reaches the pool's local lists.
            let block = unsafe { Self::pool_alloc(layout) };
            if !block.is_null() {
                return block;
            }
            OWNER_SYSTEM_ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: forwarded as is.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        let address = ptr as usize;
        if let Some(class) = Self::pool().and_then(|p| p.classes.iter().find(|c| (c.start..c.end).contains(&address))) {
            let node = ptr as *mut Node;
            if is_owner() {
                // SAFETY: a block of this class, returned by its owner.
                unsafe { node.write(Node { next: class.local.get() }) };
                class.local.set(node);
            } else {
                let mut head = class.remote.load(Ordering::Relaxed);
                loop {
                    // SAFETY: the block is ours until the exchange publishes it.
                    unsafe { node.write(Node { next: head }) };
                    match class.remote.compare_exchange_weak(head, node, Ordering::Release, Ordering::Relaxed) {
                        Ok(_) => break,
                        Err(current) => head = current,
                    }
                }
            }
            return;
        }
        // SAFETY: not a pool block, so the system allocator's.
        unsafe { System.dealloc(ptr, layout) }
    }
}

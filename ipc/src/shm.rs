//! Plain shared memory for data every process reads and writes in place: the task
//! table (heartbeats, wait requests, mailboxes), the user table, the snapshot board and
//! the scope's ring. Built on iceoryx2's POSIX layer, named under the controller's
//! namespace.
//!
//! Every region is sized in whole 2 MiB pages and mapped at a 2 MiB-aligned address, so
//! the controller can have the kernel back it with huge pages (`rt_core::huge_pages`):
//! the RT thread touches these regions every cycle, and on a virtual machine each 4 KiB
//! page touched may cost it a stall.

use std::marker::PhantomData;

use iceoryx2_bb_container::semantic_string::SemanticString;
use iceoryx2_bb_posix::creation_mode::CreationMode;
use iceoryx2_bb_posix::shared_memory::{AccessMode, SharedMemory, SharedMemoryBuilder};
use iceoryx2_bb_system_types::file_name::FileName;

use schema::layout::Shareable;

use crate::advice::shm_failed;
use crate::error::{IpcError, Refusal};
use crate::namespace::Namespace;

/// 2 MiB: the x86-64 and arm64 (4 KiB granule) PMD page, the size of a huge page.
pub const HUGE_PAGE: usize = 2 << 20;

/// A typed shared-memory region. The creator removes it when dropped.
pub struct Region<T: Shareable> {
    shm: SharedMemory,
    _type: PhantomData<T>,
}

impl<T: Shareable> Region<T> {
    /// Creates the region zeroed, replacing a stale one left by a dead controller.
    pub fn create(ns: &Namespace, what: &str) -> Result<Self, IpcError> {
        let name = file_name(ns, what)?;
        let size = Self::mapped_size();
        let shm = map_aligned(&name, size, |builder| {
            builder.creation_mode(CreationMode::PurgeAndCreate).size(size).zero_memory(true).create()
        })
        .map_err(|e| shm_failed(what, e))?;
        Self::checked(shm, what)
    }

    /// Opens a region a controller created.
    pub fn open(ns: &Namespace, what: &str) -> Result<Self, IpcError> {
        let name = file_name(ns, what)?;
        let shm = map_aligned(&name, Self::mapped_size(), |builder| builder.open_existing(AccessMode::ReadWrite))
            .map_err(|e| shm_failed(what, e))?;
        Self::checked(shm, what)
    }

    /// `T` rounded up to whole huge pages: the size of the region's file and mapping.
    fn mapped_size() -> usize {
        size_of::<T>().next_multiple_of(HUGE_PAGE)
    }

    fn checked(shm: SharedMemory, what: &str) -> Result<Self, IpcError> {
        if shm.size() < size_of::<T>() || !(shm.base_address().as_ptr() as usize).is_multiple_of(align_of::<T>()) {
            return Err(IpcError::ShmLayout(what.to_string()));
        }
        Ok(Region { shm, _type: PhantomData })
    }
}

impl<T: Shareable> std::ops::Deref for Region<T> {
    type Target = T;

    fn deref(&self) -> &T {
        // SAFETY: size and alignment were checked; `Shareable` types are valid when zeroed
        // and only mutated through atomics, so shared references are sound.
        unsafe { &*(self.shm.base_address().as_ptr() as *const T) }
    }
}

/// Maps the region `name` with `map` at a free 2 MiB-aligned address, or, where none could be
/// had (another thread took the address in between), wherever the kernel puts it.
fn map_aligned<E>(
    name: &FileName,
    size: usize,
    map: impl Fn(SharedMemoryBuilder) -> Result<SharedMemory, E>,
) -> Result<SharedMemory, E> {
    // Note the aligned start of a fresh reservation, give it back, and ask for it.
    // SAFETY: an anonymous reservation of fresh address space, unmapped at once.
    let at = unsafe {
        let len = size + HUGE_PAGE;
        let flags = libc::MAP_PRIVATE | libc::MAP_ANONYMOUS | libc::MAP_NORESERVE;
        let reserved = libc::mmap(std::ptr::null_mut(), len, libc::PROT_NONE, flags, -1, 0);
        (reserved != libc::MAP_FAILED).then(|| {
            libc::munmap(reserved, len);
            (reserved as usize).next_multiple_of(HUGE_PAGE) as u64
        })
    };
    match at.map(|at| map(SharedMemoryBuilder::new(name).enforce_base_address(at))) {
        Some(Ok(shm)) => Ok(shm),
        _ => map(SharedMemoryBuilder::new(name)),
    }
}

fn file_name(ns: &Namespace, what: &str) -> Result<FileName, IpcError> {
    let name = format!("{}{what}", ns.prefix());
    FileName::new(name.as_bytes()).map_err(|e| IpcError::Shm { what: name, source: Refusal::FileName(e) })
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicU64, Ordering};

    use super::*;

    #[repr(C)]
    struct Cells([AtomicU64; 8]);
    // SAFETY: `repr(C)` atomics, valid when zeroed.
    unsafe impl Shareable for Cells {}

    /// The file and every mapping of a region are whole huge pages at aligned addresses,
    /// so a huge page can back it in each process; and both mappings are one memory.
    #[test]
    fn a_region_is_whole_huge_pages_mapped_at_aligned_addresses() {
        let ns = Namespace::new(&format!("shm-{}", std::process::id())).expect("namespace");
        let created = Region::<Cells>::create(&ns, "cells").expect("create");
        let opened = Region::<Cells>::open(&ns, "cells").expect("open");
        let file = std::fs::metadata(format!("/dev/shm/{}cells", ns.prefix())).expect("the region's file");
        assert_eq!(file.len(), HUGE_PAGE as u64, "one huge page for 64 bytes");
        for region in [&created, &opened] {
            let at = &**region as *const Cells as usize;
            assert_eq!(at % HUGE_PAGE, 0, "mapped at {at:#x}");
        }
        created.0[7].store(42, Ordering::Relaxed);
        assert_eq!(opened.0[7].load(Ordering::Relaxed), 42);
    }
}

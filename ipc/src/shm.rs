//! Plain shared memory for data every process reads and writes in place: the task
//! table (heartbeats, wait requests) and, later, the user table. Built on iceoryx2's
//! POSIX layer, named under the controller's namespace.

use std::marker::PhantomData;

use iceoryx2_bb_container::semantic_string::SemanticString;
use iceoryx2_bb_posix::creation_mode::CreationMode;
use iceoryx2_bb_posix::shared_memory::{AccessMode, SharedMemory, SharedMemoryBuilder};
use iceoryx2_bb_system_types::file_name::FileName;

use crate::services::classify;
use crate::{IpcError, Namespace};

/// A type that may live in shared memory: `#[repr(C)]`, valid when all-zero, and only
/// changed through atomics (so `&T` is enough to write it).
///
/// # Safety
/// The implementor guarantees the three properties above.
pub unsafe trait Shareable: Sync {}

/// A `Shareable` value in this process' own memory, zeroed (for tests and tools that
/// work without a controller).
pub fn zeroed<T: Shareable>() -> Box<T> {
    let layout = std::alloc::Layout::new::<T>();
    assert!(layout.size() > 0, "shared types have a size");
    // SAFETY: a `Shareable` type is valid when zeroed, and the layout is `T`'s.
    unsafe {
        let ptr = std::alloc::alloc_zeroed(layout) as *mut T;
        if ptr.is_null() {
            std::alloc::handle_alloc_error(layout);
        }
        Box::from_raw(ptr)
    }
}

/// A typed shared-memory region. The creator removes it when dropped.
pub struct Region<T: Shareable> {
    shm: SharedMemory,
    _type: PhantomData<T>,
}

impl<T: Shareable> Region<T> {
    /// Creates the region zeroed, replacing a stale one left by a dead controller.
    pub fn create(ns: &Namespace, what: &str) -> Result<Self, IpcError> {
        let name = file_name(ns, what)?;
        let shm = SharedMemoryBuilder::new(&name)
            .creation_mode(CreationMode::PurgeAndCreate)
            .size(size_of::<T>())
            .zero_memory(true)
            .create()
            .map_err(|e| classify(what, e, IpcError::Shm))?;
        Self::checked(shm, what)
    }

    /// Opens a region a controller created.
    pub fn open(ns: &Namespace, what: &str) -> Result<Self, IpcError> {
        let name = file_name(ns, what)?;
        let shm = SharedMemoryBuilder::new(&name)
            .open_existing(AccessMode::ReadWrite)
            .map_err(|e| classify(what, e, IpcError::Shm))?;
        Self::checked(shm, what)
    }

    fn checked(shm: SharedMemory, what: &str) -> Result<Self, IpcError> {
        if shm.size() < size_of::<T>() || !(shm.base_address().as_ptr() as usize).is_multiple_of(align_of::<T>()) {
            return Err(IpcError::Shm(format!("{what}: size or alignment does not match this build")));
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

fn file_name(ns: &Namespace, what: &str) -> Result<FileName, IpcError> {
    let name = format!("{}{what}", ns.prefix());
    FileName::new(name.as_bytes()).map_err(|e| IpcError::Shm(format!("{name}: {e:?}")))
}

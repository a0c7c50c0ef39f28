//! What a type must be to live in shared memory, where every process of a namespace
//! maps it in place.

/// A type that may live in shared memory: `#[repr(C)]`, valid when all-zero, and only
/// changed through atomics (so `&T` is enough to write it).
///
/// # Safety
/// The implementor guarantees the three properties above.
pub unsafe trait Shareable: Sync {}

/// A value copied whole into shared memory by one writer while no reader looks at it
/// (a snapshot on the board): `#[repr(C)]`, plain numbers without pointers, valid when
/// all-zero.
///
/// # Safety
/// The implementor guarantees the properties above.
pub unsafe trait Plain: Copy + Send + 'static {}

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

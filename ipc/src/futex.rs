//! Futexes on words in shared memory (so not `FUTEX_PRIVATE`): the mutexes of the shared
//! data and the tasks' bells; private ones for the controller's own threads.

use std::sync::atomic::AtomicU32;
use std::time::Duration;

/// Sleeps while `word` holds `expected`, at most `timeout`; returns at once otherwise.
pub fn wait(word: &AtomicU32, expected: u32, timeout: Duration) {
    wait_op(word, expected, timeout, libc::FUTEX_WAIT);
}

/// `wait` on a word only this process' threads use. A private futex is hashed in the
/// process' own table (Linux 6.16+, `CONFIG_FUTEX_PRIVATE_HASH`), so its calls never queue
/// for a hash-bucket lock that another process' futex call holds, perhaps on a vCPU the
/// host has descheduled.
pub fn wait_private(word: &AtomicU32, expected: u32, timeout: Duration) {
    wait_op(word, expected, timeout, libc::FUTEX_WAIT | libc::FUTEX_PRIVATE_FLAG);
}

fn wait_op(word: &AtomicU32, expected: u32, timeout: Duration, op: libc::c_int) {
    let ts = libc::timespec { tv_sec: timeout.as_secs() as libc::time_t, tv_nsec: timeout.subsec_nanos() as _ };
    // SAFETY: a FUTEX_WAIT on a live, aligned u32; the kernel compares it with `expected`
    // before it sleeps, so a change made before the call is never missed.
    unsafe {
        libc::syscall(libc::SYS_futex, word.as_ptr(), op, expected, &ts as *const libc::timespec);
    }
}

/// As `wait`, after watching `word` for up to `spin` first (`spin_while`).
pub fn wait_spinning(word: &AtomicU32, expected: u32, spin: Duration, timeout: Duration) {
    if spin_while(word, expected, spin) {
        wait(word, expected, timeout);
    }
}

/// Watches `word` for up to `spin`; returns whether it still holds `expected`. On the
/// simulation clock the core and a task hand the turn to each other thousands of times a
/// second, and a change seen while spinning on the other core saves the wake-up of a
/// sleeping one (tens of microseconds each on a virtual machine).
pub fn spin_while(word: &AtomicU32, expected: u32, spin: Duration) -> bool {
    let until = crate::clock::monotonic_ns() + spin.as_nanos() as u64;
    while word.load(std::sync::atomic::Ordering::Acquire) == expected {
        if crate::clock::monotonic_ns() >= until {
            return true;
        }
        for _ in 0..64 {
            std::hint::spin_loop();
        }
    }
    false
}

/// As `wait`, for a waker that wakes by `bits` (`wake_bits`): this sleeper is woken by a
/// wake whose bits include `bit`.
pub fn wait_bit(word: &AtomicU32, expected: u32, bit: u32, timeout: Duration) {
    // FUTEX_WAIT_BITSET takes an absolute CLOCK_MONOTONIC deadline.
    let at = crate::clock::monotonic_ns() + timeout.as_nanos() as u64;
    let deadline = libc::timespec { tv_sec: (at / 1_000_000_000) as libc::time_t, tv_nsec: (at % 1_000_000_000) as _ };
    // SAFETY: a FUTEX_WAIT_BITSET on a live, aligned u32 with a valid deadline and a
    // nonzero bitset; the kernel compares the word with `expected` before it sleeps.
    unsafe {
        libc::syscall(
            libc::SYS_futex,
            word.as_ptr(),
            libc::FUTEX_WAIT_BITSET,
            expected,
            &deadline as *const libc::timespec,
            std::ptr::null::<u32>(),
            bit,
        );
    }
}

/// Wakes, in one syscall, whoever sleeps on `word` with a bit in `bits` (`wait_bit`).
/// Never blocks.
pub fn wake_bits(word: &AtomicU32, bits: u32) {
    // SAFETY: FUTEX_WAKE_BITSET on a live, aligned u32 with a nonzero bitset.
    unsafe {
        libc::syscall(
            libc::SYS_futex,
            word.as_ptr(),
            libc::FUTEX_WAKE_BITSET,
            i32::MAX,
            std::ptr::null::<libc::timespec>(),
            std::ptr::null::<u32>(),
            bits,
        );
    }
}

/// Wakes whoever sleeps on `word`. Never blocks.
pub fn wake(word: &AtomicU32) {
    // SAFETY: FUTEX_WAKE on a live, aligned u32.
    unsafe {
        libc::syscall(libc::SYS_futex, word.as_ptr(), libc::FUTEX_WAKE, i32::MAX);
    }
}

/// Wakes whoever sleeps on `word` with `wait_private`. Never blocks.
pub fn wake_private(word: &AtomicU32) {
    // SAFETY: FUTEX_WAKE_PRIVATE on a live, aligned u32.
    unsafe {
        libc::syscall(libc::SYS_futex, word.as_ptr(), libc::FUTEX_WAKE | libc::FUTEX_PRIVATE_FLAG, i32::MAX);
    }
}

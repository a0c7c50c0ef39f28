//! HMPL 2.22/2.23's mutexes of the shared data: taking one is a compare-and-swap on its
//! word (`SharedData::try_lock`); waiting for one and waking its waiters are futex calls
//! on the same word, in shared memory.

use std::time::Duration;

use schema::shared::{MUTEXES, SharedData};

use crate::futex;

/// Sleeps until mutex `id` is no longer held by `owner`, or `timeout` passes.
pub fn wait_for_mutex(shared: &SharedData, id: usize, owner: u8, timeout: Duration) {
    if let Some(word) = shared.mutex_word(id) {
        futex::wait(word, owner as u32 + 1, timeout);
    }
}

/// HMPL 2.23: releases mutex `id` if `task` holds it and wakes its waiters; otherwise
/// nothing happens.
pub fn unlock(shared: &SharedData, id: usize, task: u8) -> bool {
    let released = shared.release(id, task);
    if released && let Some(word) = shared.mutex_word(id) {
        futex::wake(word);
    }
    released
}

/// Releases every mutex `task` holds (the task stopped). Wakes the waiters; never blocks.
pub fn release_mutexes_of(shared: &SharedData, task: u8) {
    for id in 0..MUTEXES {
        unlock(shared, id, task);
    }
}

#[cfg(test)]
mod tests {
    use schema::layout::zeroed;
    use schema::shared::Lock;

    use super::*;

    /// HMPL 2.22/2.23: owner semantics, one row per rule.
    #[test]
    fn mutex_rules() {
        let d: Box<SharedData> = zeroed();
        assert_eq!(d.try_lock(0, 3), Some(Lock::Acquired), "free: taken");
        assert_eq!(d.try_lock(0, 3), Some(Lock::Twice), "the owner again: a runtime error");
        assert_eq!(d.try_lock(0, 4), Some(Lock::HeldBy(3)), "another task: it waits");
        assert!(!unlock(&d, 0, 4), "a non-owner's unlock does nothing");
        assert_eq!(d.mutex_owner(0), Some(3));
        assert!(unlock(&d, 0, 3));
        assert_eq!(d.try_lock(0, 4), Some(Lock::Acquired));
        d.try_lock(5, 4);
        release_mutexes_of(&d, 4);
        assert_eq!((d.mutex_owner(0), d.mutex_owner(5)), (None, None), "released when the owner stops");
        assert_eq!(d.try_lock(8, 0), None, "ids 0..7");
    }

    #[test]
    fn a_waiter_wakes_when_the_owner_unlocks() {
        let d: &'static SharedData = Box::leak(zeroed());
        d.try_lock(1, 0);
        let waiter = std::thread::spawn(move || {
            while d.try_lock(1, 1) != Some(Lock::Acquired) {
                wait_for_mutex(d, 1, 0, Duration::from_secs(5));
            }
        });
        std::thread::sleep(Duration::from_millis(20));
        unlock(d, 1, 0);
        waiter.join().unwrap();
        assert_eq!(d.mutex_owner(1), Some(1));
    }
}

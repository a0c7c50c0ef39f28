//! The group command buffer (HMPL 8.1: "up to 512 motion commands", SetGrpQueueSize 1..1024):
//! a ring allocated once with room for the largest size, so pushing never allocates.

/// The most entries any queue size allows (HMPL 8.3.35: 2^10).
pub const MAX_QUEUE_SIZE: usize = 1024;

pub(crate) struct Ring<T> {
    slots: Vec<Option<T>>,
    head: usize,
    len: usize,
}

impl<T> Ring<T> {
    pub(crate) fn new() -> Ring<T> {
        Ring { slots: (0..MAX_QUEUE_SIZE).map(|_| None).collect(), head: 0, len: 0 }
    }

    pub(crate) fn len(&self) -> usize {
        self.len
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.len == 0
    }

    fn slot(&self, i: usize) -> usize {
        (self.head + i) % MAX_QUEUE_SIZE
    }

    /// Appends; the caller has checked the room against the queue size.
    pub(crate) fn push(&mut self, value: T) {
        debug_assert!(self.len < MAX_QUEUE_SIZE);
        let s = self.slot(self.len);
        self.slots[s] = Some(value);
        self.len += 1;
    }

    pub(crate) fn pop_front(&mut self) -> Option<T> {
        if self.len == 0 {
            return None;
        }
        let value = self.slots[self.head].take();
        self.head = (self.head + 1) % MAX_QUEUE_SIZE;
        self.len -= 1;
        value
    }

    /// Drops everything from index `from` on.
    pub(crate) fn truncate(&mut self, from: usize) {
        while self.len > from {
            let s = self.slot(self.len - 1);
            self.slots[s] = None;
            self.len -= 1;
        }
    }

    pub(crate) fn get(&self, i: usize) -> Option<&T> {
        if i < self.len { self.slots[self.slot(i)].as_ref() } else { None }
    }

    pub(crate) fn get_mut(&mut self, i: usize) -> Option<&mut T> {
        if i < self.len {
            let s = self.slot(i);
            self.slots[s].as_mut()
        } else {
            None
        }
    }

    pub(crate) fn last(&self) -> Option<&T> {
        self.len.checked_sub(1).and_then(|i| self.get(i))
    }

    pub(crate) fn last_mut(&mut self) -> Option<&mut T> {
        self.len.checked_sub(1).and_then(|i| self.get_mut(i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn it_wraps_around_without_losing_order() {
        let mut r = Ring::new();
        for round in 0..3 {
            for i in 0..1000 {
                r.push(round * 1000 + i);
            }
            for i in 0..1000 {
                assert_eq!(r.pop_front(), Some(round * 1000 + i));
            }
        }
        assert!(r.is_empty());
        r.push(1);
        r.push(2);
        r.push(3);
        r.truncate(1);
        assert_eq!((r.len(), r.last()), (1, Some(&1)));
    }
}

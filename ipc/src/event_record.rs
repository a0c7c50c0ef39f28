//! The record of the `events` stream: what `SendEvent` and `SendMsgEvent` send and the
//! alarms the controller raises. It is the iceoryx2 service's payload, so it lives with
//! its transport.

use iceoryx2::prelude::ZeroCopySend;
use num_enum::{IntoPrimitive, TryFromPrimitive};

/// Bytes of text an event carries: `SendMsgEvent`'s 128 characters and an alarm's line.
pub const EVENT_TEXT_BYTES: usize = 160;
/// The `task` of an event the controller raised.
pub const CONTROLLER: u32 = 0xFF;

/// What an event record is. An unknown kind is an error: the tools skip the record.
#[derive(Debug, Clone, Copy, PartialEq, Eq, TryFromPrimitive, IntoPrimitive)]
#[repr(u32)]
pub enum EventKind {
    /// `SendEvent(id)` (HMPL 2.19).
    Event = 1,
    /// `SendMsgEvent(...)` (HMPL 2.20).
    Message = 2,
    /// An alarm in the DXMC format (DXMC 9, `0xXYZUABCD`).
    Alarm = 3,
}

/// One record of the `events` stream the tools follow.
#[derive(Debug, Clone, Copy, ZeroCopySend)]
#[repr(C)]
pub struct EventRecord {
    /// The cycle it was raised in.
    pub cycle: u64,
    /// `EventKind` as a number.
    pub kind: u32,
    /// The task that sent or caused it; `CONTROLLER` for the controller.
    pub task: u32,
    /// The event id or the alarm code.
    pub code: u32,
    /// Bytes used in `text`.
    pub len: u32,
    /// UTF-8 text, cut at a character boundary.
    pub text: [u8; EVENT_TEXT_BYTES],
}

impl EventRecord {
    /// A record; `text` is cut to `EVENT_TEXT_BYTES` at a character boundary.
    pub fn new(kind: EventKind, task: u32, cycle: u64, code: u32, text: &str) -> Self {
        let mut record = EventRecord { cycle, kind: kind.into(), task, code, len: 0, text: [0; EVENT_TEXT_BYTES] };
        let mut n = text.len().min(EVENT_TEXT_BYTES);
        while !text.is_char_boundary(n) {
            n -= 1;
        }
        record.text[..n].copy_from_slice(&text.as_bytes()[..n]);
        record.len = n as u32;
        record
    }

    /// The record's kind; `None` for a number no kind has.
    pub fn kind(&self) -> Option<EventKind> {
        EventKind::try_from(self.kind).ok()
    }

    /// The text (invalid UTF-8 replaced).
    pub fn text(&self) -> String {
        String::from_utf8_lossy(&self.text[..(self.len as usize).min(EVENT_TEXT_BYTES)]).into_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::{EventKind, EventRecord};

    /// The kinds of the `events` stream; a record of an unknown kind has none.
    #[test]
    fn event_kind_words() {
        let rows = [(EventKind::Event, 1u32), (EventKind::Message, 2), (EventKind::Alarm, 3)];
        for (kind, word) in rows {
            let record = EventRecord::new(kind, 0, 0, 0, "");
            assert_eq!(record.kind, word, "{kind:?}");
            assert_eq!(record.kind(), Some(kind));
        }
        for word in [0, 4, u32::MAX] {
            let record = EventRecord { kind: word, ..EventRecord::new(EventKind::Event, 0, 0, 0, "") };
            assert_eq!(record.kind(), None, "word {word}");
        }
    }
}

//! The PLC register image of the Fatek FUN147 step table (docs/fun147.md): word registers
//! R and D and the relays X, Y, M, S, as atomics in the namespace's shared memory, so the
//! core's boxes, the scripts and the Modbus server read and write the same words. Which
//! address is which word is the `fun147` and `calls` crates' business; this is storage.

use std::sync::atomic::{AtomicU8, AtomicU16, Ordering};

/// R0-R8071 (R3840-R4999 do not exist; they are kept as storage nobody names).
pub const R_WORDS: usize = 8072;
/// D0-D4095 (D4000-D4059 do not exist).
pub const D_WORDS: usize = 4096;
/// Relays X0-X255, Y0-Y255, M0-M2001, S0-S999, in that order.
pub const RELAYS: usize = 256 + 256 + 2002 + 1000;

/// A word area of the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WordArea {
    /// R.
    R,
    /// D.
    D,
}

#[repr(C)]
/// The image: zero at creation (the controller then sets its power-up relays).
pub struct PlcImage {
    r: [AtomicU16; R_WORDS],
    d: [AtomicU16; D_WORDS],
    /// One byte per relay, 0 or 1.
    relays: [AtomicU8; RELAYS],
}

impl PlcImage {
    fn area(&self, area: WordArea) -> &[AtomicU16] {
        match area {
            WordArea::R => &self.r,
            WordArea::D => &self.d,
        }
    }

    /// Word `n` of an area; `None` past its storage.
    pub fn word(&self, area: WordArea, n: usize) -> Option<u16> {
        self.area(area).get(n).map(|w| w.load(Ordering::Relaxed))
    }

    /// Writes word `n` of an area; false past its storage.
    pub fn set_word(&self, area: WordArea, n: usize, value: u16) -> bool {
        self.area(area).get(n).map(|w| w.store(value, Ordering::Relaxed)).is_some()
    }

    /// Relay `i` (X0 = 0, Y0 = 256, M0 = 512, S0 = 2514); `None` past the last.
    pub fn relay(&self, i: usize) -> Option<bool> {
        self.relays.get(i).map(|b| b.load(Ordering::Relaxed) != 0)
    }

    /// Writes relay `i`; false past the last.
    pub fn set_relay(&self, i: usize, on: bool) -> bool {
        self.relays.get(i).map(|b| b.store(u8::from(on), Ordering::Relaxed)).is_some()
    }
}

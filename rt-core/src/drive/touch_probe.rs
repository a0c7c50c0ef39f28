//! Touch probe 1 on the encoder index (CoE manual 3.9, tables 3-16, 3-17, 4-18). Only
//! TP1 exists; both edges at once (0x60B8 bits 4 and 5) is reserved and latches nothing.

use crate::drive::travel::{Edge, Edges};

/// 0x60B8 bits.
const ENABLE: u16 = 1 << 0;
const CONTINUOUS: u16 = 1 << 1;
const POSITIVE_EDGE: u16 = 1 << 4;
const NEGATIVE_EDGE: u16 = 1 << 5;
/// 0x60B9 bits.
const STATUS_ENABLED: u16 = 1 << 0;
const STATUS_POSITIVE_STORED: u16 = 1 << 1;
const STATUS_NEGATIVE_STORED: u16 = 1 << 2;

#[derive(Clone, Copy, Debug, Default)]
pub struct TouchProbe {
    function: u16,
    status: u16,
    positive: i64,
    negative: i64,
}

impl TouchProbe {
    /// One cycle: applies 0x60B8 and latches the index edges the motor crossed.
    /// `shift` turns raw positions into drive coordinates.
    pub fn update(&mut self, function: u16, edges: &Edges, shift: f64) {
        if function & ENABLE == 0 {
            self.status = 0;
        } else if self.function & ENABLE == 0 || (function & !self.function) & (POSITIVE_EDGE | NEGATIVE_EDGE) != 0 {
            // Switched on, or an edge newly selected: armed again.
            self.status = STATUS_ENABLED;
        }
        self.function = function;
        if function & ENABLE == 0 {
            return;
        }
        let (want_positive, want_negative) = match function & (POSITIVE_EDGE | NEGATIVE_EDGE) {
            POSITIVE_EDGE => (true, false),
            NEGATIVE_EDGE => (false, true),
            _ => return,
        };
        let continuous = function & CONTINUOUS != 0;
        for edge in edges.iter() {
            let Edge::IndexSignal { rising, at } = edge else { continue };
            let position = (at + shift).round() as i64;
            if rising && want_positive && (continuous || self.status & STATUS_POSITIVE_STORED == 0) {
                self.positive = position;
                self.status |= STATUS_POSITIVE_STORED;
            }
            if !rising && want_negative && (continuous || self.status & STATUS_NEGATIVE_STORED == 0) {
                self.negative = position;
                self.status |= STATUS_NEGATIVE_STORED;
            }
        }
    }

    /// 0x60B9, 0x60BA, 0x60BB.
    pub fn status(&self) -> u16 {
        self.status
    }

    pub fn positive_edge(&self) -> i64 {
        self.positive
    }

    pub fn negative_edge(&self) -> i64 {
        self.negative
    }
}

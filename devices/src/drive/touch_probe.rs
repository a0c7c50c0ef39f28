//! The drive's touch probes. The CoE manual's drive (3.9, tables 3-16, 3-17, 4-18) has
//! touch probe 1 on the encoder index only: 0x60B8 bits 2-3 and 8-15 change nothing, and
//! both edges at once (bits 4 and 5) is reserved and latches nothing. A drive with the
//! CiA 402 touch probe (docs/decisions.md, "Touch probe") has probes 1 and 2, the second
//! in the high byte of 0x60B8/0x60B9, each on its own probe input (source bits 00) or the
//! index (01), with 0x60BC/0x60BD.

use crate::cia402::touch_probe::*;
use crate::drive::travel::{Edge, Edges};
use config::TouchProbeKind;

/// What a probe latches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Source {
    Index,
    Input(usize),
    /// 0x60D0 and the reserved source: not supported, nothing latches.
    None,
}

#[derive(Clone, Copy, Debug, Default)]
pub struct TouchProbe {
    kind: TouchProbeKind,
    /// The probes' bytes of 0x60B8 as last applied.
    function: [u16; 2],
    status: [u16; 2],
    /// [probe][positive, negative] positions, drive counts.
    latched: [[i64; 2]; 2],
}

impl TouchProbe {
    pub fn new(kind: TouchProbeKind) -> Self {
        TouchProbe { kind, ..TouchProbe::default() }
    }

    /// One cycle: applies 0x60B8 and latches the edges the motor crossed.
    /// `shift` turns raw positions into drive coordinates.
    pub fn update(&mut self, function: u16, edges: &Edges, shift: f64) {
        let probes = if self.kind == TouchProbeKind::Cia402 { 2 } else { 1 };
        for probe in 0..probes {
            self.update_one(probe, (function >> (PROBE_2_SHIFT * probe)) & 0xFF, edges, shift);
        }
    }

    fn update_one(&mut self, probe: usize, function: u16, edges: &Edges, shift: f64) {
        let before = self.function[probe];
        self.function[probe] = function;
        let status = &mut self.status[probe];
        if function & ENABLE == 0 {
            *status = 0;
            return;
        }
        let newly_selected = (function & !before) & (POSITIVE_EDGE | NEGATIVE_EDGE) != 0;
        if before & ENABLE == 0 || newly_selected {
            // Switched on, or an edge newly selected: armed again.
            *status = STATUS_ENABLED;
        }
        let both = POSITIVE_EDGE | NEGATIVE_EDGE;
        let (want_positive, want_negative) = match (self.kind, function & both) {
            // CoE 3.9: both at once is reserved on the manual's drive.
            (TouchProbeKind::Index, b) if b == both => return,
            (_, b) => (b & POSITIVE_EDGE != 0, b & NEGATIVE_EDGE != 0),
        };
        let source = match (self.kind, function & SOURCE) {
            (TouchProbeKind::Index, _) => Source::Index,
            (TouchProbeKind::Cia402, 0) => Source::Input(probe),
            (TouchProbeKind::Cia402, SOURCE_INDEX) => Source::Index,
            (TouchProbeKind::Cia402, _) => Source::None,
        };
        let continuous = function & CONTINUOUS != 0;
        for edge in edges.iter() {
            let (rising, at) = match (edge, source) {
                (Edge::IndexSignal { rising, at }, Source::Index) => (rising, at),
                (Edge::ProbeInput { input, rising, at }, Source::Input(wanted)) if input == wanted => (rising, at),
                _ => continue,
            };
            let (wanted, bit, slot) = if rising {
                (want_positive, STATUS_POSITIVE_STORED, 0)
            } else {
                (want_negative, STATUS_NEGATIVE_STORED, 1)
            };
            if wanted && (continuous || *status & bit == 0) {
                self.latched[probe][slot] = (at + shift).round() as i64;
                *status |= bit;
            }
        }
    }

    /// 0x60B9: probe 1 in the low byte, probe 2 in the high byte.
    pub fn status(&self) -> u16 {
        self.status[0] | self.status[1] << PROBE_2_SHIFT
    }

    /// 0x60BA/0x60BB (probe 0) and 0x60BC/0x60BD (probe 1): (positive, negative).
    pub fn edges(&self, probe: usize) -> (i64, i64) {
        (self.latched[probe][0], self.latched[probe][1])
    }
}

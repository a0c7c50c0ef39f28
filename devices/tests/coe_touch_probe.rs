//! Conformance: touch probe 1 on the encoder index (CoE manual 3.9, tables 3-16, 3-17,
//! 4-18), and the CiA 402 touch probe of `drive_settings.touch_probe = "cia402"`
//! (docs/decisions.md, "Touch probe"). Index marks every 10 mm at 3, 13, 23 ... mm; the
//! pulse is 0.1 mm wide, so moving positive its rising edge is at the mark and its falling
//! edge 0.1 mm later.

mod bench;

use bench::{Bench, CPU};
use config::{AxisConfig, TouchProbeKind, TravelConfig};
use devices::ecat::SdoError;

/// Runs positive at 20 mm/s (profile velocity) for `ms`.
fn run_positive(b: &mut Bench, ms: usize) {
    b.write(0x60FF, 0, 200_000);
    b.cycles(ms);
    b.write(0x60FF, 0, 0);
    b.cycles(50);
}

fn probe(function: i64) -> Bench {
    probe_on(TouchProbeKind::Index, function)
}

/// A drive with the given touch probe; the CiA 402 one has probe input 1 over [5, 6] mm and
/// probe input 2 over [8, 8.5] mm.
fn probe_on(kind: TouchProbeKind, function: i64) -> Bench {
    let mut travel = TravelConfig { index_pitch: Some(10.0), index_offset: 3.0, ..TravelConfig::default() };
    let mut axis = AxisConfig { counts_per_unit: CPU, ..bench::drive_defaults() };
    if kind == TouchProbeKind::Cia402 {
        travel.probe_input_1 = Some([5.0, 6.0]);
        travel.probe_input_2 = Some([8.0, 8.5]);
    }
    axis.drive_settings.touch_probe = kind;
    let mut b = Bench::with(AxisConfig { travel, ..axis });
    b.write(0x6060, 0, 3);
    b.write(0x6083, 0, 10_000_000);
    b.write(0x6084, 0, 10_000_000);
    b.write(0x60C5, 0, 10_000_000);
    b.write(0x60C6, 0, 10_000_000);
    b.enable();
    b.write(0x60B8, 0, function);
    b.cycle();
    b
}

/// CoE 3.9: single trigger, rising edge: latches the first mark only.
#[test]
fn single_rising_edge() {
    let mut b = probe(0x0011);
    assert_eq!(b.read(0x60B9, 0), 0x0001, "enabled, nothing stored");
    run_positive(&mut b, 1200);
    assert_eq!(b.read(0x60B9, 0), 0x0003, "positive edge stored");
    assert_eq!(b.read(0x60BA, 0), (3.0 * CPU) as i64, "at the first mark");
    assert!(b.position() > (13.0 * CPU) as i64, "a later mark was crossed");
    assert_eq!(b.read(0x60BA, 0), (3.0 * CPU) as i64, "single mode keeps the first");
}

/// CoE 3.9: continuous trigger overwrites on every rising edge.
#[test]
fn continuous_rising_edge() {
    let mut b = probe(0x0013);
    run_positive(&mut b, 1200);
    assert_eq!(b.read(0x60BA, 0), (23.0 * CPU) as i64, "the last mark crossed (3, 13, 23)");
}

/// CoE 3.9: falling edge latches into 0x60BB with status bit 2.
#[test]
fn single_falling_edge() {
    let mut b = probe(0x0021);
    run_positive(&mut b, 500);
    assert_eq!(b.read(0x60B9, 0), 0x0005);
    assert_eq!(b.read(0x60BB, 0), (3.1 * CPU).round() as i64, "the end of the 0.1 mm pulse");
}

/// CoE 3.9: both edges at once is reserved and latches nothing.
#[test]
fn both_edges_latch_nothing() {
    let mut b = probe(0x0031);
    run_positive(&mut b, 1200);
    assert_eq!(b.read(0x60B9, 0) & 0b110, 0);
}

/// CoE 3.9: 0x60B8 = 0 switches the probe off.
#[test]
fn off() {
    let mut b = probe(0x0011);
    run_positive(&mut b, 500);
    b.write(0x60B8, 0, 0);
    b.cycle();
    assert_eq!(b.read(0x60B9, 0), 0);
}

/// CoE 3.9 note: on the manual's drive source bits 2-3 change nothing (TP1 still uses the
/// index) and probe 2's bits latch nothing; 0x60BC does not exist.
#[test]
fn the_manual_drive_ignores_source_and_probe_2_bits() {
    let mut b = probe(0x1111);
    run_positive(&mut b, 500);
    assert_eq!(b.read(0x60B9, 0), 0x0003, "TP1 latched, nothing in the high byte");
    assert_eq!(b.read(0x60BA, 0), (3.0 * CPU) as i64, "source 00 is still the index");
    assert!(matches!(b.try_write(0x60BC, 0, 0), Err(SdoError::Abort(_))), "0x60BC does not exist");
}

/// CiA 402: source 00 is the probe's own input; its rising edge latches into 0x60BA.
#[test]
fn cia402_probe_1_on_its_input() {
    let mut b = probe_on(TouchProbeKind::Cia402, 0x0011);
    run_positive(&mut b, 500);
    assert_eq!(b.read(0x60B9, 0), 0x0003);
    assert_eq!(b.read(0x60BA, 0), (5.0 * CPU) as i64, "probe input 1 rises at 5 mm, not the index at 3");
}

/// CiA 402: probe 2 in the high byte of 0x60B8/0x60B9, into 0x60BC/0x60BD, beside probe 1.
#[test]
fn cia402_both_probes_at_once() {
    // Probe 1: index (01), continuous, rising. Probe 2: its input (00), single, falling.
    let mut b = probe_on(TouchProbeKind::Cia402, 0x2117);
    run_positive(&mut b, 1200);
    assert_eq!(b.read(0x60B9, 0), 0x0503, "both enabled, TP1 positive and TP2 negative stored");
    assert_eq!(b.read(0x60BA, 0), (23.0 * CPU) as i64, "probe 1: the last mark");
    assert_eq!(b.read(0x60BD, 0), (8.5 * CPU) as i64, "probe 2: input 2 falls at 8.5 mm");
    assert_eq!(b.read(0x60BC, 0), 0, "no positive edge asked of probe 2");
}

/// CiA 402: source 10 (0x60D0) and 11 are not supported: enabled, nothing latches.
#[test]
fn cia402_unsupported_source_latches_nothing() {
    let mut b = probe_on(TouchProbeKind::Cia402, 0x0019);
    run_positive(&mut b, 1200);
    assert_eq!(b.read(0x60B9, 0), 0x0001);
}

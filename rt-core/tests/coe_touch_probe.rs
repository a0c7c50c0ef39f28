//! Conformance: touch probe 1 on the encoder index (CoE manual 3.9, tables 3-16, 3-17,
//! 4-18). Index marks every 10 mm at 3, 13, 23 ... mm; the pulse is 0.1 mm wide, so moving
//! positive its rising edge is at the mark and its falling edge 0.1 mm later.

mod bench;

use bench::{Bench, CPU};
use rt_core::config::TravelConfig;

/// Runs positive at 20 mm/s (profile velocity) for `ms`.
fn run_positive(b: &mut Bench, ms: usize) {
    b.write(0x60FF, 0, 200_000);
    b.cycles(ms);
    b.write(0x60FF, 0, 0);
    b.cycles(50);
}

fn probe(function: i64) -> Bench {
    let travel = TravelConfig { index_pitch: Some(10.0), index_offset: 3.0, ..TravelConfig::default() };
    let mut b = Bench::with_travel(travel);
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

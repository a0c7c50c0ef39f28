//! Conformance: modes of operation (CoE manual 3.3 to 3.8, tables 3-9 to 3-15, 4-17).

mod bench;

use bench::{Bench, CPU};
use config::{AxisConfig, TravelConfig};

/// Statusword bits 10, 12, 13.
const REACHED: u16 = 1 << 10;
const ACK: u16 = 1 << 12;
const FOLLOWING_ERROR: u16 = 1 << 13;

fn profile_position() -> Bench {
    let mut b = Bench::new();
    b.write(0x6060, 0, 1);
    b.write(0x6081, 0, 100_000);
    b.write(0x6083, 0, 1_000_000);
    b.write(0x6084, 0, 1_000_000);
    b.write(0x60C5, 0, 1_000_000);
    b.write(0x60C6, 0, 1_000_000);
    b.enable();
    b
}

/// Sends a set-point: target, then controlword `cw` with bit 4 rising from `cw` without it.
fn set_point(b: &mut Bench, target: i64, cw: u16) {
    b.set_target(target);
    b.cw(cw & !0x10);
    b.cw(cw | 0x10);
}

fn settle(b: &mut Bench) {
    assert!(b.until(5000, |b| b.net.sdo_read_local(0, 0x6041, 0).unwrap().0 as u16 & REACHED != 0), "target reached");
    b.cycles(100);
}

/// CoE table 4-17: 0x6060 accepts {0,1,3,4,6,8,9,10}; other values are ignored.
#[test]
fn mode_switching() {
    let mut b = Bench::new();
    assert_eq!((b.read(0x6060, 0), b.read(0x6061, 0)), (8, 8), "CoE table 4-17: defaults");
    for ignored in [2, 5, 7] {
        b.write(0x6060, 0, ignored);
        b.cycle();
        assert_eq!(b.read(0x6061, 0), 8, "CoE table 4-17: {ignored} leaves 0x6061 unchanged");
    }
    assert!(b.try_write(0x6060, 0, 11).is_err(), "CoE table 4-17: 11 is out of range");
    for mode in [0, 1, 3, 4, 6, 8, 9, 10] {
        b.write(0x6060, 0, mode);
        b.cycle();
        assert_eq!(b.read(0x6061, 0), mode, "CoE table 4-17: mode {mode}");
    }
}

/// CoE 3.3: a set-point is acknowledged, bit 10 is 0 while moving and 1 at the target.
#[test]
fn pp_set_point_and_target_reached() {
    let mut b = profile_position();
    set_point(&mut b, 10_000, 0x000F);
    assert_ne!(b.sw() & ACK, 0, "bit 12: acknowledged");
    b.cycles(5);
    assert_eq!(b.sw() & REACHED, 0, "bit 10 = 0 while moving");
    b.cw(0x000F);
    settle(&mut b);
    assert_ne!(b.sw() & REACHED, 0);
    assert_eq!(b.sw() & ACK, 0, "bit 12 clears once bit 4 is low and nothing is buffered");
    assert!((b.position() - 10_000).abs() <= 20, "at 10000: {}", b.position());
}

/// CoE 3.3: no edge, no set-point; bit 6 makes it relative to the last target.
#[test]
fn pp_edges_and_relative_targets() {
    let mut b = profile_position();
    set_point(&mut b, 10_000, 0x000F);
    b.set_target(50_000);
    b.cycles(200);
    settle(&mut b);
    assert!((b.position() - 10_000).abs() <= 20, "CoE 3.3: holding bit 4 takes no new set-point");
    b.cw(0x000F);
    set_point(&mut b, 5_000, 0x004F);
    b.cw(0x004F);
    settle(&mut b);
    assert!((b.position() - 15_000).abs() <= 20, "CoE 3.3: relative: 10000 + 5000, at {}", b.position());
}

/// CoE 3.3.1: the two-deep set-point buffer (fig. 3-12).
#[test]
fn pp_set_point_buffer() {
    // CoE 3.3.1: a second set-point is buffered; bit 12 stays 1 until the first completes.
    let mut b = profile_position();
    set_point(&mut b, 20_000, 0x000F);
    b.cw(0x000F);
    b.cycles(10);
    set_point(&mut b, 40_000, 0x000F);
    b.cw(0x000F);
    assert_ne!(b.sw() & ACK, 0, "buffer full: bit 12 stays 1");
    assert!(b.until(3000, |b| b.net.sdo_read_local(0, 0x6041, 0).unwrap().0 as u16 & ACK == 0), "bit 12 clears");
    assert!(b.position() > 19_000, "when the first set-point completes");
    settle(&mut b);
    assert!((b.position() - 40_000).abs() <= 20, "the buffered one ran");

    // CoE 3.3.1: a third set-point while the buffer is full is discarded.
    let mut b = profile_position();
    set_point(&mut b, 20_000, 0x000F);
    b.cw(0x000F);
    set_point(&mut b, 30_000, 0x000F);
    b.cw(0x000F);
    set_point(&mut b, 90_000, 0x000F);
    b.cw(0x000F);
    settle(&mut b);
    assert!((b.position() - 30_000).abs() <= 20, "CoE 3.3.1: ends at the second target, {}", b.position());

    // CoE 3.3.1: bit 5 drops both and runs the new one at once.
    let mut b = profile_position();
    set_point(&mut b, 20_000, 0x000F);
    b.cw(0x000F);
    set_point(&mut b, 30_000, 0x000F);
    b.cw(0x000F);
    set_point(&mut b, -5_000, 0x002F);
    b.cw(0x002F);
    settle(&mut b);
    assert!((b.position() + 5_000).abs() <= 20, "CoE 3.3.1: immediately to -5000, at {}", b.position());
}

/// CoE 3.3: halt decelerates; bit 10 is 0 while decelerating, 1 at rest; the target is not reached.
#[test]
fn pp_halt() {
    let mut b = profile_position();
    set_point(&mut b, 500_000, 0x000F);
    b.cw(0x000F);
    b.cycles(300);
    b.cw(0x010F);
    assert_eq!(b.sw() & REACHED, 0, "decelerating");
    b.cycles(300);
    assert_ne!(b.sw() & REACHED, 0, "velocity 0 with halt");
    assert!(b.position() < 100_000, "stopped short of the target");
    b.cw(0x000F);
    settle(&mut b);
    assert!((b.position() - 500_000).abs() <= 20, "halt released: carries on to the target");
}

/// CoE table 4-6: software limits stop pp at the limit; the reverse direction is accepted.
#[test]
fn pp_software_limits() {
    let mut b = profile_position();
    b.write(0x2041, 0, 1);
    b.write(0x607D, 1, -1_000);
    b.write(0x607D, 2, 1_000);
    set_point(&mut b, 5_000, 0x000F);
    b.cw(0x000F);
    settle(&mut b);
    assert!((b.position() - 1_000).abs() <= 20, "stops at 1000: {}", b.position());
    set_point(&mut b, 0, 0x000F);
    b.cw(0x000F);
    settle(&mut b);
    assert!(b.position().abs() <= 20, "the reverse target is accepted");
}

/// CoE table 4-6: a hardware limit latches 0x60FD bit 1 and blocks positive motion; negative
/// motion is accepted and clears the bit.
#[test]
fn pp_hardware_limit() {
    let travel = TravelConfig { positive_limit: Some(1.0), ..TravelConfig::default() };
    let mut b = Bench::with(AxisConfig { counts_per_unit: CPU, travel, ..bench::drive_defaults() });
    b.write(0x6060, 0, 1);
    for (index, value) in
        [(0x6081, 100_000), (0x6083, 1_000_000), (0x6084, 1_000_000), (0x60C5, 1_000_000), (0x60C6, 1_000_000)]
    {
        b.write(index, 0, value);
    }
    b.enable();
    set_point(&mut b, 50_000, 0x000F);
    b.cw(0x000F);
    b.cycles(1000);
    assert_ne!(b.read(0x60FD, 0) & 2, 0, "bit 1 latched");
    assert!(b.position() < 15_000, "stopped near the switch at 10000: {}", b.position());
    set_point(&mut b, 60_000, 0x000F);
    b.cw(0x000F);
    b.cycles(300);
    assert!(b.position() < 15_000, "positive motion blocked");
    set_point(&mut b, 0, 0x000F);
    b.cw(0x000F);
    settle(&mut b);
    assert!(b.position().abs() <= 20, "negative motion accepted");
    assert_eq!(b.read(0x60FD, 0) & 2, 0, "bit 1 cleared after moving back");
}

/// CoE 3.3.2: following error: > 0x6065 for > 0x6066 ms sets bit 13 and faults with 0x8611.
#[test]
fn following_error() {
    let mut b = profile_position();
    b.write(0x6060, 0, 8);
    b.write(0x6065, 0, 100);
    b.write(0x6066, 0, 10);
    b.enable();
    // A step of 5000 counts: the error lasts far longer than 10 ms.
    b.set_target(b.position() + 5_000);
    b.cycle();
    assert!(b.until(20, |b| b.net.sdo_read_local(0, 0x6041, 0).unwrap().0 as u16 & 0x4F == 0x08), "Fault");
    assert_eq!(b.read(0x603F, 0), 0x8611);
    assert_ne!(b.read(0x2100, 0) & (1 << 6), 0, "0x2100 bit 6");

    // A short excursion (under 10 ms) does not trip.
    let mut b = profile_position();
    b.write(0x6060, 0, 8);
    b.write(0x6065, 0, 100);
    b.write(0x6066, 0, 1_000);
    b.enable();
    b.set_target(b.position() + 500);
    b.cycles(50);
    assert_eq!(b.sw() & 0x6F, 0x27, "still Operation enabled");
    assert_eq!(b.sw() & FOLLOWING_ERROR, 0);
}

/// CoE 3.4: pv reaches 0x60FF after velocity/0x6083; halt ramps to 0.
#[test]
fn profile_velocity() {
    let mut b = Bench::new();
    b.write(0x6060, 0, 3);
    b.write(0x60FF, 0, 1_000);
    b.write(0x6083, 0, 500);
    b.write(0x6084, 0, 500);
    b.enable();
    b.cycles(1900);
    assert_eq!(b.sw() & REACHED, 0, "CoE 3.4: not yet at 1.9 s");
    b.cycles(150);
    assert_ne!(b.sw() & REACHED, 0, "CoE 3.4: 1000 counts/s after 2 s");
    b.cw(0x010F);
    b.cycles(2100);
    assert_ne!(b.sw() & REACHED, 0, "CoE 3.4: halted, velocity 0");
    assert_ne!(b.sw() & ACK, 0, "bit 12: speed 0 (table 3-12)");
}

/// CoE 3.4: in pv, software limits do not stop the motion; a hardware limit does.
#[test]
fn profile_velocity_limits() {
    let travel = TravelConfig { positive_limit: Some(2.0), ..TravelConfig::default() };
    let mut b = Bench::with(AxisConfig { counts_per_unit: CPU, travel, ..bench::drive_defaults() });
    b.write(0x2041, 0, 1);
    b.write(0x607D, 2, 5_000);
    b.write(0x6060, 0, 3);
    b.write(0x60FF, 0, 50_000);
    b.write(0x6083, 0, 10_000_000);
    b.write(0x60C5, 0, 10_000_000);
    b.enable();
    b.cycles(300);
    assert!(b.position() > 5_000, "passed the software limit");
    b.cycles(500);
    assert!(b.position() < 25_000, "stopped at the hardware limit (20000): {}", b.position());
    assert_ne!(b.read(0x60FD, 0) & 2, 0);
}

/// CoE 3.5: tq ramps the current by 0x6087; torque = Kt x I_rated x 0x6071 / 1000.
#[test]
fn profile_torque() {
    let mut b = Bench::new();
    b.write(0x6060, 0, 4);
    b.write(0x6087, 0, 1_000);
    b.write(0x6071, 0, 500);
    b.enable();
    b.cycles(400);
    assert_eq!(b.sw() & REACHED, 0, "CoE 3.5: still ramping at 0.4 s");
    b.cycles(150);
    assert_ne!(b.sw() & REACHED, 0, "CoE 3.5: 50 % after 0.5 s at 100 %/s");
    let torque = b.read(0x6077, 0);
    assert!((490..=510).contains(&torque), "CoE 3.5: 50 % of rated, {torque}");
    let current = f32::from_bits(b.read(0x2022, 0) as u32);
    assert!((current - 1.0).abs() < 0.05, "half the 2 A rated current: {current}");
}

/// CoE 3.6, 3.7: the cyclic modes ignore halt; csp applies software limits, csv does not.
#[test]
fn cyclic_modes() {
    let mut b = Bench::new();
    b.enable();
    let start = b.position();
    b.cw(0x010F);
    for k in 1..=100 {
        b.set_target(start + 100 * k);
        b.cycle();
    }
    b.cycles(50);
    assert!((b.position() - (start + 10_000)).abs() < 20, "CoE 3.6: csp follows with halt set");
    assert_ne!(b.sw() & ACK, 0, "table 3-14: target used");

    b.write(0x2041, 0, 1);
    b.write(0x607D, 2, start + 12_000);
    b.set_target(start + 50_000);
    b.cycles(200);
    assert!((b.position() - (start + 12_000)).abs() < 20, "CoE 3.6: csp stops at the software limit");

    b.write(0x6060, 0, 9);
    b.write(0x60FF, 0, 20_000);
    b.cycles(500);
    assert!(b.position() > start + 15_000, "CoE 3.7: csv passes the software limit, halt ignored");
}

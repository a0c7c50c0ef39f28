//! Conformance: homing mode (CoE manual 3.2, tables 3-6 to 3-8).
//!
//! The geometry, in mm of the machine (10 000 counts/mm): limit switches at -100 and
//! +100, the home switch active over [L, R] = [20, 30], index marks every 10 mm at
//! ..., -7, 3, 13, 23, 33, ... Hard-stop methods use a travel with hard stops at -110 and
//! +110 and no limit switches.

mod bench;

use bench::{Bench, CPU};
use config::{AxisConfig, DriveSettings, TravelConfig};
use devices::drive::DriveModel;

const OFFSET: i64 = 1_000;
/// Table 3-7, `sw & 0x3400`.
const IN_PROGRESS: u16 = 0x0000;
const INTERRUPTED: u16 = 0x0400;
const ATTAINED: u16 = 0x1400;
const ERROR_DECELERATING: u16 = 0x2000;
const ERROR_STOPPED: u16 = 0x2400;

fn switches() -> TravelConfig {
    TravelConfig {
        negative_limit: Some(-100.0),
        positive_limit: Some(100.0),
        home_switch: Some([20.0, 30.0]),
        index_pitch: Some(10.0),
        index_offset: 3.0,
        ..TravelConfig::default()
    }
}

fn hard_stops() -> TravelConfig {
    TravelConfig {
        index_pitch: Some(10.0),
        index_offset: 3.0,
        negative_hard_stop: Some(-110.0),
        positive_hard_stop: Some(110.0),
        ..TravelConfig::default()
    }
}

/// A drive in homing mode, enabled, at `start` mm, with the method set.
fn homing(model: DriveModel, travel: TravelConfig, start: f64, method: i64) -> Bench {
    let travel = TravelConfig { start_position: start, ..travel };
    let settings = DriveSettings { multi_turn_absolute: false, ..DriveSettings::default() };
    let mut b = Bench::with(AxisConfig {
        drive: model,
        counts_per_unit: CPU,
        travel,
        drive_settings: settings,
        ..bench::drive_defaults()
    });
    b.write(0x6060, 0, 6);
    b.write(0x6098, 0, method);
    b.write(0x6099, 1, 200_000);
    b.write(0x6099, 2, 50_000);
    b.write(0x609A, 0, 20_000_000);
    b.write(0x607C, 0, OFFSET);
    b.enable();
    b
}

fn status(b: &mut Bench) -> u16 {
    b.sw() & 0x3400
}

/// Runs the homing to its end (attained or error), at most 60 s.
fn run_to_end(b: &mut Bench) -> u16 {
    b.cw(0x001F);
    b.until(60_000, |b| {
        matches!(b.net.sdo_read_local(0, 0x6041, 0).unwrap().0 as u16 & 0x3400, ATTAINED | ERROR_STOPPED)
    });
    status(b)
}

/// (method, model, travel, start mm, home in mm of the machine, what)
type MethodRow = (i64, DriveModel, fn() -> TravelConfig, f64, f64, &'static str);

/// CoE 3.2, table 3-8 and the hard-stop methods: where each method ends.
#[test]
fn every_method_ends_on_its_index() {
    let rows: [MethodRow; 27] = [
        (1, DriveModel::D1, switches, 0.0, -97.0, "CoE 3.2: first index right of the negative limit"),
        (2, DriveModel::D1, switches, 0.0, 93.0, "CoE 3.2: first index left of the positive limit"),
        (7, DriveModel::D1, switches, 0.0, 13.0, "CoE table 3-8: 7 off the switch: left of L"),
        (7, DriveModel::D1, switches, 25.0, 13.0, "CoE table 3-8: 7 on the switch"),
        (7, DriveModel::D1, switches, 50.0, 13.0, "7 beyond R: turns at the positive limit"),
        (8, DriveModel::D1, switches, 0.0, 23.0, "CoE table 3-8: 8 off: right of L"),
        (8, DriveModel::D1, switches, 25.0, 23.0, "CoE table 3-8: 8 on"),
        (9, DriveModel::D1, switches, 0.0, 23.0, "CoE table 3-8: 9 off: left of R"),
        (9, DriveModel::D1, switches, 25.0, 23.0, "CoE table 3-8: 9 on"),
        (10, DriveModel::D1, switches, 0.0, 33.0, "CoE table 3-8: 10 off: right of R"),
        (10, DriveModel::D1, switches, 25.0, 33.0, "CoE table 3-8: 10 on"),
        (11, DriveModel::D1, switches, 50.0, 33.0, "CoE table 3-8: 11 off: right of R"),
        (11, DriveModel::D1, switches, 25.0, 33.0, "CoE table 3-8: 11 on"),
        (11, DriveModel::D1, switches, 0.0, 33.0, "11 left of L: turns at the negative limit"),
        (12, DriveModel::D1, switches, 50.0, 23.0, "CoE table 3-8: 12 off: left of R"),
        (12, DriveModel::D1, switches, 25.0, 23.0, "CoE table 3-8: 12 on (negative search, docs/drive.md)"),
        (13, DriveModel::D1, switches, 50.0, 23.0, "CoE table 3-8: 13 off: right of L"),
        (13, DriveModel::D1, switches, 25.0, 23.0, "CoE table 3-8: 13 on"),
        (14, DriveModel::D1, switches, 50.0, 13.0, "CoE table 3-8: 14 off: left of L"),
        (14, DriveModel::D1, switches, 25.0, 13.0, "CoE table 3-8: 14 on"),
        (33, DriveModel::D1, switches, 0.0, -7.0, "CoE 3.2: first index in -"),
        (34, DriveModel::D1, switches, 0.0, 3.0, "CoE 3.2: first index in +"),
        (37, DriveModel::D1, switches, 4.2, 4.2, "CoE 3.2: here, no motion"),
        (-1, DriveModel::D1, hard_stops, 0.0, -107.0, "-1: index right of the negative hard stop"),
        (-2, DriveModel::D1, hard_stops, 0.0, 103.0, "-2: index left of the positive hard stop"),
        (-4, DriveModel::D1N, hard_stops, 0.0, 110.0 - 0.1, "-4 (D1-N): hard stop minus the end stop offset"),
        (-5, DriveModel::D1N, hard_stops, 0.0, -110.0 + 0.1, "-5 (D1-N)"),
    ];
    for (method, model, travel, start, home_mm, what) in rows {
        let mut b = homing(model, travel(), start, method);
        assert_eq!(run_to_end(&mut b), ATTAINED, "{what}");
        b.cycles(100);
        let home = home_mm * CPU;
        assert!((b.raw() - home).abs() < 20.0, "{what}: at {} mm, not {home_mm}", b.raw() / CPU);
        assert!((b.position() - OFFSET).abs() < 20, "{what}: position actual {} = home offset", b.position());
    }
}

/// CoE 3.2: status before, during and after; the index search runs at 0x6099:02.
#[test]
fn status_bits_and_search_speed() {
    let mut b = homing(DriveModel::D1, switches(), 0.0, 34);
    assert_eq!(status(&mut b), INTERRUPTED, "CoE 3.2: not started");
    b.cw(0x001F);
    b.cycles(100);
    assert_eq!(status(&mut b), IN_PROGRESS, "CoE 3.2: in progress");
    let v = b.read(0x606C, 0);
    assert!((45_000..55_000).contains(&v), "CoE 3.2: slow + at 50000 counts/s, got {v}");
    assert!(b.until(10_000, |b| b.net.sdo_read_local(0, 0x6041, 0).unwrap().0 as u16 & 0x3400 == ATTAINED));
    // CoE 3.2: with 0x607C = 1000, 0x6064 reads 1000 at the home.
    b.cycles(100);
    assert!((b.position() - OFFSET).abs() < 20);
}

/// CoE 3.2: interruptions without error end in 0x0400 and leave 0x603F at 0.
#[test]
fn interruptions() {
    // (what, action after 500 ms of homing)
    type Action = fn(&mut Bench);
    let rows: [(&str, Action, u16); 4] = [
        ("CoE 3.2: bit 4 cleared", |b| b.cw(0x000F), 0x0F),
        ("CoE 3.2: halt", |b| b.cw(0x011F), 0x0F),
        ("CoE 3.2: disable operation", |b| b.cw(0x0007), 0x0F),
        ("CoE 3.2: mode 0", |b| b.write(0x6060, 0, 0), 0x0F),
    ];
    for (what, action, _) in rows {
        let mut b = homing(DriveModel::D1, switches(), 0.0, 1);
        b.cw(0x001F);
        b.cycles(500);
        action(&mut b);
        b.cycles(300);
        assert_eq!(status(&mut b), INTERRUPTED, "{what}");
        assert_eq!(b.read(0x603F, 0), 0, "{what}: no error code");
        assert!(b.read(0x606C, 0).abs() < 1_000, "{what}: stopped");
    }
}

/// CoE 3.2, table 3-8: errors set bit 13 and 0x603F = 0x8613.
#[test]
fn errors() {
    // CoE 3.2: mode 1 during homing: decelerating 0x2000, then 0x2400.
    let mut b = homing(DriveModel::D1, switches(), 0.0, 1);
    b.cw(0x001F);
    b.cycles(500);
    b.write(0x6060, 0, 1);
    b.cycle();
    assert_eq!(status(&mut b), ERROR_DECELERATING, "CoE 3.2: decelerating");
    assert!(b.until(100, |b| b.net.sdo_read_local(0, 0x6041, 0).unwrap().0 as u16 & 0x3400 == ERROR_STOPPED));
    assert_eq!(b.read(0x603F, 0), 0x8613, "CoE 3.2: 0x8613");
    assert_ne!(b.read(0x2101, 0) & (1 << 31), 0, "0x2101 bit 31: CiA-402 home failed");

    // CoE table 3-8: an unsupported method when bit 4 rises.
    for method in [3, 35] {
        let mut b = homing(DriveModel::D1, switches(), 0.0, method);
        assert_eq!(run_to_end(&mut b), ERROR_STOPPED, "method {method}");
        assert_eq!(b.read(0x603F, 0), 0x8613, "method {method}");
    }

    // CoE 3.2: a limit switch while searching the index: method 34 toward a limit 1 mm away
    // with no index before it.
    let travel = TravelConfig {
        positive_limit: Some(1.0),
        index_pitch: Some(10.0),
        index_offset: 3.0,
        ..TravelConfig::default()
    };
    let mut b = homing(DriveModel::D1, travel, 0.0, 34);
    assert_eq!(run_to_end(&mut b), ERROR_STOPPED, "CoE 3.2");
    assert_eq!(b.read(0x603F, 0), 0x8613);
}

/// CoE table 3-8: methods -3, -4, -5 per drive model.
#[test]
fn model_specific_methods() {
    let rows: [(i64, DriveModel, bool); 8] = [
        (-3, DriveModel::D1, false),
        (-3, DriveModel::Abily, false),
        (-4, DriveModel::D1, false),
        (-4, DriveModel::D2, false),
        (-4, DriveModel::Abily, false),
        (-5, DriveModel::D1, false),
        (-5, DriveModel::D2, false),
        (-4, DriveModel::D1N, true),
    ];
    for (method, model, supported) in rows {
        let mut b = homing(model, hard_stops(), 0.0, method);
        let end = run_to_end(&mut b);
        assert_eq!(end == ATTAINED, supported, "method {method} on {model:?}");
    }
}

/// CoE 3.2: homing restarts on a new bit-4 edge, or on a mode switch away and back.
#[test]
fn restarts() {
    let mut b = homing(DriveModel::D1, switches(), 0.0, 34);
    assert_eq!(run_to_end(&mut b), ATTAINED);
    b.cw(0x000F);
    b.cw(0x001F);
    b.cycle();
    assert_eq!(status(&mut b), IN_PROGRESS, "CoE 3.2: restarted by the edge");

    let mut b = homing(DriveModel::D1, switches(), 0.0, 34);
    assert_eq!(run_to_end(&mut b), ATTAINED);
    b.write(0x6060, 0, 1);
    b.cycles(2);
    b.write(0x6060, 0, 6);
    b.cycles(2);
    assert_eq!(status(&mut b), IN_PROGRESS, "CoE 3.2: 6 -> 1 -> 6 with bit 4 held");
}

/// CoE 3.2: leaving homing mode clears the limit flags of 0x60FD.
#[test]
fn leaving_homing_clears_the_limit_flags() {
    let mut b = homing(DriveModel::D1, switches(), 0.0, 1);
    b.cw(0x001F);
    assert!(b.until(20_000, |b| b.read(0x60FD, 0) & 1 != 0), "the negative limit is seen");
    b.cw(0x000F);
    b.cycles(200);
    b.write(0x6060, 0, 8);
    b.cycles(2);
    assert_eq!(b.read(0x60FD, 0) & 3, 0);
}

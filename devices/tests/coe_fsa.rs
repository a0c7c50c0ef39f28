//! Conformance: the CiA 402 state machine through the process data (CoE manual 3.1,
//! tables 3-3 and 3-5). Statusword values under the masks of table 3-5.

mod bench;

use bench::Bench;

const SOD: u16 = 0x40;
const RTSO: u16 = 0x21;
const SO: u16 = 0x23;
const OE: u16 = 0x27;
const QSA: u16 = 0x07;

/// The state bits under the mask table 3-5 gives each state.
fn state_bits(sw: u16) -> u16 {
    if matches!(sw & 0x4F, 0x00 | 0x40 | 0x0F | 0x08) { sw & 0x4F } else { sw & 0x6F }
}

/// Brings a fresh drive to a state with controlwords, one cycle each.
fn drive_in(path: &[u16]) -> Bench {
    let mut b = Bench::new();
    for &cw in path {
        b.cw(cw);
    }
    b.cycle();
    b
}

/// CoE 3.1: from-state (reached by a path), controlword, expected state.
#[test]
fn transitions() {
    let to_rtso: &[u16] = &[0x0006];
    let to_so: &[u16] = &[0x0006, 0x0007];
    let to_oe: &[u16] = &[0x0006, 0x0007, 0x000F];
    let to_qsa: &[u16] = &[0x0006, 0x0007, 0x000F, 0x000B];
    let rows: [(&[u16], u16, u16, &str); 19] = [
        (&[], 0x0000, SOD, "CoE 3.1: power-up ends in Switch on disabled"),
        (&[], 0x0006, RTSO, "CoE 3.1: transition 2"),
        (to_rtso, 0x0007, SO, "CoE 3.1: transition 3"),
        (to_so, 0x000F, OE, "CoE 3.1: transition 4"),
        (to_rtso, 0x000F, OE, "CoE 3.1: transitions 3+4"),
        (to_oe, 0x0007, SO, "CoE 3.1: transition 5"),
        (to_oe, 0x0006, RTSO, "CoE 3.1: transition 8"),
        (to_so, 0x0006, RTSO, "CoE 3.1: transition 6"),
        (to_oe, 0x0000, SOD, "CoE 3.1: transition 9"),
        (to_oe, 0x000D, SOD, "CoE 3.1: any value with bit 1 = 0"),
        (to_so, 0x0000, SOD, "CoE 3.1: transition 10"),
        (to_rtso, 0x0000, SOD, "CoE 3.1: transition 7"),
        (to_oe, 0x000B, QSA, "CoE 3.1: transition 11"),
        (to_qsa, 0x0000, SOD, "CoE 3.1: transition 12"),
        (to_so, 0x0002, SOD, "CoE 3.1: quick stop from Switched on (10)"),
        (to_rtso, 0x0002, SOD, "CoE 3.1: quick stop from Ready to switch on (7)"),
        (&[], 0x0007, SOD, "CoE 3.1: Switch on needs Shutdown first"),
        (&[], 0x000F, SOD, "CoE 3.1: Enable operation needs Shutdown first"),
        (to_oe, 0x000F, OE, "holding Enable operation stays"),
    ];
    for (path, cw, expected, what) in rows {
        let mut b = drive_in(path);
        b.cw(cw);
        b.cycle();
        assert_eq!(state_bits(b.sw()), expected, "{what}: sw = {:#06x}", b.sw());
    }
}

/// CoE 3.1: quick stop decelerates with 0x6085 and holds; Disable voltage ends it (transition 12).
#[test]
fn quick_stop_decelerates_with_0x6085() {
    let mut b = drive_in(&[]);
    b.write(0x6060, 0, 3);
    b.write(0x60FF, 0, 100_000);
    b.write(0x6083, 0, 1_000_000);
    b.write(0x6085, 0, 500_000);
    b.write(0x60C5, 0, 2_000_000);
    b.enable();
    b.cycles(300);
    assert!(b.read(0x606C, 0) > 90_000, "running at 100000 counts/s");
    b.cw(0x000B);
    assert_eq!(state_bits(b.sw()), QSA);
    b.cycles(100);
    let v = b.read(0x606C, 0);
    assert!((35_000..65_000).contains(&v), "after 0.1 s at 500000 counts/s²: ~50000 counts/s, got {v}");
    b.cycles(200);
    assert!(b.read(0x606C, 0).abs() < 500, "stopped (settling within 0.05 mm/s)");
    assert_eq!(state_bits(b.sw()), QSA, "still Quick stop active, energised");
    b.cw(0x0000);
    b.cycle();
    assert_eq!(state_bits(b.sw()), SOD, "CoE 3.1: transition 12");
}

/// CoE 3.1: a fault goes through Fault reaction active to Fault, de-energised.
#[test]
fn a_fault_goes_to_fault_and_de_energises() {
    let mut b = drive_in(&[]);
    b.enable();
    b.net.inject_fault(0, 0x2310).unwrap();
    b.cycle();
    let sw = b.sw();
    assert!(matches!(sw & 0x4F, 0x0F | 0x08), "Fault reaction active or already Fault: {sw:#06x}");
    b.cycles(5);
    assert_eq!(b.sw() & 0x4F, 0x08, "Fault");
    assert!(!b.drive().state().is_energised(), "motor de-energised");
}

/// CoE table 3-2: fault reset on the rising edge of bit 7 only.
#[test]
fn fault_reset_on_the_rising_edge() {
    let mut b = drive_in(&[]);
    b.enable();
    b.net.inject_fault(0, 0x3110).unwrap();
    b.cycles(5);
    b.cw(0x0080);
    b.cycles(3);
    assert_eq!(b.sw() & 0x4F, 0x40, "CoE table 3-2: 0x0000 -> 0x0080 resets (transition 15)");
    assert_eq!(b.read(0x603F, 0), 0, "the error code is cleared");

    b.enable();
    b.cw(0x0080);
    b.net.inject_fault(0, 0x3110).unwrap();
    b.cycles(10);
    assert_eq!(b.sw() & 0x4F, 0x08, "CoE table 3-2: bit 7 already high is no edge");
    b.cw(0x0000);
    b.cw(0x0080);
    b.cycle();
    assert_eq!(b.sw() & 0x4F, 0x40, "CoE table 3-2: 0 then 1 resets");
}

/// CoE table 3-4: statusword bit 5 (quick stop) is 1 in Operation enabled, 0 in Quick stop active.
#[test]
fn quick_stop_bit() {
    let mut b = drive_in(&[]);
    b.enable();
    assert_ne!(b.sw() & 0x20, 0);
    b.cw(0x000B);
    b.cycle();
    assert_eq!(b.sw() & 0x20, 0);
}

//! Issue 11, defect 5: the range of every number a command brings (the registry's
//! `Quantity`), checked in one place before the kernel sees it, and the ends of the
//! drive's 32-bit counts, which no motion passes. Requests go straight to `dispatch`, as
//! the RT thread sends them (`rig/`); the machine is the default one (10 000 counts per mm,
//! max_vel 2000 mm/s, max_acc 50 000 mm/s²).

mod rig;

use api::Command;
use api::call::Value;
use rt_core::config::FaultReaction;
use schema::AxisSnapshot;

/// The largest coordinate of the default axes: i32::MAX counts at 10 000 counts per mm.
const SPAN: f64 = i32::MAX as f64 / 10_000.0;
/// 2^31 counts: one count past the end.
const PAST: f64 = 2_147_483_648.0 / 10_000.0;

/// The dispatch rig, with the calls of task 0 and the checks of this file.
struct Rig(rig::Rig);

impl std::ops::Deref for Rig {
    type Target = rig::Rig;
    fn deref(&self) -> &rig::Rig {
        &self.0
    }
}

impl std::ops::DerefMut for Rig {
    fn deref_mut(&mut self) -> &mut rig::Rig {
        &mut self.0
    }
}

impl Rig {
    fn new() -> Self {
        Rig(rig::Rig::new(FaultReaction::Decelerate))
    }

    fn call(&mut self, command: Command, ints: &[i64], doubles: &[f64]) -> i64 {
        self.0.call(0, command, ints, doubles)
    }

    /// MovePVT(axis, time, pos, vel, n), as the bindings send it.
    fn pvt(&mut self, axis: i64, time: &[f64], pos: &[f64], vel: &[f64]) -> i64 {
        let list = |array: &[f64]| Value::List(array.iter().map(|&d| Value::Double(d)).collect());
        let values = [Value::Int(axis), list(time), list(pos), list(vel), Value::Int(time.len() as i64)];
        self.0.call_values(0, Command::MovePVT, &values).0
    }

    fn axis(&self, a: usize) -> AxisSnapshot {
        self.machine.kernel.axis_snapshot(a)
    }

    /// Every number the axis shows is finite, and the drive's command fits its counts.
    fn assert_sane(&self, a: usize, what: &str) {
        let s = self.axis(a);
        let numbers = [s.ref_pos, s.ref_vel, s.pos_out, s.pos_offset, s.pos_fb, s.pos_err, s.vel, s.acc, s.dec];
        assert!(numbers.iter().all(|n| n.is_finite()), "{what}: {s:?}");
        // Not from the snapshot: a rollover axis shows its positions within a turn.
        let drive = self.machine.kernel.axes()[a].drive_command() * 10_000.0;
        assert!(drive.abs() <= i32::MAX as f64, "{what}: drive command {drive} counts");
    }
}

/// An axis error of axis `a`: `0x83AAEEEE`.
fn axis_err(a: i64, id: i64) -> i64 {
    0x8300_0000 | a << 16 | id
}

/// One row per setter and value: the code it returns. Every refused value leaves the
/// setting as it was and the axis finite; the rows marked accepted are the edges of the
/// ranges (docs/decisions.md, "Axes").
#[test]
fn every_setter_refuses_what_is_out_of_its_range() {
    use Command::*;
    const POS: i64 = 0x0136;
    const VEL: i64 = 0x0140;
    const ACC: i64 = 0x014A;
    const DEC: i64 = 0x0154;
    const PARAM: i64 = 0x012C;
    let rows: &[(Command, &[i64], f64, i64)] = &[
        // Positions: a coordinate fits i32::MAX counts.
        (SetPos, &[0], 1e308, POS),
        (SetPos, &[0], PAST, POS),
        (SetPos, &[0], -PAST, POS),
        (SetPos, &[0], SPAN, 0),
        (SetSWRL, &[0], 1e308, POS),
        (SetSWLL, &[0], -1e308, POS),
        (SetSWLL, &[0], -SPAN, 0),
        (SetHomeOffset, &[0], f64::MAX, POS),
        (SetHomeOffset, &[0], -1e30, POS),
        (MoveAbs, &[0], PAST, POS),
        (MoveAbs, &[0], -1e308, POS),
        (MoveRel, &[0], 1e30, POS),
        (MoveRel, &[0], -PAST, POS),
        // Lengths: one count up to the counts' span.
        (SetPosWindow, &[0], 1e308, PARAM),
        (SetPosWindow, &[0], PAST, PARAM),
        (SetPosWindow, &[0], 5e-324, PARAM),
        (SetPosWindow, &[0], 0.0001, 0),
        (SetRollover, &[0], 1e308, 0x01F4),
        (SetRollover, &[0], -0.0, 0),
        (SetRollover, &[0], 360.0, 0),
        // Speeds and accelerations: one count per s (s²) up to the machine file's limits.
        (SetHomeSwitchVel, &[0], 1e308, VEL),
        (SetHomeSwitchVel, &[0], 2000.0, 0),
        (SetHomeZeroVel, &[0], 2000.5, VEL),
        (SetHomeZeroVel, &[0], 5e-324, VEL),
        (SetHomeAcc, &[0], 1e308, ACC),
        (SetHomeAcc, &[0], 50_000.0, 0),
        (SetVel, &[0], -0.0, VEL),
        (SetVel, &[0], f64::MAX, VEL),
        (SetVel, &[0], 0.0001, 0),
        (MoveVel, &[0], -1e308, VEL),
        (MoveVel, &[0], PAST, VEL),
        (SetAcc, &[0], 1e30, ACC),
        (SetDec, &[0], 2.2250738585072014e-308, DEC),
        (SetKillDec, &[0], 1e308, 0x0172),
        (SetKillDec, &[0], 50_000.0, 0),
        // Times: > 0, at most a minute; the smooth time 0..500 ms.
        (SetAccTime, &[0], 1e308, ACC),
        (SetAccTime, &[0], 60_000.0, 0),
        (SetDecTime, &[0], -1e30, DEC),
        (SetPosWindowTime, &[0], 1e308, PARAM),
        (SetPosWindowTime, &[0], -0.0, PARAM),
        (SetSMTime, &[0], 500.000_001, 0x0168),
        (SetSMTime, &[0], -0.0, 0),
        (SetVelScale, &[0], 1e308, 0x017C),
        (SetVelScale, &[0], -5e-324, 0x017C),
        // Torque: its per mille of rated torque fits 0x6071 (INT16).
        (MoveTrq, &[0], 1e308, PARAM),
        (MoveTrq, &[0], -PAST, PARAM),
    ];
    for &(command, ints, value, rc) in rows {
        let mut rig = Rig::new();
        let before = rig.axis(0);
        let got = rig.call(command, ints, &[value]);
        let expected = if rc == 0 { 0 } else { axis_err(0, rc) };
        let what = format!("{}({value:e})", command.spec().name);
        assert_eq!(got, expected, "{what}: 0x{got:08X}");
        rig.cycles(3);
        rig.assert_sane(0, &what);
        if rc != 0 {
            let after = rig.axis(0);
            assert_eq!(after.last_err as i64, expected, "{what}: recorded as the last error");
            let settings =
                |s: &AxisSnapshot| (s.vel, s.acc, s.dec, s.kill_dec, s.sm_time, s.swrl, s.swll, s.pos_offset);
            assert_eq!(settings(&after), settings(&before), "{what}: nothing changed");
        }
    }
}

/// The same path serves arguments that are not an axis' first: GearIn's ratio belongs to
/// the slave (0x83II01D6), and every number of a PVT table is checked.
#[test]
fn gear_ratios_and_pvt_tables_have_ranges() {
    let mut rig = Rig::new();
    rig.enable(0);
    rig.enable(1);
    assert_eq!(rig.call(Command::EnableGear, &[0, 1], &[]), 0);
    for ratio in [1e308, -1e30, 1000.5] {
        assert_eq!(rig.call(Command::GearIn, &[0, 1], &[ratio]), axis_err(1, 0x01D6), "ratio {ratio:e}");
    }
    assert_eq!(rig.call(Command::GearIn, &[0, 1], &[-1000.0]), 0, "the largest ratio");
    assert_eq!(rig.call(Command::DisableGear, &[1], &[]), 0);

    // (times, positions, velocities, code)
    type Table = (&'static [f64], &'static [f64], &'static [f64], i64);
    let rows: [Table; 5] = [
        (&[0.0, 1e308], &[0.0, 0.0], &[0.0, 0.0], 0x08B6),
        (&[0.0, 60_000.5], &[0.0, 0.0], &[0.0, 0.0], 0x08B6),
        (&[0.0, 100.0], &[0.0, 1e30], &[0.0, 0.0], 0x0136),
        (&[0.0, 100.0], &[0.0, 0.0], &[0.0, -1e308], 0x08A2),
        (&[0.0, 100.0], &[0.0, 0.1], &[0.0, 0.0], 0),
    ];
    for (time, pos, vel, rc) in rows {
        let expected = if rc == 0 { 0 } else { axis_err(0, rc) };
        assert_eq!(rig.pvt(0, time, pos, vel), expected, "PVT {time:?} {pos:?} {vel:?}");
    }
    rig.cycles(300);
    rig.assert_sane(0, "after the PVT");
    assert!((rig.axis(0).pos_fb - 0.1).abs() < 0.01, "the good table ran: {:?}", rig.axis(0).pos_fb);
}

/// The report of issue 11: `SetPos(0, 1e308)` is refused, and Reset, Enable and a move
/// work from a finite axis as before.
#[test]
fn set_pos_1e308_leaves_a_sane_axis() {
    let mut rig = Rig::new();
    rig.enable(0);
    assert_eq!(rig.call(Command::SetPos, &[0], &[1e308]), axis_err(0, 0x0136));
    assert_eq!(rig.call(Command::SetPos, &[0], &[-1e308]), axis_err(0, 0x0136));
    rig.cycles(5);
    rig.assert_sane(0, "after SetPos(0, ±1e308)");
    assert_eq!(rig.call(Command::Reset, &[0], &[]), 0);
    assert_eq!(rig.call(Command::Disable, &[0], &[]), 0);
    rig.cycles(20);
    rig.enable(0);
    assert_eq!(rig.call(Command::MoveAbs, &[0], &[20.0]), 0);
    rig.cycles(600);
    rig.assert_sane(0, "after the move");
    assert!((rig.axis(0).pos_fb - 20.0).abs() < 0.01, "moved to 20: {}", rig.axis(0).pos_fb);
}

/// Runs until axis `a` is at rest (at most `n` cycles), checking it every cycle.
fn run_to_rest(rig: &mut Rig, a: usize, n: usize) {
    for _ in 0..n {
        rig.cycles(1);
        rig.assert_sane(a, "on the way");
        if !rig.moving(a) {
            return;
        }
    }
    panic!("axis {a} still moves after {n} cycles: {:?}", rig.axis(a));
}

/// A velocity move runs until stopped; at the end of the counts it is stopped as at a
/// software limit (0x83II07DA), though IgnoreSWL is on.
#[test]
fn a_velocity_move_stops_before_the_counts_end() {
    let mut rig = Rig::new();
    rig.enable(0);
    assert_eq!(rig.call(Command::SetPos, &[0], &[SPAN - 50.0]), 0);
    assert_eq!(rig.call(Command::IgnoreSWL, &[0, 1], &[]), 0);
    assert_eq!(rig.call(Command::MoveVel, &[0], &[2000.0]), 0);
    run_to_rest(&mut rig, 0, 2000);
    let s = rig.axis(0);
    assert!(s.ref_pos <= SPAN && s.ref_pos > SPAN - 50.0, "stopped before the end: {}", s.ref_pos);
    assert_eq!(s.last_err as i64, axis_err(0, 0x07DA));
    assert!(s.fault_status & 0x01 != 0, "ErrorStop: {s:?}");
}

/// Second variant, the fix not written for it: a rollover axis (no software limits) and
/// a gear slave whose master would take it past the end.
#[test]
fn rollover_axes_and_gear_slaves_stop_before_the_counts_end() {
    let mut rig = Rig::new();
    assert_eq!(rig.call(Command::SetRollover, &[0], &[360.0]), 0);
    rig.enable(0);
    assert_eq!(rig.call(Command::SetPos, &[0], &[-(SPAN - 30.0)]), 0);
    assert_eq!(rig.call(Command::MoveVel, &[0], &[-2000.0]), 0);
    run_to_rest(&mut rig, 0, 2000);
    assert_eq!(rig.axis(0).last_err as i64, axis_err(0, 0x07E4), "the left end");

    rig.enable(1);
    rig.enable(2);
    assert_eq!(rig.call(Command::SetPos, &[2], &[SPAN - 100.0]), 0);
    assert_eq!(rig.call(Command::EnableGear, &[1, 2], &[]), 0);
    assert_eq!(rig.call(Command::GearIn, &[1, 2], &[4.0]), 0);
    assert_eq!(rig.call(Command::MoveVel, &[1], &[200.0]), 0);
    for _ in 0..2000 {
        rig.cycles(1);
        rig.assert_sane(2, "the slave");
        if rig.axis(2).last_err != 0 && !rig.moving(2) {
            break;
        }
    }
    let s = rig.axis(2);
    assert_eq!(s.last_err as i64, axis_err(2, 0x07DA), "{s:?}");
    assert!(s.in_gear == 0 && s.ref_pos <= SPAN, "disengaged before the end: {s:?}");
}

/// SDO and PDO values are written whole or not at all: a value that does not fit the
/// object's width is refused (-1) instead of cut to another value.
#[test]
fn drive_objects_get_whole_values() {
    let mut rig = Rig::new();
    // 0x607A target position, INT32: 2^32 + 5 cut to 4 bytes would be 5.
    assert_eq!(rig.call(Command::WriteSDO, &[0, 0x607A, 0, 4, (1 << 32) + 5], &[]), -1);
    assert_eq!(rig.call(Command::WriteSDO, &[0, 0x607A, 0, 4, -5], &[]), 0);
    assert_eq!(rig.call(Command::ForceWritePDO, &[0, 0x6040, 0, 0x1_0006], &[]), -1, "UINT16 controlword");
    assert_eq!(rig.call(Command::WritePDO, &[0, 0x6040, 0, -0x8001], &[]), -1);
    assert_eq!(rig.call(Command::WritePDO, &[0, 0x6040, 0, 0xFFFF], &[]), 0);
}

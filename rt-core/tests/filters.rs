//! HMPL ch. 15 as a conformance table: the ranges and codes of the nine functions, VSF
//! and InShape never together on an axis, nothing changed while the axis or group moves,
//! the `motion_status` bits, and which shaper acts on group motion (HMPL 15.1).

mod rig;

use api::Command;
use api::call::Value;
use rig::Rig;
use rt_core::config::FaultReaction;
use schema::{group_motion_status, motion_status};

fn rig() -> Rig {
    Rig::new(FaultReaction::None)
}

/// `SetAxisInShape` / `SetGrpInShape` (id, frequency, damping, type).
fn set_shaper(rig: &mut Rig, command: Command, id: i64, freq: f64, damping: f64, kind: i64) -> i64 {
    let args = [Value::Int(id), Value::Double(freq), Value::Double(damping), Value::Int(kind)];
    rig.call_values(0, command, &args).0
}

fn axis_status(rig: &Rig, axis: usize) -> u32 {
    rig.machine.kernel.axis_snapshot(axis).motion_status
}

fn group_status(rig: &Rig, group: usize) -> u32 {
    rig.machine.kernel.groups()[group].snapshot(rig.machine.kernel.axes()).motion_status
}

/// HMPL 15.4, 15.7, 15.10: each range's edges, with the code of table 18.1.2.1 or 18.1.3.1
/// (docs/decisions.md, "Filters").
#[test]
fn ranges_and_their_codes() {
    use Command::*;
    let mut rig = rig();
    let vsf = |rig: &mut Rig, f: f64, d: f64| rig.call(0, SetAxisVsf, &[1], &[f, d]);
    let rows: &[(&str, i64, i64)] = &[
        ("15.4 frequency 0.1", vsf(&mut rig, 0.1, 1.0), 0),
        ("15.4 frequency 200", vsf(&mut rig, 200.0, 1.0), 0),
        ("15.4 frequency 0.09", vsf(&mut rig, 0.09, 1.0), 0x8301_047E),
        ("15.4 frequency 200.1", vsf(&mut rig, 200.1, 1.0), 0x8301_047E),
        ("15.4 damping 0.7", vsf(&mut rig, 10.0, 0.7), 0),
        ("15.4 damping 1.5", vsf(&mut rig, 10.0, 1.5), 0),
        ("15.4 damping 0.69", vsf(&mut rig, 10.0, 0.69), 0x8301_0474),
        ("15.4 damping 1.51", vsf(&mut rig, 10.0, 1.51), 0x8301_0474),
        ("15.4 NaN", vsf(&mut rig, f64::NAN, 1.0), 0x8301_047E),
        ("15.7 defaults", set_shaper(&mut rig, SetAxisInShape, 1, 5.5, 0.03, 1), 0),
        ("15.7 frequency 1.5", set_shaper(&mut rig, SetAxisInShape, 1, 1.5, 0.3, 0), 0),
        ("15.7 frequency 300", set_shaper(&mut rig, SetAxisInShape, 1, 300.0, 0.0, 1), 0),
        ("15.7 frequency 1.49", set_shaper(&mut rig, SetAxisInShape, 1, 1.49, 0.03, 1), 0x8301_047E),
        ("15.7 frequency 300.1", set_shaper(&mut rig, SetAxisInShape, 1, 300.1, 0.03, 1), 0x8301_047E),
        ("15.7 damping -0.01", set_shaper(&mut rig, SetAxisInShape, 1, 5.5, -0.01, 1), 0x8301_0474),
        ("15.7 damping 0.31", set_shaper(&mut rig, SetAxisInShape, 1, 5.5, 0.31, 1), 0x8301_0474),
        ("15.7 type 2", set_shaper(&mut rig, SetAxisInShape, 1, 5.5, 0.03, 2), 0x8301_012C),
        ("15.10 frequency 3.0", set_shaper(&mut rig, SetGrpInShape, 2, 3.0, 0.3, 0), 0),
        ("15.10 frequency 2.99", set_shaper(&mut rig, SetGrpInShape, 2, 2.99, 0.1, 1), 0x8202_0118),
        ("15.10 frequency 300.1", set_shaper(&mut rig, SetGrpInShape, 2, 300.1, 0.1, 1), 0x8202_0118),
        ("15.10 damping 0.31", set_shaper(&mut rig, SetGrpInShape, 2, 10.0, 0.31, 1), 0x8202_010E),
        ("15.10 type -1", set_shaper(&mut rig, SetGrpInShape, 2, 10.0, 0.1, -1), 0x8202_005A),
    ];
    for &(row, got, want) in rows {
        assert_eq!(got, want, "HMPL {row}: 0x{got:08X}");
    }
}

/// HMPL 15.1: VSF and InShape never together; either is free once the other is off. The
/// motion_status bits 6 and 7 (table 5.1.1.5) follow.
#[test]
fn vsf_and_input_shaping_exclude_each_other() {
    use Command::*;
    let mut rig = rig();
    let status = |rig: &Rig| axis_status(rig, 0) & (motion_status::INPUT_SHAPE | motion_status::VSF);
    assert_eq!(status(&rig), 0, "both off at start");
    assert_eq!(rig.call(0, EnableAxisInShape, &[0], &[]), 0);
    assert_eq!(status(&rig), motion_status::INPUT_SHAPE);
    assert_eq!(rig.call(0, EnableAxisVsf, &[0], &[]), 0x8300_00C8, "eERR_AXIS_CMD_INVALID_INPUTSHAPING_ENABLED");
    assert_eq!(status(&rig), motion_status::INPUT_SHAPE, "refused: nothing changed");
    assert_eq!(rig.call(0, DisableAxisInShape, &[0], &[]), 0);
    assert_eq!(rig.call(0, EnableAxisVsf, &[0], &[]), 0);
    assert_eq!(status(&rig), motion_status::VSF);
    assert_eq!(rig.call(0, EnableAxisInShape, &[0], &[]), 0x8300_0064, "docs/decisions.md, Filters");
    assert_eq!(rig.call(0, DisableAxisVsf, &[0], &[]), 0);
    assert_eq!(status(&rig), 0);
}

/// HMPL 15.2-15.10: "not while the motor moves", for every switch and setting of an axis
/// and a group; all taken again at rest.
#[test]
fn nothing_changes_while_moving() {
    use Command::*;
    let mut rig = rig();
    rig.enable(0);
    rig.enable(1);
    assert_eq!(rig.call(0, EnableAxisInShape, &[0], &[]), 0);
    assert_eq!(rig.call(0, MoveRel, &[0], &[20.0]), 0);
    rig.cycles(5);
    let refusals = [
        rig.call(0, DisableAxisInShape, &[0], &[]),
        set_shaper(&mut rig, SetAxisInShape, 0, 8.0, 0.05, 1),
        rig.call(0, SetAxisVsf, &[0], &[8.0, 1.0]),
        rig.call(0, EnableAxisVsf, &[0], &[]),
        rig.call(0, DisableAxisVsf, &[0], &[]),
    ];
    assert_eq!(refusals, [0x8300_0082; 5], "eERR_AXIS_CMD_INVALID_MOVING");
    while rig.moving(0) {
        rig.cycle();
    }
    assert_eq!(set_shaper(&mut rig, SetAxisInShape, 0, 8.0, 0.05, 1), 0, "at rest");
    assert_eq!(rig.call(0, DisableAxisInShape, &[0], &[]), 0);

    for (cmd, a) in [(AddAxisToGrp, 0), (AddAxisToGrp, 1)] {
        assert_eq!(rig.call(0, cmd, &[0, a], &[]), 0);
    }
    assert_eq!(rig.call(0, EnableGroup, &[0], &[]), 0);
    let args = [Value::Int(0), Value::Double(10.0), Value::Double(10.0)];
    assert_eq!(rig.call_values(0, LineRel2D, &args).0, 0);
    rig.cycles(5);
    let refusals = [
        rig.call(0, EnableGrpInShape, &[0], &[]),
        rig.call(0, DisableGrpInShape, &[0], &[]),
        set_shaper(&mut rig, SetGrpInShape, 0, 10.0, 0.15, 1),
    ];
    assert_eq!(refusals, [0x8200_0046; 3], "eERR_CRD_CMD_INVALID_MOVING");
    while rig.machine.kernel.groups()[0].is_moving() {
        rig.cycle();
    }
    assert_eq!(set_shaper(&mut rig, SetGrpInShape, 0, 10.0, 0.15, 1), 0, "at rest");
    assert_eq!(rig.call(0, EnableGrpInShape, &[0], &[]), 0);
    assert_ne!(group_status(&rig, 0) & group_motion_status::INPUT_SHAPE, 0, "table 8.1.1.5 bit 3");
    assert_eq!(rig.call(0, DisableGrpInShape, &[0], &[]), 0);
    assert_eq!(group_status(&rig, 0) & group_motion_status::INPUT_SHAPE, 0);
}

/// The references of axes 0 and 1 while group 0 runs a line from where they stand, each
/// cycle until the group is at rest, with the axis' and the group's shapers as given.
fn group_line(axis_shaper: bool, group_shaper: bool) -> Vec<[f64; 2]> {
    use Command::*;
    let mut rig = rig();
    rig.enable(0);
    rig.enable(1);
    if axis_shaper {
        assert_eq!(set_shaper(&mut rig, SetAxisInShape, 0, 5.0, 0.1, 0), 0);
        assert_eq!(rig.call(0, EnableAxisInShape, &[0], &[]), 0);
    }
    for a in [0, 1] {
        assert_eq!(rig.call(0, AddAxisToGrp, &[0, a], &[]), 0);
    }
    assert_eq!(rig.call(0, EnableGroup, &[0], &[]), 0);
    if group_shaper {
        assert_eq!(set_shaper(&mut rig, SetGrpInShape, 0, 5.0, 0.1, 0), 0);
        assert_eq!(rig.call(0, EnableGrpInShape, &[0], &[]), 0);
    }
    let args = [Value::Int(0), Value::Double(40.0), Value::Double(20.0)];
    assert_eq!(rig.call_values(0, LineRel2D, &args).0, 0);
    let mut refs = Vec::new();
    loop {
        rig.cycle();
        let axes = rig.machine.kernel.axes();
        refs.push([axes[0].reference().pos, axes[1].reference().pos]);
        if !rig.machine.kernel.groups()[0].is_moving() {
            return refs;
        }
    }
}

/// HMPL 15.1: an axis' InShape has no effect on group motion; the group's own does, on
/// every coordinate alike, so the path keeps its shape and gets longer by the shaper's
/// delay (ZVD at 5 Hz, ζ 0.1: T_d = 201 ms).
#[test]
fn group_motion_takes_the_groups_shaper_not_the_axis() {
    let plain = group_line(false, false);
    assert_eq!(group_line(true, false), plain, "axis 0's shaper leaves the group's references alone");
    let shaped = group_line(false, true);
    let longer = shaped.len() as f64 - plain.len() as f64;
    assert!((longer - 201.0).abs() <= 2.0, "the group's shaper adds its delay: {longer} cycles");
    assert_ne!(shaped[..plain.len()], plain[..], "the group's shaper changes the references");
    for [x, y] in &shaped {
        assert!((y - x / 2.0).abs() < 1e-9, "on the line (40, 20): ({x}, {y})");
    }
    assert_eq!(shaped.last(), plain.last(), "the same end");
}

/// The slave's reference, cycle by cycle, after GearOut hands its motion (100 mm/s, the
/// master's) to its own generator, with `filter` on the slave from before the gear.
fn after_gear_out(filter: impl FnOnce(&mut Rig)) -> Vec<f64> {
    use Command::*;
    let mut rig = rig();
    rig.enable(0);
    rig.enable(1);
    filter(&mut rig);
    assert_eq!(rig.call(0, EnableGear, &[0, 1], &[]), 0);
    assert_eq!(rig.call(0, GearIn, &[0, 1], &[1.0]), 0);
    assert_eq!(rig.call(0, MoveVel, &[0], &[100.0]), 0);
    rig.cycles(300);
    assert_eq!(rig.call(0, GearOut, &[1], &[]), 0);
    (0..300)
        .map(|_| {
            rig.cycle();
            rig.machine.kernel.axes()[1].reference().pos
        })
        .collect()
}

/// A motion handed over from a coupling passes the slave's VSF and shaper unfiltered until
/// it has come to rest (as its smoothing, docs/decisions.md "Gear"): their history holds
/// where the axis stood before the gear, and would pull it back there.
#[test]
fn a_motion_handed_over_from_the_gear_passes_the_filters() {
    use Command::*;
    let in_shape = |rig: &mut Rig| {
        assert_eq!(set_shaper(rig, SetAxisInShape, 1, 5.0, 0.1, 0), 0);
        assert_eq!(rig.call(0, EnableAxisInShape, &[1], &[]), 0);
    };
    let vsf = |rig: &mut Rig| {
        assert_eq!(rig.call(0, SetAxisVsf, &[1], &[5.0, 1.0]), 0);
        assert_eq!(rig.call(0, EnableAxisVsf, &[1], &[]), 0);
    };
    let plain = after_gear_out(|_| {});
    for (name, refs) in [("InShape", after_gear_out(in_shape)), ("VSF", after_gear_out(vsf))] {
        for (i, pair) in refs.windows(2).enumerate() {
            let step = pair[1] - pair[0];
            assert!((0.0..=0.1 + 1e-9).contains(&step), "{name}, cycle {i}: a step of {step} mm at 100 mm/s");
        }
        assert_eq!(refs, plain, "{name}: the handed-over motion unfiltered");
    }
}

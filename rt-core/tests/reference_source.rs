//! An axis has one reference source (docs/decisions.md, "Reference source"): its profile
//! generator, a gear master (HMPL 6.2), a homing run (20.2) or torque mode (5.3.41). A
//! command that would give it a second is refused with the code of the one it has.

mod rig;

use api::{AxisError, Command, ErrorCode};
use rig::Rig;
use rt_core::config::FaultReaction;

fn refused(axis: u8, error: AxisError) -> i64 {
    ErrorCode::axis(axis, error).code() as i64
}

fn rig() -> Rig {
    let mut rig = Rig::new(FaultReaction::None);
    rig.enable(0);
    rig.enable(1);
    rig
}

#[test]
fn a_gear_slave_keeps_its_master_in_csp_and_csv_but_cannot_take_torque() {
    let mut rig = rig();
    assert_eq!(rig.call(0, Command::EnableGear, &[0, 1], &[]), 0);
    assert_eq!(
        rig.call(0, Command::SetOpMode, &[1, 10], &[]),
        refused(1, AxisError::CmdInvalidInSync),
        "HMPL 5.3.41: cst on a gear slave"
    );
    assert_eq!(rig.call(0, Command::SetOpMode, &[1, 9], &[]), 0, "csv: the slave keeps its master");
    assert!(rig.machine.kernel.axes()[1].is_gear_slave());
    assert_eq!(rig.call(0, Command::SetOpMode, &[1, 8], &[]), 0);
    assert_eq!(rig.call(0, Command::GearIn, &[0, 1], &[2.0]), 0, "still linked to its master");
}

#[test]
fn an_axis_in_torque_mode_cannot_become_a_gear_slave() {
    let mut rig = rig();
    assert_eq!(rig.call(0, Command::SetOpMode, &[1, 10], &[]), 0);
    assert_eq!(
        rig.call(0, Command::EnableGear, &[0, 1], &[]),
        refused(1, AxisError::CmdInvalidControlMode),
        "HMPL 6.2 on an axis in cst"
    );
    assert!(!rig.machine.kernel.axes()[1].is_gear_slave());
    // Back in csp the same link is taken.
    assert_eq!(rig.call(0, Command::SetOpMode, &[1, 8], &[]), 0);
    assert_eq!(rig.call(0, Command::EnableGear, &[0, 1], &[]), 0);
}

#[test]
fn a_homing_axis_neither_becomes_a_gear_slave_nor_changes_its_mode() {
    let mut rig = rig();
    assert_eq!(rig.call(0, Command::MoveHome, &[1], &[]), i64::MIN, "MoveHome waits for the end");
    assert!(rig.machine.kernel.axes()[1].is_homing());
    assert_eq!(
        rig.call(0, Command::EnableGear, &[0, 1], &[]),
        refused(1, AxisError::CmdInvalidState),
        "HMPL 6.2 during a homing run"
    );
    for mode in [8, 9, 10] {
        assert_eq!(
            rig.call(0, Command::SetOpMode, &[1, mode], &[]),
            refused(1, AxisError::CmdInvalidState),
            "HMPL 5.3.41 ({mode}) during a homing run"
        );
    }
    // A master may home: its slaves follow whatever its reference does.
    assert_eq!(rig.call(0, Command::EnableGear, &[1, 0], &[]), 0);
}

#[test]
fn couplings_are_the_kernels_and_show_on_both_ends() {
    let mut rig = rig();
    assert_eq!(rig.call(0, Command::EnableGear, &[0, 1], &[]), 0);
    assert_eq!(rig.call(0, Command::EnableGantryPair, &[2, 3], &[]), 0);
    let kernel = &rig.machine.kernel;
    let (master, slave, rhs, lhs) =
        (kernel.axis_snapshot(0), kernel.axis_snapshot(1), kernel.axis_snapshot(2), kernel.axis_snapshot(3));
    assert_eq!((master.gear_master, slave.gear_master), (1, 0), "HMPL 6.2: IsGearMaster on the master only");
    assert_eq!((rhs.gantry_pair_id, lhs.gantry_pair_id, master.gantry_pair_id), (0, 0, -1), "HMPL 7.2: pair 0");
    assert_eq!(rhs.motion_status & lhs.motion_status & 0x20, 0x20, "both axes Gantry");
    assert_eq!(
        rig.call(0, Command::SetPos, &[3], &[5.0]),
        refused(3, AxisError::CmdInvalidGantryMode),
        "HMPL 5.3.19: no SetPos on a gantry axis"
    );
    assert_eq!(rig.call(0, Command::DisableGantryPair, &[3], &[]), 0);
    assert_eq!(rig.call(0, Command::SetPos, &[3], &[5.0]), 0, "an axis again");
    assert_eq!(rig.call(0, Command::DisableGear, &[1], &[]), 0);
    assert_eq!(rig.machine.kernel.axis_snapshot(0).gear_master, 0, "no slave left");
}

//! Coordinate systems (HMPL 8.1.2, 8.3.30-8.3.33, example 5 of 8.1.6).

use std::f64::consts::SQRT_2;

use api::GroupError;
use nalgebra::{Rotation3, Vector3};
use path::Pose;
use path::commands::{circle_2d, line_abs_2d};
use path::frames::*;

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

const fn wcs(n: i64) -> i64 {
    n << CS_WCS_SHIFT
}

#[test]
fn flags_parse_and_refuse() {
    assert_eq!(CoordSys::parse(CS_MCS, false), Ok(CoordSys::MCS));
    let c = CoordSys::parse(wcs(1) | CS_PCS, false).unwrap();
    assert_eq!((c.pcs, c.wcs, c.offset), (true, Some(1), false));
    let c = CoordSys::parse(CS_OFFSET | wcs(15) | CS_PCS, false).unwrap();
    assert_eq!((c.pcs, c.wcs, c.offset, c.flags()), (true, Some(15), true, CS_OFFSET | wcs(15) | CS_PCS));
    assert_eq!(CoordSys::MCS.flags(), CS_MCS);
    for bad in [0, -1, CS_GLOBAL, CS_GLOBAL | CS_PCS, 0x20, 0x1000, CS_MCS | CS_PCS, CS_ACS, CS_ACS | CS_PCS] {
        assert_eq!(CoordSys::parse(bad, false), Err(GroupError::CmdCoordSysUnknown), "{bad:#x}");
    }
    assert_eq!(CoordSys::parse(CS_ACS, true).map(|c| (c.acs, c.flags())), Ok((true, CS_ACS)));
    assert_eq!(CoordSys::parse(CS_ACS | CS_PCS, true), Err(GroupError::CmdCoordSysUnknown));
}

#[test]
fn transforms_are_stored_per_system() {
    let mut f = Frames::default();
    assert_eq!(f.get(CS_PCS), Ok([0.0; 6]));
    f.set(wcs(3), &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]).unwrap();
    f.set(CS_OFFSET, &[0.0, -100.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
    assert_eq!(f.get(wcs(3)), Ok([1.0, 2.0, 3.0, 4.0, 5.0, 6.0]));
    assert_eq!(f.get(wcs(2)), Ok([0.0; 6]));
    assert_eq!(f.get(CS_OFFSET), Ok([0.0, -100.0, 0.0, 0.0, 0.0, 0.0]));
    for bad in [CS_MCS, CS_ACS, CS_GLOBAL, CS_PCS | wcs(1), 0, 0x20] {
        assert_eq!(f.set(bad, &[0.0; 6]), Err(GroupError::CmdCoordSysUnknown), "{bad:#x}");
    }
    assert_eq!(f.set(CS_PCS, &[f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0]), Err(GroupError::CmdCoordInvalidParam));
}

#[test]
fn rotation_is_fixed_frame_roll_pitch_yaw() {
    // HMPL 8.1.2: R = Rz(C)·Ry(B)·Rx(A).
    let (a, b, c) = (10f64, 20f64, 30f64);
    let expected = Rotation3::from_axis_angle(&Vector3::z_axis(), c.to_radians())
        * Rotation3::from_axis_angle(&Vector3::y_axis(), b.to_radians())
        * Rotation3::from_axis_angle(&Vector3::x_axis(), a.to_radians());
    assert!((rpy(&[a, b, c]).matrix() - expected.matrix()).abs().max() < 1e-15);
    // Back to the angles, the nearest equivalent kept.
    let back = angles(&rpy(&[a, b, c]), &[a, b, c]);
    assert!(close(&back, &[a, b, c], 1e-12), "{back:?}");
    assert!(close(&angles(&rpy(&[0.0, 0.0, 270.0]), &[0.0, 0.0, 260.0]), &[0.0, 0.0, 270.0], 1e-12));
    // The other decomposition (A + 180, 180 − B, C + 180) where it is nearer.
    assert!(close(&angles(&rpy(&[10.0, 100.0, 20.0]), &[10.0, 100.0, 20.0]), &[10.0, 100.0, 20.0], 1e-9));
    // Gimbal lock: A from the reference, C fits.
    for abc in [[30.0, 90.0, 50.0], [30.0, -90.0, 50.0]] {
        let back = angles(&rpy(&abc), &abc);
        assert!(close(&back, &abc, 1e-6), "{back:?}");
    }
    // A normal vector turns with the frame: A = 90° tips Z onto -Y.
    let f = Frame::from_params(&[5.0, 6.0, 7.0, 90.0, 0.0, 0.0]);
    assert!(close(&f.z_axis(), &[0.0, -1.0, 0.0], 1e-15));
    assert!(close(&f.vector_from_mcs(f.z_axis()), &[0.0, 0.0, 1.0], 1e-15));
}

#[test]
fn example_5_1_pcs() {
    // HMPL 8.1.6 example 5-1: PCS {400, 200, 0, 0, 0, 45}; LineAbs2D(10, 10).
    let mut frames = Frames::default();
    frames.set(CS_PCS, &[400.0, 200.0, 0.0, 0.0, 0.0, 45.0]).unwrap();
    let pcs = frames.frame(CoordSys::parse(CS_PCS, false).unwrap());
    let start = [0.0; 6];
    let line = line_abs_2d(&start, pcs.point_2d(&start, [10.0, 10.0])).unwrap();
    assert!(close(&line.end(), &[400.0, 200.0 + 10.0 * SQRT_2, 0.0, 0.0, 0.0, 0.0], 1e-12), "{:?}", line.end());
    // GetGrpPoseCmd(CS_PCS): (10, 10), the machine's orientation seen turned by -45°.
    let seen = pcs.pose_from_mcs(&line.end());
    assert!(close(&seen, &[10.0, 10.0, 0.0, 0.0, 0.0, -45.0], 1e-12), "{seen:?}");
    // The arrow's arc (Circle2D about (60, 60)) keeps its centre and direction in PCS.
    let from = pcs.point_2d(&start, [100.0, 40.0]);
    let from = [from[0], from[1], from[2], 0.0, 0.0, 0.0];
    let arc = circle_2d(&from, pcs.point_2d(&from, [60.0, 60.0]), pcs.point_2d(&from, [40.0, 100.0]), pcs.z_axis(), 0)
        .unwrap();
    let mid = pcs.pose_from_mcs(&arc.pose_at(0.5));
    let r = 1000f64.sqrt() * SQRT_2; // |(100, 40) − (60, 60)|
    assert!(((mid[0] - 60.0).hypot(mid[1] - 60.0) - r).abs() < 1e-9);
    assert!(close(&pcs.pose_from_mcs(&arc.end())[..2], &[40.0, 100.0], 1e-9));
}

#[test]
fn example_5_2_and_5_3_chain() {
    // HMPL 8.1.6 examples 5-2/5-3: PCS {100, 50, 0, 0, 0, 45} on three workpieces, then OFFSET (0, -100).
    let mut frames = Frames::default();
    frames.set(CS_PCS, &[100.0, 50.0, 0.0, 0.0, 0.0, 45.0]).unwrap();
    let origins = [[400.0, 400.0], [600.0, 0.0], [800.0, -400.0]];
    for (n, o) in origins.iter().enumerate() {
        frames.set(wcs(n as i64 + 1), &[o[0], o[1], 0.0, 0.0, 0.0, 0.0]).unwrap();
    }
    frames.set(CS_OFFSET, &[0.0, -100.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
    for (n, o) in origins.iter().enumerate() {
        let n = n as i64 + 1;
        let plain = frames.frame(CoordSys::parse(wcs(n) | CS_PCS, false).unwrap());
        let shifted = frames.frame(CoordSys::parse(CS_OFFSET | wcs(n) | CS_PCS, false).unwrap());
        let expected = [o[0] + 100.0, o[1] + 50.0 + 10.0 * SQRT_2, 0.0];
        assert!(close(&plain.point_to_mcs([10.0, 10.0, 0.0]), &expected, 1e-12), "WCS{n}");
        let expected = [expected[0], expected[1] - 100.0, 0.0];
        assert!(close(&shifted.point_to_mcs([10.0, 10.0, 0.0]), &expected, 1e-12), "OFFSET|WCS{n}");
        assert!(close(&shifted.point_from_mcs(expected), &[10.0, 10.0, 0.0], 1e-12));
    }
    // The order of the chain, with transforms that do not commute: the PCS sits inside
    // the workpiece, the workpiece inside the offset.
    let mut frames = Frames::default();
    frames.set(CS_PCS, &[10.0, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
    frames.set(wcs(1), &[0.0, 0.0, 0.0, 0.0, 0.0, 90.0]).unwrap();
    frames.set(CS_OFFSET, &[0.0, 0.0, 5.0, 90.0, 0.0, 0.0]).unwrap();
    let f = frames.frame(CoordSys::parse(wcs(1) | CS_PCS, false).unwrap());
    assert!(close(&f.point_to_mcs([0.0; 3]), &[0.0, 10.0, 0.0], 1e-12));
    let f = frames.frame(CoordSys::parse(CS_OFFSET | wcs(1) | CS_PCS, false).unwrap());
    assert!(close(&f.point_to_mcs([0.0; 3]), &[0.0, 0.0, 15.0], 1e-12), "{:?}", f.point_to_mcs([0.0; 3]));
    // Only the flags present count.
    let f = frames.frame(CoordSys::parse(CS_PCS, false).unwrap());
    assert!(close(&f.point_to_mcs([0.0; 3]), &[10.0, 0.0, 0.0], 1e-12));
}

#[test]
fn poses_round_trip_and_relative_targets() {
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..200 {
        let mut r = |scale: f64| (next() * 2.0 - 1.0) * scale;
        let params = [r(500.0), r(500.0), r(500.0), r(180.0), r(89.0), r(180.0)];
        let frame = Frame::from_params(&params);
        let pose: Pose = [r(100.0), r(100.0), r(100.0), r(170.0), r(80.0), r(170.0)];
        let mcs = frame.pose_to_mcs(&pose);
        let back = frame.pose_from_mcs(&mcs);
        assert!(close(&back, &pose, 1e-9), "{pose:?} -> {mcs:?} -> {back:?}");
        // The orientation in MCS is the frame's rotation times the pose's.
        let composed = rpy(&[params[3], params[4], params[5]]) * rpy(&[pose[3], pose[4], pose[5]]);
        assert!((rpy(&[mcs[3], mcs[4], mcs[5]]).matrix() - composed.matrix()).abs().max() < 1e-12);
    }
    // A relative move in a turned system moves along its axes.
    let frame = Frame::from_params(&[100.0, 0.0, 0.0, 0.0, 0.0, 90.0]);
    let target = frame.relative_target(&[100.0, 0.0, 0.0, 0.0, 0.0, 90.0], &[10.0, 0.0, 0.0, 0.0, 0.0, 10.0]);
    assert!(close(&target, &[100.0, 10.0, 0.0, 0.0, 0.0, 100.0], 1e-12), "{target:?}");
    // Without rotation the angles pass unchanged (no turn lost to normalisation).
    let shift = Frame::from_params(&[1.0, 2.0, 3.0, 0.0, 0.0, 0.0]);
    assert_eq!(shift.pose_to_mcs(&[0.0, 0.0, 0.0, 0.0, 0.0, 720.0]), [1.0, 2.0, 3.0, 0.0, 0.0, 720.0]);
}

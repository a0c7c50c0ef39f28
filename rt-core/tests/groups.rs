//! Axis groups (HMPL ch. 8) through the core's dispatch, cycle by cycle on the default
//! machine: membership, enable and its preconditions, status, the manual's worked
//! examples, the queue, coordinate systems and the reactions to axis faults and to the
//! commanding task's fault. One row per fact, with the manual's reference beside it.

mod rig;

use api::call::Value;
use api::{AxisError, Command, ErrorCode, GroupError};
use ipc::call::Reply;
use rig::Rig;
use rt_core::config::FaultReaction;
use schema::{group_fault_status, group_motion_status};

const G: i64 = 0;

fn code(error: GroupError) -> i64 {
    ErrorCode::group(G as u8, error).code() as i64
}

fn int(v: i64) -> Value {
    Value::Int(v)
}

fn num(v: f64) -> Value {
    Value::Double(v)
}

fn list(v: &[f64]) -> Value {
    Value::List(v.iter().map(|&x| Value::Double(x)).collect())
}

trait Groups {
    fn group(&mut self, command: Command, args: &[Value]) -> i64;
    fn six(&mut self, command: Command, coord_sys: i64) -> [f64; 6];
    fn snapshot(&self) -> schema::GroupSnapshot;
    fn pose(&self) -> [f64; 6];
    fn till_in_pos(&mut self, max_cycles: usize) -> usize;
}

impl Groups for Rig {
    /// A group command of task 0, `G` first.
    fn group(&mut self, command: Command, args: &[Value]) -> i64 {
        let mut values = vec![int(G)];
        values.extend_from_slice(args);
        self.call_values(0, command, &values).0
    }

    /// GetGrpPoseCmd / GetGrpPoseFb / GetGrpCoordTrans: the six numbers after rc 0.
    fn six(&mut self, command: Command, coord_sys: i64) -> [f64; 6] {
        let (rc, reply): (i64, Reply) = self.call_values(0, command, &[int(G), int(coord_sys)]);
        assert_eq!(rc, 0, "{command:?}");
        assert_eq!(reply.valuec, 7);
        std::array::from_fn(|i| f64::from_bits(reply.values[i + 1]))
    }

    fn snapshot(&self) -> schema::GroupSnapshot {
        let mut s = schema::Snapshot::default();
        self.machine.kernel.fill(&mut s);
        s.groups[G as usize]
    }

    fn pose(&self) -> [f64; 6] {
        self.snapshot().carte_pose_cmd
    }

    /// Cycles until the group is in position (HMPL 8.4.3); how many it took.
    fn till_in_pos(&mut self, max_cycles: usize) -> usize {
        for n in 0..max_cycles {
            self.cycle();
            if self.snapshot().motion_status & group_motion_status::IN_POSITION != 0 {
                return n + 1;
            }
        }
        panic!("not in position within {max_cycles} cycles: {:?}", self.snapshot());
    }
}

/// Axes 0 and 1 enabled and grouped as X and Y, the group enabled (HMPL 8.1.6 example 1).
fn xy() -> Rig {
    let mut rig = Rig::new(FaultReaction::Decelerate);
    rig.enable(0);
    rig.enable(1);
    assert_eq!(rig.group(Command::AddAxisToGrp, &[int(0)]), 0);
    assert_eq!(rig.group(Command::AddAxisToGrp, &[int(1)]), 0);
    assert_eq!(rig.group(Command::EnableGroup, &[]), 0);
    rig
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

#[test]
fn membership_and_enable_follow_the_manual() {
    let mut rig = Rig::with_axes(10);
    let group_id = |rig: &Rig, a: usize| rig.machine.kernel.axis_snapshot(a).group_id;
    assert_eq!(group_id(&rig, 3), -1, "HMPL 8.3.5: -1 for an ungrouped axis");
    assert_eq!(rig.group(Command::AddAxisToGrp, &[int(3)]), 0, "HMPL 8.3.1");
    assert_eq!(group_id(&rig, 3), 0, "HMPL 8.3.5");
    assert_eq!(
        rig.group(Command::AddAxisToGrp, &[int(3)]),
        code(GroupError::CmdAxisDuplicated),
        "table 18.1.3.1 0x0028"
    );
    for a in [0, 1, 2, 4, 5, 6, 7, 8] {
        assert_eq!(rig.group(Command::AddAxisToGrp, &[int(a)]), 0, "HMPL 8.3.1: up to 9 axes");
    }
    assert_eq!(
        rig.group(Command::AddAxisToGrp, &[int(9)]),
        code(GroupError::CmdGrpSizeFull),
        "HMPL 8.3.1: a 10th axis"
    );
    assert_eq!(rig.snapshot().axis_count, 9);
    assert_eq!(rig.group(Command::RemoveAxisFromGrp, &[]), 0, "HMPL 8.3.2");
    assert_eq!(group_id(&rig, 8), -1, "HMPL 8.3.2 removes the axis added last");
    assert_eq!(group_id(&rig, 7), 0);
    assert_eq!(
        rig.group(Command::EnableGroup, &[]),
        code(GroupError::CmdInvalidState),
        "HMPL 8.2.1: every axis enabled first"
    );
    assert_eq!(rig.snapshot().motion_status & group_motion_status::ENABLED, 0);
    assert_eq!(rig.group(Command::UngrpAllAxes, &[]), 0, "HMPL 8.3.4");
    assert_eq!(rig.snapshot().axis_count, 0);
    assert_eq!(group_id(&rig, 3), -1);
    assert_eq!(rig.group(Command::EnableGroup, &[]), code(GroupError::CmdGrpSizeEmpty), "table 18.1.3.1 0x0032");
    let last = rig.machine.kernel.groups().len();
    assert_eq!(rig.call_values(0, Command::EnableGroup, &[int(last as i64)]).0, 0x138F, "group id out of range");
}

#[test]
fn a_grouped_axis_refuses_its_own_motion() {
    let mut rig = xy();
    let refused = ErrorCode::axis(0, AxisError::CmdInvalidGrouped).code() as i64;
    assert_eq!(rig.call(0, Command::MoveAbs, &[0], &[10.0]), refused, "HMPL 3.2: 0x83II00E6");
    assert_eq!(rig.call(0, Command::MoveHome, &[0], &[]), refused);
    assert_eq!(rig.call(0, Command::SetPos, &[0], &[5.0]), refused, "HMPL 5.3.19: not while grouped");
    let s = rig.machine.kernel.axis_snapshot(0);
    assert_ne!(s.motion_status & schema::motion_status::GROUP, 0, "table 5.1.1.5 bit 4");
}

#[test]
fn defaults_and_ranges_of_the_settings() {
    let mut rig = xy();
    let s = rig.snapshot();
    assert_eq!(s.lin_profile, [100.0, 5000.0, 5000.0, 50.0], "HMPL 8.3.6 defaults");
    assert_eq!(s.ang_profile, [360.0, 1800.0, 1800.0, 50.0], "HMPL 8.3.7 defaults");
    assert_eq!((s.kin, s.queue_size, s.vel_scale), (1, 512, 100.0), "HMPL 8.1.3, 8.1, 8.3.29");
    let profile = |v: [f64; 4]| v.map(num);
    let rows: &[(Command, [f64; 4], GroupError)] = &[
        (Command::SetGrpMotionProfile, [5001.0, 5000.0, 5000.0, 50.0], GroupError::CmdInvalidLinVel),
        (Command::SetGrpMotionProfile, [100.0, 0.0, 5000.0, 50.0], GroupError::CmdInvalidLinAcc),
        (Command::SetGrpMotionProfile, [100.0, 50001.0, 5000.0, 50.0], GroupError::CmdInvalidLinAcc),
        (Command::SetGrpMotionProfile, [100.0, 5000.0, 5000.0, 501.0], GroupError::CmdInvalidLinSmTime),
        (Command::SetGrpAngMotionProfile, [7201.0, 1800.0, 1800.0, 50.0], GroupError::CmdInvalidAngVel),
        (Command::SetGrpAngMotionProfile, [360.0, 72001.0, 1800.0, 50.0], GroupError::CmdInvalidAngAcc),
    ];
    for (command, values, error) in rows {
        assert_eq!(rig.group(*command, &profile(*values)), code(*error), "HMPL 8.3.6/8.3.7 {command:?} {values:?}");
    }
    assert_eq!(rig.snapshot().lin_profile, [100.0, 5000.0, 5000.0, 50.0], "a refused profile changes nothing");
    assert_eq!(rig.group(Command::SetGrpKin, &[int(1)]), 0, "HMPL 8.3.9");
    for kin in [2, 3, 4] {
        assert_eq!(
            rig.group(Command::SetGrpKin, &[int(kin)]),
            code(GroupError::CmdInvalidKinSetting),
            "table 8.1.3.1 {kin}"
        );
    }
    assert_eq!(rig.group(Command::SetGrpBufferMode, &[int(7)]), code(GroupError::CmdBlendModeUnknown), "HMPL 8.3.23");
    assert_eq!(rig.group(Command::SetGrpTransMode, &[int(5)]), code(GroupError::CmdTransModeUnknown), "HMPL 8.3.25");
    assert_eq!(
        rig.group(Command::SetGrpTransPrm, &[num(5000.0), num(20.0), num(0.0), num(0.0)]),
        code(GroupError::CmdInvalidTransVel),
        "table 8.3.26.1: trans_vel < 5000"
    );
    assert_eq!(
        rig.group(Command::SetGrpTransPrm, &[num(50.0), num(0.0), num(0.0), num(0.0)]),
        code(GroupError::CmdInvalidTransDis),
        "table 8.3.26.1: trans_dis > 0"
    );
    assert_eq!(
        rig.group(Command::SetGrpLookAheadPrm, &[int(3), num(1.0)]),
        code(GroupError::CmdLookaheadInvalidParam),
        "HMPL 8.3.34"
    );
    assert_eq!(rig.group(Command::SetGrpQueueSize, &[int(11)]), code(GroupError::CmdInvalidQueueSize), "HMPL 8.3.35");
    assert_eq!(rig.group(Command::SetGrpQueueSize, &[int(3)]), 0);
    assert_eq!(rig.snapshot().queue_size, 8);
    assert_eq!(
        rig.group(Command::SetGrpCoordSys, &[int(0x8)]),
        code(GroupError::CmdCoordSysUnknown),
        "CS_GLOBAL is not supported"
    );
    let last = schema::Snapshot::default().group_last_err.len();
    assert!(last > 0);
    let mut s = schema::Snapshot::default();
    rig.machine.kernel.fill(&mut s);
    assert_eq!(s.group_last_err[0] as i64, code(GroupError::CmdCoordSysUnknown), "HMPL 18.5: the last error");
}

#[test]
fn line_rel_2d_from_100_200_by_100_100_ends_at_200_300() {
    let mut rig = xy();
    assert_eq!(rig.group(Command::LineAbs2D, &[num(100.0), num(200.0)]), 0);
    rig.till_in_pos(5000);
    assert_eq!(rig.group(Command::LineRel2D, &[num(100.0), num(100.0)]), 0, "HMPL 8.2.11");
    let moving_at_once = rig.snapshot().motion_status & group_motion_status::MOVING != 0;
    assert!(moving_at_once, "HMPL 8.4.2: moving in the cycle the command is applied");
    rig.till_in_pos(5000);
    assert!(close(&rig.pose()[..2], &[200.0, 300.0], 1e-9), "HMPL 8.2.11: (200, 300), got {:?}", rig.pose());
    for a in 0..2 {
        let fb = rig.machine.kernel.axes()[a].pos_fb();
        assert!((fb - [200.0, 300.0][a]).abs() < 1e-3, "axis {a} feedback {fb}");
    }
}

#[test]
fn a_line_moves_both_axes_together_at_the_path_speed() {
    let mut rig = xy();
    assert_eq!(rig.group(Command::LineAbs2D, &[num(100.0), num(100.0)]), 0, "HMPL 8.1.6 example 1");
    let (mut started, mut stopped) = ([None; 2], [None; 2]);
    let mut last = [0.0; 2];
    for n in 0..5000 {
        rig.cycle();
        let pose = rig.pose();
        let speed = ((pose[0] - last[0]).powi(2) + (pose[1] - last[1]).powi(2)).sqrt() / 1e-3;
        assert!(speed <= 100.0 + 1e-6, "HMPL 8.3.6: path speed {speed} > 100 mm/s");
        // A line from (0,0) to (100,100): X = Y all along (deviation below 1e-9 mm).
        assert!((pose[0] - pose[1]).abs() < 1e-9, "off the line at cycle {n}: {pose:?}");
        for a in 0..2 {
            if pose[a] != last[a] {
                started[a].get_or_insert(n);
                stopped[a] = Some(n);
            }
        }
        last = [pose[0], pose[1]];
    }
    assert_eq!(started[0], started[1], "HMPL 8.1: the axes start together");
    assert_eq!(stopped[0], stopped[1], "HMPL 8.1: the axes stop together");
    assert_eq!(&rig.pose()[..2], &[100.0, 100.0]);
    assert_ne!(rig.snapshot().motion_status & group_motion_status::IN_POSITION, 0, "HMPL 8.4.3");
}

/// (start, command, arguments after the group, end, reference).
type ArcRow = ([f64; 2], Command, Vec<Value>, [f64; 2], &'static str);

#[test]
fn arcs_and_circles_end_where_the_manual_says() {
    let s2 = 10.0 * 2f64.sqrt();
    // (start, command, args, end, reference)
    let rows: Vec<ArcRow> = vec![
        ([0.0, 0.0], Command::Arc2D, vec![num(100.0), num(100.0), num(200.0), num(0.0)], [200.0, 0.0], "HMPL 8.2.13"),
        ([0.0, 0.0], Command::ArcAngle2D, vec![num(10.0), num(10.0), num(45.0)], [10.0, 10.0 - s2], "HMPL 8.2.16"),
        (
            [0.0, 0.0],
            Command::Circle2D,
            vec![num(100.0), num(0.0), num(200.0), num(0.0), int(1)],
            [200.0, 0.0],
            "HMPL 8.2.17",
        ),
        ([0.0, 0.0], Command::ArcCW2D, vec![num(10.0), num(0.0), num(20.0), num(0.0)], [20.0, 0.0], "HMPL 8.2.14"),
        ([0.0, 0.0], Command::ArcCCW2D, vec![num(10.0), num(0.0), num(20.0), num(0.0)], [20.0, 0.0], "HMPL 8.2.15"),
    ];
    for (start, command, args, end, reference) in rows {
        let mut rig = xy();
        assert_eq!(rig.group(Command::LineAbs2D, &[num(start[0]), num(start[1])]), 0);
        rig.till_in_pos(5000);
        let mut lowest: f64 = 0.0;
        let mut highest: f64 = 0.0;
        assert_eq!(rig.group(command, &args), 0, "{reference}");
        for _ in 0..20000 {
            rig.cycle();
            lowest = lowest.min(rig.pose()[1]);
            highest = highest.max(rig.pose()[1]);
            if rig.snapshot().motion_status & group_motion_status::IN_POSITION != 0 {
                break;
            }
        }
        assert!(close(&rig.pose()[..2], &end, 1e-9), "{reference}: ends at {:?}, not {end:?}", rig.pose());
        match command {
            // From (0, 0) through (100, 100): clockwise, above the X axis. Clockwise about a
            // center on the X axis goes up too; counter-clockwise goes down (right-hand rule).
            Command::Arc2D | Command::ArcCW2D => {
                assert!(highest > 0.0 && lowest > -1e-9, "{reference}: above the axis")
            }
            Command::Circle2D | Command::ArcCCW2D => {
                assert!(lowest < 0.0 && highest < 1e-9, "{reference}: CCW goes below")
            }
            _ => assert!(lowest < 10.0 - s2 + 1e-9, "{reference}"),
        }
    }
}

#[test]
fn inconsistent_radii_are_refused_and_nothing_moves() {
    let mut rig = xy();
    assert_eq!(
        rig.group(Command::ArcCW2D, &[num(10.0), num(0.0), num(30.0), num(0.0)]),
        code(GroupError::CmdCircInvalidRadius),
        "table 18.1.3.1 0x0280"
    );
    rig.cycles(5);
    assert_eq!(rig.snapshot().cmd_num, 0);
    assert_eq!(rig.pose(), [0.0; 6]);
}

#[test]
fn the_queue_takes_512_and_refuses_the_513th_keeping_all() {
    let mut rig = xy();
    let mut accepted = 0;
    for i in 0..512 {
        let x = if i % 2 == 0 { 10.0 } else { 0.0 };
        assert_eq!(rig.group(Command::LineAbs2D, &[num(x), num(0.0)]), 0, "command {i}");
        accepted += 1;
    }
    assert_eq!(rig.snapshot().cmd_num, 512, "HMPL 8.3.27");
    assert_eq!(
        rig.group(Command::LineAbs2D, &[num(5.0), num(5.0)]),
        code(GroupError::CmdQueueFull),
        "HMPL 8.1: 0x82II0078"
    );
    assert_eq!(rig.snapshot().cmd_num, accepted, "nothing queued is lost");
    assert_eq!(rig.group(Command::SetGrpQueueSize, &[int(3)]), code(GroupError::CmdQueueIsNotEmpty), "0x008C");
    rig.cycles(200);
    let fewer = rig.snapshot().cmd_num;
    assert!(fewer < 512, "HMPL 8.3.27 decreases as segments complete");
    assert_eq!(rig.group(Command::StopGroup, &[]), 0, "HMPL 8.2.4");
    rig.till_in_pos(5000);
    assert_eq!(rig.snapshot().cmd_num, 0, "HMPL 8.2.4 clears the queue");
}

#[test]
fn halt_and_resume_keep_the_path() {
    let mut rig = xy();
    assert_eq!(rig.group(Command::LineAbs2D, &[num(100.0), num(50.0)]), 0);
    rig.cycles(300);
    assert_eq!(rig.group(Command::HaltGroup, &[]), 0, "HMPL 8.2.5");
    rig.cycles(400);
    let halted = rig.pose();
    rig.cycles(10);
    assert_eq!(rig.pose(), halted, "halted: the velocity is 0");
    assert!(halted[0] < 100.0 && (halted[1] - halted[0] / 2.0).abs() < 1e-9, "on the line: {halted:?}");
    assert_eq!(rig.group(Command::ResumeGroup, &[]), 0, "HMPL 8.2.6");
    rig.till_in_pos(5000);
    assert!(close(&rig.pose()[..2], &[100.0, 50.0], 1e-9));
}

#[test]
fn a_disabled_group_refuses_motion_and_an_axis_fault_stops_it() {
    let mut rig = xy();
    assert_eq!(rig.group(Command::DisableGroup, &[]), 0);
    assert_eq!(rig.group(Command::LineAbs2D, &[num(1.0), num(1.0)]), code(GroupError::CmdInvalidDisabled), "0x0050");
    assert_eq!(rig.group(Command::EnableGroup, &[]), 0);
    assert_eq!(rig.group(Command::LineAbs2D, &[num(100.0), num(0.0)]), 0);
    rig.cycles(200);
    assert_eq!(rig.call(0, Command::SimDriveFault, &[1, 0x2310], &[]), 0);
    rig.cycles(20);
    let s = rig.snapshot();
    assert_ne!(s.fault_status & group_fault_status::ERROR_STOP, 0, "table 8.1.1.4 bit 0");
    assert_ne!(s.fault_status & group_fault_status::AXIS_FAULT, 0, "table 8.1.1.4 bit 1");
    assert_eq!(rig.group(Command::LineAbs2D, &[num(0.0), num(0.0)]), code(GroupError::CmdInvalidState));
    assert_ne!(rig.group(Command::ResetGroup, &[]), 0, "HMPL 8.2.3: not while the cause is there");
    assert_eq!(rig.call(0, Command::Reset, &[1], &[]), 0);
    rig.cycles(50);
    rig.enable(1);
    rig.cycles(500);
    assert_eq!(rig.group(Command::ResetGroup, &[]), 0, "HMPL 8.2.3 once every cause is gone");
    assert_eq!(rig.snapshot().fault_status, 0);
    assert_eq!(rig.group(Command::LineAbs2D, &[num(0.0), num(0.0)]), 0);
}

#[test]
fn pcs_of_example_5_1_maps_targets_and_poses() {
    let mut rig = xy();
    let pcs = list(&[400.0, 200.0, 0.0, 0.0, 0.0, 45.0]);
    assert_eq!(rig.group(Command::SetGrpCoordTrans, &[int(0x2), pcs]), 0, "HMPL 8.3.31");
    assert_eq!(rig.six(Command::GetGrpCoordTrans, 0x2), [400.0, 200.0, 0.0, 0.0, 0.0, 45.0], "HMPL 8.3.30");
    assert_eq!(rig.group(Command::SetGrpCoordSys, &[int(0x2)]), 0, "HMPL 8.3.21");
    assert_eq!(rig.snapshot().coord_sys, 0x2, "HMPL 8.3.20");
    assert_eq!(rig.group(Command::LineAbs2D, &[num(10.0), num(10.0)]), 0, "HMPL 8.1.6 example 5-1");
    rig.till_in_pos(20000);
    let mcs = [400.0, 200.0 + 10.0 * 2f64.sqrt()];
    assert!(close(&rig.pose()[..2], &mcs, 1e-9), "MCS {:?}, not {mcs:?}", rig.pose());
    let in_pcs = rig.six(Command::GetGrpPoseCmd, 0x2);
    assert!(close(&in_pcs[..2], &[10.0, 10.0], 1e-9), "HMPL 8.3.32 in PCS: {in_pcs:?}");
    let fb = rig.six(Command::GetGrpPoseFb, 0x1);
    assert!(close(&fb[..2], &mcs, 1e-3), "HMPL 8.3.33: {fb:?}");
    // A Z the group has no axis for cannot be reached.
    let z = [num(0.0), num(0.0), num(5.0)];
    assert_eq!(rig.group(Command::LineAbs3D, &z), code(GroupError::CmdInvalidPos), "table 18.1.3.1 0x00D2");
    // Nor a target past an axis' drive counts (2^31 counts of 0.1 µm: 214748 mm).
    let far = [num(0.0), num(1e6)];
    assert_eq!(rig.group(Command::LineAbs2D, &far), code(GroupError::CmdInvalidPos), "past the counts");
    assert_eq!(rig.machine.kernel.axis_snapshot(1).last_err, 0, "the group's error, not the axis'");
}

#[test]
fn the_commanding_tasks_fault_stops_its_group_only() {
    let mut rig = xy();
    assert_eq!(rig.group(Command::LineAbs2D, &[num(500.0), num(0.0)]), 0);
    rig.cycles(100);
    assert!(rig.snapshot().motion_status & group_motion_status::MOVING != 0);
    rig.machine.kernel.react(1, FaultReaction::Decelerate);
    rig.cycles(5);
    let moving_on = rig.pose()[0];
    rig.cycles(5);
    assert!(rig.pose()[0] > moving_on, "another task's fault leaves the group alone");
    rig.machine.kernel.react(0, FaultReaction::Decelerate);
    rig.till_in_pos(5000);
    assert!(rig.pose()[0] < 500.0, "the commanding task's fault stops its group short of the target");
    assert_eq!(rig.snapshot().cmd_num, 0);
}

#[test]
fn a_software_limit_stops_the_axis_and_the_group_leaves_sync() {
    let mut rig = xy();
    assert_eq!(rig.call(0, Command::SetSWRL, &[1], &[50.0]), 0);
    assert_eq!(rig.group(Command::LineAbs2D, &[num(100.0), num(100.0)]), 0);
    rig.cycles(3000);
    let s = rig.snapshot();
    assert_ne!(s.fault_status & group_fault_status::ERROR_STOP, 0, "table 8.1.1.4 bit 0");
    assert_ne!(s.fault_status & group_fault_status::SOFTWARE_LIMIT, 0, "table 8.1.1.4 bit 2");
    let mut snapshot = schema::Snapshot::default();
    rig.machine.kernel.fill(&mut snapshot);
    assert_eq!(snapshot.group_last_err[0] as i64, code(GroupError::AxisSwl), "table 18.1.3.1 0x03FC");
    let y = rig.machine.kernel.axes()[1].pos_fb();
    assert!(y <= 50.0, "the axis stopped at its limit: {y}");
    assert!(rig.machine.kernel.axes()[1].is_error_stop());
    assert!(!rig.moving(0) && !rig.moving(1), "both axes came to rest on their own");
}

/// Axes 0, 1 and 2 enabled and grouped as X, Y and Z, the group enabled.
fn xyz() -> Rig {
    let mut rig = Rig::new(FaultReaction::Decelerate);
    for a in 0..3 {
        rig.enable(a);
        assert_eq!(rig.group(Command::AddAxisToGrp, &[int(a)]), 0);
    }
    assert_eq!(rig.group(Command::EnableGroup, &[]), 0);
    rig
}

/// The distance from `p` to the segment from `a` to `b` (X, Y).
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (d, w) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
    let dd = d[0] * d[0] + d[1] * d[1];
    let u = if dd > 0.0 { ((w[0] * d[0] + w[1] * d[1]) / dd).clamp(0.0, 1.0) } else { 0.0 };
    ((w[0] - u * d[0]).powi(2) + (w[1] - u * d[1]).powi(2)).sqrt()
}

/// Runs the queued path to the end: the commanded poses (X, Y) of every cycle.
fn run_path(rig: &mut Rig) -> Vec<[f64; 2]> {
    let mut poses = vec![[rig.pose()[0], rig.pose()[1]]];
    for _ in 0..20_000 {
        rig.cycle();
        let p = rig.pose();
        poses.push([p[0], p[1]]);
        if rig.snapshot().motion_status & group_motion_status::MOVING == 0 {
            return poses;
        }
    }
    panic!("the path did not end: {:?}", rig.snapshot());
}

/// (0,0) -> (100,0) -> (100,100) with TM_MAX_CORNER_DEV 1 mm at BM_LOW: the commanded path
/// (the segments between the cycles' poses, as the drives follow them) passes the corner
/// at most trans_dev away, whatever the smooth time (HMPL 8.1.5, table 8.1.5.1: "maximum
/// deviation"; HMPL 8.3.19). Beyond trans_dev only the chords of the cycles count: the blend
/// trims d = 2·1/sin 45° = 2√2 mm, its smallest radius is d/√2 = 2 mm, and a chord of one
/// cycle at 100 mm/s (0.1 mm) lies (0.1)²/(8·2) mm inside it, twice over (the planner's
/// cycle, then the smoothed one).
#[test]
fn the_corner_deviation_stays_within_trans_dev_with_smoothing_on() {
    let chords = 2.0 * 0.1f64.powi(2) / (8.0 * 2.0);
    for smooth_ms in [50.0, 0.0, 200.0] {
        let mut rig = xy();
        assert_eq!(rig.group(Command::SetGrpSMTime, &[num(smooth_ms)]), 0, "HMPL 8.3.19");
        assert_eq!(rig.group(Command::SetGrpBufferMode, &[int(2)]), 0, "BM_LOW");
        assert_eq!(rig.group(Command::SetGrpTransMode, &[int(3)]), 0, "TM_MAX_CORNER_DEV");
        assert_eq!(rig.group(Command::SetGrpTransPrm, &[num(50.0), num(20.0), num(1.0), num(0.0)]), 0);
        assert_eq!(rig.group(Command::LineAbs2D, &[num(100.0), num(0.0)]), 0);
        assert_eq!(rig.group(Command::LineAbs2D, &[num(100.0), num(100.0)]), 0);
        let poses = run_path(&mut rig);
        let nearest = poses.windows(2).map(|w| to_segment([100.0, 0.0], w[0], w[1])).fold(f64::INFINITY, f64::min);
        println!("smooth {smooth_ms} ms: the path passes the corner at {nearest:.6} mm");
        assert!(nearest <= 1.0 + chords, "smooth {smooth_ms} ms: {nearest} mm from the corner, above trans_dev 1 mm");
        assert!(nearest > 0.99, "smooth {smooth_ms} ms: the blend uses its tolerance ({nearest} mm)");
        assert_eq!(rig.pose()[..2], [100.0, 100.0]);
    }
}

/// The smoothing keeps a circle's radius (HMPL 8.2.17, 8.3.19): a moving average of each
/// coordinate would pull a 10 mm circle at 100 mm/s in by v²Ts²/(24 r) ≈ 0.1 mm.
#[test]
fn the_smoothing_keeps_a_circle_on_its_radius() {
    let mut rig = xy();
    assert_eq!(rig.group(Command::Circle2D, &[num(10.0), num(0.0), num(0.0), num(0.0), int(1)]), 0);
    let poses = run_path(&mut rig);
    let off = poses.iter().map(|p| (((p[0] - 10.0).powi(2) + p[1].powi(2)).sqrt() - 10.0).abs()).fold(0.0, f64::max);
    println!("a 10 mm circle: off its radius by {off:.2e} mm at most");
    assert!(off < 1e-3, "off the circle by {off} mm");
}

/// HMPL 8.3.4: an axis the group leaves at rest stays where the group left it: UngrpAllAxes
/// (or DisableGroup) in the cycle the move ends, and 1000 cycles later.
#[test]
fn axes_released_at_rest_stay_at_the_end_point() {
    for release in [Command::UngrpAllAxes, Command::DisableGroup] {
        let mut rig = xyz();
        assert_eq!(rig.group(Command::LineAbs3D, &[num(3.0), num(5.0), num(0.0)]), 0);
        rig.till_in_pos(5000);
        assert_eq!(rig.group(Command::LineAbs3D, &[num(0.0), num(0.0), num(2.0)]), 0);
        run_path(&mut rig);
        assert_eq!(rig.group(release, &[]), 0, "{release:?} once the group is at rest");
        for n in 0..1000 {
            rig.cycle();
            let refs: Vec<f64> = (0..3).map(|a| rig.machine.kernel.axes()[a].reference().pos).collect();
            assert!(close(&refs, &[0.0, 0.0, 2.0], 1e-9), "{release:?}: cycle {n} after, the references are {refs:?}");
        }
    }
}

/// An immediate stop (FUN147's pause or abort with M1991 OFF, docs/decisions.md "FUN147")
/// followed by the ungrouping in the same cycle: the axes stand where the stop left them.
#[test]
fn axes_released_after_an_immediate_stop_stand_where_it_stopped() {
    let mut rig = xyz();
    assert_eq!(rig.group(Command::LineAbs3D, &[num(30.0), num(50.0), num(20.0)]), 0);
    rig.cycles(300);
    let kernel = &mut rig.machine.kernel;
    kernel.rest_group(G).unwrap();
    let stopped: Vec<f64> = kernel.groups()[0].snapshot(kernel.axes()).carte_pose_cmd[..3].to_vec();
    kernel.ungrp_all_axes(G).unwrap();
    for n in 0..1000 {
        rig.cycle();
        let refs: Vec<f64> = (0..3).map(|a| rig.machine.kernel.axes()[a].reference().pos).collect();
        assert!(close(&refs, &stopped, 1e-9), "cycle {n} after: {refs:?}, stopped at {stopped:?}");
    }
}

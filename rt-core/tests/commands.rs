//! The core's command rules that involve tasks, cycle by cycle and deterministic: who owns
//! an axis' motion (DXMC alarm 0x001F), the E-stop latch (HMPL 2.9), StopAll (HMPL 2.8),
//! and the fault reactions of a stopped task. Two attached (external) tasks send requests
//! straight to `dispatch`, as the RT thread would.

mod rig;

use api::call::Value;
use api::{Command, SystemError};
use rt_core::config::FaultReaction;
use rt_core::tasks::Entry;
use schema::{MAX_TASKS, TaskSnapshot, motion_status};

use rig::Rig;

/// The alarm 0x001F of the motion core about axis 0 (DXMC 9): "command buffer busy".
const BUSY: i64 = 0x1000_001F;
/// The same about axis 1.
const BUSY_1: i64 = 0x1001_001F;

/// Cycles until axis `a` is at rest and in position (HMPL 5.3.45); fails after 20 s.
fn settle(rig: &mut Rig, a: usize) -> schema::AxisSnapshot {
    for _ in 0..20_000 {
        rig.cycle();
        let s = rig.machine.kernel.axis_snapshot(a);
        if !rig.moving(a) && s.motion_status & motion_status::IN_POSITION != 0 {
            return s;
        }
    }
    panic!("axis {a} not in position within 20 000 cycles: {:?}", rig.machine.kernel.axis_snapshot(a));
}

/// The last alarm of task `t`, as the snapshot shows it.
fn task_alarm(rig: &Rig, t: usize) -> i64 {
    let mut tasks = [TaskSnapshot::default(); MAX_TASKS];
    rig.machine.tasks.fill(&mut tasks, &[100; MAX_TASKS]);
    tasks[t].alarm as i64
}

/// DXMC 9, 0x001F (docs/decisions.md, "Axis ownership"): the task whose command set an
/// axis going owns it until that motion is over. Another task's motion command, `Disable`
/// or `DisableGear` on it is refused with 0x1AAA001F, in any later cycle, and the alarm is
/// that task's; the owner's own commands go on. Once the motion is over, anyone may.
#[test]
fn the_task_that_set_an_axis_going_owns_it_until_its_motion_is_over() {
    let mut rig = Rig::new(FaultReaction::Decelerate);
    rig.enable(0);
    rig.enable(1);
    assert_eq!(rig.call(0, Command::MoveAbs, &[0], &[100.0]), 0);
    // Task, command, its integers and numbers, the return value, what the row says.
    type Row = (u8, Command, &'static [i64], &'static [f64], i64, &'static str);
    let rows: [Row; 12] = [
        (0, Command::MoveAbs, &[0], &[100.0], 0, "the owner again, the same cycle"),
        (1, Command::MoveAbs, &[0], &[5.0], BUSY, "another task's MoveAbs"),
        (1, Command::MoveRel, &[0], &[30.0], BUSY, "another task's MoveRel"),
        (1, Command::MoveVel, &[0], &[10.0], BUSY, "another task's MoveVel"),
        (1, Command::Resume, &[0], &[], BUSY, "another task's Resume"),
        (1, Command::MoveHome, &[0], &[], BUSY, "another task's MoveHome"),
        (1, Command::GearIn, &[1, 0], &[1.0], BUSY, "another task's GearIn of it as a slave"),
        (1, Command::Disable, &[0], &[], BUSY, "another task's Disable"),
        (1, Command::DisableGear, &[0], &[], BUSY, "another task's DisableGear"),
        (0, Command::MoveRel, &[0], &[10.0], 0, "the owner's MoveRel, from the target under way"),
        (1, Command::MoveAbs, &[1], &[5.0], 0, "another task on another axis"),
        (1, Command::MoveAbs, &[0], &[5.0], BUSY, "another task, 200 cycles on"),
    ];
    for (task, command, ints, doubles, rc, what) in rows {
        assert_eq!(rig.call(task, command, ints, doubles), rc, "{what}");
        rig.cycles(20);
    }
    assert_eq!(task_alarm(&rig, 1), BUSY, "the refusals are task 1's alarms");
    let s = settle(&mut rig, 0);
    assert!((s.pos_fb - 110.0).abs() < 1e-3, "the owner's target: {}", s.pos_fb);
    assert_eq!((s.last_err, task_alarm(&rig, 0)), (0, 0), "the owner was told nothing: nothing happened to it");
    assert_eq!(rig.call(1, Command::MoveAbs, &[0], &[0.0]), 0, "the motion is over: another task may");
    rig.cycle();
    assert_eq!(rig.call(0, Command::MoveAbs, &[0], &[50.0]), BUSY, "and now the first is refused");
}

/// What ends a task's ownership besides the end of its motion: the task ended (its
/// motion, fault reaction `none`, goes on as no one's), the axis disabled or stopped in
/// error.
#[test]
fn ownership_ends_with_the_task_the_enable_or_the_error_stop() {
    let mut rig = Rig::new(FaultReaction::None);
    rig.enable(0);
    assert_eq!(rig.call(0, Command::MoveVel, &[0], &[50.0]), 0);
    rig.cycles(10);
    assert_eq!(rig.call(1, Command::MoveVel, &[0], &[-50.0]), BUSY, "task 0 runs: its axis");
    assert_eq!(rig.call(1, Command::StopTask, &[0], &[]), 0);
    rig.cycles(10);
    assert!(rig.moving(0), "fault reaction none: the motion goes on");
    assert_eq!(rig.call(1, Command::MoveAbs, &[0], &[0.0]), 0, "the ended task's motion is no one's");

    let mut rig = Rig::new(FaultReaction::Decelerate);
    rig.enable(0);
    assert_eq!(rig.call(0, Command::MoveVel, &[0], &[50.0]), 0);
    rig.cycles(10);
    assert_eq!(rig.call(0, Command::Disable, &[0], &[]), 0, "the owner disables its own axis");
    rig.cycles(20);
    assert_eq!(rig.call(1, Command::Enable, &[0], &[]), 0);
    rig.cycles(20);
    assert_eq!(rig.call(1, Command::MoveAbs, &[0], &[1.0]), 0, "a disabled axis' motion was over");
}

/// A stop must stop, whoever sends it: another task's `Stop`, `Halt` or `StopAll` is
/// carried out, and the owner, whose axis is then in position short of its target, sees
/// why: the axis' last error (HMPL 18.3 `GetAxisLastErr`) is 0x1AAA001F and so is the
/// owner task's alarm. The owner's own stop tells it nothing.
#[test]
fn another_tasks_stop_stops_the_axis_and_the_owner_sees_it() {
    let rows: [(u8, Command, &[i64], i64, &str); 5] = [
        (1, Command::Stop, &[0], BUSY, "another task's Stop"),
        (1, Command::Halt, &[0], BUSY, "another task's Halt"),
        (1, Command::StopAll, &[], BUSY, "another task's StopAll"),
        (0, Command::Stop, &[0], 0, "the owner's Stop"),
        (0, Command::StopAll, &[], 0, "the owner's StopAll"),
    ];
    for (stopper, command, ints, seen, what) in rows {
        let mut rig = Rig::new(FaultReaction::Decelerate);
        rig.enable(0);
        assert_eq!(rig.call(0, Command::MoveAbs, &[0], &[100.0]), 0);
        rig.cycles(100);
        assert_eq!(rig.call(stopper, command, ints, &[]), 0, "{what} is carried out");
        let s = settle(&mut rig, 0);
        assert!(s.pos_fb < 99.0, "{what}: in position short of 100: {}", s.pos_fb);
        assert_eq!(s.last_err as i64, seen, "{what}: the axis' last error");
        assert_eq!(task_alarm(&rig, 0), seen, "{what}: the owner's alarm");
        assert_eq!(task_alarm(&rig, 1), 0, "{what}: the stopper's command was not refused");
    }
}

/// DXMC 3.6: the console's switch out of Run (to Edit, over Modbus 0x6A81) stops every
/// axis as StopAll does; a program whose move it cut short sees it as from a task's stop.
#[test]
fn leaving_run_stops_the_axes_and_their_owners_see_it() {
    use rt_core::console::{ConsoleOrder, ControllerState};
    let mut rig = Rig::new(FaultReaction::Decelerate);
    rig.machine.carry_out(ConsoleOrder::SwitchState(ControllerState::Run));
    rig.enable(0);
    assert_eq!(rig.call(0, Command::MoveAbs, &[0], &[100.0]), 0);
    rig.cycles(100);
    rig.machine.carry_out(ConsoleOrder::SwitchState(ControllerState::Edit));
    let s = settle(&mut rig, 0);
    assert!(s.pos_fb < 99.0, "in position short of 100: {}", s.pos_fb);
    assert_eq!((s.last_err as i64, task_alarm(&rig, 0)), (BUSY, BUSY), "the axis' last error and the owner's alarm");
}

/// A homing run and an engaged gear slave are motion their task owns.
#[test]
fn a_homing_axis_and_an_engaged_slave_are_their_tasks() {
    let mut rig = Rig::new(FaultReaction::Decelerate);
    for a in 0..3 {
        rig.enable(a);
    }
    assert_eq!(rig.call(0, Command::MoveHome, &[0], &[]), i64::MIN, "MoveHome answers when it is over");
    rig.cycles(5);
    assert_eq!(rig.call(1, Command::MoveAbs, &[0], &[1.0]), BUSY, "a homing axis");
    assert_eq!(rig.call(1, Command::Disable, &[0], &[]), BUSY, "a homing axis, Disable");
    assert_eq!(rig.call(0, Command::EnableGear, &[2, 1], &[]), 0);
    assert_eq!(rig.call(0, Command::GearIn, &[2, 1], &[1.0]), 0);
    rig.cycles(5);
    assert_eq!(rig.call(1, Command::Disable, &[1], &[]), BUSY_1, "an engaged slave, Disable");
    assert_eq!(rig.call(1, Command::GearOut, &[1], &[]), BUSY_1, "an engaged slave, GearOut");
    assert_eq!(rig.call(1, Command::DisableGear, &[1], &[]), BUSY_1, "an engaged slave, DisableGear");
    assert_eq!(rig.call(0, Command::GearOut, &[1], &[]), 0, "its task disengages it");
    rig.cycles(5);
    assert_eq!(rig.call(1, Command::Disable, &[1], &[]), 0, "then it is no one's");
}

/// A group's path is its commander's, and so are the axes on it: another task's path
/// command, `DisableGroup`, or motion or `Disable` of a member axis is refused with
/// 0x1AAA001F (AAA the first member axis the command reaches) until the path is over;
/// another task's `StopGroup` stops the path, and the group's and its axes' last errors
/// say so.
#[test]
fn a_groups_path_and_its_axes_are_its_commanders() {
    let int = Value::Int;
    let num = Value::Double;
    let g = 0;
    let mut rig = Rig::new(FaultReaction::Decelerate);
    for a in 0..2 {
        rig.enable(a);
        assert_eq!(rig.call(0, Command::AddAxisToGrp, &[g, a], &[]), 0);
    }
    assert_eq!(rig.call(0, Command::EnableGroup, &[g], &[]), 0);
    let line = |x: f64| [int(g), num(x), num(0.0)];
    assert_eq!(rig.call_values(0, Command::LineAbs2D, &line(100.0)).0, 0);
    rig.cycles(20);
    assert_eq!(rig.call_values(1, Command::LineAbs2D, &line(20.0)).0, BUSY, "another task's path command");
    assert_eq!(rig.call(1, Command::DisableGroup, &[g], &[]), BUSY, "another task's DisableGroup");
    assert_eq!(rig.call(1, Command::MoveAbs, &[0], &[5.0]), BUSY, "a member axis' motion");
    assert_eq!(rig.call(1, Command::Disable, &[1], &[]), BUSY_1, "a member axis' Disable");
    assert_eq!(rig.call_values(0, Command::LineAbs2D, &line(50.0)).0, 0, "the commander's own path command");
    rig.cycles(20);
    assert_eq!(rig.call(1, Command::StopGroup, &[g], &[]), 0, "another task's StopGroup stops");
    for _ in 0..20_000 {
        rig.cycle();
        if !rig.machine.kernel.groups()[0].is_moving() {
            break;
        }
    }
    let mut snapshot = schema::Snapshot::default();
    rig.machine.kernel.fill(&mut snapshot);
    assert_eq!(
        snapshot.group_last_err[0] & 0xFFFF,
        0x001F,
        "the group's last error: {:#X}",
        snapshot.group_last_err[0]
    );
    assert_eq!(snapshot.axes[0].last_err as i64, BUSY, "axis 0's last error");
    assert!(snapshot.axes[0].pos_fb < 49.0, "stopped short: {}", snapshot.axes[0].pos_fb);
    assert_eq!(task_alarm(&rig, 0), BUSY_1, "the commander's alarm, about its group's last axis");
    assert_eq!(rig.call_values(1, Command::LineAbs2D, &line(0.0)).0, 0, "the path is over: another task may");
}

/// HMPL 2.9: after an E-stop every axis is disabled, every task stopped, and motion is
/// refused with 0x0064 until the axis is enabled again.
#[test]
fn the_estop_latch() {
    let mut rig = Rig::new(FaultReaction::Decelerate);
    rig.enable(0);
    assert_eq!(rig.call(0, Command::MoveAbs, &[0], &[50.0]), 0);
    rig.cycles(10);
    assert_eq!(rig.call(0, Command::EStop, &[], &[]), i64::MIN, "the caller stops: no answer");
    rig.cycles(10);
    assert!(!rig.machine.kernel.axes()[0].is_enabled(), "disabled");
    assert!(!rig.machine.tasks.accepts_commands(0) && !rig.machine.tasks.accepts_commands(1), "tasks stopped");
    assert_eq!(
        rig.call(0, Command::MoveAbs, &[0], &[0.0]),
        api::ErrorCode::System(SystemError::TaskNotRunning).code() as i64,
        "a stopped task is not served"
    );
    let cycle = rig.machine.cycle;
    rig.machine.tasks.start(1, Entry::TOP_LEVEL, cycle).unwrap();
    assert_eq!(rig.call(1, Command::MoveAbs, &[0], &[0.0]), 0x64, "0x0064 eERR_EMERGENCY_STOP");
    assert_eq!(rig.call(1, Command::Enable, &[0], &[]), 0, "enabling again is allowed");
    rig.cycles(20);
    assert_eq!(rig.call(1, Command::MoveAbs, &[0], &[0.0]), 0, "and lifts the latch");
}

/// HMPL 2.8: StopAll stops every moving axis with its kill deceleration; they stay enabled.
#[test]
fn stop_all() {
    let mut rig = Rig::new(FaultReaction::Decelerate);
    rig.enable(0);
    rig.enable(1);
    rig.call(0, Command::MoveVel, &[0], &[100.0]);
    rig.call(1, Command::MoveVel, &[1], &[-100.0]);
    rig.cycles(200);
    assert_eq!(rig.call(0, Command::StopAll, &[], &[]), 0);
    rig.cycles(5);
    assert!(!rig.moving(0) && !rig.moving(1), "100 mm/s at 50 000 mm/s² stops within 2 ms");
    assert!(rig.machine.kernel.axes().iter().take(2).all(|a| a.is_enabled()));
}

/// The reaction of a stopped task touches only the motion it commanded.
#[test]
fn a_stopped_task_reacts_on_its_own_motion_only() {
    for (reaction, stays_enabled, stops) in [
        (FaultReaction::None, true, false),
        (FaultReaction::Decelerate, true, true),
        (FaultReaction::QuickStop, false, true),
        (FaultReaction::Disable, false, true),
    ] {
        let mut rig = Rig::new(reaction);
        rig.enable(0);
        rig.enable(1);
        rig.call(0, Command::MoveVel, &[0], &[100.0]);
        rig.call(1, Command::MoveVel, &[1], &[100.0]);
        rig.cycles(200);
        assert_eq!(rig.call(1, Command::StopTask, &[0], &[]), 0, "{reaction:?}");
        rig.cycles(300);
        let axis0 = &rig.machine.kernel.axes()[0];
        assert_eq!(axis0.is_enabled(), stays_enabled, "{reaction:?}: axis 0 enabled");
        assert_eq!(!axis0.is_moving(), stops, "{reaction:?}: axis 0 stopped");
        assert!(rig.moving(1) && rig.machine.kernel.axes()[1].is_enabled(), "{reaction:?}: task 1's axis goes on");
    }
}

/// DXMC A.3, 0x6B03: a run speed of 1..100 % reaches the machine as one console order,
/// is kept there once, and scales the velocity of the motion that task commands (the
/// move under way included), not another task's; out of range it changes nothing.
#[test]
fn the_run_speed_scales_the_motion_of_its_task_only() {
    use rt_core::console::ConsoleOrder;
    let mut rig = Rig::new(FaultReaction::Decelerate);
    rig.enable(0);
    rig.enable(1);
    rig.call(0, Command::MoveVel, &[0], &[100.0]);
    rig.call(1, Command::MoveVel, &[1], &[100.0]);
    rig.cycles(500);
    let vel = |rig: &Rig, a: usize| rig.machine.kernel.axes()[a].reference().vel;
    assert!((vel(&rig, 0) - 100.0).abs() < 1e-9 && (vel(&rig, 1) - 100.0).abs() < 1e-9);
    rig.machine.carry_out(ConsoleOrder::SetRunSpeed { task: 0, pct: 40 });
    rig.cycles(500);
    assert!((vel(&rig, 0) - 40.0).abs() < 1e-9, "task 0's axis at 40 %: {}", vel(&rig, 0));
    assert!((vel(&rig, 1) - 100.0).abs() < 1e-9, "task 1's axis unchanged: {}", vel(&rig, 1));
    for pct in [0, 101, 255] {
        rig.machine.carry_out(ConsoleOrder::SetRunSpeed { task: 0, pct });
    }
    rig.machine.carry_out(ConsoleOrder::SetRunSpeed { task: 200, pct: 50 });
    assert_eq!(rig.machine.run_speed[0], 40, "out of range: ignored");
    rig.cycles(100);
    assert!((vel(&rig, 0) - 40.0).abs() < 1e-9);
}

/// The range check looks at the first axis of a command; a second one (a gear slave, a
/// gantry partner) only when a number of its own comes (GearIn's ratio). Otherwise the
/// command refuses it itself, after the EtherCAT check: outside Op, `EnableGear(0, 99)`
/// says "not in Op", as HMPL 2.2 wants of every motion command.
#[test]
fn a_second_axis_is_checked_where_its_command_checks_it() {
    let code = |e: SystemError| api::ErrorCode::System(e).code() as i64;
    let mut rig = Rig::new(FaultReaction::None);
    rig.machine.network.request_state(0, devices::ecat::AlState::PreOp).unwrap();
    assert_ne!(rig.machine.network.state(), devices::ecat::AlState::Op);
    assert_eq!(rig.call(0, Command::EnableGear, &[0, 99], &[]), code(SystemError::HmplNotInOpMode));
    assert_eq!(rig.call(0, Command::EnableGantryPair, &[0, 99], &[]), code(SystemError::HmplNotInOpMode));
    assert_eq!(rig.call(0, Command::EnableGear, &[99, 0], &[]), code(SystemError::HmplArgOutOfRange), "the first axis");
    assert_eq!(
        rig.call(0, Command::GearIn, &[0, 99], &[1.0]),
        code(SystemError::HmplArgOutOfRange),
        "the ratio's axis"
    );
}

//! The core's command rules that involve tasks, cycle by cycle and deterministic: one
//! task per axis and cycle (DXMC alarm 0x001F), the E-stop latch (HMPL 2.9),
//! StopAll (HMPL 2.8), and the fault reactions of a stopped task. Two attached (external)
//! tasks send requests straight to `dispatch`, as the RT thread would.

mod rig;

use api::{Command, SystemError};
use rt_core::config::FaultReaction;
use rt_core::tasks::Entry;

use rig::Rig;

/// DXMC 9 (0x001F; docs/decisions.md, "Two tasks on one axis"): one task commands an
/// axis in a cycle; the second is refused.
#[test]
fn one_task_per_axis_and_cycle() {
    let mut rig = Rig::new(FaultReaction::Decelerate);
    rig.enable(0);
    rig.enable(1);
    let rows: [(u8, i64, u64, i64, &str); 5] = [
        (0, 0, 0, 0, "task 0 commands axis 0"),
        (0, 0, 0, 0, "task 0 again, same cycle: its own command"),
        (1, 0, 0, 0x1000_001F, "task 1, same axis, same cycle: 0x001F (motion core, axis 0)"),
        (1, 1, 0, 0, "task 1, another axis, same cycle"),
        (1, 0, 1, 0, "task 1, axis 0, the next cycle"),
    ];
    for (task, axis, after, rc, what) in rows {
        rig.cycles(after as usize);
        assert_eq!(rig.call(task, Command::MoveAbs, &[axis], &[10.0]), rc, "{what}");
    }
    assert_eq!(rig.machine.kernel.axes()[0].commander(), Some(1), "the last commander owns the motion");
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
    rig.machine.network.request_state(0, rt_core::ecat::AlState::PreOp).unwrap();
    assert_ne!(rig.machine.network.state(), rt_core::ecat::AlState::Op);
    assert_eq!(rig.call(0, Command::EnableGear, &[0, 99], &[]), code(SystemError::HmplNotInOpMode));
    assert_eq!(rig.call(0, Command::EnableGantryPair, &[0, 99], &[]), code(SystemError::HmplNotInOpMode));
    assert_eq!(rig.call(0, Command::EnableGear, &[99, 0], &[]), code(SystemError::HmplArgOutOfRange), "the first axis");
    assert_eq!(
        rig.call(0, Command::GearIn, &[0, 99], &[1.0]),
        code(SystemError::HmplArgOutOfRange),
        "the ratio's axis"
    );
}

//! HMPL ch. 13 as conformance rows: the touch probe functions carried out by the kernel on
//! the drive's 0x60B8..0x60BD through the second PDOs, answered from the snapshot.
//! Axis 0 has the CoE manual's drive (probe 1 on the index only); axis 1 a CiA 402 touch
//! probe with probe input 1 over [30, 32] mm and probe input 2 over [35, 36] mm. Both
//! axes have an index every 10 mm at 0, 10, 20 ... mm, each pulse 0.1 mm wide.

mod rig;

use api::{AxisError, Command, ErrorCode, Query, QueryCall};
use calls::query::{Answer, Value};
use rig::Rig;
use rt_core::config::{FaultReaction, MachineConfig, TouchProbeKind};
use schema::Snapshot;

const INDEX_ONLY: i64 = 0;
const CIA402: i64 = 1;
/// One count of the default axes (10 000 counts/mm).
const COUNT: f64 = 1e-4;

fn rig() -> Rig {
    let mut config = MachineConfig::default();
    config.axes.truncate(2);
    let probe_axis = &mut config.axes[CIA402 as usize];
    probe_axis.drive_settings.touch_probe = TouchProbeKind::Cia402;
    probe_axis.travel.probe_input_1 = Some([30.0, 32.0]);
    probe_axis.travel.probe_input_2 = Some([35.0, 36.0]);
    let mut rig = Rig::with_config(config, FaultReaction::None);
    for axis in [INDEX_ONLY, CIA402] {
        rig.enable(axis);
        // Away from the index at 0, which the servo's jitter could cross.
        move_to(&mut rig, axis, 5.0);
    }
    rig
}

fn move_to(rig: &mut Rig, axis: i64, pos: f64) {
    assert_eq!(rig.call(0, Command::MoveAbs, &[axis], &[pos]), 0);
    rig.cycle();
    for _ in 0..5000 {
        if !rig.moving(axis as usize) {
            return;
        }
        rig.cycle();
    }
    panic!("axis {axis} did not reach {pos}");
}

fn answer(rig: &Rig, function: Query, axis: i64) -> Result<Answer, ErrorCode> {
    let mut snapshot = Box::<Snapshot>::default();
    rig.machine.kernel.fill(&mut snapshot);
    let call: QueryCall = api::call::from_values(function, &[api::call::Value::Int(axis)]).expect("as declared");
    calls::query::evaluate(&call, &snapshot)
}

fn flag(rig: &Rig, function: Query, axis: i64) -> bool {
    match answer(rig, function, axis) {
        Ok(Answer(Value::Bool(b), None)) => b,
        other => panic!("{function:?}: {other:?}"),
    }
}

/// GetTouchProbeNPos: the latched position after rc 0.
fn latched(rig: &Rig, function: Query, axis: i64) -> f64 {
    match answer(rig, function, axis) {
        Ok(Answer(Value::Int(0), Some(Value::Double(pos)))) => pos,
        other => panic!("{function:?}: {other:?}"),
    }
}

/// GetTouchProbeNPos' answer when it fails: the reason and 0.
fn failed(rc: i64) -> Answer {
    Answer(Value::Int(rc), Some(Value::Double(0.0)))
}

fn code(axis: i64, e: AxisError) -> i64 {
    ErrorCode::axis(axis as u8, e).code() as i64
}

/// `SetTouchProbeNFunc(axis, tp_input, cont_trigger, detect_edge)` then `EnableTouchProbeN`.
fn arm(rig: &mut Rig, probe: u8, axis: i64, function: [i64; 3]) {
    let (set, enable) = match probe {
        1 => (Command::SetTouchProbe1Func, Command::EnableTouchProbe1),
        _ => (Command::SetTouchProbe2Func, Command::EnableTouchProbe2),
    };
    assert_eq!(rig.call(0, set, &[axis, function[0], function[1], function[2]], &[]), 0);
    assert_eq!(rig.call(0, enable, &[axis], &[]), 0);
}

fn close(actual: f64, expected: f64, what: &str) {
    assert!((actual - expected).abs() <= COUNT, "{what}: {actual} mm, the mark is at {expected} mm");
}

/// HMPL 13.2, 13.6, 13.8, 13.10, 13.12: the index, single trigger, rising edge latches
/// the first mark crossed and keeps it.
#[test]
fn index_single_rising_keeps_the_first_mark() {
    let mut rig = rig();
    assert!(!flag(&rig, Query::IsTouchProbe1Enabled, INDEX_ONLY), "off at power-up");
    arm(&mut rig, 1, INDEX_ONLY, [1, 0, 0]);
    assert!(flag(&rig, Query::IsTouchProbe1Enabled, INDEX_ONLY), "enabled as soon as the call returns");
    assert!(!flag(&rig, Query::IsTouchProbe1Triggered, INDEX_ONLY));
    move_to(&mut rig, INDEX_ONLY, 25.0);
    assert!(flag(&rig, Query::IsTouchProbe1Triggered, INDEX_ONLY));
    close(latched(&rig, Query::GetTouchProbe1Pos, INDEX_ONLY), 10.0, "the first mark (10, 20 crossed)");
}

/// HMPL 13.12 cont_trigger 1: every mark overwrites; detect_edge 1: the pulse's end.
#[test]
fn index_continuous_and_falling() {
    let mut rig = rig();
    arm(&mut rig, 1, INDEX_ONLY, [1, 1, 0]);
    move_to(&mut rig, INDEX_ONLY, 25.0);
    close(latched(&rig, Query::GetTouchProbe1Pos, INDEX_ONLY), 20.0, "continuous: the last mark");
    arm(&mut rig, 1, INDEX_ONLY, [1, 0, 1]);
    assert!(!flag(&rig, Query::IsTouchProbe1Triggered, INDEX_ONLY), "a new function re-arms");
    move_to(&mut rig, INDEX_ONLY, 45.0);
    close(latched(&rig, Query::GetTouchProbe1Pos, INDEX_ONLY), 30.1, "falling, single: the end of the 30 mm pulse");
}

/// HMPL 13.10: the position in the axis' coordinates, as the feedback: SetPos moves the origin.
#[test]
fn latched_position_follows_set_pos() {
    let mut rig = rig();
    assert_eq!(rig.call(0, Command::SetPos, &[INDEX_ONLY], &[105.0]), 0, "5 mm reads 105 mm");
    arm(&mut rig, 1, INDEX_ONLY, [1, 0, 0]);
    move_to(&mut rig, INDEX_ONLY, 118.0);
    close(latched(&rig, Query::GetTouchProbe1Pos, INDEX_ONLY), 110.0, "the mark at 10 mm of the machine");
}

/// HMPL 13.4: disabling and enabling again re-arms a single trigger; the snapshot never
/// shows the old latch after the call returns.
#[test]
fn disable_and_enable_rearm_a_single_trigger() {
    let mut rig = rig();
    arm(&mut rig, 1, INDEX_ONLY, [1, 0, 0]);
    move_to(&mut rig, INDEX_ONLY, 15.0);
    assert!(flag(&rig, Query::IsTouchProbe1Triggered, INDEX_ONLY));
    assert_eq!(rig.call(0, Command::DisableTouchProbe1, &[INDEX_ONLY], &[]), 0);
    assert!(!flag(&rig, Query::IsTouchProbe1Enabled, INDEX_ONLY));
    assert!(!flag(&rig, Query::IsTouchProbe1Triggered, INDEX_ONLY));
    rig.cycle();
    assert_eq!(rig.call(0, Command::EnableTouchProbe1, &[INDEX_ONLY], &[]), 0);
    for _ in 0..3 {
        assert!(!flag(&rig, Query::IsTouchProbe1Triggered, INDEX_ONLY), "armed again, nothing crossed");
        rig.cycle();
    }
    move_to(&mut rig, INDEX_ONLY, 25.0);
    close(latched(&rig, Query::GetTouchProbe1Pos, INDEX_ONLY), 20.0, "the next mark");
}

/// HMPL 13.1 note 1: what the drive cannot do is refused. The CoE manual's drive has no
/// probe 2 (0x60BC/0x60BD are not in its PDO: 0x83II0258) and no probe input (0x83II012C);
/// arguments other than 0 and 1 are 0x83II012C.
#[test]
fn what_the_drive_cannot_do_is_refused() {
    let mut rig = rig();
    let no_pdo = code(INDEX_ONLY, AxisError::CmdInvalidNoSpecificPdo);
    let parameter = code(INDEX_ONLY, AxisError::CmdInvalidParameter);
    let rows: &[(Command, &[i64], i64)] = &[
        (Command::EnableTouchProbe2, &[INDEX_ONLY], no_pdo),
        (Command::DisableTouchProbe2, &[INDEX_ONLY], no_pdo),
        (Command::SetTouchProbe2Func, &[INDEX_ONLY, 1, 0, 0], no_pdo),
        (Command::SetTouchProbe1Func, &[INDEX_ONLY, 0, 0, 0], parameter),
        (Command::SetTouchProbe1Func, &[INDEX_ONLY, 2, 0, 0], parameter),
        (Command::SetTouchProbe1Func, &[INDEX_ONLY, 1, -1, 0], parameter),
        (Command::SetTouchProbe1Func, &[INDEX_ONLY, 1, 0, 2], parameter),
        (Command::SetTouchProbe2Func, &[CIA402, 1, 0, 7], code(CIA402, AxisError::CmdInvalidParameter)),
    ];
    for (command, args, expected) in rows {
        assert_eq!(rig.call(0, *command, args, &[]), *expected, "{command:?}{args:?}");
    }
    assert!(!flag(&rig, Query::IsTouchProbe2Enabled, INDEX_ONLY));
    assert_eq!(answer(&rig, Query::GetTouchProbe2Pos, INDEX_ONLY), Ok(failed(no_pdo)), "the manual's non-0");
    let out_of_range = ErrorCode::System(api::SystemError::HmplArgOutOfRange).code() as i64;
    assert_eq!(answer(&rig, Query::GetTouchProbe1Pos, 2), Ok(failed(out_of_range)), "no axis 2");
    assert_eq!(latched(&rig, Query::GetTouchProbe1Pos, INDEX_ONLY), 0.0, "nothing latched yet");
}

/// A CiA 402 touch probe: both probes at once, probe 1 on its input's rising edge, probe 2
/// on the index, continuous, falling edge.
#[test]
fn both_probes_at_once_on_an_input_and_the_index() {
    let mut rig = rig();
    arm(&mut rig, 1, CIA402, [0, 0, 0]);
    arm(&mut rig, 2, CIA402, [1, 1, 1]);
    assert!(flag(&rig, Query::IsTouchProbe1Enabled, CIA402) && flag(&rig, Query::IsTouchProbe2Enabled, CIA402));
    move_to(&mut rig, CIA402, 45.0);
    assert!(flag(&rig, Query::IsTouchProbe1Triggered, CIA402) && flag(&rig, Query::IsTouchProbe2Triggered, CIA402));
    close(latched(&rig, Query::GetTouchProbe1Pos, CIA402), 30.0, "probe input 1 rises at 30 mm");
    close(latched(&rig, Query::GetTouchProbe2Pos, CIA402), 40.1, "the last index pulse's end");
}

/// A CiA 402 touch probe: probe 2 on its own input, falling edge; moving back, the input's
/// falling edge is at its other end.
#[test]
fn probe_input_falling_edge_in_either_direction() {
    let mut rig = rig();
    arm(&mut rig, 2, CIA402, [0, 1, 1]);
    move_to(&mut rig, CIA402, 40.0);
    close(latched(&rig, Query::GetTouchProbe2Pos, CIA402), 36.0, "moving positive, input 2 falls at 36 mm");
    move_to(&mut rig, CIA402, 33.0);
    close(latched(&rig, Query::GetTouchProbe2Pos, CIA402), 35.0, "moving negative, it falls at 35 mm");
    assert!(!flag(&rig, Query::IsTouchProbe1Triggered, CIA402), "probe 1 was never enabled");
}

/// The kernel reaches the probe only through process data: without the touch probe's
/// PDO mapping every function that needs it answers 0x83II0258.
#[test]
fn without_the_pdo_the_probe_is_refused() {
    let mut config = MachineConfig::default();
    config.axes.truncate(1);
    config.axes[0].touch_probe_pdo = false;
    let mut rig = Rig::with_config(config, FaultReaction::None);
    let no_pdo = code(0, AxisError::CmdInvalidNoSpecificPdo);
    assert_eq!(rig.call(0, Command::EnableTouchProbe1, &[0], &[]), no_pdo);
    assert_eq!(rig.call(0, Command::SetTouchProbe1Func, &[0, 1, 0, 0], &[]), no_pdo);
    assert_eq!(answer(&rig, Query::GetTouchProbe1Pos, 0), Ok(failed(no_pdo)));
}

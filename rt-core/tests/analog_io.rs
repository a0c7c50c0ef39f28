//! HMPL 10.4 cycle by cycle: analog outputs bound to an axis variable hold, in the RxPDO,
//! exactly the converted `var * scale + offset` of the cycle's axis snapshot, every cycle
//! of a move, for a reference variable and for the acceleration feedback (the velocity
//! feedback's change over one cycle).

mod rig;

use api::Command;
use api::analog::{AxisVariable, ConversionType, Range};
use rig::Rig;
use rt_core::config::{FaultReaction, MachineConfig, SlaveConfig, SlaveDevice};
use schema::{ANALOG_OUTPUTS, Snapshot};

/// Axis 0's drive, then the terminal.
const TERMINAL: i64 = 1;
const PERIOD_S: f64 = 1e-3;

fn rig() -> Rig {
    let mut config = MachineConfig::default();
    config.axes.truncate(1);
    config.slaves.push(SlaveConfig { device: SlaveDevice::AnalogIo, inputs: 0, outputs: 2, loopback: false });
    Rig::with_config(config, FaultReaction::None)
}

/// What the cycle does after the kernel's stage (`cycle.rs`): the snapshot's axes, then
/// the bound outputs. Returns the axis as the outputs saw it.
fn cycle(rig: &mut Rig, snapshot: &mut Snapshot) -> schema::AxisSnapshot {
    rig.cycle();
    let m = &mut rig.machine;
    m.kernel.fill(snapshot);
    m.analog.step(&snapshot.axes, &mut m.network, PERIOD_S);
    snapshot.axes[0]
}

fn output_word(rig: &mut Rig, channel: u8) -> u16 {
    let field = rig.machine.network.output_field(TERMINAL as usize, ANALOG_OUTPUTS, channel).unwrap();
    field.read(rig.machine.network.images_mut().1) as u16
}

#[test]
fn bound_outputs_follow_their_variable_every_cycle() {
    let mut rig = rig();
    let n10_p10 = ConversionType { range: Range::N10P10, signed: false };
    let signed = ConversionType { range: Range::N5P5, signed: true };
    let (vel, acc) = (AxisVariable::RefVel.code(), AxisVariable::AccFb.code());
    for (command, ints, doubles) in [
        (Command::SetSlvAOType, vec![TERMINAL, 1, n10_p10.code()], vec![]),
        (Command::SetSlvAOMonitor, vec![TERMINAL, 1, vel], vec![]),
        (Command::SetSlvAOParam, vec![TERMINAL, 1, 1], vec![0.02, -1.0]),
        (Command::SetSlvAOType, vec![TERMINAL, 2, signed.code()], vec![]),
        (Command::SetSlvAOMonitor, vec![TERMINAL, 2, acc], vec![]),
        (Command::SetSlvAOParam, vec![TERMINAL, 2, 1], vec![1e-4, 0.0]),
    ] {
        assert_eq!(rig.call(0, command, &ints, &doubles), 0, "{command:?}");
    }
    rig.enable(0);
    assert_eq!(rig.call(0, Command::MoveRel, &[0], &[50.0]), 0);
    let mut snapshot = Box::<Snapshot>::default();
    let mut last_vel_fb = cycle(&mut rig, &mut snapshot).vel_fb;
    let (mut cycles, mut saturated, mut peak_vel) = (0, 0, 0.0_f64);
    while rig.moving(0) {
        let axis = cycle(&mut rig, &mut snapshot);
        let want_vel = n10_p10.word_clamped(axis.ref_vel * 0.02 - 1.0);
        assert_eq!(output_word(&mut rig, 1), want_vel, "cycle {cycles}: ref_vel {}", axis.ref_vel);
        let acc_fb = (axis.vel_fb - last_vel_fb) / PERIOD_S;
        let want_acc = signed.word_clamped(acc_fb * 1e-4);
        assert_eq!(output_word(&mut rig, 2), want_acc, "cycle {cycles}: acc_fb {acc_fb}");
        saturated += (want_acc == 0x7FFF || want_acc == 0x8000) as usize;
        last_vel_fb = axis.vel_fb;
        peak_vel = peak_vel.max(axis.ref_vel);
        cycles += 1;
    }
    assert!(cycles > 100 && peak_vel > 0.0, "a move of {cycles} cycles at up to {peak_vel}");
    assert_eq!(saturated, 0, "the acceleration stayed within ±5 V");
    assert_eq!(output_word(&mut rig, 1), n10_p10.word_clamped(-1.0), "at rest: the offset");
}

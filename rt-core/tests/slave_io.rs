//! HMPL 9.3 and 9.5 as a conformance table: a slave's digital outputs set by commands
//! into its process data and every channel read back from the snapshot, on a digital I/O
//! terminal (`[[slaves]] device = "digital_io"`) and on the drives' own 0x60FD/0x60FE.

mod rig;

use api::call::Value;
use api::{Command, Query, QueryCall};
use devices::terminal::DigitalIoTerminal;
use rig::Rig;
use rt_core::config::{AxisConfig, FaultReaction, MachineConfig, SlaveConfig, SlaveDevice};
use rt_core::master;
use schema::Snapshot;

const DRIVE: i64 = 0;
/// A drive with 0x60FE:01 in its RxPDO.
const DRIVE_WITH_OUTPUTS: i64 = 1;
const TERMINAL: i64 = 2;
const SLOT_1: i64 = 1 << 16;

/// Two axes (the second maps 0x60FE:01), then a terminal with 16 inputs and 16 outputs.
fn rig() -> Rig {
    let mut config = MachineConfig::default();
    config.axes.truncate(1);
    let first = config.axes[0].clone();
    let rx = vec![0x6040_0010, 0x607A_0020, 0x6060_0008, 0x60FF_0020, 0x60FE_0120];
    config.axes.push(AxisConfig { name: "y".into(), rx_pdo: Some(rx), ..first });
    config.slaves.push(SlaveConfig { device: SlaveDevice::DigitalIo, inputs: 16, outputs: 16, loopback: false });
    Rig::with_config(config, FaultReaction::None)
}

/// A query answered from the snapshot the cycle would publish.
fn query(rig: &Rig, function: Query, args: &[i64]) -> i64 {
    let mut snapshot = Box::<Snapshot>::default();
    master::describe_slaves(&rig.machine.network, &mut snapshot);
    master::update_slaves(&rig.machine.network, &mut snapshot);
    let values: Vec<Value> = args.iter().map(|&a| Value::Int(a)).collect();
    let call: QueryCall = api::call::from_values(function, &values).expect("arguments as declared");
    match calls::query::evaluate(&call, &snapshot).expect("an answer").0 {
        calls::query::Value::Int(v) => v,
        other => panic!("{function:?}: {other:?}"),
    }
}

fn call(rig: &mut Rig, function: Command, args: &[i64]) -> i64 {
    rig.call(0, function, args, &[])
}

/// One row per fact of the manual: the calls, then what a query answers.
#[test]
fn terminal_outputs_and_inputs() {
    let mut rig = rig();
    use Command::*;
    use Query::*;
    // (section, commands with their return values, query, its arguments, answer)
    type Row = (&'static str, &'static [(Command, &'static [i64], i64)], Query, &'static [i64], i64);
    let rows: &[Row] = &[
        (
            "9.3.1",
            &[(SetSlvGPO, &[TERMINAL, 2, 1], 0), (SetSlvGPO, &[TERMINAL, 3, 1], 0)],
            GetSlvGPO,
            &[TERMINAL, 2],
            1,
        ),
        ("9.5.4: outputs 2 and 3 on: 6", &[], GetSlvAllGPO, &[TERMINAL], 6),
        ("9.3.1: off", &[(SetSlvGPO, &[TERMINAL, 2, 0], 0)], GetSlvAllGPO, &[TERMINAL], 4),
        (
            "9.3.2",
            &[(ToggleSlvGPO, &[TERMINAL, 3], 0), (ToggleSlvGPO, &[TERMINAL, 16], 0)],
            GetSlvAllGPO,
            &[TERMINAL],
            0x8000,
        ),
        ("9.3.3", &[(SetSlvAllGPO, &[TERMINAL, 0x300], 0)], GetSlvAllGPO, &[TERMINAL], 0x300),
        ("9.5.6: start 8, outputs 9 and 10 on: 6", &[], GetSlvAllGPOByStartIdx, &[TERMINAL, 8], 6),
        ("9.5.2", &[], GetSlvGPO, &[TERMINAL, 10], 1),
        (
            "9.3.1: output 17 of 16",
            &[(SetSlvGPO, &[TERMINAL, 17, 1], -1), (SetSlvGPO, &[TERMINAL, 0, 1], -1)],
            GetSlvAllGPO,
            &[TERMINAL],
            0x300,
        ),
        (
            "9.3.3: a channel it lacks",
            &[(SetSlvAllGPO, &[TERMINAL, 0x1_0000], -1), (SetSlvAllGPO, &[TERMINAL, -1], -1)],
            GetSlvAllGPO,
            &[TERMINAL],
            0x300,
        ),
        ("9.1: no such slave", &[(SetSlvGPO, &[3, 1, 1], -1), (ToggleSlvGPO, &[-1, 1], -1)], GetSlvGPO, &[3, 1], -1),
        (
            "9.1: a slot the slave lacks",
            &[(SetSlvGPO, &[TERMINAL | SLOT_1, 1, 1], -1)],
            GetSlvGPO,
            &[TERMINAL | SLOT_1, 1],
            -1,
        ),
        ("9.5.2: output 0", &[], GetSlvGPO, &[TERMINAL, 0], -1),
        (
            "9.5.2: the lowest integer",
            &[(SetSlvGPO, &[TERMINAL, i64::MIN, 1], -1), (ToggleSlvGPO, &[i64::MIN, i64::MIN], -1)],
            GetSlvGPO,
            &[TERMINAL, i64::MIN],
            -1,
        ),
        (
            "9.5.6: the lowest integer",
            &[(SetSlvAllGPO, &[i64::MAX, i64::MIN], -1)],
            GetSlvAllGPOByStartIdx,
            &[TERMINAL, i64::MIN],
            -1,
        ),
        ("9.5.6: start 17 of 16", &[], GetSlvAllGPOByStartIdx, &[TERMINAL, 17], -1),
        ("9.3.1: a drive without 0x60FE:01 in its PDO", &[(SetSlvGPO, &[DRIVE, 1, 1], -1)], GetSlvGPO, &[DRIVE, 1], -1),
        (
            "9.3.1: a drive's O2 in 0x60FE:01",
            &[(SetSlvGPO, &[DRIVE_WITH_OUTPUTS, 2, 1], 0)],
            GetSlvAllGPO,
            &[DRIVE_WITH_OUTPUTS],
            2,
        ),
        ("9.3.1: O2 is bit 18 (CoE table 4-19)", &[], ReadPDO, &[DRIVE_WITH_OUTPUTS, 0x60FE, 1], 1 << 18),
        (
            "9.3.3: O1..O5 of a drive",
            &[(SetSlvAllGPO, &[DRIVE_WITH_OUTPUTS, 0x1F], 0), (SetSlvAllGPO, &[DRIVE_WITH_OUTPUTS, 0x20], -1)],
            ReadPDO,
            &[DRIVE_WITH_OUTPUTS, 0x60FE, 1],
            0x1F << 17,
        ),
        (
            "9.3.2: a drive's O2 toggled, the other outputs and the brake (bit 16) kept",
            &[
                (WritePDO, &[DRIVE_WITH_OUTPUTS, 0x60FE, 1, 0x1F << 17 | 1 << 16], 0),
                (ToggleSlvGPO, &[DRIVE_WITH_OUTPUTS, 2], 0),
            ],
            ReadPDO,
            &[DRIVE_WITH_OUTPUTS, 0x60FE, 1],
            0x1D << 17 | 1 << 16,
        ),
    ];
    for &(section, commands, function, args, answer) in rows {
        for &(command, command_args, rc) in commands {
            assert_eq!(call(&mut rig, command, command_args), rc, "{section}: {command:?}{command_args:?}");
        }
        rig.cycle();
        assert_eq!(query(&rig, function, args), answer, "{section}: {function:?}{args:?}");
    }
    let terminal = rig.machine.network.slaves()[TERMINAL as usize].device_as::<DigitalIoTerminal>().unwrap();
    assert_eq!(terminal.outputs(), 0x300, "the terminal drives what the master sent");
}

/// HMPL 9.5: inputs the simulator switches reach the program through the TxPDO.
#[test]
fn terminal_inputs() {
    let mut rig = rig();
    use Query::*;
    for pin in [1, 4, 8, 11] {
        assert_eq!(call(&mut rig, Command::SimSetSlvGPI, &[TERMINAL, pin, 1]), 0);
    }
    assert_eq!(query(&rig, GetSlvAllGPI, &[TERMINAL]), 0, "not before the next frame");
    rig.cycle();
    let rows: &[(&str, Query, &[i64], i64)] = &[
        ("9.5.3", GetSlvAllGPI, &[TERMINAL], 0b100_1000_1001),
        ("9.5.5: start 8, inputs 8 and 11 on: 9", GetSlvAllGPIByStartIdx, &[TERMINAL, 8], 9),
        ("9.5.5: start 1 is all", GetSlvAllGPIByStartIdx, &[TERMINAL, 1], 0b100_1000_1001),
        ("9.5.1", GetSlvGPI, &[TERMINAL, 4], 1),
        ("9.5.1: off", GetSlvGPI, &[TERMINAL, 5], 0),
        ("9.5.1: input 17 of 16", GetSlvGPI, &[TERMINAL, 17], -1),
        ("9.5.1: a drive's 0x60FD, no limit reached", GetSlvGPI, &[DRIVE, 1], 0),
        ("9.5.3: no such slave", GetSlvAllGPI, &[3], -1),
        ("9.5.5: the lowest integer", GetSlvAllGPIByStartIdx, &[TERMINAL, i64::MIN], -1),
        ("9.5.1: the lowest slave", GetSlvGPI, &[i64::MIN, 1], -1),
    ];
    for &(section, function, args, answer) in rows {
        assert_eq!(query(&rig, function, args), answer, "{section}: {function:?}{args:?}");
    }
    let refused: &[(&str, &[i64])] = &[
        ("input 17", &[TERMINAL, 17, 1]),
        ("a drive", &[DRIVE, 1, 1]),
        ("no slave", &[3, 1, 1]),
        ("the lowest integer", &[TERMINAL, i64::MIN, 1]),
    ];
    for &(what, args) in refused {
        assert_eq!(call(&mut rig, Command::SimSetSlvGPI, args), -1, "{what}");
    }
    assert_eq!(call(&mut rig, Command::SimSetSlvGPI, &[TERMINAL, 4, 0]), 0);
    rig.cycle();
    assert_eq!(query(&rig, GetSlvGPI, &[TERMINAL, 4]), 0, "switched off");
}

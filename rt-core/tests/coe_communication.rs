//! Conformance: EtherCAT communication and the object dictionary (CoE manual ch. 2 and 4).
//! Each row names the section or table of the HIWIN CoE drive manual (v1.1) it checks.

mod bench;

use bench::{Bench, PERIOD_NS};
use rt_core::config::AxisConfig;
use rt_core::drive::DriveModel;
use rt_core::ecat::{AlState, SdoAbort, SdoError};

fn abort(result: Result<impl std::fmt::Debug, SdoError>) -> SdoAbort {
    match result {
        Err(SdoError::Abort(a)) => a,
        other => panic!("expected an abort, got {other:?}"),
    }
}

/// CoE 2.3: Init has no mailbox; the ESM goes up one level at a time.
#[test]
fn esm_from_power_up() {
    let mut net = Bench::unstarted(bench::drive_defaults());
    assert_eq!(net.state(), AlState::Init, "CoE 2.3: Init after power-up");
    assert_eq!(net.sdo_read(0, 0x1000, 0), Err(SdoError::NoMailbox), "CoE 2.3: no SDO in Init");
    assert!(net.request_state(0, AlState::Op).is_err(), "CoE 2.3: Init -> Op refused");
    assert!(net.request_state(0, AlState::SafeOp).is_err(), "Init -> SafeOp refused");
    assert_eq!(net.slaves()[0].esm().error().map(|c| c.code()), Some(0x0011), "AL status 0x0011");
    assert!(net.request_state(0, AlState::PreOp).is_ok(), "CoE 2.3: Init -> PreOp");
    assert_eq!(net.sdo_read(0, 0x1000, 0), Ok((0x0002_0192, 4)), "CoE 2.3: device type in PreOp");
    assert!(net.request_state(0, AlState::Op).is_err(), "PreOp -> Op refused");
    assert!(net.request_state(0, AlState::Init).is_ok(), "down to any lower state");
}

/// CoE tables 4-1, 4-4, 4-6, 4-15: identity and defaults.
#[test]
fn identity_and_defaults() {
    let b = Bench::new();
    let rows: [(u16, u8, i64, &str); 32] = [
        (0x1018, 1, 0xAAAA, "CoE table 4-1: vendor id"),
        (0x1018, 0, 4, "CoE table 4-1"),
        (0x1018, 3, 1, "CoE table 4-1: revision"),
        (0x1018, 4, 0, "CoE table 4-1: serial"),
        (0x1018, 2, 2, "CoE table 4-1: product code of a D1"),
        (0x1C00, 0, 4, "CoE table 4-4"),
        (0x1C00, 1, 1, "CoE table 4-4"),
        (0x1C00, 2, 2, "CoE table 4-4"),
        (0x1C00, 3, 3, "CoE table 4-4"),
        (0x1C00, 4, 4, "CoE table 4-4"),
        (0x1C10, 0, 0, "CoE table 4-4"),
        (0x1C11, 0, 0, "CoE table 4-4"),
        (0x1C33, 1, 2, "CoE table 4-4: sync type DC"),
        (0x1C32, 4, 0x0005, "CoE table 4-4"),
        (0x1C33, 4, 0x0005, "CoE table 4-4"),
        (0x1C32, 5, 125_000, "CoE table 4-4"),
        (0x1C32, 6, 62_500, "CoE table 4-4"),
        (0x1C33, 9, 0, "CoE table 4-4"),
        (0x6502, 0, 0x03AD, "CoE table 4-15: supported modes"),
        (0x2042, 0, 1, "CoE tables 4-6, 4-15"),
        (0x2041, 0, 0, "CoE tables 4-6, 4-15"),
        (0x2043, 0, 0x07EF, "CoE tables 4-6, 4-15"),
        (0x2000, 0, 2, "CoE tables 4-6, 4-15"),
        (0x2003, 0, 1, "CoE tables 4-6, 4-15"),
        (0x2004, 0, 2, "CoE tables 4-6, 4-15"),
        (0x2004, 1, 1, "CoE tables 4-6, 4-15"),
        (0x2004, 2, 1, "CoE tables 4-6, 4-15"),
        (0x60C5, 0, 10_000, "CoE tables 4-6, 4-15"),
        (0x60C6, 0, 10_000, "CoE tables 4-6, 4-15"),
        (0x607D, 0, 2, "CoE tables 4-6, 4-15"),
        (0x6099, 0, 2, "CoE tables 4-6, 4-15"),
        (0x60FE, 0, 2, "CoE tables 4-6, 4-15"),
    ];
    for (index, sub, expected, what) in rows {
        assert_eq!(b.read(index, sub), expected, "0x{index:04X}:{sub}, {what}");
    }
    // CoE table 4-4 as configured by the master for DC at the controller's cycle.
    assert_eq!(b.read(0x1C32, 1), 2);
    assert_eq!(b.read(0x1C32, 2), PERIOD_NS as i64);
    // CoE tables 4-6, 4-15: REAL32 gains.
    for (index, value) in
        [(0x2050, 0.3f32), (0x2051, 0.001), (0x2052, 500.0), (0x2053, 100.0), (0x2054, 314.0), (0x2055, 314.0)]
    {
        assert_eq!(f32::from_bits(b.read(index, 0) as u32), value, "0x{index:04X}");
    }
}

/// CoE table 4-2: the product code of each model (abily's 4 is above the printed max 3).
#[test]
fn product_codes() {
    for (model, code) in [(DriveModel::D1N, 1), (DriveModel::D1, 2), (DriveModel::D2, 3), (DriveModel::Abily, 4)] {
        let b = Bench::with(AxisConfig { drive: model, ..bench::drive_defaults() });
        assert_eq!(b.read(0x1018, 2), code, "{model:?}");
    }
}

/// CoE 2.4, table 4-3: the default mapping, 6 and 10 bytes.
#[test]
fn default_pdo_mapping() {
    let b = Bench::new();
    let rows: [(u16, u8, i64); 9] = [
        (0x1600, 0, 2),
        (0x1600, 1, 0x6040_0010),
        (0x1600, 2, 0x607A_0020),
        (0x1A00, 0, 3),
        (0x1A00, 1, 0x6041_0010),
        (0x1A00, 2, 0x6064_0020),
        (0x1A00, 3, 0x60F4_0020),
        (0x1C12, 1, 0x1600),
        (0x1C13, 1, 0x1A00),
    ];
    for (index, sub, expected) in rows {
        assert_eq!(b.read(index, sub), expected, "CoE table 4-3: 0x{index:04X}:{sub}");
    }
    assert_eq!((b.read(0x1C12, 0), b.read(0x1C13, 0)), (1, 1), "CoE table 4-3");
    assert_eq!(b.net.slaves()[0].pdo_lengths(), (6, 10), "CoE 2.4");
}

fn pre_op() -> rt_core::ecat::Network {
    let mut net = Bench::unstarted(bench::drive_defaults());
    net.request_state(0, AlState::PreOp).unwrap();
    net
}

/// CoE 2.4, table 4-15: mapping rules, checked on the way to SafeOp or refused by the mailbox.
#[test]
fn pdo_mapping_validation() {
    let write = |net: &mut rt_core::ecat::Network, index: u16, sub: u8, v: u32| {
        let len = if sub == 0 { 1 } else { 4 };
        net.sdo_write(0, index, sub, &v.to_le_bytes()[..len])
    };
    // CoE 2.4: mapping objects are written with the SyncManager assignment off.
    let mut net = pre_op();
    assert_eq!(abort(write(&mut net, 0x1600, 1, 0x6060_0008)), SdoAbort::DeviceState, "assignment still on");
    net.sdo_write(0, 0x1C12, 0, &[0]).unwrap();
    write(&mut net, 0x1600, 0, 0).unwrap();
    // CoE 2.4: at most 7 entries.
    assert_eq!(abort(write(&mut net, 0x1600, 0, 8)), SdoAbort::ValueTooHigh, "0x1600:00 = 8");
    assert_eq!(abort(write(&mut net, 0x1600, 8, 0x6060_0008)), SdoAbort::NoSubIndex, "no entry 8");

    // Refused on PreOp -> SafeOp, one case per row: (entries, AL status code, what).
    let cases: [(&[u32], u16, &str); 6] = [
        (&[0x6063_0020], 0x0025, "CoE table 4-15: 0x6063 is not mappable"),
        (&[0x607C_0020], 0x0025, "CoE table 4-15: 0x607C is not mappable"),
        (&[0x60FC_0020], 0x0025, "CoE table 4-15: 0x60FC is not mappable"),
        (&[0x6040_0020], 0x0025, "length does not match the object's type"),
        (&[0x6041_0010], 0x0025, "a read-only object cannot be an output"),
        (
            &[0x607A_0020, 0x60FF_0020, 0x60FE_0120, 0x60FE_0220, 0x60B8_0010, 0x6071_0010, 0x6040_0010],
            0x0025,
            "CoE 2.4: 22 bytes > 20",
        ),
    ];
    for (entries, code, what) in cases {
        let mut net = pre_op();
        net.sdo_write(0, 0x1C12, 0, &[0]).unwrap();
        write(&mut net, 0x1600, 0, 0).unwrap();
        for (i, e) in entries.iter().enumerate() {
            write(&mut net, 0x1600, i as u8 + 1, *e).unwrap();
        }
        write(&mut net, 0x1600, 0, entries.len() as u32).unwrap();
        net.sdo_write(0, 0x1C12, 0, &[1]).unwrap();
        net.sdo_write(0, 0x1C32, 1, &0u16.to_le_bytes()).unwrap();
        let refused = net.request_state(0, AlState::SafeOp);
        assert_eq!(refused.map_err(|c| c.code()), Err(code), "{what}");
        assert_eq!(net.state(), AlState::PreOp, "{what}: stays in PreOp");
    }

    // CoE 2.4: after SafeOp, mapping writes are refused.
    let mut b = Bench::new();
    assert_eq!(abort(b.try_write(0x1C12, 0, 0)), SdoAbort::DeviceState, "CoE 2.4: in Op");
    assert_eq!(abort(b.try_write(0x1600, 1, 0x6060_0008)), SdoAbort::DeviceState, "CoE 2.4: in Op");
}

/// The OMRON homing example's mapping (tables 5-1, 5-2) is valid: 9 and 17 bytes.
#[test]
fn a_custom_mapping_from_the_machine_file() {
    let axis = AxisConfig {
        rx_pdo: Some(vec![0x6040_0010, 0x60B8_0010, 0x6060_0008, 0x607A_0020]),
        tx_pdo: Some(vec![0x6041_0010, 0x60BA_0020, 0x60FD_0020, 0x60B9_0010, 0x6061_0008, 0x6064_0020]),
        ..bench::drive_defaults()
    };
    let b = Bench::with(axis);
    assert_eq!(b.net.slaves()[0].pdo_lengths(), (9, 17));
    assert_eq!(b.read(0x1600, 0), 4);
    assert!(b.net.output_field(0, 0x6060, 0).is_some());
}

/// CoE 2.3: in SafeOp inputs update but outputs are not applied; in Op both.
#[test]
fn safe_op_has_inputs_only() {
    let mut b = Bench::new();
    b.net.request_state(0, AlState::SafeOp).unwrap();
    b.cw(0x0006);
    b.cycles(2);
    assert_eq!(b.sw() & 0x4F, 0x40, "the PDO controlword is not applied in SafeOp");
    b.write(0x6040, 0, 0x0006);
    b.cycles(2);
    assert_eq!(b.sw() & 0x6F, 0x21, "inputs still update: Ready to switch on");
    b.net.request_state(0, AlState::Op).unwrap();
    b.cw(0x0007);
    b.cycles(2);
    assert_eq!(b.sw() & 0x6F, 0x23, "in Op the PDO controlword applies: Switched on");
}

/// CoE 2.5, table 4-4: sync type and DC cycle.
#[test]
fn sync_settings() {
    let mut net = pre_op();
    let w16 = |net: &mut rt_core::ecat::Network, i: u16, s: u8, v: u16| net.sdo_write(0, i, s, &v.to_le_bytes());
    let w32 = |net: &mut rt_core::ecat::Network, i: u16, s: u8, v: u32| net.sdo_write(0, i, s, &v.to_le_bytes());
    assert!(w16(&mut net, 0x1C32, 1, 0).is_ok(), "CoE table 4-4: free run");
    assert!(w16(&mut net, 0x1C32, 1, 2).is_ok(), "CoE table 4-4: DC");
    assert_eq!(abort(w16(&mut net, 0x1C32, 1, 1)), SdoAbort::ValueRange, "type 1 (SM sync) is not offered");
    assert_eq!(abort(w16(&mut net, 0x1C33, 1, 0)), SdoAbort::ReadOnly, "CoE table 4-4: 0x1C33:01 read-only");
    for us in [250u32, 500, 1000, 2000, 4000] {
        assert!(w32(&mut net, 0x1C32, 2, us * 1000).is_ok(), "CoE 2.5: {us} us");
    }
    for ns in [750_000u32, 8_000_000, 125_000] {
        assert_eq!(abort(w32(&mut net, 0x1C32, 2, ns)), SdoAbort::ValueRange, "CoE 2.5: {ns} ns");
    }
    // CoE 2.5: DC needs ESC 0x0980 = 0x0300; without it SafeOp is refused.
    assert_eq!(net.request_state(0, AlState::SafeOp).map_err(|c| c.code()), Err(0x0030));
    assert_eq!(net.slaves()[0].sync_activation(), 0x0000, "free run until the master activates SYNC0");
}

/// CoE tables 4-1, 4-15: ranges and access (SDO abort codes).
#[test]
fn ranges_and_access() {
    let mut b = Bench::new();
    let gain = |v: f32| v.to_bits() as i64;
    assert_eq!(abort(b.try_write(0x2050, 0, gain(20.0))), SdoAbort::ValueTooHigh, "CoE table 4-15: 0x2050 max 10");
    assert_eq!(abort(b.try_write(0x2050, 0, gain(0.001))), SdoAbort::ValueTooLow, "CoE table 4-15: min 0.01");
    assert_eq!(abort(b.try_write(0x6071, 0, 1001)), SdoAbort::ValueTooHigh, "CoE table 4-15");
    assert_eq!(abort(b.try_write(0x6071, 0, -1001)), SdoAbort::ValueTooLow, "CoE table 4-15");
    assert_eq!(abort(b.try_write(0x6060, 0, 11)), SdoAbort::ValueTooHigh, "CoE table 4-15: mode 11");
    assert_eq!(abort(b.try_write(0x2004, 1, 0)), SdoAbort::ValueTooLow, "CoE table 4-15: gear numerator");
    for index in [0x6041, 0x6064, 0x6063, 0x1000, 0x2000] {
        assert_eq!(abort(b.try_write(index, 0, 0)), SdoAbort::ReadOnly, "CoE tables 4-1, 4-15: 0x{index:04X}");
    }
    assert_eq!(abort(b.net.sdo_read(0, 0x60BC, 0)), SdoAbort::NoObject, "CoE 3.9: no TP2");
    assert_eq!(abort(b.net.sdo_read(0, 0x60BD, 0)), SdoAbort::NoObject, "CoE 3.9");
    assert_eq!(abort(b.net.sdo_write(0, 0x607A, 0, &[1, 2])), SdoAbort::LengthTooLow, "length mismatch");
}

/// CoE table 4-1: store parameters only in Switch on disabled, with the "save" signature.
#[test]
fn store_parameters() {
    let mut b = Bench::new();
    b.cw(0);
    assert!(b.try_write(0x1010, 1, 0x1234).is_ok(), "another value is ignored");
    assert_eq!(b.read(0x1010, 1), 0);
    b.write(0x1010, 1, 0x6576_6173);
    assert_eq!(b.read(0x1010, 1), 1, "reads back 1");
    let mut b = Bench::new();
    b.enable();
    assert_eq!(abort(b.try_write(0x1010, 1, 0x6576_6173)), SdoAbort::DeviceState, "not in Operation enabled");
}

/// CoE table 4-15: outputs O1..O5 need the mask bit; the brake only when not energised.
#[test]
fn digital_outputs_and_brake() {
    let mut b = Bench::new();
    b.write(0x60FE, 1, 0x0002_0000);
    b.cycle();
    assert_eq!(b.drive().outputs() & 0x0002_0000, 0, "CoE table 4-15: without the mask bit O1 stays off");
    b.write(0x60FE, 2, 0x0002_0000);
    b.cycle();
    assert_ne!(b.drive().outputs() & 0x0002_0000, 0, "CoE table 4-15: O1 on");
    // Brake, bit 16 (1 = released): the host may release it while not energised.
    b.write(0x60FE, 2, 0x0001_0000);
    b.write(0x60FE, 1, 0x0000_0000);
    b.cycle();
    assert_eq!(b.drive().outputs() & 0x0001_0000, 0, "locked");
    b.enable();
    assert_ne!(
        b.drive().outputs() & 0x0001_0000,
        0,
        "CoE table 4-15: energised, the brake is released whatever bit 16 says"
    );
}

/// CoE tables 4-13, 4-14, 4-16: a simulated fault sets 0x603F and its event bit.
#[test]
fn fault_codes_and_event_bits() {
    let rows: [(DriveModel, u16, u16, u8, bool, &str); 5] = [
        (DriveModel::D1, 0x3110, 0x2100, 19, true, "over voltage"),
        (DriveModel::D2, 0xFF03, 0x2101, 7, true, "STO"),
        (DriveModel::D1, 0xFF03, 0x2101, 7, false, "no STO on D1COE"),
        (DriveModel::D1N, 0xFF04, 0x2100, 9, true, "HFLT on D1-N: 0x2100 bit 9"),
        (DriveModel::D1, 0xFF04, 0x2101, 17, true, "HFLT on D1: 0x2101 bit 17"),
    ];
    for (model, code, events, bit, supported, what) in rows {
        let mut b = Bench::with(AxisConfig { drive: model, ..bench::drive_defaults() });
        b.enable();
        let injected = b.net.inject_fault(0, code);
        assert_eq!(injected.is_ok(), supported, "{what}");
        if supported {
            b.cycles(2);
            assert_eq!(b.read(0x603F, 0), code as i64, "{what}");
            assert_ne!(b.read(events, 0) & (1 << bit), 0, "{what}");
            assert_eq!(b.sw() & 0x4F, 0x08, "{what}: Fault");
        }
    }
}

/// The SDO downloads that assign the second TxPDO beside the first, as bytes on the wire
/// (CoE 2.4 steps 2-4 with 0x1A01; docs/decisions.md, "Second PDO").
const ASSIGN_TOUCH_PROBE_PDO: [(u16, u8, &[u8]); 7] = [
    (0x1C13, 0, &[0x00]),
    (0x1A01, 1, &[0x10, 0x00, 0xB9, 0x60]),
    (0x1A01, 2, &[0x20, 0x00, 0xBA, 0x60]),
    (0x1A01, 0, &[0x02]),
    (0x1C13, 1, &[0x00, 0x1A]),
    (0x1C13, 2, &[0x01, 0x1A]),
    (0x1C13, 0, &[0x02]),
];

/// Slave `slave` of `net` in PreOp with 0x1A00 and 0x1A01 (0x60B9, 0x60BA) assigned.
fn assign_touch_probe_pdo(net: &mut rt_core::ecat::Network, slave: usize) {
    net.request_state(slave, AlState::PreOp).unwrap();
    for (index, sub, data) in ASSIGN_TOUCH_PROBE_PDO {
        net.sdo_write(slave, index, sub, data).unwrap_or_else(|e| panic!("0x{index:04X}:{sub}: {e}"));
    }
}

/// An axis 1.5 mm from zero at 10 000 counts/mm, with the drive's default mapping.
fn at_15000_counts() -> AxisConfig {
    let travel = rt_core::config::TravelConfig { start_position: 1.5, ..Default::default() };
    AxisConfig { counts_per_unit: bench::CPU, travel, ..bench::drive_defaults() }
}

/// CoE 2.4 with a second TxPDO: 0x1C13 = {0x1A00, 0x1A01}; the master lays the inputs out
/// from the assignment and both mappings, the touch probe after the default objects.
#[test]
fn a_second_txpdo_carries_the_touch_probe() {
    let mut net = Bench::unstarted(at_15000_counts());
    assign_touch_probe_pdo(&mut net, 0);
    assert_eq!(net.sdo_read(0, 0x1C13, 2), Ok((0x1A01, 2)), "the assignment reads back");
    net.sdo_write(0, 0x60B8, 0, &[0x01, 0x00]).unwrap();
    net.start(PERIOD_NS).expect("start-up to Op");
    assert_eq!(net.slaves()[0].pdo_lengths(), (6, 16), "10 bytes of 0x1A00, 6 of 0x1A01");
    let status = net.input_field(0, 0x60B9, 0).expect("0x60B9 mapped");
    assert!(net.input_field(0, 0x60BB, 0).is_none(), "0x60BB is not mapped");
    net.exchange(bench::PERIOD_S);
    let (inputs, _) = net.images_mut();
    #[rustfmt::skip]
    let expected: [u8; 16] = [
        0x40, 0x02,             // 0x6041 statusword: Switch on disabled, remote
        0x98, 0x3A, 0x00, 0x00, // 0x6064 position actual: 15000
        0x00, 0x00, 0x00, 0x00, // 0x60F4 following error: 0
        0x01, 0x00,             // 0x60B9 touch probe status: TP1 enabled
        0x00, 0x00, 0x00, 0x00, // 0x60BA TP1 positive edge: none yet
    ];
    assert_eq!(inputs, expected);
    assert_eq!(status.read(inputs), 1);
}

/// The rules of the assignment and of the second mapping (CoE 2.4; docs/decisions.md,
/// "Second PDO"): one PDO twice, a mapping changed while assigned, a third PDO.
#[test]
fn assignment_rules_of_the_second_pdo() {
    let mut net = pre_op();
    assert_eq!(abort(net.sdo_write(0, 0x1C13, 0, &[0x03])), SdoAbort::ValueTooHigh, "two TxPDOs at most");
    assert_eq!(abort(net.sdo_write(0, 0x1C13, 2, &[0x02, 0x1A])), SdoAbort::ValueTooHigh, "no 0x1A02");
    assert_eq!(abort(net.sdo_write(0, 0x1C12, 2, &[0x00, 0x1A])), SdoAbort::ValueTooHigh, "a TxPDO as output");
    assign_touch_probe_pdo(&mut net, 0);
    let mapping = net.sdo_write(0, 0x1A01, 1, &[0x20, 0x00, 0xBB, 0x60]);
    assert_eq!(abort(mapping), SdoAbort::DeviceState, "0x1A01 changed while assigned");

    net.sdo_write(0, 0x1C13, 0, &[0x00]).unwrap();
    net.sdo_write(0, 0x1C13, 2, &[0x00, 0x1A]).unwrap();
    net.sdo_write(0, 0x1C13, 0, &[0x02]).unwrap();
    net.sdo_write(0, 0x1C32, 1, &[0x00, 0x00]).unwrap();
    let refused = net.request_state(0, AlState::SafeOp).map_err(|c| c.code());
    assert_eq!(refused, Err(0x0024), "0x1A00 assigned twice: invalid input mapping");
    assert_eq!(net.state(), AlState::PreOp);
}

/// The process image of two slaves: each one's part after the one before it in ring
/// order, every offset from the mappings the master read back.
#[test]
fn the_process_image_of_two_slaves() {
    let mut net = rt_core::ecat::Network::new(&[at_15000_counts(), bench::drive_defaults()]);
    assign_touch_probe_pdo(&mut net, 0);
    net.start(PERIOD_NS).expect("start-up to Op");
    let (rx, tx) = net.image_entries(0);
    let offsets = |entries: &[rt_core::ecat::network::ImageEntry]| {
        entries.iter().map(|e| (e.index, e.sub, e.offset)).collect::<Vec<_>>()
    };
    assert_eq!(offsets(rx), [(0x6040, 0, 0), (0x607A, 0, 2)]);
    assert_eq!(offsets(tx), [(0x6041, 0, 0), (0x6064, 0, 2), (0x60F4, 0, 6), (0x60B9, 0, 10), (0x60BA, 0, 12)]);
    let controlword = net.output_field(1, 0x6040, 0).expect("slave 1's controlword");
    let target = net.output_field(1, 0x607A, 0).expect("slave 1's target");
    net.exchange(bench::PERIOD_S);
    let (inputs, outputs) = net.images_mut();
    controlword.write(outputs, 0x0006);
    target.write(outputs, -2);
    assert_eq!(outputs, [0, 0, 0, 0, 0, 0, 0x06, 0x00, 0xFE, 0xFF, 0xFF, 0xFF], "slave 1's outputs from byte 6");
    #[rustfmt::skip]
    let expected: [u8; 26] = [
        0x40, 0x02, 0x98, 0x3A, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x40, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, // slave 1 from byte 16
    ];
    assert_eq!(inputs, expected);
}

/// Programs see the second TxPDO too: the snapshot holds both PDOs of a direction, so
/// `ReadPDO` (HMPL 17.3) finds the touch probe's objects mapped by 0x1A01.
#[test]
fn the_snapshot_shows_the_second_pdo_to_programs() {
    use api::QueryCall;
    use calls::query::{Value, evaluate};
    // The built-in machine's TxPDO: 0x1A00 full (7 entries, 19 bytes); 0x1A01 as assigned
    // here through SDO, not the master's touch probe mapping.
    let full = AxisConfig { counts_per_unit: bench::CPU, touch_probe_pdo: false, ..AxisConfig::default() };
    let mut net = Bench::unstarted(AxisConfig { travel: at_15000_counts().travel, ..full });
    assign_touch_probe_pdo(&mut net, 0);
    net.sdo_write(0, 0x60B8, 0, &[0x01, 0x00]).unwrap();
    net.start(PERIOD_NS).expect("start-up to Op");
    net.exchange(bench::PERIOD_S);
    let mut snapshot: Box<schema::Snapshot> = Box::default();
    rt_core::master::describe_slaves(&net, &mut snapshot);
    rt_core::master::update_slaves(&net, &mut snapshot);
    assert_eq!(snapshot.slaves[0].tx_count, 9, "7 entries of 0x1A00, 2 of 0x1A01");
    let read = |index, sub| match evaluate(
        &QueryCall::ReadPDO { slv_id: 0, obj_index: index, obj_subindex: sub },
        &snapshot,
    ) {
        Ok(answer) => answer.0,
        Err(e) => panic!("ReadPDO 0x{index:04X}: {e:?}"),
    };
    assert_eq!(read(0x6064, 0), Value::Int(15000), "0x1A00: position actual");
    assert_eq!(read(0x60B9, 0), Value::Int(1), "0x1A01: touch probe status, TP1 enabled");
    assert_eq!(read(0x60BA, 0), Value::Int(0), "0x1A01: no positive edge yet");
    assert_eq!(read(0x60BB, 0), Value::Int(-1), "not mapped");
}

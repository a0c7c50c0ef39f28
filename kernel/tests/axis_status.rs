//! HMPL tables 5.1.1.4 and 5.1.1.5 on a running kernel: the `motion_status` and `fault_status` words
//! an axis publishes, as the byte literals of HMPL tables 5.1.1.4 and 5.1.1.5, in the
//! situations that set each bit (Acc, Homing and HomeSwitch pass too fast or need a
//! switch; their Lua checks cover them through IsAcc/IsHoming/IsHomeSwitch).

use config::MachineConfig;
use devices::ecat::Network;
use kernel::Kernel;

struct Rig {
    network: Network,
    kernel: Kernel,
    cycle: u64,
}

impl Rig {
    fn new() -> Self {
        let config = MachineConfig::default();
        let mut network = Network::new(&config.axes);
        network.start(config.period_ns()).unwrap();
        let kernel = Kernel::new(&config, &network);
        Rig { network, kernel, cycle: 0 }
    }

    fn cycles(&mut self, n: usize) {
        for _ in 0..n {
            self.cycle += 1;
            self.network.exchange(1e-3);
            self.kernel.step(self.cycle, &mut self.network);
        }
    }

    fn until(&mut self, what: &str, f: impl Fn(&Kernel) -> bool) {
        for _ in 0..10_000 {
            if f(&self.kernel) {
                return;
            }
            self.cycles(1);
        }
        panic!("never: {what}");
    }

    /// (motion_status, fault_status) of axis `a`.
    fn status(&self, a: usize) -> (u32, u32) {
        let s = self.kernel.axis_snapshot(a);
        (s.motion_status, s.fault_status)
    }
}

#[test]
fn status_words_as_the_tables_give_them() {
    let mut rig = Rig::new();
    assert_eq!(rig.status(0), (0x0000, 0x00), "a fresh axis: nothing set");

    rig.kernel.enable(0).unwrap();
    rig.until("in position", |k| k.axis_snapshot(0).motion_status & 0x4 != 0);
    assert_eq!(rig.status(0), (0x0005, 0x00), "Enabled | InPos");

    rig.kernel.axis_mut(0).unwrap().move_abs(50.0).unwrap();
    rig.cycles(10);
    assert_eq!(rig.status(0), (0x0403, 0x00), "Enabled | Moving | Acc");
    rig.until("cruising", |k| k.axes()[0].reference().vel >= 100.0);
    rig.cycles(1);
    assert_eq!(rig.status(0), (0x0003, 0x00), "Enabled | Moving at constant velocity");

    rig.kernel.axis_mut(0).unwrap().home_state_mut().set_homed(true);
    rig.until("settled", |k| !k.axes()[0].is_moving());
    rig.cycles(20);
    assert_eq!(rig.status(0), (0x0805, 0x00), "Enabled | InPos | Homed");
    rig.kernel.axis_mut(0).unwrap().home_state_mut().set_homed(false);

    // Gear: the slave is Sync and Gear (bits 3 and 8); the master shows neither.
    rig.kernel.enable(1).unwrap();
    rig.until("axis 1 in position", |k| k.axis_snapshot(1).motion_status & 0x4 != 0);
    rig.kernel.enable_gear(0, 1).unwrap();
    rig.cycles(1);
    assert_eq!(rig.status(1), (0x010D, 0x00), "Enabled | InPos | Sync | Gear");
    assert_eq!(rig.status(0), (0x0005, 0x00), "the master");
    rig.kernel.disable_gear(1).unwrap();

    // Software right limit: ErrorStop | SWRL; the axis stays enabled.
    rig.kernel.axis_mut(0).unwrap().set_swrl(60.0).unwrap();
    rig.kernel.axis_mut(0).unwrap().move_abs(100.0).unwrap();
    rig.until("stopped at the limit", |k| k.axes()[0].is_error_stop() && !k.axes()[0].is_moving());
    let (motion, fault) = rig.status(0);
    assert_eq!(fault, 0x21, "ErrorStop | SWRL");
    assert_eq!(motion & 0x0003, 0x0001, "still enabled, no longer moving");

    // A drive fault: ErrorStop | DriveFault, disabled.
    rig.kernel.enable(2).unwrap();
    rig.until("axis 2 enabled", |k| k.axes()[2].is_enabled());
    rig.network.inject_fault(2, 0x2310).unwrap();
    rig.until("axis 2 disabled", |k| !k.axes()[2].is_enabled());
    rig.cycles(5);
    assert_eq!(rig.status(2), (0x0000, 0x03), "ErrorStop | DriveFault");

    // Gantry: axes 2 and 3 after Reset, while disabled.
    rig.kernel.axis_mut(2).unwrap().reset().unwrap();
    rig.until("fault gone", |k| k.axis_snapshot(2).fault_status == 0);
    rig.kernel.enable_gantry_pair(2, 3).unwrap();
    rig.kernel.enable(3).unwrap();
    rig.until("pair in position", |k| k.axis_snapshot(2).motion_status & 0x4 != 0);
    assert_eq!(rig.status(2), (0x0025, 0x00), "Enabled | InPos | Gantry");
    assert_eq!(rig.status(3).0 & 0x0020, 0x0020, "both axes Gantry");
}

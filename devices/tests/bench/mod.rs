//! A one-slave test bench: a network brought to Op by the master's start-up, with the
//! default PDO mapping (controlword and target position out; statusword, position actual
//! and following error in). Other objects go through SDO, as on a real drive.

#![allow(dead_code)]

use config::{AxisConfig, TravelConfig};
use devices::drive::Drive;
use devices::ecat::{Field, Network};

pub const PERIOD_NS: u64 = 1_000_000;
pub const PERIOD_S: f64 = 1e-3;
/// Counts per mm of the bench's axis.
pub const CPU: f64 = 10_000.0;

pub struct Bench {
    pub net: Network,
    controlword: Option<Field>,
    target: Option<Field>,
    statusword: Option<Field>,
}

/// An axis whose drive keeps its default PDO mapping (CoE manual table 4-3).
pub fn drive_defaults() -> AxisConfig {
    AxisConfig { rx_pdo: None, tx_pdo: None, touch_probe_pdo: false, ..AxisConfig::default() }
}

impl Bench {
    pub fn new() -> Self {
        Self::with(AxisConfig { counts_per_unit: CPU, ..drive_defaults() })
    }

    pub fn with_travel(travel: TravelConfig) -> Self {
        Self::with(AxisConfig { counts_per_unit: CPU, travel, ..drive_defaults() })
    }

    /// A network of one slave, not yet started (in Init).
    pub fn unstarted(axis: AxisConfig) -> Network {
        Network::new(&[axis])
    }

    pub fn with(axis: AxisConfig) -> Self {
        let mut net = Network::new(&[axis]);
        net.start(PERIOD_NS).expect("start-up to Op");
        let controlword = net.output_field(0, 0x6040, 0);
        let target = net.output_field(0, 0x607A, 0);
        let statusword = net.input_field(0, 0x6041, 0);
        let mut bench = Bench { net, controlword, target, statusword };
        bench.cycle();
        bench
    }

    pub fn drive(&self) -> &Drive {
        self.net.slaves()[0].device_as::<Drive>().expect("slave 0 is a drive")
    }

    pub fn cycle(&mut self) {
        self.net.exchange(PERIOD_S);
    }

    pub fn cycles(&mut self, n: usize) {
        for _ in 0..n {
            self.cycle();
        }
    }

    /// Runs until `f` holds, at most `max` cycles; whether it held.
    pub fn until(&mut self, max: usize, mut f: impl FnMut(&Bench) -> bool) -> bool {
        for _ in 0..max {
            if f(self) {
                return true;
            }
            self.cycle();
        }
        f(self)
    }

    /// Writes the controlword into the RxPDO and runs one cycle.
    pub fn cw(&mut self, value: u16) {
        let (_, outputs) = self.net.images_mut();
        self.controlword.expect("0x6040 mapped").write(outputs, value as i64);
        self.cycle();
    }

    pub fn set_target(&mut self, counts: i64) {
        let (_, outputs) = self.net.images_mut();
        self.target.expect("0x607A mapped").write(outputs, counts);
    }

    /// The statusword from the TxPDO.
    pub fn sw(&mut self) -> u16 {
        let (inputs, _) = self.net.images_mut();
        self.statusword.expect("0x6041 mapped").read(inputs) as u16
    }

    /// An SDO upload, as a number (REAL32 objects come as their bits).
    pub fn read(&self, index: u16, sub: u8) -> i64 {
        self.net.sdo_read_local(0, index, sub).unwrap_or_else(|e| panic!("read 0x{index:04X}:{sub}: {e}")).0
    }

    /// An SDO download of `value` with the object's own length.
    pub fn write(&mut self, index: u16, sub: u8, value: i64) {
        self.try_write(index, sub, value).unwrap_or_else(|e| panic!("write 0x{index:04X}:{sub} = {value}: {e}"));
    }

    pub fn try_write(&mut self, index: u16, sub: u8, value: i64) -> Result<(), devices::ecat::SdoError> {
        let bytes = self.net.slaves()[0].sdo_describe(index, sub).map_or(4, |d| d.ty.bytes());
        self.net.sdo_write(0, index, sub, &value.to_le_bytes()[..bytes])
    }

    /// Walks the FSA to Operation enabled (0x06, 0x07, 0x0F), holding the target on the
    /// actual position so that a position mode does not jump.
    pub fn enable(&mut self) {
        let actual = self.read(0x6064, 0);
        self.set_target(actual);
        for cw in [0x0006, 0x0007, 0x000F] {
            self.cw(cw);
        }
        assert_eq!(self.sw() & 0x6F, 0x27, "Operation enabled");
    }

    /// Position actual value (0x6064), counts.
    pub fn position(&self) -> i64 {
        self.read(0x6064, 0)
    }

    /// The motor's raw position (machine coordinates), counts.
    pub fn raw(&self) -> f64 {
        self.drive().raw_position()
    }
}

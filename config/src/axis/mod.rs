//! `[[axes]]`: an axis, its drive and what stands along its travel. Its tables
//! `[axes.plant]`, `[axes.travel]` and `[axes.drive_settings]` have files of their own.

mod drive;
mod plant;
mod travel;

pub use drive::{DriveModel, DriveSettings, TouchProbeKind};
pub use plant::{MAX_LOAD_FREQUENCY_HZ, PlantConfig};
pub use travel::TravelConfig;

use serde::Deserialize;

use crate::error::{ConfigError, invalid, positive};

/// The mapping the master writes unless the machine file gives one: the objects the HMPL
/// functions use, within 7 entries and 20 bytes per PDO (CoE manual 2.4). Out:
/// controlword, target position, mode, target velocity, target torque (13 bytes). In:
/// statusword, position actual, following error, digital inputs, mode display, error
/// code, torque actual (19 bytes). This is the RxPDO half (0x1600), the 5 outputs.
pub const BUILT_IN_RX_PDO: [u32; 5] = [0x6040_0010, 0x607A_0020, 0x6060_0008, 0x60FF_0020, 0x6071_0010];
/// The TxPDO half of the built-in mapping (0x1A00): the 7 inputs listed above.
pub const BUILT_IN_TX_PDO: [u32; 7] =
    [0x6041_0010, 0x6064_0020, 0x60F4_0020, 0x60FD_0020, 0x6061_0008, 0x603F_0010, 0x6077_0010];

/// The user unit of an axis' positions: the machine file's `"mm"` or `"deg"`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Unit {
    /// A linear axis, in millimetres.
    Mm,
    /// A rotary axis, in degrees.
    Deg,
}

/// `[[axes]]`: one axis and its drive, the n-th entry being axis n of the API and slave n
/// on the bus.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AxisConfig {
    /// A name for the reader of the file; programs address the axis by its number.
    pub name: String,
    /// The drive family, which sets its product code and objects (CoE table 4-2, 4-22).
    pub drive: DriveModel,
    /// Millimetres or degrees: what `counts_per_unit` and every position are in.
    pub unit: Unit,
    /// Drive counts per mm (or per degree).
    pub counts_per_unit: f64,
    /// Highest profile velocity `SetVel` accepts (units/s).
    pub max_vel: f64,
    /// Highest acceleration or deceleration `SetAcc`/`SetDec` accept (units/s²).
    pub max_acc: f64,
    /// Profile velocity at start-up (units/s), at most `max_vel`; `SetVel` changes it.
    pub vel: f64,
    /// Profile acceleration at start-up (units/s²), at most `max_acc`.
    pub acc: f64,
    /// Profile deceleration at start-up (units/s²), at most `max_acc`.
    pub dec: f64,
    /// `[axes.plant]`: the simulated motor and load behind the drive.
    pub plant: PlantConfig,
    /// `[axes.travel]`: switches, index and hard stops along the travel.
    pub travel: TravelConfig,
    /// `[axes.drive_settings]`: the drive's parameters set outside its objects.
    pub drive_settings: DriveSettings,
    /// RxPDO mapping entries (`0xIIIISSLL`, outputs into 0x1600) the master writes in
    /// PreOp; by default the built-in mapping. `None` leaves the drive's defaults (CoE
    /// manual table 4-3).
    pub rx_pdo: Option<Vec<u32>>,
    /// TxPDO mapping entries (inputs into 0x1A00), as `rx_pdo`.
    pub tx_pdo: Option<Vec<u32>>,
    /// HMPL ch. 12: the drive has the position trigger (an E1-series drive with a digital
    /// encoder) and its PT output is wired to a controller GPO. None: no position trigger.
    pub pt: Option<PtConfig>,
    /// The master maps the touch probe (HMPL ch. 13) into the second PDOs: 0x60B8 into
    /// 0x1601 and `touch_probe_tx_pdo`'s objects into 0x1A01 (docs/decisions.md, "Touch probe").
    pub touch_probe_pdo: bool,
}

/// `[axes.pt]`: where the drive's position-trigger output is seen (docs/decisions.md,
/// "Position trigger").
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PtConfig {
    /// The controller GPO (1..8) that pulses.
    pub output: i64,
}

/// 0x1601: the touch probe function.
pub const TOUCH_PROBE_RX_PDO: [u32; 1] = [0x60B8_0010];

impl AxisConfig {
    /// 0x1A01 for the drive's touch probe: its status and the edge positions it has.
    pub fn touch_probe_tx_pdo(&self) -> &'static [u32] {
        match self.drive_settings.touch_probe {
            TouchProbeKind::Index => &[0x60B9_0010, 0x60BA_0020, 0x60BB_0020],
            TouchProbeKind::Cia402 => &[0x60B9_0010, 0x60BA_0020, 0x60BB_0020, 0x60BC_0020, 0x60BD_0020],
        }
    }
}

impl Default for AxisConfig {
    fn default() -> Self {
        AxisConfig {
            name: String::new(),
            drive: DriveModel::D1,
            unit: Unit::Mm,
            counts_per_unit: 10_000.0,
            max_vel: 2_000.0,
            max_acc: 50_000.0,
            vel: 100.0,
            acc: 1_000.0,
            dec: 1_000.0,
            plant: PlantConfig::default(),
            travel: TravelConfig::default(),
            drive_settings: DriveSettings::default(),
            rx_pdo: Some(BUILT_IN_RX_PDO.to_vec()),
            tx_pdo: Some(BUILT_IN_TX_PDO.to_vec()),
            pt: None,
            touch_probe_pdo: true,
        }
    }
}

impl AxisConfig {
    /// Checks the axis at `key` (`axes[i]`), its tables included.
    pub(crate) fn validate(&self, key: &str) -> Result<(), ConfigError> {
        positive(&format!("{key}.counts_per_unit"), self.counts_per_unit)?;
        if let Some(pt) = &self.pt
            && !(1..=schema::GPIO_PINS).contains(&pt.output)
        {
            return Err(invalid(format!("{key}.pt.output"), "a controller GPO, 1..8"));
        }
        positive(&format!("{key}.max_vel"), self.max_vel)?;
        positive(&format!("{key}.max_acc"), self.max_acc)?;
        for (name, value, max) in
            [("vel", self.vel, self.max_vel), ("acc", self.acc, self.max_acc), ("dec", self.dec, self.max_acc)]
        {
            positive(&format!("{key}.{name}"), value)?;
            if value > max {
                return Err(invalid(format!("{key}.{name}"), format!("{value} is above the axis limit {max}")));
            }
        }
        // A drive position is an INT32 count: keep one full turn of travel representable.
        if self.max_vel * self.counts_per_unit > i32::MAX as f64 {
            return Err(invalid(format!("{key}.max_vel"), "max_vel x counts_per_unit exceeds the drive's INT32 range"));
        }
        self.plant.validate(&format!("{key}.plant"))?;
        self.travel.validate(&format!("{key}.travel"), self.drive_settings.touch_probe)?;
        self.drive_settings.validate(&format!("{key}.drive_settings"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> AxisConfig {
        toml::from_str(text).unwrap()
    }

    /// The drive model is read by its CoE manual name (table 4-2) and carries its product code.
    #[test]
    fn drive_models_by_their_manual_names() {
        for (name, model, code) in [
            ("D1-N", DriveModel::D1N, 1),
            ("D1", DriveModel::D1, 2),
            ("D2", DriveModel::D2, 3),
            ("abily", DriveModel::Abily, 4),
        ] {
            let axis = parse(&format!("name = \"x\"\ndrive = \"{name}\"\n"));
            assert_eq!(axis.drive, model, "{name}");
            assert_eq!(model.product_code(), code, "{name}");
        }
        assert!(toml::from_str::<AxisConfig>("drive = \"D3\"\n").is_err(), "no D3 in table 4-2");
    }

    /// A probe input needs the CiA 402 touch probe (the CoE manual's drive latches the
    /// index only) and a window `[L, R]` with L <= R.
    #[test]
    fn probe_inputs_need_a_cia402_touch_probe() {
        let key = |text: &str| match parse(text).validate("axes[0]") {
            Err(ConfigError::Invalid { key, .. }) => key,
            other => panic!("{text}: {other:?}"),
        };
        let index_only = "travel = { probe_input_1 = [1.0, 2.0] }\n";
        assert_eq!(key(index_only), "axes[0].travel.probe_input_1");
        let reversed = "travel = { probe_input_2 = [2.0, 1.0] }\ndrive_settings = { touch_probe = \"cia402\" }\n";
        assert_eq!(key(reversed), "axes[0].travel.probe_input_2");
        let good = "travel = { probe_input_2 = [1.0, 2.0] }\ndrive_settings = { touch_probe = \"cia402\" }\n";
        assert!(parse(good).validate("axes[0]").is_ok());
        assert_eq!(parse(good).touch_probe_tx_pdo().len(), 5, "0x60B9, 0x60BA..0x60BD");
    }
}

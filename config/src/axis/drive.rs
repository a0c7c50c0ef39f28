//! The drive behind an axis: its model (CoE table 4-2) and `[axes.drive_settings]`.

use serde::Deserialize;

use crate::error::{ConfigError, positive};

/// Drive families of the HIWIN CoE manual, with their product codes (CoE table 4-2).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
pub enum DriveModel {
    /// D1-N (`"D1-N"` in the machine file), product code 1.
    #[serde(rename = "D1-N")]
    D1N,
    /// D1, product code 2.
    D1,
    /// D2, product code 3.
    D2,
    /// abily (`"abily"`), product code 4: above the table's printed maximum 3, it reports
    /// D1COE's objects (docs/drive.md).
    #[serde(rename = "abily")]
    Abily,
}

impl DriveModel {
    /// The product code in 0x1018:02 (CoE table 4-2), by which the master tells models
    /// apart.
    pub fn product_code(self) -> u32 {
        match self {
            DriveModel::D1N => 1,
            DriveModel::D1 => 2,
            DriveModel::D2 => 3,
            DriveModel::Abily => 4,
        }
    }
}

/// Which touch probe the drive has (docs/decisions.md, "Touch probe").
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum TouchProbeKind {
    /// CoE manual 3.9: touch probe 1 on the encoder index only; 0x60BC/0x60BD do not exist.
    #[default]
    Index,
    /// The CiA 402 touch probe: probes 1 and 2, each on its own probe input or the index
    /// (0x60B8 bits 2-3 and 10-11), with 0x60BC/0x60BD.
    Cia402,
}

/// Drive parameters set with HIWIN's Lightening tool rather than through objects.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DriveSettings {
    /// Hard-stop homing (methods -1, -2, -4, -5): the current that means "at the stop",
    /// in % of rated current, held for `end_stop_time_ms`.
    pub end_stop_current_pct: f64,
    /// Hard-stop homing: how long, in ms, the current must stay above
    /// `end_stop_current_pct` before the drive takes it for the stop.
    pub end_stop_time_ms: f64,
    /// Methods -4/-5: distance from the hard stop to home, counts.
    pub end_stop_offset: i64,
    /// A multi-turn absolute encoder (method -3).
    pub multi_turn_absolute: bool,
    /// Motor rated current, A (0x6075 in mA): the unit of torque and current feedback.
    pub rated_current_a: f64,
    /// Motor force (torque) constant, N/A (N·m/A): converts a force into per mille of
    /// rated current in the torque modes.
    pub force_constant: f64,
    /// Outputs O1..O5 configured as general purpose ("PDL usage"), bit 0 = O1.
    pub general_purpose_outputs: u8,
    /// The drive's touch probe: the CoE manual's (index) or the CiA 402 one.
    pub touch_probe: TouchProbeKind,
}

impl Default for DriveSettings {
    fn default() -> Self {
        DriveSettings {
            end_stop_current_pct: 80.0,
            end_stop_time_ms: 20.0,
            end_stop_offset: 1000,
            multi_turn_absolute: false,
            rated_current_a: 2.0,
            force_constant: 10.0,
            general_purpose_outputs: 0b1_1111,
            touch_probe: TouchProbeKind::Index,
        }
    }
}

impl DriveSettings {
    /// Checks the table at `key` (`axes[i].drive_settings`).
    pub(crate) fn validate(&self, key: &str) -> Result<(), ConfigError> {
        positive(&format!("{key}.rated_current_a"), self.rated_current_a)?;
        positive(&format!("{key}.force_constant"), self.force_constant)?;
        positive(&format!("{key}.end_stop_current_pct"), self.end_stop_current_pct)?;
        positive(&format!("{key}.end_stop_time_ms"), self.end_stop_time_ms)
    }
}

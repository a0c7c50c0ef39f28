//! `[axes.travel]`: switches, index and hard stops along an axis' travel.

use serde::Deserialize;

use super::drive::TouchProbeKind;
use crate::error::{ConfigError, invalid, positive};

/// Switches, index and hard stops along the travel, in units (mm or deg) of the machine's
/// own coordinates. Absent ones do not exist.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TravelConfig {
    /// The negative limit switch: active at and below this position (0x60FD bit 0).
    pub negative_limit: Option<f64>,
    /// The positive limit switch: active at and above this position (0x60FD bit 1).
    pub positive_limit: Option<f64>,
    /// The home switch is active over `[L, R]`.
    pub home_switch: Option<[f64; 2]>,
    /// Distance between encoder index pulses (one motor turn); none: no index.
    pub index_pitch: Option<f64>,
    /// Where one index pulse lies; the others follow every `index_pitch` from it.
    pub index_offset: f64,
    /// The mechanical end below which the axis cannot move (hard-stop homing pushes on
    /// it).
    pub negative_hard_stop: Option<f64>,
    /// The mechanical end above which the axis cannot move.
    pub positive_hard_stop: Option<f64>,
    /// Where the motor stands at power-up.
    pub start_position: f64,
    /// The drive's touch probe input 1 (a `cia402` touch probe only): a sensor active
    /// over `[L, R]`, like the home switch.
    pub probe_input_1: Option<[f64; 2]>,
    /// Touch probe input 2, as `probe_input_1`.
    pub probe_input_2: Option<[f64; 2]>,
}

impl TravelConfig {
    /// The built-in machine: limit switches at ±1000 mm, hard stops 10 mm beyond them, a
    /// home switch at [-10, -5] mm and an index every 10 mm (a 10 mm screw).
    pub fn built_in() -> Self {
        TravelConfig {
            negative_limit: Some(-1000.0),
            positive_limit: Some(1000.0),
            home_switch: Some([-10.0, -5.0]),
            index_pitch: Some(10.0),
            index_offset: 0.0,
            negative_hard_stop: Some(-1010.0),
            positive_hard_stop: Some(1010.0),
            start_position: 0.0,
            probe_input_1: None,
            probe_input_2: None,
        }
    }
}

impl TravelConfig {
    /// Checks the table at `key` (`axes[i].travel`) of an axis whose drive has `probe`.
    pub(crate) fn validate(&self, key: &str, probe: TouchProbeKind) -> Result<(), ConfigError> {
        if let (Some(n), Some(p)) = (self.negative_limit, self.positive_limit)
            && n >= p
        {
            return Err(invalid(key, "negative_limit must be below positive_limit"));
        }
        if let Some([l, r]) = self.home_switch
            && l > r
        {
            return Err(invalid(format!("{key}.home_switch"), "[L, R] with L <= R"));
        }
        for (name, input) in [("probe_input_1", self.probe_input_1), ("probe_input_2", self.probe_input_2)] {
            let Some([l, r]) = input else { continue };
            if !l.is_finite() || !r.is_finite() || l > r {
                return Err(invalid(format!("{key}.{name}"), "[L, R] with L <= R"));
            }
            if probe != TouchProbeKind::Cia402 {
                return Err(invalid(
                    format!("{key}.{name}"),
                    "the drive's touch probe uses the index only (CoE manual 3.9); set drive_settings.touch_probe = \"cia402\"",
                ));
            }
        }
        if let Some(pitch) = self.index_pitch {
            positive(&format!("{key}.index_pitch"), pitch)?;
        }
        if let (Some(n), Some(p)) = (self.negative_hard_stop, self.positive_hard_stop)
            && n >= p
        {
            return Err(invalid(key, "negative_hard_stop must be below positive_hard_stop"));
        }
        let inside = self.negative_hard_stop.is_none_or(|n| self.start_position > n)
            && self.positive_hard_stop.is_none_or(|p| self.start_position < p);
        if !inside {
            return Err(invalid(format!("{key}.start_position"), "must lie between the hard stops"));
        }
        Ok(())
    }
}

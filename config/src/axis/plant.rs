//! `[axes.plant]`: the motor and load behind a drive.

use serde::Deserialize;

use crate::error::{ConfigError, invalid, positive};

/// The highest natural frequency of a flexible load: the servo loops run at 16 kHz, and
/// their integration of a spring needs many steps per period.
pub const MAX_LOAD_FREQUENCY_HZ: f64 = 1000.0;

/// The motor and load behind a drive (see rt-core's `drive::plant`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PlantConfig {
    /// Bandwidth of the drive's velocity loop, Hz.
    pub bandwidth_hz: f64,
    /// Load inertia over the inertia the drive is tuned for; 1 is a perfect tuning.
    pub inertia_ratio: f64,
    /// Coulomb friction as a fraction of rated force.
    pub friction: f64,
    /// Acceleration of the tuned load at rated force, units/s².
    pub rated_acc: f64,
    /// Peak force over rated force.
    pub peak_ratio: f64,
    /// A flexible load: a second mass on a spring and damper behind the motor, ringing at
    /// this natural frequency (Hz) when the motor stands still; 0 (the default) is a rigid
    /// load. HMPL 15.1's cantilever, for the VSF and input shaping of ch. 15.
    pub load_frequency_hz: f64,
    /// The flexible load's damping ratio, 0..1.
    pub load_damping: f64,
    /// The flexible load's mass over the motor's (its inertia, `inertia_ratio`), > 0..10.
    pub load_mass_ratio: f64,
}

impl Default for PlantConfig {
    fn default() -> Self {
        PlantConfig {
            bandwidth_hz: 100.0,
            inertia_ratio: 1.0,
            friction: 0.02,
            rated_acc: 20_000.0,
            peak_ratio: 3.0,
            load_frequency_hz: 0.0,
            load_damping: 0.02,
            load_mass_ratio: 0.1,
        }
    }
}

impl PlantConfig {
    /// Checks the table at `key` (`axes[i].plant`).
    pub(crate) fn validate(&self, key: &str) -> Result<(), ConfigError> {
        positive(&format!("{key}.bandwidth_hz"), self.bandwidth_hz)?;
        if self.bandwidth_hz > 1000.0 {
            return Err(invalid(format!("{key}.bandwidth_hz"), "a servo velocity loop above 1000 Hz is not simulated"));
        }
        positive(&format!("{key}.inertia_ratio"), self.inertia_ratio)?;
        positive(&format!("{key}.rated_acc"), self.rated_acc)?;
        if !(0.0..1.0).contains(&self.friction) {
            return Err(invalid(format!("{key}.friction"), "a fraction of rated force in 0..1"));
        }
        if !(self.peak_ratio >= 1.0 && self.peak_ratio.is_finite()) {
            return Err(invalid(format!("{key}.peak_ratio"), "peak force is at least the rated force (>= 1)"));
        }
        if !(0.0..=MAX_LOAD_FREQUENCY_HZ).contains(&self.load_frequency_hz) {
            return Err(invalid(format!("{key}.load_frequency_hz"), "0 (a rigid load) or a frequency up to 1000 Hz"));
        }
        if !(0.0..1.0).contains(&self.load_damping) {
            return Err(invalid(format!("{key}.load_damping"), "a damping ratio in 0..1"));
        }
        if !(self.load_mass_ratio > 0.0 && self.load_mass_ratio <= 10.0) {
            return Err(invalid(format!("{key}.load_mass_ratio"), "a mass ratio in > 0..10"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `[axes.plant]`'s flexible load: rigid by default; a frequency, damping or mass ratio
    /// outside its range is refused by key.
    #[test]
    fn a_flexible_load_is_off_by_default_and_checked() {
        let plant = PlantConfig::default();
        assert_eq!(plant.load_frequency_hz, 0.0, "rigid");
        let plant: PlantConfig = toml::from_str("load_frequency_hz = 8.0\nload_damping = 0.05\n").unwrap();
        assert!(plant.validate("axes[0].plant").is_ok());
        assert_eq!((plant.load_frequency_hz, plant.load_damping), (8.0, 0.05));
        for (line, key) in [
            ("load_frequency_hz = -1.0", "axes[0].plant.load_frequency_hz"),
            ("load_frequency_hz = 1001.0", "axes[0].plant.load_frequency_hz"),
            ("load_damping = 1.0", "axes[0].plant.load_damping"),
            ("load_mass_ratio = 0.0", "axes[0].plant.load_mass_ratio"),
            ("load_mass_ratio = 11.0", "axes[0].plant.load_mass_ratio"),
        ] {
            let plant: PlantConfig = toml::from_str(line).unwrap();
            let refused = plant.validate("axes[0].plant");
            assert!(matches!(refused, Err(ConfigError::Invalid { key: k, .. }) if k == key), "{line}");
        }
    }
}

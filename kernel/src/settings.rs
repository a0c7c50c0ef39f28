//! An axis' settings (HMPL 5.3) and the ranges the setters enforce, with the error code
//! each refusal records (HMPL table 18.1.2.1).

use api::AxisError;

use crate::generator::Profile;
use config::AxisConfig;

/// Smooth time range (HMPL table 5.1.1.2), ms.
pub const MAX_SMOOTH_TIME_MS: f64 = 500.0;

/// HMPL 20: homing defaults: method 33, fast 20, slow 5, acc 2000, offset 0, 120 s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HomeSettings {
    /// The CiA 402 homing method written to 0x6098 (HMPL 20.3).
    pub method: i64,
    /// The speed while searching for the switch, axis units/s, to 0x6099:1 (HMPL 20.4).
    pub switch_vel: f64,
    /// The speed while searching for the zero, axis units/s, to 0x6099:2 (HMPL 20.5).
    pub zero_vel: f64,
    /// The homing acceleration, axis units/s², to 0x609A (HMPL 20.6).
    pub acc: f64,
    /// The home offset, axis units, to 0x607C (HMPL 20.7).
    pub offset: f64,
    /// How long a run may take before it fails, ms (HMPL 20.8).
    pub timeout_ms: i64,
}

impl Default for HomeSettings {
    fn default() -> Self {
        HomeSettings { method: 33, switch_vel: 20.0, zero_vel: 5.0, acc: 2000.0, offset: 0.0, timeout_ms: 120_000 }
    }
}

/// HMPL 20.3: the methods `SetHomeMethod` accepts (what the drive supports is its business).
pub fn valid_home_method(method: i64) -> bool {
    matches!(method, 1 | 2 | 7..=14 | 17 | 18 | 23..=30 | 33 | 34 | 37)
}

/// The setters of HMPL 20.3 and 20.8 with the code of their refusal; the speeds,
/// acceleration and offset are plain numbers whose ranges the registry declares.
impl HomeSettings {
    /// SetHomeMethod (HMPL 20.3): a method of [`valid_home_method`], else `CmdInvalidParameter`.
    pub fn set_method(&mut self, method: i64) -> Result<(), AxisError> {
        if !valid_home_method(method) {
            return Err(AxisError::CmdInvalidParameter);
        }
        self.method = method;
        Ok(())
    }

    /// SetHomeTimeout (HMPL 20.8): a time above 0 ms, else `CmdInvalidParameter`.
    pub fn set_timeout(&mut self, ms: i64) -> Result<(), AxisError> {
        if ms <= 0 {
            return Err(AxisError::CmdInvalidParameter);
        }
        self.timeout_ms = ms;
        Ok(())
    }
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct Settings {
    /// The machine file's limits: the most `SetVel`/`SetAcc`/`SetDec` accept.
    pub max_vel: f64,
    pub max_acc: f64,
    pub vel: f64,
    pub acc: f64,
    pub dec: f64,
    pub kill_dec: f64,
    pub sm_time_ms: f64,
    /// Software limits (HMPL 5.3.11-14): right (positive) and left (negative).
    pub swrl: f64,
    pub swll: f64,
    /// In-position window and its debounce time (HMPL 5.1, 5.3.45-48).
    pub pos_window: f64,
    pub pos_window_time_ms: f64,
    /// `HCV_ID_max_pos_err`: position error that disables the axis.
    pub max_pos_err: f64,
    /// `HCV_ID_en_delay`: how long the drive may take to enable or disable.
    pub enable_timeout_ms: f64,
    /// Velocity override, percent (HMPL 5.3.37).
    pub vel_scale: f64,
    pub ignore_hwl: bool,
    pub ignore_swl: bool,
    pub ignore_pe: bool,
    /// 0: immediate (a new command replaces the running one), 1: buffered (HMPL 5.3.42).
    pub buffer_mode: i64,
    /// Rollover length (0: off), HMPL 5.3.39.
    pub rollover: f64,
    pub home: HomeSettings,
}

impl Settings {
    pub fn new(config: &AxisConfig) -> Self {
        Settings {
            max_vel: config.max_vel,
            max_acc: config.max_acc,
            vel: config.vel,
            acc: config.acc,
            dec: config.dec,
            kill_dec: config.max_acc,
            sm_time_ms: 0.0,
            swrl: f64::INFINITY,
            swll: f64::NEG_INFINITY,
            pos_window: 0.005,
            pos_window_time_ms: 5.0,
            max_pos_err: 5.0,
            enable_timeout_ms: 1000.0,
            vel_scale: 100.0,
            ignore_hwl: false,
            ignore_swl: false,
            ignore_pe: false,
            buffer_mode: 0,
            rollover: 0.0,
            home: HomeSettings::default(),
        }
    }

    pub fn profile(&self) -> Profile {
        Profile { vel: self.vel, acc: self.acc, dec: self.dec }
    }
}

/// A time in ms (acceleration or deceleration time) turned into a rate: vel / time, > 0 and
/// at most `max`. A time of 0, a negative one or NaN gives a rate that is refused.
pub fn rate_from_time(vel: f64, time_ms: f64, max: f64, error: AxisError) -> Result<f64, AxisError> {
    let rate = vel / (time_ms / 1000.0);
    if rate > 0.0 && rate <= max { Ok(rate) } else { Err(error) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// HMPL 20.1: the defaults.
    #[test]
    fn home_defaults() {
        let h = HomeSettings::default();
        assert_eq!(
            (h.method, h.switch_vel, h.zero_vel, h.acc, h.offset, h.timeout_ms),
            (33, 20.0, 5.0, 2000.0, 0.0, 120_000)
        );
    }

    /// HMPL 20.3 and 20.8: what the setters refuse, and that a refusal keeps the value.
    #[test]
    fn home_setters() {
        let mut h = HomeSettings::default();
        assert_eq!(h.set_method(3), Err(AxisError::CmdInvalidParameter));
        assert_eq!(h.set_timeout(0), Err(AxisError::CmdInvalidParameter));
        assert_eq!(h, HomeSettings::default());
        assert_eq!(h.set_timeout(5), Ok(()));
        assert_eq!(h.timeout_ms, 5);
    }

    /// HMPL 20.3: the methods SetHomeMethod accepts.
    #[test]
    fn home_methods() {
        for m in [1, 2, 7, 14, 17, 18, 23, 30, 33, 34, 37] {
            assert!(valid_home_method(m), "{m}");
        }
        for m in [0, 3, 6, 15, 16, 19, 22, 31, 32, 35, 36, 38, -1] {
            assert!(!valid_home_method(m), "{m}");
        }
    }

    #[test]
    fn rates_from_times() {
        assert_eq!(rate_from_time(100.0, 100.0, 1e6, AxisError::CmdInvalidAcc), Ok(1000.0));
        for bad in [0.0, -0.0, -5.0, f64::NAN, f64::INFINITY] {
            assert_eq!(
                rate_from_time(100.0, bad, 1e6, AxisError::CmdInvalidAcc),
                Err(AxisError::CmdInvalidAcc),
                "{bad}"
            );
        }
    }
}

//! An axis' homing (HMPL ch. 20): the homing setters (20.3 to 20.8), `MoveHome` (20.2)
//! through the drive's homing mode (`crate::homing`), and whether the axis is homed
//! (20.9, 20.10).

use api::AxisError;

use super::Axis;
use crate::homing::Homing;
use crate::settings::HomeSettings;
use crate::source::ReferenceSource;
use devices::coe::fits_width;
use devices::ecat::Network;

/// Whether the axis is homed (HMPL 20.10) and how its last homing run ended, which
/// `MoveHome` answers once the run is over (HMPL 20.2).
#[derive(Clone, Copy, Debug, Default)]
pub struct HomeState {
    homed: bool,
    result: Option<Result<(), AxisError>>,
}

impl HomeState {
    /// HMPL 20.10: homing completed (or `SetHomedStatus`).
    pub fn is_homed(&self) -> bool {
        self.homed
    }

    /// HMPL 20.9: `SetHomedStatus`.
    pub fn set_homed(&mut self, homed: bool) {
        self.homed = homed;
    }

    /// The result of the last homing run, once, when it is over.
    pub fn take_result(&mut self) -> Option<Result<(), AxisError>> {
        self.result.take()
    }

    /// A run starts: the axis is not homed until it succeeds.
    fn start(&mut self) {
        self.homed = false;
        self.result = None;
    }

    fn finish(&mut self, result: Result<(), AxisError>) {
        if result.is_ok() {
            self.homed = true;
        }
        self.result = Some(result);
    }
}

impl Axis {
    /// HMPL 20.9, 20.10: whether the axis is homed, and the last run's result.
    pub fn home_state(&self) -> &HomeState {
        &self.home_state
    }

    /// For SetHomedStatus (HMPL 20.9) and to take MoveHome's result once the run is over.
    pub fn home_state_mut(&mut self) -> &mut HomeState {
        &mut self.home_state
    }

    /// Applies one of the homing setters (HMPL 20.3 to 20.8), recording a refusal.
    pub fn set_home(&mut self, f: impl FnOnce(&mut HomeSettings) -> Result<(), AxisError>) -> Result<(), AxisError> {
        let result = f(&mut self.settings.home);
        self.check(result)
    }

    /// HMPL 20.2: writes the homing objects by SDO and starts the drive's homing.
    pub fn start_homing(&mut self, network: &mut Network) -> Result<(), AxisError> {
        self.check_can_move()?;
        if !self.link.can_home() {
            return Err(self.fail(AxisError::CmdInvalidNoSpecificPdo));
        }
        let home = self.settings.home;
        let counts = |units: f64| self.link.counts(units).round() as i64;
        let writes: [(u16, u8, i64, usize); 5] = [
            (0x6098, 0, home.method, 1),
            (0x6099, 1, counts(home.switch_vel), 4),
            (0x6099, 2, counts(home.zero_vel), 4),
            (0x609A, 0, counts(home.acc), 4),
            (0x607C, 0, counts(home.offset), 4),
        ];
        for (index, sub, value, len) in writes {
            // A value cut to the object's width would be another value.
            if !fits_width(value, len)
                || network.sdo_write(self.link.slave(), index, sub, &value.to_le_bytes()[..len]).is_err()
            {
                return Err(self.fail(AxisError::DriveHomeFailed));
            }
        }
        let started = self.source.start_homing(Homing::new(self.cycle));
        self.check(started)?;
        Homing::enter(&mut self.link);
        self.home_state.start();
        Ok(())
    }

    /// IsHoming (HMPL 20.11): a MoveHome run is under way.
    pub fn is_homing(&self) -> bool {
        self.source.is_homing()
    }

    /// One cycle of a homing run (HMPL 20.2), within the homing timeout (20.8).
    pub(super) fn step_homing(&mut self) {
        if self.source.is_homing() {
            let timeout = self.cycles(self.settings.home.timeout_ms as f64);
            if let ReferenceSource::Homing(run) = &mut self.source
                && let Some(result) = run.step(&mut self.link, &self.sensed.feedback, self.cycle, timeout)
            {
                self.finish_homing(result);
            }
        }
    }

    /// Ends a homing run early (disabled, stopped, a fault): `MoveHome` returns 0x83II042E.
    pub(super) fn abort_homing(&mut self) {
        if self.source.is_homing() {
            Homing::abort(&mut self.link);
            self.finish_homing(Err(AxisError::DriveHomeFailed));
        }
    }

    /// Ends a homing run: the profile generator gives the reference again.
    fn finish_homing(&mut self, result: Result<(), AxisError>) {
        self.source.end_homing();
        match result {
            // The home defines the coordinates: the drive reads the home offset there.
            Ok(()) => self.pos_offset = 0.0,
            Err(e) => {
                self.fail(e);
            }
        }
        self.home_state.finish(result);
    }
}

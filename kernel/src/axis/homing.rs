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

    /// HMPL 20.2: writes the homing objects by SDO and starts the drive's homing. In
    /// memory the objects are written at once and a refusal fails the call; on a wire
    /// the run writes them first, one mailbox transfer after the other (`configure_homing`).
    pub fn start_homing(&mut self, network: &mut Network) -> Result<(), AxisError> {
        self.check_can_move()?;
        if !self.link.can_home() {
            return Err(self.fail(AxisError::CmdInvalidNoSpecificPdo));
        }
        let Some(objects) = self.homing_objects() else {
            // A value cut to the object's width would be another value.
            return Err(self.fail(AxisError::DriveHomeFailed));
        };
        let mut run = Homing::new(self.cycle);
        if run.configure(&mut self.link, network, &objects.writes()).is_err() {
            return Err(self.fail(AxisError::DriveHomeFailed));
        }
        let started = self.source.start_homing(run);
        self.check(started)?;
        self.home_state.start();
        Ok(())
    }

    /// Goes on writing the homing objects of a run that started on a wire.
    pub(super) fn configure_homing(&mut self, network: &mut Network) {
        if !matches!(self.source, ReferenceSource::Homing(Homing::Configuring { .. })) {
            return;
        }
        let Some(objects) = self.homing_objects() else { return };
        if let ReferenceSource::Homing(run) = &mut self.source
            && let Err(e) = run.configure(&mut self.link, network, &objects.writes())
        {
            Homing::abort(&mut self.link);
            self.finish_homing(Err(e));
        }
    }

    /// The homing objects of the settings (CoE manual 3.2): method, the two speeds, the
    /// acceleration and the offset, each as wide as its object; `None` when one does not fit.
    fn homing_objects(&self) -> Option<HomingObjects> {
        let home = self.settings.home;
        let counts = |units: f64| self.link.counts(units).round() as i64;
        let values =
            [home.method, counts(home.switch_vel), counts(home.zero_vel), counts(home.acc), counts(home.offset)];
        let mut bytes = [[0u8; 4]; 5];
        for ((value, len), out) in values.iter().zip(HOMING_OBJECTS.map(|(_, _, len)| len)).zip(&mut bytes) {
            if !fits_width(*value, len) {
                return None;
            }
            out.copy_from_slice(&value.to_le_bytes()[..4]);
        }
        Some(HomingObjects(bytes))
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

/// The homing objects the master writes, in order: index, sub-index, width in bytes.
const HOMING_OBJECTS: [(u16, u8, usize); 5] =
    [(0x6098, 0, 1), (0x6099, 1, 4), (0x6099, 2, 4), (0x609A, 0, 4), (0x607C, 0, 4)];

/// The values of `HOMING_OBJECTS`, little-endian.
struct HomingObjects([[u8; 4]; 5]);

impl HomingObjects {
    fn writes(&self) -> [(u16, u8, &[u8]); 5] {
        std::array::from_fn(|i| {
            let (index, sub, len) = HOMING_OBJECTS[i];
            (index, sub, &self.0[i][..len])
        })
    }
}

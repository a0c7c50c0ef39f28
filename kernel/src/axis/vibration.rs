//! HMPL 15.2 to 15.7: an axis' VSF and input shaper, the second stage of its filter chain
//! (`motion/shaping.rs`). Each is changed only at rest, and at most one of them is on
//! (HMPL 15.1); what is set takes effect from rest at the reference.

use api::AxisError;

use super::Axis;
use crate::shaping::{SHAPER_NORMAL, SHAPER_ROBUST, ShaperParams, Vibration, VsfParams};

/// Which of the two filters a command addresses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VibrationFilter {
    /// The vibration suppression filter, a notch (HMPL 15.2 to 15.4).
    Vsf,
    /// The input shaper, ZV or ZVD (HMPL 15.5 to 15.7).
    InShape,
}

impl Axis {
    /// The stage, once the axis stands: HMPL 15.2-15.7 "not while the motor moves"
    /// (docs/decisions.md, "Filters": disabling too, which would make the reference jump).
    fn vibration_at_rest(&mut self) -> Result<(&mut Vibration, f64), AxisError> {
        if self.is_moving() {
            return Err(self.fail(AxisError::CmdInvalidMoving));
        }
        let pos = self.generator.raw().pos;
        let stage = self.filters.vibration().expect("an axis' chain has the vibration stage");
        Ok((stage, pos))
    }

    /// EnableAxisVsf, DisableAxisVsf, EnableAxisInShape, DisableAxisInShape.
    pub fn switch_vibration_filter(&mut self, filter: VibrationFilter, on: bool) -> Result<(), AxisError> {
        let (stage, pos) = self.vibration_at_rest()?;
        let other_on = match filter {
            VibrationFilter::Vsf => stage.shaper.is_enabled(),
            VibrationFilter::InShape => stage.vsf.is_enabled(),
        };
        if on && other_on {
            // HMPL 15.1: never both; the axis table names only the shaper's case.
            let error = match filter {
                VibrationFilter::Vsf => AxisError::CmdInvalidInputshapingEnabled,
                VibrationFilter::InShape => AxisError::CmdInvalidState,
            };
            return Err(self.fail(error));
        }
        match filter {
            VibrationFilter::Vsf => stage.vsf.set_enabled(on, pos),
            VibrationFilter::InShape => stage.shaper.set_enabled(on, pos),
        }
        Ok(())
    }

    /// SetAxisVsf (HMPL 15.4); the registry has checked the ranges, the cycle limits the
    /// frequency to below 0.45 of its rate (the bilinear transform's room below Nyquist).
    pub fn set_vsf(&mut self, freq_hz: f64, damping: f64) -> Result<(), AxisError> {
        let params = VsfParams { freq_hz, damping };
        let (stage, pos) = self.vibration_at_rest()?;
        if !stage.vsf.fits(params) {
            return Err(self.fail(AxisError::FrequencyLimit));
        }
        stage.vsf.configure(params);
        stage.vsf.rest_at(pos);
        Ok(())
    }

    /// SetAxisInShape (HMPL 15.7).
    pub fn set_in_shape(&mut self, freq_hz: f64, damping: f64, shaper_type: i64) -> Result<(), AxisError> {
        let robust = match shaper_type {
            SHAPER_NORMAL => false,
            SHAPER_ROBUST => true,
            _ => return Err(self.fail(AxisError::CmdInvalidParameter)),
        };
        let params = ShaperParams { freq_hz, damping, robust };
        let (stage, pos) = self.vibration_at_rest()?;
        if !stage.shaper.fits(params) {
            // The room reserved at start-up holds every shaper of HMPL 15.7's ranges.
            return Err(self.fail(AxisError::FrequencyLimit));
        }
        stage.shaper.configure(params);
        stage.shaper.rest_at(pos);
        Ok(())
    }

    /// `motion_status` bits 6 (InShape) and 7 (VSF), HMPL table 5.1.1.5.
    pub(super) fn vibration_status(&self) -> u32 {
        use schema::motion_status;
        let Some(stage) = self.filters.vibration_ref() else { return 0 };
        let mut bits = 0;
        if stage.shaper.is_enabled() {
            bits |= motion_status::INPUT_SHAPE;
        }
        if stage.vsf.is_enabled() {
            bits |= motion_status::VSF;
        }
        bits
    }
}

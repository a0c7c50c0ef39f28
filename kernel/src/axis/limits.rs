//! An axis' limits (HMPL table 5.1.1.4 and its default reactions): software limits
//! stop the motion before the limit, hardware limits stop it, a position error beyond
//! the limit disables the axis; the Ignore* switches suppress each.

use api::AxisError;
use schema::fault_status;

use super::Axis;
use devices::profile::Kinematics;

impl Axis {
    /// Before the generator steps: if the move would pass a software limit, stop it with
    /// the kill deceleration so that it ends at or before the limit (HMPL 5.3.11-14).
    /// The ends of the drive's 32-bit counts are limits no switch turns off: a velocity
    /// move, a rollover axis or a PVT curve stops before the counts overflow.
    pub(super) fn guard_software_limits(&mut self) {
        if !self.profile_moving() || self.generator.is_stopping() {
            return;
        }
        let raw = self.generator.raw();
        if let Some((bit, error)) = self.passes_limit(raw) {
            self.generator.stop_with(self.settings.kill_dec);
            self.errors.enter_error_stop(bit);
            self.fail(error);
        }
    }

    /// Whether motion `k` would pass a limit before the kill deceleration could stop it:
    /// the limit's fault bit and error.
    pub(super) fn passes_limit(&self, k: Kinematics) -> Option<(u32, AxisError)> {
        let (mut left, mut right) = self.count_range();
        if !(self.settings.ignore_swl || self.settings.rollover > 0.0) {
            (left, right) = (left.max(self.settings.swll), right.min(self.settings.swrl));
        }
        let v = k.vel;
        let reach = k.pos + v * self.period_s + v * v.abs() / (2.0 * self.settings.kill_dec);
        if v > 0.0 && reach > right {
            Some((fault_status::SW_RIGHT_LIMIT, AxisError::Swrl))
        } else if v < 0.0 && reach < left {
            Some((fault_status::SW_LEFT_LIMIT, AxisError::Swll))
        } else {
            None
        }
    }

    /// 3. Limits, position error and status from this cycle's feedback and reference.
    pub fn monitor(&mut self) {
        if let Some(inputs) = self.sensed.feedback.digital_inputs {
            // 0x60FD bit 0: negative (left) limit, bit 1: positive (right) limit.
            for (bit, flag, error) in
                [(1, fault_status::HW_RIGHT_LIMIT, AxisError::Hwrl), (0, fault_status::HW_LEFT_LIMIT, AxisError::Hwll)]
            {
                let active = inputs & (1 << bit) != 0 && !self.settings.ignore_hwl;
                if active && self.errors.faults() & flag == 0 {
                    self.kill_stop();
                    self.errors.enter_error_stop(0);
                    self.fail(error);
                }
                self.errors.set_limit_switch(flag, active);
            }
        }
        let error = self.pos_err();
        if self.link.is_enabled() && !self.settings.ignore_pe && error.abs() > self.settings.max_pos_err {
            self.errors.enter_error_stop(fault_status::POSITION_ERROR);
            self.fail(AxisError::Perr);
            let _ = self.disable();
        }
        self.track_in_position();
    }
}

//! What an axis senses of its drive each cycle (HMPL 5.1.1): the drive's feedback, its
//! position in units, and the position and velocity feedback in the reference's
//! coordinates.

use crate::drive_link::Feedback;

/// The drive's inputs of this cycle, as the axis' pipeline sees them.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Sensed {
    pub(super) feedback: Feedback,
    /// The drive's position in units before the offset (a gantry replaces it).
    pub(super) drive_position: f64,
    /// The position feedback, in the reference's coordinates.
    pub(super) pos_fb: f64,
    pub(super) vel_fb: f64,
    /// The compensation the drive's feedback of this cycle holds (the last cycle's output):
    /// taken off it, the feedback is in the reference's coordinates.
    pub(super) comp_in_fb: f64,
}

impl Sensed {
    /// The feedback from the drive position, less the origin's offset (HMPL 5.3.19) and
    /// the compensation the drive was given last cycle (HMPL 14.1); the velocity from its
    /// change over the cycle.
    pub(super) fn locate(&mut self, pos_offset: f64, compensation: f64, period_s: f64) {
        self.comp_in_fb = compensation;
        let fb = self.drive_position - pos_offset - self.comp_in_fb;
        self.vel_fb = (fb - self.pos_fb) / period_s;
        self.pos_fb = fb;
    }

    /// HMPL 14.3: without compensation the feedback is the drive position less the offset.
    pub(super) fn drop_compensation(&mut self, pos_offset: f64) {
        self.comp_in_fb = 0.0;
        self.pos_fb = self.drive_position - pos_offset;
    }

    /// HMPL 5.3.21: the feedback with the compensation it holds, as the drive reports it.
    pub(super) fn pos_fb_comp(&self) -> f64 {
        self.pos_fb + self.comp_in_fb
    }
}

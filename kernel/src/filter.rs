//! An axis' filter chain: "filters modify the PG position commands" (HMPL 15.1). The
//! reference the profile generator produces passes each stage in order before it becomes
//! the axis' reference. The first stage is the smoothing of HMPL 5.1 (fig. 5.1.2), the
//! second VSF and input shaping (HMPL 15.2 to 15.7, `shaping.rs`; at most one of them on).
//! A group's output passes its own shapers instead (HMPL 15.1: axis InShape has no effect
//! on group motion). The stages are added at start-up into room reserved then: nothing in
//! the cycle allocates.

use crate::shaping::Vibration;
use crate::smoothing::Smoother;
use devices::profile::Kinematics;

/// Stages one chain holds: smoothing, VSF, input shaping, and one to spare.
pub const MAX_STAGES: usize = 4;

/// One filter of the chain.
pub(crate) enum Stage {
    /// The moving average that turns a T-curve into an S-curve (HMPL 5.1, 5.3.16).
    Smoothing(Smoother),
    /// VSF and input shaping (HMPL 15.2 to 15.7), boxed at start-up: it is larger than
    /// the smoothing.
    Vibration(Box<Vibration>),
}

impl Stage {
    #[inline]
    fn push(&mut self, k: Kinematics) -> Kinematics {
        match self {
            Stage::Smoothing(s) => s.push(k),
            Stage::Vibration(v) => v.push(k),
        }
    }

    fn rest_at(&mut self, pos: f64) {
        match self {
            Stage::Smoothing(s) => s.rest_at(pos),
            Stage::Vibration(v) => v.rest_at(pos),
        }
    }

    fn settled(&self) -> bool {
        match self {
            Stage::Smoothing(s) => s.settled(),
            Stage::Vibration(v) => v.settled(),
        }
    }

    fn as_smoother(&mut self) -> Option<&mut Smoother> {
        match self {
            Stage::Smoothing(s) => Some(s),
            Stage::Vibration(_) => None,
        }
    }

    fn as_vibration(&mut self) -> Option<&mut Vibration> {
        match self {
            Stage::Vibration(v) => Some(v),
            Stage::Smoothing(_) => None,
        }
    }

    fn vibration(&self) -> Option<&Vibration> {
        match self {
            Stage::Vibration(v) => Some(v),
            Stage::Smoothing(_) => None,
        }
    }
}

/// A stage beyond `MAX_STAGES`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChainFull;

/// The stages between an axis' profile generator and its reference, in order.
pub struct FilterChain {
    stages: Vec<Stage>,
    /// The smoothing, VSF and shaper pass samples through until a motion handed over from
    /// a coupling (a gear slave after GearOut) has come to rest: their history would hold
    /// a standstill behind a moving reference and pull the output back (docs/decisions.md,
    /// "Gear").
    smoothing_suspended: bool,
}

impl Default for FilterChain {
    fn default() -> Self {
        Self::new()
    }
}

impl FilterChain {
    /// No stages: the chain passes references through unchanged.
    pub fn new() -> Self {
        FilterChain { stages: Vec::with_capacity(MAX_STAGES), smoothing_suspended: false }
    }

    /// The chain an axis starts with: smoothing (off until a smooth time is set), with
    /// room for `max_smooth_samples`, then VSF and input shaping (off), with room for a
    /// shaper down to `min_shaper_hz` at a cycle of `period_s`.
    pub fn for_axis(max_smooth_samples: usize, min_shaper_hz: f64, period_s: f64) -> Self {
        let mut chain = Self::new();
        chain.add(Stage::Smoothing(Smoother::new(max_smooth_samples))).expect("an empty chain has room");
        chain.add(Stage::Vibration(Box::new(Vibration::new(min_shaper_hz, period_s)))).expect("room for two stages");
        chain
    }

    /// The VSF and input-shaping stage, if the chain has one.
    pub(crate) fn vibration(&mut self) -> Option<&mut Vibration> {
        self.stages.iter_mut().find_map(Stage::as_vibration)
    }

    pub(crate) fn vibration_ref(&self) -> Option<&Vibration> {
        self.stages.iter().find_map(Stage::vibration)
    }

    /// Appends a stage (at start-up: the room is reserved, so this never allocates).
    pub(crate) fn add(&mut self, stage: Stage) -> Result<(), ChainFull> {
        if self.stages.len() == MAX_STAGES {
            return Err(ChainFull);
        }
        self.stages.push(stage);
        Ok(())
    }

    /// One cycle: the reference `k` through every stage in order. Inlined into the
    /// axis' cycle, where a call per chain cost more than the loop.
    #[inline]
    pub fn push(&mut self, mut k: Kinematics) -> Kinematics {
        for stage in &mut self.stages {
            k = match stage {
                // A motion handed over passes the vibration filters too, which rest on it:
                // their history lies where the coupling took the axis from.
                Stage::Vibration(v) if self.smoothing_suspended => {
                    v.rest_at(k.pos);
                    k
                }
                _ => stage.push(k),
            };
        }
        k
    }

    /// Every stage at rest at `pos`, keeping its settings.
    pub fn reset(&mut self, pos: f64) {
        for stage in &mut self.stages {
            stage.rest_at(pos);
        }
    }

    /// Every stage's output has come to rest on its input.
    pub fn settled(&self) -> bool {
        self.stages.iter().all(Stage::settled)
    }

    fn smoother(&mut self) -> Option<&mut Smoother> {
        self.stages.iter_mut().find_map(Stage::as_smoother)
    }

    /// A new smooth time, in samples, starting at rest at `pos` (HMPL 5.3.16: the axis
    /// changes it only at rest).
    pub fn set_smoothing(&mut self, samples: usize, pos: f64) {
        if let Some(s) = self.smoother() {
            s.reset(pos, samples);
        }
    }

    /// A motion produced elsewhere continues from `pos` unsmoothed, until
    /// `resume_smoothing`.
    pub fn suspend_smoothing(&mut self, pos: f64) {
        self.set_smoothing(1, pos);
        self.smoothing_suspended = true;
    }

    pub(crate) fn is_smoothing_suspended(&self) -> bool {
        self.smoothing_suspended
    }

    /// Smoothing over `samples` again, from rest at `pos`.
    pub fn resume_smoothing(&mut self, samples: usize, pos: f64) {
        self.smoothing_suspended = false;
        self.set_smoothing(samples, pos);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(pos: f64) -> Kinematics {
        Kinematics { pos, vel: 0.0, acc: 0.0 }
    }

    #[test]
    fn a_chain_without_stages_passes_references_through() {
        let mut chain = FilterChain::new();
        for k in [at(1.0), Kinematics { pos: -3.5, vel: 20.0, acc: -7.0 }, at(f64::MAX)] {
            assert_eq!(chain.push(k), k);
            assert!(chain.settled(), "nothing to settle");
        }
        chain.set_smoothing(10, 0.0);
        assert_eq!(chain.push(at(2.0)), at(2.0), "no smoothing stage to set");
    }

    #[test]
    fn a_step_through_the_smoothing_stage_is_the_moving_average() {
        let n = 8;
        let mut chain = FilterChain::for_axis(50, 1.5, 1e-3);
        chain.set_smoothing(n, 0.0);
        let step = at(1.0);
        for i in 1..=2 * n {
            let out = chain.push(step);
            // The window holds min(i, n) samples of the step and the rest at 0.
            let average = i.min(n) as f64 / n as f64;
            assert!((out.pos - average).abs() < 1e-15, "sample {i}: {} not {average}", out.pos);
            assert_eq!(chain.settled(), i >= n, "sample {i}");
        }
        assert_eq!(chain.push(step), step, "settled exactly on the step");
    }

    #[test]
    fn the_smoothing_stage_gives_what_the_smoother_alone_gives() {
        let mut chain = FilterChain::for_axis(100, 1.5, 1e-3);
        let mut alone = Smoother::new(100);
        chain.set_smoothing(37, 5.0);
        alone.reset(5.0, 37);
        for i in 0..300 {
            let t = i as f64 * 1e-3;
            let k = Kinematics { pos: 5.0 + 100.0 * t * t, vel: 200.0 * t, acc: 200.0 };
            assert_eq!(chain.push(k), alone.push(k), "bit for bit at sample {i}");
        }
    }

    #[test]
    fn a_suspended_smoothing_passes_through_until_resumed() {
        let mut chain = FilterChain::for_axis(50, 1.5, 1e-3);
        chain.set_smoothing(10, 0.0);
        chain.suspend_smoothing(4.0);
        assert!(chain.is_smoothing_suspended());
        let k = Kinematics { pos: 4.5, vel: 30.0, acc: -100.0 };
        assert_eq!(chain.push(k), k, "unsmoothed while suspended");
        chain.resume_smoothing(10, 4.5);
        assert!(!chain.is_smoothing_suspended());
        let out = chain.push(at(5.5));
        assert!((out.pos - 4.6).abs() < 1e-12, "averaged over 10 again: {}", out.pos);
    }

    /// A motion handed over from a coupling passes an enabled shaper unchanged, and the
    /// shaper takes the axis' own motion from where it came to rest.
    #[test]
    fn a_suspended_chain_passes_the_vibration_filters_too() {
        use crate::shaping::ShaperParams;
        let mut chain = FilterChain::for_axis(50, 1.5, 1e-3);
        let v = chain.vibration().unwrap();
        v.shaper.configure(ShaperParams { freq_hz: 10.0, damping: 0.0, robust: false });
        v.shaper.set_enabled(true, 0.0);
        chain.suspend_smoothing(4.0);
        for i in 0..10 {
            let k = Kinematics { pos: 4.0 + 0.1 * i as f64, vel: 100.0, acc: 0.0 };
            assert_eq!(chain.push(k), k, "unshaped while suspended");
        }
        // At rest where the handed-over motion ended, 4.9.
        chain.resume_smoothing(1, 4.9);
        let out = chain.push(at(5.9));
        assert!((out.pos - 5.4).abs() < 1e-12, "half the step now, half 50 ms later: {}", out.pos);
    }

    #[test]
    fn reset_keeps_the_window_and_rests_every_stage() {
        let mut chain = FilterChain::for_axis(50, 1.5, 1e-3);
        chain.set_smoothing(4, 0.0);
        chain.push(at(1.0));
        assert!(!chain.settled());
        chain.reset(2.0);
        assert!(chain.settled(), "at rest after a reset");
        assert!((chain.push(at(3.0)).pos - 2.25).abs() < 1e-15, "still a window of 4");
    }

    #[test]
    fn the_chain_refuses_a_stage_beyond_its_room() {
        let mut chain = FilterChain::new();
        for _ in 0..MAX_STAGES {
            assert_eq!(chain.add(Stage::Smoothing(Smoother::new(1))), Ok(()));
        }
        assert_eq!(chain.add(Stage::Smoothing(Smoother::new(1))), Err(ChainFull));
        assert_eq!(chain.stages.capacity(), MAX_STAGES, "no room grown");
    }
}

//! What FUN147 needs of the pulse outputs Ps0-Ps3, which the controller implements on its
//! group interpolator and the crate's tests on a simulation.
//!
//! Units: positions, targets, ratios and remaining counts are pulses (Ps); speeds and
//! frequencies are pulses per second (Hz). The implementation maps pulses to its axis units.
//! Arrays are indexed by axis: 0 = Ps0 … 3 = Ps3.

/// A set of the axes Ps0-Ps3: bit i is Psi.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AxisSet(pub u8);

impl AxisSet {
    /// No axis.
    pub const NONE: AxisSet = AxisSet(0);

    /// Whether Psi is in the set.
    pub fn contains(self, axis: usize) -> bool {
        axis < 4 && self.0 & (1 << axis) != 0
    }

    /// The axes of the set, in order.
    pub fn iter(self) -> impl Iterator<Item = usize> {
        (0..4).filter(move |&i| self.contains(i))
    }

    /// Whether the sets share an axis.
    pub fn overlaps(self, other: AxisSet) -> bool {
        self.0 & other.0 != 0
    }
}

/// The pulse outputs a FUN147 instance drives. An instance only commands the axes it owns;
/// `axes` says which.
pub trait Axes {
    /// A straight line from where the axes are to `targets` (absolute pulses; `None`: the
    /// axis does not move), at the vector frequency `speed_hz` along the line, so that every
    /// axis' frequency is `speed_hz · |Δi| / |Δ|` and all finish together. Replaces any
    /// move of those axes.
    fn start_line(&mut self, targets: [Option<i64>; 4], speed_hz: f64);
    /// Runs without end in the ratio `ratio` (pulses; 0: the axis does not move), at the
    /// vector frequency `speed_hz`, until stopped.
    fn start_continuous(&mut self, ratio: [i64; 4], speed_hz: f64);
    /// Holds the move of these axes, keeping the pulses not yet output.
    fn pause(&mut self, axes: AxisSet, decelerate: bool);
    /// Goes on with a paused move, outputting exactly the pulses it kept.
    fn resume(&mut self, axes: AxisSet);
    /// Ends the move of these axes; the pulses not output are dropped (`remaining` still
    /// shows them until the next move).
    fn stop(&mut self, axes: AxisSet, decelerate: bool);
    /// Whether none of these axes outputs or holds pulses (a paused move is not done; a
    /// decelerating stop is done once at rest).
    fn is_done(&self, axes: AxisSet) -> bool;
    /// Each axis' position, pulses.
    fn position(&self) -> [i64; 4];
    /// Each axis' pulses still to output in its move, ≥ 0 (0 in a continuous run).
    fn remaining(&self) -> [i64; 4];
    /// Each axis' output frequency now, Hz, ≥ 0.
    fn frequency(&self) -> [f64; 4];
}

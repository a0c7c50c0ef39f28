//! A group's S-curve (HMPL 8.3.19, the smoothing of HMPL 5.1 on the path): a moving average
//! over the smooth time Ts, taken along the path instead of on each coordinate.
//!
//! Each cycle the planner's raw pose comes with its path position s (`Sample::path_pos`).
//! The smoothed pose is the path at the window's mean s: where the path curves (an arc, a
//! corner blend of HMPL 8.1.5) the pose stays on it, so a blend keeps its trans_dev and a
//! circle its radius. A moving average of each coordinate would cut them by up to ¼·v·Ts
//! (docs/decisions.md, "Groups").
//!
//! Where the path turns without a blend while it moves (a junction at speed, HMPL table
//! 8.1.4.1) it has no curve to follow: there the pose is averaged per coordinate, as before,
//! so that the velocity step is spread over Ts, which the planner's junction speeds count
//! on. A jog, which follows no path, is averaged per coordinate too. Both come from one
//! split of the raw pose, P(s) = Q(s) + K(s): K holds the corners as hinges,
//! K(s) = Σ step·(s − s_corner) for the corners passed, plus the jogs' displacement; Q is
//! what is left, a path without those corners. The output is Q at the mean s, interpolated
//! between the two samples around it, plus the mean of K over the window. Only the corners
//! and jogs inside the window count: one before it adds a linear function of s (or a
//! constant) to K, which the two parts cancel exactly.
//!
//! Between two cycles the pose is interpolated linearly, as the drives interpolate it; on a
//! curve this is the cycle's chord, the same as without smoothing. Nothing here allocates
//! after `new`.

use crate::sample::Sample;
use crate::segment::{Pose, lerp};

/// One cycle's raw sample in the window.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Entry {
    s: f64,
    pose: Pose,
    /// The corners passed since the sample before: Σ step, Σ step·s_corner.
    step: Pose,
    moment: Pose,
    /// A jog's displacement since the sample before.
    shift: Pose,
}

impl Entry {
    /// Whether the sample adds to K.
    fn turns(&self) -> bool {
        self.step != [0.0; 6] || self.moment != [0.0; 6] || self.shift != [0.0; 6]
    }
}

/// A group's moving average along the path over its smooth time Ts (see the module docs),
/// fed one planner [`Sample`] a cycle.
pub struct PathSmoother {
    ring: Vec<Entry>,
    /// Samples in the window (1: no smoothing).
    len: usize,
    /// The oldest sample, where the next one goes.
    next: usize,
    /// How many of the latest samples are equal (the window has settled when all are).
    unchanged: usize,
    /// Samples in the window that add to K.
    turning: usize,
}

impl PathSmoother {
    /// Room for `max_samples` (the longest smooth time at this cycle): allocated once.
    pub fn new(max_samples: usize) -> Self {
        PathSmoother { ring: vec![Entry::default(); max_samples.max(1)], len: 1, next: 0, unchanged: 1, turning: 0 }
    }

    /// Fills the window with a standstill at `pose`, path position `s`, over `len` samples
    /// (at most the room).
    pub fn reset(&mut self, pose: Pose, s: f64, len: usize) {
        self.len = len.clamp(1, self.ring.len());
        self.ring[..self.len].fill(Entry { s, pose, ..Entry::default() });
        (self.next, self.unchanged, self.turning) = (0, self.len, 0);
    }

    /// Samples in the window.
    pub fn window(&self) -> usize {
        self.len
    }

    /// Every sample in the window is the same: the output has come to rest on it.
    pub fn settled(&self) -> bool {
        self.unchanged >= self.len
    }

    /// The sample `i` cycles after the oldest in the window.
    fn at(&self, i: usize) -> &Entry {
        &self.ring[(self.next + i) % self.len]
    }

    /// Takes the planner's sample of this cycle, returns the smoothed pose.
    pub fn push(&mut self, sample: &Sample) -> Pose {
        let newest = *self.at(self.len - 1);
        let shift = if sample.jog { std::array::from_fn(|i| sample.pose[i] - newest.pose[i]) } else { [0.0; 6] };
        let entry = Entry {
            s: sample.path_pos,
            pose: sample.pose,
            step: sample.corners.step,
            moment: sample.corners.moment,
            shift,
        };
        let old = std::mem::replace(&mut self.ring[self.next], entry);
        self.next = (self.next + 1) % self.len;
        self.turning = self.turning + usize::from(entry.turns()) - usize::from(old.turns());
        let same = entry.pose == newest.pose && entry.s == newest.s && !entry.turns();
        self.unchanged = if same { self.unchanged + 1 } else { 1 };
        if self.settled() {
            // Exactly the sample, not an average computed back.
            return entry.pose;
        }
        self.smoothed()
    }

    /// Q at the window's mean s plus the mean of K (see the module's comment).
    fn smoothed(&self) -> Pose {
        let n = self.len;
        // Path positions from the oldest sample's, so that their mean keeps its digits.
        let s0 = self.at(0).s;
        let mean = (0..n).map(|i| self.at(i).s - s0).sum::<f64>() / n as f64;
        // The last sample at or before the mean (s never decreases along the window).
        let (mut lo, mut hi) = (0, n - 1);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if self.at(mid).s - s0 <= mean { lo = mid } else { hi = mid }
        }
        let (a, b) = (self.at(lo), self.at(hi));
        let ds = b.s - a.s;
        let u = if ds > 0.0 { ((mean - (a.s - s0)) / ds).clamp(0.0, 1.0) } else { 0.0 };
        if self.turning == 0 {
            return lerp(&a.pose, &b.pose, u);
        }
        // K at each sample, from the corners and jogs after the oldest sample.
        let (mut step, mut moment, mut shift) = ([0.0; 6], [0.0; 6], [0.0; 6]);
        let (mut sum, mut k_lo, mut k_hi) = ([0.0; 6], [0.0; 6], [0.0; 6]);
        for i in 0..n {
            let e = self.at(i);
            if i > 0 {
                for c in 0..6 {
                    step[c] += e.step[c];
                    moment[c] += e.moment[c];
                    shift[c] += e.shift[c];
                }
            }
            let k: Pose = std::array::from_fn(|c| step[c] * e.s - moment[c] + shift[c]);
            for c in 0..6 {
                sum[c] += k[c];
            }
            if i == lo {
                k_lo = k;
            }
            if i == hi {
                k_hi = k;
            }
        }
        let q_lo: Pose = std::array::from_fn(|c| a.pose[c] - k_lo[c]);
        let q_hi: Pose = std::array::from_fn(|c| b.pose[c] - k_hi[c]);
        let q = lerp(&q_lo, &q_hi, u);
        std::array::from_fn(|c| q[c] + sum[c] / n as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Corners;

    fn at(s: f64, pose: Pose) -> Sample {
        Sample { pose, path_pos: s, ..Sample::default() }
    }

    fn xy(x: f64, y: f64) -> Pose {
        [x, y, 0.0, 0.0, 0.0, 0.0]
    }

    #[test]
    fn without_smoothing_the_sample_passes_through() {
        let mut p = PathSmoother::new(10);
        p.reset(xy(0.0, 0.0), 0.0, 1);
        assert_eq!(p.push(&at(0.3, xy(0.1, 0.2))), xy(0.1, 0.2));
        assert!(p.settled());
    }

    /// Along an arc the smoothed pose is a point of the raw polyline at the mean s (on a
    /// line, exactly the line), and a full window of one sample gives that sample exactly.
    #[test]
    fn the_pose_is_the_path_at_the_mean_path_position() {
        let mut p = PathSmoother::new(10);
        p.reset(xy(1.0, 0.0), 0.0, 4);
        let on_circle = |s: f64| xy(s.cos(), s.sin());
        let outs: Vec<Pose> = (1..=4).map(|k| p.push(&at(0.1 * k as f64, on_circle(0.1 * k as f64)))).collect();
        // Window s = 0.1, 0.2, 0.3, 0.4: mean 0.25, halfway between the samples at 0.2 and 0.3.
        let expected = lerp(&on_circle(0.2), &on_circle(0.3), 0.5);
        assert!((0..2).all(|c| (outs[3][c] - expected[c]).abs() < 1e-15), "{:?} {expected:?}", outs[3]);
        for _ in 0..4 {
            p.push(&at(0.4, on_circle(0.4)));
        }
        assert!(p.settled());
        assert_eq!(p.push(&at(0.4, on_circle(0.4))), on_circle(0.4));
    }

    /// A corner passed at speed is averaged per coordinate, exactly as a moving average of
    /// each coordinate would: the hinge of the two legs.
    #[test]
    fn a_corner_passed_at_speed_is_averaged_per_coordinate() {
        let n = 5;
        let mut p = PathSmoother::new(10);
        p.reset(xy(0.0, 0.0), 0.0, n);
        // Along X to s = 1, then along Y: the pose at s and the corner's record.
        let pose = |s: f64| if s <= 1.0 { xy(s, 0.0) } else { xy(1.0, s - 1.0) };
        let mut raw = vec![xy(0.0, 0.0); n];
        for k in 1..=12 {
            let s = 0.3 * k as f64;
            let mut sample = at(s, pose(s));
            if s > 1.0 && s - 0.3 <= 1.0 {
                let step = xy(-1.0, 1.0);
                sample.corners = Corners { step, moment: step.map(|d| d * 1.0) };
            }
            raw.push(pose(s));
            let out = p.push(&sample);
            let window = &raw[raw.len() - n..];
            for c in 0..2 {
                let mean = window.iter().map(|q| q[c]).sum::<f64>() / n as f64;
                assert!((out[c] - mean).abs() < 1e-12, "s {s}: {out:?}, the per-coordinate mean {mean}");
            }
        }
    }

    /// A jog is averaged per coordinate, even back and forth along one axis.
    #[test]
    fn a_jog_is_averaged_per_coordinate() {
        let n = 4;
        let mut p = PathSmoother::new(10);
        p.reset(xy(0.0, 0.0), 0.0, n);
        let xs = [0.1, 0.3, 0.5, 0.6, 0.6, 0.5, 0.3, 0.1];
        let mut raw = vec![0.0f64; n];
        let mut s = 0.0;
        for (k, &x) in xs.iter().enumerate() {
            s += (x - raw[raw.len() - 1]).abs();
            raw.push(x);
            let out = p.push(&Sample { jog: true, ..at(s, xy(x, 0.0)) });
            let mean = raw[raw.len() - n..].iter().sum::<f64>() / n as f64;
            assert!((out[0] - mean).abs() < 1e-12, "cycle {k}: {} against {mean}", out[0]);
        }
    }
}

//! The smoothing of HMPL 5.1 (fig. 5.1.2), the first stage of an axis' filter chain
//! (`filter.rs`): a moving average over the smooth time Ts turns the T-curve into an
//! S-curve with jerk = acc / Ts, adding Ts to each acceleration phase. The average of a
//! profile's samples never exceeds the profile's own velocity and acceleration, so the
//! limits hold after smoothing too.

use devices::profile::Kinematics;

pub struct Smoother {
    samples: Vec<Kinematics>,
    /// Samples in the window (1: no smoothing).
    len: usize,
    next: usize,
    sum: Kinematics,
    /// Samples pushed since the sums were last recomputed from scratch.
    since_exact: usize,
    /// How many of the latest samples are equal (the window has settled when all are).
    unchanged: usize,
}

impl Smoother {
    /// Room for the longest smooth time at this cycle: allocated once, at start-up.
    pub fn new(max_samples: usize) -> Self {
        Smoother {
            samples: vec![Kinematics::default(); max_samples.max(1)],
            len: 1,
            next: 0,
            sum: Kinematics::default(),
            since_exact: 0,
            unchanged: 1,
        }
    }

    /// Fills the window with a standstill at `pos`, over `len` samples (at most the room).
    pub fn reset(&mut self, pos: f64, len: usize) {
        let len = len.clamp(1, self.samples.len());
        let rest = Kinematics { pos, vel: 0.0, acc: 0.0 };
        // A disabled axis rests at its feedback every cycle: a window already at rest
        // there stays as it is, sums included, instead of being filled again.
        if len == self.len && self.settled() && self.samples[0] == rest {
            self.next = 0;
            return;
        }
        self.len = len;
        self.samples[..self.len].fill(rest);
        self.next = 0;
        self.recompute();
        self.unchanged = self.len;
    }

    /// A standstill at `pos`, keeping the window's length.
    pub fn rest_at(&mut self, pos: f64) {
        self.reset(pos, self.len);
    }

    /// Every value in the window is the same: the output has come to rest on it.
    pub fn settled(&self) -> bool {
        self.unchanged >= self.len
    }

    fn recompute(&mut self) {
        let window = &self.samples[..self.len];
        self.sum = Kinematics {
            pos: window.iter().map(|k| k.pos).sum(),
            vel: window.iter().map(|k| k.vel).sum(),
            acc: window.iter().map(|k| k.acc).sum(),
        };
        self.since_exact = 0;
    }

    /// Takes the newest sample, returns the window's average.
    pub fn push(&mut self, k: Kinematics) -> Kinematics {
        let was_settled = self.settled();
        let old = std::mem::replace(&mut self.samples[self.next], k);
        self.next = (self.next + 1) % self.len;
        let same = self.len == 1 || self.samples[(self.next + self.len - 2) % self.len] == k;
        self.unchanged = if same { self.unchanged + 1 } else { 1 };
        if self.settled() {
            // Exactly the sample, not a sum divided back. The sums are recomputed when the
            // window has just settled; a window at rest that stays so keeps them.
            if !(was_settled && old == k) {
                self.recompute();
            }
            return k;
        }
        self.since_exact += 1;
        if self.since_exact >= self.len {
            // Sliding sums drift; start them again from the samples once per window.
            self.recompute();
        } else {
            self.sum.pos += k.pos - old.pos;
            self.sum.vel += k.vel - old.vel;
            self.sum.acc += k.acc - old.acc;
        }
        let n = self.len as f64;
        Kinematics { pos: self.sum.pos / n, vel: self.sum.vel / n, acc: self.sum.acc / n }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_becomes_a_ramp_over_the_window_and_settles_exactly() {
        let mut s = Smoother::new(10);
        s.reset(0.0, 4);
        let step = Kinematics { pos: 0.1, vel: 0.0, acc: 0.0 };
        let out: Vec<f64> = (0..6).map(|_| s.push(step).pos).collect();
        assert!((out[0] - 0.025).abs() < 1e-15 && (out[2] - 0.075).abs() < 1e-15);
        assert_eq!(out[3], 0.1, "exact once the window is full of it");
        assert!(s.settled());
    }

    /// The shortcuts of a window at rest (a reset where it rests, a push of the sample it
    /// holds) change no output bit against a window filled afresh, which a reset always did.
    #[test]
    fn a_window_at_rest_gives_the_same_bits_without_being_refilled() {
        let (mut once, mut every_cycle) = (Smoother::new(50), Smoother::new(50));
        once.reset(1.0 / 3.0, 7);
        once.push(Kinematics { pos: 1.0 / 3.0, ..Default::default() });
        for _ in 0..20 {
            every_cycle.reset(1.0 / 3.0, 7);
            assert_eq!(every_cycle.push(Kinematics { pos: 1.0 / 3.0, ..Default::default() }).pos, 1.0 / 3.0);
        }
        let ramp = (1..40).map(|i| Kinematics { pos: 1.0 / 3.0 + 0.1 * f64::from(i).min(20.0), vel: 0.7, acc: 0.0 });
        for k in ramp {
            let (a, b) = (once.push(k), every_cycle.push(k));
            assert_eq!((a.pos.to_bits(), a.vel.to_bits()), (b.pos.to_bits(), b.vel.to_bits()));
        }
        // Resting somewhere else, or over another window, still fills it.
        every_cycle.reset(5.0, 7);
        assert_eq!(every_cycle.push(Kinematics { pos: 5.0, ..Default::default() }).pos, 5.0);
        every_cycle.reset(5.0, 3);
        assert_eq!(every_cycle.len, 3, "samples in the window");
        let step = every_cycle.push(Kinematics { pos: 8.0, ..Default::default() });
        assert_eq!(step.pos, 6.0, "one of three samples moved by 3");
    }
}

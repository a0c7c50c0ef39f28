//! The vibration filters of HMPL ch. 15 as stages of a filter chain: input shaping
//! (InShape, 15.5 to 15.10) and the vibration suppression filter (VSF, 15.2 to 15.4).
//! Both are linear and act on the position, velocity and acceleration alike, so the
//! output's velocity stays the derivative of its position. Neither allocates after `new`.
//!
//! Input shaping convolves the reference with impulses timed on the load's damped period
//! T_d = 1 / (f·√(1-ζ²)), with K = exp(-ζπ/√(1-ζ²)) (docs/decisions.md, "Filters"):
//! - `SHAPER_NORMAL` (1) is the ZV shaper: 1/(1+K) at 0 and K/(1+K) at T_d/2;
//! - `SHAPER_ROBUST` (0) is the ZVD shaper: 1/(1+K)², 2K/(1+K)², K²/(1+K)² at 0, T_d/2, T_d,
//!   whose vibration stays low over a wider band of frequencies (HMPL 15.7: "stronger").
//!
//! Delays fall between cycles; a delayed sample is interpolated linearly between the two
//! cycles around it, so a shaper is tuned to its frequency and not to the nearest multiple
//! of the cycle.
//!
//! The VSF is a notch: H(s) = (s² + ω²) / (s² + 2ζωs + ω²), ω = 2πf, ζ the damping of
//! SetAxisVsf (0.7..1.5, the notch's width): no gain at f, unit gain at rest, discretised
//! with the bilinear transform prewarped at f (docs/decisions.md, "Filters").

use std::f64::consts::PI;

use devices::profile::Kinematics;

/// HMPL 15.7: `shaper_type` 1.
pub const SHAPER_NORMAL: i64 = 1;
/// HMPL 15.7: `shaper_type` 0.
pub const SHAPER_ROBUST: i64 = 0;

/// HMPL 15.7 (remark 2): the default frequency and damping ratio.
pub const DEFAULT_SHAPER: ShaperParams = ShaperParams { freq_hz: 5.5, damping: 0.03, robust: false };

/// The lowest frequency of an axis' shaper (HMPL 15.7) and of a group's (HMPL 15.10).
pub const AXIS_MIN_SHAPER_HZ: f64 = 1.5;
pub(crate) const GROUP_MIN_SHAPER_HZ: f64 = 3.0;

/// The highest damping ratio of a shaper (HMPL 15.7, 15.10): it sets the longest delay.
pub const MAX_SHAPER_DAMPING: f64 = 0.3;

/// What SetAxisInShape and SetGrpInShape set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShaperParams {
    /// The frequency of the vibration to cancel, Hz.
    pub freq_hz: f64,
    /// Its damping ratio, 0 to [`MAX_SHAPER_DAMPING`].
    pub damping: f64,
    /// ZVD (`SHAPER_ROBUST`) rather than ZV (`SHAPER_NORMAL`).
    pub robust: bool,
}

impl ShaperParams {
    /// The damped period T_d, s.
    fn damped_period(&self) -> f64 {
        1.0 / (self.freq_hz * (1.0 - self.damping * self.damping).sqrt())
    }

    /// The impulses: (amplitude, time in s), amplitudes summing to 1.
    pub fn impulses(&self) -> ([(f64, f64); 3], usize) {
        let z = self.damping;
        let k = (-z * PI / (1.0 - z * z).sqrt()).exp();
        let td = self.damped_period();
        if self.robust {
            let d = (1.0 + k) * (1.0 + k);
            ([(1.0 / d, 0.0), (2.0 * k / d, td / 2.0), (k * k / d, td)], 3)
        } else {
            ([(1.0 / (1.0 + k), 0.0), (k / (1.0 + k), td / 2.0), (0.0, 0.0)], 2)
        }
    }

    /// The residual vibration ratio V(f, ζ) of the shaper on a mode of frequency `f` (Hz)
    /// and damping `zeta`: the amplitude of the vibration a shaped move leaves over the one
    /// the same move leaves unshaped, compared at the same time after the move's start,
    /// |Σ Aᵢ·exp(ζωtᵢ)·exp(jω_d·tᵢ)|. (Singer and Seering's V carries a further
    /// exp(-ζω·t_N): it compares with the unshaped vibration t_N earlier.)
    pub fn residual_vibration(&self, f: f64, zeta: f64) -> f64 {
        let (impulses, n) = self.impulses();
        let wn = 2.0 * PI * f;
        let wd = wn * (1.0 - zeta * zeta).sqrt();
        let (mut c, mut s) = (0.0, 0.0);
        for &(a, t) in &impulses[..n] {
            let grown = a * (zeta * wn * t).exp();
            c += grown * (wd * t).cos();
            s += grown * (wd * t).sin();
        }
        (c * c + s * s).sqrt()
    }
}

/// The input shaper of one axis or one group coordinate.
pub(crate) struct InputShaper {
    /// The latest inputs, newest at `head`; room for the longest delay at this cycle.
    line: Vec<Kinematics>,
    head: usize,
    /// Inputs written since the shaper came to rest at `rest`; older ones are `rest`.
    written: usize,
    rest: Kinematics,
    /// Amplitudes and delays in cycles (fractional).
    impulses: [(f64, f64); 3],
    count: usize,
    params: ShaperParams,
    enabled: bool,
    period_s: f64,
    /// How many of the latest inputs are equal: the output has settled once they span
    /// the last impulse's delay.
    unchanged: usize,
}

impl InputShaper {
    /// Room for the longest delay of a shaper down to `min_freq_hz` at this cycle,
    /// allocated once, at start-up.
    pub fn new(min_freq_hz: f64, period_s: f64) -> Self {
        let longest = ShaperParams { freq_hz: min_freq_hz, damping: MAX_SHAPER_DAMPING, robust: true }.damped_period();
        let room = (longest / period_s).ceil() as usize + 2;
        let mut shaper = InputShaper {
            line: vec![Kinematics::default(); room],
            head: 0,
            written: 0,
            rest: Kinematics::default(),
            impulses: [(1.0, 0.0); 3],
            count: 1,
            params: DEFAULT_SHAPER,
            enabled: false,
            period_s,
            unchanged: usize::MAX,
        };
        shaper.configure(DEFAULT_SHAPER);
        shaper
    }

    pub fn is_enabled(&self) -> bool {
        self.enabled
    }

    /// Whether the shaper's delays fit the room reserved at start-up.
    pub fn fits(&self, params: ShaperParams) -> bool {
        let (impulses, n) = params.impulses();
        impulses[n - 1].1 / self.period_s + 1.0 < self.line.len() as f64
    }

    /// New parameters (taken at rest: the caller rests the shaper). The caller has checked
    /// that they `fit`.
    pub fn configure(&mut self, params: ShaperParams) {
        let (impulses, n) = params.impulses();
        for (slot, &(a, t)) in self.impulses.iter_mut().zip(&impulses[..n]) {
            *slot = (a, t / self.period_s);
        }
        self.count = n;
        self.params = params;
    }

    /// On or off, at rest at `pos`.
    pub fn set_enabled(&mut self, on: bool, pos: f64) {
        self.enabled = on;
        self.rest_at(pos);
    }

    /// At rest at `pos`, in one step whatever the room.
    pub fn rest_at(&mut self, pos: f64) {
        self.rest = Kinematics { pos, vel: 0.0, acc: 0.0 };
        self.written = 0;
        self.unchanged = usize::MAX;
    }

    /// The input `back` cycles ago (0: the newest).
    fn input(&self, back: usize) -> Kinematics {
        if back >= self.written {
            return self.rest;
        }
        self.line[(self.head + self.line.len() - back) % self.line.len()]
    }

    pub fn settled(&self) -> bool {
        !self.enabled || self.unchanged as f64 > self.impulses[self.count - 1].1 + 1.0
    }

    /// Takes the newest input, returns the shaped output.
    pub fn push(&mut self, k: Kinematics) -> Kinematics {
        if !self.enabled {
            return k;
        }
        let same = self.input(0) == k;
        self.unchanged = if same { self.unchanged.saturating_add(1) } else { 1 };
        self.head = (self.head + 1) % self.line.len();
        self.line[self.head] = k;
        self.written = (self.written + 1).min(self.line.len());
        if self.settled() {
            // Exactly the input, not a sum of its parts.
            return k;
        }
        let mut out = Kinematics::default();
        for &(a, delay) in &self.impulses[..self.count] {
            let whole = delay.floor();
            let frac = delay - whole;
            let (near, far) = (self.input(whole as usize), self.input(whole as usize + 1));
            out.pos += a * (near.pos + (far.pos - near.pos) * frac);
            out.vel += a * (near.vel + (far.vel - near.vel) * frac);
            out.acc += a * (near.acc + (far.acc - near.acc) * frac);
        }
        out
    }
}

/// What SetAxisVsf sets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VsfParams {
    /// The notch's frequency, Hz.
    pub freq_hz: f64,
    /// The damping ratio of the notch's poles: the wider, the larger.
    pub damping: f64,
}

/// The VSF until SetAxisVsf: the manual gives no default (docs/decisions.md, "Filters").
pub const DEFAULT_VSF: VsfParams = VsfParams { freq_hz: 10.0, damping: 1.0 };

/// The vibration suppression filter of one axis: a notch, one biquad per quantity
/// (transposed direct form II).
pub struct Vsf {
    /// b0, b1, b2, a1, a2 (a0 = 1).
    coefficients: [f64; 5],
    /// The two states of each of pos, vel, acc.
    state: [[f64; 2]; 3],
    input: Kinematics,
    params: VsfParams,
    enabled: bool,
    period_s: f64,
    at_rest: bool,
}

/// Below this the notch's output counts as on its input (axis units, per s and s² for the
/// velocity and acceleration): a nanometre (or microdegree), far below a count of any
/// drive, where the filter's exponential tail no longer moves the motor.
const VSF_SETTLED: f64 = 1e-6;

impl Vsf {
    /// A notch for a cycle of `period_s`, switched off, with [`DEFAULT_VSF`].
    pub fn new(period_s: f64) -> Self {
        let mut vsf = Vsf {
            coefficients: [1.0, 0.0, 0.0, 0.0, 0.0],
            state: [[0.0; 2]; 3],
            input: Kinematics::default(),
            params: DEFAULT_VSF,
            enabled: false,
            period_s,
            at_rest: true,
        };
        vsf.configure(vsf.params);
        vsf
    }

    pub(crate) fn is_enabled(&self) -> bool {
        self.enabled
    }

    /// Whether the notch lies below the cycle's Nyquist frequency, where the bilinear
    /// transform can place it.
    pub fn fits(&self, params: VsfParams) -> bool {
        params.freq_hz * self.period_s < 0.45
    }

    /// New parameters (the caller has checked that they `fit` and rests the filter).
    pub fn configure(&mut self, params: VsfParams) {
        let w = 2.0 * PI * params.freq_hz;
        // Prewarped: the discrete notch sits exactly at f.
        let k = w / (w * self.period_s / 2.0).tan();
        let (k2, w2, d) = (k * k, w * w, 2.0 * params.damping * w * k);
        let a0 = k2 + d + w2;
        self.coefficients =
            [(k2 + w2) / a0, 2.0 * (w2 - k2) / a0, (k2 + w2) / a0, 2.0 * (w2 - k2) / a0, (k2 - d + w2) / a0];
        self.params = params;
    }

    pub(crate) fn set_enabled(&mut self, on: bool, pos: f64) {
        self.enabled = on;
        self.rest_at(pos);
    }

    /// The residual vibration ratio of the notch on a mode of frequency `f` (Hz) and
    /// damping `zeta`, as `ShaperParams::residual_vibration`: the mode's free vibration
    /// e^(s·t), s = -ζω + jω_d, passes a linear filter scaled by |H| at s, here the
    /// discrete |H(z)| at z = e^(s·T). (The filter's own transient, e^(-ζ_vsf·ω_vsf·t),
    /// is gone a few of its time constants after the move.)
    pub fn residual_vibration(&self, f: f64, zeta: f64) -> f64 {
        let w = 2.0 * PI * f;
        let (re, im) = (-zeta * w * self.period_s, w * (1.0 - zeta * zeta).sqrt() * self.period_s);
        // z⁻¹ and z⁻² as (re, im).
        let r = (-re).exp();
        let z1 = (r * (-im).cos(), r * (-im).sin());
        let z2 = (z1.0 * z1.0 - z1.1 * z1.1, 2.0 * z1.0 * z1.1);
        let [b0, b1, b2, a1, a2] = self.coefficients;
        let num = (b0 + b1 * z1.0 + b2 * z2.0, b1 * z1.1 + b2 * z2.1);
        let den = (1.0 + a1 * z1.0 + a2 * z2.0, a1 * z1.1 + a2 * z2.1);
        num.0.hypot(num.1) / den.0.hypot(den.1)
    }

    /// At rest at `pos`: the states of a constant input that the filter passes unchanged.
    pub fn rest_at(&mut self, pos: f64) {
        self.input = Kinematics { pos, vel: 0.0, acc: 0.0 };
        let [b0, _, b2, _, a2] = self.coefficients;
        // TDF-II at rest on x with output x: s2 = (b2 - a2)·x, s1 = (1 - b0)·x.
        self.state = [[(1.0 - b0) * pos, (b2 - a2) * pos], [0.0; 2], [0.0; 2]];
        self.at_rest = true;
    }

    fn settled(&self) -> bool {
        !self.enabled || self.at_rest
    }

    pub(crate) fn push(&mut self, k: Kinematics) -> Kinematics {
        if !self.enabled {
            return k;
        }
        if self.at_rest && k == self.input {
            return k;
        }
        let [b0, b1, b2, a1, a2] = self.coefficients;
        let step = |s: &mut [f64; 2], x: f64| {
            let y = b0 * x + s[0];
            s[0] = b1 * x - a1 * y + s[1];
            s[1] = b2 * x - a2 * y;
            y
        };
        let [sp, sv, sa] = &mut self.state;
        let out = Kinematics { pos: step(sp, k.pos), vel: step(sv, k.vel), acc: step(sa, k.acc) };
        let still = k.vel == 0.0 && k.acc == 0.0 && k.pos == self.input.pos;
        self.input = k;
        if still && (out.pos - k.pos).abs() < VSF_SETTLED && out.vel.abs() < VSF_SETTLED && out.acc.abs() < VSF_SETTLED
        {
            // Come to rest on the input: from now on exactly the input.
            self.rest_at(k.pos);
            return k;
        }
        self.at_rest = false;
        out
    }
}

/// The two vibration stages of an axis' chain: at most one of them on (HMPL 15.1).
pub(crate) struct Vibration {
    pub vsf: Vsf,
    pub shaper: InputShaper,
}

impl Vibration {
    pub fn new(min_freq_hz: f64, period_s: f64) -> Self {
        Vibration { vsf: Vsf::new(period_s), shaper: InputShaper::new(min_freq_hz, period_s) }
    }

    #[inline]
    pub fn push(&mut self, k: Kinematics) -> Kinematics {
        self.shaper.push(self.vsf.push(k))
    }

    pub fn rest_at(&mut self, pos: f64) {
        self.vsf.rest_at(pos);
        self.shaper.rest_at(pos);
    }

    pub fn settled(&self) -> bool {
        self.vsf.settled() && self.shaper.settled()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const PERIOD: f64 = 1e-3;

    fn at(pos: f64) -> Kinematics {
        Kinematics { pos, vel: 0.0, acc: 0.0 }
    }

    /// A ZV shaper's response to a step: 1/(1+K) at once, the rest T_d/2 later.
    #[test]
    fn a_zv_shaper_splits_a_step_in_two_at_half_the_damped_period() {
        let params = ShaperParams { freq_hz: 10.0, damping: 0.1, robust: false };
        let mut s = InputShaper::new(1.5, PERIOD);
        s.configure(params);
        s.set_enabled(true, 0.0);
        let k = (-0.1 * PI / (1.0f64 - 0.01).sqrt()).exp();
        let half = 0.5 / (10.0 * (1.0f64 - 0.01).sqrt()) / PERIOD; // 50.25 cycles
        let frac = half - 50.0;
        let out: Vec<f64> = (0..60).map(|_| s.push(at(1.0)).pos).collect();
        assert!((out[0] - 1.0 / (1.0 + k)).abs() < 1e-12, "{}", out[0]);
        assert!((out[49] - 1.0 / (1.0 + k)).abs() < 1e-12, "still the first impulse at 49 < {half}");
        // Cycle 50 lies a quarter cycle before the second impulse: interpolated.
        assert!((out[50] - (1.0 / (1.0 + k) + (1.0 - frac) * k / (1.0 + k))).abs() < 1e-12, "{}", out[50]);
        assert_eq!(out[52], 1.0, "settled exactly");
        assert!(s.settled());
    }

    /// The shaper's theory: no vibration left on the mode it is tuned to, ZVD flatter
    /// around it than ZV, amplitudes summing to 1.
    #[test]
    fn residual_vibration_of_the_shapers() {
        for robust in [false, true] {
            let p = ShaperParams { freq_hz: 8.0, damping: 0.05, robust };
            let (imp, n) = p.impulses();
            assert!((imp[..n].iter().map(|i| i.0).sum::<f64>() - 1.0).abs() < 1e-15);
            assert!(p.residual_vibration(8.0, 0.05) < 1e-12, "tuned: none left");
        }
        let zv = ShaperParams { freq_hz: 8.0, damping: 0.0, robust: false };
        let zvd = ShaperParams { robust: true, ..zv };
        // ZV, undamped: V = |cos(π/2 · f/f0)|; at 1.2 f0: cos(0.6π) = 0.309.
        assert!((zv.residual_vibration(9.6, 0.0) - (0.6 * PI).cos().abs()).abs() < 1e-12);
        assert!(zvd.residual_vibration(9.6, 0.0) < zv.residual_vibration(9.6, 0.0) / 2.0);
    }

    /// The notch passes a standstill unchanged, takes out a sine at its frequency and
    /// comes to rest exactly on a step.
    #[test]
    fn the_vsf_notch() {
        let mut v = Vsf::new(PERIOD);
        v.configure(VsfParams { freq_hz: 20.0, damping: 1.0 });
        v.set_enabled(true, 3.0);
        assert_eq!(v.push(at(3.0)), at(3.0));
        let mut peak = 0.0f64;
        for i in 0..4000 {
            let y = v.push(at(3.0 + (2.0 * PI * 20.0 * i as f64 * PERIOD).sin())).pos - 3.0;
            if i > 2000 {
                peak = peak.max(y.abs());
            }
        }
        assert!(peak < 1e-3, "a sine at the notch is gone: {peak}");
        v.rest_at(0.0);
        let mut last = at(0.0);
        for _ in 0..2000 {
            last = v.push(at(1.0));
        }
        assert_eq!(last, at(1.0), "at rest on the step");
        assert!(v.settled());
    }

    /// Rest and disable in one step, whatever the room.
    #[test]
    fn an_off_shaper_passes_through_and_rest_is_immediate() {
        let mut s = InputShaper::new(1.5, PERIOD);
        let k = Kinematics { pos: 1.0, vel: 2.0, acc: 3.0 };
        assert_eq!(s.push(k), k);
        s.set_enabled(true, 5.0);
        assert_eq!(s.push(at(5.0)), at(5.0), "at rest");
        assert!(s.fits(ShaperParams { freq_hz: 1.5, damping: 0.3, robust: true }));
        assert!(!InputShaper::new(3.0, PERIOD).fits(ShaperParams { freq_hz: 1.5, damping: 0.3, robust: true }));
    }
}

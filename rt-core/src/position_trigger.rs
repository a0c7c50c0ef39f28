//! HMPL ch. 12: the position trigger (PT). On a HIWIN E1 drive the comparator runs in the
//! drive at its position sampling rate; here it runs on the RT thread after the kernel's
//! step, on each axis' feedback of this cycle and the one before: the position is taken as
//! moving linearly between the two samples, so each point crossed gets its crossing time
//! within the cycle. A drive fires at most one pulse per position sample (16 kHz, HMPL
//! 12.1.1), which is where "velocity < interval x sampling frequency" comes from: a point
//! crossed in the same drive sample as the pulse before is counted as missed, not pulsed
//! (docs/decisions.md, "Position trigger"). Each pulse shows on the axis' controller GPO
//! (`[axes.pt] output`) for one cycle and in the trace with its position and time.
//! The comparator follows the drive's travel: `SetPos` moving the origin crosses no point,
//! and a homing, which redefines the drive's position, ends the pass.
//!
//! Everything is allocated in `new`; `step` only writes fixed arrays.

use config::MachineConfig;
use schema::{MAX_AXES, PtSnapshot};

use crate::io::ControllerIo;
use kernel::Kernel;

/// HMPL 12.9: the position array's length.
pub const ARRAY_LEN: usize = 256;
/// HMPL 12.10: state words of 32 bits, one bit per array point.
pub const STATE_WORDS: usize = 8;
/// HMPL 12.1.1: the drive's position sampling frequency, Hz.
pub const SAMPLING_HZ: u64 = 16_000;
/// HMPL 12.8: the E1's pulse widths, ns.
pub const PULSE_WIDTH_NS: std::ops::RangeInclusive<i64> = 20..=80_000;
/// Pulses of a pass kept for `GetPTPulse`.
pub const PULSE_LOG: usize = 256;
/// Pulses of one axis and cycle the trace is handed, and that a trace row carries of all
/// axes together; more in one cycle are counted in the axes' columns only.
pub const TRACE_PULSES: usize = 8;

/// Why a PT function was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PtError {
    /// The axis' drive has no position trigger.
    NoTrigger,
    /// HMPL 12.1: the drive must have completed its homing.
    NotHomed,
    /// An argument out of its range, or a pass with no points.
    InvalidParameter,
}

/// One pulse: the point crossed and when.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pulse {
    /// The trigger point crossed, axis units.
    pub pos: f64,
    /// Controller time of the crossing, ms: cycle start plus the fraction of the cycle.
    pub time_ms: f64,
}

/// Which points a pass runs over: the last kind of setter called chooses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    Equidistant,
    Array,
}

#[derive(Clone, Copy, Debug)]
struct Settings {
    start: f64,
    end: f64,
    interval: f64,
    positions: [f64; ARRAY_LEN],
    states: [u32; STATE_WORDS],
    start_index: usize,
    end_index: usize,
    mode: Mode,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            start: 0.0,
            end: 0.0,
            interval: 0.0,
            positions: [0.0; ARRAY_LEN],
            states: [u32::MAX; STATE_WORDS],
            start_index: 0,
            end_index: 0,
            mode: Mode::Equidistant,
        }
    }
}

/// A pass under way: its points are fixed when it starts.
#[derive(Clone, Copy, Debug)]
struct Pass {
    settings: Settings,
    points: u64,
    next: u64,
    positive: bool,
    /// The drive sample of the last pulse.
    last_sample: Option<u64>,
}

impl Pass {
    /// Point `k` of the pass and whether it pulses (its state bit in array mode).
    fn point(&self, k: u64) -> (f64, bool) {
        let s = &self.settings;
        match s.mode {
            Mode::Equidistant => {
                let step = if self.positive { s.interval } else { -s.interval };
                (s.start + k as f64 * step, true)
            }
            Mode::Array => {
                let i = if self.positive { s.start_index + k as usize } else { s.start_index - k as usize };
                (s.positions[i], s.states[i / 32] & (1 << (i % 32)) != 0)
            }
        }
    }
}

/// One axis' trigger.
struct AxisTrigger {
    /// The controller GPO (1..8) the output is wired to.
    output: i64,
    settings: Settings,
    pass: Option<Pass>,
    /// The drive's position at the last sample (before the axis' origin offset).
    prev_drive: f64,
    log: Box<[Pulse; PULSE_LOG]>,
    pulses: u32,
    missed: u32,
    /// This cycle's pulses, for the trace.
    cycle_pulses: [Pulse; TRACE_PULSES],
    cycle_count: u32,
}

impl AxisTrigger {
    fn new(output: i64) -> Self {
        AxisTrigger {
            output,
            settings: Settings::default(),
            pass: None,
            prev_drive: 0.0,
            log: Box::new([Pulse::default(); PULSE_LOG]),
            pulses: 0,
            missed: 0,
            cycle_pulses: [Pulse::default(); TRACE_PULSES],
            cycle_count: 0,
        }
    }

    fn enable(&mut self) -> Result<(), PtError> {
        let s = self.settings;
        let (points, positive) = match s.mode {
            Mode::Equidistant => {
                let span = (s.end - s.start).abs();
                if s.interval <= 0.0 && span > 0.0 {
                    return Err(PtError::InvalidParameter);
                }
                // The end point counts when it lies on the grid up to rounding.
                let steps = if span == 0.0 { 0.0 } else { (span / s.interval + 1e-9).floor() };
                if steps >= u32::MAX as f64 {
                    return Err(PtError::InvalidParameter);
                }
                (steps as u64 + 1, s.end >= s.start)
            }
            Mode::Array => (s.start_index.abs_diff(s.end_index) as u64 + 1, s.end_index >= s.start_index),
        };
        self.pass = Some(Pass { settings: s, points, next: 0, positive, last_sample: None });
        self.pulses = 0;
        self.missed = 0;
        Ok(())
    }

    /// Fires the points the feedback crossed between the last sample and `fb`, the drive
    /// standing at `drive` (so `drive - fb` is the origin offset now); `samples` drive
    /// samples per cycle.
    fn step(&mut self, cycle: u64, fb: f64, drive: f64, period_ms: f64, samples: u64) {
        // The last sample in today's coordinates: a new origin moves no point past the axis.
        let prev = std::mem::replace(&mut self.prev_drive, drive) - (drive - fb);
        self.cycle_count = 0;
        let Some(pass) = &mut self.pass else { return };
        while pass.next < pass.points {
            let (p, pulses) = pass.point(pass.next);
            // Crossed in the pass' direction since the last sample; a point the axis stood
            // beyond when the pass began waits until the axis comes back over it.
            let crossed = if pass.positive { prev < p && p <= fb } else { prev > p && p >= fb };
            if !crossed {
                break;
            }
            let fraction = (p - prev) / (fb - prev);
            pass.next += 1;
            if !pulses {
                continue;
            }
            let sample = (cycle - 1) * samples + (fraction * samples as f64).ceil() as u64;
            if pass.last_sample == Some(sample) {
                self.missed += 1;
                continue;
            }
            pass.last_sample = Some(sample);
            let pulse = Pulse { pos: p, time_ms: ((cycle - 1) as f64 + fraction) * period_ms };
            if let Some(slot) = self.log.get_mut(self.pulses as usize) {
                *slot = pulse;
            }
            if let Some(slot) = self.cycle_pulses.get_mut(self.cycle_count as usize) {
                *slot = pulse;
            }
            self.pulses = self.pulses.saturating_add(1);
            self.cycle_count += 1;
        }
        if pass.next >= pass.points {
            self.pass = None;
        }
    }
}

/// Every axis' position trigger, stepped once a cycle after the kernel.
#[derive(Default)]
pub struct PositionTriggers {
    /// Boxed: a trigger holds this cycle's pulses (4.4 KB), and the cycle looks at every
    /// axis' entry, which unboxed cost a cache miss each (2 % of the RT thread at 96 axes).
    axes: Vec<Option<Box<AxisTrigger>>>,
    /// GPOs the triggers set high last cycle (bit i = pin i + 1).
    high: u8,
}

impl PositionTriggers {
    /// A trigger for each axis the machine file gives one (`pt`), all disabled.
    pub fn new(config: &MachineConfig) -> Self {
        let axes = config.axes.iter().map(|a| a.pt.as_ref().map(|pt| Box::new(AxisTrigger::new(pt.output)))).collect();
        PositionTriggers { axes, high: 0 }
    }

    fn axis(&mut self, axis: usize) -> Result<&mut AxisTrigger, PtError> {
        self.axes.get_mut(axis).and_then(Option::as_deref_mut).ok_or(PtError::NoTrigger)
    }

    /// HMPL 12.2: a new pass over the points set last; the axis must be homed.
    pub fn enable(&mut self, axis: usize, homed: bool) -> Result<(), PtError> {
        let trigger = self.axis(axis)?;
        if !homed {
            return Err(PtError::NotHomed);
        }
        trigger.enable()
    }

    /// HMPL 12.3.
    pub fn disable(&mut self, axis: usize) -> Result<(), PtError> {
        self.axis(axis)?.pass = None;
        Ok(())
    }

    pub(crate) fn set_start_pos(&mut self, axis: usize, pos: f64) -> Result<(), PtError> {
        self.equidistant(axis, |s| s.start = pos)
    }

    pub(crate) fn set_end_pos(&mut self, axis: usize, pos: f64) -> Result<(), PtError> {
        self.equidistant(axis, |s| s.end = pos)
    }

    pub(crate) fn set_interval(&mut self, axis: usize, interval: f64) -> Result<(), PtError> {
        if interval <= 0.0 {
            return Err(PtError::InvalidParameter);
        }
        self.equidistant(axis, |s| s.interval = interval)
    }

    /// HMPL 12.8: 20..80000 ns in steps of 20. Checked only: every width is shorter than a
    /// cycle, so the GPO shows each pulse for one cycle whatever it is.
    pub fn set_pulse_width(&mut self, axis: usize, width_ns: i64) -> Result<(), PtError> {
        self.axis(axis)?;
        if !PULSE_WIDTH_NS.contains(&width_ns) || width_ns % 20 != 0 {
            return Err(PtError::InvalidParameter);
        }
        Ok(())
    }

    pub(crate) fn set_pos_array(&mut self, axis: usize, index: i64, pos: f64) -> Result<(), PtError> {
        self.array(axis, index, ARRAY_LEN, |s, i| s.positions[i] = pos)
    }

    pub(crate) fn set_state_array(&mut self, axis: usize, index: i64, state: i64) -> Result<(), PtError> {
        // A 32-bit word: C's int, or its bits read as unsigned.
        let word = u32::try_from(state).or_else(|_| i32::try_from(state).map(|w| w as u32));
        let word = word.map_err(|_| PtError::InvalidParameter)?;
        let trigger = self.axis(axis)?;
        let i = usize::try_from(index).ok().filter(|&i| i < STATE_WORDS).ok_or(PtError::InvalidParameter)?;
        trigger.settings.states[i] = word;
        Ok(())
    }

    pub(crate) fn set_start_index(&mut self, axis: usize, index: i64) -> Result<(), PtError> {
        self.array(axis, index, ARRAY_LEN, |s, i| s.start_index = i)
    }

    pub(crate) fn set_end_index(&mut self, axis: usize, index: i64) -> Result<(), PtError> {
        self.array(axis, index, ARRAY_LEN, |s, i| s.end_index = i)
    }

    /// Pulse `n` of the axis' last pass.
    pub fn pulse(&mut self, axis: usize, n: i64) -> Result<Pulse, PtError> {
        let trigger = self.axis(axis)?;
        let kept = (trigger.pulses as usize).min(PULSE_LOG);
        usize::try_from(n).ok().filter(|&n| n < kept).map(|n| trigger.log[n]).ok_or(PtError::InvalidParameter)
    }

    fn equidistant(&mut self, axis: usize, set: impl FnOnce(&mut Settings)) -> Result<(), PtError> {
        let settings = &mut self.axis(axis)?.settings;
        set(settings);
        settings.mode = Mode::Equidistant;
        Ok(())
    }

    fn array(
        &mut self,
        axis: usize,
        index: i64,
        len: usize,
        set: impl FnOnce(&mut Settings, usize),
    ) -> Result<(), PtError> {
        let settings = &mut self.axis(axis)?.settings;
        let i = usize::try_from(index).ok().filter(|&i| i < len).ok_or(PtError::InvalidParameter)?;
        set(settings, i);
        settings.mode = Mode::Array;
        Ok(())
    }

    /// Runs every trigger on this cycle's feedback and drives the PT outputs: a GPO is
    /// high in a cycle in which one of its axes pulsed, and the triggers take it low again
    /// in the next (a pulse of at most 80 µs is shorter than any cycle).
    pub(crate) fn step(&mut self, cycle: u64, period_ns: u64, kernel: &Kernel, io: &mut ControllerIo) {
        let period_ms = period_ns as f64 * 1e-6;
        let samples = (period_ns * SAMPLING_HZ / 1_000_000_000).max(1);
        let mut high = 0u8;
        for (trigger, axis) in self.axes.iter_mut().zip(kernel.axes()) {
            let Some(trigger) = trigger else { continue };
            if axis.is_homing() {
                trigger.pass = None;
            }
            trigger.step(cycle, axis.pos_fb(), axis.drive_position(), period_ms, samples);
            if trigger.cycle_count > 0 {
                high |= 1 << (trigger.output - 1);
            }
        }
        for pin in 1..=8i64 {
            let bit = 1u8 << (pin - 1);
            if (high | self.high) & bit != 0 {
                // Pins come from the validated machine file.
                let _ = io.set_gpo(pin, (high & bit != 0) as i64);
            }
        }
        self.high = high;
    }

    /// Each axis' trigger in the snapshot.
    pub fn fill(&self, out: &mut [PtSnapshot; MAX_AXES]) {
        for (out, trigger) in out.iter_mut().zip(&self.axes) {
            *out = match trigger {
                Some(t) => PtSnapshot { enabled: t.pass.is_some() as u32, pulses: t.pulses, missed: t.missed },
                None => PtSnapshot::default(),
            };
        }
    }

    /// Axes, with a trigger or not.
    pub fn axis_count(&self) -> usize {
        self.axes.len()
    }

    /// The pulses axis `axis` gave this cycle (at most `TRACE_PULSES`) and how many it gave.
    pub fn cycle_pulses(&self, axis: usize) -> (&[Pulse], u32) {
        match self.axes.get(axis).and_then(Option::as_ref) {
            Some(t) => (&t.cycle_pulses[..(t.cycle_count as usize).min(TRACE_PULSES)], t.cycle_count),
            None => (&[], 0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 16 drive samples in a 1 ms cycle.
    const SAMPLES: u64 = 16;

    fn trigger() -> AxisTrigger {
        AxisTrigger::new(1)
    }

    /// An equidistant pass from `start` to `end`, enabled.
    fn equidistant(start: f64, interval: f64, end: f64) -> AxisTrigger {
        let mut t = trigger();
        t.settings.start = start;
        t.settings.interval = interval;
        t.settings.end = end;
        t.enable().unwrap();
        t
    }

    /// Feedback `from + c x step` for cycles c = 1..=n.
    fn ramp(from: f64, step: f64, n: usize) -> Vec<f64> {
        (1..=n).map(|c| from + c as f64 * step).collect()
    }

    /// Runs `t` over feedback positions, one a cycle from cycle 1, and returns its pulses.
    fn run(t: &mut AxisTrigger, positions: &[f64]) -> Vec<Pulse> {
        for (c, &fb) in positions.iter().enumerate() {
            t.step(c as u64 + 1, fb, fb, 1.0, SAMPLES);
        }
        t.log[..(t.pulses as usize).min(PULSE_LOG)].to_vec()
    }

    #[test]
    fn equidistant_points_at_their_crossing_times_both_ways() {
        let mut t = equidistant(10.0, 1.0, 20.0);
        // 0.3 mm a cycle: point p is crossed at p / 0.3 cycles.
        let pulses = run(&mut t, &ramp(0.0, 0.3, 100));
        assert_eq!(pulses.len(), 11);
        for (k, pulse) in pulses.iter().enumerate() {
            let p = 10.0 + k as f64;
            assert_eq!(pulse.pos, p);
            assert!((pulse.time_ms - p / 0.3).abs() < 1e-9, "{pulse:?}");
        }
        assert!(t.pass.is_none(), "the pass ends after its last point");

        t.settings.start = 20.0;
        t.settings.end = 10.0;
        t.enable().unwrap();
        let pulses = run(&mut t, &ramp(30.0, -0.3, 100));
        let positions: Vec<f64> = pulses.iter().map(|p| p.pos).collect();
        assert_eq!(positions, (0..=10).rev().map(|k| 10.0 + k as f64).collect::<Vec<_>>());
        for pulse in &pulses {
            assert!((pulse.time_ms - (30.0 - pulse.pos) / 0.3).abs() < 1e-9, "{pulse:?}");
        }
    }

    #[test]
    fn negative_pass_ignores_positive_motion() {
        let mut t = equidistant(20.0, 1.0, 10.0);
        assert_eq!(run(&mut t, &ramp(0.0, 0.3, 100)).len(), 0, "forward over 10..20: no crossing downwards");
        assert!(t.pass.is_some());
        assert_eq!(run(&mut t, &ramp(30.0, -0.3, 100)).len(), 11);
    }

    #[test]
    fn array_with_state_words_and_reverse_indices() {
        let mut t = trigger();
        let pos = [10.0, 12.0, 13.0, 16.0, 17.0, 20.0, 22.0, 25.0, 26.0, 28.0, 30.0];
        t.settings.positions[..11].copy_from_slice(&pos);
        t.settings.mode = Mode::Array;
        t.settings.end_index = 10;
        // Points 1 and 4 give no pulse.
        t.settings.states[0] = !((1 << 1) | (1 << 4));
        t.enable().unwrap();
        let got: Vec<f64> = run(&mut t, &ramp(0.0, 0.25, 200)).iter().map(|p| p.pos).collect();
        assert_eq!(got, [10.0, 13.0, 16.0, 20.0, 22.0, 25.0, 26.0, 28.0, 30.0]);

        t.settings.states[0] = u32::MAX;
        t.settings.start_index = 10;
        t.settings.end_index = 0;
        t.enable().unwrap();
        let got: Vec<f64> = run(&mut t, &ramp(50.0, -0.25, 200)).iter().map(|p| p.pos).collect();
        assert_eq!(got, pos.iter().rev().copied().collect::<Vec<_>>());
    }

    #[test]
    fn faster_than_interval_times_sampling_misses_points() {
        let mut t = equidistant(0.5, 0.01, 1.5);
        // 1 mm a cycle = 1000 mm/s: 0.0625 mm a drive sample, 6.25 points in each.
        run(&mut t, &[1.0, 2.0]);
        // Points 0.5..1.5 lie in drive samples 8..24 (ceil(16 x fraction) on from cycle 1).
        assert_eq!((t.pulses, t.missed), (17, 84), "one pulse per drive sample that holds a point");
        // Below the limit (0.01 mm x 16 kHz = 160 mm/s) none is missed.
        t.enable().unwrap();
        t.prev_drive = 0.0;
        run(&mut t, &ramp(0.0, 0.15, 20));
        assert_eq!((t.pulses, t.missed), (101, 0));
    }

    /// HMPL 5.3.19 `SetPos` during a pass: the feedback jumps, the drive does not move.
    #[test]
    fn a_new_origin_crosses_no_point() {
        let mut t = equidistant(10.0, 1.0, 20.0);
        t.step(1, 5.0, 5.0, 1.0, SAMPLES);
        // The origin moves by -10: 5 mm now reads 15 mm.
        t.step(2, 15.0, 5.0, 1.0, SAMPLES);
        assert_eq!(t.pulses, 0, "no point crossed by the jump");
        // From 15 on, real travel crosses 16 (and 10..15 wait behind the axis).
        t.step(3, 16.5, 6.5, 1.0, SAMPLES);
        assert_eq!(t.pulses, 0, "10 comes first in the pass");
        let mut t = equidistant(16.0, 1.0, 20.0);
        t.step(1, 5.0, 5.0, 1.0, SAMPLES);
        t.step(2, 15.0, 5.0, 1.0, SAMPLES);
        t.step(3, 16.5, 6.5, 1.0, SAMPLES);
        assert_eq!(t.log[0], Pulse { pos: 16.0, time_ms: 2.0 + 1.0 / 1.5 });
    }

    #[test]
    fn settings_are_checked() {
        let mut config = MachineConfig::default();
        config.axes[0].pt = Some(config::PtConfig { output: 3 });
        let mut pt = PositionTriggers::new(&config);
        assert_eq!(pt.set_pulse_width(0, 1000), Ok(()));
        for bad in [0, 10, 1010, 80_020, -20] {
            assert_eq!(pt.set_pulse_width(0, bad), Err(PtError::InvalidParameter), "{bad}");
        }
        assert_eq!(pt.set_pos_array(0, 256, 1.0), Err(PtError::InvalidParameter));
        assert_eq!(pt.set_pos_array(0, -1, 1.0), Err(PtError::InvalidParameter));
        assert_eq!(pt.set_state_array(0, 8, 1), Err(PtError::InvalidParameter));
        assert_eq!(pt.set_state_array(0, 7, -1), Ok(()));
        assert_eq!(pt.set_interval(0, 0.0), Err(PtError::InvalidParameter));
        assert_eq!(pt.enable(0, false), Err(PtError::NotHomed));
        assert_eq!(pt.enable(1, true), Err(PtError::NoTrigger));
        // Equidistant without an interval over a span.
        pt.set_start_pos(0, 0.0).unwrap();
        pt.set_end_pos(0, 5.0).unwrap();
        assert_eq!(pt.enable(0, true), Err(PtError::InvalidParameter));
    }
}

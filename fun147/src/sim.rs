//! A reference [`Axes`]: straight lines at a constant vector frequency, started at full
//! speed, and a linear ramp to rest over `ramp_s` when a stop or pause decelerates. Time
//! advances only through [`SimAxes::advance`], which a test calls once per cycle.

use crate::axes::{Axes, AxisSet};

#[derive(Clone, Debug)]
struct Move {
    axes: AxisSet,
    start: [i64; 4],
    /// Travel (LIN) or ratio (LINE), pulses.
    delta: [i64; 4],
    /// |delta|.
    norm: f64,
    continuous: bool,
    /// Path covered, in units of |delta|.
    s: f64,
    speed: f64,
    velocity: f64,
    paused: bool,
    stopping: bool,
    braking: bool,
}

impl Move {
    fn offset(&self, axis: usize) -> i64 {
        (self.delta[axis] as f64 * self.s / self.norm).round() as i64
    }

    fn length(&self) -> f64 {
        if self.continuous { f64::INFINITY } else { self.norm }
    }
}

/// Four simulated pulse outputs.
#[derive(Clone, Debug)]
pub struct SimAxes {
    position: [i64; 4],
    moves: Vec<Move>,
    /// What a stopped move left unsent, until the axis moves again.
    dropped: [i64; 4],
    /// Time of a decelerating stop or pause from the move's speed, s.
    pub ramp_s: f64,
}

impl SimAxes {
    /// Four axes at 0, with a 0.1 s ramp.
    pub fn new() -> Self {
        SimAxes { position: [0; 4], moves: Vec::new(), dropped: [0; 4], ramp_s: 0.1 }
    }

    /// Puts an axis at a position (at rest).
    pub fn set_position(&mut self, axis: usize, pulses: i64) {
        self.position[axis] = pulses;
    }

    /// One cycle of `dt` seconds.
    pub fn advance(&mut self, dt: f64) {
        for m in &mut self.moves {
            let v0 = m.velocity;
            if m.braking {
                m.velocity = (v0 - m.speed / self.ramp_s * dt).max(0.0);
            }
            m.s = (m.s + (v0 + m.velocity) / 2.0 * dt).min(m.length());
            for axis in m.axes.iter() {
                self.position[axis] = m.start[axis] + m.offset(axis);
            }
            if m.braking && m.velocity == 0.0 {
                m.braking = false;
                if m.stopping {
                    for axis in m.axes.iter() {
                        self.dropped[axis] = m.delta[axis].abs() - m.offset(axis).abs();
                    }
                }
            }
        }
        self.moves.retain(|m| !(m.s >= m.length() || (m.stopping && m.velocity == 0.0)));
    }

    fn start(&mut self, delta: [i64; 4], speed_hz: f64, continuous: bool) {
        let axes = AxisSet((0..4).filter(|&i| delta[i] != 0).fold(0, |set, i| set | 1 << i));
        self.moves.retain(|m| !m.axes.overlaps(axes));
        axes.iter().for_each(|a| self.dropped[a] = 0);
        let norm = delta.iter().map(|&d| (d as f64).powi(2)).sum::<f64>().sqrt();
        if axes == AxisSet::NONE {
            return;
        }
        self.moves.push(Move {
            axes,
            start: self.position,
            delta,
            norm,
            continuous,
            s: 0.0,
            speed: speed_hz,
            velocity: speed_hz,
            paused: false,
            stopping: false,
            braking: false,
        });
    }

    fn touching(&mut self, axes: AxisSet) -> impl Iterator<Item = &mut Move> {
        self.moves.iter_mut().filter(move |m| m.axes.overlaps(axes))
    }
}

impl Default for SimAxes {
    fn default() -> Self {
        Self::new()
    }
}

impl Axes for SimAxes {
    fn start_line(&mut self, targets: [Option<i64>; 4], speed_hz: f64) {
        let delta = std::array::from_fn(|i| targets[i].map_or(0, |t| t - self.position[i]));
        self.start(delta, speed_hz, false);
    }

    fn start_continuous(&mut self, ratio: [i64; 4], speed_hz: f64) {
        self.start(ratio, speed_hz, true);
    }

    fn pause(&mut self, axes: AxisSet, decelerate: bool) {
        for m in self.touching(axes) {
            m.paused = true;
            m.braking = decelerate;
            if !decelerate {
                m.velocity = 0.0;
            }
        }
    }

    fn resume(&mut self, axes: AxisSet) {
        for m in self.touching(axes).filter(|m| !m.stopping) {
            (m.paused, m.braking, m.velocity) = (false, false, m.speed);
        }
    }

    fn stop(&mut self, axes: AxisSet, decelerate: bool) {
        for m in self.moves.iter_mut().filter(|m| m.axes.overlaps(axes)) {
            m.stopping = true;
            m.braking = decelerate && m.velocity > 0.0;
            if !m.braking {
                m.velocity = 0.0;
                for a in m.axes.iter().filter(|_| !m.continuous) {
                    self.dropped[a] = m.delta[a].abs() - m.offset(a).abs();
                }
            }
        }
        self.moves.retain(|m| !m.stopping || m.braking);
    }

    fn is_done(&self, axes: AxisSet) -> bool {
        !self.moves.iter().any(|m| m.axes.overlaps(axes))
    }

    fn position(&self) -> [i64; 4] {
        self.position
    }

    fn remaining(&self) -> [i64; 4] {
        let mut remaining = self.dropped;
        for m in self.moves.iter().filter(|m| !m.continuous) {
            m.axes.iter().for_each(|a| remaining[a] = m.delta[a].abs() - m.offset(a).abs());
        }
        remaining
    }

    fn frequency(&self) -> [f64; 4] {
        let mut frequency = [0.0; 4];
        for m in &self.moves {
            m.axes.iter().for_each(|a| frequency[a] = m.velocity * m.delta[a].abs() as f64 / m.norm);
        }
        frequency
    }
}

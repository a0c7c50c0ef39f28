//! What the drive senses along the axis' travel: the negative and positive limit switches,
//! the home switch and the touch probe inputs (each active over [L, R]), the encoder index
//! pulses and the hard stops. In
//! raw encoder counts, fixed to the machine (homing shifts the drive's coordinates, not
//! the switches).

use config::TravelConfig;

/// Signal edges found while the motor moved from one position to the next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Edge {
    /// The index mark at `at` was crossed (the position homing and 0x2021 use).
    Index {
        at: f64,
    },
    /// The index signal went high (`rising`) or low, at `at` (what a touch probe latches).
    IndexSignal {
        rising: bool,
        at: f64,
    },
    HomeSwitch {
        rising: bool,
        at: f64,
    },
    /// Touch probe input `input` (0 or 1) went high or low.
    ProbeInput {
        input: usize,
        rising: bool,
        at: f64,
    },
    NegativeLimit {
        rising: bool,
        at: f64,
    },
    PositiveLimit {
        rising: bool,
        at: f64,
    },
}

/// At most this many edges in one servo period.
pub const MAX_EDGES: usize = 12;

/// A fixed-size list of edges: the servo loop must not allocate.
#[derive(Clone, Copy, Debug)]
pub struct Edges {
    list: [Option<Edge>; MAX_EDGES],
    len: usize,
}

impl Default for Edges {
    fn default() -> Self {
        Edges { list: [None; MAX_EDGES], len: 0 }
    }
}

impl Edges {
    fn push(&mut self, edge: Edge) {
        if self.len < MAX_EDGES {
            self.list[self.len] = Some(edge);
            self.len += 1;
        }
    }

    pub fn iter(&self) -> impl Iterator<Item = Edge> + '_ {
        self.list[..self.len].iter().flatten().copied()
    }

    pub fn clear(&mut self) {
        self.len = 0;
    }

    pub fn extend(&mut self, other: &Edges) {
        for edge in other.iter() {
            self.push(edge);
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub struct Travel {
    pub negative_limit: Option<f64>,
    pub positive_limit: Option<f64>,
    pub home_switch: Option<(f64, f64)>,
    pub probe_inputs: [Option<(f64, f64)>; 2],
    pub index_pitch: Option<f64>,
    pub index_offset: f64,
    pub index_width: f64,
    pub negative_hard_stop: Option<f64>,
    pub positive_hard_stop: Option<f64>,
}

impl Travel {
    pub fn from_config(config: &TravelConfig, counts_per_unit: f64) -> Self {
        let counts = |v: f64| v * counts_per_unit;
        let pitch = config.index_pitch.map(counts);
        Travel {
            negative_limit: config.negative_limit.map(counts),
            positive_limit: config.positive_limit.map(counts),
            home_switch: config.home_switch.map(|[l, r]| (counts(l), counts(r))),
            probe_inputs: [config.probe_input_1, config.probe_input_2].map(|i| i.map(|[l, r]| (counts(l), counts(r)))),
            index_pitch: pitch,
            index_offset: counts(config.index_offset),
            // The pulse lasts 1 % of a turn, at least one count.
            index_width: pitch.map_or(1.0, |p| (p / 100.0).max(1.0)),
            negative_hard_stop: config.negative_hard_stop.map(counts),
            positive_hard_stop: config.positive_hard_stop.map(counts),
        }
    }

    pub fn negative_limit_active(&self, x: f64) -> bool {
        self.negative_limit.is_some_and(|l| x <= l)
    }

    pub fn positive_limit_active(&self, x: f64) -> bool {
        self.positive_limit.is_some_and(|l| x >= l)
    }

    pub fn home_switch_active(&self, x: f64) -> bool {
        self.home_switch.is_some_and(|(l, r)| (l..=r).contains(&x))
    }

    pub fn index_active(&self, x: f64) -> bool {
        self.index_pitch.is_some_and(|p| (x - self.index_offset).rem_euclid(p) < self.index_width)
    }

    /// The index marks strictly after `from` up to `to` in the direction of motion, nearest first.
    pub fn index_marks(&self, from: f64, to: f64) -> impl Iterator<Item = f64> {
        let (pitch, offset) = (self.index_pitch.unwrap_or(f64::INFINITY), self.index_offset);
        let forward = to >= from;
        let first = if !pitch.is_finite() || from == to {
            None
        } else if forward {
            Some(((from - offset) / pitch).floor() + 1.0)
        } else {
            Some(((from - offset) / pitch).ceil() - 1.0)
        };
        let mut k = first;
        std::iter::from_fn(move || {
            let n = k?;
            let at = offset + n * pitch;
            let inside = if forward { at <= to } else { at >= to };
            if !inside {
                return None;
            }
            k = Some(if forward { n + 1.0 } else { n - 1.0 });
            Some(at)
        })
    }

    /// Every edge between two positions of the motor, in order of travel.
    pub fn edges(&self, from: f64, to: f64, edges: &mut Edges) {
        if from == to {
            return;
        }
        let crossing = |active: &dyn Fn(f64) -> bool, boundary: f64| (active(from) != active(to)).then_some(boundary);
        if let Some(l) = self.negative_limit
            && let Some(at) = crossing(&|x| self.negative_limit_active(x), l)
        {
            edges.push(Edge::NegativeLimit { rising: to < from, at });
        }
        if let Some(l) = self.positive_limit
            && let Some(at) = crossing(&|x| self.positive_limit_active(x), l)
        {
            edges.push(Edge::PositiveLimit { rising: to > from, at });
        }
        if let Some(window) = self.home_switch {
            window_edges(window, from, to, |rising, at| edges.push(Edge::HomeSwitch { rising, at }));
        }
        for (input, window) in self.probe_inputs.iter().enumerate() {
            if let Some(window) = *window {
                window_edges(window, from, to, |rising, at| edges.push(Edge::ProbeInput { input, rising, at }));
            }
        }
        // The pulse is high over [mark, mark + width): moving positive it rises at the mark
        // and falls at its end; moving negative the other way round.
        let w = self.index_width;
        let (rise_shift, fall_shift) = if to > from { (0.0, w) } else { (w, 0.0) };
        for at in self.index_marks(from, to) {
            edges.push(Edge::Index { at });
        }
        for at in self.index_marks(from - rise_shift, to - rise_shift) {
            edges.push(Edge::IndexSignal { rising: true, at: at + rise_shift });
        }
        for at in self.index_marks(from - fall_shift, to - fall_shift) {
            edges.push(Edge::IndexSignal { rising: false, at: at + fall_shift });
        }
    }
}

/// The edges of a sensor active over `[l, r]` between two positions: entering on one side,
/// leaving on the other, or both within one step.
fn window_edges((l, r): (f64, f64), from: f64, to: f64, mut push: impl FnMut(bool, f64)) {
    let active = |x: f64| (l..=r).contains(&x);
    let (was, is) = (active(from), active(to));
    if was != is || (!was && from.min(to) < l && from.max(to) > r) {
        let (entry, exit) = if to > from { (l, r) } else { (r, l) };
        if !was {
            push(true, entry);
        }
        if !is {
            push(false, exit);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn travel() -> Travel {
        Travel {
            negative_limit: Some(-1000.0),
            positive_limit: Some(1000.0),
            home_switch: Some((100.0, 200.0)),
            probe_inputs: [Some((300.0, 310.0)), None],
            index_pitch: Some(50.0),
            index_offset: 10.0,
            index_width: 1.0,
            negative_hard_stop: None,
            positive_hard_stop: None,
        }
    }

    #[test]
    fn index_marks_in_either_direction_nearest_first() {
        let t = travel();
        assert_eq!(t.index_marks(0.0, 120.0).collect::<Vec<_>>(), vec![10.0, 60.0, 110.0]);
        assert_eq!(t.index_marks(120.0, 0.0).collect::<Vec<_>>(), vec![110.0, 60.0, 10.0]);
        assert_eq!(t.index_marks(10.0, 60.0).collect::<Vec<_>>(), vec![60.0], "strictly after the start");
    }

    #[test]
    fn switch_edges_are_where_the_switch_is() {
        let t = travel();
        let mut edges = Edges::default();
        t.edges(90.0, 105.0, &mut edges);
        assert!(edges.iter().any(|e| e == Edge::HomeSwitch { rising: true, at: 100.0 }));
        edges.clear();
        t.edges(205.0, 195.0, &mut edges);
        assert!(edges.iter().any(|e| e == Edge::HomeSwitch { rising: true, at: 200.0 }), "entering R moving negative");
        edges.clear();
        t.edges(999.0, 1001.0, &mut edges);
        assert!(edges.iter().any(|e| e == Edge::PositiveLimit { rising: true, at: 1000.0 }));
        edges.clear();
        t.edges(295.0, 315.0, &mut edges);
        let probe: Vec<_> = edges.iter().filter(|e| matches!(e, Edge::ProbeInput { .. })).collect();
        assert_eq!(
            probe,
            [
                Edge::ProbeInput { input: 0, rising: true, at: 300.0 },
                Edge::ProbeInput { input: 0, rising: false, at: 310.0 }
            ],
            "a probe input crossed within one step"
        );
    }
}

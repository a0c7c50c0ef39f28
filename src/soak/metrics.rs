//! The soak test's measurements: one histogram per metric (ns, 1 ns to 60 s, 3 significant
//! digits), the counters that must stay 0, and the form in which a worker process hands
//! them to the soak run.

use std::collections::BTreeMap;

use hdrhistogram::Histogram;
use serde::{Deserialize, Serialize};

pub fn histogram() -> Histogram<u64> {
    Histogram::new_with_bounds(1, 60_000_000_000, 3).expect("valid bounds")
}

/// Records `ns`, clamped into the histogram's range.
pub fn record(h: &mut Histogram<u64>, ns: u64) {
    let _ = h.record(ns.clamp(1, 60_000_000_000));
}

/// A histogram as (value, count) pairs, for JSON.
fn pairs(h: &Histogram<u64>) -> Vec<(u64, u64)> {
    h.iter_recorded().map(|v| (v.value_iterated_to(), v.count_at_value())).collect()
}

/// What the scripts counted: calls, and the replies that must stay 0.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize)]
pub struct CallCounts {
    pub commands: u64,
    pub queries: u64,
    /// Calls that raised a Lua error (a lost reply raises one).
    pub call_errors: u64,
    pub lost: u64,
    pub duplicated: u64,
    pub out_of_order: u64,
}

impl CallCounts {
    fn add(&mut self, other: &CallCounts) {
        self.commands += other.commands;
        self.queries += other.queries;
        self.call_errors += other.call_errors;
        self.lost += other.lost;
        self.duplicated += other.duplicated;
        self.out_of_order += other.out_of_order;
    }

    /// No reply lost, duplicated or out of order.
    pub fn clean(&self) -> bool {
        self.lost == 0 && self.duplicated == 0 && self.out_of_order == 0
    }
}

/// What one worker measured.
#[derive(Debug, Default, Serialize, Deserialize)]
pub struct WorkerResult {
    pub histograms: BTreeMap<String, Vec<(u64, u64)>>,
    pub counts: CallCounts,
    /// The process' CPU time over the workload, and the workload's wall time, ns.
    pub cpu_ns: u64,
    pub wall_ns: u64,
}

/// The metrics of a whole run, merged from the workers.
#[derive(Default)]
pub struct Merged {
    pub histograms: BTreeMap<String, Histogram<u64>>,
    pub counts: CallCounts,
}

impl WorkerResult {
    pub fn put(&mut self, name: &str, h: &Histogram<u64>) {
        self.histograms.insert(name.to_string(), pairs(h));
    }

    /// The histogram of metric `name` (empty when the worker recorded none).
    pub fn histogram(&self, name: &str) -> Histogram<u64> {
        let mut h = histogram();
        for &(value, count) in self.histograms.get(name).into_iter().flatten() {
            let _ = h.record_n(value.clamp(1, 60_000_000_000), count);
        }
        h
    }
}

impl Merged {
    pub fn add(&mut self, worker: &WorkerResult) {
        for name in worker.histograms.keys() {
            let h = self.histograms.entry(name.clone()).or_insert_with(histogram);
            let _ = h.add(worker.histogram(name));
        }
        self.counts.add(&worker.counts);
    }

    pub fn get(&self, name: &str) -> Option<&Histogram<u64>> {
        self.histograms.get(name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn workers_merge_into_one_histogram() {
        let mut a = histogram();
        let mut b = histogram();
        for v in [1_000, 2_000, 3_000] {
            record(&mut a, v);
        }
        record(&mut b, 1_000_000);
        let (mut wa, mut wb) = (
            WorkerResult { counts: CallCounts { commands: 3, ..Default::default() }, ..Default::default() },
            WorkerResult::default(),
        );
        wa.put("round trip", &a);
        wb.put("round trip", &b);
        let json = serde_json::to_string(&wa).unwrap();
        let back: WorkerResult = serde_json::from_str(&json).unwrap();
        let mut merged = Merged::default();
        merged.add(&back);
        merged.add(&wb);
        let h = merged.get("round trip").unwrap();
        assert_eq!((h.len(), merged.counts.commands), (4, 3));
        assert!(h.max() >= 1_000_000 && h.min() <= 1_000);
    }
}

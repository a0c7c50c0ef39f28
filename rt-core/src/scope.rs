//! The scope's RT end: each cycle, the channels a tool (or `run --scope`) asked for are
//! sampled from the snapshot and the shared data into the scope ring (`ipc::scope`), while
//! its gate is open (HMPL 2.17 `SetHMIScope`). A new channel request is taken over at the
//! start of a cycle; nothing here allocates or waits.

use calls::scope::Var;
use ipc::scope::{CHANNELS, ScopeRing};
use ipc::shm::Region;
use schema::Snapshot;
use schema::shared::SharedData;

/// The RT thread's writer of the scope ring: the channels asked for and this cycle's values.
pub struct ScopeSampler {
    ring: Region<ScopeRing>,
    vars: [Option<Var>; CHANNELS],
    len: usize,
    values: [f64; CHANNELS],
}

impl ScopeSampler {
    /// Samples into `ring`, no channel asked for yet.
    pub fn new(ring: Region<ScopeRing>) -> Self {
        ScopeSampler { ring, vars: [None; CHANNELS], len: 0, values: [0.0; CHANNELS] }
    }

    /// Records this cycle's row, if any channel is asked for and the gate is open.
    pub fn sample(&mut self, snapshot: &Snapshot, shared: &SharedData) {
        let mut codes = [0; CHANNELS];
        if let Some(len) = self.ring.take_request(&mut codes) {
            self.len = len;
            for (var, &code) in self.vars.iter_mut().zip(&codes[..len]) {
                *var = Var::from_code(code);
            }
        }
        if self.len == 0 || !self.ring.gate_open() {
            return;
        }
        for (value, var) in self.values.iter_mut().zip(&self.vars[..self.len]) {
            // A code this build does not know reads as NaN: the tool named it wrongly.
            *value = var.map_or(f64::NAN, |v| v.sample(snapshot, shared));
        }
        self.ring.push(snapshot.cycle, &self.values[..self.len]);
    }
}

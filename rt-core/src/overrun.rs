//! Why a cycle overran: the OS woke the RT thread late, or the cycle's work took too long
//! (docs/decisions.md, "Overrun causes").
//!
//! A cycle overruns when it ends after the next deadline: lateness L plus execution E
//! exceed the period P. With the wake-up allowance X (a tenth of the period), a late
//! wake-up is L > X and a long execution E > P - X; since L + E > P, every overrun is at
//! least one of the two, so "late only", "long only" and "both" add up to the overruns.
//! E is wall time: of the long executions, those whose own CPU time also exceeded P - X
//! were the cycle's own work; the rest were the thread preempted while it worked. (A VM
//! may charge a stall of its vCPU to the thread as CPU time: the soak measures how often
//! the machine alone does so, beside the count.)

/// The wake-up allowance: a tenth of the period.
pub fn wake_up_allowance_ns(period_ns: u64) -> u64 {
    period_ns / 10
}

/// What a cycle's work may take: the period less the wake-up allowance.
pub fn work_budget_ns(period_ns: u64) -> u64 {
    period_ns.saturating_sub(wake_up_allowance_ns(period_ns))
}

/// What is known of an overrun cycle at the next wake-up, ns.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OverrunCycle {
    /// How late it woke after its deadline.
    pub lateness_ns: u64,
    /// Its work's wall time.
    pub execution_ns: u64,
    /// The RT thread's CPU time from its wake-up to its sleep.
    pub cpu_ns: u64,
}

/// The overruns of a run by cause; plain counters, so the RT thread counts without allocating.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OverrunCauses {
    /// Woke more than the allowance late; the work itself fitted.
    pub late_wake_up: u64,
    /// Woke within the allowance; the work took more than the period less the allowance.
    pub long_execution: u64,
    /// Both at once.
    pub both: u64,
    /// Of `long_execution` and `both`, the cycles whose own CPU time exceeded the period
    /// less the allowance: overruns caused by the cycle's own work.
    pub own_work: u64,
}

impl OverrunCauses {
    /// Counts one overrun.
    pub fn count(&mut self, period_ns: u64, cycle: OverrunCycle) {
        let budget = work_budget_ns(period_ns);
        let late = cycle.lateness_ns > wake_up_allowance_ns(period_ns);
        // An overrun that woke in time must have worked past the budget (L + E > P).
        let long = cycle.execution_ns > budget || !late;
        match (late, long) {
            (true, true) => self.both += 1,
            (true, false) => self.late_wake_up += 1,
            _ => self.long_execution += 1,
        }
        if long && cycle.cpu_ns > budget {
            self.own_work += 1;
        }
    }

    /// All overruns counted.
    pub fn total(&self) -> u64 {
        self.late_wake_up + self.long_execution + self.both
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: u64 = 1_000_000;

    fn cycle(lateness_ns: u64, execution_ns: u64, cpu_ns: u64) -> OverrunCycle {
        OverrunCycle { lateness_ns, execution_ns, cpu_ns }
    }

    #[test]
    fn each_overrun_has_one_cause() {
        let mut c = OverrunCauses::default();
        c.count(P, cycle(500_000, 600_000, 100_000)); // late wake-up, the work fitted
        c.count(P, cycle(20_000, 990_000, 950_000)); // on time, the work itself too long
        c.count(P, cycle(20_000, 990_000, 300_000)); // on time, preempted while working
        c.count(P, cycle(300_000, 950_000, 950_000)); // both
        // CPU time counts from the wake-up to the sleep, the way out of and into the sleep
        // too, so it may exceed the execution: a late wake-up whose work fitted is still not
        // the work's fault.
        c.count(P, cycle(300_000, 800_000, 950_000));
        assert_eq!(c, OverrunCauses { late_wake_up: 2, long_execution: 2, both: 1, own_work: 2 });
        assert_eq!(c.total(), 5);
    }

    /// Every overrun (L + E > P) lands in exactly one of the three, whatever L and E.
    #[test]
    fn the_causes_add_up_to_the_overruns() {
        let mut c = OverrunCauses::default();
        let mut overruns = 0;
        for lateness in (0..=P).step_by(P as usize / 40) {
            for execution in (0..=P).step_by(P as usize / 40) {
                if lateness + execution > P {
                    overruns += 1;
                    c.count(P, cycle(lateness, execution, execution));
                }
            }
        }
        assert_eq!(c.total(), overruns);
        assert!(c.late_wake_up > 0 && c.long_execution > 0 && c.both > 0, "{c:?}");
        assert_eq!(c.own_work, c.long_execution + c.both, "CPU time = wall time: all long ones are own work");
    }
}

//! The master's side of the CiA 402 state machine: which controlword to send, cycle after
//! cycle, to bring a drive to Operation enabled or out of it (CoE manual 3.1, table 3-3).
//! Each step shows in the statusword one bus cycle later, so enabling takes several cycles,
//! as on a real drive.

use devices::cia402::{State, controlword};

/// Where the axis is on its way to or from being energised.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Power {
    Disabled,
    Enabling {
        since: u64,
    },
    Enabled,
    Disabling {
        since: u64,
    },
    /// Clearing a drive fault: controlword bit 7 low, then its rising edge (CoE manual 3.1).
    Resetting {
        since: u64,
        edge_sent: bool,
    },
    /// The drive's quick stop (CoE manual 3.1, transitions 11 and 12): Quick stop until the
    /// motor stands in Quick stop active, then Disable voltage.
    QuickStopping {
        since: u64,
    },
}

/// What one step of the sequence found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PowerEvent {
    None,
    /// The drive reached Operation enabled.
    Enabled,
    /// The drive left Operation enabled as asked.
    Disabled,
    /// The drive did not follow within the timeout.
    Timeout,
    /// The drive reports Fault or Fault reaction active.
    DriveFault,
    /// The drive left Operation enabled without being asked.
    AbnormalDisable,
    /// The drive's fault is cleared (Switch on disabled after the reset edge).
    FaultCleared,
}

impl Power {
    pub fn is_enabled(self) -> bool {
        self == Power::Enabled
    }

    /// One cycle: reads the drive's state, returns the controlword to send and what happened.
    /// `at_rest`: the motor stands (ends a quick stop).
    pub fn step(&mut self, drive: Option<State>, cycle: u64, timeout_cycles: u64, at_rest: bool) -> (u16, PowerEvent) {
        use controlword::*;
        if let Power::Resetting { since, edge_sent } = *self {
            return match drive {
                Some(State::Fault | State::FaultReactionActive) if cycle.saturating_sub(since) > timeout_cycles => {
                    *self = Power::Disabled;
                    (DISABLE_VOLTAGE, PowerEvent::Timeout)
                }
                Some(State::Fault | State::FaultReactionActive) => {
                    *self = Power::Resetting { since, edge_sent: !edge_sent };
                    (if edge_sent { DISABLE_VOLTAGE } else { FAULT_RESET }, PowerEvent::None)
                }
                _ => {
                    *self = Power::Disabled;
                    (SHUTDOWN, PowerEvent::FaultCleared)
                }
            };
        }
        if matches!(drive, Some(State::Fault | State::FaultReactionActive)) {
            let event = if *self == Power::Disabled { PowerEvent::None } else { PowerEvent::DriveFault };
            *self = Power::Disabled;
            return (SHUTDOWN, event);
        }
        match *self {
            Power::Disabled => (SHUTDOWN, PowerEvent::None),
            Power::Resetting { .. } => (DISABLE_VOLTAGE, PowerEvent::None),
            Power::QuickStopping { since } => match drive {
                Some(State::OperationEnabled) if cycle.saturating_sub(since) <= timeout_cycles => {
                    (QUICK_STOP_CMD, PowerEvent::None)
                }
                Some(State::QuickStopActive) if !at_rest && cycle.saturating_sub(since) <= timeout_cycles => {
                    (QUICK_STOP_CMD, PowerEvent::None)
                }
                _ => {
                    *self = Power::Disabled;
                    (DISABLE_VOLTAGE, PowerEvent::Disabled)
                }
            },
            Power::Enabling { since } => {
                let cw = match drive {
                    Some(State::OperationEnabled) => {
                        *self = Power::Enabled;
                        return (ENABLE_OPERATION_CMD, PowerEvent::Enabled);
                    }
                    Some(State::SwitchOnDisabled) => SHUTDOWN,
                    Some(State::ReadyToSwitchOn) => SWITCH_ON_CMD,
                    Some(State::SwitchedOn) => ENABLE_OPERATION_CMD,
                    _ => DISABLE_VOLTAGE,
                };
                if cycle.saturating_sub(since) > timeout_cycles {
                    *self = Power::Disabled;
                    return (SHUTDOWN, PowerEvent::Timeout);
                }
                (cw, PowerEvent::None)
            }
            Power::Enabled => {
                if drive == Some(State::OperationEnabled) {
                    (ENABLE_OPERATION_CMD, PowerEvent::None)
                } else {
                    *self = Power::Disabled;
                    (SHUTDOWN, PowerEvent::AbnormalDisable)
                }
            }
            Power::Disabling { since } => {
                if drive != Some(State::OperationEnabled) {
                    *self = Power::Disabled;
                    (SHUTDOWN, PowerEvent::Disabled)
                } else if cycle.saturating_sub(since) > timeout_cycles {
                    *self = Power::Disabled;
                    (SHUTDOWN, PowerEvent::Timeout)
                } else {
                    (SHUTDOWN, PowerEvent::None)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use devices::drive::fsa::Fsa;

    /// The master's sequence walks a drive from Switch on disabled to Operation enabled in
    /// a few cycles, with the one-cycle bus delay in each direction.
    #[test]
    fn the_enable_sequence_walks_a_drive_to_operation_enabled() {
        let mut fsa = Fsa::default();
        let mut power = Power::Enabling { since: 0 };
        let mut cw = 0;
        let mut enabled_at = None;
        for cycle in 0..20 {
            fsa.step(cw, true);
            let (next, event) = power.step(Some(fsa.state()), cycle, 100, false);
            cw = next;
            if event == PowerEvent::Enabled {
                enabled_at = Some(cycle);
                break;
            }
        }
        let cycles = enabled_at.expect("enabled");
        assert!(cycles >= 3, "takes several cycles, took {cycles}");
        assert_eq!(fsa.state(), State::OperationEnabled);
    }

    #[test]
    fn a_fault_is_cleared_by_the_rising_edge_of_bit_7() {
        let mut fsa = Fsa::default();
        fsa.step(0, true);
        fsa.fault();
        let mut power = Power::Resetting { since: 0, edge_sent: false };
        let mut cw = 0;
        for cycle in 0..10 {
            fsa.step(cw, true);
            let (next, event) = power.step(Some(fsa.state()), cycle, 100, false);
            cw = next;
            if event == PowerEvent::FaultCleared {
                assert_eq!(fsa.state(), State::SwitchOnDisabled);
                return;
            }
        }
        panic!("the fault was not cleared: {:?}", fsa.state());
    }

    /// CoE manual 3.1: Quick stop (11) to Quick stop active, which holds until the motor
    /// stands; then Disable voltage (12) to Switch on disabled.
    #[test]
    fn a_quick_stop_ends_in_switch_on_disabled() {
        let mut fsa = Fsa::default();
        let mut power = Power::Enabling { since: 0 };
        let mut cw = 0;
        for cycle in 0..20 {
            fsa.step(cw, true);
            cw = power.step(Some(fsa.state()), cycle, 100, false).0;
        }
        assert_eq!(fsa.state(), State::OperationEnabled);
        power = Power::QuickStopping { since: 20 };
        for cycle in 20..30 {
            fsa.step(cw, true);
            cw = power.step(Some(fsa.state()), cycle, 100, false).0;
        }
        assert_eq!((fsa.state(), cw), (State::QuickStopActive, controlword::QUICK_STOP_CMD), "held while moving");
        fsa.step(cw, true);
        let (next, event) = power.step(Some(fsa.state()), 30, 100, true);
        assert_eq!((next, event, power), (controlword::DISABLE_VOLTAGE, PowerEvent::Disabled, Power::Disabled));
        fsa.step(next, true);
        assert_eq!(fsa.state(), State::SwitchOnDisabled);
    }

    #[test]
    fn a_drive_that_never_follows_times_out() {
        let mut power = Power::Enabling { since: 0 };
        let mut last = PowerEvent::None;
        for cycle in 0..=11 {
            last = power.step(Some(State::NotReadyToSwitchOn), cycle, 10, false).1;
        }
        assert_eq!(last, PowerEvent::Timeout);
        assert_eq!(power, Power::Disabled);
    }
}

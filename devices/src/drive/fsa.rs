//! The drive's CiA 402 finite state automaton (CoE manual 3.1, tables 3-1 to 3-5).
//!
//! Transition numbers are those of CiA 402, which the manual's table 3-3 cites.

use crate::cia402::{Command, State, controlword};

/// A transition the controlword asks for: `(new state, CiA 402 transition number)`.
/// "3+4" (Switch on + Enable operation from Ready to switch on) is reported as 4.
///
/// Quick stop active only leaves on Disable voltage (12), as the manual lists it: HIWIN has
/// no 0x605A, so there is neither an automatic end of the quick stop nor transition 16 back
/// to Operation enabled (docs/drive.md). The stopped motor stays energised.
pub fn commanded(state: State, command: Command) -> Option<(State, u8)> {
    use Command::*;
    use State::*;
    match (state, command) {
        (SwitchOnDisabled, Shutdown) => Some((ReadyToSwitchOn, 2)),
        (ReadyToSwitchOn, SwitchOn) => Some((SwitchedOn, 3)),
        (ReadyToSwitchOn, EnableOperation) => Some((OperationEnabled, 4)),
        (ReadyToSwitchOn, DisableVoltage | QuickStop) => Some((SwitchOnDisabled, 7)),
        (SwitchedOn, EnableOperation) => Some((OperationEnabled, 4)),
        (SwitchedOn, Shutdown) => Some((ReadyToSwitchOn, 6)),
        (SwitchedOn, DisableVoltage | QuickStop) => Some((SwitchOnDisabled, 10)),
        (OperationEnabled, SwitchOn) => Some((SwitchedOn, 5)),
        (OperationEnabled, Shutdown) => Some((ReadyToSwitchOn, 8)),
        (OperationEnabled, DisableVoltage) => Some((SwitchOnDisabled, 9)),
        (OperationEnabled, QuickStop) => Some((QuickStopActive, 11)),
        (QuickStopActive, DisableVoltage) => Some((SwitchOnDisabled, 12)),
        _ => None,
    }
}

/// The automaton of one drive, with the controlword history it needs for edges.
#[derive(Clone, Debug)]
pub struct Fsa {
    state: State,
    fault_reset_bit: bool,
}

impl Default for Fsa {
    fn default() -> Self {
        Fsa { state: State::NotReadyToSwitchOn, fault_reset_bit: false }
    }
}

impl Fsa {
    /// The state the automaton is in.
    pub fn state(&self) -> State {
        self.state
    }

    /// One cycle of the automaton. `stopped` tells whether the motor has come to rest,
    /// which ends Fault reaction active.
    pub fn step(&mut self, cw: u16, stopped: bool) -> Option<u8> {
        let reset_edge = cw & controlword::FAULT_RESET != 0 && !self.fault_reset_bit;
        self.fault_reset_bit = cw & controlword::FAULT_RESET != 0;
        let (next, number) = match self.state {
            // Transitions 0 and 1: initialisation is done by the first cycle.
            State::NotReadyToSwitchOn => (State::SwitchOnDisabled, 1),
            State::FaultReactionActive if stopped => (State::Fault, 14),
            State::FaultReactionActive => return None,
            State::Fault if reset_edge => (State::SwitchOnDisabled, 15),
            State::Fault => return None,
            state => commanded(state, Command::decode(cw))?,
        };
        self.state = next;
        Some(number)
    }

    /// Transition 13: a fault in any state but Fault reaction active and Fault.
    pub fn fault(&mut self) {
        if !matches!(self.state, State::FaultReactionActive | State::Fault) {
            self.state = State::FaultReactionActive;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fsa_in(state: State) -> Fsa {
        Fsa { state, fault_reset_bit: false }
    }

    /// CoE manual 3.1, tables 3-3 and 3-5: from-state, controlword, expected state.
    #[test]
    fn transitions_used_by_the_enable_sequence() {
        use State::*;
        let rows: [(State, u16, State, &str); 12] = [
            (SwitchOnDisabled, 0x0006, ReadyToSwitchOn, "2: Shutdown"),
            (ReadyToSwitchOn, 0x0007, SwitchedOn, "3: Switch on"),
            (SwitchedOn, 0x000F, OperationEnabled, "4: Enable operation"),
            (ReadyToSwitchOn, 0x000F, OperationEnabled, "3+4: 0x000F goes through"),
            (OperationEnabled, 0x0007, SwitchedOn, "5: Disable operation"),
            (SwitchedOn, 0x0006, ReadyToSwitchOn, "6: Shutdown"),
            (OperationEnabled, 0x0006, ReadyToSwitchOn, "8: Shutdown"),
            (OperationEnabled, 0x0000, SwitchOnDisabled, "9: Disable voltage"),
            (OperationEnabled, 0x000B, QuickStopActive, "11: Quick stop"),
            (QuickStopActive, 0x0000, SwitchOnDisabled, "12: Disable voltage"),
            (SwitchOnDisabled, 0x0007, SwitchOnDisabled, "Switch on needs Shutdown first"),
            (SwitchOnDisabled, 0x000F, SwitchOnDisabled, "Enable operation needs Shutdown first"),
        ];
        for (from, cw, to, what) in rows {
            let mut fsa = fsa_in(from);
            fsa.step(cw, false);
            assert_eq!(fsa.state(), to, "{what}: {from:?} + {cw:#06x}");
        }
    }

    #[test]
    fn power_up_ends_in_switch_on_disabled() {
        let mut fsa = Fsa::default();
        assert_eq!(fsa.state(), State::NotReadyToSwitchOn);
        assert_eq!(fsa.step(0x0000, true), Some(1));
        assert_eq!(fsa.state(), State::SwitchOnDisabled);
    }

    /// CoE manual 3.1: a fault goes through Fault reaction active to Fault, and only a
    /// rising edge of controlword bit 7 resets it.
    #[test]
    fn fault_reset_acts_on_the_rising_edge_only() {
        let mut fsa = fsa_in(State::OperationEnabled);
        fsa.fault();
        assert_eq!(fsa.state(), State::FaultReactionActive);
        fsa.step(0x0080, true);
        assert_eq!(fsa.state(), State::Fault, "14: reaction done; bit 7 already high is no edge");
        fsa.step(0x0080, true);
        assert_eq!(fsa.state(), State::Fault, "bit 7 held high resets nothing");
        fsa.step(0x0000, true);
        fsa.step(0x0080, true);
        assert_eq!(fsa.state(), State::SwitchOnDisabled, "15: rising edge");
    }
}

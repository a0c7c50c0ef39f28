//! The EtherCAT state machine of a slave (CoE manual 2.3, table 2-3; ETG.1000.6 for the
//! codes the manual does not give).

/// AL states, with their AL Control / AL Status codes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
#[repr(u8)]
pub enum AlState {
    /// Init: no mailbox, no process data.
    Init = 1,
    /// Pre-Operational: mailbox, no process data; the master maps the PDOs here.
    PreOp = 2,
    /// Safe-Operational: mailbox and inputs; outputs are not applied.
    SafeOp = 4,
    /// Operational: mailbox, inputs and outputs.
    Op = 8,
}

impl AlState {
    /// The state's code in AL Control (0x0120) and AL Status (0x0130).
    pub fn code(self) -> u8 {
        self as u8
    }

    /// The next state up, one level at a time.
    fn up(self) -> Option<AlState> {
        match self {
            AlState::Init => Some(AlState::PreOp),
            AlState::PreOp => Some(AlState::SafeOp),
            AlState::SafeOp => Some(AlState::Op),
            AlState::Op => None,
        }
    }
}

/// AL status codes (ETG.1000.6, table "AL Status Codes").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u16)]
pub enum AlStatusCode {
    /// 0x0011: a state skipped going up (CoE manual 2.3: "no skipping").
    InvalidRequestedStateChange = 0x0011,
    /// 0x0024: the TxPDO assignment or mapping does not resolve.
    InvalidInputMapping = 0x0024,
    /// 0x0025: the RxPDO assignment or mapping does not resolve.
    InvalidOutputMapping = 0x0025,
    /// 0x0030: 0x1C32:01 and the activation in ESC register 0x0980 disagree.
    InvalidDcSyncConfiguration = 0x0030,
    /// 0x0035: DC mode with a cycle (0x1C32:02) the device does not run.
    InvalidSyncCycleTime = 0x0035,
}

impl AlStatusCode {
    /// The code as AL Status Code (0x0134) shows it.
    pub fn code(self) -> u16 {
        self as u16
    }
}

/// One slave's ESM: its state and the error of the last refused request.
#[derive(Clone, Copy, Debug)]
pub struct Esm {
    state: AlState,
    error: Option<AlStatusCode>,
}

impl Default for Esm {
    fn default() -> Self {
        Esm { state: AlState::Init, error: None }
    }
}

impl Esm {
    /// The state AL Status shows.
    pub fn state(&self) -> AlState {
        self.state
    }

    /// The AL status error indication and its code, if the last request was refused.
    pub fn error(&self) -> Option<AlStatusCode> {
        self.error
    }

    /// A state request of the master: up one level at a time ("no skipping"), down to
    /// any lower state. `check` validates the slave's configuration for the transition.
    pub fn request(
        &mut self,
        target: AlState,
        check: impl FnOnce(AlState, AlState) -> Result<(), AlStatusCode>,
    ) -> Result<(), AlStatusCode> {
        let allowed = target <= self.state || self.state.up() == Some(target);
        let result = if allowed { check(self.state, target) } else { Err(AlStatusCode::InvalidRequestedStateChange) };
        match result {
            Ok(()) => {
                self.state = target;
                self.error = None;
            }
            Err(code) => self.error = Some(code),
        }
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CoE manual 2.3: states may not be skipped going up; ETG.1000.6: down to any state.
    #[test]
    fn up_one_level_at_a_time_down_to_any() {
        let ok = |_: AlState, _: AlState| Ok(());
        let mut esm = Esm::default();
        assert_eq!(esm.request(AlState::Op, ok), Err(AlStatusCode::InvalidRequestedStateChange));
        assert_eq!(esm.state(), AlState::Init);
        assert_eq!(esm.error(), Some(AlStatusCode::InvalidRequestedStateChange));
        for target in [AlState::PreOp, AlState::SafeOp, AlState::Op] {
            assert_eq!(esm.request(target, ok), Ok(()));
        }
        assert_eq!(esm.error(), None);
        assert_eq!(esm.request(AlState::Init, ok), Ok(()));
        assert_eq!(esm.state(), AlState::Init);
    }
}
